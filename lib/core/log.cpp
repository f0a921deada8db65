#include "core/log.h"

#include <atomic>
#include <cstdio>
#include <mutex>

namespace inlight::log {
namespace {

std::atomic<int> g_level{static_cast<int>(Level::kNormal)};
std::mutex g_mutex;  // serialises stderr lines and the warning list
std::atomic<bool> g_bar_on_screen{false};

std::vector<std::string>& warnings() {
    static std::vector<std::string> list;
    return list;
}

void emit(const char* prefix, const std::string& message) {
    std::lock_guard<std::mutex> lock(g_mutex);
    if (g_bar_on_screen.exchange(false)) std::fputs("\r\033[K", stderr);
    std::fprintf(stderr, "%s%s\n", prefix, message.c_str());
    std::fflush(stderr);
}

}  // namespace

void set_bar_on_screen(bool on) { g_bar_on_screen = on; }

void set_level(Level l) { g_level = static_cast<int>(l); }
Level level() { return static_cast<Level>(g_level.load()); }

void info(const std::string& message) {
    if (g_level >= static_cast<int>(Level::kNormal)) emit("", message);
}

void verbose(const std::string& message) {
    if (g_level >= static_cast<int>(Level::kVerbose)) emit("", message);
}

void warn(const std::string& message) {
    if (g_level >= static_cast<int>(Level::kNormal)) emit("warning: ", message);
    std::lock_guard<std::mutex> lock(g_mutex);
    warnings().push_back(message);
}

void error(const std::string& message) { emit("", message); }

void summary(const std::string& tool, const std::string& what, const std::string& text) {
    info(tool + ": " + what + ": " + text);
}

std::string num(double value, int digits) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*g", digits, value);
    return buf;
}

std::string count(int64_t n, const std::string& noun, const std::string& plural_form) {
    const std::string word = n == 1 ? noun : plural_form.empty() ? noun + "s" : plural_form;
    return std::to_string(n) + " " + word;
}

std::vector<std::string> take_warnings() {
    std::lock_guard<std::mutex> lock(g_mutex);
    std::vector<std::string> out;
    out.swap(warnings());
    return out;
}

}  // namespace inlight::log

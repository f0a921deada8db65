#include "core/fs.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.h"

namespace inlight::fs {

std::string temp_sibling(const std::string& path) {
    static std::atomic<int> counter{0};
    const std::filesystem::path p(path);
    const std::string tag = str(".tmp-", ::getpid(), "-", counter++);
    return (p.parent_path() / (p.stem().string() + tag + p.extension().string())).string();
}

void write_atomic(const std::string& path, const std::function<void(const std::string&)>& write) {
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    std::error_code ec;
    if (!parent.empty()) {
        std::filesystem::create_directories(parent, ec);
        if (ec) throw Error(str(path, ": cannot create directory ", parent, ": ", ec.message()));
    }
    const std::string tmp = temp_sibling(path);
    try {
        write(tmp);
    } catch (...) {
        std::filesystem::remove(tmp, ec);
        throw;
    }
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::filesystem::remove(tmp, ec);
        throw Error(str(path, ": cannot move the finished file into place"));
    }
}

void write_text_atomic(const std::string& path, const std::string& content) {
    write_atomic(path, [&](const std::string& tmp) {
        std::ofstream out(tmp, std::ios::binary);
        out.write(content.data(), static_cast<std::streamsize>(content.size()));
        out.close();
        if (!out) throw Error(str(path, ": write failed"));
    });
}

std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(str(path, ": cannot open for reading"));
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

std::string extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext;
}

}  // namespace inlight::fs

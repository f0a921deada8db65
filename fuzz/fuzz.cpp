#include "fuzz.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "core/check.h"

namespace inlight::fuzz {
namespace {

struct TempDir {
    std::string path;
    TempDir() {
        std::string pattern =
            (std::filesystem::temp_directory_path() / "inlight-fuzz-XXXXXX").string();
        INLIGHT_CHECK(mkdtemp(pattern.data()) != nullptr) << "cannot make " << pattern;
        path = pattern;
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
};

}  // namespace

std::string temp_path(const std::string& name) {
    static const TempDir dir;
    return dir.path + "/" + name;
}

std::string write_temp(const std::string& name, const uint8_t* data, size_t size) {
    const std::string path = temp_path(name);
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    INLIGHT_CHECK(out.good()) << "cannot write " << path;
    return path;
}

std::pair<std::string, std::string> split_pair(const uint8_t* data, size_t size) {
    const std::string all(reinterpret_cast<const char*>(data), size);
    const size_t nul = all.find('\0');
    if (nul == std::string::npos) return {all, ""};
    return {all.substr(0, nul), all.substr(nul + 1)};
}

}  // namespace inlight::fuzz

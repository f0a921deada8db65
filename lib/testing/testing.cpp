#include "testing/testing.h"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>

namespace inlight::testing {

std::string shared_dir() {
    const char* env = std::getenv("INLIGHT_SHARED_DIR");
    if (env == nullptr || !std::filesystem::is_directory(env)) return "";
    return env;
}

std::string shared_data(const std::string& sub) {
    const std::string root = shared_dir();
    if (root.empty()) return "";
    const std::string p = root + "/data/" + sub;
    if (std::filesystem::exists(p)) return p;
    ADD_FAILURE() << p << " not found although " << root
                  << " exists: a data set is missing (see shared/data/README.md)";
    return "";
}

std::string blender_hdri_dir() {
    const std::string p = "/usr/share/blender/datafiles/studiolights/world";
    return std::filesystem::exists(p + "/city.exr") ? p : "";
}

std::string temp_dir(const std::string& name) {
    const std::filesystem::path p = std::filesystem::temp_directory_path() /
                                    ("inlight-test-" + std::to_string(::getpid()) + "-" + name);
    std::filesystem::remove_all(p);
    std::filesystem::create_directories(p);
    return p.string();
}

}  // namespace inlight::testing

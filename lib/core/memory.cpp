#include "core/memory.h"

#include <fstream>
#include <string>

namespace inlight {
namespace {

uint64_t status_kib(const std::string& key, const char* file = "/proc/self/status") {
    std::ifstream in(file);
    std::string line;
    while (std::getline(in, line)) {
        if (line.compare(0, key.size(), key) == 0 && line.size() > key.size() &&
            line[key.size()] == ':') {
            return std::stoull(line.substr(key.size() + 1));  // "VmHWM:   12345 kB"
        }
    }
    return 0;
}

}  // namespace

uint64_t peak_rss_bytes() { return status_kib("VmHWM") * 1024; }
uint64_t current_rss_bytes() { return status_kib("VmRSS") * 1024; }
uint64_t physical_memory_bytes() { return status_kib("MemTotal", "/proc/meminfo") * 1024; }

}  // namespace inlight

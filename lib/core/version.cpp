#include "core/version.h"

#ifndef INLIGHT_VERSION
#define INLIGHT_VERSION "0.0.0"
#endif
#ifndef INLIGHT_COMMIT
#define INLIGHT_COMMIT "unknown"
#endif

namespace inlight {

std::string version_string() { return INLIGHT_VERSION; }

std::string build_commit() { return INLIGHT_COMMIT; }

std::string version_line(const std::string& tool) {
    return tool.substr(0, tool.find(' ')) + " " + version_string() + " (commit " + build_commit() +
           ")";
}

}  // namespace inlight

// core/version.h: what build a tool is. The release version goes into what ships (bundle
// manifests, SH and BRDF table files) and so changes only with a release; the commit goes only
// into --version and the run report, so the same inputs give the same shipped bytes from any
// commit of one release.
#pragma once

#include <string>

namespace inlight {

/// Release version, e.g. "0.1.0" (CMake's PROJECT_VERSION).
std::string version_string();

/// The git commit the binary was built from: 12 hex digits, with "-dirty" when tracked files
/// differed from it at configure time; "unknown" when built outside a git checkout.
std::string build_commit();

/// The one --version line of every tool: "<tool> <version> (commit <commit>)". `tool` is the
/// binary's name ("render"); for a mode's parser ("calibrate geometry") only the first word is
/// used.
std::string version_line(const std::string& tool);

}  // namespace inlight

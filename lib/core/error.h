// core/error.h: the one exception type for bad input, I/O failure and non-convergence.
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

namespace inlight {

/// Thrown for conditions the user can cause: unreadable or malformed files, bad parameter
/// combinations, numerical non-convergence. The message starts with its context, e.g.
/// "sky.exr: expected a 2:1 lat-long map, got 1024x1000". Tools map it to exit code 1.
class Error : public std::runtime_error {
  public:
    explicit Error(const std::string& message) : std::runtime_error(message) {}
};

/// Thrown for invalid option values detected by a library (e.g. an unknown model name in a
/// config). Tools map it to exit code 2 (usage).
class UsageError : public Error {
  public:
    explicit UsageError(const std::string& message) : Error(message) {}
};

/// Concatenates any streamable values into a string: str("got ", w, "x", h).
template <typename... Args>
std::string str(Args&&... args) {
    std::ostringstream os;
    (os << ... << std::forward<Args>(args));
    return os.str();
}

}  // namespace inlight

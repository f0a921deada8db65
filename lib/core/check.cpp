#include "core/check.h"

#include <cstdio>
#include <cstdlib>

namespace inlight::detail {

CheckFailure::CheckFailure(const char* file, int line, const char* what) {
    m_os << file << ":" << line << ": " << what << " ";
}

CheckFailure::~CheckFailure() {
    std::fprintf(stderr, "%s\n", m_os.str().c_str());
    std::fflush(stderr);
    std::abort();
}

}  // namespace inlight::detail

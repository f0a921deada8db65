// core/check.h: assertions for programmer errors, on in Release (after pbrt-v4 util/check.h).
#pragma once

#include <sstream>

namespace inlight::detail {

/// Collects a failure message; its destructor prints "file:line: Check failed: ..." and aborts.
class CheckFailure {
  public:
    CheckFailure(const char* file, int line, const char* what);
    [[noreturn]] ~CheckFailure();
    std::ostream& stream() { return m_os; }

  private:
    std::ostringstream m_os;
};

/// Lowers the precedence of the stream expression so it binds inside the ternary.
struct Voidify {
    void operator&(std::ostream&) {}
};

}  // namespace inlight::detail

/// INLIGHT_CHECK(cond) << "message": aborts with file:line when cond is false, in every build.
#define INLIGHT_CHECK(cond)                                                                  \
    (cond) ? (void)0                                                                         \
           : ::inlight::detail::Voidify() &                                                  \
                 ::inlight::detail::CheckFailure(__FILE__, __LINE__, "Check failed: " #cond) \
                     .stream()

#define INLIGHT_CHECK_OP_(a, b, op)                                                        \
    ((a)op(b)) ? (void)0                                                                   \
               : ::inlight::detail::Voidify() &                                            \
                     ::inlight::detail::CheckFailure(__FILE__, __LINE__,                   \
                                                     "Check failed: " #a " " #op " " #b)   \
                             .stream()                                                     \
                         << "(" #a " = " << (a) << ", " #b " = " << (b) << ") "

/// Comparison checks print both operand values.
#define INLIGHT_CHECK_EQ(a, b) INLIGHT_CHECK_OP_(a, b, ==)
#define INLIGHT_CHECK_NE(a, b) INLIGHT_CHECK_OP_(a, b, !=)
#define INLIGHT_CHECK_LT(a, b) INLIGHT_CHECK_OP_(a, b, <)
#define INLIGHT_CHECK_LE(a, b) INLIGHT_CHECK_OP_(a, b, <=)
#define INLIGHT_CHECK_GT(a, b) INLIGHT_CHECK_OP_(a, b, >)
#define INLIGHT_CHECK_GE(a, b) INLIGHT_CHECK_OP_(a, b, >=)

/// Debug-only checks for hot loops.
#ifdef NDEBUG
#define INLIGHT_DCHECK(cond) \
    while (false) INLIGHT_CHECK(cond)
#define INLIGHT_DCHECK_LT(a, b) \
    while (false) INLIGHT_CHECK_LT(a, b)
#else
#define INLIGHT_DCHECK(cond) INLIGHT_CHECK(cond)
#define INLIGHT_DCHECK_LT(a, b) INLIGHT_CHECK_LT(a, b)
#endif

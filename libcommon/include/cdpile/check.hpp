/// CDPILE_DEBUG_CHECK(condition, message): an invariant the code relies on, checked in
/// debug builds (the asan preset) and compiled out when NDEBUG is defined (Release), where
/// neither the condition nor the message is evaluated.
///
/// A broken invariant is a bug, not bad input (bad input is a cdpile::Error, error.hpp):
/// the check prints `FILE:LINE: invariant broken: MESSAGE (CONDITION)` on stderr and
/// aborts, so a test or a sanitizer run stops at the step that broke it. `message` is
/// converted to std::string only when the check fails, so it may be built from numbers.
/// A check that needs a loop goes in a function whose body is under #ifndef NDEBUG.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <string>

namespace cdpile::detail {

/// What CDPILE_DEBUG_CHECK calls when its condition is false.
[[noreturn]] inline void invariant_broken(const char* condition, const std::string& message,
                                          const char* file, int line) {
  std::fprintf(stderr, "%s:%d: invariant broken: %s (%s)\n", file, line, message.c_str(),
               condition);
  std::fflush(stderr);
  std::abort();
}

}  // namespace cdpile::detail

#ifdef NDEBUG
#define CDPILE_DEBUG_CHECK(condition, message) static_cast<void>(0)
#else
#define CDPILE_DEBUG_CHECK(condition, message) \
  ((condition)                                 \
       ? static_cast<void>(0)                  \
       : ::cdpile::detail::invariant_broken(#condition, std::string(message), __FILE__, __LINE__))
#endif

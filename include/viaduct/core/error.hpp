#pragma once
/// \file Error types and checks.
///
/// Two kinds of checks (DESIGN.md §3.3): broken invariants use VIADUCT_ASSERT (debug builds
/// only); input and runtime errors throw InputError / SolverError in every build.

#include <cmath>
#include <stdexcept>
#include <string>

namespace viaduct {

/// Where in an input an error was found. Empty file and line 0 mean "not from a file".
struct SourceLocation {
  std::string file;  ///< path of the file, as given
  int line = 0;      ///< 1-based line number, 0 if unknown
  std::string key;   ///< dotted scenario key, e.g. "track.pad.k"; empty if none
};

/// Invalid input: bad scenario key or value, invalid physics, malformed file. CLI exit code 2.
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& what) : std::runtime_error(what) {}
  InputError(const SourceLocation& where, const std::string& what)
      : std::runtime_error(format(where, what)), where_(where) {}
  const SourceLocation& where() const noexcept { return where_; }

 private:
  static std::string format(const SourceLocation& w, const std::string& what);
  SourceLocation where_;
};

/// A computation could not be completed (singular matrix, non-finite state). CLI exit code 1.
class SolverError : public std::runtime_error {
 public:
  explicit SolverError(const std::string& what) : std::runtime_error(what) {}
};

namespace detail {
[[noreturn]] void assert_fail(const char* expr, const char* file, int line);
}

/// A number as it should appear in a message: up to `significant` digits, no trailing zeros.
std::string format_number(double value, int significant = 12);

/// Requires value > 0 and finite; throws InputError naming `what` otherwise.
void require_positive(double value, const std::string& what);
/// Requires value >= 0 and finite; throws InputError naming `what` otherwise.
void require_non_negative(double value, const std::string& what);
/// Requires a finite value; throws InputError naming `what` otherwise.
void require_finite(double value, const std::string& what);

}  // namespace viaduct

#ifndef NDEBUG
#define VIADUCT_ASSERT(expr) \
  ((expr) ? static_cast<void>(0) : ::viaduct::detail::assert_fail(#expr, __FILE__, __LINE__))
#else
#define VIADUCT_ASSERT(expr) static_cast<void>(0)
#endif

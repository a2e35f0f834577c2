#include "viaduct/core/error.hpp"

#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace viaduct {

std::string InputError::format(const SourceLocation& w, const std::string& what) {
  std::ostringstream os;
  if (!w.file.empty()) {
    os << w.file;
    if (w.line > 0) os << ':' << w.line;
    os << ": ";
  }
  if (!w.key.empty()) os << "key '" << w.key << "': ";
  os << what;
  return os.str();
}

namespace detail {
void assert_fail(const char* expr, const char* file, int line) {
  std::fprintf(stderr, "viaduct: internal assertion failed: %s (%s:%d)\n", expr, file, line);
  std::abort();
}
}  // namespace detail

std::string format_number(double value, int significant) {
  std::ostringstream os;
  os.precision(significant);
  os << value;
  return os.str();
}

static std::string num(double v) { return format_number(v, 17); }

void require_finite(double value, const std::string& what) {
  if (!std::isfinite(value)) throw InputError(what + " must be finite, got " + num(value));
}

void require_positive(double value, const std::string& what) {
  require_finite(value, what);
  if (!(value > 0.0)) throw InputError(what + " must be > 0, got " + num(value));
}

void require_non_negative(double value, const std::string& what) {
  require_finite(value, what);
  if (!(value >= 0.0)) throw InputError(what + " must be >= 0, got " + num(value));
}

}  // namespace viaduct

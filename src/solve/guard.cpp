// The divergence guard (guard.hpp).
#include "viaduct/solve/guard.hpp"

#include <cmath>

#include "viaduct/core/error.hpp"

namespace viaduct::solve {

namespace {
std::string guard_num(double v) { return format_number(v, 4); }

[[noreturn]] void diverged(const DivergenceBound& b, const std::string& what, double value, double bound, double t,
                           const std::string& cause) {
  std::string msg = "the run diverged: " + what + " reached " + guard_num(value);
  if (t >= 0.0) msg += " at t = " + guard_num(t) + " s";
  msg += ", beyond " + guard_num(bound);
  if (!b.basis.empty()) msg += " (" + b.basis + ")";
  msg += ", which no physical response reaches; likely cause: " + cause;
  throw SolverError(msg);
}

std::string output_name(const DivergenceBound& b, Index j) {
  const auto i = static_cast<std::size_t>(j);
  return i < b.names.size() && !b.names[i].empty() ? b.names[i] : "output " + std::to_string(j + 1);
}
}  // namespace

namespace detail {
void diverged_output(const DivergenceBound& b, Index j, double value, double t, const std::string& cause) {
  diverged(b, output_name(b, j), value, b.max_abs[j], t, cause);
}
void diverged_contact(const DivergenceBound& b, std::size_t wheel, double force, double t, const std::string& cause) {
  diverged(b, "the contact force of wheel " + std::to_string(wheel + 1) + " [N]", force, b.max_contact_force, t, cause);
}
}  // namespace detail

void check_maxima(const DivergenceBound& b, const Vector& max_abs, const std::string& cause) {
  for (Index j = 0; j < max_abs.size(); ++j)
    if (b.guards(j) && !(max_abs[j] <= b.max_abs[j])) diverged(b, "|" + output_name(b, j) + "|", max_abs[j], b.max_abs[j], -1.0, cause);
}

}  // namespace viaduct::solve

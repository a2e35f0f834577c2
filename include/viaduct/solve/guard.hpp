#pragma once
/// \file The divergence guard behind every integrator (docs/reliability.md, "No silent wrong
/// answer"). The caller states, per load case, bounds that no physical response reaches — study
/// takes a multiple of the static response of the whole train placed where each output is
/// largest, and of the wheels' static loads — and every kernel stops a run that passes one with a
/// SolverError naming the output, its value, the time, the bound and the likely cause (the
/// scheme, the step, the contact). A run that diverges never ends with exit 0 and 1e24 m; in a
/// sweep the case goes to failures.csv with that message.

#include <cmath>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include "viaduct/core/types.hpp"

namespace viaduct::solve {

/// Bounds of one load case.
struct DivergenceBound {
  /// Per output, in the output's unit: |value| beyond it is a divergence. An entry <= 0, NaN or
  /// +infinity leaves that output unguarded; an empty vector guards no output.
  Vector max_abs;
  std::vector<std::string> names;  ///< per output, for the message (optional: "output j")
  /// [N] > 0: the largest total wheel–rail force of any wheel (vehicles); +infinity: unguarded.
  double max_contact_force = std::numeric_limits<double>::infinity();
  std::string basis;  ///< how the bounds were formed, for the message ("20 x the static response ...")
  /// True when output j has a bound.
  bool guards(Index j) const { return j >= 0 && j < max_abs.size() && max_abs[j] > 0.0 && std::isfinite(max_abs[j]); }
};

namespace detail {
[[noreturn]] void diverged_output(const DivergenceBound& b, Index j, double value, double t, const std::string& cause);
[[noreturn]] void diverged_contact(const DivergenceBound& b, std::size_t wheel, double force, double t, const std::string& cause);
// The cause as given: a string, or a callable that makes it (only on failure: messages cost).
template <class Cause>
std::string cause_text(Cause&& c) {
  if constexpr (std::is_invocable_v<Cause>) return c();
  else return std::string(c);
}
}  // namespace detail

/// SolverError when |value| of output j at time t [s] exceeds its bound; `cause` (a string, or a
/// callable returning one, called only then) names what most likely diverged (the kernel's scheme
/// and step). NaN counts as beyond. Inline: one comparison when the bound holds.
template <class Cause>
inline void check_output(const DivergenceBound& b, Index j, double value, double t, Cause&& cause) {
  if (!b.guards(j) || std::abs(value) <= b.max_abs[j]) return;
  detail::diverged_output(b, j, value, t, detail::cause_text(cause));
}
/// The same on a case's running maxima (|value| per output, the time unknown).
void check_maxima(const DivergenceBound& b, const Vector& max_abs, const std::string& cause);
/// SolverError when |force| of wheel w at time t exceeds max_contact_force.
template <class Cause>
inline void check_contact(const DivergenceBound& b, std::size_t wheel, double force, double t, Cause&& cause) {
  if (std::abs(force) <= b.max_contact_force) return;
  detail::diverged_contact(b, wheel, force, t, detail::cause_text(cause));
}

}  // namespace viaduct::solve

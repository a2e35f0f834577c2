#pragma once
/// \file Constant axle loads moving along the load path of a structure.

#include <vector>

#include "viaduct/core/types.hpp"
#include "viaduct/load/train.hpp"
#include "viaduct/model/structure.hpp"

namespace viaduct::load {

/// The first axle enters the load path (start of the approach track, or of the bridge without
/// track) at t = 0 and every axle moves at constant `speed`. An axle acts only while it is on
/// the path; its load is distributed consistently (Hermite shape functions) to the element's
/// DOFs. Loads are positive downwards, like deflections.
class MovingLoads {
 public:
  /// speed [m/s] > 0; load_factor [-] > 0 scales every axle (e.g. 0.5 for one rail of a
  /// half-deck model). Keeps a copy of the path; `s` need not outlive this object.
  MovingLoads(const model::Structure& s, const Train& train, double speed, double load_factor = 1.0);

  /// Adds the nodal forces at time t [s] into f (size n_dofs). Allocation-free.
  void add_to(double t, Vector& f) const;
  /// The same forces as (dof, value) entries; `out` is cleared first. Allocation-free once
  /// `out` has the capacity of the axles on the path × 4.
  void entries(double t, SparseForce& out) const;
  /// [s] time at which the last axle leaves the path.
  double t_exit() const;
  /// [s] times at which an axle enters or leaves the path (the force jumps there), ascending.
  std::vector<double> event_times() const;
  double speed() const { return speed_; }

 private:
  template <class Sink>
  void for_each_entry(double t, Sink&& sink) const;
  std::vector<model::PathElement> path_;
  std::vector<double> offset_, load_;
  double x_start_ = 0.0, x_end_ = 0.0, speed_ = 0.0;
};

}  // namespace viaduct::load

#include "viaduct/load/moving_loads.hpp"

#include <algorithm>
#include <cmath>

#include "viaduct/core/error.hpp"
#include "viaduct/model/beam_element.hpp"

namespace viaduct::load {

MovingLoads::MovingLoads(const model::Structure& s, const Train& train, double speed,
                         double load_factor)
    : path_(s.load_path()), offset_(train.offset), load_(train.load), speed_(speed) {
  require_positive(speed, "speed [m/s]");
  require_positive(load_factor, "load factor");
  train.validate();
  if (path_.empty()) throw InputError("structure has no load path");
  for (double& p : load_) p *= load_factor;
  x_start_ = s.path_start();
  x_end_ = s.path_end();
}

double MovingLoads::t_exit() const { return (x_end_ - x_start_ + offset_.back()) / speed_; }

void MovingLoads::add_to(double t, Vector& f) const {
  const double head = x_start_ + speed_ * t;
  for (std::size_t i = 0; i < offset_.size(); ++i) {
    const double x = head - offset_[i];
    if (x < x_start_) break;  // offsets are non-decreasing: the rest have not entered yet
    if (x > x_end_) continue;
    auto it = std::upper_bound(path_.begin(), path_.end(), x,
                               [](double v, const model::PathElement& e) { return v < e.x0; });
    if (it != path_.begin()) --it;
    const double xi = std::clamp((x - it->x0) / it->h, 0.0, 1.0);
    const auto N = model::hermite_shape(xi, it->h);
    for (std::size_t q = 0; q < 4; ++q)
      if (it->dofs[q] >= 0) f[it->dofs[q]] += load_[i] * N[q];
  }
}

}  // namespace viaduct::load

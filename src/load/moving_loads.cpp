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

std::vector<double> MovingLoads::event_times() const {
  std::vector<double> t;
  for (double o : offset_) {
    t.push_back(o / speed_);
    t.push_back((x_end_ - x_start_ + o) / speed_);
  }
  std::sort(t.begin(), t.end());
  return t;
}

template <class Sink>
void MovingLoads::for_each_entry(double t, Sink&& sink) const {
  const double head = x_start_ + speed_ * t;
  // Axle i is on the path when head - offset_i is in [x_start, x_end]; offsets are sorted.
  const auto first = std::lower_bound(offset_.begin(), offset_.end(), head - x_end_);
  const auto last = std::upper_bound(first, offset_.end(), head - x_start_);
  for (auto o = first; o != last; ++o) {
    const std::size_t i = static_cast<std::size_t>(o - offset_.begin());
    const double x = head - *o;
    auto it = std::upper_bound(path_.begin(), path_.end(), x,
                               [](double v, const model::PathElement& e) { return v < e.x0; });
    if (it != path_.begin()) --it;
    const double xi = std::clamp((x - it->x0) / it->h, 0.0, 1.0);
    const auto N = model::hermite_shape(xi, it->h);
    for (std::size_t q = 0; q < 4; ++q)
      if (it->dofs[q] >= 0) sink(it->dofs[q], load_[i] * N[q]);
  }
}

void MovingLoads::add_to(double t, Vector& f) const {
  for_each_entry(t, [&f](Index d, double v) { f[d] += v; });
}

void MovingLoads::entries(double t, SparseForce& out) const {
  out.clear();
  for_each_entry(t, [&out](Index d, double v) { out.add(d, v); });
}

}  // namespace viaduct::load

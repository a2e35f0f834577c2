// A train's wheels rolling along a structure's load path, the irregularity under them and the
// wheel–rail contact law (load/contacts.hpp); moved from study/vehicles.cpp unchanged.
#include "viaduct/load/contacts.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "viaduct/core/error.hpp"
#include "viaduct/model/beam_element.hpp"

namespace viaduct::load {

double hertz_stiffness(double axle_load, double wheel_radius) {
  require_positive(axle_load, "axle load [N]");
  require_positive(wheel_radius, "train.wheel_radius_m [m]");
  const double G = 4.57e-8 * std::pow(wheel_radius, -0.149);
  return 2.0 * 1.5 * std::cbrt(axle_load / 2.0) / G;
}

double irregularity_at(const load::RailProfile* profile, double x, double x_from, double x_end, double taper) {
  if (!profile || x <= x_from || x >= x_end + taper) return 0.0;
  double w = 1.0;
  if (taper > 0.0) {
    if (x < x_from + taper) w = 0.5 * (1.0 - std::cos(M_PI * (x - x_from) / taper));
    if (x > x_end) w = std::min(w, 0.5 * (1.0 + std::cos(M_PI * (x - x_end) / taper)));
  }
  return -w * profile->at(x);
}

namespace {

// d/dx and d²/dx² of irregularity_at() at x (the same ramps and profile).
void irregularity_slopes(const load::RailProfile* profile, double x, double x_from, double x_end, double taper,
                         double& d1, double& d2) {
  d1 = d2 = 0.0;
  if (!profile || x <= x_from || x >= x_end + taper) return;
  // r = −w p: w the ramp (1 inside), p the profile.
  double w = 1.0, w1 = 0.0, w2 = 0.0;
  if (taper > 0.0) {
    const double k = M_PI / taper;
    if (x < x_from + taper) {
      const double a = k * (x - x_from);
      w = 0.5 * (1.0 - std::cos(a)), w1 = 0.5 * k * std::sin(a), w2 = 0.5 * k * k * std::cos(a);
    }
    if (x > x_end) {
      const double a = k * (x - x_end), v = 0.5 * (1.0 + std::cos(a));
      if (v < w) w = v, w1 = -0.5 * k * std::sin(a), w2 = -0.5 * k * k * std::cos(a);
    }
  }
  double p1 = 0.0, p2 = 0.0;
  profile->slopes(x, p1, p2);
  const double p = profile->at(x);
  d1 = -(w1 * p + w * p1);
  d2 = -(w2 * p + 2.0 * w1 * p1 + w * p2);
}

// The wheels of a train rolling at a constant speed along the structure's load path: the first
// at the path's start at t = 0, the others behind it on rigid ground until they reach it.
class TrainContacts : public ContactPath {
 public:
  TrainContacts(const model::Structure& s, const load::Train& t, double speed, const load::RailProfile* profile,
                double run_in, double taper, double t_start, double transition)
      : path_(s.load_path()), offset_(t.offset), x_start_(s.path_start()), x_end_(s.path_end()), speed_(speed),
        profile_(profile), x_from_(s.path_start() - run_in), taper_(taper), t_start_(t_start),
        transition_(s.has_track ? transition : 0.0) {}
  // Each wheel reaching the path's ends, the transitions' ends and the irregularity's taper ends.
  std::vector<double> breaks(double t_end) const override {
    std::vector<double> t, at{x_start_, x_end_};
    if (transition_ > 0.0) at.insert(at.end(), {x_start_ + transition_, x_end_ - transition_});
    if (profile_) at.insert(at.end(), {x_from_, x_from_ + taper_, x_end_ + taper_});
    for (const double off : offset_)
      for (const double x : at) {
        const double tb = t_start_ + (x - x_start_ + off) / speed_;
        if (tb > 0.0 && tb < t_end) t.push_back(tb);
      }
    return t;
  }
  void contact(std::size_t w, double t, std::vector<Index>& dof, std::vector<double>& weight, double& r) const override {
    dof.clear();
    weight.clear();
    const double x = x_start_ + speed_ * (t - t_start_) - offset_[w];
    r = irregularity_at(profile_, x, x_from_, x_end_, taper_);
    if (x < x_start_ || x > x_end_) return;  // rigid ground
    // Near the ends of a track the wheel's load passes between rigid ground and the rail
    // gradually, the rail's level under it weighted alike (a free rail end would be a dip).
    double phi = 1.0;
    const double from_end = std::min(x - x_start_, x_end_ - x);
    if (from_end < transition_) phi = 0.5 * (1.0 - std::cos(M_PI * from_end / transition_));
    auto it = std::upper_bound(path_.begin(), path_.end(), x, [](double v, const model::PathElement& e) { return v < e.x0; });
    if (it != path_.begin()) --it;
    const double xi = std::clamp((x - it->x0) / it->h, 0.0, 1.0);
    const auto N = model::hermite_shape(xi, it->h);
    for (std::size_t q = 0; q < 4; ++q)
      if (it->dofs[q] >= 0) {
        dof.push_back(it->dofs[q]);
        weight.push_back(phi * N[q]);
      }
  }
  // d/dt = v d/dx of φ(x) N(x) and of the irregularity, over the DOFs contact() gave.
  bool contact_rates(std::size_t w, double t, std::vector<double>& dweight, std::vector<double>& ddweight, double& dr,
                     double& ddr) const override {
    dweight.clear();
    ddweight.clear();
    const double x = x_start_ + speed_ * (t - t_start_) - offset_[w], v = speed_;
    double r1 = 0.0, r2 = 0.0;
    irregularity_slopes(profile_, x, x_from_, x_end_, taper_, r1, r2);
    dr = v * r1;
    ddr = v * v * r2;
    if (x < x_start_ || x > x_end_) return true;
    double phi = 1.0, phi1 = 0.0, phi2 = 0.0;  // the end transition's weight and its x-derivatives
    const double from_start = x - x_start_, from_end = x_end_ - x;
    const double s = std::min(from_start, from_end), ds = from_start <= from_end ? 1.0 : -1.0;
    if (s < transition_) {
      const double k = M_PI / transition_;
      phi = 0.5 * (1.0 - std::cos(k * s)), phi1 = ds * 0.5 * k * std::sin(k * s), phi2 = 0.5 * k * k * std::cos(k * s);
    }
    auto it = std::upper_bound(path_.begin(), path_.end(), x, [](double v0, const model::PathElement& e) { return v0 < e.x0; });
    if (it != path_.begin()) --it;
    const double xi = std::clamp((x - it->x0) / it->h, 0.0, 1.0);
    const auto N = model::hermite_shape(xi, it->h), N1 = model::hermite_slope(xi, it->h), N2 = model::hermite_curvature(xi, it->h);
    for (std::size_t q = 0; q < 4; ++q)
      if (it->dofs[q] >= 0) {
        dweight.push_back(v * (phi1 * N[q] + phi * N1[q]));
        ddweight.push_back(v * v * (phi2 * N[q] + 2.0 * phi1 * N1[q] + phi * N2[q]));
      }
    return true;
  }

 private:
  std::vector<model::PathElement> path_;
  std::vector<double> offset_;
  double x_start_, x_end_, speed_;
  const load::RailProfile* profile_;
  double x_from_, taper_, t_start_, transition_;
};

}  // namespace

void require_transition(const model::Structure& s, double transition) {
  require_non_negative(transition, "train.end_transition_m [m]");
  if (!s.has_track || s.deck_elements.empty()) return;
  const double before = s.deck_elements.front().x0 - s.path_start();
  const double after = s.path_end() - (s.deck_elements.back().x0 + s.deck_elements.back().h);
  if (transition > std::min(before, after))
    throw InputError("train.end_transition_m = " + format_number(transition, 6) + " m reaches the bridge: the track runs " +
                     format_number(before, 6) + " m before it and " + format_number(after, 6) +
                     " m after it (lengthen track.approach_length / exit_length or shorten the transition)");
}

std::unique_ptr<ContactPath> train_contacts(const model::Structure& s, const load::Train& train, double speed,
                                            const load::RailProfile* profile, double run_in, double taper,
                                            double t_start, double transition) {
  require_positive(speed, "speed [m/s]");
  require_transition(s, transition);
  train.validate();
  if (s.load_path().empty()) throw InputError("structure has no load path");
  return std::make_unique<TrainContacts>(s, train, speed, profile, run_in, taper, t_start, transition);
}

}  // namespace viaduct::load

#include "viaduct/load/vehicle.hpp"

#include <cmath>

#include "viaduct/core/error.hpp"
#include "viaduct/core/options.hpp"

namespace viaduct::load {

namespace {

// A point of a body: Σ coef·z[dof].
struct Point {
  Index dof[2] = {-1, -1};
  double coef[2] = {0.0, 0.0};
};
Point at(Index d) { return Point{{d, -1}, {1.0, 0.0}}; }
// e metres ahead of the centre of a body with bounce DOF `bounce` and pitch DOF `bounce + 1`.
Point ahead(Index bounce, double e) { return Point{{bounce, bounce + 1}, {1.0, e}}; }

// A spring (or dashpot) of value k between points a and b: A += k (a − b)(a − b)ᵀ.
void connect(Matrix& A, const Point& a, const Point& b, double k) {
  Index d[4];
  double w[4];
  int n = 0;
  for (int i = 0; i < 2; ++i)
    if (a.dof[i] >= 0) d[n] = a.dof[i], w[n++] = a.coef[i];
  for (int i = 0; i < 2; ++i)
    if (b.dof[i] >= 0) d[n] = b.dof[i], w[n++] = -b.coef[i];
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) A(d[i], d[j]) += k * w[i] * w[j];
}

void resize(TrainVehicles& v, Index n) {
  v.M = Matrix::Zero(n, n);
  v.C = Matrix::Zero(n, n);
  v.K = Matrix::Zero(n, n);
}

}  // namespace

TrainVehicles sprung_vehicles(const Train& t, const SprungSpec& s, double g) {
  t.validate();
  const std::string who = "train '" + t.name + "' as sprung masses: ";
  if (!(std::isfinite(s.unsprung_mass) && s.unsprung_mass >= 0.0))
    throw InputError(who + "unsprung mass = " + format_number(s.unsprung_mass) + " kg: violated constraint >= 0");
  if (!(std::isfinite(s.k) && s.k > 0.0)) throw InputError(who + "suspension stiffness = " + format_number(s.k) + " N/m: violated constraint > 0");
  if (!(std::isfinite(s.c) && s.c >= 0.0)) throw InputError(who + "suspension damping = " + format_number(s.c) + " N s/m: violated constraint >= 0");
  if (!(g > 0.0)) throw InputError(who + "gravity must be > 0");
  const Index na = static_cast<Index>(t.n_axles());
  TrainVehicles v;
  resize(v, 2 * na);
  for (Index i = 0; i < na; ++i) {
    const double sprung = t.load[static_cast<std::size_t>(i)] / g - s.unsprung_mass;
    if (!(sprung > 0.0))
      throw InputError(who + "axle " + std::to_string(i + 1) + " weighs " + format_number(t.load[static_cast<std::size_t>(i)] / g) +
                       " kg, not more than its unsprung mass " + format_number(s.unsprung_mass) + " kg");
    const Index body = 2 * i, wheel = 2 * i + 1;
    v.M(body, body) = sprung;
    v.M(wheel, wheel) = s.unsprung_mass;
    connect(v.K, at(body), at(wheel), s.k);
    connect(v.C, at(body), at(wheel), s.c);
    const std::string a = "a" + std::to_string(i + 1);
    v.dof_names.push_back(a + "_body");
    v.dof_names.push_back(a + "_wheel");
    v.wheel_dof.push_back(wheel);
    v.body_dof.push_back(body);
    v.body_names.push_back(a);
    v.body_pitch_dof.push_back(-1);
    v.body_arm.push_back(0.0);
  }
  return v;
}

SprungSpec sprung_of(const CoachSpec& c) {
  c.validate();
  auto series = [](double a, double b) { return a > 0.0 && b > 0.0 ? 1.0 / (1.0 / a + 1.0 / b) : 0.0; };
  return SprungSpec{c.wheelset_mass, series(c.primary_k, c.secondary_k / 2.0), series(c.primary_c, c.secondary_c / 2.0)};
}

namespace {

// Bodies on n + 1 shared bogies: DOFs body k (bounce, pitch) at 2k, bogie j (bounce, pitch) at
// 2n + 2j, its wheelsets at 4n + 2 + 2j and + 1.
TrainVehicles articulated_vehicles(const Train& t) {
  const Index n = static_cast<Index>(t.coaches.size());
  if (t.n_axles() != 2 * t.coaches.size() + 2)
    throw InputError("train '" + t.name + "': " + std::to_string(t.n_axles()) + " axles for " + std::to_string(n) +
                     " articulated coaches (2 per bogie, n + 1 bogies)");
  TrainVehicles v;
  resize(v, 6 * n + 4);
  const Index bogie0 = 2 * n, wheel0 = 4 * n + 2;
  for (Index j = 0; j <= n; ++j) {
    // A bogie carries the neighbouring coaches' pivots; its own data are the first coach's.
    const CoachSpec& c = t.coaches[static_cast<std::size_t>(std::min(j, n - 1))];
    const Index bg = bogie0 + 2 * j;
    v.M(bg, bg) = c.bogie_mass;
    v.M(bg + 1, bg + 1) = c.bogie_pitch_inertia;
    for (int i = 0; i < 2; ++i) {
      const Index wheel = wheel0 + 2 * j + i;
      v.M(wheel, wheel) = c.wheelset_mass;
      const double ew = i == 0 ? c.wheelbase / 2.0 : -c.wheelbase / 2.0;
      connect(v.K, ahead(bg, ew), at(wheel), c.primary_k);
      connect(v.C, ahead(bg, ew), at(wheel), c.primary_c);
      v.wheel_dof.push_back(wheel);
      v.dof_names.push_back("b" + std::to_string(j + 1) + "_wheel" + std::to_string(i + 1));
    }
  }
  for (Index k = 0; k < n; ++k) {
    const CoachSpec& c = t.coaches[static_cast<std::size_t>(k)];
    c.validate();
    const Index body = 2 * k;
    v.M(body, body) = c.body_mass;
    v.M(body + 1, body + 1) = c.body_pitch_inertia;
    for (int j = 0; j < 2; ++j) {  // front pivot on bogie k, rear on bogie k + 1
      const Index bg = bogie0 + 2 * (k + j);
      const double e = j == 0 ? c.bogie_spacing / 2.0 : -c.bogie_spacing / 2.0;
      connect(v.K, ahead(body, e), at(bg), c.secondary_k);
      connect(v.C, ahead(body, e), at(bg), c.secondary_c);
    }
    v.body_dof.push_back(body);
    v.body_names.push_back("c" + std::to_string(k + 1));
    v.body_pitch_dof.push_back(body + 1);
    v.body_arm.push_back(c.bogie_spacing / 2.0);
  }
  // DOF names in DOF order: bodies, bogies, wheelsets.
  std::vector<std::string> names;
  for (Index k = 0; k < n; ++k)
    for (const char* s : {"_body_bounce", "_body_pitch"}) names.push_back("c" + std::to_string(k + 1) + s);
  for (Index j = 0; j <= n; ++j)
    for (const char* s : {"_bounce", "_pitch"}) names.push_back("b" + std::to_string(j + 1) + s);
  for (auto& w : v.dof_names) names.push_back(w);
  v.dof_names = std::move(names);
  return v;
}

}  // namespace

TrainVehicles multibody_vehicles(const Train& t) {
  t.validate();
  if (t.coaches.empty())
    throw InputError("train '" + t.name + "' is a list of axles, not of coaches: a multibody model needs a train of kind \"coaches\"");
  if (t.articulated) return articulated_vehicles(t);
  if (t.n_axles() != 4 * t.coaches.size())
    throw InputError("train '" + t.name + "': " + std::to_string(t.n_axles()) + " axles for " + std::to_string(t.coaches.size()) +
                     " coaches (4 each)");
  const Index nc = static_cast<Index>(t.coaches.size());
  TrainVehicles v;
  resize(v, 10 * nc);
  for (Index k = 0; k < nc; ++k) {
    const CoachSpec& c = t.coaches[static_cast<std::size_t>(k)];
    c.validate();
    const Index o = 10 * k;
    const Index body = o, bogie[2] = {o + 2, o + 4};
    v.M(body, body) = c.body_mass;
    v.M(body + 1, body + 1) = c.body_pitch_inertia;
    const double half_s = c.bogie_spacing / 2.0, half_w = c.wheelbase / 2.0;
    for (int j = 0; j < 2; ++j) {
      const Index bg = bogie[j];
      v.M(bg, bg) = c.bogie_mass;
      v.M(bg + 1, bg + 1) = c.bogie_pitch_inertia;
      const double e = j == 0 ? half_s : -half_s;  // front bogie ahead of the body's centre
      connect(v.K, ahead(body, e), at(bg), c.secondary_k);
      connect(v.C, ahead(body, e), at(bg), c.secondary_c);
      for (int i = 0; i < 2; ++i) {
        const Index wheel = o + 6 + 2 * j + i;
        const double ew = i == 0 ? half_w : -half_w;
        v.M(wheel, wheel) = c.wheelset_mass;
        connect(v.K, ahead(bg, ew), at(wheel), c.primary_k);
        connect(v.C, ahead(bg, ew), at(wheel), c.primary_c);
      }
    }
    const std::string ck = "c" + std::to_string(k + 1);
    for (const char* s : {"_body_bounce", "_body_pitch", "_bogie1_bounce", "_bogie1_pitch", "_bogie2_bounce", "_bogie2_pitch",
                          "_wheel1", "_wheel2", "_wheel3", "_wheel4"})
      v.dof_names.push_back(ck + s);
    for (Index i = 0; i < 4; ++i) v.wheel_dof.push_back(o + 6 + i);
    v.body_dof.push_back(body);
    v.body_names.push_back(ck);
    v.body_pitch_dof.push_back(body + 1);
    v.body_arm.push_back(half_s);
  }
  return v;
}

}  // namespace viaduct::load

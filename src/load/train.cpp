#include "viaduct/load/train.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include "viaduct/core/error.hpp"
#include "viaduct/core/options.hpp"

namespace viaduct::load {

double Train::total_load() const { return std::accumulate(load.begin(), load.end(), 0.0); }

void Train::validate() const {
  const std::string n = "train '" + name + "': ";
  if (offset.empty()) throw InputError(n + "has no axles");
  if (offset.size() != load.size()) throw InputError(n + "offsets and loads differ in count");
  if (offset.size() > kMaxAxles)
    throw InputError(n + std::to_string(offset.size()) + " axles, more than the limit of " + std::to_string(kMaxAxles));
  if (offset.front() != 0.0) throw InputError(n + "first axle offset must be 0");
  for (std::size_t i = 0; i < offset.size(); ++i) {
    if (!std::isfinite(offset[i]) || !std::isfinite(load[i]))
      throw InputError(n + "axle " + std::to_string(i + 1) + " has a non-finite value");
    if (i > 0 && offset[i] < offset[i - 1])
      throw InputError(n + "axle offsets must not decrease (axle " + std::to_string(i + 1) + ")");
    if (!(load[i] > 0.0))
      throw InputError(n + "axle " + std::to_string(i + 1) + " load must be > 0 [N]");
  }
}

void CoachSpec::validate() const {
  auto need = [&](bool ok, const char* field, double v, const char* rule) {
    if (!ok || std::isnan(v))
      throw InputError("coach '" + name + "': " + field + " = " + format_number(v) + ": violated constraint " + rule);
  };
  need(std::isfinite(body_mass) && body_mass > 0.0, "body_mass", body_mass, "> 0 [kg]");
  need(std::isfinite(body_pitch_inertia) && body_pitch_inertia > 0.0, "body_pitch_inertia", body_pitch_inertia, "> 0 [kg m2]");
  need(std::isfinite(bogie_mass) && bogie_mass > 0.0, "bogie_mass", bogie_mass, "> 0 [kg]");
  need(std::isfinite(bogie_pitch_inertia) && bogie_pitch_inertia > 0.0, "bogie_pitch_inertia", bogie_pitch_inertia, "> 0 [kg m2]");
  need(std::isfinite(wheelset_mass) && wheelset_mass > 0.0, "wheelset_mass", wheelset_mass, "> 0 [kg]");
  need(std::isfinite(wheelbase) && wheelbase > 0.0, "wheelbase", wheelbase, "> 0 [m]");
  need(std::isfinite(bogie_spacing) && bogie_spacing > wheelbase, "bogie_spacing", bogie_spacing, "> wheelbase (the bogies would overlap)");
  need(std::isfinite(primary_k) && primary_k > 0.0, "primary_k", primary_k, "> 0 [N/m]");
  need(std::isfinite(primary_c) && primary_c >= 0.0, "primary_c", primary_c, ">= 0 [N s/m]");
  need(std::isfinite(secondary_k) && secondary_k > 0.0, "secondary_k", secondary_k, "> 0 [N/m]");
  need(std::isfinite(secondary_c) && secondary_c >= 0.0, "secondary_c", secondary_c, ">= 0 [N s/m]");
  need(std::isfinite(length) && length > bogie_spacing + wheelbase, "length", length,
       "> bogie_spacing + wheelbase (the coach's axles would reach into the next coach)");
}

Train coach_train(const std::string& name, const CoachSpec& coach, int n_coaches, double g) {
  coach.validate();
  if (n_coaches < 1 || static_cast<std::size_t>(n_coaches) * 4 > kMaxAxles)
    throw InputError("train '" + name + "': n_coaches = " + std::to_string(n_coaches) + ": violated constraint 1 .. " +
                     std::to_string(kMaxAxles / 4));
  if (!(g > 0.0)) throw InputError("train '" + name + "': gravity must be > 0");
  Train t;
  t.name = name;
  for (int k = 0; k < n_coaches; ++k) {
    for (double o : coach.axle_offsets()) {
      t.offset.push_back(k * coach.length + o);
      t.load.push_back(coach.axle_load(g));
    }
    t.coaches.push_back(coach);
  }
  t.validate();
  return t;
}

Train articulated_train(const std::string& name, const CoachSpec& coach, int n_coaches, double g) {
  coach.validate();
  if (n_coaches < 1 || static_cast<std::size_t>(n_coaches + 1) * 2 > kMaxAxles)
    throw InputError("train '" + name + "': n_coaches = " + std::to_string(n_coaches) + ": violated constraint 1 .. " +
                     std::to_string(kMaxAxles / 2 - 1));
  if (!(g > 0.0)) throw InputError("train '" + name + "': gravity must be > 0");
  Train t;
  t.name = name;
  t.articulated = true;
  for (int j = 0; j <= n_coaches; ++j) {
    const double bodies = (j == 0 || j == n_coaches) ? 0.5 : 1.0;  // halves of bodies on bogie j
    const double axle = g * (bodies * coach.body_mass / 2.0 + coach.bogie_mass / 2.0 + coach.wheelset_mass);
    for (double o : {0.0, coach.wheelbase}) {
      t.offset.push_back(j * coach.bogie_spacing + o);
      t.load.push_back(axle);
    }
  }
  t.coaches.assign(static_cast<std::size_t>(n_coaches), coach);
  t.validate();
  return t;
}

HslmRow hslm_a_row(int number) {
  // EN 1991-2 Annex E, Table E.4 (REFERENCE.md §3): N, D [m], d [m], P [kN].
  static const double table[10][4] = {
      {18, 18, 2.0, 170}, {17, 19, 3.5, 200}, {16, 20, 2.0, 180}, {15, 21, 3.0, 190},
      {14, 22, 2.0, 170}, {13, 23, 2.0, 180}, {13, 24, 2.0, 190}, {12, 25, 2.5, 190},
      {11, 26, 2.0, 210}, {11, 27, 2.0, 210}};
  if (number < 1 || number > 10)
    throw InputError("HSLM-A number must be 1..10, got " + std::to_string(number));
  const double* r = table[number - 1];
  return HslmRow{static_cast<int>(r[0]), r[1], r[2], r[3] * 1e3};
}

Train hslm_a(const std::string& name, const HslmRow& row) {
  if (row.n_coaches < 1) throw InputError("HSLM train '" + name + "': n_coaches must be >= 1");
  if (!(row.coach_length > 0.0) || !(row.bogie_spacing > 0.0) || !(row.axle_load > 0.0) ||
      !(row.bogie_spacing < row.coach_length))
    throw InputError("HSLM train '" + name +
                     "': need coach_length > bogie_spacing > 0 and axle_load > 0");
  const double D = row.coach_length, d = row.bogie_spacing;
  // Layout (reproduces 2N + 14 axles and 397.525 m for A1, REFERENCE.md §3):
  //  - power car axles at 0, 3, 14, 17 m;
  //  - coupling point midway in the 3.525 m gap to the end coach (x = 17 + 3.525/2);
  //  - end coach: length D from the coupling point to the first articulation, its own bogie
  //    (axle spacing d) at the outer end, first axle 3.525 m behind the power car;
  //  - N + 1 articulated bogies (axle spacing d) centred D apart (N intermediate coaches);
  //  - the tail mirrors the head.
  const double gap = 3.525;
  const double coupling = 17.0 + gap / 2.0;
  std::vector<double> x = {0.0, 3.0, 14.0, 17.0, 17.0 + gap, 17.0 + gap + d};
  for (int k = 0; k <= row.n_coaches; ++k) {
    const double c = coupling + D * (k + 1);
    x.push_back(c - d / 2.0);
    x.push_back(c + d / 2.0);
  }
  const double rear_coupling = coupling + D * (row.n_coaches + 2);
  x.push_back(rear_coupling - gap / 2.0 - d);
  x.push_back(rear_coupling - gap / 2.0);
  for (double p : {0.0, 3.0, 14.0, 17.0}) x.push_back(rear_coupling + gap / 2.0 + p);
  Train t;
  t.name = name;
  t.offset = x;
  t.load.assign(x.size(), row.axle_load);
  t.validate();
  return t;
}

double characteristic_distance(const Train& t, double min_m, double max_m) {
  if (t.n_axles() < 2 || !(min_m > 0.0) || !(max_m > min_m)) return 0.0;
  // Steps of 1 mm in λ: fine against the peak width, about d²/L (0.2 m for 20 coaches of 20 m).
  const int n = static_cast<int>(std::min(1e5, std::ceil((max_m - min_m) / 1e-3)));
  std::vector<double> s(static_cast<std::size_t>(n) + 1);
  double best = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double lambda = min_m + (max_m - min_m) * i / n;
    double re = 0.0, im = 0.0;
    for (std::size_t k = 0; k < t.n_axles(); ++k) {
      const double phase = 2.0 * M_PI * t.offset[k] / lambda;
      re += t.load[k] * std::cos(phase);
      im -= t.load[k] * std::sin(phase);
    }
    s[static_cast<std::size_t>(i)] = std::hypot(re, im);
    best = std::max(best, s[static_cast<std::size_t>(i)]);
  }
  double peak = 0.0;
  for (int i = n; i >= 0; --i)
    if (s[static_cast<std::size_t>(i)] >= 0.99 * best) {
      // The top of that peak: climb while the signature still grows towards shorter λ.
      while (i > 0 && s[static_cast<std::size_t>(i - 1)] > s[static_cast<std::size_t>(i)]) --i;
      peak = min_m + (max_m - min_m) * i / n;
      break;
    }
  // The loads that are not periodic (power cars) pull the peak by up to 0.5 %: the distance is
  // the axle spacing within 3 % of it that occurs most often (the coach length), when one does.
  std::map<long, int> count;
  for (std::size_t i = 0; i < t.n_axles(); ++i)
    for (std::size_t j = i + 1; j < t.n_axles() && j <= i + 8; ++j) {
      const double gap = t.offset[j] - t.offset[i];
      if (std::abs(gap - peak) <= 0.03 * peak) ++count[std::lround(gap * 1e3)];
    }
  long mode = 0;
  int most = 0;
  for (const auto& [mm, c] : count)
    if (c > most) most = c, mode = mm;
  return most >= 2 ? static_cast<double>(mode) * 1e-3 : peak;
}

Train regular_train(const std::string& name, int n_axles, double spacing, double load) {
  if (n_axles < 1) throw InputError("train '" + name + "': n_axles must be >= 1");
  if (static_cast<std::size_t>(n_axles) > kMaxAxles)
    throw InputError("train '" + name + "': n_axles must be at most " + std::to_string(kMaxAxles));
  if (n_axles > 1 && !(spacing > 0.0)) throw InputError("train '" + name + "': spacing must be > 0 [m]");
  Train t;
  t.name = name;
  for (int i = 0; i < n_axles; ++i) {
    t.offset.push_back(i * spacing);
    t.load.push_back(load);
  }
  t.validate();
  return t;
}

}  // namespace viaduct::load

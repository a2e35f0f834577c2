// S-N curves and the Palmgren–Miner sum (fatigue.hpp).
#include "viaduct/study/fatigue.hpp"

#include <algorithm>
#include <cmath>
#include <mutex>

#include "viaduct/core/cancel.hpp"
#include "viaduct/core/error.hpp"
#include "viaduct/core/thread_pool.hpp"

namespace viaduct::study {

const std::vector<double>& en1993_1_9_categories() {
  static const std::vector<double> c = {36, 40, 45, 50, 56, 63, 71, 80, 90, 100, 112, 125, 140, 160};
  return c;
}

void SnCurve::validate() const {
  const std::string who = "S-N curve " + (name.empty() ? std::string("(unnamed)") : name) + ": ";
  if (!(first_slope > 0.0) || !std::isfinite(first_slope))
    throw InputError(who + "slope m = " + format_number(first_slope, 6) + ": violated constraint m > 0");
  if (knee_n.empty() || knee_n.size() != knee_s.size()) throw InputError(who + "give as many knee ranges as knee cycles, at least one");
  for (std::size_t i = 0; i < knee_n.size(); ++i) {
    if (!(knee_n[i] > 0.0) || !(knee_s[i] > 0.0) || !std::isfinite(knee_n[i]) || !std::isfinite(knee_s[i]))
      throw InputError(who + "knee " + std::to_string(i + 1) + ": violated constraint cycles > 0 and range > 0");
    if (i > 0 && !(knee_n[i] > knee_n[i - 1] && knee_s[i] < knee_s[i - 1]))
      throw InputError(who + "knee " + std::to_string(i + 1) + ": cycles must ascend and ranges descend along the curve");
  }
}

double SnCurve::cycles(double s) const {
  if (!(s > 0.0) || s < knee_s.back()) return std::numeric_limits<double>::infinity();
  if (s >= knee_s.front()) return knee_n.front() * std::pow(knee_s.front() / s, first_slope);
  std::size_t i = 1;
  while (s < knee_s[i]) ++i;  // knee_s[i] <= s < knee_s[i - 1]
  const double m = std::log(knee_n[i] / knee_n[i - 1]) / std::log(knee_s[i - 1] / knee_s[i]);
  return knee_n[i] * std::pow(knee_s[i] / s, m);
}

SnCurve SnCurve::two_slopes(double delta_c, double m1, double m2, double n_c, double n_d, double n_l) {
  if (!(delta_c > 0.0) || !std::isfinite(delta_c))
    throw InputError("S-N curve: delta_sigma_c = " + format_number(delta_c, 6) + " Pa: violated constraint > 0");
  if (!(n_c > 0.0) || !(n_d > n_c))
    throw InputError("S-N curve: the knee n_d = " + format_number(n_d, 6) + " must lie beyond n_c = " + format_number(n_c, 6) + " cycles");
  SnCurve c;
  c.first_slope = m1;
  const double s_d = delta_c * std::pow(n_c / n_d, 1.0 / m1);
  c.knee_n = {n_d};
  c.knee_s = {s_d};
  if (m2 > 0.0 && n_l > n_d) {
    c.knee_n.push_back(n_l);
    c.knee_s.push_back(s_d * std::pow(n_d / n_l, 1.0 / m2));
  }
  c.validate();
  return c;
}

SnCurve SnCurve::en1993_1_9(double category) {
  const auto& cats = en1993_1_9_categories();
  if (std::find(cats.begin(), cats.end(), category) == cats.end()) {
    std::string list;
    for (double x : cats) list += (list.empty() ? "" : ", ") + format_number(x, 4);
    throw InputError("detail category " + format_number(category, 6) + " is not one of EN 1993-1-9's: " + list + " (MPa)");
  }
  SnCurve c = two_slopes(category * 1e6, 3.0, 5.0);
  c.name = "EN 1993-1-9 detail category " + format_number(category, 4);
  return c;
}

MinerSum::MinerSum(SnCurve curve, double to_pa, double gamma_ff, double gamma_mf) : curve_(std::move(curve)) {
  curve_.validate();
  if (!(to_pa > 0.0) || !std::isfinite(to_pa)) throw InputError("fatigue: the history's unit to Pa = " + format_number(to_pa, 6) + ": violated constraint > 0");
  if (!(gamma_ff >= 1.0) || !(gamma_mf >= 1.0) || !std::isfinite(gamma_ff * gamma_mf))
    throw InputError("fatigue: gamma_Ff = " + format_number(gamma_ff, 6) + ", gamma_Mf = " + format_number(gamma_mf, 6) +
                     ": violated constraint partial factors >= 1");
  factor_ = to_pa * gamma_ff * gamma_mf;
}

void MinerSum::add(const signal::Cycle& c) {
  const double s = c.range * factor_;
  cycles += c.count;
  max_range_pa = std::max(max_range_pa, s);
  const double n = curve_.cycles(s);
  if (std::isfinite(n)) {
    damage += c.count / n;
    damaging += c.count;
  }
}

double equivalent_range_2e6(double damage, const SnCurve& curve) {
  if (!(damage >= 0.0)) throw InputError("fatigue: damage must be >= 0");
  // On the first branch N = N_1 (S_1/S)^m: the range whose 2e6 cycles do D.
  const double n1 = curve.knee_n.front(), s1 = curve.knee_s.front(), m = curve.first_slope;
  return s1 * std::pow(damage * n1 / 2e6, 1.0 / m);
}

CountedHistory count_history(const Vector& x, double to_pa, const FatigueCount& f) {
  CountedHistory out{MinerSum(f.curve, to_pa, f.gamma_ff, f.gamma_mf), {}};
  const double mpa = to_pa * 1e-6;  // MPa per unit of the history
  signal::Rainflow rf(
      [&](const signal::Cycle& c) {
        out.miner.add(c);
        out.bins[{static_cast<long>(std::floor(c.range * mpa / f.range_bin_mpa)), static_cast<long>(std::floor(c.mean * mpa / f.mean_bin_mpa))}] +=
            c.count;
      },
      f.method, f.hysteresis_mpa / mpa);
  rf.push(x);
  rf.finish();
  return out;
}

SnCurve sn_curve(std::optional<double> detail_mpa, std::optional<double> delta_c_mpa, double m1, double m2) {
  if (detail_mpa.has_value() == delta_c_mpa.has_value())
    throw InputError("give exactly one of --detail (an EN 1993-1-9 category, MPa) or --delta-c-mpa (a curve of your own)");
  if (detail_mpa) return SnCurve::en1993_1_9(*detail_mpa);
  SnCurve c = SnCurve::two_slopes(*delta_c_mpa * 1e6, m1, m2);
  c.name = "user curve: " + format_number(*delta_c_mpa, 6) + " MPa at 2e6 cycles with slopes " + format_number(m1, 3) + " and " +
           format_number(m2, 3);
  return c;
}

double stress_per_unit(const std::string& channel, const std::string& unit, double youngs_modulus_pa,
                       std::optional<double> section_modulus_m3) {
  if (unit == "Pa") return 1.0;
  if (unit == "ue") return youngs_modulus_pa * 1e-6;
  if (unit == "Nm") {
    if (!section_modulus_m3)
      throw InputError("channel " + channel + " is a moment [N m]: give --section-modulus-m3 W (sigma = M / W at the detail; Python: section_modulus_m3)");
    return 1.0 / *section_modulus_m3;
  }
  throw InputError("channel " + channel + " is in " + unit +
                   ": fatigue needs a stress (Pa, MPa), a strain (microstrain, times --youngs-modulus-pa) or a moment "
                   "(N m, over --section-modulus-m3)");
}

std::size_t fatigue_effect(const PreparedModel& m, const std::string& channel) {
  std::string names;
  for (std::size_t i = 0; i < m.effects.size(); ++i) {
    const std::string& n = m.effects[i].name;
    const auto cut = n.rfind('_');
    const std::string unit = n.substr(cut + 1);
    if (unit != "Nm" && unit != "ue") continue;
    if (n.substr(0, cut) == channel) return i;
    names += (names.empty() ? "" : ", ") + n.substr(0, cut);
  }
  throw InputError("channel " + channel + ": the scenario has no such load effect; fatigue takes " +
                   (names.empty() ? std::string("none (no deck station)") : names) + " (a strain needs the station's fibre_m)");
}

MixDamage traffic_damage(const PreparedModel& m, const RunSettings& settings, std::size_t effect, double to_pa,
                         const TrafficMix& mix, const FatigueCount& f, int threads, const ProgressSink& progress) {
  if (effect >= m.effects.size()) throw InputError("traffic_damage: the model was prepared without that load effect");
  (void)MinerSum(f.curve, to_pa, f.gamma_ff, f.gamma_mf);  // the curve, unit and factors checked once, before any run
  MixDamage out;
  out.trains.resize(mix.trains.size());
  std::mutex done_mutex;
  std::size_t done = 0;
  parallel_for(mix.trains.size(), threads, [&](std::size_t i, int) {
    const MixTrain& t = mix.trains[i];
    TrainDamage& d = out.trains[i];
    d.name = t.name;
    d.per_day = t.per_day;
    d.speed = t.speed;
    try {
      const RunResult r = simulate(m, t.train, t.speed, settings);
      if (effect >= r.effects.size() || r.effects[effect].value.size() == 0)
        throw SolverError("the run recorded no history of " + m.effects[effect].name);  // never an index past the end
      d.passage = count_history(r.effects[effect].value, to_pa, f);
      d.per_year = d.passage->miner.damage * t.per_day * 365.0;
    } catch (const std::exception& e) {
      d.error = e.what();
    }
    if (progress) {
      const std::lock_guard<std::mutex> lock(done_mutex);
      progress(++done, mix.trains.size());
    }
  });
  if (cancel_requested()) throw Cancelled();  // the runs cut short are not failures of the model
  for (const TrainDamage& d : out.trains) {
    if (!d.error.empty()) ++out.n_failed;
    out.per_year += d.per_year;
  }
  return out;
}

std::string stress_range_warning(const std::string& what, double max_range_pa) {
  if (!(max_range_pa > 0.0)) return "";
  const std::string r = format_number(max_range_pa * 1e-6, 4) + " MPa";
  if (max_range_pa < kMinPlausibleRangePa)
    return what + ": its largest stress range is " + r + ", below 0.1 MPa (0.5 µε on steel), quieter than any strain gauge's noise "
           "under a train: a history in another unit than its name says (ε read as µε, Pa as MPa), or a section modulus in cm³ "
           "given as m³? The damage would be 0 for it";
  if (max_range_pa > kMaxPlausibleRangePa)
    return what + ": its largest stress range is " + r + ", above 1000 MPa, beyond any structural steel's elastic range: a "
           "history in another unit than its name says (µε read as ε, MPa as Pa), or a section modulus too small?";
  return "";
}

}  // namespace viaduct::study

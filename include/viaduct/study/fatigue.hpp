#pragma once
/// \file Fatigue damage from counted cycles (issue #42; REFERENCE.md §11): S-N curves of
/// EN 1993-1-9 by detail category or given by the user, and the Palmgren–Miner sum.
///
/// EN 1993-1-9 Fig. 7.1 (direct stress): Δσ_C at N = 2·10⁶ (the detail category, MPa); slope
/// m = 3 down to the constant-amplitude limit Δσ_D = (2/5)^(1/3) Δσ_C at 5·10⁶; slope 5 down to
/// the cut-off Δσ_L = (5/100)^(1/5) Δσ_D at 10⁸; no damage below Δσ_L. That is the curve for
/// variable amplitudes (the m = 5 branch counts the small ranges of a train passage); a history
/// of one constant range below Δσ_D does no damage, which the sum does not know: it is stated,
/// not applied. Partial factors: a range counts as γFf·γMf·Δσ against the curve (EN 1993-1-9
/// 8(1): γFf Δσ against Δσ_C / γMf, which is the same for every branch of a power law).

#include <limits>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "viaduct/core/log.hpp"
#include "viaduct/core/types.hpp"
#include "viaduct/load/train.hpp"
#include "viaduct/signal/rainflow.hpp"
#include "viaduct/study/simulation.hpp"

namespace viaduct::study {

/// A piecewise power-law S-N curve: above the first knee's range N = N_1 (S_1/S)^m; between
/// knees a straight line in log N – log S; below the last knee's range no damage (N = ∞).
struct SnCurve {
  std::string name;
  double first_slope = 3.0;   ///< m above the first knee, > 0
  std::vector<double> knee_n; ///< cycles at the knees, ascending, > 0
  std::vector<double> knee_s; ///< [Pa] ranges at the knees, descending, > 0
  /// Cycles to failure at range s [Pa] (∞ below the cut-off, and for s <= 0).
  double cycles(double s) const;
  /// InputError naming the rule broken.
  void validate() const;
  /// EN 1993-1-9's curve of a detail category [MPa] (36, 40, 45, 50, 56, 63, 71, 80, 90, 100,
  /// 112, 125, 140, 160); InputError listing them for any other.
  static SnCurve en1993_1_9(double category_mpa);
  /// A user curve: Δσ_C [Pa] at n_c cycles with slope m1 down to n_d, slope m2 down to n_l,
  /// no damage below (m2 = 0 or n_l <= n_d: the curve ends at n_d).
  static SnCurve two_slopes(double delta_c_pa, double m1, double m2, double n_c = 2e6, double n_d = 5e6, double n_l = 1e8);
};

/// EN 1993-1-9's curve of detail category `detail_mpa`, or a user curve of Δσ_C = `delta_c_mpa` at
/// 2e6 cycles with slopes m1 and m2 (SnCurve::two_slopes, named with its values): exactly one of
/// the two (InputError otherwise, naming the CLI's --detail and --delta-c-mpa).
SnCurve sn_curve(std::optional<double> detail_mpa, std::optional<double> delta_c_mpa, double m1 = 3.0, double m2 = 5.0);

/// The detail categories of EN 1993-1-9 Tables 8.1–8.10 [MPa].
const std::vector<double>& en1993_1_9_categories();

/// The Palmgren–Miner sum of cycles as they are counted: ranges in the history's unit times
/// `to_pa` (e.g. E·1e-6 for microstrain, 1e6 for MPa) and γFf·γMf, against `curve`.
struct MinerSum {
  MinerSum(SnCurve curve, double to_pa, double gamma_ff = 1.0, double gamma_mf = 1.0);
  void add(const signal::Cycle& c);
  double damage = 0.0;        ///< D = Σ n_i / N_i
  double cycles = 0.0;        ///< counted (half cycles as 0.5)
  double damaging = 0.0;      ///< of them above the cut-off
  double max_range_pa = 0.0;  ///< the largest range counted, factored [Pa]
  const SnCurve& curve() const { return curve_; }

 private:
  SnCurve curve_;
  double factor_;
};

/// The equivalent constant range at 2·10⁶ cycles of a damage D against `curve`'s first branch
/// (Δσ_E,2 = Δσ_C (D)^(1/m) for the EN curve): what EN 1993-1-9's check compares with Δσ_C.
double equivalent_range_2e6(double damage, const SnCurve& curve);

/// How a history's cycles are counted and what they damage.
struct FatigueCount {
  SnCurve curve;
  double gamma_ff = 1.0, gamma_mf = 1.0;  ///< partial factors (EN 1993-1-9 γFf, γMf)
  signal::RainflowMethod method = signal::RainflowMethod::three_point;
  double hysteresis_mpa = 0.0;                     ///< reversals smaller than this are no turning points
  double range_bin_mpa = 1.0, mean_bin_mpa = 5.0;  ///< bins of the range–mean matrix, > 0
};

/// The cycles of one history and their damage.
struct CountedHistory {
  MinerSum miner;
  /// (range bin, mean bin) → cycles, the bins FatigueCount's widths in MPa without the factors
  /// (bin k holds [k·width, (k+1)·width)).
  std::map<std::pair<long, long>, double> bins;
};

/// Counts `x` (in a unit that times `to_pa` is Pa), streamed, and sums its damage.
CountedHistory count_history(const Vector& x, double to_pa, const FatigueCount& f);

/// A traffic mix (EN 1991-2 Annex D Tables D.1–D.3, or a line's own): trains a day at their speeds.
struct MixTrain {
  std::string name;      ///< as the mix names it (its file's stem)
  load::Train train;
  double per_day = 0.0;  ///< passages a day, >= 0
  double speed = 0.0;    ///< [m/s] > 0
};
struct TrafficMix {
  std::string title;
  std::vector<MixTrain> trains;
};

/// One train of a mix: the damage of one passage, and of a year.
struct TrainDamage {
  std::string name;
  double per_day = 0.0, speed = 0.0;
  std::optional<CountedHistory> passage;  ///< one passage's cycles (none when the run failed: `error`)
  double per_year = 0.0;   ///< passage damage × per_day × 365
  std::string error;       ///< why the train's run failed (empty: it ran)
};
struct MixDamage {
  std::vector<TrainDamage> trains;  ///< in the mix's order
  double per_year = 0.0;            ///< Σ over the trains that ran
  std::size_t n_failed = 0;         ///< trains whose run failed: per_year then lacks them
  /// Years of this traffic to D = 1 (∞ without damage).
  double years_to_d1() const { return per_year > 0.0 ? 1.0 / per_year : std::numeric_limits<double>::infinity(); }
};

/// [Pa] A history whose largest stress range under traffic lies outside these is in another unit
/// than its name says: below 0.1 MPa (0.5 µε on steel, quieter than any strain gauge's noise under
/// a train: ε read as µε, Pa as MPa, a section modulus in cm³ as m³), above 1000 MPa (beyond any
/// structural steel's elastic range: µε read as ε, MPa as Pa).
constexpr double kMinPlausibleRangePa = 1e5;
constexpr double kMaxPlausibleRangePa = 1e9;
/// A warning naming `what` (a channel, or a mix's station), or "": its largest range [Pa] outside
/// [kMinPlausibleRangePa, kMaxPlausibleRangePa] (0: no cycle, not judged). Either way the damage
/// would be silently wrong: 0 below, absurd above.
std::string stress_range_warning(const std::string& what, double max_range_pa);

/// [Pa] per unit of a history named `channel` in `unit`: Pa 1, µε ("ue") E·1e-6, N·m ("Nm") 1/W.
/// InputError for a moment without W, or a unit that is none of these (naming what fatigue takes).
double stress_per_unit(const std::string& channel, const std::string& unit, double youngs_modulus_pa,
                       std::optional<double> section_modulus_m3);

/// The load effect of `m` (prepared with load effects) that `channel` names: a deck station's
/// "<station>_moment" or "<station>_strain" (history.csv's column without its unit). InputError
/// listing those there are otherwise.
std::size_t fatigue_effect(const PreparedModel& m, const std::string& channel);

/// Every train of `mix` over the model at its speed (simulate() with `settings`): the history of
/// load effect `effect` (an index into m.effects: prepare_model with load effects), times `to_pa`,
/// counted and summed per passage and per year of 365 days. A train whose run fails is recorded
/// with its message and left out of the sum (n_failed says so); a cancelled call (core/cancel.hpp)
/// throws Cancelled. Trains run on `threads`; `progress` (may be empty) hears trains done of all.
MixDamage traffic_damage(const PreparedModel& m, const RunSettings& settings, std::size_t effect, double to_pa,
                         const TrafficMix& mix, const FatigueCount& f, int threads, const ProgressSink& progress = {});

}  // namespace viaduct::study

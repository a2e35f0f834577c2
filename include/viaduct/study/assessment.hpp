#pragma once
/// \file The EN 1991-2 6.4 / EN 1990 A2 dynamic check as a workflow (plan → result), shared by
/// `viaduct assess` and the Python package (issue #37): io::plan_assessment reads the [assess]
/// keys and forms the plan (damping, cut-off, trains and their speeds, mass cases);
/// run_assessment runs the sweep with load effects, the statics of the nominal model and LM71,
/// and forms every check; io::write_assessment writes the tables and the report. The numbers of
/// the standard are in study/assess.hpp.

#include <atomic>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "viaduct/core/log.hpp"
#include "viaduct/model/modes.hpp"
#include "viaduct/study/assess.hpp"
#include "viaduct/study/influence.hpp"
#include "viaduct/study/sweep.hpp"

namespace viaduct::study {

/// The [assess] keys, resolved (docs/scenarios.md, "assess").
struct AssessConfig {
  double line_speed = 0.0;  ///< [m/s]
  DeckType deck = DeckType::prestressed;
  std::string track = "ballasted";
  double acc_limit = 3.5;  ///< [m/s²]
  Edition edition = Edition::en2003;  ///< whose clauses the report and checks.csv cite (assess.edition)
  double speed_factor = 1.2;  ///< [-] the highest speed over the line speed (6.4.6.2)
  double v_min = 0.0, v_max = 0.0, step = 0.0, fine_step = 0.0;  ///< [m/s]
  double band = 0.03;                                             ///< [-] refinement band around each resonance
  int harmonics = 4;
  std::optional<double> damping_ratio;
  bool interaction_damping = true;
  double ballast = 0.0, ballast_lower = 1.0, ballast_upper = 1.3;  ///< [kg/m] (< 0: not given), [-]
  /// EN 1991-2 6.4.6.3.2's bounds from the ballast bed (used when ballast_width is given): the
  /// bed's width carried by the model [m], its depth [m], the nominal, minimum and saturated
  /// densities [kg/m³] and the depth's increase for the upper bound [-] (+30 %).
  std::optional<double> ballast_width;
  double ballast_depth = 0.5, density_nominal = 1800.0, density_min = 1700.0, density_saturated = 2100.0, depth_increase = 0.3;
  double alpha = 1.0;                                              ///< LM71 classification factor
  bool careful = true;                                             ///< Φ2 (careful maintenance), else Φ3
  double deflection_ratio = 600.0, rotation_limit = 6.5e-3;        ///< [-], [rad]
  std::optional<double> determinant_length;                        ///< [m] Lφ of every quantity
  std::string comfort_level = "very-good";
  double comfort_limit = 1.0;    ///< [m/s²] b_v, EN 1990 A2.4.4.3.1 Table A2.9 (to confirm)
  double unloading_limit = 1.0;  ///< [-] (P0 − Pmin)/P0
  /// L/δ of EN 1990 Fig. A2.3 for the span and speed at b_v = 1 m/s² (not carried: unset, the
  /// comfort-by-deflection rows say the limit is to be given).
  std::optional<double> comfort_deflection_ratio;
};

/// [m/s²] b_v of a level of comfort (EN 1990 A2.4.4.3.1 Table A2.9, to confirm): very-good 1.0,
/// good 1.3, acceptable 2.0.
double comfort_limit_of(const std::string& level);

/// What the assessment decided before running: damping, cut-off, trains, masses (for the report).
struct AssessPlan {
  AssessConfig config;
  double span_for_damping = 0.0, zeta_table = 0.0, zeta_extra = 0.0, zeta = 0.0;
  bool zeta_given = false;
  double f1 = 0.0, f3 = 0.0, f_cut = 0.0;  ///< [Hz] f1 of the structure; f3 and the cut-off of the governing member
  int f3_span = 0;                          ///< the member f3 belongs to (1-based span; 0: the continuous deck)
  std::vector<MemberFrequencies> members;   ///< each member's f1, f3 and cut-off (A2.4.4.2.1(4))
  std::vector<model::DeckMode> deck_modes;  ///< of the nominal model
  std::vector<std::string> notes;           ///< what the report must say (defaults taken, limits)
  /// The model's and the step's warnings (study::scenario_warnings of the nominal model at every
  /// speed run: f1 outside Fig. 6.10, a deflection beyond L/100, a mass under 500 kg/m, …): a unit
  /// slip gets a warning printed, in the manifest and at the top of the report.
  std::vector<std::string> warnings;
  std::vector<Variant> variants;            ///< the mass cases, each with every train and its speeds
  /// [m] each train's characteristic distance (load::characteristic_distance; 0: none), in the
  /// variants' trains' order: computed once for the speeds and the resonance-speed table.
  std::vector<double> train_distance;
  std::vector<std::string> real_trains;     ///< the scenario's trains besides HSLM
  /// [kg/m] the ballast included in bridge.mass_per_m and the lower and upper bounds' ballast (all
  /// 0 when not bounded), and how they were formed (for the report).
  double ballast_nominal = 0.0, ballast_lower = 0.0, ballast_upper = 0.0;
  std::string ballast_basis;
};

/// Each train's speeds: the config's grid, refined around f·d/j for the deck modes of `sc` below
/// f_cut [Hz] (j up to config.harmonics, d = `distances`' entry for the train: its characteristic
/// distance, load::characteristic_distance; 0: no refinement).
std::vector<std::vector<double>> assessment_train_speeds(const std::vector<double>& distances, const Scenario& sc,
                                                         const AssessConfig& c, double f_cut);

/// One row of checks.csv and of the report's summary.
struct AssessCheck {
  std::string check, quantity;
  double value = 0.0, limit = 0.0;  ///< in the quantity's unit (its name's suffix)
  std::string verdict, variant, train;
  double speed = std::numeric_limits<double>::quiet_NaN();  ///< [m/s] the governing case's (NaN: none)
  std::string clause;
  double utilisation() const { return limit > 0.0 ? value / limit : std::numeric_limits<double>::quiet_NaN(); }
};

/// The worst φ′dyn of one (variant, train, quantity) over the speeds.
struct AssessIncrement {
  std::string variant, train, quantity;
  double dynamic = 0.0, quasi_static = 0.0, speed = 0.0;  ///< max |.|, [m/s] where the dynamic peak is
  double phi() const { return quasi_static > 0.0 ? dynamic / quasi_static - 1.0 : std::numeric_limits<double>::quiet_NaN(); }
};

/// The sleeper layout at the joints (issue #20 part 3): identical spans coupled through the track
/// have near-equal first modes, and which span dominates the lower one flips with where the
/// sleepers sit; the per-span peaks follow, their sum and the resonance speeds do not.
struct LayoutSensitivity {
  bool near = false;  ///< two spans' modes of the same order within 2 %
  int span_a = 0, span_b = 0;
  double split = 0.0;  ///< their relative frequency difference
  std::string train, variant;
  double speed = 0.0;                      ///< [m/s] the governing acceleration case
  std::vector<double> offsets;             ///< [m] track.first_sleeper_offset
  std::vector<std::vector<double>> peaks;  ///< [offset][station] max |acc| [m/s²]
};

struct AssessOptions {
  int threads = 1;        ///< >= 1
  ProgressSink progress;  ///< optional, per case
  bool layout = true;     ///< run the sleeper-layout sensitivity when two spans' modes are near
  /// Optional: cases not started when it becomes true fail with "cancelled" (SweepOptions::cancel).
  const std::atomic<bool>* cancel = nullptr;
};

/// Everything an assessment found.
struct AssessResult {
  AssessPlan plan;
  SweepResult sweep;
  std::vector<AssessCheck> checks;
  std::vector<AssessIncrement> increments;
  LayoutSensitivity layout;
  /// The nominal (first) mass case's scenario.
  const Scenario& nominal() const { return plan.variants.front().scenario; }
};

/// Runs the plan: the sweep of every mass case with load effects, the nominal model's statics
/// (influence lines, LM71, permanent bearing loads), every check, the layout sensitivity.
/// InputError/SolverError as the sweep's; failed cases are in sweep.failures.
AssessResult run_assessment(AssessPlan plan, const AssessOptions& options);

/// One box of EN 1991-2 Fig. 6.9 (is a dynamic analysis required?), answered for the bridge.
struct FlowAnswer {
  std::string question, answer;
};

/// Fig. 6.9 as far as a 2D model answers it (REFERENCE.md §9; to confirm against the text): the
/// boxes passed, whether the chart requires a dynamic analysis, and Fig. 6.10's limits per member.
struct DynamicAnalysisNeed {
  std::vector<FlowAnswer> steps;
  bool required = true;  ///< false only when the chart's boxes that were answered exempt the bridge
  std::string conclusion;
  struct Member {
    int span = 0;  ///< 1-based; 0: the continuous deck
    /// [m] the span (a continuous deck: its determinant length Lφ, to confirm), [Hz] n0 and Fig. 6.10's limits
    double length = 0.0, f1 = 0.0, lower = 0.0, upper = 0.0;
    bool within() const { return f1 >= lower && f1 <= upper; }
  };
  std::vector<Member> members;
};

/// Fig. 6.9 for the plan's line speed, deck (continuous or a chain) and members' f1.
DynamicAnalysisNeed dynamic_analysis_need(const AssessPlan& p, const Scenario& nominal);

/// A resonance speed v = f·d/j of one train (6.4.6.2; the speeds are refined around them).
struct ResonanceSpeed {
  std::string train;
  double distance = 0.0;     ///< [m] the train's characteristic distance d
  double frequency_hz = 0.0;  ///< [Hz] f of the deck mode
  int mode = 0;               ///< 1-based index among the plan's deck modes
  int harmonic = 1;           ///< j
  double speed = 0.0;         ///< [m/s]
};

/// Every f·d/j within the plan's speed range, for the nominal model's deck modes below the
/// cut-off and j up to config.harmonics, per train in the order run, d from p.train_distance
/// (std::logic_error when the plan does not hold one per train).
std::vector<ResonanceSpeed> resonance_speeds(const AssessPlan& p);

/// The SI unit of a quantity from its name's suffix, as checks.csv states it ("m/s2", "m", "N m",
/// "N", "rad", "ue", "Hz", "mm/3m"; "-" for a ratio).
std::string quantity_unit(const std::string& quantity);

/// Lφ of a quantity (6.4.5.3, Table 6.2): AssessConfig::determinant_length when given; on a
/// continuous deck Table 6.2 for girders continuous over n spans (to confirm); else the length of
/// the quantity's span.
double assessment_determinant_length(const std::string& quantity, const Scenario& sc, const AssessConfig& c);

/// A number as the report shows it: `significant` digits, "—" when it is not finite.
std::string shown_number(double x, int significant = 4);

/// A value in the unit a reader expects (mm, kN, kN·m, mrad, m/s², µε), from the quantity's
/// suffix; "—" for a value that is not finite.
std::string shown_value(const std::string& quantity, double x);

}  // namespace viaduct::study

#pragma once
/// \file Trains as lists of constant axle loads.

#include <array>
#include <string>
#include <vector>

namespace viaduct::load {

/// A train of constant axle loads. Axle i is `offset[i]` metres behind the first axle.
/// Most axles a train may have (a 1.5 km freight train has about 400).
constexpr std::size_t kMaxAxles = 10000;

/// A 2D coach (REFERENCE.md §8; per rail line, both sides summed): a car body (bounce, pitch) on
/// two bogies (bounce, pitch), each on two wheelsets; a primary suspension per axle and a
/// secondary one per bogie. Its centre of mass midway between the bogies: each axle carries a
/// quarter of the body, half a bogie and its wheelset.
struct CoachSpec {
  std::string name;
  double body_mass = 0.0;            ///< [kg] > 0
  double body_pitch_inertia = 0.0;   ///< [kg·m²] > 0
  double bogie_spacing = 0.0;        ///< [m] between the bogie centres, > wheelbase
  double bogie_mass = 0.0;           ///< [kg] > 0
  double bogie_pitch_inertia = 0.0;  ///< [kg·m²] > 0
  double wheelbase = 0.0;            ///< [m] a bogie's axle spacing, > 0
  double wheelset_mass = 0.0;        ///< [kg] > 0
  double primary_k = 0.0;            ///< [N/m] per axle, > 0
  double primary_c = 0.0;            ///< [N·s/m] per axle, >= 0
  double secondary_k = 0.0;          ///< [N/m] per bogie, > 0
  double secondary_c = 0.0;          ///< [N·s/m] per bogie, >= 0
  /// [m] from a coach's first axle to the next coach's first axle, > bogie_spacing + wheelbase.
  double length = 0.0;
  double mass() const { return body_mass + 2.0 * bogie_mass + 4.0 * wheelset_mass; }  ///< [kg]
  /// [N] static load of each axle under gravity g [m/s²].
  double axle_load(double g) const { return g * (body_mass / 4.0 + bogie_mass / 2.0 + wheelset_mass); }
  /// [m] the axles behind the coach's first: 0, wheelbase, bogie_spacing, bogie_spacing + wheelbase.
  std::array<double, 4> axle_offsets() const {
    return {0.0, wheelbase, bogie_spacing, bogie_spacing + wheelbase};
  }
  /// Throws InputError naming the coach, the field, its value and the violated constraint.
  void validate() const;
};

/// [m/s²] standard gravity, as REFERENCE.md's static axle loads use it.
constexpr double kGravity = 9.81;

struct Train {
  std::string name;
  std::vector<double> offset;  ///< [m] first 0, non-decreasing
  std::vector<double> load;    ///< [N] per axle, > 0
  /// The coaches, head first, when the train is made of vehicles (coach_train()); empty for a
  /// list of axles. Coach k's axles are axles 4k … 4k + 3 (articulated: bogie j's axles are 2j
  /// and 2j + 1, and coach k rests on bogies k and k + 1).
  std::vector<CoachSpec> coaches;
  /// True when neighbouring coaches share a bogie (Jacobs bogies): n coaches on n + 1 bogies.
  bool articulated = false;

  std::size_t n_axles() const { return offset.size(); }
  double length() const { return offset.empty() ? 0.0 : offset.back(); }  ///< [m] first to last axle
  double total_load() const;                                               ///< [N]
  /// Throws InputError naming the train and the broken rule.
  void validate() const;
};

/// Eurocode HSLM-A train (EN 1991-2 Annex E) from its table row: N coaches of length D with
/// articulated bogies of axle spacing d, axle load P. Power cars: axles at 0, 3, 14, 17 m;
/// 3.525 m to the end coach's first axle; symmetric tail; 2N + 14 axles.
struct HslmRow {
  int n_coaches = 0;          ///< N
  double coach_length = 0.0;  ///< [m] D
  double bogie_spacing = 0.0; ///< [m] d
  double axle_load = 0.0;     ///< [N] P
};
Train hslm_a(const std::string& name, const HslmRow& row);
/// The ten table rows A1…A10 (REFERENCE.md §3); index 1..10.
HslmRow hslm_a_row(int number);

/// `n_coaches` coaches of `coach` one behind the other (coach k's first axle k·length behind the
/// head), with their static axle loads under gravity g. InputError for an invalid coach or count.
Train coach_train(const std::string& name, const CoachSpec& coach, int n_coaches, double g = kGravity);

/// An articulated train: `n_coaches` bodies of `coach` on n + 1 shared bogies (Jacobs bogies,
/// as the TGV's), bogie centres bogie_spacing apart (coach.length is not used: a body spans from
/// one pivot to the next). Each body's weight goes half to each of its bogies: an inner axle
/// carries g (body/2 + bogie/2 + wheelset), an end axle g (body/4 + bogie/2 + wheelset).
/// InputError for an invalid coach or count.
Train articulated_train(const std::string& name, const CoachSpec& coach, int n_coaches, double g = kGravity);

/// `n_axles` equal loads `load` [N] spaced `spacing` [m].
Train regular_train(const std::string& name, int n_axles, double spacing, double load);

/// The train's characteristic distance d [m]: the wavelength λ in [min_m, max_m] at which its
/// loads add up best, |Σ P_k exp(−2πi x_k/λ)| (the first term of ERRI D214's train signature);
/// the longest λ within 1 % of the best, so that a regular train gives its spacing, not a
/// fraction of it. Resonance of a span with frequency f is expected at v = f·d/j. 0 for fewer
/// than two axles.
double characteristic_distance(const Train& t, double min_m = 5.0, double max_m = 50.0);

}  // namespace viaduct::load

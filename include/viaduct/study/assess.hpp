#pragma once
/// \file The numbers of the EN 1991-2 dynamic check (2003 edition numbering; docs/assess.md and
/// REFERENCE.md §9): damping lower bounds, the additional damping standing for the vehicle–bridge
/// interaction, dynamic factors, the frequency cut-off, and the speeds to run. `viaduct assess`
/// puts them together; each function names its clause.

#include <optional>
#include <string>
#include <vector>

#include "viaduct/model/structure.hpp"

namespace viaduct::study {

/// Deck types of EN 1991-2 Table 6.6 (steel and composite share a row; so do reinforced and
/// filler-beam concrete).
enum class DeckType { steel, composite, prestressed, reinforced, filler_beam };
/// "steel" | "composite" | "prestressed" | "reinforced" | "filler-beam"; InputError otherwise.
DeckType deck_type_of(const std::string& name);
const char* deck_type_name(DeckType t);

/// The edition of EN 1991-2 (with the EN 1990 Annex A2 it goes with) whose clauses an assessment
/// cites (assess.edition). The numbers are the 2003 edition's in both: the 2023 edition (second
/// generation) moves the railway rules into Section 8 and revises values that viaduct cannot
/// confirm without its text; those values stay keys (REFERENCE.md §9).
enum class Edition { en2003, en2023 };
/// "2003" | "2023"; InputError otherwise.
Edition edition_of(const std::string& name);
const char* edition_name(Edition e);

/// What the assessment cites a clause for.
enum class Clause {
  trains,              ///< HSLM-A and the real trains
  hslm_b,              ///< HSLM-B, spans under 7 m
  speeds,              ///< the speeds to 1.2 × the line speed, refined near resonance
  dynamic_analysis,    ///< when a dynamic analysis is required (V > 200 km/h)
  damping,             ///< the damping lower bounds
  interaction_damping, ///< the additional damping for the interaction not modelled
  mass,                ///< the lower and upper mass bounds (ballast)
  lm71,                ///< Load Model 71 and α
  dynamic_factor,      ///< Φ2, Φ3
  determinant_length,  ///< Lφ
  irregularities,      ///< φ″
  flow_chart,          ///< is a dynamic analysis required
  frequency_limits,    ///< the limits of n0
  speed_frequency_ratio,  ///< (v/n0)lim of the flow chart
  increments,          ///< φ′dyn
  design_effect,       ///< (1 + φ′dyn + φ″/2) × the train against Φ × LM71
  deck_acceleration,   ///< the peak deck acceleration limits
  cut_off,             ///< the frequencies to consider, f3 of the member
  deformation,         ///< vertical deflection and end rotation
  comfort_acceleration,///< car-body acceleration b_v
  comfort_deflection,  ///< passenger comfort by deck deflection
  twist,               ///< deck twist
  lateral,             ///< first lateral frequency
};

/// Where `c` is in edition `e`. 2003: EN 1991-2:2003's clause (e.g. "EN 1991-2 6.4.6.5(3)") or
/// EN 1990:2002/A1:2005's ("EN 1990 A2.4.4.2.1(4)"). 2023: the clause where it is known (HSLM-A
/// Fig. 8.12 and Table 8.4, the determinant length Table 8.2), otherwise the part that holds it
/// with the 2003 clause named and "to confirm" ("EN 1991-2:2023 Section 8 [2003: 6.4.6.2; to
/// confirm]"), never a guessed number.
std::string cite(Edition e, Clause c);
/// The same as a sentence cites it within its document: 2003 "Table 6.6", "6.4.6.2"; 2023 as cite().
std::string cite_brief(Edition e, Clause c);
/// True when cite(e, c) is a clause viaduct carries as the text has it (every 2003 one; in 2023
/// only the HSLM-A figure and table and the determinant length's table).
bool clause_known(Edition e, Clause c);

/// Lower bound of the damping ratio [-] for span L [m], Table 6.6: steel/composite 0.5 + 0.125
/// (20 − L) %, prestressed 1.0 + 0.07 (20 − L) %, reinforced/filler-beam 1.5 + 0.07 (20 − L) % for
/// L < 20 m; 0.5, 1.0, 1.5 % from 20 m on.
double damping_lower_bound(DeckType t, double span_m);

/// Additional damping Δζ [-] for L < 30 m when the vehicle–bridge interaction is not modelled
/// (Fig. 6.8, Eq. 6.13): (0.0187 L − 0.00064 L²) / (1 − 0.0441 L − 0.0044 L² + 0.000255 L³) %;
/// 0 from 30 m on.
double additional_damping(double span_m);

/// Dynamic factors of 6.4.5.2 for the determinant length Lφ [m]: Φ2 = 1.44 / (√Lφ − 0.2) + 0.82
/// within [1.00, 1.67] (carefully maintained track), Φ3 = 2.16 / (√Lφ − 0.2) + 0.73 within
/// [1.00, 2.00] (standard maintenance).
double phi2(double length_m);
double phi3(double length_m);

/// Determinant length Lφ [m] of a continuous deck of n ≥ 2 spans (Table 6.2, girders continuous over n spans; to confirm):
/// k × the mean span, k = 1.2, 1.3, 1.4, 1.5 for n = 2, 3, 4, ≥ 5, and not less than the longest
/// span. One span: its length. InputError for no span or a non-positive length.
double continuous_determinant_length(const std::vector<double>& spans_m);

/// φ″ of Annex C (track irregularities, to confirm against the text): α/100 [56 e^{−(Lφ/10)²} +
/// 50 (Lφ n0/80 − 1) e^{−(Lφ/20)²}], α = v/22 for v ≤ 22 m/s and 1 above, never below 0. v in
/// m/s, n0 [Hz] the first natural frequency.
double phi_irregularities(double length_m, double speed_mps, double n0_hz);

/// The frequencies to consider (A2.4.4.2.1(4)): max(30 Hz, 1.5 f1, f3) [Hz].
double cutoff_frequency(double f1_hz, double f3_hz);

/// The frequencies of one member (A2.4.4.2.1(4): f3 is the third mode of the member).
struct MemberFrequencies {
  int span = 0;            ///< 1-based; 0: the whole continuous deck
  double f1 = 0.0;         ///< [Hz] the member's first bending frequency
  double f3 = 0.0;         ///< [Hz] its third bending mode (0 when the model has no third)
  int f3_order = 0;        ///< the bending order of the mode taken as f3 (3; another when no third was found)
  double cutoff = 0.0;     ///< [Hz] max(30, 1.5 f1, f3)
};

/// Each member's f1, f3 and cut-off. A chain of simply supported spans: each span is a member,
/// modelled alone on its bearings with the track over it (its own third bending mode, whatever
/// its neighbours: among identical spans the structure's third mode is another span's first).
/// A continuous deck (bridge.continuous): one member, the deck, its third bending mode (docs/
/// assess.md states this reading). SolverError from the eigensolver.
std::vector<MemberFrequencies> member_frequencies(const model::BridgeParams& bridge,
                                                  const std::optional<model::TrackParams>& track);

/// Speeds [m/s] of an assessment: v_min, v_min + step, ... up to v_max (v_max included), plus
/// every fine_step within ±band (a fraction) of each resonance speed, sorted, without duplicates
/// closer than fine_step/100. InputError for non-positive or inconsistent values.
std::vector<double> assessment_speeds(double v_min, double v_max, double step, double fine_step,
                                      const std::vector<double>& resonances, double band);

}  // namespace viaduct::study

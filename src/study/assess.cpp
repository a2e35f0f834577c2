#include "viaduct/study/assess.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "viaduct/core/error.hpp"
#include "viaduct/model/modes.hpp"

namespace viaduct::study {

DeckType deck_type_of(const std::string& name) {
  if (name == "steel") return DeckType::steel;
  if (name == "composite") return DeckType::composite;
  if (name == "prestressed") return DeckType::prestressed;
  if (name == "reinforced") return DeckType::reinforced;
  if (name == "filler-beam") return DeckType::filler_beam;
  throw InputError("deck type '" + name +
                   "' is not in EN 1991-2 Table 6.6: steel, composite, prestressed, reinforced or filler-beam");
}

const char* deck_type_name(DeckType t) {
  switch (t) {
    case DeckType::steel: return "steel";
    case DeckType::composite: return "composite";
    case DeckType::prestressed: return "prestressed";
    case DeckType::reinforced: return "reinforced";
    case DeckType::filler_beam: return "filler-beam";
  }
  return "?";
}

Edition edition_of(const std::string& name) {
  if (name == "2003") return Edition::en2003;
  if (name == "2023") return Edition::en2023;
  throw InputError("edition '" + name + "' is not one viaduct cites: 2003 (EN 1991-2:2003, EN 1990 Annex A2) or 2023 (EN 1991-2:2023)");
}

const char* edition_name(Edition e) { return e == Edition::en2023 ? "2023" : "2003"; }

namespace {

// Each clause: the 2003 reference in full (EN 1991-2:2003, or EN 1990:2002/A1:2005 Annex A2) and
// as a sentence cites it, and the 2023 ones where they are known; empty: the 2023 text places it
// in Section 8 (EN 1991-2) or Annex A.2 (EN 1990) at a clause to confirm.
struct ClauseRef {
  Clause clause;
  const char *full2003, *brief2003, *full2023, *brief2023;
};

const ClauseRef kClauses[] = {
    {Clause::trains, "EN 1991-2 6.4.6.1.1, Annex E", "6.4.6.1.1, Annex E",
     "EN 1991-2:2023 Section 8, Fig. 8.12 and Table 8.4 (HSLM-A)", "Fig. 8.12, Table 8.4"},
    {Clause::hslm_b, "EN 1991-2 6.4.6.1.1, Fig. E.4", "Fig. E.4", "", ""},
    {Clause::speeds, "EN 1991-2 6.4.6.2", "6.4.6.2", "", ""},
    {Clause::dynamic_analysis, "EN 1991-2 6.4.6", "6.4.6", "", ""},
    {Clause::damping, "EN 1991-2 Table 6.6", "Table 6.6", "", ""},
    {Clause::interaction_damping, "EN 1991-2 Fig. 6.8, Eq. 6.13", "Fig. 6.8, Eq. 6.13", "", ""},
    {Clause::mass, "EN 1991-2 6.4.6.3.2", "6.4.6.3.2", "", ""},
    {Clause::lm71, "EN 1991-2 6.3.2", "6.3.2", "", ""},
    {Clause::dynamic_factor, "EN 1991-2 6.4.5.2", "6.4.5.2", "", ""},
    {Clause::determinant_length, "EN 1991-2 6.4.5.3, Table 6.2", "Table 6.2", "EN 1991-2:2023 Section 8, Table 8.2", "Table 8.2"},
    {Clause::irregularities, "EN 1991-2 Annex C", "Annex C", "", ""},
    {Clause::flow_chart, "EN 1991-2 6.4.4, Fig. 6.9", "6.4.4", "", ""},
    {Clause::frequency_limits, "EN 1991-2 6.4.4, Fig. 6.10", "Fig. 6.10", "", ""},
    {Clause::speed_frequency_ratio, "EN 1991-2 Annex F", "Annex F", "", ""},
    {Clause::increments, "EN 1991-2 6.4.6.5", "6.4.6.5", "", ""},
    {Clause::design_effect, "EN 1991-2 6.4.6.5(3)", "6.4.6.5(3)", "", ""},
    {Clause::deck_acceleration, "EN 1990 A2.4.4.2.1(4)", "A2.4.4.2.1(4)", "", ""},
    {Clause::cut_off, "EN 1990 A2.4.4.2.1(4)", "A2.4.4.2.1(4)", "", ""},
    {Clause::deformation, "EN 1990 A2.4.4.2.3", "A2.4.4.2.3", "", ""},
    {Clause::comfort_acceleration, "EN 1990 A2.4.4.3.1, Table A2.9", "Table A2.9", "", ""},
    {Clause::comfort_deflection, "EN 1990 A2.4.4.3.2, Fig. A2.3", "Fig. A2.3", "", ""},
    {Clause::twist, "EN 1990 A2.4.4.2.2, Table A2.7", "Table A2.7", "", ""},
    {Clause::lateral, "EN 1990 A2.4.4.2.4(3)", "A2.4.4.2.4(3)", "", ""},
};

const ClauseRef& clause_ref(Clause c) {
  for (const ClauseRef& r : kClauses)
    if (r.clause == c) return r;
  throw std::logic_error("a clause without its reference");  // every enumerator is in kClauses (test)
}

// 2023 without a known clause: the document's part that holds it, the 2003 clause, to confirm.
std::string unknown_2023(const ClauseRef& r, const std::string& was) {
  const bool en1990 = std::string(r.full2003).rfind("EN 1990 ", 0) == 0;
  return std::string(en1990 ? "EN 1990:2023 Annex A.2 [2002/A1: " : "EN 1991-2:2023 Section 8 [2003: ") + was + "; to confirm]";
}

}  // namespace

std::string cite(Edition e, Clause c) {
  const ClauseRef& r = clause_ref(c);
  if (e == Edition::en2003) return r.full2003;
  if (*r.full2023) return r.full2023;
  const std::string full = r.full2003;
  return unknown_2023(r, full.substr(full.find(' ', full.find(' ') + 1) + 1));  // the clause past "EN 199x(-2) "
}

std::string cite_brief(Edition e, Clause c) {
  const ClauseRef& r = clause_ref(c);
  if (e == Edition::en2003) return r.brief2003;
  if (*r.brief2023) return r.brief2023;
  return unknown_2023(r, r.brief2003);
}

bool clause_known(Edition e, Clause c) { return e == Edition::en2003 || *clause_ref(c).full2023; }

double damping_lower_bound(DeckType t, double L) {
  require_positive(L, "span length [m]");
  const double short_by = std::max(0.0, 20.0 - L);
  double pct = 0.0;
  switch (t) {
    case DeckType::steel:
    case DeckType::composite: pct = 0.5 + 0.125 * short_by; break;
    case DeckType::prestressed: pct = 1.0 + 0.07 * short_by; break;
    case DeckType::reinforced:
    case DeckType::filler_beam: pct = 1.5 + 0.07 * short_by; break;
  }
  return pct / 100.0;
}

double additional_damping(double L) {
  require_positive(L, "span length [m]");
  if (L >= 30.0) return 0.0;
  const double pct = (0.0187 * L - 0.00064 * L * L) / (1.0 - 0.0441 * L - 0.0044 * L * L + 0.000255 * L * L * L);
  return pct / 100.0;
}

double phi2(double L) {
  require_positive(L, "determinant length [m]");
  return std::clamp(1.44 / (std::sqrt(L) - 0.2) + 0.82, 1.0, 1.67);
}

double phi3(double L) {
  require_positive(L, "determinant length [m]");
  return std::clamp(2.16 / (std::sqrt(L) - 0.2) + 0.73, 1.0, 2.0);
}

double continuous_determinant_length(const std::vector<double>& spans) {
  if (spans.empty()) throw InputError("a continuous deck needs at least one span");
  double sum = 0.0, longest = 0.0;
  for (double L : spans) {
    require_positive(L, "span length [m]");
    sum += L;
    longest = std::max(longest, L);
  }
  const std::size_t n = spans.size();
  if (n == 1) return longest;
  const double k = n == 2 ? 1.2 : n == 3 ? 1.3 : n == 4 ? 1.4 : 1.5;
  return std::max(k * sum / static_cast<double>(n), longest);
}

double phi_irregularities(double L, double v, double n0) {
  require_positive(L, "determinant length [m]");
  require_positive(v, "speed [m/s]");
  require_positive(n0, "first natural frequency [Hz]");
  const double alpha = v <= 22.0 ? v / 22.0 : 1.0;
  const double a = L / 10.0, b = L / 20.0;
  const double phi = alpha / 100.0 * (56.0 * std::exp(-a * a) + 50.0 * (L * n0 / 80.0 - 1.0) * std::exp(-b * b));
  return std::max(phi, 0.0);
}

double cutoff_frequency(double f1, double f3) { return std::max({30.0, 1.5 * f1, f3}); }

namespace {
// f1 and f3 of one model's deck: its first bending mode and its first of order 3 (the third deck
// bending mode when the orders cannot be told).
MemberFrequencies member_of(const model::Structure& s, int span) {
  MemberFrequencies m;
  m.span = span;
  const std::vector<model::DeckMode> modes = model::deck_bending_modes(s, 8);
  if (modes.empty()) throw SolverError("assess: a member without a deck bending mode (span " + std::to_string(span) + ")");
  m.f1 = modes.front().frequency_hz;
  for (const auto& d : modes)
    if (d.bending.order == 3) {
      m.f3 = d.frequency_hz, m.f3_order = 3;
      break;
    }
  if (m.f3_order == 0 && modes.size() >= 3) m.f3 = modes[2].frequency_hz, m.f3_order = modes[2].bending.order;
  m.cutoff = cutoff_frequency(m.f1, m.f3);
  return m;
}
}  // namespace

std::vector<MemberFrequencies> member_frequencies(const model::BridgeParams& bridge, const std::optional<model::TrackParams>& track) {
  if (bridge.spans.empty()) throw InputError("assess: a bridge without spans");
  if (bridge.continuous || bridge.spans.size() == 1) return {member_of(model::build_structure(bridge, track), bridge.continuous ? 0 : 1)};
  std::vector<MemberFrequencies> out;
  for (std::size_t k = 0; k < bridge.spans.size(); ++k) {
    // A span equal to an earlier one (same length, EI and mass: the same bearings and track) is
    // the same eigenproblem: its member frequencies are that span's.
    std::size_t same = k;
    for (std::size_t j = 0; j < k && same == k; ++j) {
      const model::SpanParams &a = bridge.spans[j], &b = bridge.spans[k];
      if (a.length == b.length && a.EI == b.EI && a.mass_per_m == b.mass_per_m) same = j;
    }
    if (same < k) {
      MemberFrequencies m = out[same];
      m.span = static_cast<int>(k + 1);
      out.push_back(m);
      continue;
    }
    model::BridgeParams one = bridge;
    one.spans = {bridge.spans[k]};
    out.push_back(member_of(model::build_structure(one, track), static_cast<int>(k + 1)));
  }
  return out;
}

std::vector<double> assessment_speeds(double v_min, double v_max, double step, double fine_step,
                                      const std::vector<double>& resonances, double band) {
  require_positive(v_min, "lowest speed [m/s]");
  require_positive(step, "speed step [m/s]");
  require_positive(fine_step, "refined speed step [m/s]");
  require_non_negative(band, "refinement band [-]");
  if (!(v_max >= v_min)) throw InputError("the highest speed is below the lowest");
  if ((v_max - v_min) / std::min(step, fine_step) > 1e6) throw InputError("more than a million speeds: raise the steps");
  std::vector<double> v;
  for (double x = v_min; x <= v_max * (1 + 1e-12); x = v_min + step * static_cast<double>(v.size())) v.push_back(x);
  if (v.back() < v_max * (1 - 1e-12)) v.push_back(v_max);
  for (double r : resonances) {
    const double lo = std::max(v_min, r * (1.0 - band)), hi = std::min(v_max, r * (1.0 + band));
    if (!(r > 0.0) || lo > hi) continue;
    // On the fine grid through the resonance itself, so that the peak is hit.
    const double first = r - fine_step * std::floor((r - lo) / fine_step);
    for (double x = first; x <= hi * (1 + 1e-12); x += fine_step) v.push_back(x);
  }
  std::sort(v.begin(), v.end());
  std::vector<double> out;
  for (double x : v)
    if (out.empty() || x - out.back() > fine_step / 100.0) out.push_back(x);
  return out;
}

}  // namespace viaduct::study

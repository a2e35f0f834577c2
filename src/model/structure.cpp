#include "viaduct/model/structure.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

#include <Eigen/SparseCholesky>

#include "viaduct/core/error.hpp"
#include "viaduct/model/beam_element.hpp"
#include "viaduct/model/damping.hpp"

namespace viaduct::model {

namespace {

bool fail(std::string* why, const std::string& msg) {
  if (why) *why = msg;
  return false;
}

bool finite_ge(double v, double lo) { return std::isfinite(v) && v >= lo; }
bool finite_gt(double v, double lo) { return std::isfinite(v) && v > lo; }

std::string str(double v) { return format_number(v, 10); }

bool check_sd(const SpringDashpot& s, const std::string& name, std::string* why) {
  if (!finite_ge(s.k, 0.0)) return fail(why, name + ".k must be >= 0 [N/m], got " + str(s.k));
  if (!finite_ge(s.c, 0.0)) return fail(why, name + ".c must be >= 0 [N·s/m], got " + str(s.c));
  return true;
}

// Adds the symmetric 2-point spring/dashpot between interpolated points a and b (either may
// have fewer DOFs; -1 entries are ground) into triplet lists.
struct Link {
  std::array<Index, 8> dofs;
  std::array<double, 8> coef;  // relative displacement = Σ coef u[dofs]
  int n = 0;
  void add(Index d, double c) {
    if (d < 0 || c == 0.0) return;
    dofs[static_cast<std::size_t>(n)] = d;
    coef[static_cast<std::size_t>(n)] = c;
    ++n;
  }
};

void add_link(std::vector<Triplet>& t, const Link& l, double value) {
  if (value == 0.0) return;
  for (int i = 0; i < l.n; ++i)
    for (int j = 0; j < l.n; ++j)
      t.emplace_back(l.dofs[static_cast<std::size_t>(i)], l.dofs[static_cast<std::size_t>(j)],
                     value * (l.coef[static_cast<std::size_t>(i)] * l.coef[static_cast<std::size_t>(j)]));
}

void add_element(std::vector<Triplet>& t, const PathElement& e, const Matrix4& m) {
  for (int i = 0; i < 4; ++i) {
    const Index di = e.dofs[static_cast<std::size_t>(i)];
    if (di < 0) continue;
    for (int j = 0; j < 4; ++j) {
      const Index dj = e.dofs[static_cast<std::size_t>(j)];
      if (dj >= 0) t.emplace_back(di, dj, m(i, j));
    }
  }
}

// Beam elements of length h between consecutive nodes (w, θ) from x0 on: appended to `out`, their
// stiffness and mass to the triplet lists.
void add_beam_chain(const std::vector<std::array<Index, 2>>& node, double x0, double h, const Matrix4& ke, const Matrix4& me,
                    std::vector<PathElement>& out, std::vector<Triplet>& tk, std::vector<Triplet>& tm) {
  for (std::size_t j = 0; j + 1 < node.size(); ++j) {
    PathElement e;
    e.x0 = x0 + static_cast<double>(j) * h;
    e.h = h;
    e.dofs = {node[j][0], node[j][1], node[j + 1][0], node[j + 1][1]};
    out.push_back(e);
    add_element(tk, e, ke);
    add_element(tm, e, me);
  }
}

}  // namespace

double BridgeParams::total_length() const {
  double L = 0.0;
  for (const auto& s : spans) L += s.length;
  return L;
}

bool BridgeParams::is_valid(std::string* why) const {
  if (spans.empty()) return fail(why, "bridge needs at least one span");
  for (std::size_t i = 0; i < spans.size(); ++i) {
    const std::string n = "span " + std::to_string(i + 1);
    if (!finite_gt(spans[i].length, 0.0))
      return fail(why, n + " length must be > 0 [m], got " + str(spans[i].length));
    if (!finite_gt(spans[i].EI, 0.0))
      return fail(why, n + " EI must be > 0 [N·m²], got " + str(spans[i].EI));
    if (!finite_gt(spans[i].mass_per_m, 0.0))
      return fail(why, n + " mass_per_m must be > 0 [kg/m], got " + str(spans[i].mass_per_m));
    if (element_size > spans[i].length * 1.000001 && spans[i].length > 0.0) {
      // allowed: one element per span (rounded); nothing to reject
    }
  }
  if (!finite_gt(element_size, 0.0))
    return fail(why, "bridge element_size must be > 0 [m], got " + str(element_size));
  if (!finite_ge(added_mass_per_m, 0.0))
    return fail(why, "added_mass_per_m must be >= 0 [kg/m], got " + str(added_mass_per_m));
  if (!finite_ge(bearings.rotational_k, 0.0))
    return fail(why, "rotational stiffness rotational_k must be >= 0 [N·m/rad], got " + str(bearings.rotational_k));
  if (!bearings.rigid) {
    if (!finite_gt(bearings.k, 0.0))
      return fail(why, "elastic bearing stiffness k must be > 0 [N/m], got " + str(bearings.k));
    if (!finite_ge(bearings.c, 0.0))
      return fail(why, "bearing damping c must be >= 0 [N·s/m], got " + str(bearings.c));
  }
  const auto ratio_ok = [](double z) { return std::isfinite(z) && z >= 0.0 && z < 1.0; };
  switch (damping.kind) {
    case DampingKind::none: break;
    case DampingKind::modal:
      if (!ratio_ok(damping.ratio))
        return fail(why, "modal damping ratio must be in [0, 1), got " + str(damping.ratio));
      break;
    case DampingKind::rayleigh:
      if (!finite_gt(damping.f1_hz, 0.0))
        return fail(why, "Rayleigh f1_hz must be > 0, got " + str(damping.f1_hz));
      if (!(finite_gt(damping.f2_hz, damping.f1_hz)))
        return fail(why, "Rayleigh f2_hz must be > f1_hz, got " + str(damping.f2_hz));
      if (!ratio_ok(damping.ratio1) || !ratio_ok(damping.ratio2))
        return fail(why, "Rayleigh ratios must be in [0, 1)");
      break;
  }
  return true;
}

double TrackParams::mass_per_m() const {
  return rail_mass_per_m + (sleeper_mass + ballast_mass) / sleeper_spacing;
}

bool TrackParams::is_valid(std::string* why) const {
  if (!finite_gt(rail_EI, 0.0)) return fail(why, "rail EI must be > 0 [N·m²], got " + str(rail_EI));
  if (!finite_gt(rail_mass_per_m, 0.0))
    return fail(why, "rail mass per metre must be > 0 [kg/m], got " + str(rail_mass_per_m));
  if (!finite_gt(sleeper_spacing, 0.0))
    return fail(why, "sleeper_spacing must be > 0 [m], got " + str(sleeper_spacing));
  if (!finite_gt(sleeper_mass, 0.0))
    return fail(why, "sleeper_mass must be > 0 [kg], got " + str(sleeper_mass));
  if (!finite_gt(ballast_mass, 0.0))
    return fail(why, "ballast_mass must be > 0 [kg], got " + str(ballast_mass));
  if (!check_sd(pad, "pad", why) || !check_sd(ballast, "ballast", why) ||
      !check_sd(shear, "shear", why) || !check_sd(subgrade, "subgrade", why) ||
      !check_sd(subgrade_on_bridge, "subgrade_on_bridge", why))
    return false;
  if (!(pad.k > 0.0)) return fail(why, "pad.k must be > 0 [N/m] (the rail must rest on the sleepers)");
  if (!(ballast.k > 0.0)) return fail(why, "ballast.k must be > 0 [N/m]");
  if (!(subgrade.k > 0.0)) return fail(why, "subgrade.k must be > 0 [N/m] (track off the bridge needs support)");
  if (!(subgrade_on_bridge.k > 0.0)) return fail(why, "subgrade_on_bridge.k must be > 0 [N/m]");
  if (!finite_ge(approach_length, 0.0))
    return fail(why, "approach_length must be >= 0 [m], got " + str(approach_length));
  if (!finite_ge(exit_length, 0.0))
    return fail(why, "exit_length must be >= 0 [m], got " + str(exit_length));
  if (rail_elements_per_bay < 1)
    return fail(why, "rail_elements_per_bay must be >= 1, got " + std::to_string(rail_elements_per_bay));
  if (first_sleeper_offset >= 0.0 && !(first_sleeper_offset < sleeper_spacing))
    return fail(why, "first_sleeper_offset must be in [0, sleeper_spacing = " + str(sleeper_spacing) + ") [m], got " +
                         str(first_sleeper_offset));
  return true;
}

double TrackParams::start_x() const {
  if (!(first_sleeper_offset >= 0.0)) return -approach_length;
  // The sleeper grid through first_sleeper_offset, from its first node at or before −approach_length.
  return first_sleeper_offset - sleeper_spacing * std::ceil((approach_length + first_sleeper_offset) / sleeper_spacing - 1e-9);
}

double PointCoupling::value(const Vector& u) const {
  double w = 0.0;
  for (std::size_t i = 0; i < 4; ++i)
    if (dofs[i] >= 0) w += N[i] * u[dofs[i]];
  return w;
}

std::complex<double> PointCoupling::complex_value(const Eigen::VectorXcd& u) const {
  std::complex<double> w = 0.0;
  for (std::size_t i = 0; i < 4; ++i)
    if (dofs[i] >= 0) w += N[i] * u[dofs[i]];
  return w;
}

PointCoupling point_on(const std::vector<PathElement>& elements, double x, const char* what) {
  if (elements.empty()) throw InputError(std::string("no ") + what + " to place a point on");
  const double x0 = elements.front().x0, x1 = elements.back().x0 + elements.back().h;
  const double tol = 1e-9 * std::max(1.0, x1 - x0);
  if (!(x >= x0 - tol && x <= x1 + tol))
    throw InputError("x = " + str(x) + " m lies outside the " + what + " [" + str(x0) + ", " +
                     str(x1) + "] m");
  auto it = std::upper_bound(elements.begin(), elements.end(), x,
                             [](double v, const PathElement& e) { return v < e.x0; });
  if (it != elements.begin()) --it;
  const PathElement& e = *it;
  const double xi = std::clamp((x - e.x0) / e.h, 0.0, 1.0);
  PointCoupling pc;
  pc.dofs = e.dofs;
  pc.N = hermite_shape(xi, e.h);
  return pc;
}

double DofWeights::value(const Vector& u) const {
  double y = 0.0;
  for (std::size_t k = 0; k < dof.size(); ++k) y += weight[k] * u[dof[k]];
  return y;
}

std::pair<std::size_t, std::size_t> Structure::span_elements(std::size_t span) const {
  if (span >= span_start.size())
    throw InputError("span " + std::to_string(span + 1) + " does not exist (the bridge has " +
                     std::to_string(span_start.size()) + ")");
  const std::size_t first = span_first_element[span];
  const std::size_t last = span + 1 < span_first_element.size() ? span_first_element[span + 1] : deck_elements.size();
  return {first, last};
}

namespace {
void add_weight(DofWeights& f, Index dof, double w) {
  if (dof < 0 || w == 0.0) return;
  for (std::size_t k = 0; k < f.dof.size(); ++k)
    if (f.dof[k] == dof) {
      f.weight[k] += w;
      return;
    }
  f.dof.push_back(dof);
  f.weight.push_back(w);
}
}  // namespace

DofWeights Structure::deck_derivative(std::size_t span, double x_local, int order) const {
  auto [first, last] = span_elements(span);
  const double L = span_length[span];
  const double tol = 1e-9 * std::max(1.0, L);
  if (!(x_local >= -tol && x_local <= L + tol))
    throw InputError("x = " + str(x_local) + " m lies outside span " + std::to_string(span + 1) + " [0, " + str(L) + "] m");
  const double x = span_start[span] + std::clamp(x_local, 0.0, L);
  // A continuous deck's moment is continuous over a support: both sides' elements there.
  if (continuous && order == 2) {
    if (first > 0) --first;
    if (last < deck_elements.size()) ++last;
  }
  // The elements that hold x: one inside an element, both at a node between two.
  std::vector<std::pair<std::size_t, double>> at;  // element, xi
  for (std::size_t e = first; e < last; ++e) {
    const PathElement& el = deck_elements[e];
    const double xi = (x - el.x0) / el.h;
    if (xi >= -1e-9 && xi <= 1.0 + 1e-9) at.emplace_back(e, std::clamp(xi, 0.0, 1.0));
  }
  DofWeights f;
  for (const auto& [e, xi] : at) {
    // The element's own span (the neighbouring one's over a support) gives its EI.
    const auto owner = std::upper_bound(span_first_element.begin(), span_first_element.end(), e) - span_first_element.begin() - 1;
    const double share = -span_EI[static_cast<std::size_t>(owner)] / static_cast<double>(at.size());
    const PathElement& el = deck_elements[e];
    const auto d = order == 2 ? hermite_curvature(xi, el.h) : hermite_third(el.h);
    for (std::size_t i = 0; i < 4; ++i) add_weight(f, el.dofs[i], share * d[i]);
  }
  return f;
}

DofWeights Structure::deck_moment(std::size_t span, double x_local) const { return deck_derivative(span, x_local, 2); }

DofWeights Structure::deck_shear(std::size_t span, double x_local) const { return deck_derivative(span, x_local, 3); }

DofWeights Structure::deck_end_rotation(std::size_t span, bool end) const {
  const auto [first, last] = span_elements(span);
  const PathElement& el = deck_elements[end ? last - 1 : first];
  DofWeights f;
  add_weight(f, el.dofs[end ? 3 : 1], 1.0);
  return f;
}

double Structure::path_start() const { return load_path().front().x0; }
double Structure::path_end() const { return load_path().back().x0 + load_path().back().h; }

PointCoupling Structure::deck_point(std::size_t span, double x_local) const {
  const auto [first, last] = span_elements(span);
  std::vector<PathElement> els(deck_elements.begin() + static_cast<std::ptrdiff_t>(first),
                               deck_elements.begin() + static_cast<std::ptrdiff_t>(last));
  return point_on(els, span_start[span] + x_local, "span");
}

PointCoupling Structure::rail_point(double x) const {
  if (!has_track) throw InputError("a rail station needs a track in the scenario");
  return point_on(rail_elements, x, "rail");
}

namespace {
// The triplets of M, K and C and the next free DOF while a structure is assembled.
struct Assembly {
  Structure& s;
  std::vector<Triplet> tm, tk, tc;
  Index next = 0;
};

// A deck element meeting at a support, with the element matrices of its span.
struct SupportElement {
  BearingForce::Element at;
  const Matrix4* ke = nullptr;
  const Matrix4* me = nullptr;
};

// The force of a rigid bearing whose deck elements are `els`: minus the fixed DOF's row of the
// element stiffness and mass, and of the structural damping. Modal damping has no row for a fixed
// DOF: its damping force field is M Φ diag(2ζω) Φᵀ M v, whose fixed-DOF entry is M_Af M_ff⁻¹ C_ff v;
// Rayleigh's is a0 M_Af + a1 K_Af. Ms, Cs: the deck's matrices over its free DOFs from first_dof.
void rigid_bearing_weights(BearingForce& b, const std::vector<SupportElement>& els, const BridgeDamping& damping,
                           const Eigen::SimplicialLDLT<SparseMatrix>* Mff, const Matrix& Cs, Index first_dof) {
  const Index n_deck = Cs.rows();
  Vector mrow = Vector::Zero(n_deck), krow = Vector::Zero(n_deck);  // over the deck's free DOFs
  for (const auto& se : els) {
    b.elements.push_back(se.at);
    for (int q = 0; q < 4; ++q) {
      const Index d = se.at.element.dofs[static_cast<std::size_t>(q)];
      if (d < 0) continue;
      add_weight(b.k, d, -(*se.ke)(se.at.fixed_local, q));
      add_weight(b.m, d, -(*se.me)(se.at.fixed_local, q));
      mrow[d - first_dof] += (*se.me)(se.at.fixed_local, q);
      krow[d - first_dof] += (*se.ke)(se.at.fixed_local, q);
    }
  }
  Vector crow = Vector::Zero(n_deck);
  if (damping.kind == DampingKind::modal) {
    crow = Cs * Mff->solve(mrow);  // (M_Af M_ff⁻¹ C_ff)ᵀ, C symmetric
  } else if (damping.kind == DampingKind::rayleigh) {
    const auto [a0, a1] = rayleigh_coefficients(damping.f1_hz, damping.ratio1, damping.f2_hz, damping.ratio2);
    crow = a0 * mrow + a1 * krow;
  }
  for (Index i = 0; i < n_deck; ++i)
    if (crow[i] != 0.0) add_weight(b.c, first_dof + i, -crow[i]);
}

// One support of a deck: its node (w, θ) and the deck elements meeting there.
struct Support {
  std::array<Index, 2> node{{-1, -1}};
  double x = 0.0;
  std::size_t span = 0;
  bool end = false;
  std::vector<SupportElement> elements;
};

// The spans [s0, s1) as one deck from x: a single simply supported span, or all the spans of a
// continuous deck (nodes shared over the intermediate supports). Nodes (a support's deflection
// fixed when rigid), beam elements, rotational restraint at the deck's two ends, one bearing per
// support, and the structural damping from the deck's own M and K.
void add_deck(Assembly& as, const BridgeParams& bridge, std::size_t s0, std::size_t s1, double x, double deck_mass_reduction) {
  auto& [s, tm, tk, tc, next] = as;
  const Index first_dof = next;
  std::vector<Triplet> lm, lk;  // the deck's own matrices (for damping), global DOF numbers
  std::vector<Support> supports;
  std::vector<Matrix4> ke(s1 - s0), me(s1 - s0);
  for (std::size_t si = s0; si < s1; ++si) {
    const SpanParams& sp = bridge.spans[si];
    const double m = sp.mass_per_m + bridge.added_mass_per_m - deck_mass_reduction;
    if (si == 0) s.deck_mass_per_m_used = m;
    const double n_el_real = std::ceil(sp.length / bridge.element_size - 1e-9);
    const int n_el = std::max(1, static_cast<int>(n_el_real));
    const double h = sp.length / n_el;
    s.span_start.push_back(x);
    s.span_length.push_back(sp.length);
    s.span_EI.push_back(sp.EI);
    s.span_first_element.push_back(s.deck_elements.size());
    std::vector<std::array<Index, 2>> node(static_cast<std::size_t>(n_el + 1));
    for (int j = 0; j <= n_el; ++j) {
      if (j == 0 && si > s0) {  // the support shared with the previous span
        node[0] = supports.back().node;
        continue;
      }
      const bool support = (j == 0 || j == n_el);
      node[static_cast<std::size_t>(j)][0] = (support && bridge.bearings.rigid) ? -1 : next++;
      node[static_cast<std::size_t>(j)][1] = next++;
    }
    const Matrix4& k_el = ke[si - s0] = beam_stiffness(sp.EI, h);
    const Matrix4& m_el = me[si - s0] = beam_mass(m, h);
    add_beam_chain(node, x, h, k_el, m_el, s.deck_elements, lk, lm);
    if (si == s0) supports.push_back({node.front(), x, si, false, {}});
    supports.back().elements.push_back({{s.deck_elements[s.span_first_element.back()], 0}, &k_el, &m_el});
    supports.push_back({node.back(), x + sp.length, si, true, {{{s.deck_elements.back(), 2}, &k_el, &m_el}}});
    x += sp.length;
  }
  // Rotational restraint of the deck's ends: a spring on each end's rotation (part of the
  // deck's stiffness, so modal damping sees it).
  if (bridge.bearings.rotational_k > 0.0)
    for (const Support* sup : {&supports.front(), &supports.back()}) lk.emplace_back(sup->node[1], sup->node[1], bridge.bearings.rotational_k);
  const std::size_t first_bearing = s.bearings.size();
  auto bearing_at = [&](const Support& sup) {
    BearingForce b;
    b.name = bridge.continuous ? "support" + std::to_string(s.bearings.size() + 1)
                               : "span" + std::to_string(sup.span + 1) + (sup.end ? "_end" : "_start");
    b.span = sup.span;
    b.end = sup.end;
    b.rigid = bridge.bearings.rigid;
    b.x = sup.x;
    return b;
  };
  if (!bridge.bearings.rigid)
    for (const Support& sup : supports) {
      const Index d = sup.node[0];
      lk.emplace_back(d, d, bridge.bearings.k);
      tc.emplace_back(d, d, bridge.bearings.c);
      BearingForce b = bearing_at(sup);
      add_weight(b.k, d, bridge.bearings.k);
      add_weight(b.c, d, bridge.bearings.c);
      for (const auto& se : sup.elements) b.elements.push_back(se.at);
      s.bearings.push_back(b);
    }
  // Structural damping from the deck's own M and K (bearing springs included).
  const Index n_deck = next - first_dof;
  SparseMatrix Ms(n_deck, n_deck), Ks(n_deck, n_deck);
  auto shift = [&](const std::vector<Triplet>& in) {
    std::vector<Triplet> out;
    out.reserve(in.size());
    for (const auto& t : in) out.emplace_back(t.row() - first_dof, t.col() - first_dof, t.value());
    return out;
  };
  const auto lms = shift(lm), lks = shift(lk);
  Ms.setFromTriplets(lms.begin(), lms.end());
  Ks.setFromTriplets(lks.begin(), lks.end());
  const Matrix Cs = structural_damping(Ms, Ks, bridge.damping);
  for (Index i = 0; i < n_deck; ++i)
    for (Index j = 0; j < n_deck; ++j)
      if (Cs(i, j) != 0.0) tc.emplace_back(first_dof + i, first_dof + j, Cs(i, j));
  if (bridge.bearings.rigid) {
    std::optional<Eigen::SimplicialLDLT<SparseMatrix>> Mff;  // modal damping only
    if (bridge.damping.kind == DampingKind::modal) Mff.emplace(Ms);
    for (const Support& sup : supports) {
      BearingForce b = bearing_at(sup);
      rigid_bearing_weights(b, sup.elements, bridge.damping, Mff ? &*Mff : nullptr, Cs, first_dof);
      s.bearings.push_back(b);
    }
  }
  for (std::size_t si = s0; si < s1; ++si) {  // support k carries spans k − 1 and k
    const std::size_t k = first_bearing + (si - s0);
    s.span_bearings.push_back({k, k + 1});
  }
  tm.insert(tm.end(), lm.begin(), lm.end());
  tk.insert(tk.end(), lk.begin(), lk.end());
}

// The permanent load of every bearing of a continuous deck: the deck under its weight and the
// track's (q = g·m per span, consistent nodal loads), solved on the bridge's own stiffness, then
// each bearing's force R = k·u + the consistent load at its fixed DOF.
void continuous_permanent_loads(Structure& s, const std::vector<Triplet>& bridge_k, const std::vector<double>& q_span) {
  SparseMatrix K(s.n_bridge_dofs, s.n_bridge_dofs);
  K.setFromTriplets(bridge_k.begin(), bridge_k.end());
  Vector f = Vector::Zero(s.n_bridge_dofs);
  auto consistent = [](double q, double h) { return std::array<double, 4>{{q * h / 2, q * h * h / 12, q * h / 2, -q * h * h / 12}}; };
  for (std::size_t si = 0; si < s.span_start.size(); ++si) {
    const auto [e0, e1] = s.span_elements(si);
    for (std::size_t e = e0; e < e1; ++e) {
      const PathElement& el = s.deck_elements[e];
      const auto fe = consistent(q_span[si], el.h);
      for (std::size_t i = 0; i < 4; ++i)
        if (el.dofs[i] >= 0) f[el.dofs[i]] += fe[i];
    }
  }
  Eigen::SimplicialLDLT<SparseMatrix> ldlt(K);
  if (ldlt.info() != Eigen::Success) throw InputError("bridge: the continuous deck's stiffness is singular (a mechanism)");
  const Vector u = ldlt.solve(f);
  for (BearingForce& b : s.bearings) {
    b.permanent = b.k.value(u);
    if (!b.rigid) continue;
    for (const auto& be : b.elements) {  // the span holding the element's middle gives its load
      const double xm = be.element.x0 + be.element.h / 2;
      const auto si = std::upper_bound(s.span_start.begin(), s.span_start.end(), xm) - s.span_start.begin() - 1;
      b.permanent += consistent(q_span[static_cast<std::size_t>(si)], be.element.h)[static_cast<std::size_t>(be.fixed_local)];
    }
  }
}

// The track over [−approach, L_bridge + exit]: rail elements, and per sleeper the sleeper and
// ballast masses, pad, ballast, shear and subgrade links (to the deck where it lies on a span).
void add_track(Assembly& as, const TrackParams& tp, double L_bridge) {
  auto& [s, tm, tk, tc, next] = as;
  const double d = tp.sleeper_spacing;
  const double x_start = tp.start_x();
  const double L_track = L_bridge + tp.exit_length - x_start;
  const double n_bays_real = std::floor(L_track / d + 1e-9);
  const int n_bays = static_cast<int>(n_bays_real);
  const int n_sub = tp.rail_elements_per_bay;
  const int n_nodes = n_bays * n_sub + 1;
  const double h = d / n_sub;
  std::vector<std::array<Index, 2>> rn(static_cast<std::size_t>(n_nodes));
  for (auto& r : rn) {
    r[0] = next++;
    r[1] = next++;
  }
  const Matrix4 ke = beam_stiffness(tp.rail_EI, h), me = beam_mass(tp.rail_mass_per_m, h);
  add_beam_chain(rn, x_start, h, ke, me, s.rail_elements, tk, tm);
  const double tol = 1e-9;
  for (int i = 0; i <= n_bays; ++i) {
    const double xs = x_start + i * d;
    const Index rail_w = rn[static_cast<std::size_t>(i * n_sub)][0];
    const Index sl = next++, bl = next++;
    s.sleeper_x.push_back(xs);
    s.sleeper_dof.push_back(sl);
    s.ballast_dof.push_back(bl);
    tm.emplace_back(sl, sl, tp.sleeper_mass);
    tm.emplace_back(bl, bl, tp.ballast_mass);
    Link pad;
    pad.add(rail_w, 1.0);
    pad.add(sl, -1.0);
    add_link(tk, pad, tp.pad.k);
    add_link(tc, pad, tp.pad.c);
    Link bal;
    bal.add(sl, 1.0);
    bal.add(bl, -1.0);
    add_link(tk, bal, tp.ballast.k);
    add_link(tc, bal, tp.ballast.c);
    if (i > 0) {
      Link sh;
      sh.add(s.ballast_dof[static_cast<std::size_t>(i - 1)], 1.0);
      sh.add(bl, -1.0);
      add_link(tk, sh, tp.shear.k);
      add_link(tc, sh, tp.shear.c);
    }
    // Subgrade: to the deck where the sleeper lies on a span, to ground elsewhere.
    Link sub;
    sub.add(bl, 1.0);
    const SpringDashpot* sd = &tp.subgrade;
    for (std::size_t si = 0; si < s.span_start.size(); ++si) {
      const double a = s.span_start[si], b = a + s.span_length[si];
      if (xs >= a - tol && xs <= b + tol) {
        const PointCoupling pc = s.deck_point(si, std::clamp(xs - a, 0.0, s.span_length[si]));
        for (std::size_t q = 0; q < 4; ++q) sub.add(pc.dofs[q], -pc.N[q]);
        sd = &tp.subgrade_on_bridge;
        // The link's force on a rigid bearing's fixed DOF (coefficient −N there), which the
        // assembly leaves out: minus k·c_A·(link elongation), into that bearing's force.
        for (std::size_t q : {0u, 2u})
          if (pc.dofs[q] < 0 && pc.N[q] != 0.0) {
            BearingForce& bf = s.bearings[s.span_bearings[si][q == 2 ? 1 : 0]];
            const double cA = -pc.N[q];
            for (int l = 0; l < sub.n; ++l) {
              add_weight(bf.k, sub.dofs[static_cast<std::size_t>(l)], -sd->k * cA * sub.coef[static_cast<std::size_t>(l)]);
              add_weight(bf.c, sub.dofs[static_cast<std::size_t>(l)], -sd->c * cA * sub.coef[static_cast<std::size_t>(l)]);
            }
          }
        break;
      }
    }
    add_link(tk, sub, sd->k);
    add_link(tc, sub, sd->c);
  }
}
}  // namespace

void check_model_size(const BridgeParams& bridge, const std::optional<TrackParams>& track) {
  const double deck_mass_reduction = track && bridge.mass_includes_track ? track->mass_per_m() : 0.0;
  double deck_elements = 0.0;
  for (std::size_t si = 0; si < bridge.spans.size(); ++si) {
    const SpanParams& sp = bridge.spans[si];
    const double m = sp.mass_per_m + bridge.added_mass_per_m - deck_mass_reduction;
    if (!(m > 0.0))
      throw InputError("bridge.mass_per_m plus added_mass_per_m minus the modelled track mass (" + str(deck_mass_reduction) +
                       " kg/m, mass_includes_track = true) must be > 0 on span " + std::to_string(si + 1) + ", got " + str(m) +
                       " kg/m");
    const double n_el_real = std::ceil(sp.length / bridge.element_size - 1e-9);
    if (!(n_el_real <= kMaxSpanElements))
      throw InputError("bridge.element_size " + str(bridge.element_size) + " m gives " + str(n_el_real) + " elements on span " +
                       std::to_string(si + 1) + "; at most " + std::to_string(kMaxSpanElements) +
                       " per span (raise bridge.element_size)");
    deck_elements += n_el_real;
  }
  if (bridge.continuous && !(deck_elements <= kMaxDeckElements))
    throw InputError("bridge.element_size " + str(bridge.element_size) + " m gives " + str(deck_elements) +
                     " elements on the continuous deck; at most " + std::to_string(kMaxDeckElements) + " (raise bridge.element_size)");
  if (!track) return;
  const TrackParams& tp = *track;
  const double L_track = bridge.total_length() + tp.exit_length - tp.start_x();
  const double n_bays_real = std::floor(L_track / tp.sleeper_spacing + 1e-9);
  if (!(n_bays_real >= 1))
    throw InputError("track.sleeper_spacing " + str(tp.sleeper_spacing) + " m is longer than the track (" + str(L_track) + " m)");
  if (!(n_bays_real * tp.rail_elements_per_bay <= kMaxRailElements))
    throw InputError("track.rail_elements_per_bay " + std::to_string(tp.rail_elements_per_bay) + " with sleepers every " +
                     str(tp.sleeper_spacing) + " m over " + str(L_track) + " m of track gives " +
                     str(n_bays_real * tp.rail_elements_per_bay) + " rail elements; at most " + std::to_string(kMaxRailElements) +
                     " (shorten the approach/exit track or coarsen it)");
}

Structure build_structure(const BridgeParams& bridge, const std::optional<TrackParams>& track) {
  std::string why;
  if (!bridge.is_valid(&why)) throw InputError("bridge: " + why);
  if (track && !track->is_valid(&why)) throw InputError("track: " + why);
  check_model_size(bridge, track);

  Structure s;
  s.has_track = track.has_value();
  double deck_mass_reduction = 0.0;
  if (track && bridge.mass_includes_track) deck_mass_reduction = track->mass_per_m();

  Assembly a{s, {}, {}, {}, 0};
  // --- bridge: one continuous deck, or spans with their own nodes (simply supported) ---
  s.continuous = bridge.continuous;
  double x = 0.0;
  if (bridge.continuous) {
    add_deck(a, bridge, 0, bridge.spans.size(), x, deck_mass_reduction);
    x = bridge.total_length();
  } else {
    for (std::size_t si = 0; si < bridge.spans.size(); ++si) {
      add_deck(a, bridge, si, si + 1, x, deck_mass_reduction);
      x += bridge.spans[si].length;
    }
  }
  s.n_bridge_dofs = a.next;
  // The self-weight each bearing carries, deck and track (with mass_includes_track the deck's
  // mass holds the track already): half the span's, g·m·L/2, on simply supported spans.
  std::vector<double> q_span;
  for (const SpanParams& sp : bridge.spans)
    q_span.push_back(9.80665 * (sp.mass_per_m + bridge.added_mass_per_m +
                                (track && !bridge.mass_includes_track ? track->mass_per_m() : 0.0)));
  if (bridge.continuous)
    continuous_permanent_loads(s, a.tk, q_span);
  else
    for (auto& b : s.bearings) b.permanent = q_span[b.span] * bridge.spans[b.span].length / 2.0;
  // --- track ---
  if (track) add_track(a, *track, x);
  const Index next = a.next;
  s.n_dofs = next;
  s.n_track_dofs = next - s.n_bridge_dofs;
  s.M.resize(next, next);
  s.K.resize(next, next);
  s.C.resize(next, next);
  s.M.setFromTriplets(a.tm.begin(), a.tm.end());
  s.K.setFromTriplets(a.tk.begin(), a.tk.end());
  s.C.setFromTriplets(a.tc.begin(), a.tc.end());
  s.M.prune(0.0);
  s.K.prune(0.0);
  s.C.prune(0.0);
  return s;
}

}  // namespace viaduct::model

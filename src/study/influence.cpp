#include "viaduct/study/influence.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/SparseCholesky>

#include "viaduct/core/error.hpp"
#include "viaduct/load/moving_loads.hpp"

namespace viaduct::study {

double InfluenceLines::at(std::size_t q, double x) const {
  const Vector& y = value[q];
  const double u = (x - x0) / h;
  if (!(u >= 0.0) || y.size() == 0) return 0.0;
  const auto i = static_cast<Index>(std::floor(u));
  if (i >= y.size() - 1) return i == y.size() - 1 && u == static_cast<double>(i) ? y[i] : 0.0;
  const double w = u - static_cast<double>(i);
  return (1.0 - w) * y[i] + w * y[i + 1];
}

InfluenceLines influence_lines(const PreparedModel& m, double h) {
  const model::Structure& s = m.structure;
  std::vector<solve::Functional> funcs;
  std::vector<const LoadEffect*> bearing;
  for (const auto& st : m.stations)
    if (st.has_deck) {
      funcs.push_back(functional_of(st.deck));
      bearing.push_back(nullptr);
    }
  for (const auto& e : m.effects) {
    funcs.push_back(e.functional);
    bearing.push_back(e.bearing >= 0 ? &e : nullptr);
  }
  InfluenceLines il;
  il.names = quantity_names(m);
  if (h <= 0.0) {
    double shortest = s.path_end() - s.path_start();
    for (const auto& e : s.load_path()) shortest = std::min(shortest, e.h);
    h = shortest / 8.0;
  }
  require_positive(h, "influence line spacing [m]");
  // A whole number of samples over the path, so that its end (a bearing at the bridge's end,
  // without track) is a sample.
  const double length = s.path_end() - s.path_start();
  const double n_real = std::ceil(length / h - 1e-9);
  if (!(n_real <= 1e7)) throw InputError("influence lines: more than 1e7 samples (spacing " + format_number(h, 6) + " m)");
  h = length / std::max(1.0, n_real);
  il.x0 = s.path_start();
  il.h = h;
  const auto n = static_cast<Index>(std::max(1.0, n_real)) + 1;
  Eigen::SimplicialLDLT<SparseMatrix> K(s.K);
  if (K.info() != Eigen::Success) throw SolverError("influence lines: the stiffness matrix cannot be factorised");
  std::vector<Vector> z;
  for (const auto& f : funcs) {
    Vector c = Vector::Zero(s.n_dofs);
    for (std::size_t k = 0; k < f.dof.size(); ++k) c[f.dof[k]] += f.weight[k];
    z.push_back(K.solve(c));
    if (!z.back().allFinite())
      throw SolverError("influence lines: the stiffness matrix is singular (a part of the model is not supported)");
  }
  // One 1 N axle moving at 1 m/s: at time t it stands at path_start + t.
  load::Train unit;
  unit.name = "unit axle";
  unit.offset = {0.0};
  unit.load = {1.0};
  const load::MovingLoads loads(s, unit, 1.0, 1.0);
  il.value.assign(funcs.size(), Vector::Zero(n));
  SparseForce f;
  for (Index i = 0; i < n; ++i) {
    const double x = i + 1 == n ? s.path_end() : il.x0 + static_cast<double>(i) * h;
    loads.entries(x - il.x0, f);
    for (std::size_t q = 0; q < z.size(); ++q) {
      double y = 0.0;
      for (std::size_t e = 0; e < f.dof.size(); ++e) y += z[q][f.dof[e]] * f.value[e];
      if (bearing[q]) y += bearing_load(s, *bearing[q], unit, 1.0, x);
      il.value[q][i] = y;
    }
  }
  return il;
}

std::vector<EffectPeak> static_extremes(const InfluenceLines& il, const load::Train& train, double load_factor) {
  require_positive(load_factor, "train.load_factor");
  train.validate();
  std::vector<EffectPeak> out(il.value.size());
  if (il.value.empty()) return out;
  const double x_end = il.x0 + il.h * static_cast<double>(il.value.front().size() - 1);
  const auto n_pos = static_cast<Index>(std::ceil((x_end - il.x0 + train.length()) / il.h)) + 1;
  // Only the axles on the lines' extent [x0, x_end] add anything (InfluenceLines::at is 0 beyond):
  // offsets are non-decreasing, so those of a head position are one run [first, last), padded by
  // one sample each side; the others' terms are exact zeros, so skipping them changes no value.
  const std::size_t n_axles = train.n_axles();
  auto axles_on = [&](double head) {
    const auto lo = std::lower_bound(train.offset.begin(), train.offset.end(), head - x_end - il.h);
    const auto hi = std::upper_bound(lo, train.offset.end(), head - il.x0 + il.h);
    return std::pair<std::size_t, std::size_t>(static_cast<std::size_t>(lo - train.offset.begin()),
                                               static_cast<std::size_t>(hi - train.offset.begin()));
  };
  auto at_head = [&](std::size_t q, double head) {
    double y = 0.0;
    const auto [first, last] = axles_on(head);
    for (std::size_t k = first; k < last && k < n_axles; ++k) y += train.load[k] * il.at(q, head - train.offset[k]);
    return y * load_factor;
  };
  // Every h: per head position, each axle's sample and weight once for all quantities (as
  // InfluenceLines::at takes them, every line having the same samples), then each quantity's sum
  // over the axles in the same order: the same numbers as at_head, without finding the axles on the
  // lines and their samples once per quantity.
  const std::size_t nq = il.value.size();
  const Index n_samples = il.value.front().size();
  std::vector<double> x_max(nq, il.x0), x_min(nq, il.x0), y(nq);
  struct Tap {
    Index i;      // the sample at or before the axle; -1: 0 (off the lines)
    double w;     // the weight of sample i + 1 (0 and no sample i + 1 at the lines' end)
    double load;  // the axle's
  };
  std::vector<Tap> taps;
  for (Index step = 0; step < n_pos; ++step) {
    const double head = il.x0 + static_cast<double>(step) * il.h;
    const auto [first, last] = axles_on(head);
    taps.clear();
    for (std::size_t k = first; k < last && k < n_axles; ++k) {
      const double u = (head - train.offset[k] - il.x0) / il.h;
      Tap t{-1, 0.0, train.load[k]};
      if (u >= 0.0) {
        const auto i = static_cast<Index>(std::floor(u));
        if (i < n_samples - 1) t.i = i, t.w = u - static_cast<double>(i);
        else if (i == n_samples - 1 && u == static_cast<double>(i)) t.i = i;  // the end sample itself
      }
      taps.push_back(t);
    }
    std::fill(y.begin(), y.end(), 0.0);
    for (const Tap& t : taps) {
      // Off the lines InfluenceLines::at gives 0: y + load·0 is y for a load Train::validate
      // admits (finite, > 0), so the axle adds nothing.
      if (t.i < 0) continue;
      if (t.i == n_samples - 1) {
        for (std::size_t q = 0; q < nq; ++q) y[q] += t.load * il.value[q][t.i];
      } else {
        for (std::size_t q = 0; q < nq; ++q) {
          const Vector& v = il.value[q];
          y[q] += t.load * ((1.0 - t.w) * v[t.i] + t.w * v[t.i + 1]);
        }
      }
    }
    for (std::size_t q = 0; q < nq; ++q) {
      const double yq = y[q] * load_factor;
      if (yq > out[q].max) out[q].max = yq, x_max[q] = head;
      if (yq < out[q].min) out[q].min = yq, x_min[q] = head;
    }
  }
  // Then around the largest and the smallest: the response is piecewise linear in the head
  // position between the positions that put an axle on a sample, so its extremes within ±h are at
  // those (an axle on a support or on the station).
  for (std::size_t q = 0; q < nq; ++q) {
    for (const double around : {x_max[q], x_min[q]})
      for (std::size_t k = 0; k < n_axles; ++k)
        for (const double side : {-1.0, 0.0, 1.0}) {
          // the sample nearest to axle k, and its neighbours: the head that puts the axle there
          const double u = std::round((around - train.offset[k] - il.x0) / il.h) + side;
          const double head = il.x0 + u * il.h + train.offset[k];
          if (std::abs(head - around) > il.h) continue;
          const double yh = at_head(q, head);
          out[q].max = std::max(out[q].max, yh);
          out[q].min = std::min(out[q].min, yh);
        }
  }
  return out;
}

std::vector<EffectPeak> lm71_extremes(const InfluenceLines& il, double alpha, double load_factor) {
  require_positive(alpha, "LM71 classification factor alpha");
  require_positive(load_factor, "train.load_factor");
  constexpr double P = 250e3, q = 80e3, a = 1.6, gap = 0.8;  // [N], [N/m], [m], [m] (EN 1991-2 Fig. 6.1)
  std::vector<EffectPeak> out(il.value.size());
  for (std::size_t k = 0; k < il.value.size(); ++k) {
    const Vector& y = il.value[k];
    const Index n = y.size();
    // Running integrals of the positive and negative parts (trapezoids): the UDL's share over
    // [x_a, x_b] is a difference of two of them.
    Vector pos = Vector::Zero(n), neg = Vector::Zero(n);
    for (Index i = 1; i < n; ++i) {
      pos[i] = pos[i - 1] + 0.5 * il.h * (std::max(y[i - 1], 0.0) + std::max(y[i], 0.0));
      neg[i] = neg[i - 1] + 0.5 * il.h * (std::min(y[i - 1], 0.0) + std::min(y[i], 0.0));
    }
    auto integral_to = [&](const Vector& cum, double x) {
      const double u = std::clamp((x - il.x0) / il.h, 0.0, static_cast<double>(n - 1));
      const auto i = std::min(static_cast<Index>(std::floor(u)), n - 1);
      if (i == n - 1) return cum[i];
      return cum[i] + (u - static_cast<double>(i)) * (cum[i + 1] - cum[i]);  // linear between samples
    };
    // Each axle on every sample (the extremes put one on a kink of the line: a support, the
    // station), from the group wholly before the path to wholly after it.
    const Index lo = -static_cast<Index>(std::ceil((3.0 * a + gap) / il.h)), hi = n + static_cast<Index>(std::ceil(gap / il.h));
    for (Index i = lo; i <= hi; ++i)
      for (int on = 0; on < 4; ++on) {
        const double x1 = il.x0 + static_cast<double>(i) * il.h + a * on;  // the leading axle; the others behind it
        double axles = 0.0;
        for (int j = 0; j < 4; ++j) axles += P * il.at(k, x1 - a * j);
        const double gap_lo = x1 - 3.0 * a - gap, gap_hi = x1 + gap;  // no UDL within
        const double up = pos[n - 1] - (integral_to(pos, gap_hi) - integral_to(pos, gap_lo));
        const double down = neg[n - 1] - (integral_to(neg, gap_hi) - integral_to(neg, gap_lo));
        out[k].max = std::max(out[k].max, alpha * load_factor * (axles + q * up));
        out[k].min = std::min(out[k].min, alpha * load_factor * (axles + q * down));
      }
  }
  return out;
}

}  // namespace viaduct::study

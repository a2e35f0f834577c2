// The divergence guard's bounds (divergence.hpp).
#include "divergence.hpp"

#include <cmath>
#include <limits>

#include <Eigen/SparseCholesky>

#include "viaduct/core/error.hpp"
#include "viaduct/model/beam_element.hpp"

namespace viaduct::study {

std::shared_ptr<const StaticFactor> factor_statics(const model::Structure& s) {
  auto f = std::make_shared<StaticFactor>();
  f->ldlt.compute(s.K);
  f->ok = f->ldlt.info() == Eigen::Success;
  return f;
}

Vector influence_maxima(const model::Structure& s, const std::vector<solve::Functional>& outputs,
                        const StaticFactor* factor) {
  const auto n_out = static_cast<Index>(outputs.size());
  std::shared_ptr<const StaticFactor> own;
  if (!factor) {
    own = factor_statics(s);
    factor = own.get();
  }
  if (!factor->ok) return Vector::Constant(n_out, std::numeric_limits<double>::infinity());
  const auto& lk = factor->ldlt;
  const auto& path = s.load_path();
  // The Hermite weights at five points of an element (per element length: the rotations' scale).
  constexpr int kPoints = 5;
  Vector out = Vector::Zero(n_out);
  Vector rhs = Vector::Zero(s.K.rows());
  for (Index j = 0; j < n_out; ++j) {
    const solve::Functional& f = outputs[static_cast<std::size_t>(j)];
    if (f.dof.empty()) continue;
    rhs.setZero();
    for (std::size_t q = 0; q < f.dof.size(); ++q) rhs[f.dof[q]] += f.weight[q];
    const Vector z = lk.solve(rhs);  // K symmetric: F K⁻¹ N(x)ᵀ = N(x) z
    if (!z.allFinite()) {
      out[j] = std::numeric_limits<double>::infinity();
      continue;
    }
    double m = 0.0;
    for (const model::PathElement& e : path)
      for (int p = 0; p < kPoints; ++p) {
        const auto N = model::hermite_shape(static_cast<double>(p) / (kPoints - 1), e.h);
        double y = 0.0;
        for (std::size_t q = 0; q < 4; ++q)
          if (e.dofs[q] >= 0) y += N[q] * z[e.dofs[q]];
        m = std::max(m, std::abs(y));
      }
    out[j] = m;
  }
  return out;
}

solve::DivergenceBound divergence_bound(const Vector& imax, std::vector<std::string> names, const load::Train& train,
                                        double load_factor, bool vehicles) {
  double total = 0.0, largest = 0.0;
  for (const double p : train.load) {
    total += std::abs(p);
    largest = std::max(largest, std::abs(p));
  }
  total *= std::abs(load_factor);
  solve::DivergenceBound b;
  b.max_abs = (kDivergenceFactor * total) * imax;
  b.names = std::move(names);
  b.basis = format_number(kDivergenceFactor, 3) + " x its static value with the whole train (" +
            format_number(total / 1e3, 6) + " kN) where it is largest";
  if (vehicles) {
    b.max_contact_force = kContactForceFactor * largest * std::abs(load_factor);
    b.basis += "; contact forces " + format_number(kContactForceFactor, 3) + " x the largest static axle load";
  }
  return b;
}

}  // namespace viaduct::study

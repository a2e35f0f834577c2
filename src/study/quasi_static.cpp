#include "viaduct/study/quasi_static.hpp"

#include <cmath>
#include <limits>

#include <Eigen/SparseCholesky>

#include "viaduct/core/error.hpp"
#include "viaduct/load/moving_loads.hpp"

namespace viaduct::study {

namespace {
Vector as_dense(const solve::Functional& f, Index n) {
  Vector c = Vector::Zero(n);
  for (std::size_t k = 0; k < f.dof.size(); ++k) c[f.dof[k]] += f.weight[k];
  return c;
}

double max_abs(const Vector& v) { return v.size() ? v.cwiseAbs().maxCoeff() : 0.0; }
}  // namespace

QuasiStaticResult quasi_static(const PreparedModel& m, const load::Train& train, double speed, double load_factor,
                               const RunResult& run) {
  const model::Structure& s = m.structure;
  // The quantities: deck stations' deflections, then the load effects (as run records them).
  std::vector<std::string> names;
  std::vector<solve::Functional> funcs;
  std::vector<const Vector*> dynamic;
  std::vector<const LoadEffect*> bearing;  // per quantity: the bearing force it is, or null
  for (std::size_t i = 0; i < m.stations.size() && i < run.stations.size(); ++i)
    if (m.stations[i].has_deck) {
      names.push_back(m.stations[i].name + "_disp_m");
      funcs.push_back(functional_of(m.stations[i].deck));
      dynamic.push_back(&run.stations[i].disp);
      bearing.push_back(nullptr);
    }
  for (std::size_t j = 0; j < m.effects.size() && j < run.effects.size(); ++j) {
    names.push_back(m.effects[j].name);
    funcs.push_back(m.effects[j].functional);
    dynamic.push_back(&run.effects[j].value);
    bearing.push_back(m.effects[j].bearing >= 0 ? &m.effects[j] : nullptr);
  }
  Eigen::SimplicialLDLT<SparseMatrix> K(s.K);
  if (K.info() != Eigen::Success) throw SolverError("quasi-static response: the stiffness matrix cannot be factorised");
  // Influence lines: y(t) = cᵀ K⁻¹ f(t) = zᵀ f(t), z = K⁻¹ c (K symmetric).
  std::vector<Vector> z;
  for (const auto& f : funcs) {
    z.push_back(K.solve(as_dense(f, s.n_dofs)));
    if (!z.back().allFinite())
      throw SolverError("quasi-static response: the stiffness matrix is singular (a part of the model is not supported)");
  }
  const load::MovingLoads loads(s, train, speed, load_factor);
  QuasiStaticResult out;
  out.names = names;
  out.value.assign(names.size(), Vector::Zero(run.t.size()));
  SparseForce f;
  for (Index k = 0; k < run.t.size(); ++k) {
    loads.entries(run.t[k], f);
    for (std::size_t q = 0; q < z.size(); ++q) {
      double y = 0.0;
      for (std::size_t e = 0; e < f.dof.size(); ++e) y += z[q][f.dof[e]] * f.value[e];
      // A rigid bearing's force: plus the axles on its element (no inertia or damping at rest).
      if (bearing[q]) y += bearing_load(s, *bearing[q], train, load_factor, s.path_start() + speed * run.t[k]);
      out.value[q][k] = y;
    }
  }
  for (std::size_t q = 0; q < names.size(); ++q) {
    DynamicIncrement d;
    d.name = names[q];
    d.max_dynamic = max_abs(*dynamic[q]);
    d.max_static = max_abs(out.value[q]);
    d.phi_dyn = d.max_static > 0.0 ? d.max_dynamic / d.max_static - 1.0 : std::numeric_limits<double>::quiet_NaN();
    out.increments.push_back(d);
  }
  return out;
}

}  // namespace viaduct::study

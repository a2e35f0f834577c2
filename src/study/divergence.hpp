#pragma once
// The divergence guard's bounds of a prepared model's cases (private to src/study; the guard
// itself is solve/guard.hpp): per output, the largest |static value| under one unit axle
// anywhere on the load path, from one factorisation of K.

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <Eigen/SparseCholesky>

#include "viaduct/load/train.hpp"
#include "viaduct/model/structure.hpp"
#include "viaduct/solve/guard.hpp"
#include "viaduct/solve/second_order_system.hpp"

namespace viaduct::study {

/// No physical passage takes an output past this many times its largest static value under the
/// whole train (every axle's load placed where that output is largest: an upper bound of any
/// static position of the train). Dynamic amplification, resonance build-up under a train of
/// many axles and wheel-rail impacts stay below it with a wide margin (measured, docs/reliability.md:
/// the largest ratio on the shipped scenarios, HSLM at resonance with no damping included, is
/// below 1); a diverging run passes it within a few steps of growth.
constexpr double kDivergenceFactor = 20.0;
/// No wheel-rail force exceeds this many times the largest static axle load unless the run
/// diverged: landings on a linear Hertz spring after lift-off reach 21 x on FRA class 5 at 360 km/h
/// (scenarios/vehicles-25m.toml, the same at every step down to 0.125 ms) and 263 x on a 1e12 N/m
/// contact stepped at 1 ms (tests/verification/test_vehicles.cpp, "at the extremes"); a diverging
/// contact (the displacement-level rigid constraint before #36) 8500 x. Plausibility, not the
/// guard, flags the forces past a few static loads (study::plausibility_warnings).
constexpr double kContactForceFactor = 1000.0;

/// PreparedModel::imax: the influence maxima last computed, of `outputs` on `structure`.
struct InfluenceMaximaCache {
  std::mutex m;
  const model::Structure* structure = nullptr;  // null: none kept yet
  std::vector<solve::Functional> outputs;
  Vector value;
};

/// One factorisation of K, shared by a prepared model's static computations (PreparedModel::statics).
struct StaticFactor {
  Eigen::SimplicialLDLT<SparseMatrix> ldlt;
  bool ok = false;  ///< false: K could not be factored (an unsupported structure)
};
std::shared_ptr<const StaticFactor> factor_statics(const model::Structure& s);

/// Per functional: max over load positions x on the path of |F K⁻¹ N(x)ᵀ| (the Hermite weights at
/// five points of each path element). +infinity for every functional when K cannot be factored
/// (an unsupported structure reports its own error); 0 for a functional no path load reaches.
/// `factor`: K's factorisation (null: factored here).
Vector influence_maxima(const model::Structure& s, const std::vector<solve::Functional>& outputs,
                        const StaticFactor* factor = nullptr);

/// The bounds of a case of `train` × load_factor on outputs whose influence_maxima() are `imax`,
/// named `names`; the contact bound from the largest static axle load × load_factor when
/// `vehicles`.
solve::DivergenceBound divergence_bound(const Vector& imax, std::vector<std::string> names, const load::Train& train,
                                        double load_factor, bool vehicles = false);

}  // namespace viaduct::study

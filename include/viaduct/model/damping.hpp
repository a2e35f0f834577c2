#pragma once
/// \file Structural damping matrices.

#include "viaduct/core/types.hpp"
#include "viaduct/model/structure.hpp"

namespace viaduct::model {

/// Rayleigh coefficients (a0 [1/s], a1 [s]) such that ζ(ω) = a0/(2ω) + a1·ω/2 passes through
/// (f1_hz, ratio1) and (f2_hz, ratio2). Requires 0 < f1_hz < f2_hz.
std::pair<double, double> rayleigh_coefficients(double f1_hz, double ratio1, double f2_hz,
                                                double ratio2);

/// Damping matrix of one substructure with mass Ms and stiffness Ks (SPD, small, dense result):
/// none → 0; modal → M Φ diag(2ζω) Φᵀ M over all its modes; rayleigh → a0 M + a1 K.
Matrix structural_damping(const SparseMatrix& Ms, const SparseMatrix& Ks, const BridgeDamping& d);

}  // namespace viaduct::model

#pragma once
/// \file Undamped eigenmodes of an assembled structure: K φ = ω² M φ.

#include "viaduct/model/structure.hpp"

namespace viaduct::model {

struct Modes {
  Vector frequency_hz;  ///< [Hz] ascending
  Matrix shape;         ///< n_dofs × n_modes, mass-normalised (φᵀ M φ = 1)
};

/// Largest model compute_modes() accepts (dense: memory ~ 8 n², time ~ n³).
constexpr Index kMaxDenseModeDofs = 6000;

/// Lowest `n_modes` modes (all when n_modes <= 0 or larger than the DOF count). Dense solver:
/// fine for the few thousand DOFs of a span-and-track model; InputError beyond kMaxDenseModeDofs.
Modes compute_modes(const Structure& s, Index n_modes);

}  // namespace viaduct::model

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

/// Share of a mode's modal mass on the deck (bridge DOFs): φ_bᵀ M φ_b / φᵀ M φ, in [0, 1]; 1
/// without track.
double deck_mass_share(const Structure& s, const Vector& phi);

/// "deck" (deck_mass_share >= 0.5), "track" (<= 0.1) or "coupled".
const char* mode_kind(double deck_share);

/// Where a mode bends the deck: the span that carries most of its deck deflection (Σ w²·h over
/// the span's nodes) and the number of half-waves on that span, counted as the sign changes of
/// the deflection relative to the chord between the span's ends (bearings may move) plus one:
/// 1 for the first bending mode of a span, 2 for the second... order 0: the span moves as a
/// rigid body on its bearings (bending under 5 % of its deflection). span 0: no deck deflection.
struct DeckBending {
  int span = 0;   ///< 1-based
  int order = 0;
};
DeckBending deck_bending(const Structure& s, const Vector& phi);

/// What a mode is: its deck mass share, kind, and where it bends the deck (span 0 for a track
/// mode, whose deck barely moves: share <= 0.1).
struct ModeTag {
  double deck_share = 0.0;
  const char* kind = "track";
  DeckBending bending;
};
ModeTag tag_mode(const Structure& s, const Vector& phi);

/// A mode that bends the deck.
struct DeckMode {
  double frequency_hz = 0.0;  ///< [Hz]
  DeckBending bending;
  double deck_share = 0.0;    ///< deck_mass_share
};
/// The lowest `n` modes that bend the deck (deck mass share above 0.1, bending order >= 1),
/// skipping track modes and rigid motions on the bearings; fewer when the model has fewer.
/// f1 of the deck is the first. SolverError when the eigensolver fails.
std::vector<DeckMode> deck_bending_modes(const Structure& s, std::size_t n);

/// How compute_modes_up_to() solves the eigenproblem.
enum class ModeSolver {
  automatic,  ///< sparse when the model has more than 1000 DOFs and few modes are wanted
  dense,      ///< all eigenpairs (LAPACK-style, O(n³)), then the selection
  sparse,     ///< shift-invert Lanczos on the sparse K and M (Spectra), only the modes wanted
};

/// The lowest modes satisfying both limits: at most n_modes (0: no count limit) and frequencies
/// up to max_frequency_hz (0: no limit). The sparse solver asks for more modes until it has
/// passed max_frequency_hz, and hands over to the dense one beyond a quarter of the DOFs.
/// SolverError when the sparse iteration does not converge.
Modes compute_modes_up_to(const Structure& s, Index n_modes, double max_frequency_hz,
                          ModeSolver solver = ModeSolver::automatic);

}  // namespace viaduct::model

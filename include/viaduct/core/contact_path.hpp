#pragma once
/// \file The wheel–rail contact geometry a coupled vehicle kernel reads (solve/coupled.hpp) and
/// the loads give (load/contacts.hpp: a train rolling along a structure's load path;
/// solve/modal.hpp: the same in modal coordinates): here, below both, so that neither layer
/// includes the other.

#include <cstddef>
#include <vector>

#include "viaduct/core/types.hpp"

namespace viaduct {

/// Where each wheel is: the rail deflection under it as a functional of the structure's
/// coordinates, and the irregularity there. Called once per wheel and step, with t ascending.
class ContactPath {
 public:
  virtual ~ContactPath() = default;
  /// Clears `dof` and `weight` and fills them (nothing when the wheel is off the structure, on
  /// rigid ground); writes the irregularity [m] under the wheel (positive down) to `irregularity`.
  /// Must not allocate once the vectors have grown to their working size.
  virtual void contact(std::size_t wheel, double t, std::vector<Index>& dof, std::vector<double>& weight,
                       double& irregularity) const = 0;
  /// The times in (0, t_end) at which a wheel's contact stops being smooth in time (a wheel
  /// entering or leaving the structure or a transition, an irregularity's taper starting or
  /// ending): the adaptive kernel (coupled_ida) stops and restarts there. May be empty.
  virtual std::vector<double> breaks(double /*t_end*/) const { return {}; }
  /// The static correction of a truncated modal structure: writes F [m/N] (n_wheels², symmetric),
  /// the quasi-static deflection of the rail under wheel a per unit force at wheel b that the
  /// structure's coordinates leave out — N_a (K⁻¹ − Φ Ω⁻² Φᵀ) N_bᵀ for the dropped modes, rows and
  /// columns of wheels off the structure zero — and returns true; or returns false (the default:
  /// the coordinates are complete). The rail under wheel a is then N_a u + Σ_b F_ab P_b, P the
  /// total contact forces. Called right after contact() was called for every wheel at the same t.
  /// Must not allocate once F has its size.
  virtual bool residual_flexibility(double /*t*/, Matrix& /*F*/) const { return false; }
  /// For a wheel that follows the rail (a rigid contact): the first and second time derivatives of
  /// the weights contact() gave for `wheel` at t, in the same order and over the same DOFs (a
  /// wheel moving at speed v along the path sees v ∂/∂x and v² ∂²/∂x² of its weights), and of the
  /// irregularity under it [m/s, m/s²]. Called right after contact() for the same wheel and t.
  /// Returns false when the path cannot give them (the default): a rigid contact is then refused.
  virtual bool contact_rates(std::size_t /*wheel*/, double /*t*/, std::vector<double>& /*dweight*/,
                             std::vector<double>& /*ddweight*/, double& /*dr*/, double& /*ddr*/) const {
    return false;
  }
};

}  // namespace viaduct

#pragma once
/// \file Vehicle–structure interaction: a linear structure (M, C, K; every DOF or modal
/// coordinates) and linear vehicles coupled at moving wheel–rail contacts, integrated together by
/// Newmark's scheme (docs/vehicles.md has the derivation).
///
/// Vehicle coordinates z are measured from the static equilibrium of the vehicles on a rigid,
/// smooth rail, so gravity leaves their equations: wheel w presses on the rail with
/// P_w = P0_w + p_w, its static load P0_w plus the dynamic part p_w. The contact is a linearised
/// Hertz spring, p_w = k_w (z_w − y_w − r_w) with y_w the rail's deflection under the wheel and r_w
/// the irregularity there (positive down: a dip), or rigid (k_w = ∞: z_w = y_w + r_w, p_w a
/// Lagrange multiplier). A rigid wheel follows the rail: its constraint is imposed on the
/// accelerations, z̈_w = N ü + 2 Ṅ u̇ + N̈ u + r̈ (ContactPath::contact_rates), and its position and
/// velocity are set on the rail after every step, so that the constraint force is not the
/// 1/dt²-amplified multiplier of a displacement constraint (an index-3 system, whose forces grew
/// as the step shrank) and converges as dt → 0; it is the limit of a Hertz spring as k → ∞.
/// Each step solves the contact forces first, from a small dense system
/// (wheels × wheels: flexibility of the structure between the contacts, of the vehicles, and of
/// the springs, plus a modal structure's static correction, ContactPath::residual_flexibility), then the structure and vehicles; the structure's effective matrix is factored
/// once and its inverse columns at the rail DOFs the wheels cross are cached, so a step costs one
/// sparse solve, as without vehicles, plus the columns of newly reached DOFs. A wheel off the
/// structure (before the path, after it) rolls on rigid ground and still sees the irregularity.
/// A wheel whose total contact force would become tensile leaves the rail and lands again when it
/// would press into it (an active set per step, LinearVehicle::release; a rigid wheel's landing is
/// an impact whose force grows without bound as the step shrinks: SolverError); the result counts the
/// steps each wheel spent in the air. With release off the linear contact keeps a tensile force,
/// which the result reports (CoupledSummary::min_contact_force) instead of hiding.

#include <functional>
#include <limits>
#include <vector>

#include "viaduct/core/contact_path.hpp"
#include "viaduct/core/types.hpp"
#include "viaduct/solve/guard.hpp"
#include "viaduct/solve/options.hpp"
#include "viaduct/solve/summary.hpp"

namespace viaduct::solve {

/// Linear vehicles (a whole train's): M z̈ + C ż + K z = −B p, dense, symmetric. M may have
/// zero rows (a massless wheel) when K and C make M + γ dt C + β dt² K positive definite.
struct LinearVehicle {
  Matrix M, C, K;                  ///< n_v × n_v
  std::vector<Index> wheel_dof;    ///< per contact: the vehicle DOF that touches the rail
  Vector static_load;              ///< [N] per contact: P0 > 0
  /// [N/m] per contact: linearised Hertz stiffness > 0, or +infinity for a rigid contact.
  Vector contact_stiffness;
  /// true: unilateral contact — a wheel whose total force would pull leaves the rail (its force
  /// 0) and lands again when it would press; false: the linear contact holds it (a tensile force).
  bool release = true;
  Index n_dofs() const { return M.rows(); }
  std::size_t n_contacts() const { return wheel_dof.size(); }
  /// Sizes, symmetry, finite values, wheel DOFs in range and distinct, P0 > 0, k > 0. *why
  /// names the field and the rule.
  bool is_valid(std::string* why) const;
};

/// Where each wheel is (core/contact_path.hpp: below both the kernels and the loads that give it).
using ContactPath = viaduct::ContactPath;

/// The coupled state after each step, valid during the call: structure u, v, a; vehicles z, ż, z̈;
/// the total contact forces P0 + p [N] per wheel (compression positive).
struct CoupledState {
  const Vector &u, &v, &a, &z, &zv, &za, &contact_force;
};
using CoupledObserver = std::function<void(Index step, double t, const CoupledState& s)>;

/// A wheel leaving the rail (landed = false) or landing on it again, at time t [s]: the step at
/// whose end it was found (coupled_newmark, resolution dt) or the root located by IDA (coupled_ida).
struct ContactEvent {
  std::size_t wheel = 0;
  double t = 0.0;
  bool landed = false;
};

/// What a coupled run did: the summary of any kernel plus the contact's extremes.
struct CoupledSummary {
  Summary summary;
  Vector min_contact_force;  ///< [N] per wheel over the run (negative: the wheel would have lifted)
  Vector max_contact_force;  ///< [N] per wheel
  std::vector<Index> steps_released;  ///< per wheel: steps ended off the rail (LinearVehicle::release)
  double first_release_t = -1.0;      ///< [s] first time a wheel left the rail (-1: never)
  Vector airborne_s;                  ///< [s] per wheel: time spent off the rail
  std::vector<ContactEvent> events;   ///< every loss and return of contact, in time order
  Index n_cached_columns = 0;  ///< structure inverse columns computed (one sparse solve each)
};

/// Integrates structure and vehicles from rest (u = v = 0, z = ż = 0: the vehicles in static
/// equilibrium on rigid ground, which needs a zero irregularity under every wheel at t = 0) with
/// Newmark's β and γ (HHT's α must be 0). InputError for invalid options, vehicles or grid, a
/// non-zero irregularity at t = 0 or a contact DOF out of range; SolverError for an effective
/// matrix that is not positive definite or a non-finite state (with its time).
/// `bound` (optional): the divergence guard's contact-force bound (guard.hpp), checked every step.
CoupledSummary coupled_newmark(const SparseMatrix& M, const SparseMatrix& C, const SparseMatrix& K,
                               const LinearVehicle& vehicle, const ContactPath& path, const TimeGrid& grid,
                               const NewmarkOptions& opt, const CoupledObserver& observe,
                               const DivergenceBound* bound = nullptr);

/// The same coupled system integrated by SUNDIALS IDA (variable-order BDF with error control),
/// meant for the reduced system: the structure in modal coordinates (M, C, K small), the vehicles
/// physical. The unknowns are y = [u, v, z, ż]; the contact law of each wheel is fixed between
/// events, and IDA's root finding locates the events: a wheel whose total force P0 + k (z − y − r)
/// crosses zero downwards leaves the rail, one whose would-be force crosses zero upwards lands; at
/// each event and at each of path.breaks() the integration restarts from a consistent state. The
/// Newton systems are solved reduced to the displacements: the vehicles' block sparse, the
/// structure's Schur complement dense, so n <= 3000 (InputError beyond: integrate the modes; on
/// every DOF of a FE model the error test would follow its kHz modes anyway). Hertz contacts only (a rigid contact under a mass is an index-3 constraint: InputError), and every vehicle DOF
/// needs mass (M positive definite). Outputs at k·grid.dt (IDA's interpolant). Summary: internal
/// steps, Jacobians, rejected steps, restarts (breaks and events); CoupledSummary::events with
/// the root times (to IDA's tolerances, not the recording step). With the path's static
/// correction (ContactPath::residual_flexibility) the wheels on the structure's rail are solved
/// together, (1/k + F) P = P0/k + z − y − r, and the Newton matrix takes that coupling.
CoupledSummary coupled_ida(const SparseMatrix& M, const SparseMatrix& C, const SparseMatrix& K,
                           const LinearVehicle& vehicle, const ContactPath& path, const TimeGrid& grid,
                           const IdaOptions& opt, const CoupledObserver& observe,
                           const DivergenceBound* bound = nullptr);

/// Static equilibrium of the structure (K) and the vehicles standing with the contacts `path`
/// gives at time t: K u = Σ Nᵀ(P0 + p), K_v z = −B p, with the contact law and the path's static
/// correction (the rail under a wheel N u + F P). Returns u (the coordinates' share) and writes
/// z and the total contact forces. SolverError when the system is singular (a structure without
/// supports, a vehicle that is a mechanism on its wheels).
Vector coupled_static(const SparseMatrix& K, const LinearVehicle& vehicle, const ContactPath& path, double t,
                      Vector* z, Vector* contact_force);

}  // namespace viaduct::solve

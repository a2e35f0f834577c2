#pragma once
/// \file Trains as vehicles with masses and suspensions: the linear equations of every vehicle of
/// a train, M z̈ + C ż + K z = −B p, in coordinates measured from the static equilibrium of the
/// vehicles on a rigid, smooth rail (gravity then leaves them: it is the axles' static loads).
/// Vertical displacements are positive down, like the structure's; a pitch θ is positive nose
/// down, so a point e metres ahead of a body's centre moves z + e·θ.

#include <string>
#include <vector>

#include "viaduct/core/types.hpp"
#include "viaduct/load/train.hpp"

namespace viaduct::load {

/// One sprung mass on one unsprung mass per axle (the "sprung" rung of docs/vehicles.md).
struct SprungSpec {
  double unsprung_mass = 0.0;  ///< [kg] per axle, >= 0 (0: the spring bears on the rail directly)
  double k = 0.0;              ///< [N/m] suspension per axle, > 0
  double c = 0.0;              ///< [N·s/m] per axle, >= 0
};

/// The vehicles of a train as one linear system.
struct TrainVehicles {
  Matrix M, C, K;                     ///< n × n, symmetric
  std::vector<Index> wheel_dof;       ///< per axle of the train, head first: its wheelset's DOF
  std::vector<std::string> dof_names; ///< "c1_body_bounce", "c1_body_pitch", "a3_wheel", ...
  /// The DOF whose acceleration is the passengers' (car-body bounce of each coach, or the
  /// sprung mass of each axle), with its name ("c1", "a1").
  std::vector<Index> body_dof;
  std::vector<std::string> body_names;
  /// Per body: its pitch DOF (−1: none, a sprung mass) and the distance [m] from its centre to the
  /// floor above each bogie centre, where a coach pitching adds to its bounce (EN 12299's floor
  /// positions: the centre and above the bogie centres); 0 without pitch.
  std::vector<Index> body_pitch_dof;
  std::vector<double> body_arm;
  Index n_dofs() const { return M.rows(); }
};

/// One sprung and one unsprung mass per axle of `t`: sprung mass P/g − unsprung, where P is the
/// axle's static load. DOFs per axle: sprung (a<k>_body), then unsprung (a<k>_wheel). InputError
/// for an invalid spec or an axle too light for its unsprung mass.
TrainVehicles sprung_vehicles(const Train& t, const SprungSpec& s, double g = kGravity);

/// The sprung-mass reduction of a coach: the wheelset is the unsprung mass and the rest of the
/// axle's load rides on the primary suspension in series with the axle's share of the secondary
/// (half a bogie's): k = 1/(1/k1 + 2/k2), and the dashpots alike (0 when either is 0).
SprungSpec sprung_of(const CoachSpec& c);

/// The 2D multibody coaches of `t` (made by coach_train()): per coach 10 DOFs, body bounce and
/// pitch, front bogie bounce and pitch, rear bogie bounce and pitch, four wheelsets. InputError
/// when the train has no coaches or its axles are not its coaches'.
TrainVehicles multibody_vehicles(const Train& t);

}  // namespace viaduct::load

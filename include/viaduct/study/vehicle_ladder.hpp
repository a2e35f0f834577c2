#pragma once
/// \file When vehicles matter (issue #21 part 7): one train at one speed over a scenario's model
/// as moving forces, sprung masses, multibody coaches and multibody coaches on the scenario's
/// rail profile, each on the full model and on the modal fast path, with its peaks, its wall time
/// and its deck peaks against the richest rung's (`viaduct ladder`).

#include <string>
#include <vector>

#include "viaduct/study/simulation.hpp"

namespace viaduct::study {

/// One rung on one path.
struct LadderRow {
  std::string rung;               ///< "forces", "sprung", "multibody", "<richest> + profile"
  Method method = Method::newmark;
  Index n_modes = 0;              ///< modal path: modes kept
  std::vector<StationPeaks> peaks;          ///< per station (acceleration filtered as the scenario says)
  std::vector<double> acc_vs_richest;       ///< per station: peak / the richest rung's − 1
  std::vector<double> disp_vs_richest;
  VehiclePeaks vehicle;           ///< vehicle rungs
  Index n_steps = 0;
  double wall_s = 0.0;            ///< [s] the model's preparation (modes) and the run
  std::string error;              ///< non-empty: the rung failed with this message (no peaks)
};

struct LadderResult {
  std::vector<std::string> stations;
  std::vector<LadderRow> rows;    ///< rungs in order, each on Newmark then (with the fast path) modal
  std::size_t richest = 0;        ///< index of the reference row: the richest rung on Newmark
};

/// The rungs a train allows: forces always; sprung when the scenario gives the sprung masses or
/// the train has coaches; multibody with coaches; the richest of them again on the scenario's
/// rail profile when it has one (`[irregularity]`). Newmark with the scenario's step and
/// options; with `modal_max_hz` > 0 also the modal path with modes up to it. `speed` [m/s] > 0.
/// A rung that fails is recorded with its message; the others complete. InputError when no
/// rung could run.
LadderResult vehicle_ladder(const Scenario& sc, const load::Train& train, double speed, double modal_max_hz);

}  // namespace viaduct::study

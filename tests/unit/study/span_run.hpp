#pragma once
// A simulated passage over one simply supported span, the "record" of the tests of the record
// workflows (comparison, speed identification).
#include <optional>

#include "viaduct/load/train.hpp"
#include "viaduct/model/structure.hpp"
#include "viaduct/study/simulation.hpp"

namespace viaduct::test {

// One simply supported span (length L [m], EI [N·m²], mass m [kg/m]; 0.5 m elements, 2 % damping)
// under `train` at v [m/s]: its mid-span station every 2 ms, unfiltered, with t_free [s] of free
// vibration after the train.
inline study::RunResult mid_span_run(double L, double EI, double m, const load::Train& train, double v, double t_free) {
  model::BridgeParams b;
  b.spans = {{L, EI, m}};
  b.element_size = 0.5;
  b.damping.ratio = 0.02;
  const model::Structure s = model::build_structure(b, std::nullopt);
  study::RunSettings rs;
  rs.dt = 2e-3;
  rs.filter.enabled = false;
  rs.free_vibration_s = t_free;
  return study::simulate(s, study::resolve_stations(s, {{"mid", true, 0, L / 2, 0.0}}), train, v, rs);
}

}  // namespace viaduct::test

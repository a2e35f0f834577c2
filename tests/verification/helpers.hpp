#pragma once
// Shared set-ups for the verification tests.
#include <string>

#include "viaduct/io/scenario.hpp"
#include "viaduct/model/modes.hpp"
#include "viaduct/study/simulation.hpp"

namespace vt {

inline std::string source(const std::string& rel) { return std::string(VIADUCT_SOURCE_DIR) + "/" + rel; }

/// A scenario shipped with viaduct, resolved, with optional overrides.
inline viaduct::study::Scenario shipped(const std::string& name, const std::vector<std::string>& set = {}) {
  return viaduct::io::to_scenario(viaduct::io::load_flat(source("scenarios/" + name + ".toml"), set));
}

/// Simply supported single span without track, undamped unless told.
inline viaduct::model::BridgeParams span(double L, double EI, double m, double element_size, double zeta = 0.0) {
  viaduct::model::BridgeParams b;
  b.spans = {{L, EI, m}};
  b.element_size = element_size;
  b.damping.kind = zeta > 0 ? viaduct::model::DampingKind::modal : viaduct::model::DampingKind::none;
  b.damping.ratio = zeta;
  return b;
}

inline double closed_form_f(int n, double L, double EI, double m) {
  return n * n * M_PI / (2 * L * L) * std::sqrt(EI / m);
}

}  // namespace vt

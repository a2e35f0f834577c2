#pragma once
// Shared set-ups for the verification tests.
#include <string>

#include "viaduct/io/scenario.hpp"
#include "viaduct/model/modes.hpp"
#include "viaduct/study/simulation.hpp"
#include "source_dir.hpp"

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

/// A Newmark (HHT alpha, beta and gamma following) run at 0.2 ms without filter of `sc` on rigid
/// bearings, or on elastic ones of k = 1e12 N/m without dashpots: the same bridge, to compare a
/// rigid bearing's recovered force with k·w.
inline viaduct::study::RunResult run_on_bearings(viaduct::study::Scenario sc, bool rigid, double alpha,
                                                 const viaduct::load::Train& train, double v) {
  sc.settings.filter.enabled = false;
  sc.settings.method = viaduct::study::Method::newmark;
  sc.settings.dt = 2e-4;
  sc.settings.newmark.alpha = alpha;
  sc.settings.newmark.beta = (1 - alpha) * (1 - alpha) / 4;
  sc.settings.newmark.gamma = (1 - 2 * alpha) / 2;
  sc.bridge.bearings = {rigid, rigid ? 0.0 : 1e12, 0.0};
  return viaduct::study::simulate(viaduct::study::prepare_model(sc, true, true), train, v, sc.settings);
}

inline double closed_form_f(int n, double L, double EI, double m) {
  return n * n * M_PI / (2 * L * L) * std::sqrt(EI / m);
}

}  // namespace vt

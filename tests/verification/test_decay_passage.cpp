// viaduct decay on viaduct's own passages (issue #19 part 6): the free vibration after HSLM-A1
// leaves the shipped 15 m span, 3 s of it, at 1 to 3 % modal damping. The record ends while the
// mode still rings (at 1 %: 40 % of its amplitude after the train), so the noise floor must not be
// taken from its end, and the train's last seconds on the span make the peaks fall without a
// rise, so the start must be where they fall as one exponential.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>

#include "helpers.hpp"
#include "viaduct/ident/decay.hpp"

using namespace viaduct;

TEST_CASE("decay: frequency and damping of the shipped span from 3 s of free vibration after HSLM-A1, 1 to 3 %") {
  for (const double zeta : {0.01, 0.015, 0.02, 0.03}) {
    study::Scenario sc = vt::shipped("hslm-simply-supported", {"filter.enabled=false", "analysis.free_vibration_s=3.0"});
    sc.bridge.damping.ratio = zeta;
    const study::PreparedModel pm = study::prepare_model(sc, false);
    const study::RunResult r = study::simulate(pm, sc.trains.front(), 300 / 3.6, sc.settings);
    REQUIRE(!r.stations.empty());
    const Vector& acc = r.stations.front().acc;
    ident::DecayOptions o;
    o.frequency_hz = 5.0;
    const ident::DecayResult d = ident::analyse_decay(acc, 1.0 / sc.settings.dt, 0.0, o);
    const double t_exit = (sc.trains.front().length() + sc.bridge.spans.front().length) / (300 / 3.6);
    std::printf("decay after HSLM-A1, zeta %.3f: start %.3f s (last axle off %.3f s), %.1f cycles, f %.5f Hz, zeta: envelope %.5f, "
                "Hilbert %.5f, log decrement %.5f\n",
                zeta, d.start_s, t_exit, d.n_cycles, d.frequency_hz, d.zeta_envelope_fit, d.zeta_hilbert, d.zeta_log_decrement);
    const double f1 = vt::closed_form_f(1, 15.0, 7.694e9, 15000.0);
    // The start may come up to two cycles before the last axle leaves (the last bogie's forcing
    // is small against the ringing: measured 0.42 s at 1.5 %), but the analysis, after the
    // cycles skipped for the filter's transient, begins after it.
    CHECK(d.start_s + o.skip_cycles / f1 > t_exit);
    CHECK(d.start_s > t_exit - 2.5 / f1);
    CHECK(d.n_cycles >= 8);
    CHECK(std::abs(d.frequency_hz / f1 - 1) < 1e-3);
    // Measured (2026-12-02): envelope fit and Hilbert within 6 % of ζ at 1 % (9.5 cycles, the
    // band-pass's edge bends the last ones), 1 % at 3 %; log decrement within 10 %.
    CHECK(std::abs(d.zeta_envelope_fit / zeta - 1) < 0.08);
    CHECK(std::abs(d.zeta_hilbert / zeta - 1) < 0.08);
    CHECK(std::abs(d.zeta_log_decrement / zeta - 1) < 0.12);
  }
}

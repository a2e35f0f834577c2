// viaduct tradeoff
#include <chrono>
#include <cmath>
#include <cstdio>

#include "cli.hpp"
#include "viaduct/core/error.hpp"
#include "viaduct/io/results.hpp"
#include "viaduct/solve/integrator.hpp"
#include "viaduct/study/tradeoff.hpp"

namespace viaduct::cli {

namespace {
std::string num(double v) { return io::table_cell(v, 6); }

std::vector<std::string> cells(const study::TradeoffRow& r) {
  const auto& s = r.settings;
  const bool modal = s.method == study::Method::modal;
  return {r.label, solve::method_name(s.method),
          s.superposition == study::Superposition::unit_response ? "unit-response" : "direct",
          num(s.dt * 1e3), modal ? num(s.modal.max_frequency_hz) : "", modal ? std::to_string(r.n_modes) : "",
          modal ? (s.modal.static_correction ? "true" : "false") : "", num(r.wall_s), std::to_string(r.n_failed),
          num(r.max_acc_error), num(r.max_disp_error)};
}
struct TradeoffOptions {
  std::optional<int> speeds;
  std::optional<double> reference_dt;
  bool with_ida = false;
};
}  // namespace

Command tradeoff_command() {
  Command c = command("tradeoff", "SCENARIO", "envelope error against wall time for a ladder of methods and settings (tradeoff.csv)");
  const auto declare = [](po::options_description& d, TradeoffOptions& t) {
    d.add_options()("speeds", optional_value(t.speeds), "use N of the scenario's sweep speeds, evenly spread (default: all)")(
        "reference-dt", optional_value(t.reference_dt), "[s] step of the Newmark reference (default: analysis.dt / 4)")(
        "with-ida", po::bool_switch(&t.with_ida), "add IDA rungs (rtol 1e-2, 1e-3, 1e-4; slow on track models)");
  };
  c.usage_and_samples =
      "Runs the scenario's speeds and trains (not its variants) with a converged reference (Newmark at\n"
      "analysis.dt/4) and a ladder: Newmark at 4, 2, 1, 1/2 x dt; modal bases up to 1, 1.5, 2, 3, 5 x the\n"
      "band edge f_c (filter.high_hz, or 30 Hz), with and without the static correction; unit-response\n"
      "superposition when there are several trains; IDA rungs with --with-ida. Error of a rung: the largest envelope difference\n"
      "over speeds, relative to the largest reference value of the same (train, station) curve.\n"
      "Writes OUT/tradeoff.csv (one row per rung, the reference first), OUT/tradeoff_stations.csv\n"
      "(errors per station) and OUT/manifest.toml. Plot with scripts/plot/plot_tradeoff.py OUT.\n\n"
      "Sample runs:\n"
      "  viaduct tradeoff scenarios/hslm-simply-supported.toml --speeds 3 --set 'train.files=[\"data/trains/hslm/A1.toml\"]' --out out/tradeoff-hslm\n"
      "  viaduct tradeoff scenarios/old-guadiana-sensitivity.toml --speeds 1 --set track.approach_length=3 --set track.exit_length=3 --out out/tradeoff-og\n";
  const auto body = [](const Common& o, const TradeoffOptions& t) {
    const auto t0 = std::chrono::steady_clock::now();
    const io::FlatScenario flat = load_scenario(o);
    study::Scenario sc = io::to_scenario(flat);
    sc.settings.ida.log = log_printer(o.quiet);
    if (sc.sweep_speeds.empty())
      throw InputError(SourceLocation{o.scenario, 0, "sweep"}, "no speeds: the trade-off runs the scenario's sweep speeds");
    if (t.speeds) {
      const int n = *t.speeds;
      if (n < 1) throw InputError("--speeds must be >= 1");
      if (static_cast<std::size_t>(n) < sc.sweep_speeds.size()) {
        std::vector<double> pick;
        const double step = n > 1 ? static_cast<double>(sc.sweep_speeds.size() - 1) / (n - 1) : 0.0;
        for (int i = 0; i < n; ++i) pick.push_back(sc.sweep_speeds[static_cast<std::size_t>(std::lround(i * step))]);
        sc.sweep_speeds = pick;
      }
    }
    double ref_dt = 0.0;
    if (t.reference_dt) {
      ref_dt = *t.reference_dt;
      if (!(ref_dt > 0.0)) throw InputError("--reference-dt must be > 0 [s]");
    }
    const study::RunSettings ref = study::reference_settings(sc, ref_dt);
    if (const solve::MethodTraits ida = solve::method_traits(solve::Method::ida); t.with_ida && !ida.built)
      throw InputError(std::string("--with-ida: ") + ida.not_built);
    const auto ladder = study::default_ladder(sc, t.with_ida);
    make_out_dir(o.out);
    const study::TradeoffResult r = study::run_tradeoff(sc, ref, ladder, o.threads, progress_printer("tradeoff", o.quiet, "sweeps"));

    const std::vector<std::string> header = {"rung", "method", "superposition", "dt_ms", "max_frequency_hz", "n_modes",
                                             "static_correction", "wall_s", "n_failed", "max_acc_error",
                                             "max_disp_error"};
    std::vector<std::vector<std::string>> rows = {cells(r.reference)};
    for (const auto& row : r.rungs) rows.push_back(cells(row));
    io::write_table_csv(o.out + "/tradeoff.csv", header, rows);
    std::vector<std::vector<std::string>> srows;
    for (const auto& row : r.rungs)
      for (std::size_t s = 0; s < r.stations.size(); ++s)
        srows.push_back({row.label, r.stations[s], num(row.station_acc_error[s]), num(row.station_disp_error[s])});
    io::write_table_csv(o.out + "/tradeoff_stations.csv", {"rung", "station", "max_acc_error", "max_disp_error"}, srows);
    io::Manifest m = start_manifest(o, "tradeoff");
    m.as_run = io::settings_as_run(ref);
    m.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    m.extra = {{"threads", std::to_string(o.threads)},
               {"n_speeds", std::to_string(sc.sweep_speeds.size())},
               {"n_trains", std::to_string(sc.trains.size())},
               {"reference_dt_s", num(ref.dt)}};
    io::write_manifest(o.out + "/manifest.toml", m, flat);
    if (!o.quiet) {
      std::printf("%-44s %9s %12s %12s\n", "rung", "wall [s]", "acc error", "disp error");
      std::printf("%-44s %9.2f %12s %12s\n", r.reference.label.c_str(), r.reference.wall_s, "(reference)", "");
      for (const auto& row : r.rungs)
        std::printf("%-44s %9.2f %12.3g %12.3g%s\n", row.label.c_str(), row.wall_s, row.max_acc_error, row.max_disp_error,
                    row.n_failed ? "  (failed cases)" : "");
      std::printf("wrote %s/tradeoff.csv\n", o.out.c_str());
    }
    for (const auto& row : r.rungs)
      if (row.n_failed) return runtime_failure;
    return ok;
  };
  return bound(std::move(c), +declare, +body);
}

}  // namespace viaduct::cli

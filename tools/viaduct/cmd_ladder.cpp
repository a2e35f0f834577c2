// viaduct ladder
#include <chrono>
#include <cmath>
#include <cstdio>

#include "cli.hpp"
#include "viaduct/core/error.hpp"
#include "viaduct/io/results.hpp"
#include "viaduct/study/vehicle_ladder.hpp"

namespace viaduct::cli {

namespace {
struct LadderOptions {
  std::optional<double> speed_kmh;
  std::optional<std::string> train;
  double modal_max_hz = 200.0;
};

std::string ladder_cell(double v) { return io::table_cell(v, 6); }
}  // namespace

Command ladder_command() {
  Command c = command("ladder", "SCENARIO", "when vehicles matter: forces, sprung masses, multibody coaches, + rail profile (ladder.csv)");
  const auto declare = [](po::options_description& d, LadderOptions& l) {
    d.add_options()("speed-kmh", optional_value(l.speed_kmh), "train speed [km/h] (default: run.speed_kmh)")(
        "train", optional_value(l.train), "train name (default: the first of train.files)")(
        "modal-max-hz", value(l.modal_max_hz), "modes of the fast path up to this frequency [Hz]; 0: no fast path");
  };
  c.usage_and_samples =
      "Runs one train at one speed as moving forces, as sprung masses (train.unsprung_mass_kg and\n"
      "train.suspension_* or the train's coaches), as multibody coaches (trains of kind \"coaches\") and,\n"
      "when the scenario has an [irregularity], as the richest of these on that rail profile; each\n"
      "on the full model (Newmark at analysis.dt) and on the modal fast path (modes up to\n"
      "--modal-max-hz). Writes OUT/ladder.csv (per rung, path and station: the deck's peaks and their\n"
      "ratio to the richest rung's on Newmark minus 1, contact extremes, car-body acceleration,\n"
      "steps, wall time, error) and OUT/manifest.toml. A rung that fails is listed and the exit\n"
      "code is 1. docs/vehicles.md has the ladder measured on the shipped scenarios.\n\n"
      "Sample runs:\n"
      "  viaduct ladder scenarios/vehicles-25m.toml --modal-max-hz 60 --out out/ladder\n";
  const auto body = [](const Common& o, const LadderOptions& l) {
    const auto t0 = std::chrono::steady_clock::now();
    const io::FlatScenario flat = load_scenario(o);
    const study::Scenario sc = io::to_scenario(flat);
    const double speed = speed_of(sc, l.speed_kmh);
    if (!(l.modal_max_hz >= 0.0) || !std::isfinite(l.modal_max_hz)) throw InputError("--modal-max-hz must be >= 0 [Hz]");
    const load::Train* train = &train_of(sc, l.train);
    const study::LadderResult r = study::vehicle_ladder(sc, *train, speed, l.modal_max_hz);
    make_out_dir(o.out);
    std::vector<std::vector<std::string>> rows;
    for (const auto& row : r.rows)
      for (std::size_t s = 0; s < r.stations.size(); ++s) {
        const bool okay = row.error.empty();
        const bool veh = okay && row.vehicle.present;
        rows.push_back({row.rung, solve::method_name(row.method), std::to_string(row.n_modes), r.stations[s],
                        okay ? ladder_cell(row.peaks[s].max_abs_acc) : "", okay ? ladder_cell(row.acc_vs_richest[s]) : "",
                        okay ? ladder_cell(row.peaks[s].max_abs_disp) : "", okay ? ladder_cell(row.disp_vs_richest[s]) : "",
                        veh ? ladder_cell(row.vehicle.min_contact) : "", veh ? ladder_cell(row.vehicle.max_contact) : "",
                        veh ? ladder_cell(row.vehicle.max_unloading_ratio) : "", veh ? ladder_cell(row.vehicle.max_body_acc) : "",
                        std::to_string(row.n_steps), ladder_cell(row.wall_s), row.error});
      }
    io::write_table_csv(o.out + "/ladder.csv",
                        {"rung", "method", "n_modes", "station", "max_abs_acc_mps2", "acc_vs_richest", "max_abs_disp_m",
                         "disp_vs_richest", "min_contact_N", "max_contact_N", "max_unloading_ratio", "max_body_acc_mps2",
                         "n_steps", "wall_s", "error"},
                        rows);
    io::Manifest m = start_manifest(o, "ladder");
    m.as_run = io::settings_as_run(sc.settings);
    m.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    m.extra = {{"train", "\"" + train->name + "\""},
               {"speed_kmh", std::to_string(speed * 3.6)},
               {"richest", "\"" + r.rows[r.richest].rung + "\""}};
    io::write_manifest(o.out + "/manifest.toml", m, flat);
    bool failed = false;
    for (const auto& row : r.rows) failed = failed || !row.error.empty();
    if (!o.quiet) {
      std::printf("%s at %.1f km/h, station %s, against %s on Newmark:\n", train->name.c_str(), speed * 3.6,
                  r.stations.front().c_str(), r.rows[r.richest].rung.c_str());
      std::printf("  %-26s %-8s %12s %9s %11s %9s %18s %9s\n", "rung", "path", "max|acc|", "vs", "max|disp|", "vs",
                  "contact [kN]", "wall [s]");
      for (const auto& row : r.rows) {
        if (!row.error.empty()) {
          std::printf("  %-26s %-8s failed: %s\n", row.rung.c_str(), solve::method_name(row.method), row.error.c_str());
          continue;
        }
        char contact[64] = "-";
        if (row.vehicle.present)
          std::snprintf(contact, sizeof contact, "%.1f to %.1f", row.vehicle.min_contact / 1e3, row.vehicle.max_contact / 1e3);
        std::printf("  %-26s %-8s %10.4f   %+8.1f%% %9.4f mm %+8.1f%% %18s %9.2f\n", row.rung.c_str(),
                    solve::method_name(row.method), row.peaks[0].max_abs_acc, 100 * row.acc_vs_richest[0],
                    1e3 * row.peaks[0].max_abs_disp, 100 * row.disp_vs_richest[0], contact, row.wall_s);
      }
      std::printf("wrote %s/ladder.csv\n", o.out.c_str());
    }
    return failed ? runtime_failure : ok;
  };
  return bound(std::move(c), +declare, +body);
}

}  // namespace viaduct::cli

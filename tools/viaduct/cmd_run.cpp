// viaduct run
#include <chrono>
#include <cmath>
#include <cstdio>

#include "cli.hpp"
#include "viaduct/io/results.hpp"
#include "viaduct/study/guards.hpp"
#include "viaduct/study/quasi_static.hpp"

namespace viaduct::cli {

namespace {
struct RunOptions {
  std::optional<double> speed_kmh;
  std::optional<std::string> train;
};

// quasi_static.csv (the crawling train's histories, same columns as history.csv's load effects and
// deflections) and dynamic_increments.csv (quantity, max_dynamic, max_static, phi_dyn).
void write_quasi_static(const std::string& out, const study::RunResult& r, const study::QuasiStaticResult& qs) {
  std::vector<std::string> names = {"t_s"};
  std::vector<Vector> cols = {r.t};
  for (std::size_t q = 0; q < qs.names.size(); ++q) {
    names.push_back(qs.names[q]);
    cols.push_back(qs.value[q]);
  }
  io::write_columns_csv(out + "/quasi_static.csv", names, cols);
  std::vector<std::vector<std::string>> rows;
  for (const auto& d : qs.increments)
    rows.push_back({d.name, io::table_cell(d.max_dynamic), io::table_cell(d.max_static), io::table_cell(d.phi_dyn)});
  io::write_table_csv(out + "/dynamic_increments.csv", {"quantity", "max_dynamic", "max_static", "phi_dyn"}, rows);
}

// vehicles.csv (t_s, each axle's contact force a<k>_contact_N, each car body's acceleration
// <body>_acc_mps2) and contact.csv (one row per axle: its offset, static load, extremes, the
// unloading ratio (P0 - min)/P0 and whether the wheel would have lifted).
void write_vehicles(const std::string& out, const study::RunResult& r, const load::Train& train) {
  const study::VehicleHistory& v = r.vehicles;
  std::vector<std::string> names = {"t_s"};
  std::vector<Vector> cols = {r.t};
  for (Index k = 0; k < v.contact_force.cols(); ++k) {
    names.push_back("a" + std::to_string(k + 1) + "_contact_N");
    cols.push_back(v.contact_force.col(k));
  }
  for (std::size_t b = 0; b < v.body_names.size(); ++b) {
    names.push_back(v.body_names[b] + "_acc_mps2");
    cols.push_back(v.body_acc.col(static_cast<Index>(b)));
  }
  io::write_columns_csv(out + "/vehicles.csv", names, cols);
  std::vector<std::vector<std::string>> rows;
  for (Index k = 0; k < v.static_load.size(); ++k) {
    const double p0 = v.static_load[k], lo = v.min_contact[k], hi = v.max_contact[k];
    const double air = v.airborne_s.size() > k ? v.airborne_s[k] : 0.0;
    const double first = v.first_loss_s.size() > k ? v.first_loss_s[k] : std::nan("");
    rows.push_back({"a" + std::to_string(k + 1), io::table_cell(train.offset[static_cast<std::size_t>(k)]), io::table_cell(p0),
                    io::table_cell(lo), io::table_cell(hi), io::table_cell((p0 - lo) / p0), io::table_cell(air),
                    std::isnan(first) ? "" : io::table_cell(first), lo < 0.0 || air > 0.0 ? "true" : "false"});
  }
  io::write_table_csv(out + "/contact.csv",
                      {"axle", "offset_m", "static_N", "min_N", "max_N", "unloading_ratio", "airborne_s", "first_loss_s",
                       "contact_lost"},
                      rows);
}

// The vehicles' extremes, one line each, and a warning for every wheel that would have lifted.
std::vector<std::string> describe_vehicles(const study::RunResult& r, bool quiet) {
  const study::VehicleHistory& v = r.vehicles;
  std::vector<std::string> warnings;
  std::vector<std::string> lifted;
  for (Index k = 0; k < v.min_contact.size(); ++k)
    if (v.min_contact[k] < 0.0 || (v.airborne_s.size() > k && v.airborne_s[k] > 0.0)) lifted.push_back("a" + std::to_string(k + 1));
  if (!lifted.empty()) {
    std::string list;
    for (std::size_t i = 0; i < lifted.size() && i < 8; ++i) list += (i ? ", " : "") + lifted[i];
    if (lifted.size() > 8) list += ", ...";
    const std::string n = std::to_string(lifted.size()) + " of " + std::to_string(v.min_contact.size()) + " axles ";
    if (v.released && r.method == study::Method::ida)
      warnings.push_back(n + "left the rail (" + list + "; the most " + format_number(1e3 * v.airborne_s.maxCoeff(), 3) +
                         " ms in the air in all, contact.csv airborne_s and first_loss_s): unilateral contact, each loss and "
                         "landing located by IDA; with wheels bouncing the deck's peaks can move by per cent with ida.rtol "
                         "(compare two tolerances)");
    else if (v.released)
      warnings.push_back(n + "left the rail (" + list + "; the most " + format_number(1e3 * v.airborne_s.maxCoeff(), 3) +
                         " ms in the air in all, contact.csv airborne_s): unilateral contact, each landed again; landings "
                         "are impacts, resolved only by a step well below the contact's period (compare with a smaller analysis.dt, "
                         "or analysis.method = \"ida\", which locates each loss and landing)");
    else
      warnings.push_back(n + "would have lost contact (" + list + "; contact force below zero, largest unloading ratio " +
                         format_number(v.max_unloading_ratio(), 3) +
                         "): the linear contact kept them on the rail (train.contact_release = false), so the response after "
                         "that is not physical");
  }
  if (!quiet) {
    double acc = 0.0, floor = 0.0;
    std::string body, floor_body;
    for (Index b = 0; b < v.body_acc.cols(); ++b) {
      const double a = v.body_acc.col(b).cwiseAbs().maxCoeff();
      if (a > acc) acc = a, body = v.body_names[static_cast<std::size_t>(b)];
      if (v.max_floor_acc[b] > floor) floor = v.max_floor_acc[b], floor_body = v.body_names[static_cast<std::size_t>(b)];
    }
    std::printf("vehicles: %s, %ld DOFs; contact force %.1f to %.1f kN (static %.1f to %.1f), largest unloading ratio %.3f; "
                "car body max |acc| %.4f m/s² (%s, unfiltered; %.4f over the floor above the bogies, %s)\n",
                v.model.c_str(), static_cast<long>(v.n_dofs), v.min_contact.minCoeff() / 1e3, v.max_contact.maxCoeff() / 1e3,
                v.static_load.minCoeff() / 1e3, v.static_load.maxCoeff() / 1e3, v.max_unloading_ratio(), acc, body.c_str(), floor,
                floor_body.c_str());
  }
  return warnings;
}

void print_increments(const study::QuasiStaticResult& qs, const study::RunResult& r, const study::PreparedModel& pm) {
  std::printf("dynamic increments phi'dyn = max|dynamic| / max|quasi-static| - 1:\n");
  for (const auto& d : qs.increments)
    std::printf("  %-24s %8.4f  (dynamic %.5g, quasi-static %.5g)\n", d.name.c_str(), d.phi_dyn, d.max_dynamic, d.max_static);
  // Bearing forces swing below zero after a resonant passage; the permanent load holds the
  // bearing down unless the swing exceeds it: uplift is flagged.
  std::printf("bearing forces (compression positive), traffic and with the permanent g·m·L/2:\n");
  for (std::size_t j = 0; j < pm.effects.size() && j < r.effects.size(); ++j) {
    if (pm.effects[j].bearing < 0) continue;
    const model::BearingForce& b = pm.structure.bearings[static_cast<std::size_t>(pm.effects[j].bearing)];
    const Vector& f = r.effects[j].value;
    const double lo = f.minCoeff(), hi = f.maxCoeff(), perm = b.permanent;
    const std::string name = "span" + std::to_string(b.span + 1) + (b.end ? "_end" : "_start");
    std::printf("  %-24s traffic %.1f to %.1f kN, permanent %.1f kN: %.1f to %.1f kN%s\n", name.c_str(), lo / 1e3, hi / 1e3,
                perm / 1e3, (perm + lo) / 1e3, (perm + hi) / 1e3, perm + lo < 0 ? "  UPLIFT" : "");
  }
}
}  // namespace

Command run_command() {
  Command c = command("run", "SCENARIO", "one train at one speed: station time histories (history.csv)");
  const auto declare = [](po::options_description& d, RunOptions& r) {
    d.add_options()("speed-kmh", optional_value(r.speed_kmh), "train speed [km/h] (default: run.speed_kmh)")(
        "train", optional_value(r.train), "train name (default: the first of train.files)");
  };
  c.usage_and_samples =
      "Writes OUT/history.csv (t_s and, per station, deflection, raw and filtered acceleration,\n"
      "rail deflection with track; then the load effects: bending moment <station>_moment_Nm,\n"
      "strain <station>_strain_ue at stations[].fibre_m, shear force <station>_shear_N,\n"
      "span<k>_start/end_rot_rad, bearing forces span<k>_start/end_reaction_N; on a continuous\n"
      "deck support<k>_rot_rad and support<k>_reaction_N, k from 1 at the bridge's start),\n"
      "OUT/quasi_static.csv (the same train crawling: deck deflections and load effects),\n"
      "OUT/dynamic_increments.csv (phi'dyn = max|dynamic| / max|quasi-static| - 1 per quantity)\n"
      "and OUT/manifest.toml. Plot with scripts/plot/plot_history.py OUT.\n"
      "With vehicles (train.vehicle = sprung or multibody, docs/vehicles.md) also OUT/vehicles.csv\n"
      "(t_s, a<k>_contact_N per axle, <coach>_acc_mps2 per car body) and OUT/contact.csv (per axle:\n"
      "static_N, min_N, max_N, unloading_ratio, airborne_s, first_loss_s, contact_lost); a wheel that left the rail\n"
      "is warned of (with train.contact_release = false: whose linear contact force went below\n"
      "zero). Plot with scripts/plot/plot_vehicles.py OUT.\n\n"
      "Sample runs:\n"
      "  viaduct run scenarios/old-guadiana-talgo.toml --out out/talgo\n"
      "  viaduct run scenarios/hslm-simply-supported.toml --speed-kmh 300 --train HSLM-A4 --out out/a4\n"
      "  viaduct run scenarios/vehicles-25m.toml --out out/vehicles\n";
  const auto body = [](const Common& o, const RunOptions& ro) {
    const auto t0 = std::chrono::steady_clock::now();
    const io::FlatScenario flat = load_scenario(o);
    study::Scenario sc = io::to_scenario(flat);
    const double speed = speed_of(sc, ro.speed_kmh);
    const load::Train* train = &train_of(sc, ro.train);
    sc.settings.ida.log = log_printer(o.quiet);
    const study::PreparedModel pm = study::prepare_model(sc, /*rail_outputs=*/true, /*with_load_effects=*/true);
    const model::Structure& s = pm.structure;
    const study::RunResult r = study::simulate(pm, *train, speed, sc.settings);
    // The same train crawling: the quasi-static response and φ′dyn per quantity (EN 1991-2 6.4.6.5).
    const study::QuasiStaticResult qs = study::quasi_static(pm, *train, speed, sc.settings.load_factor, r);
    make_out_dir(o.out);
    io::write_history_csv(o.out + "/history.csv", r);
    write_quasi_static(o.out, r, qs);
    io::Manifest m = start_manifest(o, "run");
    m.warnings = study::scenario_warnings(sc, {speed});
    {
      std::vector<double> max_disp;
      for (const auto& p : study::peaks(r)) max_disp.push_back(p.max_abs_disp);
      for (auto& w : study::response_warnings(sc, max_disp)) m.warnings.push_back(std::move(w));
    }
    if (!r.vehicles.empty()) {
      write_vehicles(o.out, r, *train);
      for (auto& w : describe_vehicles(r, o.quiet)) m.warnings.push_back(std::move(w));
    }
    print_warnings("run", m.warnings);
    m.as_run = io::settings_as_run(sc.settings);
    m.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    m.extra = {{"train", "\"" + train->name + "\""},
               {"speed_kmh", std::to_string(speed * 3.6)},
               {"n_dofs", std::to_string(s.n_dofs)},
               {"n_steps", std::to_string(r.summary.n_steps)},
               {"method", std::string("\"") + solve::method_name(sc.settings.method) + "\""},
               {"stop_reason", "\"" + r.summary.describe() + "\""},
               {"n_modes", std::to_string(r.n_modes)},
               {"solver_wall_s", std::to_string(r.summary.wall_s)}};
    io::write_manifest(o.out + "/manifest.toml", m, flat);
    if (!o.quiet) {
      std::printf("%s at %.1f km/h: %ld DOFs, %ld steps, %.2f s\n", train->name.c_str(), speed * 3.6,
                  static_cast<long>(s.n_dofs), static_cast<long>(r.summary.n_steps), r.summary.wall_s);
      std::printf("%s\n", describe_f1(s).c_str());
      if (sc.settings.method == study::Method::ida) std::printf("IDA: %s\n", r.summary.describe().c_str());
      if (pm.modal)
        std::printf("modal: %ld modes, %.2f to %.1f Hz; damping coupling up to %.3f (%s)\n",
                    static_cast<long>(pm.modal->n_modes()), pm.modal_frequency_hz[0],
                    pm.modal_frequency_hz[pm.modal_frequency_hz.size() - 1], pm.modal->max_damping_coupling(),
                    pm.modal->complex_modes() ? "complex modes" : "classical modes");
      const auto pk = study::peaks(r);
      for (std::size_t i = 0; i < pk.size(); ++i)
        std::printf("  %-16s max |acc| %.4f m/s²  max |disp| %.4f mm\n", r.stations[i].name.c_str(), pk[i].max_abs_acc,
                    pk[i].max_abs_disp * 1e3);
      print_increments(qs, r, pm);
      std::printf("wrote %s/history.csv, quasi_static.csv, dynamic_increments.csv%s\n", o.out.c_str(),
                  r.vehicles.empty() ? "" : ", vehicles.csv, contact.csv");
    }
    return ok;
  };
  return bound(std::move(c), +declare, +body);
}

}  // namespace viaduct::cli

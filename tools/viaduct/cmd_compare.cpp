// viaduct compare: a scenario's simulation against a measured record.
#include <chrono>
#include <cmath>
#include <cstdio>

#include "cli.hpp"
#include "viaduct/io/record.hpp"
#include "viaduct/io/results.hpp"
#include "viaduct/io/scenario.hpp"
#include "viaduct/study/comparison.hpp"
#include "viaduct/study/speed.hpp"

namespace viaduct::cli {

namespace {
struct Mapping {
  std::size_t channel = 0;
  std::size_t station = 0;
  std::string quantity;  // "acc" or "disp"
  double scale = 1.0;    // model SI value -> channel unit
};
}  // namespace

namespace {
// --map CHANNEL=STATION pairs: the record channel, the station, and the model quantity its unit asks for.
std::vector<Mapping> mappings_of(const std::vector<std::string>& pairs, const io::Record& rec, const study::Scenario& sc) {
  std::vector<Mapping> maps;
  for (const auto& m : pairs) {
    const auto eq = m.find('=');
    if (eq == std::string::npos) throw InputError("--map needs CHANNEL=STATION, got '" + m + "'");
    Mapping mp;
    mp.channel = rec.channel(m.substr(0, eq));
    const std::string st = m.substr(eq + 1);
    bool found = false;
    for (std::size_t i = 0; i < sc.stations.size(); ++i)
      if (sc.stations[i].name == st) {
        mp.station = i;
        found = true;
      }
    if (!found) throw InputError("--map: no station '" + st + "' in the scenario");
    const io::ChannelQuantity q = io::channel_quantity(rec.units[mp.channel], rec.channels[mp.channel], "--map");
    mp.quantity = q.acceleration ? "acc" : "disp";
    mp.scale = q.scale;
    maps.push_back(mp);
  }
  return maps;
}

// --train, or the first of the scenario's trains.
const load::Train* train_of(const study::Scenario& sc, const po::variables_map& vm) {
  if (!vm.count("train")) return &sc.trains.front();
  for (const auto& t : sc.trains)
    if (t.name == vm["train"].as<std::string>()) return &t;
  throw InputError("no train named '" + vm["train"].as<std::string>() + "' in the scenario");
}
}  // namespace

Command compare_command() {
  Command c;
  c.name = "compare";
  c.summary = "simulation against a measured record: aligned overlays, spectra and metrics";
  c.add_options = [](po::options_description& d) {
    d.add_options()("record", po::value<std::string>(), "record CSV (docs/records.md)")(
        "map", po::value<std::vector<std::string>>()->composing(),
        "CHANNEL=STATION: compare a record channel with a scenario station (repeatable)")(
        "speed-kmh", po::value<double>(), "train speed [km/h] (default: run.speed_kmh)")(
        "train", po::value<std::string>(), "train name (default: the first of train.files)")(
        "max-shift-s", po::value<double>()->default_value(60.0), "alignment search range [s]")(
        "identify-speed-m", po::value<double>(),
        "identify the speed from the record: the train's characteristic distance d [m] (spectral lines of the first mapped channel)")(
        "v-min-kmh", po::value<double>()->default_value(40.0), "speed identification: lowest speed [km/h]")(
        "v-max-kmh", po::value<double>()->default_value(400.0), "speed identification: highest speed [km/h]");
  };
  c.usage_and_samples =
      "Runs the scenario at the train's speed, filters model and record with the scenario's\n"
      "[filter], aligns them by cross-correlation (the shift is reported) and writes OUT/\n"
      "compare_time.csv, compare_spectrum.csv, compare_metrics.csv and manifest.toml. The\n"
      "channel's unit picks the model quantity: _mps2 or _g acceleration, _m or _mm deflection.\n"
      "Plot with scripts/plot_compare.py OUT.\n\n"
      "The speed is --speed-kmh, or identified from the record with --identify-speed-m d (the\n"
      "lines k·v/d of the first mapped channel, as viaduct speed does), or run.speed_kmh.\n\n"
      "Sample runs:\n"
      "  viaduct compare scenarios/old-guadiana-talgo.toml --record data/records/synthetic-deck.csv --map deck_acc=S1_mid --out out/compare\n"
      "  viaduct compare scenarios/old-guadiana-talgo.toml --record data/records/synthetic-deck.csv --map deck_acc=S1_mid --identify-speed-m 13.14 --v-min-kmh 100 --v-max-kmh 250 --out out/compare-id\n";
  c.run = [](const Common& o, const po::variables_map& vm) {
    const auto t0 = std::chrono::steady_clock::now();
    if (!vm.count("record")) throw InputError("--record FILE is required");
    if (!vm.count("map")) throw InputError("at least one --map CHANNEL=STATION is required");
    const io::Record rec = io::read_record(vm["record"].as<std::string>());
    const io::FlatScenario flat = io::load_flat(o.scenario, o.set);
    study::Scenario sc = io::to_scenario(flat);
    double speed = 0.0;
    std::string speed_source = "run.speed_kmh";
    if (vm.count("speed-kmh") && vm.count("identify-speed-m"))
      throw InputError("give --speed-kmh or --identify-speed-m, not both");
    if (vm.count("speed-kmh")) {
      speed = vm["speed-kmh"].as<double>() / 3.6;
      speed_source = "--speed-kmh";
    } else if (sc.run_speed && !vm.count("identify-speed-m")) {
      speed = *sc.run_speed;
    }
    const load::Train* train = train_of(sc, vm);
    const std::vector<Mapping> maps = mappings_of(vm["map"].as<std::vector<std::string>>(), rec, sc);
    if (vm.count("identify-speed-m")) {
      const study::SpeedEstimate e = study::speed_from_spectrum(
          rec.data.col(static_cast<Index>(maps.front().channel)), rec.fs_hz, vm["identify-speed-m"].as<double>(),
          vm["v-min-kmh"].as<double>() / 3.6, vm["v-max-kmh"].as<double>() / 3.6, 4);
      speed = e.speed;
      speed_source = "identified from " + rec.channels[maps.front().channel] + " (+- " + format_number(e.uncertainty * 3.6, 3) + " km/h)";
    }
    if (!(speed > 0.0) || !std::isfinite(speed))
      throw InputError("no valid speed: give --speed-kmh > 0, --identify-speed-m or run.speed_kmh");
    // Simulate unfiltered: the comparison filters model and record alike.
    study::RunSettings rs = sc.settings;
    rs.filter.enabled = false;
    const model::Structure s = model::build_structure(sc.bridge, sc.track);
    const auto stations = study::resolve_stations(s, sc.stations);
    const study::RunResult run = study::simulate(s, stations, *train, speed, rs);
    study::ComparisonOptions co;
    co.filter = sc.settings.filter;
    co.max_shift_s = vm["max-shift-s"].as<double>();
    std::vector<std::string> tnames = {"t_s"}, fnames = {"frequency_hz"};
    std::vector<Vector> tcols, fcols;
    std::vector<std::string> mnames = {"channel", "station", "quantity", "shift_s", "peak_record", "peak_model",
                                       "peak_ratio", "rms_ratio", "correlation", "f_peak_record_hz", "f_peak_model_hz",
                                       "spectral_correlation"};
    std::vector<std::vector<std::string>> metrics;
    if (!o.quiet)
      std::printf("%s at %.1f km/h (%s) against %s (%ld samples at %.6g Hz)\n%-22s %-10s %9s %10s %8s %8s %8s %9s %9s\n",
                  train->name.c_str(), speed * 3.6, speed_source.c_str(), vm["record"].as<std::string>().c_str(),
                  static_cast<long>(rec.n_samples()), rec.fs_hz, "channel", "station", "shift_s", "peak_ratio", "rms", "corr",
                  "spec_corr", "f_rec_hz", "f_mod_hz");
    for (const auto& mp : maps) {
      const auto& h = run.stations[mp.station];
      const Vector model = (mp.quantity == "acc" ? h.acc : h.disp) * mp.scale;
      const study::ChannelComparison cc = study::compare_channel(rec.data.col(static_cast<Index>(mp.channel)), rec.fs_hz,
                                                                 rec.t0_s, model, 1.0 / rs.dt, co);
      const std::string base = rec.channels[mp.channel].substr(0, rec.channels[mp.channel].size() - rec.units[mp.channel].size() - 1);
      const std::string& u = rec.units[mp.channel];
      if (tcols.empty()) tcols.push_back(cc.t);
      tnames.push_back(base + "_record_" + u);
      tcols.push_back(cc.record);
      tnames.push_back(base + "_model_" + u);
      tcols.push_back(cc.model);
      if (fcols.empty()) fcols.push_back(cc.frequency_hz);
      fnames.push_back(base + "_record_amp_" + u);
      fcols.push_back(cc.record_amplitude);
      fnames.push_back(base + "_model_amp_" + u);
      fcols.push_back(cc.model_amplitude);
      auto num = [](double v) { return format_number(v, 8); };
      metrics.push_back({rec.channels[mp.channel], sc.stations[mp.station].name, mp.quantity, num(cc.shift_s),
                         num(cc.peak_record), num(cc.peak_model), num(cc.peak_ratio), num(cc.rms_ratio),
                         num(cc.correlation), num(cc.f_peak_record_hz), num(cc.f_peak_model_hz),
                         num(cc.spectral_correlation)});
      if (!o.quiet)
        std::printf("%-22s %-10s %9.4f %10.4f %8.4f %8.4f %8.4f %9.3f %9.3f\n", rec.channels[mp.channel].c_str(),
                    sc.stations[mp.station].name.c_str(), cc.shift_s, cc.peak_ratio, cc.rms_ratio, cc.correlation,
                    cc.spectral_correlation, cc.f_peak_record_hz, cc.f_peak_model_hz);
    }
    make_out_dir(o.out);
    io::write_columns_csv(o.out + "/compare_time.csv", tnames, tcols);
    io::write_columns_csv(o.out + "/compare_spectrum.csv", fnames, fcols);
    io::write_table_csv(o.out + "/compare_metrics.csv", mnames, metrics);
    io::Manifest m = start_manifest(o, "compare");
    m.inputs = {vm["record"].as<std::string>()};
    m.as_run = io::settings_as_run(sc.settings);
    m.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    m.extra = {{"record", "\"" + vm["record"].as<std::string>() + "\""},
               {"train", "\"" + train->name + "\""},
               {"speed_kmh", format_number(speed * 3.6, 10)},
               {"speed_source", "\"" + speed_source + "\""}};
    io::write_manifest(o.out + "/manifest.toml", m, flat);
    if (!o.quiet) std::printf("wrote %s/compare_{time,spectrum,metrics}.csv\n", o.out.c_str());
    return ok;
  };
  return c;
}

}  // namespace viaduct::cli

// viaduct compare: a scenario's simulation against a measured record.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

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
  study::ResponseKind kind = study::ResponseKind::acceleration;
};

// --map CHANNEL=STATION pairs: the record channel, the station, and the model quantity its unit asks for.
std::vector<Mapping> mappings_of(const std::vector<std::string>& pairs, const io::Record& rec, const study::Scenario& sc) {
  std::vector<Mapping> maps;
  for (const auto& m : pairs) {
    const auto eq = m.find('=');
    if (eq == std::string::npos) throw InputError("--map needs CHANNEL=STATION, got '" + m + "'");
    Mapping mp;
    mp.channel = rec.channel(m.substr(0, eq));
    mp.station = station_index(sc, m.substr(eq + 1), "--map");
    const io::ChannelQuantity q = io::channel_quantity(rec.units[mp.channel], rec.channels[mp.channel], "--map");
    require_strain_fibre(sc, mp.station, rec.channels[mp.channel], q, "--map");
    mp.kind = q;
    maps.push_back(mp);
  }
  return maps;
}

// compare_time.csv's and compare_spectrum.csv's columns: each channel's record and model overlays.
struct Overlays {
  std::vector<std::string> tnames = {"t_s"}, fnames = {"frequency_hz"};
  std::vector<Vector> tcols, fcols;
  void add(const std::string& base, const std::string& u, const study::ChannelComparison& cc) {
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
  }
};

struct CompareOptions {
  std::optional<std::string> record, train;
  std::vector<std::string> maps;
  std::optional<double> speed_kmh, identify_speed_m;
  double max_shift_s = 60.0, v_min_kmh = 40.0, v_max_kmh = 400.0;
  std::string zero = "keep";
};


// The comparison: the scenario run at the identified or given speed, each mapped channel filtered,
// aligned and compared; compare_*.csv and the manifest into --out.
int compare_body(const Common& o, const CompareOptions& k) {
  const auto t0 = std::chrono::steady_clock::now();
  if (!k.record) throw InputError("--record FILE is required");
  if (k.maps.empty()) throw InputError("at least one --map CHANNEL=STATION is required");
  const std::string& record_path = *k.record;
  const io::Record whole = read_record(record_path, o);
  const io::FlatScenario flat = load_scenario(o);
  study::Scenario sc = io::to_scenario(flat);
  double speed = 0.0;
  std::string speed_source = "run.speed_kmh";
  if (k.speed_kmh && k.identify_speed_m) throw InputError("give --speed-kmh or --identify-speed-m, not both");
  if (k.speed_kmh) {
    speed = *k.speed_kmh / 3.6;
    speed_source = "--speed-kmh";
  } else if (sc.run_speed && !k.identify_speed_m) {
    speed = *sc.run_speed;
  }
  const load::Train* train = &train_of(sc, k.train);
  const std::vector<Mapping> maps = mappings_of(k.maps, whole, sc);
  std::vector<std::size_t> used;
  for (const auto& mp : maps) used.push_back(mp.channel);
  const io::Record rec = usable(whole, used, o);  // another channel's missing samples cut nothing
  if (k.identify_speed_m) {
    const study::SpeedEstimate e = study::speed_from_spectrum(rec.data.col(static_cast<Index>(maps.front().channel)), rec.fs_hz,
                                                              *k.identify_speed_m, k.v_min_kmh / 3.6, k.v_max_kmh / 3.6, 4);
    speed = e.speed;
    speed_source = "identified from " + rec.channels[maps.front().channel] + " (+- " + format_number(e.uncertainty * 3.6, 3) + " km/h)";
  }
  if (!(speed > 0.0) || !std::isfinite(speed))
    throw InputError("no valid speed: give --speed-kmh > 0, --identify-speed-m or run.speed_kmh");
  // Simulate unfiltered: the comparison filters model and record alike.
  study::RunSettings rs = sc.settings;
  rs.filter.enabled = false;
  const bool strain = std::any_of(maps.begin(), maps.end(), [](const Mapping& mp) { return mp.kind == study::ResponseKind::strain; });
  study::RunResult run;
  if (strain) {  // strain is a load effect: the prepared model records them
    const study::PreparedModel pm = study::prepare_model(model::build_structure(sc.bridge, sc.track), sc.stations, rs, true, true);
    run = study::simulate(pm, *train, speed, rs);
  } else {
    const model::Structure s = model::build_structure(sc.bridge, sc.track);
    run = study::simulate(s, study::resolve_stations(s, sc.stations), *train, speed, rs);
  }
  study::ComparisonOptions co;
  co.filter = sc.settings.filter;
  co.max_shift_s = k.max_shift_s;
  Overlays ov;
  std::vector<std::string> mnames = {"channel", "station", "quantity", "shift_s", "peak_record", "peak_model",
                                     "peak_ratio", "rms_ratio", "correlation", "f_peak_record_hz", "f_peak_model_hz",
                                     "spectral_correlation", "zero_removed"};
  std::vector<std::vector<std::string>> metrics;
  const study::ZeroSpec zero = study::parse_zero(k.zero, "--zero");
  std::vector<std::string> warnings;
  if (!o.quiet)
    std::printf("%s at %.1f km/h (%s) against %s (%ld samples at %.6g Hz)\n%-22s %-10s %9s %10s %8s %8s %8s %9s %9s\n",
                train->name.c_str(), speed * 3.6, speed_source.c_str(), record_path.c_str(),
                static_cast<long>(rec.n_samples()), rec.fs_hz, "channel", "station", "shift_s", "peak_ratio", "rms", "corr",
                "spec_corr", "f_rec_hz", "f_mod_hz");
  for (const auto& mp : maps) {
    const Vector model = study::station_response(run, mp.station, mp.kind);
    co.filter = study::filter_for(sc.settings.filter, mp.kind);
    study::ChannelComparison cc;
    Vector x = rec.data.col(static_cast<Index>(mp.channel));
    double zeroed = 0.0;
    try {
      cc = study::compare_channel(x, rec.fs_hz, rec.t0_s, model, 1.0 / rs.dt, co);
      if (study::quasi_static_kind(mp.kind)) {  // an accelerometer's or geophone's offset is filtered out
        // The train's entry: where the aligned model's response rises above 1 % of its peak.
        const study::ZeroOutcome z = study::apply_zero(zero, x, rec.fs_hz, rec.t0_s, cc.shift_s + study::response_onset_s(model, 1.0 / rs.dt),
                                                       rec.channels[mp.channel], rec.units[mp.channel], "--zero");
        zeroed = z.removed;
        if (!z.warning.empty()) warnings.push_back(z.warning);
        if (zeroed != 0.0) cc = study::compare_channel(x, rec.fs_hz, rec.t0_s, model, 1.0 / rs.dt, co);
      }
    } catch (const InputError& e) {  // name record and channel, and why the record is short
      const bool cut = rec.n_samples() < whole.n_samples();
      throw InputError("record " + record_path + ", channel " + rec.channels[mp.channel] + ": " + e.what() +
                       (cut ? " (the record was cut to where the channels used have values: see the warning above)" : ""));
    }
    const std::string slip = study::unit_slip_warning(cc.peak_ratio, cc.rms_ratio, cc.correlation, rec.channels[mp.channel]);
    if (!slip.empty()) warnings.push_back(slip);
    const std::string base = rec.channels[mp.channel].substr(0, rec.channels[mp.channel].size() - rec.units[mp.channel].size() - 1);
    const std::string& u = rec.units[mp.channel];
    ov.add(base, u, cc);
    auto num = [](double v) { return io::table_cell(v, 8); };
    metrics.push_back({rec.channels[mp.channel], sc.stations[mp.station].name, study::response_name(mp.kind), num(cc.shift_s),
                       num(cc.peak_record), num(cc.peak_model), num(cc.peak_ratio), num(cc.rms_ratio),
                       num(cc.correlation), num(cc.f_peak_record_hz), num(cc.f_peak_model_hz),
                       num(cc.spectral_correlation), num(zeroed)});
    if (!o.quiet)
      std::printf("%-22s %-10s %9.4f %10.4f %8.4f %8.4f %8.4f %9.3f %9.3f\n", rec.channels[mp.channel].c_str(),
                  sc.stations[mp.station].name.c_str(), cc.shift_s, cc.peak_ratio, cc.rms_ratio, cc.correlation,
                  cc.spectral_correlation, cc.f_peak_record_hz, cc.f_peak_model_hz);
  }
  for (const auto& w : warnings) std::fprintf(stderr, "viaduct compare: warning: %s\n", w.c_str());
  make_out_dir(o.out);
  io::write_columns_csv(o.out + "/compare_time.csv", ov.tnames, ov.tcols);
  io::write_columns_csv(o.out + "/compare_spectrum.csv", ov.fnames, ov.fcols);
  io::write_table_csv(o.out + "/compare_metrics.csv", mnames, metrics);
  io::Manifest m = start_manifest(o, "compare");
  m.inputs = {record_path};
  m.as_run = io::settings_as_run(sc.settings);
  m.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  m.warnings = warnings;
  m.extra = {{"record", "\"" + record_path + "\""},
             {"zero", "\"" + k.zero + "\""},
             {"train", "\"" + train->name + "\""},
             {"speed_kmh", format_number(speed * 3.6, 10)},
             {"speed_source", "\"" + speed_source + "\""}};
  io::write_manifest(o.out + "/manifest.toml", m, flat);
  if (!o.quiet) std::printf("wrote %s/compare_{time,spectrum,metrics}.csv\n", o.out.c_str());
  return ok;
}

}  // namespace

Command compare_command() {
  Command c = record_command("compare", "SCENARIO", "simulation against a measured record: aligned overlays, spectra and metrics");
  const auto declare = [](po::options_description& d, CompareOptions& k) {
    d.add_options()("record", optional_value(k.record), "record CSV (docs/records.md)")(
        "map", list_value(k.maps), "CHANNEL=STATION: compare a record channel with a scenario station (repeatable)")(
        "speed-kmh", optional_value(k.speed_kmh), "train speed [km/h] (default: run.speed_kmh)")(
        "train", optional_value(k.train), "train name (default: the first of train.files)")(
        "max-shift-s", value(k.max_shift_s), "alignment search range [s]")(
        "identify-speed-m", optional_value(k.identify_speed_m),
        "identify the speed from the record: the train's characteristic distance d [m] (spectral lines of the first mapped channel)")(
        "v-min-kmh", value(k.v_min_kmh), "speed identification: lowest speed [km/h]")(
        "v-max-kmh", value(k.v_max_kmh), "speed identification: highest speed [km/h]");
    add_zero_option(d, k.zero);
  };
  c.usage_and_samples =
      "Runs the scenario at the train's speed, filters model and record with the scenario's\n"
      "[filter], aligns them by cross-correlation (the shift is reported) and writes OUT/\n"
      "compare_time.csv, compare_spectrum.csv, compare_metrics.csv and manifest.toml (deflection\n"
      "and strain only low-passed at the filter's upper edge: they carry the quasi-static load). The\n"
      "channel's unit picks the model quantity: acceleration (_mps2, [g], ...), deflection (_m,\n"
      "[mm], ...) or strain (_ue, [µε], [microstrain], ...: the model's 1e6 M y/EI at the\n"
      "station's stations[].fibre_m). Records are read as logger files are (docs/records.md).\n"
      "Plot with scripts/plot/plot_compare.py OUT.\n\n"
      "The speed is --speed-kmh, or identified from the record with --identify-speed-m d (the\n"
      "lines k·v/d of the first mapped channel, as viaduct speed does), or run.speed_kmh.\n\n"
      "Sample runs:\n"
      "  viaduct compare scenarios/old-guadiana-talgo.toml --record data/records/synthetic-deck.csv --map deck_acc=S1_mid --out out/compare\n"
      "  viaduct compare scenarios/old-guadiana-talgo.toml --record data/records/synthetic-deck.csv --map deck_acc=S1_mid --identify-speed-m 13.14 --v-min-kmh 100 --v-max-kmh 250 --out out/compare-id\n"
      "  viaduct compare scenarios/old-guadiana-talgo.toml --record data/records/logger-semicolon.csv --map 'Acc S1 mid=S1_mid' --map 'Strain S1 mid=S1_mid' --set 'stations[0].fibre_m=0.8' --out out/compare-logger\n";
  bind(c, +declare, +compare_body);
  return c;
}

}  // namespace viaduct::cli

// viaduct passages: recorded passages over the model's speed envelope (issue #19 part 5).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include "cli.hpp"
#include "viaduct/io/record.hpp"
#include "viaduct/io/results.hpp"
#include "viaduct/io/scenario.hpp"
#include "viaduct/study/passages.hpp"

namespace viaduct::cli {

namespace {

struct PassagesOptions {
  std::vector<std::string> records, maps;
  std::optional<std::string> train;
  std::optional<double> v_min_kmh, v_max_kmh;
  double speed_band = 3.0, noise_band = 4.0;
  std::string zero = "keep";
};

// A record to read: its path, the train it carries (a name or a file, as written) and a speed.
struct Entry {
  std::string file, train, where;  // where: "TABLE:LINE" or the folder
  double speed_kmh = 0.0;
  std::string base;  // the table's folder, against which a relative train file is also tried
};

// Every --records: a folder (its record files in name order) or a table of passages.
std::vector<Entry> entries_of(const std::vector<std::string>& sources) {
  std::vector<Entry> out;
  for (const auto& src : sources) {
    namespace fs = std::filesystem;
    if (fs::is_directory(src)) {
      for (const auto& f : record_files_in(src)) out.push_back({f, "", src, 0.0, ""});
    } else if (fs::exists(src)) {
      const std::string base = fs::path(src).parent_path().string();
      for (const auto& e : io::read_passage_table(src))
        out.push_back({e.file, e.train, src + ":" + std::to_string(e.line), e.speed_kmh, base.empty() ? "" : base + "/"});
    } else {
      throw InputError("--records " + src + ": no such folder or table");
    }
  }
  return out;
}

// The trains the entries name (a scenario train's name, or a train file: as written, then
// against the table's folder), into `trains`; each entry's index. Every unknown train in one error.
std::vector<std::size_t> resolve_trains(const std::vector<Entry>& entries, const std::optional<std::string>& dflt,
                                        const study::Scenario& sc, std::vector<load::Train>& trains) {
  trains = sc.trains;
  std::map<std::string, std::size_t> files;  // train file -> index
  std::vector<std::size_t> idx;
  std::string errors;
  for (const auto& e : entries) {
    const std::string name = !e.train.empty() ? e.train : dflt ? *dflt : sc.trains.size() == 1 ? sc.trains.front().name : "";
    if (name.empty()) {
      errors += "\n  " + e.where + ": no train for " + e.file + ": give a train column, --train, or a scenario with one train";
      idx.push_back(0);
      continue;
    }
    const auto it = std::find_if(trains.begin(), trains.begin() + static_cast<long>(sc.trains.size()),
                                 [&](const load::Train& t) { return t.name == name; });
    if (it != trains.begin() + static_cast<long>(sc.trains.size())) {
      idx.push_back(static_cast<std::size_t>(it - trains.begin()));
      continue;
    }
    std::string path = name;
    if (!e.train.empty() && name.front() != '/' && std::filesystem::is_regular_file(e.base + name)) path = e.base + name;
    if (!std::filesystem::is_regular_file(path)) {
      std::string have;
      for (const auto& t : sc.trains) have += (have.empty() ? "" : ", ") + t.name;
      errors += "\n  " + e.where + ": train '" + name + "' is neither a train of the scenario (" + (have.empty() ? "none" : have) +
                ") nor a train file";
      idx.push_back(0);
      continue;
    }
    const auto f = files.find(path);
    if (f != files.end()) {
      idx.push_back(f->second);
      continue;
    }
    trains.push_back(io::read_train_file(path));
    files[path] = trains.size() - 1;
    idx.push_back(trains.size() - 1);
  }
  if (!errors.empty()) throw InputError("passages: trains not found:" + errors);
  return idx;
}

struct MapSpec {
  std::string channel;
  std::size_t station = 0;
};

std::vector<MapSpec> maps_of(const std::vector<std::string>& pairs, const study::Scenario& sc) {
  if (pairs.empty()) throw InputError("at least one --map CHANNEL=STATION is required (the first identifies the speed)");
  std::vector<MapSpec> out;
  for (const auto& m : pairs) {
    const auto eq = m.find('=');
    if (eq == std::string::npos) throw InputError("--map needs CHANNEL=STATION, got '" + m + "'");
    out.push_back({m.substr(0, eq), station_index(sc, m.substr(eq + 1), "--map")});
  }
  return out;
}

// One record read into a passage: the mapped channels only, their kind from their units.
study::Passage passage_of(const Entry& e, std::size_t train, const std::vector<MapSpec>& maps, const study::Scenario& sc,
                          const Common& o) {
  const io::Record whole = read_record(e.file, o);
  std::vector<std::size_t> used;
  for (const auto& m : maps) used.push_back(whole.channel(m.channel));
  const io::Record rec = usable(whole, used, o);  // another channel's missing samples cut nothing
  study::Passage p;
  p.name = e.file;
  p.train = train;
  p.fs_hz = rec.fs_hz;
  p.t0_s = rec.t0_s;
  p.speed = e.speed_kmh / 3.6;
  for (const auto& m : maps) {
    const std::size_t c = rec.channel(m.channel);
    const study::ResponseKind k = io::channel_quantity(rec.units[c], rec.channels[c], "--map");
    require_strain_fibre(sc, m.station, rec.channels[c], k, "--map");
    p.channels.push_back({rec.channels[c], m.station, k, rec.data.col(static_cast<Index>(c))});
  }
  return p;
}

std::string cell(double v) { return io::table_cell(v, 8); }

void write_results(const std::string& out, const study::PassageStudy& r, double speed_band) {
  std::vector<std::vector<std::string>> rows, curves, failures, summary;
  std::map<std::pair<std::string, std::string>, std::vector<const study::ChannelVerdict*>> groups;
  std::vector<std::pair<std::string, std::string>> order;
  for (const auto& p : r.passages) {
    if (!p.failure.empty()) {
      failures.push_back({p.name, p.train, p.failure});
      continue;
    }
    std::string speed_flag;
    for (const auto& f : p.speed_flags) speed_flag += (speed_flag.empty() ? "" : "; ") + f;
    for (const auto& c : p.channels) {
      rows.push_back({p.name, p.train, cell(p.speed * 3.6), cell(speed_band * p.speed_se * 3.6), p.identified ? "identified" : "given",
                      p.identified ? cell(p.signature_correlation) : "", c.channel, c.station, study::response_name(c.kind),
                      study::response_unit(c.kind), cell(c.measured), cell(c.predicted), cell(c.predicted_low), cell(c.predicted_high),
                      std::isfinite(c.ratio) ? cell(c.ratio) : "", cell(c.noise_rms), cell(c.correlation), c.within ? "true" : "false",
                      c.residual, c.residual == "white" ? "" : cell(c.residual_size), cell(c.zero_removed), speed_flag});
      const auto key = std::make_pair(c.station, std::string(study::response_name(c.kind)));
      if (!groups.count(key)) order.push_back(key);
      groups[key].push_back(&c);
    }
  }
  for (const auto& c : r.curves)
    for (std::size_t i = 0; i < c.speeds.size(); ++i)
      curves.push_back({c.train, c.station, study::response_name(c.kind), study::response_unit(c.kind), cell(c.speeds[i] * 3.6), cell(c.peaks[i])});
  for (const auto& key : order) {
    std::vector<double> ratios;
    int within = 0;
    for (const auto* c : groups[key]) {
      if (std::isfinite(c->ratio)) ratios.push_back(c->ratio);
      within += c->within;
    }
    std::sort(ratios.begin(), ratios.end());
    const std::size_t n = ratios.size();
    const double median = n == 0 ? NAN : n % 2 ? ratios[n / 2] : 0.5 * (ratios[n / 2 - 1] + ratios[n / 2]);
    summary.push_back({key.first, key.second, std::to_string(groups[key].size()), n ? cell(median) : "", n ? cell(ratios.front()) : "",
                       n ? cell(ratios.back()) : "", std::to_string(within)});
  }
  io::write_table_csv(out + "/passages.csv",
                      {"passage", "train", "speed_kmh", "speed_uncertainty_kmh", "speed_source", "signature_correlation", "channel",
                       "station", "quantity", "unit", "measured", "predicted", "predicted_low", "predicted_high", "ratio", "noise_rms",
                       "correlation", "within", "residual", "residual_size", "zero_removed", "speed_flag"},
                      rows);
  io::write_table_csv(out + "/model_envelope.csv", {"train", "station", "quantity", "unit", "speed_kmh", "peak"}, curves);
  io::write_table_csv(out + "/passages_summary.csv", {"station", "quantity", "n", "ratio_median", "ratio_min", "ratio_max", "n_within"},
                      summary);
  io::write_table_csv(out + "/failures.csv", {"passage", "train", "message"}, failures);
}

void print_passages(const study::PassageStudy& r, double speed_band) {
  std::printf("\n%-34s %-16s %11s %8s  %s\n", "passage", "train", "km/h", "+-", "measured/predicted per channel (* outside the band)");
  for (const auto& p : r.passages) {
    const std::string name = std::filesystem::path(p.name).filename().string();
    if (!p.failure.empty()) {
      std::printf("%-34s %-16s failed: %s\n", name.c_str(), p.train.c_str(), p.failure.c_str());
      continue;
    }
    std::string cells;
    for (const auto& c : p.channels) cells += "  " + c.channel + " " + format_number(c.ratio, 4) + (c.within ? "" : " *");
    std::printf("%-34s %-16s %11.2f %8s %s\n", name.c_str(), p.train.c_str(), p.speed * 3.6,
                p.identified ? format_number(speed_band * p.speed_se * 3.6, 3).c_str() : "given", cells.c_str());
  }
}

int passages_body(const Common& o, const PassagesOptions& k) {
  const auto t0 = std::chrono::steady_clock::now();
  if (k.records.empty()) throw InputError("--records FOLDER|TABLE is required (a folder of records or a table file,train,speed_kmh)");
  const io::FlatScenario flat = load_scenario(o);
  study::Scenario sc = io::to_scenario(flat);
  if (sc.sweep_speeds.empty())
    throw InputError(SourceLocation{o.scenario, 0, "sweep"},
                     "no speeds for the model's envelope: give sweep.speeds_kmh, sweep.speed_min/max/step_kmh or sweep.speed_min/max_mps with n_speeds");
  const std::vector<MapSpec> maps = maps_of(k.maps, sc);
  const std::vector<Entry> entries = entries_of(k.records);
  std::vector<load::Train> trains;
  const std::vector<std::size_t> train_of = resolve_trains(entries, k.train, sc, trains);
  study::PassageOptions po;
  const auto [lo, hi] = std::minmax_element(sc.sweep_speeds.begin(), sc.sweep_speeds.end());
  po.v_min = k.v_min_kmh ? *k.v_min_kmh / 3.6 : *lo;
  po.v_max = k.v_max_kmh ? *k.v_max_kmh / 3.6 : *hi;
  po.speed_band = k.speed_band;
  po.noise_band = k.noise_band;
  po.zero = study::parse_zero(k.zero, "--zero");
  po.threads = o.threads;
  // Read every record (the mapped channels only); one that cannot be read is a failed passage.
  std::vector<study::Passage> passages;
  std::vector<study::PassageResult> unread;
  bool strain = false;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    try {
      passages.push_back(passage_of(entries[i], train_of[i], maps, sc, o));
      for (const auto& c : passages.back().channels) strain = strain || c.kind == study::ResponseKind::strain;
    } catch (const InputError& e) {
      study::PassageResult f;
      f.name = entries[i].file;
      f.train = trains[train_of[i]].name;
      f.failure = e.what();
      f.input_error = true;
      unread.push_back(f);  // reported with the others at the end
    }
  }
  study::RunSettings rs = sc.settings;
  rs.filter.enabled = false;
  rs.ida.log = log_printer(o.quiet);
  const study::PreparedModel pm = study::prepare_model(model::build_structure(sc.bridge, sc.track), sc.stations, rs, true, strain);
  po.progress = progress_printer("passages", o.quiet, "runs");
  study::PassageStudy r = passages.empty() ? study::PassageStudy{}
                                           : study::run_passages(pm, rs, sc.settings.filter, trains, sc.sweep_speeds, passages, po);
  r.passages.insert(r.passages.end(), unread.begin(), unread.end());
  std::vector<std::string> warnings = r.envelope_failures;
  for (const auto& p : r.passages) {
    if (!p.failure.empty() || !p.identified) continue;
    if (p.speed < po.v_min * 1.005 || p.speed > po.v_max * 0.995)
      warnings.push_back(p.name + ": identified speed " + format_number(p.speed * 3.6, 5) +
                         " km/h at the edge of the range searched; widen --v-min-kmh/--v-max-kmh");
    if (p.speed < *lo || p.speed > *hi)
      warnings.push_back(p.name + ": " + format_number(p.speed * 3.6, 5) + " km/h is outside the envelope's speeds (sweep.*)");
    for (const auto& f : p.speed_flags) warnings.push_back(p.name + ": identified speed: " + f + " (passages.csv speed_flag)");
  }
  for (const auto& p : r.passages)
    for (const auto& c : p.channels)
      if (!c.offset_warning.empty()) warnings.push_back(p.name + ", " + c.offset_warning);
  for (const auto& p : r.passages)
    for (const auto& c : p.channels)
      if (c.residual != "white")
        warnings.push_back(p.name + ", " + c.channel + ": the record less the model holds a" +
                           (c.residual == "offset" ? "n offset" : " " + c.residual) + " of " + format_number(c.residual_size, 4) +
                           " " + study::response_unit(c.kind) + " (passages.csv residual): the peak is not judged (within = false); "
                           "zero the channel, or cut the record where it jumps or drifts");
  make_out_dir(o.out);
  write_results(o.out, r, po.speed_band);
  io::Manifest m = start_manifest(o, "passages");
  for (const auto& e : entries) m.inputs.push_back(e.file);
  m.warnings = warnings;
  print_warnings("passages", warnings);
  m.as_run = io::settings_as_run(sc.settings);
  m.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::size_t n_failed = 0, n_input = 0;
  for (const auto& p : r.passages) n_failed += !p.failure.empty(), n_input += p.input_error;
  m.extra = {{"n_passages", std::to_string(r.passages.size())}, {"n_failed", std::to_string(n_failed)},
             {"speed_band_se", format_number(po.speed_band)}, {"noise_band_rms", format_number(po.noise_band)}};
  io::write_manifest(o.out + "/manifest.toml", m, flat);
  if (!o.quiet) {
    print_passages(r, po.speed_band);
    std::printf("\n%zu passages, %zu failed, %.1f s; wrote %s/passages.csv, passages_summary.csv, model_envelope.csv\n",
                r.passages.size(), n_failed, m.wall_s, o.out.c_str());
  }
  for (const auto& p : r.passages)
    if (!p.failure.empty()) std::fprintf(stderr, "viaduct passages: failed: %s: %s\n", p.name.c_str(), p.failure.c_str());
  if (n_failed == 0) return ok;
  return n_input == r.passages.size() ? 2 : 1;
}

}  // namespace

Command passages_command() {
  Command c = record_command("passages", "SCENARIO",
                             "recorded passages over the model's speed envelope: measured/predicted peaks per station (passages.csv)");
  const auto declare = [](po::options_description& d, PassagesOptions& k) {
    d.add_options()("records", list_value(k.records),
                    "a folder of records, or a table (CSV: file[,train][,speed_kmh]; files relative to it) (repeatable)")(
        "map", list_value(k.maps), "CHANNEL=STATION: a record channel at a scenario station (repeatable; the first identifies the speed)")(
        "train", optional_value(k.train), "the train of records without one: a train of the scenario or a train file (default: its only train)")(
        "v-min-kmh", optional_value(k.v_min_kmh), "speed identification: lowest speed [km/h] (default: the sweep's lowest)")(
        "v-max-kmh", optional_value(k.v_max_kmh), "speed identification: highest speed [km/h] (default: the sweep's highest)")(
        "speed-band", value(k.speed_band), "the predicted peak's range over the speed +- this many standard errors")(
        "noise-band", value(k.noise_band), "within the model: measured in the predicted range +- this many noise RMS");
    add_zero_option(d, k.zero);
  };
  c.usage_and_samples =
      "For each record: the train's speed identified from the first --map channel by matching\n"
      "the train's signature (as `viaduct speed --model`, with its checks of a model that does\n"
      "not match: speed_flag, and an uncertainty that covers the axles' timing), or the table's\n"
      "speed_kmh; each mapped\n"
      "channel's peak under the scenario's [filter] (deflection and strain: its low-pass part),\n"
      "against the model's peak for that train at that speed (run at it and at +-speed-band\n"
      "standard errors: predicted_low/high) and the model's envelope at the sweep's speeds.\n"
      "noise_rms: the filtered record minus the aligned model scaled by least squares; a passage\n"
      "is within the model when measured lies in [predicted_low - noise-band*noise_rms,\n"
      "predicted_high + noise-band*noise_rms]. The channel's unit picks the model quantity, as in\n"
      "compare. Writes OUT/passages.csv (one row per passage and channel), passages_summary.csv\n"
      "(per station and quantity: n, median, min and max ratio, n within), model_envelope.csv\n"
      "(train,station,quantity,unit,speed_kmh,peak), failures.csv and manifest.toml. A record that\n"
      "cannot be read or matched is listed in failures.csv and the others complete (exit 1; 2 when\n"
      "none could be read). Plot with scripts/plot/plot_passages.py OUT.\n\n"
      "Sample runs:\n"
      "  viaduct passages scenarios/hslm-simply-supported.toml --records data/records/passages/passages.csv --map mid_acc=mid --map mid_disp=mid --set analysis.method=modal --set sweep.speed_step_kmh=10 --out out/passages\n";
  bind(c, +declare, +passages_body);
  return c;
}

}  // namespace viaduct::cli

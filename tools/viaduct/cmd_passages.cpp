// viaduct passages: recorded passages over the model's speed envelope (issue #19 part 5).
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "cli.hpp"
#include "viaduct/io/passages.hpp"
#include "viaduct/io/results.hpp"
#include "viaduct/io/scenario.hpp"

namespace viaduct::cli {

namespace {

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

// The options bind straight into the request (io/passages.hpp); the rest comes from Common.
int passages_body(const Common& o, const io::PassagesRequest& options) {
  const auto t0 = std::chrono::steady_clock::now();
  const io::FlatScenario flat = load_scenario(o);
  io::PassagesRequest q = options;
  q.threads = o.threads;
  q.read = o.read;
  q.on_read = [&o](const std::string& path, const io::ImportReport& rep) { print_import_report(path, rep, o); };
  q.on_cut = [](const std::string& note) { std::fprintf(stderr, "viaduct passages: warning: %s\n", note.c_str()); };
  q.progress = progress_printer("passages", o.quiet, "runs");
  q.log = log_printer(o.quiet);
  const io::PassagesOutcome r = io::run_passages(flat, q);
  make_out_dir(o.out);
  io::write_passages_tables(o.out, r);
  io::Manifest m = start_manifest(o, "passages");
  m.inputs = r.inputs;
  m.warnings = r.warnings;
  print_warnings("passages", r.warnings);
  m.as_run = io::settings_as_run(r.settings);
  m.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  m.extra = {{"n_passages", std::to_string(r.study.passages.size())}, {"n_failed", std::to_string(r.n_failed)},
             {"speed_band_se", format_number(r.speed_band)}, {"noise_band_rms", format_number(r.noise_band)}};
  io::write_manifest(o.out + "/manifest.toml", m, flat);
  if (!o.quiet) {
    print_passages(r.study, r.speed_band);
    std::printf("\n%zu passages, %zu failed, %.1f s; wrote %s/passages.csv, passages_summary.csv, model_envelope.csv\n",
                r.study.passages.size(), r.n_failed, m.wall_s, o.out.c_str());
  }
  for (const auto& p : r.study.passages)
    if (!p.failure.empty()) std::fprintf(stderr, "viaduct passages: failed: %s: %s\n", p.name.c_str(), p.failure.c_str());
  if (r.n_failed == 0) return ok;
  return r.n_input_errors == r.study.passages.size() ? 2 : 1;
}

}  // namespace

Command passages_command() {
  Command c = record_command("passages", "SCENARIO",
                             "recorded passages over the model's speed envelope: measured/predicted peaks per station (passages.csv)");
  const auto declare = [](po::options_description& d, io::PassagesRequest& k) {
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

// viaduct sweep
#include <algorithm>
#include <chrono>
#include <cstdio>

#include "cli.hpp"
#include "viaduct/study/guards.hpp"
#include "viaduct/io/results.hpp"
#include "viaduct/io/sampled.hpp"

namespace viaduct::cli {

namespace {
// The governing case of each station, at a glance.
void print_governing(const std::vector<study::GoverningRow>& gov, bool with_variant) {
  if (gov.empty()) return;
  std::printf("\ngoverning cases (largest over %strains and speeds):\n", with_variant ? "variants, " : "");
  std::printf("  %-14s %14s  %-16s %7s%s   %12s  %-16s %7s%s\n", "station", "max|acc| m/s²", "train", "km/h",
              with_variant ? "  variant" : "", "max|disp| mm", "train", "km/h", with_variant ? "  variant" : "");
  for (const auto& g : gov)
    std::printf("  %-14s %14.4f  %-16s %7.1f%s   %12.3f  %-16s %7.1f%s\n", g.station.c_str(), g.acc.value, g.acc.train.c_str(),
                g.acc.speed * 3.6, with_variant ? ("  " + g.acc.variant).c_str() : "", g.disp.value * 1e3,
                g.disp.train.c_str(), g.disp.speed * 3.6, with_variant ? ("  " + g.disp.variant).c_str() : "");
}

struct SweepOpts {
  bool load_effects = false;
  SampleCliOptions sample;
};

void declare_sweep(po::options_description& d, SweepOpts& s) {
  d.add_options()("load-effects", po::bool_switch(&s.load_effects),
                  "also the extremes of every deck deflection and load effect with phi'dyn (load_effects.csv); "
                  "modal sweeps keep the peaks kernel when every effect is a functional of the deflections")(
      "shard", value(s.sample.shard),
      "sampled studies: run the K-th of N parts of the samples (K/N) into --out; viaduct merge joins the parts")(
      "resume", po::bool_switch(&s.sample.resume),
      "sampled studies: carry on the run interrupted in --out from its last complete batch");
}

int run_sweep_command(const Common& o, const SweepOpts& opts);
}  // namespace

Command sweep_command() {
  Command c;
  c.name = "sweep";
  c.summary = "speeds x trains x parameter variants: maximum-response envelopes (envelope.csv)";
  c.usage_and_samples =
      "Writes OUT/envelope.csv (variant,train,speed_kmh,station,max_abs_acc_mps2,max_abs_disp_m;\n"
      "accelerations filtered as the scenario says; with sweep.variants, a column KEY_factor per\n"
      "varied key after variant), OUT/governing.csv (the largest value per station and where it\n"
      "occurs), OUT/failures.csv and OUT/manifest.toml; with --load-effects OUT/load_effects.csv\n"
      "(per case and quantity: max, min, the quasi-static extremes of the train crawling, phi_dyn);\n"
      "with vehicle models (train.vehicle = sprung or multibody) OUT/vehicles.csv (per case: the\n"
      "smallest and largest contact force, unloading ratio, contact_lost, car-body acceleration).\n"
      "Results are identical for any --threads. A case that fails is listed in failures.csv,\n"
      "the others complete, and the exit code is 1 (2 when every case failed on its input, as\n"
      "`run` exits with the same value). Plot with scripts/plot/plot_envelope.py OUT.\n\n"
      "With sweep.mode = \"sample\" (docs/sampled.md) each sample draws every variant key's factor from\n"
      "its distribution; writes OUT/samples.csv (the design), OUT/sample_peaks.csv (per sample, train,\n"
      "speed and station), OUT/percentiles.csv and OUT/peak_percentiles.csv (percentiles of the peaks,\n"
      "probability of exceeding sweep.acceleration_limit_mps2 with its standard error and 95 % bound)\n"
      "and, with sweep.sensitivity, OUT/sensitivity.csv and OUT/peak_sensitivity.csv (Sobol indices with\n"
      "bootstrap intervals). Results are flushed batch by batch: --resume carries on an interrupted run;\n"
      "--shard K/N runs a part, viaduct merge joins them. Plot with scripts/plot/plot_sampled.py OUT.\n\n"
      "Sample runs:\n"
      "  viaduct sweep scenarios/hslm-simply-supported.toml --set 'train.files=[\"data/trains/hslm/A1.toml\"]' --set sweep.speed_step_kmh=20 --out out/hslm\n"
      "  viaduct sweep scenarios/old-guadiana-sensitivity.toml --set sweep.speed_min_mps=90 --set sweep.n_speeds=1 --threads 0 --out out/og\n"
      "  viaduct sweep scenarios/vehicles-25m.toml --set sweep.speed_step_kmh=120 --out out/vehicles-sweep\n"
      "  viaduct sweep scenarios/old-guadiana-sampled.toml --set sweep.n_samples=8 --set sweep.n_speeds=4 --threads 0 --out out/og-sampled\n";
  bind(c, declare_sweep, run_sweep_command);
  return c;
}

namespace {
int run_sweep_command(const Common& o, const SweepOpts& opts) {
    const auto t0 = std::chrono::steady_clock::now();
    const io::FlatScenario flat = load_scenario(o);
    if (io::is_sampled(flat)) {
      if (opts.load_effects)
        throw InputError(flat.at("sweep.mode").where, "--load-effects is not available for sampled studies (they keep the deck peaks)");
      return run_sampled_sweep(o, flat, opts.sample);
    }
    const SourceLocation mode_at = flat.has("sweep.mode") ? flat.at("sweep.mode").where : SourceLocation{o.scenario, 0, "sweep.mode"};
    if (study::mpi_world().size > 1)
      throw InputError(mode_at, "an MPI run shares the samples of a sampled study (sweep.mode = \"sample\"); "
                                                    "this sweep runs in one process (viaduct sweep --threads N)");
    if (!opts.sample.shard.empty() || opts.sample.resume)
      throw InputError(mode_at, "--shard and --resume apply to sampled studies (sweep.mode = \"sample\")");
    auto variants = io::sweep_variants(flat, /*isolate_failures=*/true);
    for (auto& v : variants) v.scenario.settings.ida.log = log_printer(o.quiet);
    if (variants.front().scenario.sweep_speeds.empty())
      throw InputError(SourceLocation{o.scenario, 0, "sweep"},
                       "no speeds: give sweep.speeds_kmh, sweep.speed_min/max/step_kmh or sweep.speed_min/max_mps with n_speeds");
    make_out_dir(o.out);
    study::SweepOptions so;
    so.threads = o.threads;
    so.progress = progress_printer("sweep", o.quiet);
    so.load_effects = opts.load_effects;
    const study::SweepResult r = study::run_sweep(variants, so);
    io::write_envelope_csv(o.out + "/envelope.csv", r.rows, variants);
    if (opts.load_effects) io::write_quantities_csv(o.out + "/load_effects.csv", r.quantities, variants);
    if (!r.vehicles.empty()) io::write_vehicle_envelope_csv(o.out + "/vehicles.csv", r.vehicles, variants);
    io::write_failures_csv(o.out + "/failures.csv", r.failures);
    const std::vector<study::GoverningRow> gov = study::governing(r.rows);
    io::write_governing_csv(o.out + "/governing.csv", gov);
    io::Manifest m = start_manifest(o, "sweep");
    m.warnings = study::accuracy_warnings(variants.front().scenario, variants.front().scenario.sweep_speeds);
    print_warnings("sweep", m.warnings);
    m.as_run = io::settings_as_run(variants.front().scenario.settings);
    m.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    m.extra = {{"threads", std::to_string(o.threads)},
               {"n_variants", std::to_string(variants.size())},
               {"n_cases", std::to_string(r.summary.n_cases)},
               {"n_failed", std::to_string(r.summary.n_failed)},
               {"n_steps_total", std::to_string(r.summary.n_steps_total)},
               {"n_dofs_reference", std::to_string(r.summary.n_dofs.front())},
               {"sweep_wall_s", std::to_string(r.summary.wall_s)}};
    io::write_manifest(o.out + "/manifest.toml", m, flat);
    if (!o.quiet) {
      std::printf("%zu cases (%zu variants), %zu failed, %.1f s; wrote %s/envelope.csv and governing.csv\n", r.summary.n_cases,
                  variants.size(), r.summary.n_failed, r.summary.wall_s, o.out.c_str());
      print_governing(gov, variants.size() > 1);
      // Where the peaks are expected, from the reference model's first deck bending frequency.
      const study::Scenario& ref = variants.front().scenario;
      std::vector<model::DeckMode> deck;
      const std::string f1 = describe_f1(model::build_structure(ref.bridge, ref.track), &deck);
      if (deck.empty()) std::printf("\n%s\n", f1.c_str());
      else {
        const auto [lo, hi] = std::minmax_element(ref.sweep_speeds.begin(), ref.sweep_speeds.end());
        print_resonance_speeds(deck.front().frequency_hz, ref.trains, *lo, *hi);
      }
    }
    return sweep_exit_code("sweep", o.scenario, r);
}
}  // namespace

}  // namespace viaduct::cli

// viaduct sweep
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <tuple>

#include "cli.hpp"
#include "viaduct/study/guards.hpp"
#include "viaduct/io/results.hpp"
#include "viaduct/io/sampled.hpp"
#include "viaduct/io/sweep_shard.hpp"

namespace viaduct::cli {

namespace {
struct SweepOpts {
  bool load_effects = false;
  SampleCliOptions sample;
};

void declare_sweep(po::options_description& d, SweepOpts& s) {
  d.add_options()("load-effects", po::bool_switch(&s.load_effects),
                  "also the extremes of every deck deflection and load effect with phi'dyn (load_effects.csv); "
                  "modal sweeps keep them in the peaks kernel")(
      "shard", value(s.sample.shard),
      "run the K-th of N parts (K/N) of the cases (of the samples of a sampled study) into --out; viaduct merge "
      "joins the parts")(
      "resume", po::bool_switch(&s.sample.resume),
      "sampled studies: carry on the run interrupted in --out from its last complete batch");
}

int run_sweep_command(const Common& o, const SweepOpts& opts);

// shard.toml of a shard of a sweep: its range, the files it wrote and its governing cases.
void write_shard(io::SweepShard& shard, const std::string& out, const io::FlatScenario& flat, const study::SweepOptions& so,
                 const study::SweepResult& r, const std::vector<study::GoverningRow>& gov, std::size_t variants_count) {
  shard.dir = out;
  shard.begin = so.case_begin;
  shard.end = so.case_end;
  shard.fingerprint = io::sha256_hex(io::resolved_toml(flat));
  shard.files = {"envelope.csv", "failures.csv"};
  if (so.load_effects) shard.files.push_back("load_effects.csv");
  if (!r.vehicles.empty()) shard.files.push_back("vehicles.csv");
  shard.load_effects = so.load_effects;
  shard.n_variants = variants_count;
  shard.n_rows = r.rows.size();
  shard.n_failed = r.failures.size();
  shard.n_failed_input =
      static_cast<std::size_t>(std::count_if(r.failures.begin(), r.failures.end(), [](const auto& f) { return f.input_error; }));
  shard.governing = gov;
  io::write_sweep_shard_toml(shard);
}
}  // namespace

Command sweep_command() {
  Command c = command("sweep", "SCENARIO", "speeds x trains x parameter variants: maximum-response envelopes (envelope.csv)");
  c.usage_and_samples =
      "Writes OUT/envelope.csv (variant,train,speed_kmh,station,max_abs_acc_mps2,max_abs_disp_m;\n"
      "accelerations filtered as the scenario says; with sweep.variants, a column KEY_factor per\n"
      "varied key after variant), OUT/governing.csv (the largest value per station and where it\n"
      "occurs), OUT/failures.csv and OUT/manifest.toml; with --load-effects OUT/load_effects.csv\n"
      "(per case and quantity: max, min, the quasi-static extremes of the train crawling, phi_dyn);\n"
      "with vehicle models (train.vehicle = sprung or multibody) OUT/vehicles.csv (per case: the\n"
      "smallest and largest contact force, unloading ratio, contact_lost, car-body acceleration at\n"
      "the centre and, max_floor_acc_mps2, over the floor above the bogie centres).\n"
      "Results are identical for any --threads. A case that fails is listed in failures.csv,\n"
      "the others complete, and the exit code is 1 (2 when every case failed on its input, as\n"
      "`run` exits with the same value). Plot with scripts/plot/plot_envelope.py OUT.\n"
      "--shard K/N runs the K-th of N parts of the cases (variant, train, speed order) and writes\n"
      "shard.toml beside its files; viaduct merge joins the parts into the one-process files.\n\n"
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
      "  viaduct sweep scenarios/old-guadiana-sampled.toml --set sweep.n_samples=4 --set sweep.n_speeds=3 --threads 0 --out out/og-sampled\n";
  bind(c, declare_sweep, run_sweep_command);
  return c;
}

namespace {
int run_sweep_command(const Common& o, const SweepOpts& opts) {
    const auto t0 = std::chrono::steady_clock::now();
    const io::FlatScenario flat = load_scenario(o);
    // Stations along a span give load effects only: without --load-effects (or in a sampled
    // study, which keeps the deck peaks) they would add nothing, so say so rather than drop them.
    if (!opts.load_effects || io::is_sampled(flat))
      for (const auto& [key, value] : flat.values)
        if (key.size() > 8 && key.compare(key.size() - 8, 8, ".every_m") == 0 && !o.quiet) {
          // InputError's message names the file, line and key as its errors do.
          print_warnings("sweep", {InputError(value.where, "stations along a span give load effects only, which this sweep "
                                                           "does not keep (add --load-effects; sampled studies keep the deck "
                                                           "peaks): they are left out").what()});
          break;
        }
    if (io::is_sampled(flat)) {
      if (opts.load_effects)
        throw InputError(flat.at("sweep.mode").where, "--load-effects is not available for sampled studies (they keep the deck peaks)");
      return run_sampled_sweep(o, flat, opts.sample);
    }
    const SourceLocation mode_at = flat.has("sweep.mode") ? flat.at("sweep.mode").where : SourceLocation{o.scenario, 0, "sweep.mode"};
    if (study::mpi_world().size > 1)
      throw InputError(mode_at, "an MPI run shares the samples of a sampled study (sweep.mode = \"sample\"); "
                                "this sweep runs in one process (viaduct sweep --threads N) or in shards (--shard K/N)");
    if (opts.sample.resume)
      throw InputError(mode_at, "--resume applies to sampled studies (sweep.mode = \"sample\"); rerun a failed shard "
                                "of this sweep alone (--shard K/N)");
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
    io::SweepShard shard;
    if (!opts.sample.shard.empty()) {
      std::tie(shard.k, shard.n) = io::parse_shard(opts.sample.shard);
      shard.n_total = study::count_cases(variants);
      std::tie(so.case_begin, so.case_end) = io::sweep_shard_range(shard.k, shard.n, shard.n_total);
      // A rerun into the same directory: until it has finished, the directory is no shard.
      std::remove((o.out + "/shard.toml").c_str());
    }
    const study::SweepResult r = study::run_sweep(variants, so);
    io::write_envelope_csv(o.out + "/envelope.csv", r.rows, variants);
    if (opts.load_effects) io::write_quantities_csv(o.out + "/load_effects.csv", r.quantities, variants, o.threads);
    if (!r.vehicles.empty()) io::write_vehicle_envelope_csv(o.out + "/vehicles.csv", r.vehicles, variants);
    io::write_failures_csv(o.out + "/failures.csv", r.failures);
    const std::vector<study::GoverningRow> gov = study::governing(r.rows);
    io::write_governing_csv(o.out + "/governing.csv", gov);
    if (shard.n) write_shard(shard, o.out, flat, so, r, gov, variants.size());
    io::Manifest m = start_manifest(o, "sweep");
    m.warnings = study::scenario_warnings(variants.front().scenario, variants.front().scenario.sweep_speeds);
    {
      // The governing deflection of each station (the reference's stations, the envelope's order).
      std::vector<double> max_disp;
      for (const auto& st : variants.front().scenario.stations) {
        double d = 0.0;
        for (const auto& g : gov)
          if (g.station == st.name) d = g.disp.value;
        max_disp.push_back(d);
      }
      for (auto& w : study::response_warnings(variants.front().scenario, max_disp)) m.warnings.push_back(std::move(w));
    }
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
    if (shard.n)
      m.extra.insert(m.extra.end(), {{"shard", "\"" + opts.sample.shard + "\""},
                                     {"cases_begin", std::to_string(so.case_begin)},
                                     {"cases_end", std::to_string(so.case_end)},
                                     {"n_cases_total", std::to_string(shard.n_total)}});
    io::write_manifest(o.out + "/manifest.toml", m, flat);
    if (!o.quiet) {
      std::printf("%zu cases (%zu variants), %zu failed, %.1f s; wrote %s/envelope.csv and governing.csv\n", r.summary.n_cases,
                  variants.size(), r.summary.n_failed, r.summary.wall_s, o.out.c_str());
      if (shard.n)
        std::printf("shard %d/%d: cases %zu to %zu of %zu; wrote %s/shard.toml (join the shards with viaduct merge)\n", shard.k,
                    shard.n, so.case_begin + 1, so.case_end, shard.n_total, o.out.c_str());
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

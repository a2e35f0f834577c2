// viaduct sweep with sweep.mode = "sample" (streamed, resumable, sharded) and viaduct merge.
#include <chrono>
#include <cstdio>
#include <fstream>

#include "cli.hpp"
#include "viaduct/io/output_dir.hpp"
#include "viaduct/io/sampled.hpp"
#include "viaduct/io/sweep_shard.hpp"

namespace viaduct::cli {

namespace sample_cli {

// The statistics at a glance: per train and station, the peak over the speeds.
void print_peaks(const std::string& dir, const io::StatisticsSpec& spec) {
  std::ifstream in(dir + "/peak_percentiles.csv");
  std::string header, line;
  std::getline(in, header);
  std::printf("\nthe peak over the speeds per sample (%s/peak_percentiles.csv; acceleration limit %.2f m/s²):\n", dir.c_str(),
              spec.stats.acc_limit);
  std::printf("  %s\n", header.c_str());
  int shown = 0;
  while (std::getline(in, line) && shown++ < 12) std::printf("  %s\n", line.c_str());
}

int exit_code(const study::SampledRunSummary& s) {
  if (s.n_failed == 0) return ok;
  std::fprintf(stderr, "viaduct sweep: %lld of %lld cases failed (failures.csv); the statistics use the samples that completed\n",
               static_cast<long long>(s.n_failed), static_cast<long long>(s.n_cases));
  return runtime_failure;
}

}  // namespace sample_cli

int run_sampled_sweep(const Common& o, const io::FlatScenario& flat, const SampleCliOptions& opts) {
  const auto t0 = std::chrono::steady_clock::now();
  io::SampledRunRequest q;
  q.out = o.out;
  q.threads = o.threads;
  q.shard = opts.shard;
  q.resume = opts.resume;
  // Under MPI only rank 0 reports (io::run_sampled tells it alone).
  q.log = log_printer(o.quiet);
  q.progress = progress_printer("sweep", o.quiet, "samples");
  q.on_start = [&o](const std::string& line, bool note) {
    if (note) std::fprintf(stderr, "viaduct sweep: note: %s\n", line.c_str());
    else if (!o.quiet) std::printf("%s\n", line.c_str());
  };
  const io::SampledRunOutcome r = io::run_sampled(flat, q);
  if (!r.started) return runtime_failure;
  if (!r.writer) return ok;
  const io::SampledStudy& st = r.study;
  const study::SampledRunSummary& sum = r.summary;
  io::Manifest m = start_manifest(o, "sweep");
  m.warnings = r.warnings;
  print_warnings("sweep", m.warnings);
  m.as_run = io::settings_as_run(r.settings);
  m.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  m.extra = {{"threads", std::to_string(o.threads)},
             {"mpi_ranks", std::to_string(r.mpi_ranks)},
             {"n_samples_total", std::to_string(st.n_total())},
             {"samples_begin", std::to_string(r.begin)},
             {"samples_end", std::to_string(r.end)},
             {"n_samples_run", std::to_string(sum.n_samples)},
             {"n_cases_run", std::to_string(sum.n_cases)},
             {"n_failed_run", std::to_string(sum.n_failed)},
             {"n_steps_run", std::to_string(sum.n_steps_total)},
             {"resumed", opts.resume ? "true" : "false"},
             {"fingerprint", "\"" + st.fingerprint + "\""}};
  io::write_manifest(o.out + "/manifest.toml", m, flat);
  if (!o.quiet) {
    std::printf("%lld samples (%lld cases, %lld failed) in %.1f s; wrote %s/samples.csv, sample_peaks.csv%s\n",
                static_cast<long long>(sum.n_samples), static_cast<long long>(sum.n_cases), static_cast<long long>(sum.n_failed),
                sum.wall_s, o.out.c_str(),
                r.shard_n ? " and shard.toml (join the shards with viaduct merge)"
                          : (st.spec.sensitivity ? ", percentiles.csv, sensitivity.csv" : ", percentiles.csv"));
    if (!r.shard_n) sample_cli::print_peaks(o.out, io::statistics_spec(st));
  }
  return sample_cli::exit_code(sum);
}

namespace sample_cli {
struct MergeOpts {};
void declare_merge(po::options_description&, MergeOpts&) {}

// Shards of a sweep: envelope.csv and the other files concatenated, governing.csv from theirs.
int merge_sweep(const Common& o, const std::vector<std::string>& dirs, std::chrono::steady_clock::time_point t0) {
  const io::SweepMerge r = io::merge_sweep_shards(dirs, o.out);
  std::vector<std::string> inputs;
  for (const auto& d : dirs) inputs.push_back(d + "/shard.toml");
  io::Manifest m = start_manifest(o, "merge", inputs);
  m.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  m.extra = {{"kind", "\"sweep\""},
             {"n_shards", std::to_string(r.n_shards)},
             {"n_cases", std::to_string(r.n_cases)},
             {"n_failed", std::to_string(r.n_failed)}};
  io::write_manifest(o.out + "/manifest.toml", m, nullptr);
  if (!o.quiet) {
    std::printf("merged %zu shards (%zu cases, %zu failed) into %s:", r.n_shards, r.n_cases, r.n_failed, o.out.c_str());
    for (const auto& f : r.files) std::printf(" %s", f.c_str());
    std::printf("\n");
    print_governing(r.governing, r.n_variants > 1);
  }
  // The exit codes of the one-process sweep (sweep_exit_code).
  if (r.n_failed == 0) return ok;
  const bool all_input = r.n_rows == 0 && r.n_failed_input == r.n_failed;
  std::fprintf(stderr, "viaduct merge: %zu of %zu cases failed (%s/failures.csv)%s\n", r.n_failed, r.n_cases, o.out.c_str(),
               all_input ? ": every case failed on its input" : "");
  return all_input ? usage_error : runtime_failure;
}

int run_merge(const Common& o, const MergeOpts&) {
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<std::string> dirs{o.scenario};
  dirs.insert(dirs.end(), o.more.begin(), o.more.end());
  make_out_dir(o.out);
  const std::string kind = io::shard_kind(dirs.front());
  for (const auto& d : dirs)
    if (io::shard_kind(d) != kind)
      throw InputError(SourceLocation{d + "/shard.toml", 1, "shard.kind"},
                       d + " is a shard of a " + (kind == "sweep" ? "sampled study" : "sweep") + ", " + dirs.front() + " of a " +
                           (kind == "sweep" ? "sweep" : "sampled study") + ": merge the shards of one study");
  // Each shard's run finished and its files are the ones it wrote (its manifest's [[outputs]]).
  for (const auto& d : dirs) io::check_output_dir(d);
  if (kind == "sweep") return merge_sweep(o, dirs, t0);
  const io::StatisticsSpec spec = io::merge_shards(dirs, o.out);
  std::vector<std::string> inputs;
  for (const auto& d : dirs) inputs.push_back(d + "/shard.toml");
  io::Manifest m = start_manifest(o, "merge", inputs);
  m.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  m.extra = {{"n_shards", std::to_string(dirs.size())}, {"n_samples_total", std::to_string(spec.n_total)}};
  io::write_manifest(o.out + "/manifest.toml", m, nullptr);
  if (!o.quiet) {
    std::printf("merged %zu shards (%lld samples) into %s\n", dirs.size(), static_cast<long long>(spec.n_total), o.out.c_str());
    print_peaks(o.out, spec);
  }
  return ok;
}
}  // namespace sample_cli

Command merge_command() {
  Command c = command("merge", "SHARD_DIR...", "join the shards of a sweep or a sampled study (viaduct sweep --shard K/N) into its files");
  c.many_positionals = true;
  c.needs_scenario = true;
  c.usage_and_samples =
      "Joins the output directories of the N shards of one study (viaduct sweep SCENARIO --shard K/N,\n"
      "K = 1..N, in any order) into OUT: byte for byte the files one process writes. Shards of a\n"
      "sweep: envelope.csv, failures.csv, load_effects.csv and vehicles.csv in case order, and\n"
      "governing.csv (exit code 1 when a case failed, as the sweep's). Shards of a sampled study:\n"
      "samples.csv, sample_peaks.csv and failures.csv in sample order, then percentiles.csv,\n"
      "peak_percentiles.csv and, with sweep.sensitivity, sensitivity.csv and peak_sensitivity.csv. A\n"
      "missing, repeated or unfinished shard, or one of another study, is an error naming it: rerun\n"
      "that shard alone. See docs/sampled.md for SLURM job arrays and GNU parallel.\n\n"
      "Sample runs:\n"
      "  viaduct sweep scenarios/old-guadiana-sampled.toml --set sweep.n_samples=2 --set sweep.n_speeds=3 --shard 1/2 --out out/og-shard-1\n"
      "  viaduct sweep scenarios/old-guadiana-sampled.toml --set sweep.n_samples=2 --set sweep.n_speeds=3 --shard 2/2 --out out/og-shard-2\n"
      "  viaduct merge out/og-shard-1 out/og-shard-2 --out out/og-merged\n"
      "  viaduct sweep scenarios/hslm-simply-supported.toml --set sweep.speed_step_kmh=70 --shard 1/2 --out out/hslm-shard-1\n"
      "  viaduct sweep scenarios/hslm-simply-supported.toml --set sweep.speed_step_kmh=70 --shard 2/2 --out out/hslm-shard-2\n"
      "  viaduct merge out/hslm-shard-1 out/hslm-shard-2 --out out/hslm-merged\n";
  bind(c, sample_cli::declare_merge, sample_cli::run_merge);
  return c;
}

}  // namespace viaduct::cli

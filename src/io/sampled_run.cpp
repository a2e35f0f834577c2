// A sampled study's run (sweep.mode = "sample"): the command's and the Python package's.
#include <cstdio>
#include <exception>
#include <fstream>
#include <optional>
#include <tuple>

#include "viaduct/core/cancel.hpp"
#include "viaduct/core/error.hpp"
#include "viaduct/io/output_dir.hpp"
#include "viaduct/io/sampled.hpp"
#include "viaduct/study/guards.hpp"

namespace viaduct::io {

SampledRunOutcome run_sampled(const FlatScenario& flat, const SampledRunRequest& q) {
  SampledRunOutcome r;
  r.study = sampled_study(flat);
  const SampledStudy& st = r.study;
  study::Scenario reference = to_scenario(flat);
  // Under MPI rank 0 writes every file and reports; the other ranks compute.
  const study::MpiWorld world = study::mpi_world();
  r.writer = world.rank == 0;
  r.mpi_ranks = world.size;
  reference.settings.ida.log = r.writer ? q.log : LogSink{};
  if (reference.sweep_speeds.empty())
    throw InputError(flat.at("sweep.mode").where,
                     "no speeds: give sweep.speeds_kmh, sweep.speed_min/max/step_kmh or sweep.speed_min/max_mps with n_speeds");
  const study::SampleDesign design = study::sample_design(st.spec);
  r.begin = 0;
  r.end = st.n_total();
  if (!q.shard.empty()) {
    std::tie(r.shard_k, r.shard_n) = parse_shard(q.shard);
    std::tie(r.begin, r.end) = shard_range(r.shard_k, r.shard_n, st.n_total(), st.spec.sensitivity ? Index(st.keys.size()) + 2 : 1);
  }
  std::optional<SampleStream> stream;
  Index start = -1;
  std::exception_ptr setup_failed;
  if (r.writer) {
    try {
      begin_outputs(q.out);
      if (!q.resume && std::ifstream(q.out + "/sample_progress.toml") && q.on_start)
        q.on_start(q.out + " holds an interrupted sampled run: starting over (--resume carries it on)", true);
      write_samples_csv(q.out + "/samples.csv", st, design, r.begin, r.end);
      if (q.resume) stream.emplace(SampleStream::resume(q.out, r.begin, r.end, st.fingerprint));
      else stream.emplace(q.out, r.begin, r.end, st.fingerprint);
      start = stream->next();
    } catch (...) {
      setup_failed = std::current_exception();
    }
  }
  start = study::mpi_broadcast(start);
  if (setup_failed) std::rethrow_exception(setup_failed);
  if (start < 0) {  // rank 0 said why
    r.started = false;
    return r;
  }
  if (r.writer && q.on_start)
    q.on_start(std::string(q.resume ? "resuming" : "running") + " " + std::to_string(r.end - r.begin) + " samples" +
                   (r.shard_n ? " (shard " + q.shard + ")" : "") + " of " + std::to_string(st.keys.size()) + " keys (" +
                   flat.at("sweep.sampling").s + "), " + std::to_string(reference.sweep_speeds.size()) + " speeds x " +
                   std::to_string(reference.trains.size()) + " trains each; from sample " + std::to_string(start) +
                   (world.size > 1 ? " over " + std::to_string(world.size) + " MPI ranks" : ""),
               false);
  study::SampledRunOptions ro;
  ro.threads = q.threads;
  ro.batch = st.batch;
  if (r.writer) ro.progress = q.progress;
  auto make = [&](Index s) {
    study::Variant v = sample_variant(flat, st, design, s, reference);
    v.scenario.settings.ida.log = reference.settings.ida.log;
    return v;
  };
  // A cancelled call (the Python package's Ctrl-C) records no batch from then on: the files hold
  // the whole batches before it, and a resumed run carries on from there.
  auto sink = [&](const study::SampleBatch& b) {
    if (cancel_requested()) throw Cancelled();
    stream->append(b);
  };
  r.summary = study::run_samples_mpi(start, r.end, make, sink, ro);
  r.warnings = study::scenario_warnings(reference, reference.sweep_speeds);
  r.settings = reference.settings;
  if (!r.writer) return r;
  stream->finish();
  if (r.shard_n) write_shard_toml(q.out + "/shard.toml", r.shard_k, r.shard_n, r.begin, r.end, st);
  else write_sample_statistics(q.out, statistics_spec(st));
  return r;
}

}  // namespace viaduct::io

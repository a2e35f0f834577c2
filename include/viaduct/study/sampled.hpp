#pragma once
/// \file Sampled studies: the samples of a design run in batches through run_sweep (so memory
/// holds one batch's models, whatever the sample count), their deck peaks handed to a sink as
/// each batch finishes; and the statistics of the peaks per output column (percentiles,
/// exceedance of a limit, Sobol indices).

#include <functional>
#include <string>
#include <vector>

#include "viaduct/study/sampling.hpp"
#include "viaduct/study/statistics.hpp"
#include "viaduct/study/sweep.hpp"

namespace viaduct::study {

/// The deck peaks of one case of one sample.
struct SamplePeak {
  Index sample = 0;
  std::string train, station;
  double speed = 0.0;        ///< [m/s]
  double max_abs_acc = 0.0;  ///< [m/s²] filtered as the scenario says
  double max_abs_disp = 0.0; ///< [m]
};
struct SampleFailure {
  Index sample = 0;
  std::string train;
  double speed = 0.0;  ///< [m/s]
  std::string message;
  bool input_error = false;
};
/// The results of samples [begin, end), in the order sample, train, speed, station.
struct SampleBatch {
  Index begin = 0, end = 0;
  std::vector<SamplePeak> peaks;
  std::vector<SampleFailure> failures;
  Index n_cases = 0, n_steps = 0;
};

/// The variant (resolved scenario) of sample `s`; a sample that cannot be formed returns a
/// Variant with `error` set (its cases fail, the study goes on).
using VariantMaker = std::function<Variant(Index s)>;
/// Receives each batch as it completes, in sample order (it writes and flushes them).
using BatchSink = std::function<void(const SampleBatch&)>;

struct SampledRunOptions {
  int threads = 1;        ///< >= 1
  Index batch = 16;       ///< >= 1: samples per batch (models held in memory at once)
  ProgressSink progress;  ///< optional: samples done of the range
  CaseRunner runner;      ///< optional, as SweepOptions::runner
};
struct SampledRunSummary {
  Index n_samples = 0, n_cases = 0, n_failed = 0, n_steps_total = 0;
  double wall_s = 0.0;  ///< [s]
};
/// Runs samples [begin, end). Each sample's results depend on nothing but the sample (not the
/// batch, the range or the thread count), so shards and resumed runs give the same peaks.
SampledRunSummary run_samples(Index begin, Index end, const VariantMaker& make, const BatchSink& sink,
                              const SampledRunOptions& options);

/// The MPI world of this process: rank 0 of 1 unless viaduct was started by mpirun (an Open MPI
/// or PMI environment) and built with MPI (VIADUCT_HAVE_MPI). mpi_start initialises MPI then,
/// asking for MPI_THREAD_MULTIPLE; mpi_finish finalises it (both no-ops otherwise).
struct MpiWorld {
  int rank = 0, size = 1;
  bool threads_multiple = false;  ///< rank 0 computes beside its coordinator thread
  /// Started on several ranks (size > 1, read from the launcher) by a build without MPI.
  bool without_mpi = false;
};
MpiWorld mpi_start(int* argc, char*** argv);
MpiWorld mpi_world();
void mpi_finish();
/// Rank 0's value on every rank (the start of a resumed run; −1: rank 0 could not set up).
Index mpi_broadcast(Index value);
/// Samples [begin, end) over the ranks with dynamic load balancing: rank 0's coordinator hands
/// out units of `options.batch` samples to whichever rank asks next (rank 0 itself computes too
/// when MPI gives it threads), gathers their peaks and calls `sink` on rank 0 in sample order,
/// so the files are those of one process. Every rank must call it with the same arguments; the
/// summary on rank 0 counts every rank's work, on the others their own. Without MPI (or one
/// rank): run_samples.
SampledRunSummary run_samples_mpi(Index begin, Index end, const VariantMaker& make, const BatchSink& sink,
                                  const SampledRunOptions& options);

struct SampleStatsOptions {
  std::vector<double> percentiles{5.0, 50.0, 95.0};  ///< each in [0, 100]
  double acc_limit = 3.5;                            ///< [m/s²] exceedance of the deck acceleration
  SobolOptions sobol;
};
/// The statistics of one response over the samples.
struct ResponseStats {
  Index n = 0;                         ///< independent samples with a value
  double mean = 0.0, sd = 0.0;         ///< sd: with n − 1
  std::vector<double> percentiles;     ///< as SampleStatsOptions::percentiles
  Exceedance exceed;                   ///< of the limit given (acceleration)
  Index n_base = 0;                    ///< Saltelli base points complete (every block has a value)
  std::vector<SobolIndex> sobol;       ///< one per key, with a Saltelli design
};
/// `by_sample[s]` the response of sample s (NaN: missing, a failed case). Percentiles, mean, sd
/// and exceedance over the independent samples (SampleDesign::independent); Sobol indices over
/// the base points whose d + 2 samples all have a value. `limit` NaN: no exceedance.
ResponseStats response_statistics(const std::vector<double>& by_sample, const SampleDesign& layout, double limit,
                                  const SampleStatsOptions& options);

}  // namespace viaduct::study

#pragma once
/// \file Sampled studies on disk (sweep.mode = "sample"; docs/sampled.md): the study read from a
/// scenario, one variant per sample, the per-sample peaks streamed to OUT as batches finish
/// (resumable), shards of the samples and their merge, and the statistics files.
///
/// Files of a study in OUT: samples.csv (the design: sample, block, KEY_factor per key),
/// sample_peaks.csv (sample, train, speed_kmh, station, max_abs_acc_mps2, max_abs_disp_m),
/// failures.csv, percentiles.csv and peak_percentiles.csv (per speed, and of the maximum over
/// the speeds), with sweep.sensitivity sensitivity.csv and peak_sensitivity.csv. While a run is
/// going, the peaks and failures grow in *.partial files and sample_progress.toml says how far
/// they are complete; a shard writes shard.toml instead of the statistics.

#include <functional>
#include <string>
#include <vector>

#include "viaduct/io/scenario.hpp"
#include "viaduct/study/sampled.hpp"

namespace viaduct::io {

/// A sampled study as the scenario states it.
struct SampledStudy {
  study::SampleSpec spec;
  std::vector<std::string> keys, labels;  ///< per varied key, in the order of sweep.variants
  study::SampleStatsOptions stats;
  Index batch = 16;
  /// SHA-256 of the resolved scenario: shards of one study carry the same.
  std::string fingerprint;
  study::SampleDesign layout() const;     ///< d, n_base and the Saltelli layout, without factors
  Index n_total() const;                  ///< samples to run: n, or n (d + 2) with sensitivity
};

/// True when the scenario's sweep.mode is "sample".
bool is_sampled(const FlatScenario& flat);
/// Reads and checks the study (InputError with file, line and key): each key's distribution and
/// its parameters, the key's rule at both ends of the distribution's support, a key whose
/// reference value is 0 (no factor varies it), correlations (refused with sensitivity).
SampledStudy sampled_study(const FlatScenario& flat);
/// The variant of sample `s` (label: the sample's number); a sample breaking a rule of the model
/// (InputError from to_scenario) is a Variant whose `error` says why, with `reference`'s trains
/// and speeds.
study::Variant sample_variant(const FlatScenario& flat, const SampledStudy& st, const study::SampleDesign& design, Index s,
                              const study::Scenario& reference);

/// samples.csv for samples [begin, end): sample, block (A, B or AB_<label>; "sample" without
/// sensitivity), then KEY_factor per key. Atomic.
void write_samples_csv(const std::string& path, const SampledStudy& st, const study::SampleDesign& design, Index begin,
                       Index end);

/// The per-sample peaks and failures of a run in OUT, appended batch by batch to
/// sample_peaks.csv.partial and failures.csv.partial; after each batch both are flushed to disk
/// and sample_progress.toml (atomic) records the samples done and the bytes that hold them. An
/// interrupted run leaves whole batches behind; resume() cuts any part written after the last
/// record and says where to carry on.
class SampleStream {
 public:
  /// Starts a run of samples [begin, end) in `dir` (any earlier partial files are replaced).
  SampleStream(std::string dir, Index begin, Index end, std::string fingerprint);
  /// Carries on the run recorded in `dir`: InputError when there is none, or when it belongs to
  /// another study (fingerprint) or another range.
  static SampleStream resume(const std::string& dir, Index begin, Index end, const std::string& fingerprint);
  Index next() const { return done_; }  ///< the first sample not yet recorded
  void append(const study::SampleBatch& batch);
  /// Renames the partial files to sample_peaks.csv and failures.csv and removes the record.
  void finish();

 private:
  SampleStream() = default;
  void record() const;
  std::string dir_, fingerprint_;
  Index begin_ = 0, end_ = 0, done_ = 0;
  long long peaks_bytes_ = 0, failures_bytes_ = 0;
};

/// What statistics a set of per-sample peaks gets, and over which layout.
struct StatisticsSpec {
  study::SampleDesign layout;  ///< d, n_base, saltelli (factors unused)
  Index n_total = 0;
  std::vector<std::string> keys, labels;
  study::SampleStatsOptions stats;
};
StatisticsSpec statistics_spec(const SampledStudy& st);
/// Reads DIR/sample_peaks.csv and writes percentiles.csv, peak_percentiles.csv and, with a
/// Saltelli layout, sensitivity.csv and peak_sensitivity.csv into DIR. Memory: the peaks are read
/// in passes over groups of (train, station) columns, at most ~32 MB of values per pass.
/// Returns the (train, station) groups' count.
std::size_t write_sample_statistics(const std::string& dir, const StatisticsSpec& spec);

/// shard.toml of shard k of n (samples [begin, end) of n_total) with the statistics spec.
void write_shard_toml(const std::string& path, int k, int n, Index begin, Index end, const SampledStudy& st);
/// One shard as its shard.toml says.
struct ShardInfo {
  std::string dir;
  int k = 0, n = 0;
  Index begin = 0, end = 0;
  std::string fingerprint;
  StatisticsSpec spec;
};
ShardInfo read_shard_toml(const std::string& dir);
/// Joins shards 1..n of one study into `out`: samples.csv, sample_peaks.csv and failures.csv
/// concatenated in sample order, then the statistics: the files a one-process run writes, byte
/// for byte. InputError naming the missing, repeated or foreign shard.
StatisticsSpec merge_shards(const std::vector<std::string>& dirs, const std::string& out);

/// How a sampled study runs (viaduct sweep on sweep.mode = "sample", viaduct.sampled_sweep).
struct SampledRunRequest {
  std::string out;          ///< the study's directory (created; its files as this file's header says)
  int threads = 1;          ///< >= 1
  std::string shard;        ///< "K/N": only shard K of N, which writes shard.toml instead of the statistics
  bool resume = false;      ///< carry on the interrupted run recorded in `out`
  ProgressSink progress;    ///< samples done of the range; may be empty
  LogSink log;              ///< IDA's messages; may be empty
  /// Told what the run is about to do (the samples, keys, speeds and trains, where it starts) and
  /// that `out` holds an interrupted run it starts over; may be empty. Rank 0 only under MPI.
  std::function<void(const std::string& line, bool note)> on_start;
};
/// What ran. Under MPI every rank runs its part and rank 0 (`writer`) writes every file.
struct SampledRunOutcome {
  bool writer = true;
  bool started = true;      ///< false: rank 0 could not start (it threw; the other ranks return)
  SampledStudy study;
  study::SampledRunSummary summary;
  Index begin = 0, end = 0; ///< the samples of this run (a shard's range)
  int shard_k = 0, shard_n = 0;
  int mpi_ranks = 1;
  std::vector<std::string> warnings;  ///< the scenario's (study::scenario_warnings)
  study::RunSettings settings;        ///< the reference scenario's, as run
};
/// Runs the study of `flat` into request.out: samples.csv, the peaks streamed as batches finish,
/// then the statistics (or shard.toml). InputError for a study that cannot run.
SampledRunOutcome run_sampled(const FlatScenario& flat, const SampledRunRequest& request);

/// "K/N" -> (K, N), 1 <= K <= N; InputError otherwise.
std::pair<int, int> parse_shard(const std::string& text);
/// Samples [begin, end) of shard k of n over n_total samples (whole Saltelli groups of `group`).
std::pair<Index, Index> shard_range(int k, int n, Index n_total, Index group);

}  // namespace viaduct::io

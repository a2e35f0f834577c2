#pragma once
/// \file Shards of a sweep (viaduct sweep --shard K/N on a scenario without sweep.mode =
/// "sample"): shard K of N runs the cases [begin, end) of the sweep's order (variant, train,
/// speed; SweepOptions::case_begin) and writes its envelope.csv, failures.csv and the other
/// files of a sweep for those cases, with shard.toml (kind = "sweep"): the range, the study's
/// fingerprint, the files written and the shard's governing cases to the last bit.
/// merge_sweep_shards() joins them into the files one process writes, byte for byte.

#include <string>
#include <vector>

#include "viaduct/study/sweep.hpp"

namespace viaduct::io {

struct SweepShard {
  std::string dir;
  int k = 0, n = 0;
  std::size_t begin = 0, end = 0, n_total = 0;  ///< cases [begin, end) of n_total
  std::string fingerprint;                      ///< SHA-256 of the resolved scenario
  std::vector<std::string> files;               ///< the CSV files the shard wrote, in merge order
  bool load_effects = false;                    ///< run with --load-effects
  std::size_t n_variants = 1;                   ///< of the whole sweep
  std::size_t n_rows = 0;                       ///< envelope rows
  std::size_t n_failed = 0, n_failed_input = 0; ///< failed cases; of them, failed on their input
  std::vector<study::GoverningRow> governing;   ///< of the shard's rows, values exact
};

/// Cases [begin, end) of shard k of n over n_total cases: contiguous, sizes differing by at most 1.
std::pair<std::size_t, std::size_t> sweep_shard_range(int k, int n, std::size_t n_total);
/// Writes dir/shard.toml (atomic).
void write_sweep_shard_toml(const SweepShard& s);
/// "sweep" for a shard of a sweep, "sample" for a shard of a sampled study (no kind); InputError
/// when `dir` holds no shard.toml.
std::string shard_kind(const std::string& dir);
SweepShard read_sweep_shard_toml(const std::string& dir);

/// What a merge of sweep shards found.
struct SweepMerge {
  std::size_t n_shards = 0, n_cases = 0, n_rows = 0, n_failed = 0, n_failed_input = 0, n_variants = 1;
  std::vector<study::GoverningRow> governing;  ///< as written to governing.csv
  std::vector<std::string> files;              ///< written to `out`, governing.csv last
};
/// Joins shards 1..n of one sweep into `out`: each file concatenated in shard order (a file only
/// some shards wrote — vehicles.csv, written when a shard has vehicle rows — from those), then
/// governing.csv from the shards' governing cases (the first of equal values in case order
/// wins, as in study::governing). InputError naming a missing, repeated, unfinished or foreign
/// shard.
SweepMerge merge_sweep_shards(const std::vector<std::string>& dirs, const std::string& out);

}  // namespace viaduct::io

// Sampled studies on disk: the streamed per-sample peaks (resumable), the statistics files,
// shards and their merge.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include <unistd.h>

#include <toml.hpp>

#include "atomic_file.hpp"
#include "csv_cells.hpp"
#include "shard_files.hpp"
#include "toml_file.hpp"
#include "viaduct/io/results.hpp"
#include "viaduct/io/sampled.hpp"

namespace viaduct::io {

namespace fs = std::filesystem;

namespace sampled_files_detail {

using detail::AtomicFile;
using detail::csv_text;

const char* kPeaksHeader = "sample,train,speed_kmh,station,max_abs_acc_mps2,max_abs_disp_m\n";
const char* kFailuresHeader = "sample,train,speed_kmh,error\n";

// Appends `text` to `path`, flushed to the disk; returns the file's size after it.
long long append_synced(const std::string& path, const std::string& text) {
  std::FILE* f = std::fopen(path.c_str(), "ab");
  if (!f) throw SolverError(path + ": cannot open for appending");
  const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size() && std::fflush(f) == 0 && ::fsync(fileno(f)) == 0;
  const long long size = ok ? static_cast<long long>(std::ftell(f)) : -1;
  if (std::fclose(f) != 0 || !ok || size < 0) throw SolverError(path + ": write failed (disk full?)");
  return size;
}

using detail::find_in;
using detail::g17;
using detail::toml_string;

// One output column group: a train and a station, with the speeds (text as written, ascending).
struct Group {
  std::string train, station;
  std::size_t train_order = 0, station_order = 0;
  std::vector<std::string> speeds;
};

struct PeakFile {
  std::vector<Group> groups;
  std::map<std::pair<std::string, std::string>, std::size_t> index;  // (train, station) -> group
};

// The groups of a peaks file, in the order train, station of first appearance.
PeakFile scan_groups(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open");
  std::string line;
  std::getline(in, line);
  std::map<std::string, std::size_t> trains, stations;
  std::map<std::pair<std::string, std::string>, std::set<std::pair<double, std::string>>> speeds;
  while (std::getline(in, line)) {
    const auto c = detail::split_quoted_csv(line);
    if (c.size() != 6) throw InputError(path + ": a row without 6 cells: '" + line + "'");
    trains.emplace(c[1], trains.size());
    stations.emplace(c[3], stations.size());
    speeds[{c[1], c[3]}].insert({std::stod(c[2]), c[2]});
  }
  PeakFile pf;
  for (const auto& [ts, sp] : speeds) {
    Group g{ts.first, ts.second, trains.at(ts.first), stations.at(ts.second), {}};
    for (const auto& s : sp) g.speeds.push_back(s.second);
    pf.groups.push_back(g);
  }
  std::sort(pf.groups.begin(), pf.groups.end(), [](const Group& a, const Group& b) {
    return std::tie(a.train_order, a.station_order) < std::tie(b.train_order, b.station_order);
  });
  for (std::size_t g = 0; g < pf.groups.size(); ++g) pf.index[{pf.groups[g].train, pf.groups[g].station}] = g;
  return pf;
}

std::vector<std::string> stats_header(const std::vector<double>& pct) {
  std::vector<std::string> h{"n", "acc_mean_mps2", "acc_sd_mps2"};
  for (double p : pct) h.push_back("acc_p" + format_number(p) + "_mps2");
  for (const char* s : {"p_exceed", "p_exceed_se", "p_exceed_upper95", "disp_mean_m", "disp_sd_m"}) h.push_back(s);
  for (double p : pct) h.push_back("disp_p" + format_number(p) + "_m");
  return h;
}

void stats_cells(const study::ResponseStats& acc, const study::ResponseStats& disp, std::vector<std::string>& row) {
  row.push_back(std::to_string(acc.n));
  row.push_back(table_cell(acc.mean));
  row.push_back(table_cell(acc.sd));
  for (double x : acc.percentiles) row.push_back(table_cell(x));
  row.push_back(table_cell(acc.n > 0 ? acc.exceed.p : std::nan("")));
  row.push_back(table_cell(acc.n > 0 ? acc.exceed.se : std::nan("")));
  row.push_back(table_cell(acc.n > 0 ? acc.exceed.upper95 : std::nan("")));
  row.push_back(table_cell(disp.mean));
  row.push_back(table_cell(disp.sd));
  for (double x : disp.percentiles) row.push_back(table_cell(x));
}

void sobol_rows(const std::vector<std::string>& lead, const char* quantity, const study::ResponseStats& r,
                const StatisticsSpec& spec, std::vector<std::vector<std::string>>& rows) {
  for (std::size_t i = 0; i < r.sobol.size(); ++i) {
    std::vector<std::string> row = lead;
    row.push_back(quantity);
    row.push_back(spec.keys[i]);
    row.push_back(spec.labels[i]);
    row.push_back(std::to_string(r.n_base));
    const study::SobolIndex& s = r.sobol[i];
    for (double x : {s.s, s.s_lo, s.s_hi, s.st, s.st_lo, s.st_hi}) row.push_back(table_cell(x));
    rows.push_back(row);
  }
}

struct StatsTables {
  std::map<std::tuple<std::size_t, double, std::size_t>, std::vector<std::string>> per_speed;  // train, speed, station
  std::map<std::tuple<std::size_t, double, std::size_t>, std::vector<std::vector<std::string>>> per_speed_sobol;
  std::vector<std::vector<std::string>> peak, peak_sobol;
};

// The statistics of groups [g0, g1) from one pass over the file.
void chunk_statistics(const std::string& path, const PeakFile& pf, std::size_t g0, std::size_t g1, const StatisticsSpec& spec,
                      StatsTables& t) {
  const std::size_t n = std::size_t(spec.n_total);
  std::vector<std::size_t> offset{0};  // column offset of each group in the chunk
  for (std::size_t g = g0; g < g1; ++g) offset.push_back(offset.back() + pf.groups[g].speeds.size());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> acc(offset.back() * n, nan), disp(offset.back() * n, nan);
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    const auto c = detail::split_quoted_csv(line);
    const std::size_t g = pf.index.at({c[1], c[3]});
    if (g < g0 || g >= g1) continue;
    const auto& sp = pf.groups[g].speeds;
    const std::size_t col = offset[g - g0] + std::size_t(std::find(sp.begin(), sp.end(), c[2]) - sp.begin());
    const std::size_t s = std::size_t(std::stoll(c[0]));
    if (s >= n) throw InputError(path + ": sample " + c[0] + " beyond the study's " + std::to_string(n));
    acc[col * n + s] = std::stod(c[4]);
    disp[col * n + s] = std::stod(c[5]);
  }
  const double limit = spec.stats.acc_limit;
  for (std::size_t g = g0; g < g1; ++g) {
    const Group& gr = pf.groups[g];
    std::vector<double> peak_acc(n, -1.0), peak_disp(n, -1.0);
    for (std::size_t k = 0; k < gr.speeds.size(); ++k) {
      const std::size_t col = offset[g - g0] + k;
      const std::vector<double> a(acc.begin() + long(col * n), acc.begin() + long((col + 1) * n));
      const std::vector<double> d(disp.begin() + long(col * n), disp.begin() + long((col + 1) * n));
      for (std::size_t s = 0; s < n; ++s) {  // a sample missing one speed has no peak over them
        peak_acc[s] = std::isnan(a[s]) || std::isnan(peak_acc[s]) ? nan : std::max(peak_acc[s], a[s]);
        peak_disp[s] = std::isnan(d[s]) || std::isnan(peak_disp[s]) ? nan : std::max(peak_disp[s], d[s]);
      }
      const auto ra = study::response_statistics(a, spec.layout, limit, spec.stats);
      const auto rd = study::response_statistics(d, spec.layout, nan, spec.stats);
      const double v = std::stod(gr.speeds[k]);
      std::vector<std::string> row{gr.train, gr.speeds[k], gr.station};
      stats_cells(ra, rd, row);
      const auto key = std::make_tuple(gr.train_order, v, gr.station_order);
      t.per_speed[key] = row;
      auto& sob = t.per_speed_sobol[key];
      sobol_rows({row[0], row[1], row[2]}, "max_abs_acc_mps2", ra, spec, sob);
      sobol_rows({row[0], row[1], row[2]}, "max_abs_disp_m", rd, spec, sob);
    }
    const auto ra = study::response_statistics(peak_acc, spec.layout, limit, spec.stats);
    const auto rd = study::response_statistics(peak_disp, spec.layout, nan, spec.stats);
    std::vector<std::string> row{gr.train, gr.station};
    stats_cells(ra, rd, row);
    t.peak.push_back(row);
    sobol_rows({row[0], row[1]}, "max_abs_acc_mps2", ra, spec, t.peak_sobol);
    sobol_rows({row[0], row[1]}, "max_abs_disp_m", rd, spec, t.peak_sobol);
  }
}

}  // namespace sampled_files_detail

using sampled_files_detail::append_synced;

SampleStream::SampleStream(std::string dir, Index begin, Index end, std::string fingerprint)
    : dir_(std::move(dir)), fingerprint_(std::move(fingerprint)), begin_(begin), end_(end), done_(begin) {
  for (const char* name : {"sample_peaks.csv.partial", "failures.csv.partial"}) {
    std::error_code ec;
    fs::remove(dir_ + "/" + name, ec);
  }
  peaks_bytes_ = append_synced(dir_ + "/sample_peaks.csv.partial", sampled_files_detail::kPeaksHeader);
  failures_bytes_ = append_synced(dir_ + "/failures.csv.partial", sampled_files_detail::kFailuresHeader);
  record();
}

SampleStream SampleStream::resume(const std::string& dir, Index begin, Index end, const std::string& fingerprint) {
  const std::string path = dir + "/sample_progress.toml";
  if (!fs::exists(path))
    throw InputError("--resume: nothing to resume in " + dir + " (no sample_progress.toml: no sampled run was interrupted there)");
  const toml::value root = detail::read_state_toml(path, "progress");
  SampleStream s;
  s.dir_ = dir;
  s.fingerprint_ = detail::find_in<std::string>(root, "progress", "fingerprint", path);
  s.begin_ = detail::find_in<Index>(root, "progress", "begin", path);
  s.end_ = detail::find_in<Index>(root, "progress", "end", path);
  s.done_ = detail::find_in<Index>(root, "progress", "done", path);
  s.peaks_bytes_ = detail::find_in<long long>(root, "progress", "peaks_bytes", path);
  s.failures_bytes_ = detail::find_in<long long>(root, "progress", "failures_bytes", path);
  if (s.fingerprint_ != fingerprint)
    throw InputError(SourceLocation{path, 1, "fingerprint"}, "the interrupted run in " + dir +
                                                                 " is of another study (the scenario or a --set differs)");
  if (s.begin_ != begin || s.end_ != end)
    throw InputError(SourceLocation{path, 1, "begin"}, "the interrupted run in " + dir + " ran samples [" +
                                                           std::to_string(s.begin_) + ", " + std::to_string(s.end_) +
                                                           "), not [" + std::to_string(begin) + ", " + std::to_string(end) + ")");
  // Cut whatever was written after the last record (a batch cut short).
  for (const auto& [name, bytes] : {std::pair<const char*, long long>{"sample_peaks.csv.partial", s.peaks_bytes_},
                                    {"failures.csv.partial", s.failures_bytes_}}) {
    const std::string p = dir + "/" + name;
    std::error_code ec;
    if (!fs::exists(p) || static_cast<long long>(fs::file_size(p)) < bytes)
      throw InputError(SourceLocation{path, 1, "peaks_bytes"}, p + " is shorter than its record: cannot resume");
    fs::resize_file(p, static_cast<std::uintmax_t>(bytes), ec);
    if (ec) throw SolverError(p + ": cannot cut to its last complete batch: " + ec.message());
  }
  return s;
}

void SampleStream::record() const {
  std::ostringstream os;
  os << "# viaduct sweep: a sampled run in progress (viaduct sweep ... --resume carries it on)\n[progress]\n"
     << "fingerprint = " << detail::toml_string(fingerprint_) << "\nbegin = " << begin_ << "\nend = " << end_
     << "\ndone = " << done_ << "\npeaks_bytes = " << peaks_bytes_ << "\nfailures_bytes = " << failures_bytes_ << "\n";
  write_text_file(dir_ + "/sample_progress.toml", os.str());
}

void SampleStream::append(const study::SampleBatch& b) {
  using sampled_files_detail::csv_text;
  if (b.begin != done_) throw std::logic_error("SampleStream: batches out of order");
  std::string peaks, failures;
  char buf[128];
  for (const auto& p : b.peaks) {
    std::snprintf(buf, sizeof buf, "%lld,", static_cast<long long>(p.sample));
    peaks += buf + csv_text(p.train);
    std::snprintf(buf, sizeof buf, ",%.10g,", p.speed * 3.6);
    peaks += buf + csv_text(p.station);
    std::snprintf(buf, sizeof buf, ",%.10g,%.10g\n", p.max_abs_acc, p.max_abs_disp);
    peaks += buf;
  }
  for (const auto& f : b.failures) {
    std::snprintf(buf, sizeof buf, "%lld,", static_cast<long long>(f.sample));
    failures += buf + csv_text(f.train);
    std::snprintf(buf, sizeof buf, ",%.10g,", f.speed * 3.6);
    failures += buf + csv_text(f.message) + "\n";
  }
  peaks_bytes_ = append_synced(dir_ + "/sample_peaks.csv.partial", peaks);
  failures_bytes_ = append_synced(dir_ + "/failures.csv.partial", failures);
  done_ = b.end;
  record();
}

void SampleStream::finish() {
  if (done_ != end_) throw std::logic_error("SampleStream: finished before its last sample");
  fs::rename(dir_ + "/sample_peaks.csv.partial", dir_ + "/sample_peaks.csv");
  fs::rename(dir_ + "/failures.csv.partial", dir_ + "/failures.csv");
  fs::remove(dir_ + "/sample_progress.toml");
}

StatisticsSpec statistics_spec(const SampledStudy& st) { return {st.layout(), st.n_total(), st.keys, st.labels, st.stats}; }

std::size_t write_sample_statistics(const std::string& dir, const StatisticsSpec& spec) {
  using namespace sampled_files_detail;
  const std::string path = dir + "/sample_peaks.csv";
  const PeakFile pf = scan_groups(path);
  std::size_t max_speeds = 1;
  for (const auto& g : pf.groups) max_speeds = std::max(max_speeds, g.speeds.size());
  // Two values per sample and column: groups per pass so that a pass holds at most 2^22 values.
  const std::size_t per_group = 2 * max_speeds * std::size_t(std::max<Index>(1, spec.n_total));
  const std::size_t groups_per_pass = std::max<std::size_t>(1, (std::size_t(1) << 22) / per_group);
  StatsTables t;
  for (std::size_t g0 = 0; g0 < pf.groups.size(); g0 += groups_per_pass)
    chunk_statistics(path, pf, g0, std::min(pf.groups.size(), g0 + groups_per_pass), spec, t);
  const std::vector<std::string> stats = stats_header(spec.stats.percentiles);
  std::vector<std::string> h{"train", "speed_kmh", "station"};
  h.insert(h.end(), stats.begin(), stats.end());
  std::vector<std::vector<std::string>> rows;
  for (const auto& kv : t.per_speed) rows.push_back(kv.second);
  write_table_csv(dir + "/percentiles.csv", h, rows);
  std::vector<std::string> hp{"train", "station"};
  hp.insert(hp.end(), stats.begin(), stats.end());
  write_table_csv(dir + "/peak_percentiles.csv", hp, t.peak);
  if (spec.layout.saltelli) {
    const std::vector<std::string> sh{"quantity", "key", "label", "n_base", "S", "S_lo", "S_hi", "ST", "ST_lo", "ST_hi"};
    std::vector<std::string> h1{"train", "speed_kmh", "station"}, h2{"train", "station"};
    h1.insert(h1.end(), sh.begin(), sh.end());
    h2.insert(h2.end(), sh.begin(), sh.end());
    rows.clear();
    for (const auto& kv : t.per_speed_sobol) rows.insert(rows.end(), kv.second.begin(), kv.second.end());
    write_table_csv(dir + "/sensitivity.csv", h1, rows);
    write_table_csv(dir + "/peak_sensitivity.csv", h2, t.peak_sobol);
  }
  return pf.groups.size();
}

std::pair<int, int> parse_shard(const std::string& text) {
  const auto slash = text.find('/');
  auto bad = [&] { throw InputError(SourceLocation{"--shard", 1, "--shard"}, "expected K/N with 1 <= K <= N, got '" + text + "'"); };
  if (slash == std::string::npos) bad();
  int k = 0, n = 0;
  try {
    std::size_t pk = 0, pn = 0;
    k = std::stoi(text.substr(0, slash), &pk);
    n = std::stoi(text.substr(slash + 1), &pn);
    if (pk != slash || pn != text.size() - slash - 1) bad();
  } catch (const std::logic_error&) {
    bad();
  }
  if (k < 1 || n < 1 || k > n) bad();
  return {k, n};
}

std::pair<Index, Index> shard_range(int k, int n, Index n_total, Index group) {
  const Index groups = n_total / group;
  return {Index(k - 1) * groups / n * group, Index(k) * groups / n * group};
}

void write_shard_toml(const std::string& path, int k, int n, Index begin, Index end, const SampledStudy& st) {
  using sampled_files_detail::g17;
  using detail::toml_string;
  std::ostringstream os;
  os << "# viaduct sweep --shard: one part of a sampled study; viaduct merge joins the parts\n[shard]\nk = " << k
     << "\nn = " << n << "\nbegin = " << begin << "\nend = " << end << "\nn_total = " << st.n_total()
     << "\nfingerprint = " << toml_string(st.fingerprint) << "\n\n[study]\nn_base = " << st.spec.n
     << "\nsaltelli = " << (st.spec.sensitivity ? "true" : "false") << "\nkeys = [";
  for (std::size_t i = 0; i < st.keys.size(); ++i) os << (i ? ", " : "") << toml_string(st.keys[i]);
  os << "]\nlabels = [";
  for (std::size_t i = 0; i < st.labels.size(); ++i) os << (i ? ", " : "") << toml_string(st.labels[i]);
  os << "]\npercentiles = [";
  for (std::size_t i = 0; i < st.stats.percentiles.size(); ++i) os << (i ? ", " : "") << g17(st.stats.percentiles[i]);
  os << "]\nacceleration_limit_mps2 = " << g17(st.stats.acc_limit) << "\nn_bootstrap = " << st.stats.sobol.n_bootstrap
     << "\nseed = " << st.stats.sobol.seed << "\n";
  write_text_file(path, os.str());
}

ShardInfo read_shard_toml(const std::string& dir) {
  const std::string path = dir + "/shard.toml";
  const toml::value v = detail::read_shard_file(dir);
  ShardInfo s;
  s.dir = dir;
  s.k = detail::find_in<int>(v, "shard", "k", path);
  s.n = detail::find_in<int>(v, "shard", "n", path);
  s.begin = detail::find_in<Index>(v, "shard", "begin", path);
  s.end = detail::find_in<Index>(v, "shard", "end", path);
  s.spec.n_total = detail::find_in<Index>(v, "shard", "n_total", path);
  s.fingerprint = detail::find_in<std::string>(v, "shard", "fingerprint", path);
  s.spec.keys = detail::find_in<std::vector<std::string>>(v, "study", "keys", path);
  s.spec.labels = detail::find_in<std::vector<std::string>>(v, "study", "labels", path);
  s.spec.layout.d = int(s.spec.keys.size());
  s.spec.layout.n_base = detail::find_in<Index>(v, "study", "n_base", path);
  s.spec.layout.saltelli = detail::find_in<bool>(v, "study", "saltelli", path);
  s.spec.stats.percentiles = detail::find_in<std::vector<double>>(v, "study", "percentiles", path);
  s.spec.stats.acc_limit = detail::find_in<double>(v, "study", "acceleration_limit_mps2", path);
  s.spec.stats.sobol.n_bootstrap = detail::find_in<int>(v, "study", "n_bootstrap", path);
  s.spec.stats.sobol.seed = detail::find_in<std::uint64_t>(v, "study", "seed", path);
  if (s.k < 1 || s.k > s.n || s.begin < 0 || s.end < s.begin || s.end > s.spec.n_total)
    throw InputError(SourceLocation{path, 1, "shard"}, "inconsistent shard (k, n, begin, end)");
  return s;
}

StatisticsSpec merge_shards(const std::vector<std::string>& dirs, const std::string& out) {
  std::vector<ShardInfo> shards;
  for (const auto& d : dirs) shards.push_back(read_shard_toml(d));
  if (shards.empty()) throw InputError("no shard directories given");
  std::sort(shards.begin(), shards.end(), [](const ShardInfo& x, const ShardInfo& y) { return x.k < y.k; });
  std::vector<detail::ShardPart> parts;
  for (const auto& s : shards) parts.push_back({s.dir, s.k, s.n, s.begin, s.end, s.spec.n_total, s.fingerprint});
  detail::check_shards_join(parts, "samples");
  const ShardInfo& a = shards.front();
  for (const char* name : {"samples.csv", "sample_peaks.csv", "failures.csv"}) {
    detail::AtomicFile f(out + "/" + name);
    for (std::size_t i = 0; i < shards.size(); ++i) detail::concatenate(shards[i].dir, name, i == 0, f.get());
    f.commit();
  }
  write_sample_statistics(out, a.spec);
  return a.spec;
}

}  // namespace viaduct::io

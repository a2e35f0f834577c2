#include "viaduct/io/record.hpp"

#include "atomic_file.hpp"

#include "csv_cells.hpp"

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <initializer_list>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>

#include "viaduct/core/error.hpp"

namespace viaduct::io {

void write_record_csv(const std::string& path, const Record& r, int significant_digits) {
  for (Index c = 0; c < r.data.cols(); ++c)
    if (!r.data.col(c).allFinite())
      throw SolverError("not writing " + path + ": channel " + r.channels[static_cast<std::size_t>(c)] + " holds a non-finite value");
  detail::AtomicFile f(path);
  std::fprintf(f.get(), "t_s");
  for (const auto& c : r.channels) std::fprintf(f.get(), ",%s", c.c_str());
  std::fprintf(f.get(), "\n");
  for (Index k = 0; k < r.n_samples(); ++k) {
    std::fprintf(f.get(), "%.12g", r.t0_s + static_cast<double>(k) / r.fs_hz);
    for (Index c = 0; c < r.data.cols(); ++c) std::fprintf(f.get(), ",%.*g", significant_digits, r.data(k, c));
    std::fprintf(f.get(), "\n");
  }
  f.commit();
}

Record time_window(const Record& r, std::optional<double> start_s, std::optional<double> end_s, const std::string& what) {
  if (!start_s && !end_s) return r;
  const double t_last = r.t0_s + static_cast<double>(r.n_samples() - 1) / r.fs_hz;
  const double a = start_s.value_or(r.t0_s), b = end_s.value_or(t_last);
  if (!std::isfinite(a) || !std::isfinite(b) || !(b > a))
    throw InputError(what + ": the window [" + format_number(a) + ", " + format_number(b) + "] s is empty or reversed");
  // Samples k with a <= t0 + k/fs <= b (half a microsample of rounding allowed).
  const double k0 = std::max(0.0, std::ceil((a - r.t0_s) * r.fs_hz - 1e-6));
  const double k1 = std::min(static_cast<double>(r.n_samples() - 1), std::floor((b - r.t0_s) * r.fs_hz + 1e-6));
  if (!(k1 - k0 >= 1.0))
    throw InputError(what + ": the window [" + format_number(a) + ", " + format_number(b) + "] s holds fewer than 2 of the record's samples (" +
                     format_number(r.t0_s) + " to " + format_number(t_last) + " s)");
  Record out = r;
  const auto first = static_cast<Index>(k0), n = static_cast<Index>(k1 - k0) + 1;
  out.data = r.data.middleRows(first, n);
  out.t0_s = r.t0_s + k0 / r.fs_hz;
  return out;
}

std::vector<std::pair<Index, Index>> missing_runs(const Record& r, std::size_t c) {
  std::vector<std::pair<Index, Index>> runs;
  const auto col = r.data.col(static_cast<Index>(c));
  for (Index i = 0; i < col.size();) {
    if (!std::isnan(col[i])) {
      ++i;
      continue;
    }
    Index j = i;
    while (j < col.size() && std::isnan(col[j])) ++j;
    runs.emplace_back(i, j);
    i = j;
  }
  return runs;
}

Record valid_span(const Record& r, const std::vector<std::size_t>& used, const std::string& who, std::vector<std::string>* notes) {
  const Index n = r.n_samples();
  std::vector<char> bad(static_cast<std::size_t>(n), 0);
  std::vector<std::string> lost;
  auto t_of = [&](Index i) { return format_number(r.t0_s + static_cast<double>(i) / r.fs_hz, 8); };
  for (const std::size_t c : used) {
    for (const auto& [a, b] : missing_runs(r, c)) {
      std::fill(bad.begin() + a, bad.begin() + b, char{1});
      lost.push_back(r.channels[c] + " from " + t_of(a) + " to " + t_of(b - 1) + " s");
    }
  }
  if (lost.empty()) return r;
  Index best_a = 0, best_n = 0;
  for (Index i = 0; i < n;) {
    if (bad[static_cast<std::size_t>(i)]) {
      ++i;
      continue;
    }
    Index j = i;
    while (j < n && !bad[static_cast<std::size_t>(j)]) ++j;
    if (j - i > best_n) best_a = i, best_n = j - i;
    i = j;
  }
  std::string runs;
  for (std::size_t k = 0; k < lost.size(); ++k) runs += (k ? "; " : "") + lost[k];
  if (best_n < 2)
    throw InputError(who + ": no 2 successive samples in which every channel used has a value (missing: " + runs + ")");
  if (notes)
    notes->push_back("the channels used miss samples (" + runs + "): " + who + " takes the longest piece where they all have values, " +
                     t_of(best_a) + " to " + t_of(best_a + best_n - 1) + " s (" + std::to_string(best_n) + " of " +
                     std::to_string(n) + " samples)");
  Record out = r;
  out.data = r.data.middleRows(best_a, best_n);
  out.t0_s = r.t0_s + static_cast<double>(best_a) / r.fs_hz;
  return out;
}

ChannelSummary summarise_channel(const Vector& x_in) {
  ChannelSummary s;
  // A channel's missing samples (a long run left missing) count in the report, not here.
  Vector kept;
  if (!x_in.allFinite()) {
    kept.resize(x_in.size());
    Index m = 0;
    for (Index i = 0; i < x_in.size(); ++i)
      if (std::isfinite(x_in[i])) kept[m++] = x_in[i];
    kept.conservativeResize(m);
  }
  const Vector& x = x_in.allFinite() ? x_in : kept;
  const Index n = x.size();
  if (n == 0) return s;
  s.min = x.minCoeff();
  s.max = x.maxCoeff();
  s.mean = x.mean();
  s.rms_ac = std::sqrt((x.array() - s.mean).square().mean());
  const Index tenth = std::max<Index>(1, n / 10);
  s.drift = x.tail(tenth).mean() - x.head(tenth).mean();
  // Runs of one value (exactly: a clipped ADC or a stuck sensor repeats its code).
  Index at_limit_run = 0, other_run = 1;
  for (Index i = 0; i < n;) {
    Index j = i + 1;
    while (j < n && x[j] == x[i]) ++j;
    s.longest_flat = std::max(s.longest_flat, j - i);
    if ((x[i] == s.max || x[i] == s.min) && s.max > s.min) {
      if (j - i >= 3) s.at_limits += j - i;
      at_limit_run = std::max(at_limit_run, j - i);
    } else {
      other_run = std::max(other_run, j - i);
    }
    i = j;
  }
  s.clipped = at_limit_run >= 3 && at_limit_run >= 2 * other_run;
  return s;
}

ChannelQuantity channel_quantity(const std::string& unit, const std::string& channel, const std::string& who) {
  if (unit == "mps2") return ChannelQuantity::acceleration;
  if (unit == "m") return ChannelQuantity::deflection;
  if (unit == "ue") return ChannelQuantity::strain;
  if (unit == "mps") return ChannelQuantity::velocity;
  throw InputError(who + ": channel '" + channel + "' is in " + unit +
                   "; only accelerations (_mps2, [g], ...), velocities (_mps, [mm/s], ...), deflections (_m, [mm], ...) and strains "
                   "(_ue, [µε], ...) compare with the model");
}

std::vector<PassageEntry> read_passage_table(const std::string& path) {
  const detail::TextTable t = detail::read_text_table(path, true);
  auto column = [&](std::initializer_list<const char*> names) -> int {
    for (std::size_t c = 0; c < t.header.size(); ++c)
      for (const char* n : names)
        if (t.header[c] == n) return static_cast<int>(c);
    return -1;
  };
  const int file = column({"file", "record", "path"}), train = column({"train"}), speed = column({"speed_kmh"});
  if (file < 0)
    throw InputError(SourceLocation{path, t.header_line, "file"},
                     "a table of passages needs a column 'file' (the record; optional: train, speed_kmh)");
  std::vector<PassageEntry> out;
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    PassageEntry e;
    e.line = t.lines[r];
    e.file = t.rows[r][static_cast<std::size_t>(file)];
    if (e.file.empty()) throw InputError(SourceLocation{path, e.line, "file"}, "empty file cell");
    if (train >= 0) e.train = t.rows[r][static_cast<std::size_t>(train)];
    if (speed >= 0 && !t.rows[r][static_cast<std::size_t>(speed)].empty()) {
      const std::string& cell = t.rows[r][static_cast<std::size_t>(speed)];
      char* end = nullptr;
      e.speed_kmh = std::strtod(cell.c_str(), &end);
      if (end != cell.c_str() + cell.size() || !(e.speed_kmh > 0) || !std::isfinite(e.speed_kmh))
        throw InputError(SourceLocation{path, e.line, "speed_kmh"}, "'" + cell + "' is not a speed > 0 [km/h] (leave it empty to identify it)");
    }
    if (!e.file.empty() && e.file.front() != '/') {
      const auto slash = path.find_last_of('/');
      if (slash != std::string::npos) e.file = path.substr(0, slash + 1) + e.file;
    }
    out.push_back(std::move(e));
  }
  if (out.empty()) throw InputError(SourceLocation{path, t.header_line, "file"}, "no passages in the table");
  return out;
}

std::vector<std::string> record_files_in(const std::string& folder) {
  static const char* exts[] = {".csv", ".txt", ".tsv", ".dat", ".uff", ".unv", ".mat"};
  std::vector<std::string> files;
  for (const auto& f : std::filesystem::directory_iterator(folder)) {
    const std::string e = f.path().extension().string(), name = f.path().filename().string();
    if (f.is_regular_file() && name.front() != '.' && std::any_of(std::begin(exts), std::end(exts), [&](const char* x) { return e == x; }))
      files.push_back(f.path().string());
  }
  std::sort(files.begin(), files.end());
  if (files.empty()) throw InputError(folder + ": no record files (.csv, .txt, .tsv, .dat, .uff, .unv, .mat) in the folder");
  return files;
}

}  // namespace viaduct::io

#include "viaduct/io/record.hpp"

#include "atomic_file.hpp"

#include "csv_cells.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <set>

#include "viaduct/core/error.hpp"

namespace viaduct::io {

const std::vector<std::string>& known_units() {
  static const std::vector<std::string> u = {"m", "mm", "mps", "mps2", "g", "N", "kN", "Nm", "kNm", "ue", "Pa", "V", "rad", "1"};
  return u;
}

std::size_t Record::channel(const std::string& name) const {
  for (std::size_t i = 0; i < channels.size(); ++i)
    if (channels[i] == name || channels[i] == name + "_" + units[i]) return i;
  std::string have;
  for (const auto& c : channels) have += " " + c;
  throw InputError("no channel '" + name + "' in the record; it has:" + have);
}

using detail::split_csv;
using detail::trim;

Record read_record_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError("cannot open record " + path);
  bool cut = false;  // the line being read is the last and has no newline: an error in it may be a file cut short
  auto err = [&](int line, const std::string& msg) {
    return InputError(SourceLocation{path, line, ""},
                      cut ? msg + " (the file ends inside this line, without a newline: cut short?)" : msg);
  };
  Record r;
  double declared_fs = 0.0;
  bool has_time = false;
  std::vector<std::string> header;
  std::vector<double> values;  // row-major, grown as we stream
  std::vector<double> times;
  std::string line;
  int ln = 0;
  std::size_t n_cols = 0;
  while (std::getline(in, line)) {
    if (++ln == 1) detail::drop_bom(line);
    cut = in.eof();
    const std::string t = trim(line);
    if (t.empty()) continue;
    if (t[0] == '#') {
      const auto eq = t.find('=');
      if (eq != std::string::npos && trim(t.substr(1, eq - 1)) == "sampling_rate_hz") {
        const std::string v = trim(t.substr(eq + 1));
        const auto res = std::from_chars(v.data(), v.data() + v.size(), declared_fs);
        if (res.ec != std::errc() || res.ptr != v.data() + v.size() || !(declared_fs > 0.0) || !std::isfinite(declared_fs))
          throw err(ln, "sampling_rate_hz must be a number > 0, got '" + v + "'");
      }
      continue;
    }
    if (header.empty()) {
      header = split_csv(t);
      has_time = header.front() == "t_s";
      std::set<std::string> seen;
      for (std::size_t c = has_time ? 1 : 0; c < header.size(); ++c) {
        const std::string& name = header[c];
        if (name.empty()) throw err(ln, "column " + std::to_string(c + 1) + " has no name");
        if (!seen.insert(name).second) throw err(ln, "channel '" + name + "' appears twice");
        const auto us = name.rfind('_');
        const std::string unit = us == std::string::npos ? "" : name.substr(us + 1);
        if (std::find(known_units().begin(), known_units().end(), unit) == known_units().end()) {
          std::string list;
          for (const auto& u : known_units()) list += " _" + u;
          throw err(ln, "channel '" + name + "' has no known unit suffix (one of" + list + ")");
        }
        r.channels.push_back(name);
        r.units.push_back(unit);
      }
      if (r.channels.empty()) throw err(ln, "the header names no channel");
      n_cols = header.size();
      continue;
    }
    // data row: parse without allocating per cell
    std::size_t col = 0;
    const char* p = t.data();
    const char* end = t.data() + t.size();
    while (true) {
      while (p < end && (*p == ' ' || *p == '\t')) ++p;
      double v = 0.0;
      const auto res = std::from_chars(p, end, v);
      if (res.ec != std::errc() || !std::isfinite(v)) {
        const std::string colname = col < header.size() ? header[col] : "column " + std::to_string(col + 1);
        throw err(ln, "column '" + colname + "': not a finite number (missing samples and NaN are not repaired)");
      }
      if (col >= n_cols) throw err(ln, "more than the header's " + std::to_string(n_cols) + " columns");
      if (has_time && col == 0) times.push_back(v);
      else values.push_back(v);
      ++col;
      p = res.ptr;
      while (p < end && (*p == ' ' || *p == '\t')) ++p;
      if (p == end) break;
      if (*p != ',') throw err(ln, "unexpected text after a number in column " + std::to_string(col));
      ++p;
    }
    if (col != n_cols)
      throw err(ln, "expected " + std::to_string(n_cols) + " columns as in the header, got " + std::to_string(col));
  }
  if (header.empty()) throw InputError(path + ": no header line (and no data)");
  const std::size_t nc = r.channels.size();
  const std::size_t ns = values.size() / nc;
  if (ns < 2) throw InputError(path + ": a record needs at least 2 samples, got " + std::to_string(ns));
  if (has_time) {
    // Strictly increasing, and regular: each step within 1 % of the median step.
    std::vector<double> dts(ns - 1);
    for (std::size_t k = 0; k + 1 < ns; ++k) {
      dts[k] = times[k + 1] - times[k];
      if (!(dts[k] > 0.0))
        throw InputError(path + ": time does not increase at sample " + std::to_string(k + 2) + " (t = " +
                         format_number(times[k + 1]) + " s after " + format_number(times[k]) + " s)");
    }
    std::vector<double> sorted = dts;
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
    const double dt = sorted[sorted.size() / 2];
    for (std::size_t k = 0; k < dts.size(); ++k)
      if (std::abs(dts[k] - dt) > 0.01 * dt)
        throw InputError(path + ": irregular sampling at sample " + std::to_string(k + 2) + " (step " +
                         format_number(dts[k], 6) + " s, median " + format_number(dt, 6) +
                         " s): viaduct needs uniformly sampled records and does not repair them; resample the logger's output first");
    // Rate from the whole span (less sensitive to rounded time stamps than the median step).
    r.fs_hz = static_cast<double>(ns - 1) / (times.back() - times.front());
    r.t0_s = times.front();
    if (declared_fs > 0.0 && std::abs(declared_fs - r.fs_hz) > 1e-3 * declared_fs)
      throw InputError(path + ": declared sampling_rate_hz = " + format_number(declared_fs) +
                       " disagrees with the time column (" + format_number(r.fs_hz, 8) + " Hz)");
  } else {
    if (!(declared_fs > 0.0))
      throw InputError(path + ": no t_s column and no '# sampling_rate_hz = ...' comment: the sampling rate is unknown");
    r.fs_hz = declared_fs;
  }
  r.data = Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      values.data(), static_cast<Index>(ns), static_cast<Index>(nc));
  return r;
}

void write_record_csv(const std::string& path, const Record& r, int significant_digits) {
  for (Index c = 0; c < r.data.cols(); ++c)
    if (!r.data.col(c).allFinite())
      throw SolverError("not writing " + path + ": channel " + r.channels[static_cast<std::size_t>(c)] + " holds a non-finite value");
  detail::AtomicFile f(path);
  std::fprintf(f.get(), "# sampling_rate_hz = %.17g\nt_s", r.fs_hz);
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

ChannelQuantity channel_quantity(const std::string& unit, const std::string& channel, const std::string& who) {
  if (unit == "mps2") return {true, 1.0};
  if (unit == "g") return {true, 1.0 / 9.80665};
  if (unit == "m") return {false, 1.0};
  if (unit == "mm") return {false, 1e3};
  throw InputError(who + ": channel '" + channel + "' is in " + unit + "; only _mps2, _g, _m or _mm compare with the model");
}

}  // namespace viaduct::io

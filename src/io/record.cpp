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

ChannelSummary summarise_channel(const Vector& x) {
  ChannelSummary s;
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
  if (unit == "mps2") return {true, 1.0};
  if (unit == "m") return {false, 1.0};
  throw InputError(who + ": channel '" + channel + "' is in " + unit + "; only accelerations (_mps2, [g], ...) and deflections (_m, [mm], ...) compare with the model");
}

}  // namespace viaduct::io

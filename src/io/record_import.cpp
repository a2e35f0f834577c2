// Record CSV as loggers write it: layout detection, units, time grid, NaN and gap repair
// (docs/records.md). One pass over the file collects every problem; the error lists them all.
#include <algorithm>
#include <cctype>
#include <map>
#include <memory>
#include <charconv>
#include <cmath>
#include <fstream>
#include <climits>
#include <cstdint>
#include <numeric>
#include <set>

#include <matio.h>

#include "csv_cells.hpp"
#include "viaduct/core/error.hpp"
#include "viaduct/io/record.hpp"

namespace viaduct::io {

namespace {

constexpr double kStandardGravity = 9.80665;  // [m/s²] the g of accelerometers (CGPM 1901)

// Lower case, micro signs and ε as ASCII, superscript two as 2, degree sign as "deg", no spaces,
// '^' or '*': "m/s²" → "m/s2", "µε" → "ue", "N·m" → "n.m", "°C" → "degc".
std::string normalise_unit(const std::string& text) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    const unsigned char n = i + 1 < text.size() ? static_cast<unsigned char>(text[i + 1]) : 0;
    if ((c == 0xC2 && n == 0xB5) || (c == 0xCE && n == 0xBC)) out += 'u', ++i;        // µ (micro sign, Greek mu)
    else if ((c == 0xCE && n == 0xB5) || (c == 0xCF && n == 0xB5)) out += 'e', ++i;   // ε, ϵ
    else if (c == 0xC2 && n == 0xB2) out += '2', ++i;                                  // ²
    else if (c == 0xC2 && n == 0xB0) out += "deg", ++i;                                // °
    else if (c == 0xC2 && n == 0xB7) out += '.', ++i;                                  // ·
    else if (c == ' ' || c == '^' || c == '*') continue;
    else out += static_cast<char>(std::tolower(c));
  }
  return out;
}

bool is_missing_marker(std::string_view c) {
  return c.empty() || c == "-" || c == "--" || c == "NA" || c == "N/A" || c == "#N/A" || c == "null" || c == "NULL" ||
         c == "nan" || c == "NaN" || c == "NAN";
}

std::string_view trim_view(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r' || s.front() == '"')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r' || s.back() == '"')) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> split_view(std::string_view line, char sep) {
  std::vector<std::string_view> out;
  std::size_t start = 0;
  while (true) {
    const auto pos = line.find(sep, start);
    out.push_back(trim_view(line.substr(start, pos == std::string_view::npos ? std::string_view::npos : pos - start)));
    if (pos == std::string_view::npos) break;
    start = pos + 1;
  }
  return out;
}

enum class Cell { number, missing, bad };

// A cell as a number: decimal comma allowed when ',' is not the separator; "hh:mm:ss.fff" (after
// an optional date and 'T' or space) as seconds of the day when `clock` is set.
Cell parse_cell(std::string_view c, bool decimal_comma, bool clock, double& v) {
  if (is_missing_marker(c)) return Cell::missing;
  char buf[64];
  if (decimal_comma && c.find(',') != std::string_view::npos && c.size() < sizeof buf) {
    std::copy(c.begin(), c.end(), buf);
    std::replace(buf, buf + c.size(), ',', '.');
    c = std::string_view(buf, c.size());
  }
  if (c.front() == '+') c.remove_prefix(1);
  const auto res = std::from_chars(c.data(), c.data() + c.size(), v);
  if (res.ec == std::errc() && res.ptr == c.data() + c.size()) return std::isfinite(v) ? Cell::number : Cell::missing;
  if (!clock || c.find(':') == std::string_view::npos) return Cell::bad;
  const auto sp = c.find_last_of(" T");
  std::string_view hms = sp == std::string_view::npos ? c : c.substr(sp + 1);
  double h = 0, m = 0, s = 0;
  const auto c1 = hms.find(':'), c2 = hms.find(':', c1 + 1);
  if (c2 == std::string_view::npos) return Cell::bad;
  const auto a = std::from_chars(hms.data(), hms.data() + c1, h);
  const auto b = std::from_chars(hms.data() + c1 + 1, hms.data() + c2, m);
  const auto d = std::from_chars(hms.data() + c2 + 1, hms.data() + hms.size(), s);
  if (a.ec != std::errc() || b.ec != std::errc() || d.ec != std::errc() || d.ptr != hms.data() + hms.size()) return Cell::bad;
  v = 3600 * h + 60 * m + s;
  return Cell::number;
}

// A header cell split into name and unit text: "Acc1 [g]", "Acc2 (m/s^2)", "acc_mps2" (a known
// suffix), or no unit.
struct HeaderCell {
  std::string text, base, unit_text;
  bool bracketed = false;
};

HeaderCell split_header(const std::string& text) {
  HeaderCell h{text, text, "", false};
  const std::string t = detail::trim(text);
  if (!t.empty() && (t.back() == ']' || t.back() == ')')) {
    const auto open = t.find_last_of(t.back() == ']' ? '[' : '(');
    if (open != std::string::npos && open > 0) {
      h.base = detail::trim(t.substr(0, open));
      h.unit_text = detail::trim(t.substr(open + 1, t.size() - open - 2));
      h.bracketed = true;
      while (!h.base.empty() && (h.base.back() == '_' || h.base.back() == '-')) h.base.pop_back();
      return h;
    }
  }
  const auto us = t.rfind('_');
  if (us != std::string::npos && us > 0) {
    const std::string suffix = t.substr(us + 1);
    if (std::find(known_units().begin(), known_units().end(), suffix) != known_units().end()) {
      h.base = t.substr(0, us);
      h.unit_text = suffix;
    }
  }
  return h;
}

// A name usable in file names and CSV headers: letters, digits, '_', '-', '.'; others become '_'.
std::string clean_name(const std::string& s) {
  std::string out;
  for (char c : s) {
    const bool ok = std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
    if (ok) out += c;
    else if (!out.empty() && out.back() != '_') out += '_';
  }
  while (!out.empty() && out.back() == '_') out.pop_back();
  return out;
}

bool is_time_name(const std::string& base) {
  std::string l;
  for (char c : base) l += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return l == "t" || l == "time" || l == "zeit" || l == "timestamp" || l == "time_stamp" || l == "tiempo" || l == "temps";
}

// The first line that is data: as many cells as the candidate header, all numbers or missing,
// one at least a number. The separator comes from the header: ';' if it has one, else a tab,
// else ','.
char separator_of(const std::string& header) {
  if (header.find(';') != std::string::npos) return ';';
  if (header.find('\t') != std::string::npos) return '\t';
  return ',';
}

bool is_data_line(const std::string& line, char sep, std::size_t n_cells) {
  const auto cells = split_view(line, sep);
  if (cells.size() != n_cells) return false;
  bool any = false;
  for (const auto& c : cells) {
    double v = 0;
    const Cell k = parse_cell(c, sep != ',', c.find(':') != std::string_view::npos, v);
    if (k == Cell::bad) return false;
    any = any || k == Cell::number;
  }
  return any;
}

// "Sample rate: 1651.2 Hz", "Sampling frequency = 1651.2", "fs;1651,2", "# sampling_rate_hz = F":
// a preamble or comment line that declares the rate. 0 when the line does not.
double rate_in_line(const std::string& line) {
  std::string l;
  for (char c : line) l += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const auto sep = l.find_first_of(":=;\t,");
  if (sep == std::string::npos) return 0.0;
  const std::string key = detail::trim(l.substr(l[0] == '#' ? 1 : 0, sep - (l[0] == '#' ? 1 : 0)));
  const bool rate_key = key == "fs" || key == "sampling_rate_hz" ||
                        ((key.find("sampl") != std::string::npos || key.find("scan") != std::string::npos) &&
                         (key.find("rate") != std::string::npos || key.find("freq") != std::string::npos));
  if (!rate_key) return 0.0;
  std::string v = detail::trim(l.substr(sep + 1));
  std::replace(v.begin(), v.end(), ',', '.');
  double fs = 0;
  const auto res = std::from_chars(v.data(), v.data() + v.size(), fs);
  const std::string unit = detail::trim(v.substr(static_cast<std::size_t>(res.ptr - v.data())));
  const bool unit_ok = unit.empty() || unit == "hz" || unit == "1/s" || unit == "s/s" || unit == "sps" || unit == "samples/s";
  if (res.ec == std::errc() && unit_ok && fs > 0 && std::isfinite(fs)) return fs;
  // A rate key with something else after it (a header cell named "fs", "Sampling rate: see
  // below") is no declaration, unless it is viaduct's own comment or a number.
  const bool meant_a_number = key == "sampling_rate_hz" || res.ec == std::errc();
  return meant_a_number ? -1.0 : 0.0;
}

// Problems of one file, each with its line, listed together in one InputError.
struct Problems {
  std::string path;
  std::vector<std::pair<int, std::string>> list;
  std::size_t count = 0;
  void add(int line, const std::string& msg) {
    ++count;
    if (list.size() < 20) list.emplace_back(line, msg);
  }
  void throw_if_any() {
    if (list.empty()) return;
    std::stable_sort(list.begin(), list.end(), [](const auto& a, const auto& b) {
      return (a.first == 0 ? INT32_MAX : a.first) < (b.first == 0 ? INT32_MAX : b.first);
    });
    std::string msg = list.front().second;
    for (std::size_t i = 1; i < list.size(); ++i)
      msg += "\n  " + path + (list[i].first > 0 ? ":" + std::to_string(list[i].first) : std::string()) + ": " + list[i].second;
    if (count > list.size()) msg += "\n  ... and " + std::to_string(count - list.size()) + " more problems of the same file";
    else if (count > 1) msg += "\n  (" + std::to_string(count) + " problems in this file)";
    throw InputError(SourceLocation{path, list.front().first, ""}, msg);
  }
};

// The file's text up to the header, the header, and every data row.
struct RawTable {
  std::vector<std::string> header;
  int header_line = 0;
  char sep = ',';
  bool decimal_comma = false;
  std::vector<std::string> preamble;
  double declared_fs = 0.0;
  int declared_line = 0;
  std::string declared_where;  // where the rate was declared when not on a line ("variable 'fs'")
  std::vector<double> cells;   // row-major; NaN for missing cells
  std::vector<int> lines;      // line of each row
  std::size_t time_col = std::string::npos;
};

std::size_t find_time_column(const std::vector<std::string>& header, const ReadOptions& o, Problems& pb, int header_line);

// A line of units under a line of names ("Time;Acc1;Strain1" then "s;g;µε"): the two make one
// header ("Acc1 [g]").
bool is_unit_line(const std::vector<std::string_view>& cells) {
  for (const auto& c : cells) {
    const std::string u = normalise_unit(std::string(c));
    if (!c.empty() && !parse_unit(std::string(c)) && u != "s" && u != "ms" && u != "[s]") return false;
  }
  return true;
}

void take_header(RawTable& t, const std::string& text, int line, const ReadOptions& o, Problems& pb) {
  const auto cells = split_view(text, t.sep);
  const auto names = t.preamble.empty() ? std::vector<std::string_view>{} : split_view(t.preamble.back(), t.sep);
  const bool units_below_names = names.size() == cells.size() && is_unit_line(cells) && !is_unit_line(names);
  for (std::size_t c = 0; c < cells.size(); ++c) {
    std::string h(cells[c]);
    if (units_below_names) h = std::string(names[c]) + (cells[c].empty() ? "" : " [" + h + "]");
    t.header.push_back(h);
  }
  if (units_below_names) t.preamble.pop_back();
  t.header_line = line;
  t.time_col = find_time_column(t.header, o, pb, line);
}

RawTable read_table(std::ifstream& in, const ReadOptions& o, Problems& pb) {
  RawTable t;
  std::string line, pending;
  int pending_line = 0, ln = 0;
  std::size_t n = 0;
  while (std::getline(in, line)) {
    if (++ln == 1) detail::drop_bom(line);
    const bool last_unterminated = in.eof();
    const std::string tr = detail::trim(line);
    if (tr.empty()) continue;
    if (t.header.empty()) {
      const double fs = rate_in_line(tr);
      if (fs != 0.0 && t.declared_fs == 0.0) {
        if (fs < 0) pb.add(ln, "the sampling rate declared here is not a number > 0");
        t.declared_fs = std::max(fs, 0.0), t.declared_line = ln;
      }
      if (tr[0] == '#') continue;
      if (pending.empty() || !is_data_line(tr, separator_of(pending), split_view(pending, separator_of(pending)).size())) {
        if (!pending.empty()) t.preamble.push_back(pending);
        pending = tr, pending_line = ln;
        continue;
      }
      t.sep = separator_of(pending);
      take_header(t, pending, pending_line, o, pb);
      n = t.header.size();
    }
    if (tr[0] == '#') continue;
    // A data row.
    const auto cells = split_view(tr, t.sep);
    const std::string cut = last_unterminated ? " (the file ends inside this line, without a newline: cut short?)" : "";
    if (cells.size() != n) {
      pb.add(ln, "expected " + std::to_string(n) + " columns as in the header (line " + std::to_string(t.header_line) + "), got " +
                     std::to_string(cells.size()) + cut);
      continue;
    }
    for (std::size_t c = 0; c < n; ++c) {
      double v = 0;
      const Cell k = parse_cell(cells[c], t.sep != ',', c == t.time_col, v);
      if (k == Cell::bad) {
        pb.add(ln, "column '" + t.header[c] + "': '" + std::string(cells[c].substr(0, 30)) + "' is not a number" + cut);
        v = std::nan("");
      } else if (k == Cell::missing) {
        v = std::nan("");
      } else if (t.sep != ',' && cells[c].find(',') != std::string_view::npos) {
        t.decimal_comma = true;
      }
      t.cells.push_back(v);
    }
    t.lines.push_back(ln);
  }
  if (t.header.empty()) {
    if (!pending.empty())
      pb.add(pending_line, "no data row under this line: a header needs rows of as many numbers below it (',', ';' or tab separated)");
    else pb.add(0, "no header line (and no data)");
  }
  return t;
}

}  // namespace

const std::vector<std::string>& known_units() {
  static const std::vector<std::string> u = {"m", "mm", "mps", "mps2", "g", "N", "kN", "Nm", "kNm", "ue", "Pa", "V", "rad", "1", "degC"};
  return u;
}

std::optional<UnitConversion> parse_unit(const std::string& text) {
  struct Spelling {
    const char* text;
    const char* unit;
    double factor;
  };
  static const Spelling table[] = {
      // acceleration
      {"mps2", "mps2", 1}, {"m/s2", "mps2", 1}, {"ms-2", "mps2", 1}, {"m.s-2", "mps2", 1}, {"m/s/s", "mps2", 1},
      {"g", "mps2", kStandardGravity}, {"mg", "mps2", 1e-3 * kStandardGravity}, {"mm/s2", "mps2", 1e-3},
      // velocity
      {"mps", "mps", 1}, {"m/s", "mps", 1}, {"mm/s", "mps", 1e-3},
      // displacement
      {"m", "m", 1}, {"mm", "m", 1e-3}, {"cm", "m", 1e-2}, {"um", "m", 1e-6},
      // force and moment ("nm" is N·m: nanometres are not a bridge logger's unit)
      {"n", "N", 1}, {"kn", "N", 1e3}, {"nm", "Nm", 1}, {"n.m", "Nm", 1}, {"knm", "Nm", 1e3}, {"kn.m", "Nm", 1e3},
      // strain: viaduct's strain unit is the microstrain of the model's <station>_strain_ue
      {"ue", "ue", 1}, {"microstrain", "ue", 1}, {"ustrain", "ue", 1}, {"um/m", "ue", 1}, {"strain", "ue", 1e6},
      {"m/m", "ue", 1e6}, {"mm/m", "ue", 1e3},
      // stress, voltage, rotation, dimensionless, temperature
      {"pa", "Pa", 1}, {"kpa", "Pa", 1e3}, {"mpa", "Pa", 1e6}, {"n/mm2", "Pa", 1e6}, {"v", "V", 1}, {"mv", "V", 1e-3},
      {"rad", "rad", 1}, {"mrad", "rad", 1e-3}, {"urad", "rad", 1e-6}, {"deg", "rad", 3.14159265358979323846 / 180},
      {"1", "1", 1}, {"-", "1", 1}, {"degc", "degC", 1}};
  const std::string n = normalise_unit(text);
  for (const auto& s : table)
    if (n == s.text) return UnitConversion{s.unit, s.factor};
  return std::nullopt;
}

std::size_t Record::channel(const std::string& name) const {
  const std::string clean = clean_name(name);  // "Acc S1 mid" names Acc_S1_mid_mps2
  for (std::size_t i = 0; i < channels.size(); ++i)
    if (channels[i] == name || channels[i] == name + "_" + units[i] || channels[i] == clean + "_" + units[i] ||
        (i < sources.size() && sources[i] == name))
      return i;
  std::string have;
  for (const auto& c : channels) have += " " + c;
  throw InputError("no channel '" + name + "' in the record; it has:" + have);
}

namespace {

// Which header column holds time: the option, else a column named like time; npos for none.
std::size_t find_time_column(const std::vector<std::string>& header, const ReadOptions& o, Problems& pb, int header_line) {
  if (o.time_column == "none") return std::string::npos;
  if (!o.time_column.empty()) {
    const std::string& tc = o.time_column;
    if (tc.size() < 7 && std::all_of(tc.begin(), tc.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); })) {
      const std::size_t k = std::stoul(tc);
      if (k >= 1 && k <= header.size()) return k - 1;
      pb.add(header_line, "--time-column " + tc + ": the header has columns 1 to " + std::to_string(header.size()));
      return std::string::npos;
    }
    for (std::size_t c = 0; c < header.size(); ++c)
      if (header[c] == tc || split_header(header[c]).base == tc) return c;
    pb.add(header_line, "--time-column '" + tc + "' is not a column of the header");
    return std::string::npos;
  }
  for (std::size_t c = 0; c < header.size(); ++c) {
    const HeaderCell h = split_header(header[c]);
    if (header[c] == "t_s" || is_time_name(h.base)) return c;
  }
  return std::string::npos;
}

// The factor from the time column's unit to seconds, named "s", "ms", "us" or absent (seconds).
double time_factor(const std::string& header, std::string& note) {
  const HeaderCell h = split_header(header);
  std::string u = normalise_unit(h.unit_text);
  if (h.unit_text.empty()) {
    // "t_s" is split as base "t" with no known unit suffix "s": seconds either way.
    const auto us = header.rfind('_');
    const std::string suffix = us == std::string::npos ? "" : header.substr(us + 1);
    if (suffix == "ms") return 1e-3;
    if (suffix == "s" || suffix == "us") return suffix == "s" ? 1.0 : 1e-6;
    note = "time column '" + header + "' has no unit: seconds assumed";
    return 1.0;
  }
  if (u == "s" || u == "sec") return 1.0;
  if (u == "ms") return 1e-3;
  if (u == "us") return 1e-6;
  if (u == "min") return 60.0;
  note = "time column '" + header + "': unit '" + h.unit_text + "' is not s, ms, us or min; seconds assumed";
  return 1.0;
}

// The uniform grid of the time stamps: sample index of each row, rate and start. Steps are
// counted in samples (a gap is a step of several), the rate fitted by least squares over all
// stamps (or the declared one, checked against the fit), and a stamp more than half a sample off
// the grid is a problem (jitter or clock trouble, not rounding).
struct Grid {
  std::vector<Index> k;
  double fs = 0, t0 = 0, max_offset = 0;
  std::string how;
};

Grid time_grid(const std::vector<double>& t, const std::vector<int>& lines, double declared_fs, const std::string& declared_by,
               Problems& pb) {
  Grid g;
  const std::size_t n = t.size();
  std::vector<double> steps(n - 1);
  bool ok = true;
  for (std::size_t i = 0; i + 1 < n; ++i) {
    steps[i] = t[i + 1] - t[i];
    if (!(steps[i] > 0)) {
      pb.add(lines[i + 1], "time does not increase (t = " + format_number(t[i + 1]) + " s after " + format_number(t[i]) + " s on line " +
                               std::to_string(lines[i]) + ")");
      ok = false;
    }
  }
  if (!ok) return g;
  std::vector<double> sorted = steps;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
  const double median = sorted[sorted.size() / 2];
  double sum = 0;
  std::size_t cnt = 0;
  for (double s : steps)
    if (s < 1.5 * median) sum += s, ++cnt;
  const double single = sum / static_cast<double>(cnt);  // the mean single step: telescopes over each run without a gap
  if (declared_fs > 0) {
    // Stamps within half a sample of the grid put the mean single step within (gaps + 1)/count
    // samples of the true one; more than that (and 0.1 %) off, the rates disagree (a time column
    // at half the declared rate would otherwise read as a gap every other sample).
    std::size_t runs = 1;
    for (double s : steps) runs += s >= 1.5 * median ? 1 : 0;
    const double tol = std::min(0.45, std::max(1e-3, static_cast<double>(runs) / static_cast<double>(cnt)));
    if (std::abs(single * declared_fs - 1) > tol) {
      pb.add(lines.front(), "the rate declared (" + declared_by + ") is " + format_number(declared_fs) + " Hz; the time column steps by " +
                                format_number(single, 6) + " s (" + format_number(1 / single, 8) + " Hz): they disagree");
      return g;
    }
  }
  const double dt0 = declared_fs > 0 ? 1.0 / declared_fs : single;
  g.k.assign(n, 0);
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const long long m = std::llround(steps[i] / dt0);
    if (m < 1) {
      pb.add(lines[i + 1], "time step of " + format_number(steps[i], 6) + " s, less than half a sample (" + format_number(dt0, 6) +
                               " s): two stamps for one sample, or a rate above the declared one");
      ok = false;
    }
    g.k[i + 1] = g.k[i] + std::max<long long>(m, 1);
  }
  if (!ok) return g;
  // Least squares t = a + b k.
  const double nk = static_cast<double>(n);
  double mk = 0, mt = 0;
  for (std::size_t i = 0; i < n; ++i) mk += static_cast<double>(g.k[i]) / nk, mt += t[i] / nk;
  double skk = 0, skt = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double dk = static_cast<double>(g.k[i]) - mk;
    skk += dk * dk, skt += dk * (t[i] - mt);
  }
  double b = skt / skk;
  if (declared_fs <= 0 && std::abs(b / dt0 - 1) > 0.01) {
    // The single steps say one rate, the grid through all stamps another: some step is a
    // fraction of a sample off (not rounding, not a whole-sample gap). Name the worst.
    std::size_t worst = 0;
    double worst_frac = -1;
    for (std::size_t i = 0; i + 1 < n; ++i) {
      const double q = steps[i] / dt0, frac = std::abs(q - std::round(q));
      if (frac > worst_frac) worst_frac = frac, worst = i;
    }
    pb.add(lines[worst + 1], "irregular sampling: a step of " + format_number(steps[worst], 6) + " s where the others are " +
                                 format_number(dt0, 6) + " s (" + format_number(steps[worst] / dt0, 3) +
                                 " samples): the time stamps are not on one uniform grid within half a sample (viaduct needs uniform "
                                 "sampling: resample the logger's output on a uniform time base first)");
    return g;
  }
  if (declared_fs > 0) {
    if (std::abs(1.0 / b - declared_fs) > 1e-3 * declared_fs) {
      pb.add(lines.front(), "the rate declared (" + declared_by + ") is " + format_number(declared_fs) + " Hz; the time column says " + format_number(1.0 / b, 8) +
                                " Hz: they disagree by more than 0.1 %");
      return g;
    }
    b = 1.0 / declared_fs;
  } else {
    // Time stamps written with 12 digits cannot tell a rate from its 9-digit rounding: take that.
    const double fs = 1.0 / b;
    const double p = std::pow(10.0, 8 - std::floor(std::log10(fs)));
    const double snapped = std::round(fs * p) / p;
    if (std::abs(snapped - fs) < 1e-9 * fs) b = 1.0 / snapped;
  }
  g.fs = 1.0 / b;
  g.t0 = mt - b * mk;
  std::size_t reported = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double off = (t[i] - g.t0 - b * static_cast<double>(g.k[i])) / b;
    g.max_offset = std::max(g.max_offset, std::abs(off));
    if (std::abs(off) > 0.5 && reported++ < 5)
      pb.add(lines[i], "time stamp " + format_number(t[i]) + " s is " + format_number(off, 3) + " samples off the uniform grid of " +
                           format_number(g.fs, 8) + " Hz: jitter beyond rounding (viaduct needs uniform sampling: resample the "
                           "logger's output on a uniform time base first)");
  }
  // The first stamp as written when it is within a tenth of a sample of the fitted start (rounded
  // stamps: 10.0000, not 9.99999998).
  if (std::abs(t[0] - g.t0) < 0.1 * b) g.t0 = t[0];
  return g;
}

// Runs of NaN in the columns of `data`: interior runs up to `fill_max` samples are interpolated
// linearly; longer ones (and those at either end) are cut: the record keeps its longest piece
// without them (split) or is refused.
void repair_missing(Record& r, Index fill_max, bool split, const std::vector<int>& row_line, ImportReport& rep, Problems& pb) {
  const Index n = r.data.rows();
  std::vector<char> cut(static_cast<std::size_t>(n), 0);
  std::vector<std::pair<int, std::string>> long_runs;  // line of the run's first sample, what
  for (Index c = 0; c < r.data.cols(); ++c) {
    auto col = r.data.col(c);
    auto& rc = rep.channels[static_cast<std::size_t>(c)];
    for (Index i = 0; i < n;) {
      if (!std::isnan(col[i])) {
        ++i;
        continue;
      }
      Index j = i;
      while (j < n && std::isnan(col[j])) ++j;
      rc.missing += j - i;
      const double ta = r.t0_s + static_cast<double>(i) / r.fs_hz, tb = r.t0_s + static_cast<double>(j - 1) / r.fs_hz;
      const std::string where = r.channels[static_cast<std::size_t>(c)] + ", " + std::to_string(j - i) + " samples from " +
                                format_number(ta, 8) + " to " + format_number(tb, 8) + " s";
      if (i > 0 && j < n && j - i <= fill_max) {
        for (Index m = i; m < j; ++m)
          col[m] = col[i - 1] + (col[j] - col[i - 1]) * static_cast<double>(m - i + 1) / static_cast<double>(j - i + 1);
        rc.interpolated += j - i;
      } else {
        for (Index m = i; m < j; ++m) cut[static_cast<std::size_t>(m)] = 1;
        long_runs.emplace_back(row_line[static_cast<std::size_t>(i)], where);
      }
      i = j;
    }
    if (rc.missing == n) pb.add(row_line.front(), "channel '" + rc.header + "' holds no number");
  }
  std::string filled;
  for (const auto& c : rep.channels)
    if (c.interpolated > 0) filled += (filled.empty() ? "" : ", ") + c.channel + " " + std::to_string(c.interpolated);
  if (!filled.empty())
    rep.repairs.push_back("missing samples interpolated linearly (runs up to " + std::to_string(fill_max) + " samples, --fill-max-s): " + filled);
  if (long_runs.empty() || pb.count > 0) return;
  if (!split) {
    for (const auto& [line, w] : long_runs)
      pb.add(line, "missing samples too long to interpolate (--fill-max-s " + format_number(static_cast<double>(fill_max) / r.fs_hz) +
                    " s) or at an end: " + w + "; --long-gaps split keeps the longest piece without them");
    return;
  }
  // Pieces between cut rows; keep the longest.
  Index best_a = 0, best_n = 0;
  std::vector<std::pair<Index, Index>> pieces;
  for (Index i = 0; i < n;) {
    if (cut[static_cast<std::size_t>(i)]) {
      ++i;
      continue;
    }
    Index j = i;
    while (j < n && !cut[static_cast<std::size_t>(j)]) ++j;
    pieces.emplace_back(i, j);
    if (j - i > best_n) best_a = i, best_n = j - i;
    i = j;
  }
  if (best_n < 2) {
    pb.add(row_line.front(), "no 2 successive samples without a missing value in every channel");
    return;
  }
  auto t_of = [&](Index i) { return format_number(r.t0_s + static_cast<double>(i) / r.fs_hz, 8); };
  std::string msg = "missing samples too long to interpolate or at an end (" + long_runs.front().second + ", line " +
                    std::to_string(long_runs.front().first) +
                    (long_runs.size() > 1 ? ", and " + std::to_string(long_runs.size() - 1) + " more" : std::string()) +
                    "): kept the longest piece without them, " + t_of(best_a) + " to " + t_of(best_a + best_n - 1) + " s (" +
                    std::to_string(best_n) + " of " + std::to_string(n) + " samples)";
  if (pieces.size() > 1) {
    msg += "; dropped";
    for (const auto& p : pieces)
      if (p.first != best_a) msg += " " + t_of(p.first) + "–" + t_of(p.second - 1) + " s";
  }
  rep.repairs.push_back(msg + " (--long-gaps refuse to refuse instead)");
  r.t0_s += static_cast<double>(best_a) / r.fs_hz;
  r.data = Matrix(r.data.middleRows(best_a, best_n));
}

// The channels of the header (all columns but time): names, units and factors to viaduct's units.
void take_channels(const RawTable& t, const ReadOptions& o, std::size_t skip, Record& r, ImportReport& rep, Problems& pb) {
  std::set<std::string> seen;
  std::vector<bool> used(o.units.size(), false);
  for (std::size_t c = 0; c < t.header.size(); ++c) {
    if (c == t.time_col || c == skip) continue;
    const HeaderCell h = split_header(t.header[c]);
    const std::string name = clean_name(h.base);
    std::string unit_text = h.unit_text;
    for (std::size_t u = 0; u < o.units.size(); ++u)
      if (o.units[u].first == t.header[c] || o.units[u].first == name || o.units[u].first == h.base)
        unit_text = o.units[u].second, used[u] = true;
    ImportReport::Channel rc;
    rc.header = t.header[c];
    rc.unit_given = h.bracketed ? "[" + h.unit_text + "]" : h.unit_text;
    const auto conv = unit_text.empty() ? std::nullopt : parse_unit(unit_text);
    if (name.empty()) {
      pb.add(t.header_line, "column " + std::to_string(c + 1) + " has no name");
    } else if (unit_text.empty()) {
      pb.add(t.header_line, "channel '" + t.header[c] + "' has no unit: name it " + name + "_<unit> or '" + name +
                                " [unit]', or give --unit '" + t.header[c] + "=UNIT' (e.g. ue for microstrain, g, m/s^2, mm, kN)");
    } else if (!conv) {
      pb.add(t.header_line, "channel '" + t.header[c] + "': unit '" + unit_text + "' is not known (known: m/s^2, g, mg, m/s, m, mm, "
                                "um, N, kN, Nm, kNm, µε (ue, microstrain), strain, Pa, MPa, V, mV, rad, mrad, deg, °C, 1)");
    } else {
      rc.channel = name + "_" + conv->unit;
      rc.factor = conv->factor;
      if (!seen.insert(rc.channel).second) pb.add(t.header_line, "channel '" + rc.channel + "' appears twice");
      r.channels.push_back(rc.channel);
      r.units.push_back(conv->unit);
      r.sources.push_back(t.header[c]);
    }
    rep.channels.push_back(rc);
  }
  for (std::size_t u = 0; u < o.units.size(); ++u)
    if (!used[u]) pb.add(t.header_line, "--unit " + o.units[u].first + "=" + o.units[u].second + ": no such column in the header");
  if (r.channels.empty() && rep.channels.empty()) pb.add(t.header_line, "the header names no channel");
}

}  // namespace

namespace {

// The record of a table read from a file (CSV or MATLAB): its channels and units, the time grid
// from the time column or the declared rate, missing samples repaired; every problem of the
// file in one error. `layout` describes the file; `plain`: the file may be a record as viaduct
// writes it (a CSV), whose reading needs no report.
Record finish_table(const RawTable& t, const ReadOptions& o, Problems& pb, ImportReport* report, const std::string& layout, bool plain);

}  // namespace

Record read_record_csv(const std::string& path, const ReadOptions& o, ImportReport* report) {
  std::ifstream in(path);
  if (!in) throw InputError("cannot open record " + path);
  Problems pb{path, {}, 0};
  const RawTable t = read_table(in, o, pb);
  if (t.header.empty()) pb.throw_if_any();
  const std::string layout = std::string(t.sep == ';' ? "semicolon" : t.sep == '\t' ? "tab" : "comma") + "-separated, decimal " +
                             (t.decimal_comma ? "comma" : "point") + ", header on line " + std::to_string(t.header_line) +
                             (t.preamble.empty() ? "" : " under " + std::to_string(t.preamble.size()) + " preamble lines");
  return finish_table(t, o, pb, report, layout, t.sep == ',' && !t.decimal_comma && t.preamble.empty());
}

namespace {

Record finish_table(const RawTable& t, const ReadOptions& o, Problems& pb, ImportReport* report, const std::string& layout, bool plain) {
  Record r;
  ImportReport rep;
  const std::size_t n_cols = t.header.size(), n_rows = t.lines.size();
  // A separator at the end of every line (spreadsheet exports) makes a last column without a
  // name or a value: not a channel.
  std::size_t skip = std::string::npos;
  if (n_cols > 1 && t.header.back().empty()) {
    bool empty = true;
    for (std::size_t i = 0; i < n_rows && empty; ++i) empty = std::isnan(t.cells[i * n_cols + n_cols - 1]);
    if (empty) skip = n_cols - 1, rep.notes.push_back("every line ends with a separator: the empty last column is not a channel");
  }
  take_channels(t, o, skip, r, rep, pb);
  rep.layout = layout;
  if (n_rows < 2) pb.add(t.lines.empty() ? t.header_line : t.lines.front(), "a record needs at least 2 samples, got " + std::to_string(n_rows));
  double fs = o.fs_hz.value_or(t.declared_fs);
  const std::string declared_at = t.declared_where.empty() ? "line " + std::to_string(t.declared_line) : t.declared_where;
  const std::string declared_by = o.fs_hz ? "--rate-hz" : declared_at;
  if (o.fs_hz && t.declared_fs > 0 && std::abs(*o.fs_hz - t.declared_fs) > 1e-9 * t.declared_fs)
    rep.notes.push_back("--rate-hz " + format_number(*o.fs_hz) + " replaces the " + format_number(t.declared_fs) + " Hz declared (" + declared_at + ")");
  Grid g;
  if (t.time_col != std::string::npos && n_rows >= 2) {
    std::string note;
    const double f = time_factor(t.header[t.time_col], note);
    if (!note.empty()) rep.notes.push_back(note);
    std::vector<double> times(n_rows);
    bool all_stamped = true;
    for (std::size_t i = 0; i < n_rows; ++i) {
      times[i] = f * t.cells[i * n_cols + t.time_col];
      if (std::isnan(times[i])) pb.add(t.lines[i], "no time stamp in column '" + t.header[t.time_col] + "'"), all_stamped = false;
    }
    if (all_stamped) g = time_grid(times, t.lines, fs, declared_by, pb);
    rep.time = "column '" + t.header[t.time_col] + "'" + (fs > 0 ? ", rate " + format_number(fs) + " Hz declared (" + declared_by + ")"
                                                                 : ", rate " + format_number(g.fs, 10) + " Hz from the stamps");
  } else if (n_rows >= 2) {
    if (!(fs > 0))
      pb.add(t.header_line, "no time column (named t_s, time, Time [s], ...: --time-column) and no declared rate (a '# sampling_rate_hz "
                            "= F' or 'Sample rate: F Hz' line, or --rate-hz): the sampling rate is unknown");
    g.fs = fs;
    g.k.resize(n_rows);
    std::iota(g.k.begin(), g.k.end(), Index{0});
    rep.time = "no time column; rate " + format_number(fs) + " Hz declared (" + declared_by + "), start 0 s";
  }
  pb.throw_if_any();
  r.fs_hz = g.fs;
  r.t0_s = g.t0;
  rep.max_time_offset = g.max_offset;
  const Index n = g.k.back() + 1;
  rep.gap_samples = n - static_cast<Index>(n_rows);
  r.data = Matrix::Constant(n, static_cast<Index>(r.channels.size()), std::nan(""));
  std::vector<int> row_line(static_cast<std::size_t>(n), 0);  // the file's line of each sample (a gap's: the row after it)
  for (std::size_t i = 0; i < n_rows; ++i)
    for (Index k = i == 0 ? 0 : g.k[i - 1] + 1; k <= g.k[i]; ++k) row_line[static_cast<std::size_t>(k)] = t.lines[i];
  for (std::size_t i = 0; i < n_rows; ++i) {
    Index col = 0;
    for (std::size_t c = 0; c < n_cols; ++c)
      if (c != t.time_col && c != skip) {
        r.data(g.k[i], col) = rep.channels[static_cast<std::size_t>(col)].factor * t.cells[i * n_cols + c];
        ++col;
      }
  }
  if (rep.gap_samples > 0)
    rep.repairs.push_back("the time column skips " + std::to_string(rep.gap_samples) + " samples of the " + format_number(g.fs, 10) +
                          " Hz grid (gaps): they count as missing in every channel");
  const auto fill_max = static_cast<Index>(std::floor(o.fill_max_s * g.fs + 1e-9));
  repair_missing(r, fill_max, o.split_long_gaps, row_line, rep, pb);
  pb.throw_if_any();
  for (const auto& c : rep.channels)
    if (c.factor != 1.0 || c.channel != c.header)
      rep.plain = false;
  rep.plain = rep.plain && plain && rep.repairs.empty() && rep.notes.empty() &&
              (t.time_col == std::string::npos || t.header[t.time_col] == "t_s") && rep.max_time_offset < 0.01;
  if (report) *report = std::move(rep);
  return r;
}

}  // namespace

namespace {

// A MATLAB variable as read: real numbers column-major (rows × cols), or text.
struct MatVar {
  std::string name;
  std::size_t rows = 0, cols = 0;
  std::vector<double> v;
  std::vector<std::string> text;  // a char array (one entry) or a cell array of char arrays
  bool numeric = false;
};

std::string mat_text(const matvar_t* m) {
  std::string out;
  if (!m || m->class_type != MAT_C_CHAR || !m->data) return out;
  std::size_t n = 1;
  for (int d = 0; d < m->rank; ++d) n *= m->dims[d];
  if (m->data_size == 1 && m->data_type == MAT_T_UTF8) {
    out.assign(static_cast<const char*>(m->data), m->nbytes);
  } else if (m->data_size == 1) {  // Latin-1 to UTF-8
    for (std::size_t k = 0; k < n; ++k) {
      const auto c = static_cast<const unsigned char*>(m->data)[k];
      if (c < 0x80) out += static_cast<char>(c);
      else out += static_cast<char>(0xC0 | (c >> 6)), out += static_cast<char>(0x80 | (c & 0x3F));
    }
  } else if (m->data_size == 2) {  // UTF-16 (the basic plane) to UTF-8
    for (std::size_t k = 0; k < n; ++k) {
      const unsigned c = static_cast<const std::uint16_t*>(m->data)[k];
      if (c < 0x80) {
        out += static_cast<char>(c);
      } else if (c < 0x800) {
        out += static_cast<char>(0xC0 | (c >> 6));
        out += static_cast<char>(0x80 | (c & 0x3F));
      } else {
        out += static_cast<char>(0xE0 | (c >> 12));
        out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
        out += static_cast<char>(0x80 | (c & 0x3F));
      }
    }
  }
  return out;
}

template <class T>
void mat_copy(const void* data, std::size_t n, std::vector<double>& v) {
  const T* p = static_cast<const T*>(data);
  v.assign(n, 0.0);
  for (std::size_t k = 0; k < n; ++k) v[k] = static_cast<double>(p[k]);
}

// Every variable of the file; numeric ones real and two-dimensional, others as text or skipped
// (named in `skipped`).
std::vector<MatVar> read_mat_vars(mat_t* mat, std::vector<std::string>& skipped) {
  std::vector<MatVar> out;
  while (true) {
    std::unique_ptr<matvar_t, void (*)(matvar_t*)> m(Mat_VarReadNext(mat), Mat_VarFree);
    if (!m) break;
    MatVar v;
    v.name = m->name ? m->name : "";
    if (m->rank != 2) {
      skipped.push_back(v.name + " (" + std::to_string(m->rank) + "-dimensional)");
      continue;
    }
    v.rows = m->dims[0];
    v.cols = m->dims[1];
    const std::size_t n = v.rows * v.cols;
    if (m->class_type == MAT_C_CHAR) {
      v.text.push_back(mat_text(m.get()));
    } else if (m->class_type == MAT_C_CELL) {
      for (std::size_t k = 0; k < n; ++k) v.text.push_back(mat_text(Mat_VarGetCell(m.get(), static_cast<int>(k))));
    } else if (m->isComplex || m->isLogical || !m->data || n == 0) {
      skipped.push_back(v.name + (m->isComplex ? " (complex)" : m->isLogical ? " (logical)" : " (empty)"));
      continue;
    } else {
      switch (m->class_type) {
        case MAT_C_DOUBLE: mat_copy<double>(m->data, n, v.v); break;
        case MAT_C_SINGLE: mat_copy<float>(m->data, n, v.v); break;
        case MAT_C_INT8: mat_copy<std::int8_t>(m->data, n, v.v); break;
        case MAT_C_UINT8: mat_copy<std::uint8_t>(m->data, n, v.v); break;
        case MAT_C_INT16: mat_copy<std::int16_t>(m->data, n, v.v); break;
        case MAT_C_UINT16: mat_copy<std::uint16_t>(m->data, n, v.v); break;
        case MAT_C_INT32: mat_copy<std::int32_t>(m->data, n, v.v); break;
        case MAT_C_UINT32: mat_copy<std::uint32_t>(m->data, n, v.v); break;
        case MAT_C_INT64: mat_copy<std::int64_t>(m->data, n, v.v); break;
        case MAT_C_UINT64: mat_copy<std::uint64_t>(m->data, n, v.v); break;
        default: skipped.push_back(v.name + " (a struct, object or sparse matrix: save its fields as variables)"); continue;
      }
      v.numeric = true;
    }
    out.push_back(std::move(v));
  }
  return out;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// The text variable named one of `names` (or VAR_names for a matrix VAR) with k entries.
const std::vector<std::string>* mat_labels(const std::vector<MatVar>& vars, const std::string& var, std::initializer_list<const char*> names,
                                           std::size_t k) {
  for (const auto& v : vars) {
    if (v.text.size() != k || v.numeric) continue;
    const std::string n = lower(v.name);
    for (const char* x : names)
      if (n == x || n == lower(var) + "_" + x) return &v.text;
  }
  return nullptr;
}

void silent_matio(int, char*) {}

}  // namespace

Record read_record_mat(const std::string& path, const ReadOptions& o, ImportReport* report) {
  if (!std::ifstream(path)) throw InputError("cannot open record " + path);
  Mat_LogInitFunc("viaduct", silent_matio);
  std::unique_ptr<mat_t, int (*)(mat_t*)> mat(Mat_Open(path.c_str(), MAT_ACC_RDONLY), Mat_Close);
  if (!mat) throw InputError(path + ": not a MATLAB .mat file (v4, v5 or v7.3) that can be read");
  const enum mat_ft ver = Mat_GetVersion(mat.get());
  Problems pb{path, {}, 0};
  std::vector<std::string> skipped;
  const std::vector<MatVar> vars = read_mat_vars(mat.get(), skipped);
  // The record's length: the time vector's, else the most common length of the numeric
  // variables (samples along a matrix's longer side; the longer of equally common lengths).
  std::size_t n = 0;
  std::map<std::size_t, int> count;
  for (const auto& v : vars)
    if (v.numeric && v.rows * v.cols >= 2) {
      const std::size_t len = std::max(v.rows, v.cols);
      ++count[len];
      if (std::min(v.rows, v.cols) == 1 && is_time_name(lower(v.name)) && n == 0) n = len;
    }
  if (n == 0)
    for (const auto& [len, c] : count)
      if (c >= count[n]) n = len;
  RawTable t;
  std::vector<const std::vector<double>*> data;
  std::vector<std::size_t> stride, offset;
  for (const auto& v : vars) {
    if (!v.numeric) continue;
    const std::string lname = lower(v.name);
    if (v.rows * v.cols == 1) {
      static const char* rates[] = {"fs", "fs_hz", "sample_rate", "samplerate", "sampling_rate", "sampling_rate_hz", "rate_hz", "sr", "srate"};
      static const char* steps[] = {"dt", "dt_s", "delta_t", "ts", "sampling_interval", "sample_interval"};
      if (std::any_of(std::begin(rates), std::end(rates), [&](const char* r) { return lname == r; }))
        t.declared_fs = v.v[0], t.declared_where = "variable '" + v.name + "'";
      else if (std::any_of(std::begin(steps), std::end(steps), [&](const char* r) { return lname == r; }) && v.v[0] > 0)
        t.declared_fs = 1.0 / v.v[0], t.declared_where = "variable '" + v.name + "' = " + format_number(v.v[0], 10) + " s";
      else
        skipped.push_back(v.name + " (a scalar)");
      continue;
    }
    const bool column_major_samples = v.rows >= v.cols;  // samples down the rows (N×k) or along a row vector
    const std::size_t len = column_major_samples ? v.rows : v.cols, k = column_major_samples ? v.cols : v.rows;
    if (len != n) {
      skipped.push_back(v.name + " (" + std::to_string(v.rows) + "×" + std::to_string(v.cols) + ", not " + std::to_string(n) + " samples)");
      continue;
    }
    if (k == 1) {
      t.header.push_back(v.name);
      data.push_back(&v.v), stride.push_back(1), offset.push_back(0);
      continue;
    }
    const auto* names = mat_labels(vars, v.name, {"names", "channels", "channel_names", "labels"}, k);
    const auto* units = mat_labels(vars, v.name, {"units", "unit"}, k);
    for (std::size_t j = 0; j < k; ++j) {
      std::string h = names ? (*names)[j] : v.name + "_" + std::to_string(j + 1);
      if (units && !(*units)[j].empty()) h += " [" + (*units)[j] + "]";
      t.header.push_back(h);
      data.push_back(&v.v);
      // element (sample i, channel j): column-major N×k at j·N + i, k×N at i·k + j
      stride.push_back(column_major_samples ? 1 : k), offset.push_back(column_major_samples ? j * n : j);
    }
  }
  if (t.header.empty()) {
    pb.add(0, "no numeric variable of 2 samples or more (a record's channels: vectors, or a matrix with a sample per row)");
    pb.throw_if_any();
  }
  t.cells.resize(n * t.header.size());
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t c = 0; c < t.header.size(); ++c) t.cells[i * t.header.size() + c] = (*data[c])[offset[c] + i * stride[c]];
    t.lines.push_back(static_cast<int>(i + 1));
  }
  t.time_col = find_time_column(t.header, o, pb, 0);
  std::string layout = std::string("MATLAB ") + (ver == MAT_FT_MAT73 ? "v7.3" : ver == MAT_FT_MAT4 ? "v4" : "v5") + " file, " +
                       std::to_string(n) + " samples in " + std::to_string(t.header.size()) + (t.header.size() == 1 ? " column" : " columns") +
                       " (errors name the sample's row)";
  if (!skipped.empty()) {
    layout += "; not read:";
    for (std::size_t k = 0; k < skipped.size(); ++k) layout += (k ? ", " : " ") + skipped[k];
  }
  return finish_table(t, o, pb, report, layout, false);
}

std::vector<std::string> describe(const ImportReport& rep) {
  std::vector<std::string> out;
  out.push_back("layout: " + rep.layout);
  out.push_back("time: " + rep.time + (rep.max_time_offset > 0.01 ? "; stamps within " + format_number(rep.max_time_offset, 2) +
                                                                        " samples of the uniform grid (rounding)" : ""));
  for (const auto& c : rep.channels) {
    if (c.channel.empty()) continue;
    std::string line = "'" + c.header + "' -> " + c.channel;
    if (c.factor != 1.0) line += " (x " + format_number(c.factor, 10) + ")";
    if (c.factor != 1.0 || c.channel != c.header) out.push_back(line);
  }
  for (const auto& n : rep.notes) out.push_back(n);
  for (const auto& n : rep.repairs) out.push_back(n);
  return out;
}

}  // namespace viaduct::io

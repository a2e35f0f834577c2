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
constexpr double kMinStampedRateHz = 5.0;      // [Hz] below: stamps not in seconds (read_record's note)

std::string lower(std::string_view text) {
  std::string s(text);
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

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

// Days from 1970-01-01 of a civil date (proleptic Gregorian; H. Hinnant's days_from_civil).
long days_from_civil(long y, long m, long d) {
  y -= m <= 2;
  const long era = (y >= 0 ? y : y - 399) / 400;
  const long yoe = y - era * 400;
  const long doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
  const long doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + doe - 719468;
}

bool whole_number(std::string_view s, long& v) {
  if (s.empty() || s.size() > 4) return false;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

// A date "YYYY-MM-DD", "YYYY/MM/DD" or "DD.MM.YYYY" as seconds from 1970-01-01; false for others.
bool parse_date(std::string_view c, double& seconds) {
  long y = 0, m = 0, d = 0;
  if (c.size() == 10 && (c[4] == '-' || c[4] == '/') && c[7] == c[4]) {
    if (!whole_number(c.substr(0, 4), y) || !whole_number(c.substr(5, 2), m) || !whole_number(c.substr(8, 2), d)) return false;
  } else if (c.size() == 10 && c[2] == '.' && c[5] == '.') {
    if (!whole_number(c.substr(6, 4), y) || !whole_number(c.substr(3, 2), m) || !whole_number(c.substr(0, 2), d)) return false;
  } else {
    return false;
  }
  if (m < 1 || m > 12 || d < 1 || d > 31) return false;
  seconds = 86400.0 * static_cast<double>(days_from_civil(y, m, d));
  return true;
}

// "hh:mm:ss[.f…]" (',' as the decimal mark too) after an optional date and 'T' or a space, and an
// optional zone ("Z", "+01:00", "-0500"): seconds of the day, or from 1970-01-01 (UTC) with a date.
bool parse_clock(std::string_view c, double& v, double* day_out = nullptr) {
  double day = 0;
  const auto sp = c.find_first_of(" T");
  if (sp != std::string_view::npos) {
    // A date in another order ("05/14/2026": month or day first?) is not guessed: the clock
    // counts from its own midnight, as before dates were read. Other text is no clock time.
    const std::string_view date = c.substr(0, sp);
    const bool date_like = !date.empty() && std::all_of(date.begin(), date.end(), [](char ch) {
      return std::isdigit(static_cast<unsigned char>(ch)) || ch == '/' || ch == '.' || ch == '-';
    });
    if (!parse_date(date, day) && !date_like) return false;
    c = c.substr(sp + 1);
    while (!c.empty() && c.front() == ' ') c.remove_prefix(1);
  }
  double zone = 0;
  if (!c.empty() && c.back() == 'Z') {
    c.remove_suffix(1);
  } else {
    const auto z = c.find_first_of("+-");
    if (z != std::string_view::npos) {
      std::string_view zs = c.substr(z + 1);
      long zh = 0, zm = 0;
      const auto colon = zs.find(':');
      const bool ok = colon != std::string_view::npos ? whole_number(zs.substr(0, colon), zh) && whole_number(zs.substr(colon + 1), zm)
                      : zs.size() == 4                 ? whole_number(zs.substr(0, 2), zh) && whole_number(zs.substr(2, 2), zm)
                                                       : whole_number(zs, zh);
      if (!ok) return false;
      zone = (c[z] == '-' ? -1.0 : 1.0) * (3600.0 * static_cast<double>(zh) + 60.0 * static_cast<double>(zm));
      c = c.substr(0, z);
    }
  }
  const auto c1 = c.find(':');
  if (c1 == std::string_view::npos) return false;
  const auto c2 = c.find(':', c1 + 1);
  if (c2 == std::string_view::npos) return false;
  long h = 0, m = 0;
  double s = 0;
  if (!whole_number(c.substr(0, c1), h) || !whole_number(c.substr(c1 + 1, c2 - c1 - 1), m)) return false;
  char buf[40];
  std::string_view sec = c.substr(c2 + 1);
  if (sec.empty() || sec.size() >= sizeof buf) return false;
  std::copy(sec.begin(), sec.end(), buf);
  std::replace(buf, buf + sec.size(), ',', '.');
  const auto d = std::from_chars(buf, buf + sec.size(), s);
  if (d.ec != std::errc() || d.ptr != buf + sec.size() || h > 24 || m > 59 || s >= 61) return false;
  v = 3600.0 * static_cast<double>(h) + 60.0 * static_cast<double>(m) + s - zone;
  if (day_out) *day_out = day;  // kept apart: 1.7e9 s of dates would round the clock's fraction
  else v += day;
  return true;
}

// A cell as a number: decimal comma allowed when ',' is not the separator; a clock time, with or
// without a date (parse_clock), or a date alone, when `clock` is set.
Cell parse_cell(std::string_view c, bool decimal_comma, bool clock, double& v, double* day = nullptr) {
  if (is_missing_marker(c)) return Cell::missing;
  char buf[64];
  const std::string_view raw = c;
  if (decimal_comma && c.find(',') != std::string_view::npos && c.size() < sizeof buf) {
    std::copy(c.begin(), c.end(), buf);
    std::replace(buf, buf + c.size(), ',', '.');
    c = std::string_view(buf, c.size());
  }
  if (c.front() == '+') c.remove_prefix(1);
  const auto res = std::from_chars(c.data(), c.data() + c.size(), v);
  if (res.ec == std::errc() && res.ptr == c.data() + c.size()) return std::isfinite(v) ? Cell::number : Cell::missing;
  if (!clock) return Cell::bad;
  if (raw.find(':') != std::string_view::npos) return parse_clock(raw, v, day) ? Cell::number : Cell::bad;
  if (!parse_date(raw, v)) return Cell::bad;
  if (day) *day = v, v = 0;
  return Cell::number;
}

// A date, a clock time or both ("03.12.2026 14:22:05.0008", "2026-12-03T14:22:05Z"): the cells a
// time column holds when it is not in seconds.
bool looks_like_time(std::string_view c) {
  double v = 0;
  return !c.empty() && (c.find(':') != std::string_view::npos ? parse_clock(c, v) : parse_date(c, v));
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
  const std::string l = lower(base);
  static const char* names[] = {"t", "time", "zeit", "timestamp", "time_stamp", "tiempo", "temps", "date/time", "datetime", "date_time",
                                "date time", "datum/zeit", "datum_zeit", "datum zeit", "x_value", "abs time", "absolute time", "uhrzeit"};
  if (std::any_of(std::begin(names), std::end(names), [&](const char* n) { return l == n; })) return true;
  // catman's "Time  1 - default sample rate", "Zeit  1 - Standardmessrate"
  return l.rfind("time ", 0) == 0 || l.rfind("zeit ", 0) == 0;
}

// A column of dates alone ("Date", "Datum"): joined to the time column's clock times.
bool is_date_name(const std::string& base) {
  const std::string l = lower(base);
  return l == "date" || l == "datum" || l == "fecha";
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
    const Cell k = parse_cell(c, sep != ',', true, v);
    if (k == Cell::bad) return false;
    any = any || k == Cell::number;
  }
  return any;
}

// "Sample rate: 1651.2 Hz", "Sampling frequency = 1651.2", "fs;1651,2", "# sampling_rate_hz = F":
// a preamble or comment line that declares the rate. 0 when the line does not.
double rate_in_line(const std::string& line) {
  const std::string l = lower(line);
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
  std::size_t date_col = std::string::npos;  // dates alone, joined to the time column's clock times
  bool clock_time = false;                   // the time column holds clock times (and dates), in seconds already
  std::optional<double> day0;                // [s from 1970] the first stamp's date: dates count from it
  std::set<std::size_t> ignored;             // record numbers (unit RN) and the like: not channels
  std::vector<std::string> layout_notes;     // what the header's reading assumed
};

std::size_t find_time_column(const std::vector<std::string>& header, const ReadOptions& o, Problems& pb, int header_line);

// A line of units under a line of names ("Time;Acc1;Strain1" then "s;g;µε"): the two make one
// header ("Acc1 [g]"). Campbell's TS (timestamp) and RN (record number) count as units.
bool is_unit_line(const std::vector<std::string_view>& cells) {
  bool any = false;
  for (const auto& c : cells) {
    const std::string u = normalise_unit(std::string(c));
    if (!c.empty() && !parse_unit(std::string(c)) && u != "s" && u != "ms" && u != "[s]" && u != "ts" && u != "rn") return false;
    any = any || !c.empty();
  }
  return any;
}

// A line of a logger's processing codes under the units (Campbell TOA5: "", "", "Smp", "Avg"):
// every cell empty or a code, one at least a code.
bool is_processing_line(const std::vector<std::string_view>& cells) {
  static const char* codes[] = {"smp", "avg", "max", "min", "tot", "std", "wvc", "mom", "med", "cov", "hst", "tmx", "tmn"};
  bool any = false;
  for (const auto& c : cells) {
    if (c.empty()) continue;
    const std::string l = lower(c);
    if (std::none_of(std::begin(codes), std::end(codes), [&](const char* k) { return l == k; })) return false;
    any = true;
  }
  return any;
}

// A preamble line that gives the channels' units: "Y_Unit_Label" (NI LVM), "Unit", "Units",
// "Einheit" followed by one unit per column after the time column.
std::vector<std::string_view> preamble_units(const std::vector<std::string>& preamble, char sep) {
  for (auto it = preamble.rbegin(); it != preamble.rend(); ++it) {
    auto cells = split_view(*it, sep);
    if (cells.size() < 2) continue;
    std::string k = lower(cells.front());
    if (!k.empty() && k.back() == ':') k.pop_back();
    if (k == "y_unit_label" || k == "unit" || k == "units" || k == "einheit" || k == "einheiten") {
      cells.erase(cells.begin());
      return cells;
    }
  }
  return {};
}

void take_header(RawTable& t, const std::string& text, int line, const std::string& first_row, const ReadOptions& o, Problems& pb) {
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
  const auto row = split_view(first_row, t.sep);
  if (t.time_col == std::string::npos && o.time_column.empty()) {
    // No column named like time: the first whose cells are clock times or dates (a logger's
    // "Date/Time" column, "03.12.2026 14:22:05.0008").
    for (std::size_t c = 0; c < row.size() && c < t.header.size(); ++c)
      if (row[c].find(':') != std::string_view::npos && looks_like_time(row[c])) {
        t.time_col = c;
        t.layout_notes.push_back("column '" + t.header[c] + "' holds clock times: it is the time column");
        break;
      }
  }
  // Dates in a column of their own, the clock in the time column ("Date;Time;..." exports).
  for (std::size_t c = 0; c < t.header.size() && t.time_col != std::string::npos; ++c)
    if (c != t.time_col && c < row.size() && is_date_name(split_header(t.header[c]).base) && looks_like_time(row[c])) {
      t.date_col = c;
      t.layout_notes.push_back("column '" + t.header[c] + "' holds the dates of the time column's clock times");
    }
  // Units from a preamble line (NI LVM's Y_Unit_Label): one per column after the time column.
  const auto units = preamble_units(t.preamble, t.sep);
  if (!units.empty() && t.time_col == 0) {
    for (std::size_t k = 0; k < units.size() && k + 1 < t.header.size(); ++k)
      if (!units[k].empty() && split_header(t.header[k + 1]).unit_text.empty()) t.header[k + 1] += " [" + std::string(units[k]) + "]";
    t.layout_notes.push_back("channel units from a preamble line");
  }
  for (std::size_t c = 0; c < t.header.size(); ++c) {
    const HeaderCell h = split_header(t.header[c]);
    if (c != t.time_col && normalise_unit(h.unit_text) == "rn") {
      t.ignored.insert(c);
      t.layout_notes.push_back("column '" + t.header[c] + "' numbers the records: not a channel");
    }
  }
}

// A line as its cells see it: the line end and surrounding spaces gone, tabs kept (a tab at
// the end is an empty last cell: NI LVM's Comment column).
std::string row_text(const std::string& line) {
  const auto a = line.find_first_not_of(" \r\n");
  if (a == std::string::npos) return "";
  return line.substr(a, line.find_last_not_of(" \r\n") - a + 1);
}

struct TextLine {
  int line = 0;
  std::string text;
  bool unterminated = false;  // the file's last line, without a newline
};

// The header: the line above the first run of rows (kRun, or every row left when fewer) with the
// header's number of cells, each a number, a clock time or a missing-value marker. Lines of
// processing codes (Campbell's "Smp") between units and rows are passed over; a units line right
// under the names joins them (take_header). Index into `lines`, or npos.
constexpr std::size_t kRun = 10;
std::size_t find_header(const std::vector<TextLine>& lines, const ReadOptions& o, Problems& pb) {
  if (o.header_line > 0) {
    for (std::size_t i = 0; i < lines.size(); ++i)
      if (lines[i].line == o.header_line) return i;
    pb.add(0, "--header-line " + std::to_string(o.header_line) + " is not a line of text of the file (after --skip-lines, blank and '#' lines)");
    return std::string::npos;
  }
  // A header names: no cell of it is a number or a clock time.
  auto names_only = [](const std::string& text) {
    const char sep = separator_of(text);
    for (const auto& c : split_view(text, sep)) {
      double v = 0;
      if (parse_cell(c, sep != ',', true, v) == Cell::number) return false;
    }
    return true;
  };
  // The first names line with a whole run of rows under it; else (a bad cell among the first
  // rows, reported as such) the first with a row under it.
  for (const std::size_t want : {kRun, std::size_t{1}})
    for (std::size_t i = 0; i + 1 < lines.size(); ++i) {
      if (!names_only(lines[i].text)) continue;
      const char sep = separator_of(lines[i].text);
      const std::size_t n = split_view(lines[i].text, sep).size();
      const std::size_t need = std::min(want, lines.size() - i - 1);
      std::size_t run = 0;
      while (run < need && is_data_line(lines[i + 1 + run].text, sep, n)) ++run;
      if (run == need) return i;
    }
  return std::string::npos;
}

RawTable read_table(std::ifstream& in, const ReadOptions& o, Problems& pb) {
  RawTable t;
  std::string line;
  int ln = 0;
  // The lines up to the header and a few hundred rows beyond it, for finding the header.
  constexpr std::size_t kLook = 2000;
  std::vector<TextLine> head;
  bool more = true;
  while (head.size() < kLook && (more = static_cast<bool>(std::getline(in, line)))) {
    if (++ln == 1) detail::drop_bom(line);
    if (ln <= o.skip_lines) continue;
    const std::string tr = detail::trim(line);
    if (tr.empty()) continue;
    const double fs = rate_in_line(tr);
    if (fs != 0.0 && t.declared_fs == 0.0) {
      if (fs < 0) pb.add(ln, "the sampling rate declared here is not a number > 0");
      t.declared_fs = std::max(fs, 0.0), t.declared_line = ln;
    }
    if (tr[0] == '#') continue;
    head.push_back({ln, row_text(line), in.eof()});
  }
  std::size_t h = find_header(head, o, pb);
  if (h == std::string::npos) {
    if (pb.count == 0) {
      if (head.empty()) pb.add(0, "no header line (and no data)");
      else pb.add(head.front().line, "no header with rows of numbers under it: a header needs at least " + std::to_string(kRun) +
                                         " rows of as many numbers (or clock times) below it, ',', ';' or tab separated; "
                                         "--header-line N names the header's line, --skip-lines N skips a preamble");
    }
    return t;
  }
  const std::size_t first_row = h + 1;
  while (h > 0 && is_processing_line(split_view(head[h].text, separator_of(head[h].text)))) {
    t.layout_notes.push_back("line " + std::to_string(head[h].line) + " lists processing codes: skipped");
    --h;
  }
  for (std::size_t i = 0; i < h; ++i) t.preamble.push_back(head[i].text);
  t.sep = separator_of(head[h].text);
  take_header(t, head[h].text, head[h].line, first_row < head.size() ? head[first_row].text : std::string(), o, pb);
  const std::size_t n = t.header.size();
  std::vector<bool> hinted(n, false);
  // A data row.
  auto take_row = [&](const std::string& tr, int at, bool last_unterminated) {
    auto cells = split_view(tr, t.sep);
    // A separator at the end of the rows but not of the header, or the other way round.
    if (cells.size() == n + 1 && cells.back().empty()) cells.pop_back();
    else if (cells.size() + 1 == n && t.header.back().empty()) cells.emplace_back();
    const std::string cut = last_unterminated ? " (the file ends inside this line, without a newline: cut short?)" : "";
    if (cells.size() != n) {
      pb.add(at, "expected " + std::to_string(n) + " columns as in the header (line " + std::to_string(t.header_line) + "), got " +
                     std::to_string(cells.size()) + cut);
      return;
    }
    for (std::size_t c = 0; c < n; ++c) {
      double v = 0, day = 0;
      const bool dated = c == t.time_col || c == t.date_col;
      const Cell k = parse_cell(cells[c], t.sep != ',', dated, v, dated ? &day : nullptr);
      if (k == Cell::number && day != 0.0) {  // dates count from the first one's
        if (!t.day0) t.day0 = day;
        v += day - *t.day0;
      }
      if (k == Cell::bad) {
        std::string hint;
        if (!hinted[c] && looks_like_time(cells[c]))
          hint = ": it reads as a date or clock time; if this is the time, give --time-column '" + t.header[c] + "'";
        else if (!hinted[c])
          hint = " (if line " + std::to_string(t.header_line) + " is not the header, --header-line N names it)";
        hinted[c] = true;
        pb.add(at, "column '" + t.header[c] + "': '" + std::string(cells[c].substr(0, 30)) + "' is not a number" + hint + cut);
        v = std::nan("");
      } else if (k == Cell::missing) {
        v = std::nan("");
      } else if (c == t.time_col && cells[c].find(':') != std::string_view::npos) {
        t.clock_time = true;
      } else if (t.sep != ',' && cells[c].find(',') != std::string_view::npos) {
        t.decimal_comma = true;
      }
      t.cells.push_back(v);
    }
    t.lines.push_back(at);
  };
  for (std::size_t i = first_row; i < head.size(); ++i) take_row(head[i].text, head[i].line, head[i].unterminated);
  while (more && std::getline(in, line)) {
    ++ln;
    const bool last_unterminated = in.eof();
    const std::string tr = detail::trim(line);
    if (tr.empty() || tr[0] == '#') continue;
    take_row(row_text(line), ln, last_unterminated);
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
// linearly; longer ones (and those at either end) stay missing in their own channel (split) or
// refuse the file.
void repair_missing(Record& r, Index fill_max, bool split, const std::vector<int>& row_line, ImportReport& rep, Problems& pb) {
  const Index n = r.data.rows();
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
                    " s) or at an end: " + w + "; --long-gaps split leaves them missing in their own channel");
    return;
  }
  // A long run marks its own channel only: it stays missing there, and a command that uses the
  // channel takes the longest piece where its channels have values (valid_span).
  const std::size_t shown = std::min<std::size_t>(long_runs.size(), 8);
  for (std::size_t k = 0; k < shown; ++k)
    rep.repairs.push_back("missing samples too long to interpolate or at an end (" + long_runs[k].second + ", line " +
                          std::to_string(long_runs[k].first) + "): that channel has no value there; the other channels keep theirs, "
                          "and a command using it takes the longest piece where its channels have values (--long-gaps refuse to refuse instead)");
  if (long_runs.size() > shown)
    rep.repairs.push_back("... and " + std::to_string(long_runs.size() - shown) + " more runs of missing samples (viaduct inspect lists them per channel)");
}

// A clipped stretch (the channel's runs at its max or min, summarise_channel's rule) holds no
// measurement: its samples become missing in that channel only, as a long NaN run does.
void mark_clipped(Record& r, ImportReport& rep) {
  for (Index c = 0; c < r.data.cols(); ++c) {
    // Responses and forces only: a trigger or status channel (V, 1) sits at its limits by design.
    const std::string& u = r.units[static_cast<std::size_t>(c)];
    if (u != "mps2" && u != "mps" && u != "m" && u != "ue" && u != "N" && u != "Nm" && u != "Pa") continue;
    auto col = r.data.col(c);
    const ChannelSummary s = summarise_channel(col);
    if (!s.clipped) continue;
    Index marked = 0;
    for (Index i = 0; i < col.size();) {
      Index j = i + 1;
      while (j < col.size() && col[j] == col[i]) ++j;
      if ((col[i] == s.max || col[i] == s.min) && j - i >= 3) {
        for (Index m = i; m < j; ++m) col[m] = std::nan("");
        marked += j - i;
      }
      i = j;
    }
    rep.channels[static_cast<std::size_t>(c)].missing += marked;
    rep.channels[static_cast<std::size_t>(c)].clipped = marked;
    rep.repairs.push_back(r.channels[static_cast<std::size_t>(c)] + " is clipped (" + std::to_string(marked) + " samples in runs at its max " +
                          format_number(s.max, 6) + " or min " + format_number(s.min, 6) +
                          "): those samples count as missing in that channel; a command using it takes the longest piece without them");
  }
}

// The channels of the header (all columns but time): names, units and factors to viaduct's units.
void take_channels(const RawTable& t, const ReadOptions& o, const std::set<std::size_t>& skip, Record& r, ImportReport& rep, Problems& pb) {
  std::set<std::string> seen;
  std::vector<bool> used(o.units.size(), false);
  for (std::size_t c = 0; c < t.header.size(); ++c) {
    if (c == t.time_col || skip.count(c) > 0) continue;
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
  std::set<std::size_t> skip = t.ignored;
  if (t.date_col != std::string::npos) skip.insert(t.date_col);
  for (const auto& n : t.layout_notes) rep.notes.push_back(n);
  auto all_missing = [&](std::size_t c) {
    for (std::size_t i = 0; i < n_rows; ++i)
      if (!std::isnan(t.cells[i * n_cols + c])) return false;
    return true;
  };
  if (n_cols > 1 && t.header.back().empty() && all_missing(n_cols - 1))
    skip.insert(n_cols - 1), rep.notes.push_back("every line ends with a separator: the empty last column is not a channel");
  for (std::size_t c = 0; c < n_cols; ++c) {  // a comment column (NI LVM's "Comment") left empty
    const std::string l = lower(split_header(t.header[c]).base);
    if ((l == "comment" || l == "comments" || l == "kommentar" || l == "note" || l == "notes") && c != t.time_col && all_missing(c))
      skip.insert(c), rep.notes.push_back("column '" + t.header[c] + "' holds no value: not a channel");
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
    std::vector<double> times(n_rows);
    bool all_stamped = true;
    // Spreadsheet serial days (a "Date/Time" column of plain numbers such as 46359.598): seconds
    // from the midnight of the first day.
    const std::string tl = lower(split_header(t.header[t.time_col]).base);
    const double first = t.cells[t.time_col];
    const bool serial_days = !t.clock_time && (tl.find("date") != std::string::npos || tl.find("datum") != std::string::npos) &&
                             split_header(t.header[t.time_col]).unit_text.empty() && first > 1.0 && first < 2958466.0;
    std::string note;
    const double f = t.clock_time || serial_days ? 1.0 : time_factor(t.header[t.time_col], note);
    if (!note.empty()) rep.notes.push_back(note);
    const double first_day = serial_days ? std::floor(first) : 0.0;
    if (serial_days)
      rep.notes.push_back("time column '" + t.header[t.time_col] + "' holds spreadsheet serial days (from 1899-12-30): seconds from the "
                          "midnight before the first");
    if (t.day0) rep.notes.push_back("time stamps with dates: seconds from the midnight (UTC) of the first one's day");
    for (std::size_t i = 0; i < n_rows; ++i) {
      times[i] = serial_days ? 86400.0 * (t.cells[i * n_cols + t.time_col] - first_day) : f * t.cells[i * n_cols + t.time_col];
      if (t.date_col != std::string::npos) times[i] += t.cells[i * n_cols + t.date_col];
      if (std::isnan(times[i])) pb.add(t.lines[i], "no time stamp in column '" + t.header[t.time_col] + "'"), all_stamped = false;
    }
    // Dates with the clock (from 1970-01-01): counted from the midnight (UTC) before the first stamp.
    if (all_stamped && std::abs(times.front()) >= 1e8) {
      const double midnight = 86400.0 * std::floor(times.front() / 86400.0);
      for (auto& x : times) x -= midnight;
      rep.notes.push_back("time stamps with dates: seconds from the midnight (UTC) before the first, " +
                          format_number(times.front(), 10) + " s");
    }
    if (all_stamped) g = time_grid(times, t.lines, fs, declared_by, pb);
    rep.time = "column '" + t.header[t.time_col] + "'" + (fs > 0 ? ", rate " + format_number(fs) + " Hz declared (" + declared_by + ")"
                                                                 : ", rate " + format_number(g.fs, 10) + " Hz from the stamps");
    // Accelerations or velocities stamped a few hundred milliseconds or more apart are not seconds
    // (1000 times too slow a rate: a record at 500 Hz stamped in ms reads 0.5 Hz); a slow log of
    // deflections, strains or temperatures may be.
    const bool vibration = std::any_of(r.units.begin(), r.units.end(), [](const std::string& u) { return u == "mps2" || u == "mps"; });
    if (!(fs > 0) && all_stamped && vibration && g.fs > 0.0 && g.fs < kMinStampedRateHz && f == 1.0)
      rep.notes.push_back("the time stamps of column '" + t.header[t.time_col] + "' are read as seconds and give " +
                          format_number(g.fs, 4) + " Hz, below the " + format_number(kMinStampedRateHz) +
                          " Hz of any record of a bridge's vibration: are they milliseconds? name the column t_ms (or give --rate-hz)");
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
      if (c != t.time_col && skip.count(c) == 0) {
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
  mark_clipped(r, rep);
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

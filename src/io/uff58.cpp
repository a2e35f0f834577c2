// Universal File Format, dataset 58 (ASCII): records for measured time histories.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "viaduct/core/error.hpp"
#include "viaduct/io/record.hpp"
#include "csv_cells.hpp"

namespace viaduct::io {

namespace {

std::string trim_field(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  return s.substr(a, s.find_last_not_of(" \t\r") - a + 1);
}

// Fixed-width field [pos, pos + w) of a line as a number (Fortran E or D exponents allowed).
bool field(const std::string& line, std::size_t pos, std::size_t w, double& out) {
  if (pos >= line.size()) return false;
  std::string f = trim_field(line.substr(pos, w));
  if (f.empty()) return false;
  std::replace(f.begin(), f.end(), 'D', 'E');
  std::replace(f.begin(), f.end(), 'd', 'e');
  try {
    std::size_t used = 0;
    out = std::stod(f, &used);
    return used == f.size() && std::isfinite(out);
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace

Record read_uff58(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError("cannot open record " + path);
  auto err = [&](int line, const std::string& msg) { return InputError(SourceLocation{path, line, ""}, msg); };
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) {
    if (!l.empty() && l.back() == '\r') l.pop_back();
    if (lines.empty()) detail::drop_bom(l);
    lines.push_back(l);
  }
  Record r;
  std::vector<std::vector<double>> cols;
  double fs = 0, t0 = 0;
  std::size_t i = 0;
  while (i < lines.size()) {
    if (trim_field(lines[i]) != "-1") {
      // Between datasets only blank lines: anything else means a "-1" went missing and a
      // dataset would be lost without a word.
      if (!trim_field(lines[i]).empty())
        throw err(static_cast<int>(i + 1), "'" + trim_field(lines[i]).substr(0, 40) +
                                               "' outside any dataset: a -1 delimiter is missing before or after it");
      ++i;
      continue;
    }
    // dataset start: "-1", then the type line
    if (i + 1 >= lines.size()) break;
    const std::string type = trim_field(lines[i + 1]);
    const int type_line = static_cast<int>(i + 2);
    std::size_t end = i + 2;
    while (end < lines.size() && trim_field(lines[end]) != "-1") ++end;
    if (type.rfind("58", 0) != 0) {  // other dataset: skip it
      i = end + 1;
      continue;
    }
    if (type.size() > 2 && (type.find('b') != std::string::npos || type.find('B') != std::string::npos))
      throw err(type_line, "binary dataset 58b is not supported yet: export ASCII");
    if (end - (i + 2) < 11) throw err(type_line, "dataset 58 shorter than its 11 header records");
    const std::size_t h = i + 2;  // first ID line
    const std::string name_raw = trim_field(lines[h]);
    const std::string& rec7 = lines[h + 6];
    double ord_type = 0, n_pts = 0, spacing = 0, xmin = 0, dx = 0;
    if (!field(rec7, 0, 10, ord_type) || !field(rec7, 10, 10, n_pts) || !field(rec7, 20, 10, spacing) ||
        !field(rec7, 30, 13, xmin) || !field(rec7, 43, 13, dx))
      throw err(static_cast<int>(h + 7), "record 7 must hold data type, number of points, spacing, minimum and increment");
    if (ord_type == 5 || ord_type == 6)
      throw err(static_cast<int>(h + 7), "complex ordinates (an FRF): records hold real time histories");
    if (ord_type != 2 && ord_type != 4) throw err(static_cast<int>(h + 7), "unknown ordinate data type " + std::to_string(ord_type));
    if (spacing != 1) throw err(static_cast<int>(h + 7), "uneven abscissa: resample the record to a uniform rate first");
    if (!(dx > 0) || !(n_pts >= 2)) throw err(static_cast<int>(h + 7), "need at least 2 points and a positive increment");
    // Ordinate record 9: 4 integers (25 columns), axis label and unit label of 21 columns each.
    const std::string& rec9 = lines[h + 8];
    const std::string units_label = rec9.size() > 46 ? trim_field(rec9.substr(46, 21)) : "";
    const auto conv = parse_unit(units_label);
    if (!conv)
      throw err(static_cast<int>(h + 9), "ordinate unit '" + units_label + "' is not known (m/s^2, g, m, mm, m/s, N, kN, Pa, V, µε, ...)");
    const std::string& unit = conv->unit;
    const std::size_t w = ord_type == 2 ? 13 : 20;
    std::vector<double> v;
    for (std::size_t k = h + 11; k < end; ++k)
      for (std::size_t pos = 0; pos + 1 < lines[k].size(); pos += w) {
        double x = 0;
        if (trim_field(lines[k].substr(pos, w)).empty()) continue;
        if (!field(lines[k], pos, w, x))
          throw err(static_cast<int>(k + 1), "not a finite number in columns " + std::to_string(pos + 1) + "-" + std::to_string(pos + w));
        v.push_back(conv->factor * x);
      }
    if (v.size() != static_cast<std::size_t>(n_pts))
      throw err(type_line, "dataset '" + name_raw + "' declares " + std::to_string(static_cast<long>(n_pts)) +
                               " points but holds " + std::to_string(v.size()));
    std::string name;
    for (char c : name_raw) name += (c == ' ' || c == ',' || c == '"') ? '_' : c;
    if (name.empty() || name == "NONE") name = "ch" + std::to_string(cols.size() + 1);
    name += "_" + unit;
    if (std::find(r.channels.begin(), r.channels.end(), name) != r.channels.end())
      throw err(type_line, "channel '" + name + "' appears twice");
    if (cols.empty()) {
      fs = 1.0 / dx;
      t0 = xmin;
    } else if (std::abs(1.0 / dx - fs) > 1e-6 * fs || std::abs(xmin - t0) > 0.5 / fs || v.size() != cols.front().size()) {
      throw err(type_line, "dataset '" + name_raw + "' differs in rate, start or length from the first; resample first");
    }
    r.channels.push_back(name);
    r.units.push_back(unit);
    cols.push_back(std::move(v));
    i = end + 1;
  }
  if (cols.empty()) throw InputError(path + ": no dataset 58 found");
  r.fs_hz = fs;
  r.t0_s = t0;
  r.data.resize(static_cast<Index>(cols.front().size()), static_cast<Index>(cols.size()));
  for (std::size_t c = 0; c < cols.size(); ++c)
    r.data.col(static_cast<Index>(c)) = Eigen::Map<const Vector>(cols[c].data(), static_cast<Index>(cols[c].size()));
  return r;
}

Record read_record(const std::string& path, const ReadOptions& options, ImportReport* report) {
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext == ".uff" || ext == ".unv" || ext == ".UFF" || ext == ".UNV") {
    Record r = read_uff58(path);
    if (report) {
      *report = ImportReport{};
      report->layout = "Universal File, datasets 58";
      report->time = "abscissa of the datasets, " + format_number(r.fs_hz, 10) + " Hz";
    }
    return r;
  }
  return read_record_csv(path, options, report);
}

}  // namespace viaduct::io

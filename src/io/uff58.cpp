// Universal File Format, dataset 58 (ASCII): records for measured time histories.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <functional>
#include <iterator>
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

namespace {

// The file's bytes read line by line, except where a binary block is taken whole.
struct Cursor {
  const std::string& bytes;
  std::size_t pos = 0;
  int line = 0;  // of the last line read
  bool next(std::string& out) {
    if (pos >= bytes.size()) return false;
    const auto e = bytes.find('\n', pos);
    out = bytes.substr(pos, (e == std::string::npos ? bytes.size() : e) - pos);
    if (!out.empty() && out.back() == '\r') out.pop_back();
    pos = e == std::string::npos ? bytes.size() : e + 1;
    ++line;
    return true;
  }
};

// Records 1-11 of a dataset 58: its name, rate, start, point count, ordinate type and unit.
struct Header58 {
  std::string name_raw;
  double ord_type = 0, n_pts = 0, xmin = 0, dx = 0;
  UnitConversion conv;
};

Header58 parse_header58(const std::vector<std::string>& h, int first_line, const std::function<InputError(int, const std::string&)>& err) {
  Header58 d;
  d.name_raw = trim_field(h[0]);
  const std::string& rec7 = h[6];
  double spacing = 0;
  if (!field(rec7, 0, 10, d.ord_type) || !field(rec7, 10, 10, d.n_pts) || !field(rec7, 20, 10, spacing) ||
      !field(rec7, 30, 13, d.xmin) || !field(rec7, 43, 13, d.dx))
    throw err(first_line + 6, "record 7 must hold data type, number of points, spacing, minimum and increment");
  if (d.ord_type == 5 || d.ord_type == 6) throw err(first_line + 6, "complex ordinates (an FRF): records hold real time histories");
  if (d.ord_type != 2 && d.ord_type != 4) throw err(first_line + 6, "unknown ordinate data type " + std::to_string(d.ord_type));
  if (spacing != 1) throw err(first_line + 6, "uneven abscissa: resample the record to a uniform rate first");
  if (!(d.dx > 0) || !(d.n_pts >= 2) || d.n_pts > 1e9) throw err(first_line + 6, "need at least 2 points and a positive increment");
  // Ordinate record 9: 4 integers (25 columns), axis label and unit label of 21 columns each.
  const std::string& rec9 = h[8];
  const std::string units_label = rec9.size() > 46 ? trim_field(rec9.substr(46, 21)) : "";
  const auto conv = parse_unit(units_label);
  if (!conv) throw err(first_line + 8, "ordinate unit '" + units_label + "' is not known (m/s^2, g, m, mm, m/s, N, kN, Pa, V, µε, ...)");
  d.conv = *conv;
  return d;
}

// The type line of a binary dataset: "    58b" then byte order (1 little, 2 big endian),
// floating-point format (2: IEEE 754), ASCII header lines (11) and bytes of data (I6,A1,I6,I6,I12,I12).
struct Binary58 {
  bool big_endian = false;
  std::size_t n_bytes = 0;
};

Binary58 parse_58b(const std::string& type, int line, const std::function<InputError(int, const std::string&)>& err) {
  double order = 0, fp = 0, n_ascii = 0, n_bytes = 0;
  if (!field(type, 7, 6, order) || !field(type, 13, 6, fp) || !field(type, 19, 12, n_ascii) || !field(type, 31, 12, n_bytes))
    throw err(line, "dataset 58b: the type line must give byte order, floating-point format, header lines and bytes (I6,A1,I6,I6,I12,I12)");
  if (order != 1 && order != 2) throw err(line, "dataset 58b: byte order " + format_number(order) + " is neither 1 (little endian) nor 2 (big endian)");
  if (fp != 2) throw err(line, "dataset 58b: floating-point format " + format_number(fp) + " is not IEEE 754 (2); DEC VMS (1) and IBM (3) are not read");
  if (n_ascii != 11) throw err(line, "dataset 58b: " + format_number(n_ascii) + " ASCII header lines; dataset 58 has 11");
  if (!(n_bytes >= 0) || n_bytes > 8e9) throw err(line, "dataset 58b: invalid byte count " + format_number(n_bytes));
  return {order == 2, static_cast<std::size_t>(n_bytes)};
}

// n values of `size` bytes (4: float, 8: double) in the given byte order.
std::vector<double> decode_binary(const char* p, std::size_t n, std::size_t size, bool big_endian) {
  std::vector<double> v(n);
  const uint16_t probe = 1;
  const bool host_little = *reinterpret_cast<const unsigned char*>(&probe) == 1;
  unsigned char b[8];
  for (std::size_t i = 0; i < n; ++i) {
    std::memcpy(b, p + i * size, size);
    if (big_endian == host_little) std::reverse(b, b + size);
    if (size == 4) {
      float f;
      std::memcpy(&f, b, 4);
      v[i] = f;
    } else {
      std::memcpy(&v[i], b, 8);
    }
  }
  return v;
}

}  // namespace

Record read_uff58(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot open record " + path);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::function<InputError(int, const std::string&)> err = [&](int line, const std::string& msg) {
    return InputError(SourceLocation{path, line, ""}, msg);
  };
  Cursor cur{bytes};
  Record r;
  std::vector<std::vector<double>> cols;
  double fs = 0, t0 = 0;
  std::string l;
  while (cur.next(l)) {
    if (cur.line == 1) detail::drop_bom(l);
    if (trim_field(l) != "-1") {
      // Between datasets only blank lines: anything else means a "-1" went missing and a
      // dataset would be lost without a word.
      if (!trim_field(l).empty())
        throw err(cur.line, "'" + trim_field(l).substr(0, 40) + "' outside any dataset: a -1 delimiter is missing before or after it");
      continue;
    }
    std::string type_raw;
    if (!cur.next(type_raw)) break;
    const std::string type = trim_field(type_raw);
    const int type_line = cur.line;
    const bool binary = type.size() > 2 && type.rfind("58", 0) == 0 && (type[2] == 'b' || type[2] == 'B');
    if (type.rfind("58", 0) != 0 || (type.size() > 2 && !binary && type[2] != ' ')) {  // other dataset: skip to its end
      while (cur.next(l) && trim_field(l) != "-1") {
      }
      continue;
    }
    const Binary58 bin = binary ? parse_58b(type_raw, type_line, err) : Binary58{};
    std::vector<std::string> h(11);
    for (auto& x : h)
      if (!cur.next(x) || trim_field(x) == "-1") throw err(type_line, "dataset 58 shorter than its 11 header records");
    const Header58 d = parse_header58(h, type_line + 1, err);
    const auto n = static_cast<std::size_t>(d.n_pts);
    std::vector<double> v;
    if (binary) {
      const std::size_t size = d.ord_type == 2 ? 4 : 8;
      if (bin.n_bytes != n * size)
        throw err(type_line, "dataset 58b '" + d.name_raw + "' declares " + std::to_string(bin.n_bytes) + " bytes; " + std::to_string(n) +
                                 " points of " + std::to_string(size) + " bytes are " + std::to_string(n * size));
      if (cur.pos + bin.n_bytes > bytes.size())
        throw err(type_line, "dataset 58b '" + d.name_raw + "': the file ends " + std::to_string(cur.pos + bin.n_bytes - bytes.size()) +
                                 " bytes before its data does (cut short?)");
      v = decode_binary(bytes.data() + cur.pos, n, size, bin.big_endian);
      cur.pos += bin.n_bytes;
      for (double& x : v) {
        if (!std::isfinite(x)) throw err(type_line, "dataset 58b '" + d.name_raw + "': a value that is not a finite number");
        x *= d.conv.factor;
      }
      // After the data: the rest of its line (a newline), then the closing -1.
      while (cur.next(l) && trim_field(l) != "-1")
        if (!trim_field(l).empty()) throw err(cur.line, "dataset 58b '" + d.name_raw + "': bytes after its data and before -1");
    } else {
      const std::size_t w = d.ord_type == 2 ? 13 : 20;
      while (cur.next(l) && trim_field(l) != "-1")
        for (std::size_t pos = 0; pos + 1 < l.size(); pos += w) {
          double x = 0;
          if (trim_field(l.substr(pos, w)).empty()) continue;
          if (!field(l, pos, w, x))
            throw err(cur.line, "not a finite number in columns " + std::to_string(pos + 1) + "-" + std::to_string(pos + w));
          v.push_back(d.conv.factor * x);
        }
      if (v.size() != n)
        throw err(type_line, "dataset '" + d.name_raw + "' declares " + std::to_string(n) + " points but holds " + std::to_string(v.size()));
    }
    std::string name;
    for (char c : d.name_raw) name += (c == ' ' || c == ',' || c == '"') ? '_' : c;
    if (name.empty() || name == "NONE") name = "ch" + std::to_string(cols.size() + 1);
    name += "_" + d.conv.unit;
    if (std::find(r.channels.begin(), r.channels.end(), name) != r.channels.end()) throw err(type_line, "channel '" + name + "' appears twice");
    if (cols.empty()) {
      fs = 1.0 / d.dx;
      t0 = d.xmin;
    } else if (std::abs(1.0 / d.dx - fs) > 1e-6 * fs || std::abs(d.xmin - t0) > 0.5 / fs || v.size() != cols.front().size()) {
      throw err(type_line, "dataset '" + d.name_raw + "' differs in rate, start or length from the first; resample first");
    }
    r.channels.push_back(name);
    r.units.push_back(d.conv.unit);
    cols.push_back(std::move(v));
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
  if (ext == ".mat" || ext == ".MAT") return read_record_mat(path, options, report);
  return read_record_csv(path, options, report);
}

}  // namespace viaduct::io

#include "viaduct/io/profile.hpp"

#include <cmath>
#include <cstdlib>

#include "csv_cells.hpp"
#include "viaduct/core/error.hpp"
#include "viaduct/io/record.hpp"

namespace viaduct::io {

namespace {

// "x_m" -> m, "level [mm]" -> mm, "z (cm)" -> cm: the factor to metres; 0 when the unit is not a length.
double length_factor(const std::string& header, std::string& unit) {
  std::string u;
  const auto open = header.find_last_of("[(");
  if (open != std::string::npos && (header.back() == ']' || header.back() == ')')) u = header.substr(open + 1, header.size() - open - 2);
  else if (header.find('_') != std::string::npos) u = header.substr(header.rfind('_') + 1);
  unit = detail::trim(u);
  const auto conv = parse_unit(unit);
  return conv && conv->unit == "m" ? conv->factor : 0.0;
}

}  // namespace

load::RailProfile read_rail_profile(const std::string& path) {
  const detail::TextTable t = detail::read_text_table(path, false);
  auto err = [&](int line, const std::string& key, const std::string& msg) { return InputError(SourceLocation{path, line, key}, msg); };
  if (t.header.size() != 2)
    throw err(t.header_line, "", "a rail profile has two columns, the position and the level (x_m,z_mm), not " + std::to_string(t.header.size()));
  double factor[2];
  for (int c = 0; c < 2; ++c) {
    std::string unit;
    factor[c] = length_factor(t.header[static_cast<std::size_t>(c)], unit);
    if (factor[c] == 0.0)
      throw err(t.header_line, t.header[static_cast<std::size_t>(c)],
                "column '" + t.header[static_cast<std::size_t>(c)] + "': " + (unit.empty() ? "no unit" : "'" + unit + "' is not a length") +
                    " (name it x_m, z_mm, 'level [mm]': m, mm, cm or um)");
  }
  const std::size_t n = t.rows.size();
  if (n < 4) throw err(n ? t.lines.back() : t.header_line, "", "a rail profile needs at least 4 points, got " + std::to_string(n));
  std::vector<double> x(n), z(n);
  for (std::size_t i = 0; i < n; ++i)
    for (int c = 0; c < 2; ++c) {
      const std::string& cell = t.rows[i][static_cast<std::size_t>(c)];
      char* end = nullptr;
      const double v = std::strtod(cell.c_str(), &end);
      if (cell.empty() || end != cell.c_str() + cell.size() || !std::isfinite(v))
        throw err(t.lines[i], t.header[static_cast<std::size_t>(c)], "'" + cell + "' is not a number");
      (c == 0 ? x : z)[i] = v * factor[c];
    }
  const double dx = (x[n - 1] - x[0]) / static_cast<double>(n - 1);
  for (std::size_t i = 1; i < n; ++i)
    if (!(x[i] > x[i - 1]))
      throw err(t.lines[i], t.header[0], "position " + format_number(x[i]) + " m does not follow " + format_number(x[i - 1]) + " m");
  for (std::size_t i = 1; i < n; ++i) {
    if (std::abs(x[i] - (x[0] + dx * static_cast<double>(i))) > 0.01 * dx)
      throw err(t.lines[i], t.header[0], "position " + format_number(x[i], 10) + " m is off the uniform step of " + format_number(dx, 10) +
                                             " m: resample the profile to a uniform step first");
  }
  load::RailProfile p;
  p.x0 = x[0];
  p.dx = dx;
  p.z = Eigen::Map<const Vector>(z.data(), static_cast<Index>(n));
  return p;
}

}  // namespace viaduct::io

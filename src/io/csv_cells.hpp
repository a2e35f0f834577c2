#pragma once
// Private to src/io: one CSV line split into trimmed cells (no quoting: record, FRF and schedule
// files are numbers and plain names).
#include <string>
#include <vector>

namespace viaduct::io::detail {

inline std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  const auto b = s.find_last_not_of(" \t\r");
  return s.substr(a, b - a + 1);
}

/// Cells between commas, trimmed; "a,,b" gives an empty middle cell, a trailing comma an empty last one.
inline std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (true) {
    const auto comma = line.find(',', start);
    out.push_back(trim(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

}  // namespace viaduct::io::detail

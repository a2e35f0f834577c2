#pragma once
// Private to src/io: CSV lines split into trimmed cells (plain for record, FRF and schedule files,
// which hold numbers and plain names; quoted for tables written by write_table_csv).
#include <fstream>
#include <string>
#include <vector>

#include "viaduct/core/error.hpp"

namespace viaduct::io::detail {

/// A text cell as write_table_csv quotes it: in double quotes (inner quotes doubled) when it holds
/// a comma, a quote or a line break.
inline std::string csv_text(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string o = "\"";
  for (char c : s) o += (c == '"') ? std::string("\"\"") : std::string(1, c);
  return o + "\"";
}

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

/// Cells of a line as write_table_csv writes them: a double-quoted cell may hold commas and "".
inline std::vector<std::string> split_quoted_csv(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') cell += '"', ++i;
      else if (c == '"') quoted = false;
      else cell += c;
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      out.push_back(trim(cell));
      cell.clear();
    } else {
      cell += c;
    }
  }
  out.push_back(trim(cell));
  return out;
}

/// A CSV file as text: the header, then rows of as many cells with their line numbers; '#' and
/// empty lines skipped. InputError naming file and line for a missing file or header, or a row
/// whose width differs from the header.
struct TextTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::vector<int> lines;
  int header_line = 0;
};

// Drops a UTF-8 byte-order mark from the first line of a file (spreadsheets and Windows editors
// write one; it would otherwise stick to the first header cell or the first "-1").
inline void drop_bom(std::string& first_line) {
  if (first_line.compare(0, 3, "\xEF\xBB\xBF") == 0) first_line.erase(0, 3);
}

inline TextTable read_text_table(const std::string& path, bool quoted) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open");
  TextTable t;
  std::string line;
  int ln = 0;
  while (std::getline(in, line)) {
    if (++ln == 1) drop_bom(line);
    if (line.empty() || line[0] == '#' || line == "\r") continue;
    auto cells = quoted ? split_quoted_csv(line) : split_csv(line);
    if (t.header.empty()) {
      t.header = std::move(cells);
      t.header_line = ln;
      continue;
    }
    if (cells.size() != t.header.size())
      throw InputError(path + ":" + std::to_string(ln) + ": " + std::to_string(cells.size()) + " cells, the header has " +
                       std::to_string(t.header.size()));
    t.rows.push_back(std::move(cells));
    t.lines.push_back(ln);
  }
  if (t.header.empty()) throw InputError(path + ": no header");
  return t;
}

}  // namespace viaduct::io::detail

#pragma once
// TOML files parsed in time linear in their size. toml11 takes time quadratic in the length of a
// line (a 1 MB array on one line: minutes), so lines longer than kLongLine are first split after
// the commas of their arrays — the same TOML — and the line numbers of values mapped back.

#include <string>
#include <vector>

#include <toml.hpp>

namespace viaduct::io::detail {

constexpr std::size_t kLongLine = 4096;

struct TomlFile {
  toml::value root;
  std::vector<int> original_line;  ///< per parsed line (1-based, [0] unused); empty: no line was split
  /// The line of `v` in the file as written.
  int line_of(const toml::value& v) const;
};

/// InputError at `path`:line when `text` holds a byte that is not UTF-8, or a control character
/// other than tab, CR and LF (toml11 must not see them).
void require_utf8(const std::string& text, const std::string& path);

/// Parses `path` (toml::syntax_error and std::runtime_error as toml::parse throws them; a syntax
/// error in a split line names the line as split, with a note saying so).
TomlFile parse_toml_file(const std::string& path);

/// `text` with every line longer than kLongLine broken after the commas inside its arrays (not in
/// strings or comments); `original_line` maps each line of the result to the line of `text`.
std::string split_long_lines(const std::string& text, std::vector<int>& original_line);

}  // namespace viaduct::io::detail

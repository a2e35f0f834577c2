#include "toml_file.hpp"

#include "viaduct/core/error.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace viaduct::io::detail {

int TomlFile::line_of(const toml::value& v) const {
  const auto parsed = static_cast<std::size_t>(v.location().line());
  if (original_line.empty()) return static_cast<int>(parsed);
  return parsed < original_line.size() ? original_line[parsed] : static_cast<int>(parsed);
}

std::string split_long_lines(const std::string& text, std::vector<int>& original_line) {
  std::string out;
  out.reserve(text.size() + text.size() / 8);
  original_line.assign(1, 0);
  int line = 1;
  bool in_multiline = false;  // inside a """ or ''' string that spans lines: left as it is
  std::size_t start = 0;
  while (start <= text.size()) {
    std::size_t end = text.find('\n', start);
    const bool last = end == std::string::npos;
    if (last) end = text.size();
    const std::string_view l(text.data() + start, end - start);
    const std::size_t triples = [&] {
      std::size_t n = 0;
      for (const char* q : {"\"\"\"", "'''"})
        for (std::size_t p = l.find(q); p != std::string_view::npos; p = l.find(q, p + 3)) ++n;
      return n;
    }();
    if (l.size() <= kLongLine || in_multiline || triples > 0) {
      out.append(l);
      original_line.push_back(line);
    } else {
      // Break after each comma inside brackets, outside strings and comments.
      int depth = 0, braces = 0;  // inline tables must stay on one line: no break inside {...}
      char quote = 0;
      for (std::size_t i = 0; i < l.size(); ++i) {
        const char c = l[i];
        out.push_back(c);
        if (quote) {
          if (c == '\\' && quote == '"' && i + 1 < l.size()) out.push_back(l[++i]);
          else if (c == quote) quote = 0;
        } else if (c == '"' || c == '\'') {
          quote = c;
        } else if (c == '#') {
          out.append(l.substr(i + 1));
          break;
        } else if (c == '[') {
          ++depth;
        } else if (c == ']') {
          --depth;
        } else if (c == '{') {
          ++braces;
        } else if (c == '}') {
          --braces;
        } else if (c == ',' && depth > 0 && braces == 0) {
          out.push_back('\n');
          original_line.push_back(line);
        }
      }
      original_line.push_back(line);
    }
    if (triples % 2 == 1) in_multiline = !in_multiline;
    if (last) break;
    out.push_back('\n');
    start = end + 1;
    ++line;
  }
  return out;
}

// TOML is UTF-8 text. toml11 reads past its buffer on some invalid bytes inside a literal string
// (found by fuzzing: heap-buffer-overflow in location::reset), so they are refused before it runs.
void require_utf8(const std::string& text, const std::string& path) {
  int line = 1;
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c == '\n') ++line;
    // Well-formed UTF-8 as toml11 checks it (Unicode table 3-7): no overlong forms (C0, C1,
    // E0 80-9F, F0 80-8F), no surrogates (ED A0-BF), nothing above U+10FFFF (F4 90-, F5-FF).
    std::size_t n = c < 0x80 ? 1 : (c >= 0xC2 && c <= 0xDF) ? 2 : (c >= 0xE0 && c <= 0xEF) ? 3 : (c >= 0xF0 && c <= 0xF4) ? 4 : 0;
    bool ok = n > 0 && i + n <= text.size() && !(c < 0x20 && c != '\t' && c != '\n' && c != '\r') && c != 0x7F;
    for (std::size_t k = 1; ok && k < n; ++k) ok = (static_cast<unsigned char>(text[i + k]) >> 6) == 0x2;
    if (ok && n > 1) {
      const auto c1 = static_cast<unsigned char>(text[i + 1]);
      ok = !(c == 0xE0 && c1 < 0xA0) && !(c == 0xED && c1 >= 0xA0) && !(c == 0xF0 && c1 < 0x90) && !(c == 0xF4 && c1 >= 0x90);
    }
    if (!ok) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "0x%02x", c);
      throw InputError(SourceLocation{path, line, ""}, std::string("not UTF-8 text or a control character (byte ") + hex +
                                                           "): a TOML file is UTF-8 text");
    }
    i += n;
  }
}

// Arrays and inline tables nested deeper than kMaxNesting: toml11 parses them recursively and a
// few thousand '[' overflow the stack (found by fuzzing), so they are refused first. Strings and
// comments are skipped; the scan follows TOML's quoting rules.
void require_shallow(const std::string& text, const std::string& path) {
  constexpr int kMaxNesting = 64;
  int depth = 0, line = 1;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
    } else if (c == '#') {
      while (i + 1 < text.size() && text[i + 1] != '\n') ++i;
    } else if (c == '"' || c == '\'') {
      const bool triple = text.compare(i, 3, std::string(3, c)) == 0;
      const std::string close = triple ? std::string(3, c) : std::string(1, c);
      std::size_t j = i + close.size();
      while (j < text.size() && text.compare(j, close.size(), close) != 0) {
        if (c == '"' && text[j] == '\\') ++j;
        else if (text[j] == '\n') {
          if (!triple) break;
          ++line;
        }
        ++j;
      }
      i = std::min(text.size(), j + close.size()) - 1;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxNesting)
        throw InputError(SourceLocation{path, line, ""}, "arrays or tables nested more than " + std::to_string(kMaxNesting) + " deep");
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
}

TomlFile parse_toml_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open " + path);
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  if (text.compare(0, 3, "\xEF\xBB\xBF") == 0) text.erase(0, 3);  // a byte-order mark
  require_utf8(text, path);
  require_shallow(text, path);
  TomlFile f;
  bool long_line = false;
  for (std::size_t start = 0, end; start < text.size(); start = end + 1) {
    end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    if (end - start > kLongLine) {
      long_line = true;
      break;
    }
  }
  if (!long_line) {
    std::istringstream is(text);
    f.root = toml::parse(is, path);
    return f;
  }
  std::istringstream is(split_long_lines(text, f.original_line));
  try {
    f.root = toml::parse(is, path);
  } catch (const toml::syntax_error& e) {
    throw toml::syntax_error(std::string(e.what()) +
                                 "\n(lines longer than " + std::to_string(kLongLine) +
                                 " characters were split after their commas to be read: the line numbers above count "
                                 "those parts)",
                             e.location());
  }
  return f;
}

}  // namespace viaduct::io::detail

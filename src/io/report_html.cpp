// report.md as one self-contained HTML page, and its PDF by headless Chromium (report_html.hpp).
#include "viaduct/io/report_html.hpp"

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <sstream>
#include <vector>

namespace viaduct::io {

namespace {

std::string html_escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '&') o += "&amp;";
    else if (c == '<') o += "&lt;";
    else if (c == '>') o += "&gt;";
    else if (c == '"') o += "&quot;";
    else o += c;
  }
  return o;
}

std::string base64(const std::string& bytes) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string o;
  o.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const unsigned b0 = static_cast<unsigned char>(bytes[i]);
    const unsigned b1 = i + 1 < bytes.size() ? static_cast<unsigned char>(bytes[i + 1]) : 0u;
    const unsigned b2 = i + 2 < bytes.size() ? static_cast<unsigned char>(bytes[i + 2]) : 0u;
    const unsigned n = (b0 << 16) | (b1 << 8) | b2;
    o += t[(n >> 18) & 63];
    o += t[(n >> 12) & 63];
    o += i + 1 < bytes.size() ? t[(n >> 6) & 63] : '=';
    o += i + 2 < bytes.size() ? t[n & 63] : '=';
  }
  return o;
}

// The class of a verdict's cell or bold word: coloured in the page.
std::string verdict_class(const std::string& text) {
  if (text.rfind("FAIL", 0) == 0 || text.rfind("UPLIFT", 0) == 0) return "fail";
  if (text.rfind("dynamic governs", 0) == 0) return "warn";
  if (text.rfind("not checked", 0) == 0 || text.rfind("limit to give", 0) == 0) return "nc";
  if (text == "pass" || text == "LM71 governs") return "pass";
  if (text == "warning") return "fail";
  return "";
}

// **bold**, `code` and name.csv links of one line of text.
std::string inline_html(const std::string& s) {
  static const std::regex bold(R"(\*\*([^*]+)\*\*)"), csv(R"(\b([A-Za-z0-9_\-]+\.csv)\b)");
  std::string out;
  std::size_t i = 0;
  while (i < s.size()) {
    const std::size_t tick = s.find('`', i);
    const std::size_t end = tick == std::string::npos ? std::string::npos : s.find('`', tick + 1);
    std::string text = html_escape(s.substr(i, (end == std::string::npos ? s.size() : tick) - i));
    text = std::regex_replace(text, csv, "<a href=\"$1\">$1</a>");
    std::string styled;
    auto it = std::sregex_iterator(text.begin(), text.end(), bold);
    std::size_t at = 0;
    for (; it != std::sregex_iterator(); ++it) {
      const std::string word = (*it)[1].str(), cls = verdict_class(word);
      styled += text.substr(at, static_cast<std::size_t>(it->position()) - at) + "<strong" +
                (cls.empty() ? std::string() : " class=\"" + cls + "\"") + ">" + word + "</strong>";
      at = static_cast<std::size_t>(it->position() + it->length());
    }
    out += styled + text.substr(at);
    if (end == std::string::npos) break;
    out += "<code>" + html_escape(s.substr(tick + 1, end - tick - 1)) + "</code>";
    i = end + 1;
  }
  return out;
}

std::vector<std::string> table_cells(std::string line) {
  if (!line.empty() && line.front() == '|') line.erase(0, 1);
  if (!line.empty() && line.back() == '|') line.pop_back();
  std::vector<std::string> cells;
  std::stringstream ss(line);
  for (std::string c; std::getline(ss, c, '|');) {
    const std::size_t a = c.find_first_not_of(' '), b = c.find_last_not_of(' ');
    cells.push_back(a == std::string::npos ? std::string() : c.substr(a, b - a + 1));
  }
  return cells;
}

void table_html(std::ostringstream& o, const std::vector<std::string>& lines) {
  const std::vector<std::string> head = table_cells(lines.front());
  std::vector<std::string> align(head.size());
  std::size_t first_body = 1;
  if (lines.size() > 1 && lines[1].find("---") != std::string::npos) {
    const std::vector<std::string> a = table_cells(lines[1]);
    for (std::size_t k = 0; k < a.size() && k < align.size(); ++k)
      align[k] = !a[k].empty() && a[k].back() == ':' ? " class=\"num\"" : "";
    first_body = 2;
  }
  o << "<table>\n<thead><tr>";
  for (std::size_t k = 0; k < head.size(); ++k) o << "<th" << align[k] << ">" << inline_html(head[k]) << "</th>";
  o << "</tr></thead>\n<tbody>\n";
  for (std::size_t r = first_body; r < lines.size(); ++r) {
    o << "<tr>";
    const std::vector<std::string> cells = table_cells(lines[r]);
    for (std::size_t k = 0; k < cells.size(); ++k) {
      const std::string cls = verdict_class(cells[k]);
      o << "<td" << (k < align.size() ? align[k] : "") << (cls.empty() ? "" : " data-verdict=\"" + cls + "\"") << ">"
        << inline_html(cells[k]) << "</td>";
    }
    o << "</tr>\n";
  }
  o << "</tbody>\n</table>\n";
}

// ![alt](file) embedded from `dir`, or said to be missing.
void figure_html(std::ostringstream& o, const std::string& line, const std::string& dir) {
  const std::size_t close = line.find("](");
  const std::string alt = line.substr(2, close - 2), src = line.substr(close + 2, line.size() - close - 3);
  std::ifstream f(dir + "/" + src, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  if (!f.good() && bytes.empty()) {
    o << "<p class=\"missing\">Figure not drawn: " << html_escape(src) << " (" << html_escape(alt) << ")</p>\n";
    return;
  }
  o << "<figure><img alt=\"" << html_escape(alt) << "\" src=\"data:image/png;base64," << base64(bytes) << "\"><figcaption>"
    << inline_html(alt) << "</figcaption></figure>\n";
}

const char* kStyle = R"(body{font-family:"DejaVu Sans",Arial,sans-serif;font-size:10.5pt;line-height:1.4;max-width:1180px;margin:1.5em auto;padding:0 1em;color:#1a1a1a}
h1{font-size:1.5em;border-bottom:2px solid #333;padding-bottom:.2em}h2{font-size:1.2em;margin-top:1.6em;border-bottom:1px solid #bbb}
table{border-collapse:collapse;margin:.6em 0;font-size:.88em}th,td{border:1px solid #bbb;padding:2px 6px;vertical-align:top}
th{background:#eee;text-align:left}.num{text-align:right}td[data-verdict=fail]{background:#f8d0d0;font-weight:bold}
td[data-verdict=warn]{background:#fbe7c2}td[data-verdict=pass]{background:#e2f2e2}td[data-verdict=nc]{background:#eee;font-style:italic}
strong.fail{color:#b00000}strong.pass{color:#1d6b1d}strong.nc{color:#555}strong.warn{color:#9a5a00}
code{font-size:.95em;background:#f4f4f4;padding:0 2px}figure{margin:1em 0;page-break-inside:avoid}img{max-width:100%}
figcaption{font-size:.9em;color:#444}.missing{color:#b00000}tr{page-break-inside:avoid}
@page{size:A4;margin:14mm}@media print{body{max-width:none;margin:0;font-size:9pt}})";

}  // namespace

std::string report_html(const std::string& markdown, const std::string& title, const std::string& dir) {
  std::ostringstream o;
  o << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" << html_escape(title)
    << "</title>\n<style>\n" << kStyle << "\n</style>\n</head>\n<body>\n";
  std::vector<std::string> lines;
  std::stringstream ss(markdown);
  for (std::string l; std::getline(ss, l);) lines.push_back(l);
  std::string para;
  auto flush = [&] {
    if (!para.empty()) o << "<p>" << inline_html(para) << "</p>\n";
    para.clear();
  };
  static const std::regex ordered(R"(^\d+\. )");
  for (std::size_t i = 0; i < lines.size();) {
    const std::string& l = lines[i];
    if (l.empty()) {
      flush(), ++i;
    } else if (l.rfind("#", 0) == 0) {
      flush();
      const std::size_t level = l.find_first_not_of('#');
      o << "<h" << level << ">" << inline_html(l.substr(level + 1)) << "</h" << level << ">\n";
      ++i;
    } else if (l.front() == '|') {
      flush();
      std::vector<std::string> rows;
      for (; i < lines.size() && !lines[i].empty() && lines[i].front() == '|'; ++i) rows.push_back(lines[i]);
      table_html(o, rows);
    } else if (l.rfind("- ", 0) == 0 || std::regex_search(l, ordered)) {
      flush();
      const bool ol = l.rfind("- ", 0) != 0;
      o << (ol ? "<ol>\n" : "<ul>\n");
      for (; i < lines.size() && (ol ? std::regex_search(lines[i], ordered) : lines[i].rfind("- ", 0) == 0); ++i)
        o << "<li>" << inline_html(lines[i].substr(lines[i].find(' ') + 1)) << "</li>\n";
      o << (ol ? "</ol>\n" : "</ul>\n");
    } else if (l.rfind("![", 0) == 0 && l.find("](") != std::string::npos && l.back() == ')') {
      flush();
      figure_html(o, l, dir);
      ++i;
    } else {
      para += (para.empty() ? "" : " ") + l;
      ++i;
    }
  }
  flush();
  o << "</body>\n</html>\n";
  return o.str();
}

std::string find_chromium() {
  if (const char* env = std::getenv("VIADUCT_CHROMIUM"); env && *env) return std::filesystem::exists(env) ? env : "";
  for (const char* p : {"/usr/bin/chromium", "/usr/bin/chromium-browser"})
    if (std::filesystem::exists(p)) return p;
  return "";
}

namespace {
// A file path as a file:// URL: every byte but the unreserved ones and '/' percent-encoded (a '#',
// '?' or '%' in a directory name would otherwise point Chromium at another file, and it prints
// its error page as the PDF).
std::string file_url(const std::string& path) {
  static const char* hex = "0123456789ABCDEF";
  std::string o = "file://";
  for (unsigned char c : path) {
    if (std::isalnum(c) || c == '/' || c == '-' || c == '_' || c == '.' || c == '~') o += static_cast<char>(c);
    else o += '%', o += hex[c >> 4], o += hex[c & 15];
  }
  return o;
}
}  // namespace

std::string print_to_pdf(const std::string& chromium, const std::string& html, const std::string& pdf) {
  namespace fs = std::filesystem;
  for (const std::string& p : {chromium, html, pdf})
    if (p.find('\'') != std::string::npos) return "a path holds a single quote: " + p;
  std::error_code ec;
  const std::string abs_html = fs::absolute(html, ec).lexically_normal().string();
  std::string tmpl = (fs::temp_directory_path(ec) / "viaduct-chromium-XXXXXX").string();
  std::vector<char> buf(tmpl.begin(), tmpl.end());
  buf.push_back('\0');
  if (!mkdtemp(buf.data())) return "no temporary directory for Chromium's profile";
  const std::string profile(buf.data()), tmp_pdf = pdf + ".tmp";
  // The flags this machine's closed network needs (no background connections, no sandbox as root).
  const std::string cmd = "timeout 120 '" + chromium + "' --headless --no-sandbox --disable-gpu --disable-quic --no-first-run "
                          "--disable-background-networking --disable-component-update --disable-sync --user-data-dir='" + profile +
                          "' --no-pdf-header-footer --print-to-pdf='" + tmp_pdf + "' '" + file_url(abs_html) + "' >'" + profile +
                          "/log' 2>&1";
  const int rc = std::system(cmd.c_str());
  std::string err;
  if (rc != 0 || !fs::exists(tmp_pdf) || fs::file_size(tmp_pdf, ec) == 0) {
    std::ifstream log(profile + "/log");
    std::string text((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>());
    if (text.size() > 400) text = "…" + text.substr(text.size() - 400);
    err = "Chromium (" + chromium + ") did not print the PDF (exit " + std::to_string(rc) + ")" + (text.empty() ? "" : ": " + text);
    fs::remove(tmp_pdf, ec);
  } else {
    fs::rename(tmp_pdf, pdf, ec);
    if (ec) err = "could not rename " + tmp_pdf + ": " + ec.message();
  }
  fs::remove_all(profile, ec);
  return err;
}

}  // namespace viaduct::io

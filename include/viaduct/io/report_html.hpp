#pragma once
/// \file A report to hand over (issue #38): report.md's text as one self-contained HTML page
/// (figures embedded as data URIs, tables, links to the CSVs beside it, readable offline), and
/// its PDF printed by headless Chromium.

#include <string>

namespace viaduct::io {

/// The HTML page of a Markdown report as viaduct writes it (headings, paragraphs, "-" and "1."
/// lists, pipe tables with their alignment row, **bold**, `code`, ![alt](file.png) on a line of
/// its own). Images are read from `dir` and embedded (a missing one is said, not linked); every
/// word `name.csv` becomes a link to the file beside the page; verdict cells (FAIL, UPLIFT, pass,
/// not checked) are coloured. `title` is the page's title.
std::string report_html(const std::string& markdown, const std::string& title, const std::string& dir);

/// The Chromium this machine has: $VIADUCT_CHROMIUM when set (empty when it names no file), else
/// /usr/bin/chromium, else /usr/bin/chromium-browser; empty when none is there.
std::string find_chromium();

/// Prints `html` (a file) to `pdf` with headless Chromium `chromium` (A4, no header or footer,
/// backgrounds printed), written through a temporary file and renamed. Returns an empty string, or
/// what went wrong (the PDF is then not there).
std::string print_to_pdf(const std::string& chromium, const std::string& html, const std::string& pdf);

}  // namespace viaduct::io

#!/usr/bin/env bash
# The report to hand over (issue #38 part 3): every `viaduct assess` writes report.html, self-
# contained (figures as data URIs, links to the CSVs beside it), and report.pdf printed by headless
# Chromium. On a single span (HSLM), a chain of two spans under a half-deck model (Old Guadiana)
# and a continuous two-span deck: Chromium renders the page without a console message, its
# screenshot is not blank, and the PDF's text holds the verdict and the report's sections. The
# detector of console errors is shown to find one in a page made to raise it. Needs Debian's
# chromium and poppler-utils (pdftotext): scripts/setup.sh --tests installs them.
. "$(dirname "$0")/lib.sh"
CHROMIUM=${VIADUCT_CHROMIUM:-/usr/bin/chromium}
if [ ! -x "$CHROMIUM" ] || ! command -v pdftotext >/dev/null; then
  echo "FAIL: $CHROMIUM or pdftotext missing: run scripts/setup.sh --tests (Debian packages chromium, poppler-utils)"
  exit 1
fi

# render PAGE SHOT: a screenshot of PAGE; prints the console messages Chromium logged.
render() {
  local profile
  profile=$(mktemp -d "$WORK/profile.XXXXXX")
  timeout 120 "$CHROMIUM" --headless --no-sandbox --disable-gpu --disable-quic --no-first-run --disable-background-networking \
    --disable-component-update --disable-sync --user-data-dir="$profile" --enable-logging=stderr --v=0 \
    --window-size=1280,2000 --screenshot="$2" "file://$1" 2>&1 | grep -a "CONSOLE" || true
}

# not_blank SHOT: a page that rendered holds text, tables and figures: many pixels far from white.
not_blank() {
  /usr/bin/python3 - "$1" <<'PY'
import sys
import matplotlib.image as mpimg
a = mpimg.imread(sys.argv[1])[..., :3]
dark = (a.mean(axis=2) < 0.6).mean()
print("dark fraction %.4f" % dark)
sys.exit(0 if dark > 0.01 else 1)
PY
}

run_case() {  # name scenario sets...
  local name=$1 sc=$2
  shift 2
  local O=$WORK/$name
  expect 0 "report.pdf" -- "$VIADUCT" assess "$sc" "$@" --out "$O"
  expect 0 "" -- test -s "$O/report.html"
  expect 0 "" -- test -s "$O/report.pdf"
  # self-contained: every image embedded, nothing fetched from elsewhere, the CSVs linked
  expect 0 "3" -- grep -c "src=\"data:image/png;base64," "$O/report.html"
  expect 1 "" -- grep -Eq "(src|href)=\"(https?:|//)" "$O/report.html"
  expect 0 "<a href=\"checks.csv\">checks.csv</a>" -- cat "$O/report.html"
  expect 0 "" -- test -z "$(render "$O/report.html" "$O/shot.png")"
  expect 0 "dark fraction" -- not_blank "$O/shot.png"
  pdftotext -layout "$O/report.pdf" "$O/report.txt"
  local verdict
  verdict=$(grep -m1 -E "check\(s\) fail|Every limit check made passes" "$O/report.md" | sed 's/\*//g; s/^ *//' | cut -c1-30)
  for s in "$verdict" "Model" "Deck modes and resonance speeds" "Is a dynamic analysis required?" "Fig. 6.10" \
           "passenger comfort, deck deflection" "not checked (2D model)" "Provenance"; do
    expect 0 "$s" -- cat "$O/report.txt"
  done
}

HS=$SRC/scenarios/hslm-simply-supported.toml
run_case hslm "$HS" --set assess.speed_min_kmh=300 --set assess.speed_step_kmh=40 --set assess.refine_band=0
run_case guadiana "$SRC/scenarios/old-guadiana-assess.toml" --set assess.speed_min_kmh=330 --set assess.speed_step_kmh=30 \
  --set assess.refine_band=0
expect 0 "per rail line / half deck" -- cat "$WORK/guadiana/report.txt"
# Its two spans' modes are 0.5 % apart: the governing case again with the sleepers moved by a
# quarter of their 0.6 m spacing each time (the four layouts run on the assessment's threads),
# each row at its own offset, in order, every station's peak a number.
expect 0 "layouts ok" -- python3 - "$WORK/guadiana/report.md" <<'PY'
import sys
lines = open(sys.argv[1]).read().split("\n")
head = [i for i, l in enumerate(lines) if l.startswith("| offset [m] |")]
assert len(head) == 1, "no sleeper-layout table"
rows = [l.strip("|").split("|") for l in lines[head[0] + 2:head[0] + 6]]
assert [float(r[0]) for r in rows] == [0.0, 0.15, 0.3, 0.45], rows
n_st = len(lines[head[0]].strip("|").split("|")) - 1
assert all(len(r) == n_st + 1 and all(float(c) > 0 for c in r[1:]) for r in rows), rows
assert lines[head[0] + 6].startswith("| spread |"), lines[head[0] + 6]
print("layouts ok")
PY
run_case continuous "$SRC/scenarios/continuous-two-span.toml" --set assess.speed_min_kmh=300 --set assess.speed_step_kmh=40 \
  --set assess.refine_band=0

# An output directory whose name holds '#' and a space: the page's URL is encoded (unencoded,
# Chromium opened another file and printed its error page as the PDF).
H="$WORK/dir #1 x"
expect 0 "report.pdf" -- "$VIADUCT" assess "$HS" --set assess.speed_min_kmh=400 --set assess.speed_step_kmh=40 \
  --set assess.refine_band=0 --no-plots --out "$H"
expect 0 "Dynamic assessment" -- pdftotext "$H/report.pdf" -

# The detector can fail: a page that raises an error logs it.
sed 's|</body>|<script>not_a_function();</script></body>|' "$WORK/hslm/report.html" > "$WORK/broken.html"
expect 0 "not_a_function" -- render "$WORK/broken.html" "$WORK/broken.png"
# ...and a blank page is told from a report.
echo '<!DOCTYPE html><html><body></body></html>' > "$WORK/blank.html"
render "$WORK/blank.html" "$WORK/blank.png" >/dev/null
expect 1 "dark fraction 0.0000" -- not_blank "$WORK/blank.png"

# Without Chromium: report.html still, no report.pdf, a warning that says how, exit 0.
N=$WORK/nopdf
expect 0 "report.pdf not written: Chromium not found" -- env VIADUCT_CHROMIUM=$WORK/none "$VIADUCT" assess "$HS" \
  --set assess.speed_min_kmh=400 --set assess.speed_step_kmh=40 --set assess.refine_band=0 --no-plots --out "$N"
expect 0 "" -- test -s "$N/report.html"
expect 1 "" -- test -e "$N/report.pdf"
finish

#!/usr/bin/python3
"""Bending moment and shear envelopes along the deck from `viaduct sweep --load-effects` or
`viaduct assess`.

Usage: scripts/plot/plot_load_effects.py DIR [--out FILE]

Reads DIR/load_effects.csv and draws, for the stations along a span (`stations[].every_m`: names
<name>_<x>m), the envelope over every speed of each train's moment M(x) and shear V(x), largest
and smallest, with the quasi-static values of the train crawling (dashed). From an assessment
(DIR/checks.csv present) it adds, along x, the dynamic design effect of the governing case and
Phi x LM71 x alpha ("dynamic design effect vs LM71" rows: the larger governs the design).
Writes DIR/load_effects_along.png.
"""
import os
import re
import sys


import plotlib  # noqa: E402

plt = plotlib.pyplot()

ALONG = re.compile(r"^(?P<line>.+)_(?P<x>\d+\.\d+)m_(?P<kind>moment_Nm|shear_N)$")
KINDS = (("moment_Nm", "bending moment M(x)", 1e-3, "kN·m"), ("shear_N", "shear force V(x)", 1e-3, "kN"))


def along(rows):
    """{(line, kind): {train: {x: [max, min, qs_max, qs_min]}}} over every speed and variant."""
    out = {}
    for r in rows:
        m = ALONG.match(r["quantity"])
        if not m:
            continue
        x = float(m["x"])
        per = out.setdefault((m["line"], m["kind"]), {}).setdefault(r["train"], {})
        hi, lo = float(r["max"]), float(r["min"])
        qs_hi, qs_lo = plotlib.number(r["quasi_static_max"]), plotlib.number(r["quasi_static_min"])
        e = per.setdefault(x, [hi, lo, qs_hi, qs_lo])
        e[0], e[1] = max(e[0], hi), min(e[1], lo)
        if qs_hi is not None:
            e[2] = qs_hi if e[2] is None else max(e[2], qs_hi)
        if qs_lo is not None:
            e[3] = qs_lo if e[3] is None else min(e[3], qs_lo)
    return out


def design_rows(directory):
    """{(line, kind): {x: (dynamic design effect, Phi x LM71 x alpha, governing case)}} of an assessment."""
    path = os.path.join(directory, "checks.csv")
    if not os.path.exists(path):
        return {}
    out = {}
    for r in plotlib.rows(path, "plot_load_effects", "assess"):
        if r["check"] != "dynamic design effect vs LM71":
            continue
        name = r["quantity"]
        m = ALONG.match(name)
        if not m:
            continue
        case = "%s %s km/h" % (r["train"], r["speed_kmh"]) if r["train"] else ""
        out.setdefault((m["line"], m["kind"]), {})[float(m["x"])] = (float(r["value"]), float(r["limit"]), case)
    return out


def draw(directory, out=None, tool="plot_load_effects"):
    """Draws the envelopes along x of `directory`'s stations along a span into `out` (default
    DIR/load_effects_along.png); returns False, drawing nothing, when it has none."""
    env = along(plotlib.rows(os.path.join(directory, "load_effects.csv"), tool, "sweep --load-effects"))
    if not env:
        return False
    design = design_rows(directory)
    lines = sorted({line for line, _ in env})
    fig, axes = plt.subplots(len(lines), 2, figsize=(12, 4.2 * len(lines)), squeeze=False)
    for row, line in enumerate(lines):
        for col, (kind, what, factor, unit) in enumerate(KINDS):
            ax = axes[row][col]
            trains = env.get((line, kind), {})
            peak = (0.0, "", 0.0)
            for i, (train, per) in enumerate(sorted(trains.items())):
                xs = sorted(per)
                c = "C%d" % (i % 10)
                ax.plot(xs, [factor * per[x][0] for x in xs], color=c, lw=1.2, label=train)
                ax.plot(xs, [factor * per[x][1] for x in xs], color=c, lw=1.2)
                if all(per[x][2] is not None for x in xs):
                    ax.plot(xs, [factor * per[x][2] for x in xs], color=c, lw=0.8, ls="--")
                    ax.plot(xs, [factor * per[x][3] for x in xs], color=c, lw=0.8, ls="--")
                for x in xs:
                    if abs(per[x][0]) > abs(peak[0]):
                        peak = (per[x][0], train, x)
                    if abs(per[x][1]) > abs(peak[0]):
                        peak = (per[x][1], train, x)
            d = design.get((line, kind), {})
            if d:
                xs = sorted(d)
                ax.plot(xs, [factor * d[x][0] for x in xs], color="k", lw=2.0, label="dynamic design effect, |max|")
                ax.plot(xs, [factor * d[x][1] for x in xs], color="k", lw=2.0, ls=":", label="Φ × LM71 × α, |max|")
            ax.axhline(0.0, color="0.6", lw=0.6)
            ax.set_xlabel("x along span line '%s' [m]" % line)
            ax.set_ylabel("%s [%s]" % (what, unit))
            title = "%s: %s" % (line, what)
            if peak[1]:
                title += "\nlargest |value| %.4g %s: %s at x = %.2f m" % (factor * peak[0], unit, peak[1], peak[2])
            ax.set_title(title, fontsize=9)
            ax.grid(alpha=0.3)
            plotlib.no_offset(ax)
            ax.legend(fontsize=7, ncol=2)
    factor = plotlib.manifest(directory).get("scenario", {}).get("train.load_factor", 1.0)
    note = "; per rail line / half deck (train.load_factor = %g)" % factor if factor != 1.0 else ""
    fig.suptitle("%s\nenvelopes over every speed (solid), quasi-static extremes (dashed)%s"
                 % (plotlib.scenario_title(directory), note), fontsize=10)
    fig.tight_layout()
    plotlib.save(fig, out or os.path.join(directory, "load_effects_along.png"), tool)
    return True


def main():
    ap = plotlib.dir_parser(__doc__)
    ap.add_argument("--out")
    a = plotlib.parse_dir(ap, "plot_load_effects")
    if not draw(a.dir, a.out):
        sys.exit("plot_load_effects.py: %s/load_effects.csv has no stations along a span (give a station "
                 "stations[].every_m)" % a.dir)


if __name__ == "__main__":
    main()

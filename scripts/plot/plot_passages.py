#!/usr/bin/python3
"""Draw recorded passages over the model's speed envelope, as `viaduct passages` wrote them.

Usage: scripts/plot/plot_passages.py DIR [--out FILE]

Reads DIR/passages.csv and DIR/model_envelope.csv and writes DIR/passages.png: one panel per
station and quantity, the model's envelope of each train as a line (peak against speed), each
passage a point of its train's colour at its identified speed with error bars (speed: its stated
uncertainty; peak: the noise band, noise_band × noise_rms), hollow when outside the model's band.
The title names the passage with the largest measured/predicted ratio of each panel.
"""
import os
import sys


import plotlib  # noqa: E402

plt = plotlib.pyplot()

LABELS = {"acc": "deck acceleration", "disp": "deflection", "strain": "strain"}


def rows(path):
    return plotlib.rows(path, "plot_passages", "passages")


def main():
    ap = plotlib.dir_parser(__doc__)
    ap.add_argument("--out", help="output PNG (default DIR/passages.png)")
    a = plotlib.parse_dir(ap, "plot_passages")
    passages = rows(os.path.join(a.dir, "passages.csv"))
    curves = rows(os.path.join(a.dir, "model_envelope.csv"))
    if not passages:
        sys.exit("plot_passages: no passages in %s/passages.csv (see failures.csv)" % a.dir)
    noise_band = float(plotlib.manifest(a.dir).get("run", {}).get("noise_band_rms", 4.0))
    panels = []
    for r in passages:
        key = (r["station"], r["quantity"], r["unit"])
        if key not in panels:
            panels.append(key)
    trains = []
    for r in curves + passages:
        if r["train"] not in trains:
            trains.append(r["train"])
    colour = {t: "C%d" % (i % 10) for i, t in enumerate(trains)}
    n = len(panels)
    fig, axes = plt.subplots(n, 1, figsize=(9, 3.6 * n + 0.8), squeeze=False)
    for ax, (station, quantity, unit) in zip(axes[:, 0], panels):
        factor, shown = plotlib.UNITS.get(unit, (1.0, unit))
        for t in trains:
            c = [r for r in curves if r["train"] == t and r["station"] == station and r["quantity"] == quantity]
            if c:
                ax.plot([float(r["speed_kmh"]) for r in c], [float(r["peak"]) * factor for r in c], color=colour[t], lw=1.2,
                        label="model, %s" % t)
        pts = [r for r in passages if r["station"] == station and r["quantity"] == quantity]
        for t in trains:
            for within in (True, False):
                p = [r for r in pts if r["train"] == t and (r["within"] == "true") == within]
                if not p:
                    continue
                ax.errorbar([float(r["speed_kmh"]) for r in p], [float(r["measured"]) * factor for r in p],
                            xerr=[plotlib.number(r["speed_uncertainty_kmh"]) or 0.0 for r in p],
                            yerr=[noise_band * float(r["noise_rms"]) * factor for r in p], fmt="o", ms=5, capsize=2,
                            color=colour[t], mfc=colour[t] if within else "white",
                            label="recorded, %s%s" % (t, "" if within else " (outside the band)"))
        ratios = [(plotlib.number(r["ratio"]), r) for r in pts if plotlib.number(r["ratio"]) is not None]
        n_within = sum(r["within"] == "true" for r in pts)
        title = "%s, %s: %d passages, %d within the model" % (station, LABELS.get(quantity, quantity), len(pts), n_within)
        if ratios:
            worst, r = max(ratios, key=lambda x: x[0])
            title += "\nlargest measured/predicted %.3f (%s, %s at %.1f km/h)" % (
                worst, os.path.basename(r["passage"]), r["train"], float(r["speed_kmh"]))
        ax.set_title(title, fontsize=9)
        ax.set_xlabel("speed [km/h]")
        ax.set_ylabel("max |%s| [%s]" % (LABELS.get(quantity, quantity), shown))
        ax.grid(True, alpha=0.3)
        ax.set_ylim(bottom=0)
        plotlib.no_offset(ax)
        ax.legend(fontsize=7, ncol=2, loc="upper left")
    fig.suptitle("%s: recorded passages over the model's envelope" % plotlib.scenario_title(a.dir), fontsize=11)
    fig.tight_layout()
    plotlib.save(fig, a.out or os.path.join(a.dir, "passages.png"), "plot_passages")


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Overlay FRFs written by `viaduct frf` (measured and model).

Usage: scripts/plot/plot_frf.py FRF.csv [FRF.csv ...] [--label NAME ...] [--out FILE]

Draws magnitude (logarithmic), phase and, when the file has it, coherence against frequency,
one colour per response and one line style per file (first file solid with markers when it has
few points, e.g. a stepped-sine test). Writes FILE (default: frf.png next to the first file).
"""
import argparse
import csv
import math
import os
import sys


import plotlib  # noqa: E402

plt = plotlib.pyplot()


def read(path):
    if not os.path.exists(path):
        sys.exit(f"plot_frf.py: {path} not found (run viaduct frf first)")
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows or "frequency_hz" not in rows[0]:
        sys.exit(f"plot_frf.py: {path} is not an FRF file")
    f = [float(r["frequency_hz"]) for r in rows]
    out = {}
    for col in rows[0]:
        if "_re_" in col:
            name, unit = col.split("_re_", 1)
            re = [float(r[col]) for r in rows]
            im = [float(r[col.replace("_re_", "_im_")]) for r in rows]
            coh = [float(r[name + "_coherence"]) for r in rows] if name + "_coherence" in rows[0] else None
            out[name] = (unit, re, im, coh)
    return f, out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("files", nargs="+")
    ap.add_argument("--label", action="append", default=[])
    ap.add_argument("--out")
    a = ap.parse_args()
    for path in a.files:  # FRF tables from viaduct's runs (a hand-made table in a directory without one too)
        if os.path.exists(os.path.join(os.path.dirname(path) or ".", "manifest.toml")):
            plotlib.check_outputs(path, "plot_frf")
    data = [read(p) for p in a.files]
    labels = a.label + [os.path.basename(os.path.dirname(os.path.abspath(p))) for p in a.files[len(a.label):]]
    has_coh = any(c is not None for _, d in data for (_, _, _, c) in d.values())
    n = 3 if has_coh else 2
    fig, ax = plt.subplots(n, 1, figsize=(9, 2.6 * n + 1), sharex=True,
                           gridspec_kw=dict(height_ratios=[2, 1, 1][:n]))
    styles = ["-", "--", ":", "-."]
    names = []
    for _, d in data:
        names += [k for k in d if k not in names]
    colours = {k: f"C{i % 10}" for i, k in enumerate(names)}
    for i, ((f, d), lab) in enumerate(zip(data, labels)):
        few = len(f) < 100
        for name, (unit, re, im, coh) in d.items():
            mag = [math.hypot(x, y) for x, y in zip(re, im)]
            ph = [math.degrees(math.atan2(y, x)) for x, y in zip(re, im)]
            kw = dict(color=colours[name], ls=styles[i % 4], lw=1.2, marker="o" if few else None, ms=3)
            ax[0].semilogy(f, mag, label=f"{name} ({lab})", **kw)
            ax[1].plot(f, ph, **kw)
            if coh is not None:
                ax[2].plot(f, coh, **kw)
    unit = plotlib.unit_label(next(iter(data[0][1].values()))[0].replace("_per_", "/"))
    ax[0].set_ylabel(f"|H| [{unit}]")
    ax[1].set_ylabel("phase [°]")
    ax[1].set_ylim(-185, 185)
    if has_coh:
        ax[2].set_ylabel("coherence")
        ax[2].set_ylim(0, 1.05)
    ax[-1].set_xlabel("frequency [Hz]")
    ax[0].legend(fontsize=8, ncol=2)
    for x in ax:
        x.grid(True, which="both", alpha=0.3)
    fig.suptitle(plotlib.scenario_title(os.path.dirname(os.path.abspath(a.files[0])), "Measured") +
                 ": frequency response functions")
    fig.tight_layout()
    out = a.out or os.path.join(os.path.dirname(os.path.abspath(a.files[0])), "frf.png")
    plotlib.save(fig, out, "plot_frf", dpi=120)


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Stabilization diagram of `viaduct modal-fit`.

Usage: scripts/plot/plot_stabilization.py DIR [--frf FRF.csv] [--out FILE]

Reads DIR/stabilization.csv (every physical pole of every LSCF order, with its status) and
DIR/modes.csv; draws the poles against frequency and model order (o new, + frequency stable,
filled: frequency and damping stable), the selected LSCF modes as vertical lines, and, with
--frf, the sum of the FRF magnitudes behind them. Writes DIR/stabilization.png.
"""
import csv
import math
import os
import sys

from matplotlib.ticker import MaxNLocator  # noqa: E402

import plotlib  # noqa: E402

plt = plotlib.pyplot()

rows_of = plotlib.rows_reader("plot_stabilization", "modal-fit")


def main():
    ap = plotlib.dir_parser(__doc__)
    ap.add_argument("--frf")
    ap.add_argument("--out")
    a = plotlib.parse_dir(ap, "plot_stabilization")
    poles = rows_of(os.path.join(a.dir, "stabilization.csv"))
    modes = [m for m in rows_of(os.path.join(a.dir, "modes.csv")) if m["method"] == "lscf"]
    fig, ax = plt.subplots(figsize=(9, 5))
    marks = {"new": dict(marker="o", mfc="none", color="0.6", ms=4, label="new"),
             "frequency": dict(marker="+", color="tab:orange", ms=6, label="f stable"),
             "stable": dict(marker="o", color="tab:green", ms=5, label="f and ζ stable")}
    for st, kw in marks.items():
        sel = [p for p in poles if p["status"] == st]
        if sel:
            ax.plot([float(p["frequency_hz"]) for p in sel], [int(p["order"]) for p in sel], ls="none", **kw)
    for i, m in enumerate(modes):
        f = float(m["frequency_hz"])
        ax.axvline(f, color=f"C{(i + 3) % 10}", lw=0.9, alpha=0.8,
                   label=f"mode {m['mode']}: {f:.4f} Hz, " + (f"ζ {100 * z:.2f} %" if (z := plotlib.number(m['damping_ratio'])) is not None
                                                                else "ζ not determined"))
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("model order")
    ax.yaxis.set_major_locator(MaxNLocator(integer=True))  # orders are whole numbers
    ax.legend(loc="lower right", fontsize=8)
    if a.frf:
        with open(a.frf, newline="") as f:
            rows = list(csv.DictReader(f))
        fr = [float(r["frequency_hz"]) for r in rows]
        cols = [c for c in rows[0] if "_re_" in c]
        s = [sum(math.hypot(float(r[c]), float(r[c.replace("_re_", "_im_")])) for c in cols) for r in rows]
        ax2 = ax.twinx()
        ax2.semilogy(fr, s, color="tab:blue", lw=1, alpha=0.6)
        ax2.set_ylabel("Σ |H|", color="tab:blue")
    ax.grid(True, alpha=0.3)
    ax.set_title(plotlib.scenario_title(a.dir, "modal fit") + ": LSCF stabilization diagram")
    fig.tight_layout()
    out = a.out or os.path.join(a.dir, "stabilization.png")
    plotlib.save(fig, out, "plot_stabilization", dpi=120)


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Rainflow range histogram and damage from `viaduct fatigue`.

Usage: scripts/plot/plot_fatigue.py DIR [--out FILE]

Reads DIR/cycles.csv (the range-mean matrix, long format) and DIR/damage.csv; draws, per channel,
the cycles per range bin (log scale: the few large ranges that do the damage stay visible) and
each range bin's share of sum(n * range^3) (slope 3 without the cut-off: an illustration of where
the damage sits; damage.csv's D is summed over the exact cycles against the real curve); and the
rainflow matrix (cycles per range and mean bin, log colour) of the channel with the largest damage,
named. Writes DIR/fatigue.png.
"""
import argparse
import math
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import plotlib  # noqa: E402


def rows_of(path):
    return plotlib.rows(path, "plot_fatigue", "fatigue")


def draw_matrix(fig, ax, cycles, damage):
    """The rainflow matrix of the channel with the largest damage: cycles per range and mean bin
    on the bins' regular grid (cycles.csv lists only the bins that hold cycles)."""
    def d_of(d):
        x = plotlib.number(d["damage"])
        return x if x is not None and math.isfinite(x) else 0.0
    counted = {r["channel"] for r in cycles}
    ranked = [d for d in damage if d["channel"] in counted]
    if not ranked:  # no channel with a cycle: nothing to draw
        ax.set_axis_off()
        return
    worst = max(ranked, key=d_of)["channel"]
    cells = [(float(r["range_low_mpa"]), float(r["range_high_mpa"]), float(r["mean_low_mpa"]),
              float(r["mean_high_mpa"]), float(r["count"])) for r in cycles if r["channel"] == worst]
    wr, wm = cells[0][1] - cells[0][0], cells[0][3] - cells[0][2]
    r0, m0 = min(c[0] for c in cells), min(c[2] for c in cells)
    nr = round((max(c[1] for c in cells) - r0) / wr)
    nm = round((max(c[3] for c in cells) - m0) / wm)
    grid = [[float("nan")] * nr for _ in range(nm)]
    for lo_r, _, lo_m, _, n in cells:
        i, j = round((lo_m - m0) / wm), round((lo_r - r0) / wr)
        grid[i][j] = n if math.isnan(grid[i][j]) else grid[i][j] + n
    mesh = ax.pcolormesh([r0 + k * wr for k in range(nr + 1)], [m0 + k * wm for k in range(nm + 1)], grid,
                         norm=matplotlib.colors.LogNorm(), cmap="viridis", shading="flat")
    fig.colorbar(mesh, ax=ax, label="cycles per bin (log; blank: none)")
    ax.set_xlabel("stress range [MPa]")
    ax.set_ylabel("mean stress [MPa]")
    ax.set_title(f"rainflow matrix of {worst} (largest D)", fontsize=9)
    ax.grid(True, alpha=0.3)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dir")
    ap.add_argument("--out")
    a = ap.parse_args()
    plotlib.check_outputs(a.dir, "plot_fatigue")
    cycles = rows_of(os.path.join(a.dir, "cycles.csv"))
    damage = rows_of(os.path.join(a.dir, "damage.csv"))
    if not cycles or not damage:
        sys.exit("plot_fatigue.py: no cycles to draw")
    fig, ax = plt.subplots(1, 3, figsize=(15.5, 4.4))
    lines = []
    for i, d in enumerate(damage):
        ch = d["channel"]
        per_bin = {}
        for r in cycles:
            if r["channel"] != ch:
                continue
            key = (float(r["range_low_mpa"]), float(r["range_high_mpa"]))
            per_bin[key] = per_bin.get(key, 0.0) + float(r["count"])
        if not per_bin:
            continue
        bins = sorted(per_bin)
        width = bins[0][1] - bins[0][0]
        mids = [0.5 * (lo + hi) for lo, hi in bins]
        c = f"C{i % 10}"
        ax[0].bar(mids, [per_bin[b] for b in bins], width=0.9 * width, color=c, alpha=0.7, label=ch)
        ax[0].axvline(float(d["max_range_mpa"]), color=c, ls="--", lw=1)
        # Each bin's share of Σ n·Δσ³ (slope 3 everywhere, no cut-off): a picture of where the
        # damage sits; the curve's slope 5 and cut-off are in damage.csv's D.
        w = [per_bin[b] * m ** 3 for b, m in zip(bins, mids)]
        total = sum(w) or 1.0
        ax[1].plot(mids, [100 * x / total for x in w], "o-", ms=3, color=c, label=ch)
        dmg = plotlib.number(d["damage"])
        years = plotlib.number(d["years_to_d1_at_record_rate"])
        lines.append(f"{ch}: D = {dmg:.3g}" + (f", {years:.3g} years to D = 1 at this record's rate" if years is not None and math.isfinite(years) else ""))
    draw_matrix(fig, ax[2], cycles, damage)
    ax[0].set_yscale("log")
    ax[0].set_xlabel("stress range [MPa] (dashed: the largest, factored)")
    ax[0].set_ylabel("cycles per bin")
    ax[1].set_xlabel("stress range [MPa]")
    ax[1].set_ylabel("share of Σ n·Δσ³ by range [%]")
    for x in ax[:2]:
        x.grid(True, alpha=0.3)
        x.legend(fontsize=8)
    title = plotlib.scenario_title(a.dir, "Fatigue") + f": rainflow cycles against {damage[0]['curve']}"
    fig.suptitle(title + "\n" + "; ".join(lines), fontsize=10)
    fig.tight_layout()
    plotlib.save(fig, a.out or os.path.join(a.dir, "fatigue.png"), "plot_fatigue")


if __name__ == "__main__":
    main()

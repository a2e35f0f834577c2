#!/usr/bin/python3
"""Rainflow range histogram and damage from `viaduct fatigue`.

Usage: scripts/plot/plot_fatigue.py DIR [--out FILE]

Reads DIR/cycles.csv (the range-mean matrix, long format) and DIR/damage.csv; draws, per channel
(per train of a traffic mix, `viaduct fatigue --mix`), the cycles per range bin (log scale: the
few large ranges that do the damage stay visible); for a record, each range bin's share of
sum(n * range^3) (slope 3 without the cut-off: an illustration of where the damage sits;
damage.csv's D is summed over the exact cycles against the real curve), for a mix the damage a
year of each train type with its share; and the rainflow matrix (cycles per range and mean bin,
log colour) of the channel or train with the largest damage, named. Writes DIR/fatigue.png.
"""
import math
import os
import sys

import matplotlib

import plotlib  # noqa: E402

plt = plotlib.pyplot()

rows_of = plotlib.rows_reader("plot_fatigue", "fatigue")


def damage_of(d):
    """A damage.csv row's damage: of the record, or of a year of the mix (0 when empty)."""
    x = plotlib.number(d["damage"] if "damage" in d else d["damage_per_year"])
    return x if x is not None and math.isfinite(x) else 0.0


def draw_matrix(fig, ax, cycles, damage, key):
    """The rainflow matrix of the channel (train) with the largest damage: cycles per range and
    mean bin on the bins' regular grid (cycles.csv lists only the bins that hold cycles)."""
    counted = {r[key] for r in cycles}
    ranked = [d for d in damage if d[key] in counted]
    if not ranked:  # no channel with a cycle: nothing to draw
        ax.set_axis_off()
        return
    worst = max(ranked, key=damage_of)[key]
    cells = [(float(r["range_low_mpa"]), float(r["range_high_mpa"]), float(r["mean_low_mpa"]),
              float(r["mean_high_mpa"]), float(r["count"])) for r in cycles if r[key] == worst]
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


def draw_per_train(ax, damage, total):
    """The damage a year of each train type of a mix, with its share of the total."""
    names = [d["train"] for d in damage]
    per_year = [damage_of(d) for d in damage]
    whole = damage_of(total) or 1.0
    bars = ax.bar(range(len(names)), per_year, color=[f"C{i % 10}" for i in range(len(names))], alpha=0.8)
    for b, v, d in zip(bars, per_year, damage):
        label = f"{100 * v / whole:.0f} %" if d["message"] == "" else "failed"
        ax.annotate(label, (b.get_x() + b.get_width() / 2, v), ha="center", va="bottom", fontsize=7)
    ax.set_xticks(range(len(names)))
    ax.set_xticklabels(names, rotation=45, ha="right", fontsize=8)
    ax.set_ylabel("damage a year [-]")
    ax.set_title("damage a year by train type (share of the mix's)", fontsize=9)
    ax.grid(True, axis="y", alpha=0.3)


def main():
    ap = plotlib.dir_parser(__doc__)
    ap.add_argument("--out")
    a = plotlib.parse_dir(ap, "plot_fatigue")
    cycles = rows_of(os.path.join(a.dir, "cycles.csv"))
    damage = rows_of(os.path.join(a.dir, "damage.csv"))
    if not cycles or not damage:
        sys.exit("plot_fatigue.py: no cycles to draw")
    key = "train" if "train" in damage[0] else "channel"
    total = [d for d in damage if key == "train" and d["train"] == "total"]
    damage = [d for d in damage if d not in total]
    fig, ax = plt.subplots(1, 3, figsize=(15.5, 4.4))
    lines = []
    for i, d in enumerate(damage):
        ch = d[key]
        per_bin = {}
        for r in cycles:
            if r[key] != ch:
                continue
            k = (float(r["range_low_mpa"]), float(r["range_high_mpa"]))
            per_bin[k] = per_bin.get(k, 0.0) + float(r["count"])
        if not per_bin:
            continue
        bins = sorted(per_bin)
        width = bins[0][1] - bins[0][0]
        mids = [0.5 * (lo + hi) for lo, hi in bins]
        c = f"C{i % 10}"
        ax[0].bar(mids, [per_bin[b] for b in bins], width=0.9 * width, color=c, alpha=0.7, label=ch)
        ax[0].axvline(float(d["max_range_mpa"]), color=c, ls="--", lw=1)
        if total:
            continue
        # Each bin's share of Σ n·Δσ³ (slope 3 everywhere, no cut-off): a picture of where the
        # damage sits; the curve's slope 5 and cut-off are in damage.csv's D.
        w = [per_bin[b] * m ** 3 for b, m in zip(bins, mids)]
        weight = sum(w) or 1.0
        ax[1].plot(mids, [100 * x / weight for x in w], "o-", ms=3, color=c, label=ch)
        dmg = plotlib.number(d["damage"])
        years = plotlib.number(d["years_to_d1_at_record_rate"])
        lines.append(f"{ch}: D = {dmg:.3g}" + (f", {years:.3g} years to D = 1 at this record's rate" if years is not None and math.isfinite(years) else ""))
    if total:
        draw_per_train(ax[1], damage, total[0])
        years = plotlib.number(total[0]["years_to_d1"])
        lines.append(f"D = {damage_of(total[0]):.3g} a year" + (f", {years:.3g} years to D = 1" if years is not None else ""))
    draw_matrix(fig, ax[2], cycles, damage, key)
    ax[0].set_yscale("log")
    ax[0].set_xlabel("stress range [MPa] (dashed: the largest, factored)")
    ax[0].set_ylabel("cycles per bin" + (" (one passage)" if total else ""))
    ax[0].grid(True, alpha=0.3)
    ax[0].legend(fontsize=7 if total else 8, ncol=2 if len(damage) > 6 else 1)
    if not total:
        ax[1].set_xlabel("stress range [MPa]")
        ax[1].set_ylabel("share of Σ n·Δσ³ by range [%]")
        ax[1].grid(True, alpha=0.3)
        ax[1].legend(fontsize=8)
    what = plotlib.manifest(a.dir).get("run", {}).get("mix", "") if total else ""
    title = plotlib.scenario_title(a.dir, "Fatigue") + (f", {what}" if what else "") + f": rainflow cycles against {damage[0]['curve']}"
    fig.suptitle(title + "\n" + "; ".join(lines), fontsize=10)
    fig.tight_layout()
    plotlib.save(fig, a.out or os.path.join(a.dir, "fatigue.png"), "plot_fatigue")


if __name__ == "__main__":
    main()

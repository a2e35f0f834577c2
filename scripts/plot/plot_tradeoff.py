#!/usr/bin/python3
"""Draw the speed/accuracy trade-off written by `viaduct tradeoff`.

Usage: scripts/plot/plot_tradeoff.py DIR [--out FILE]

Reads DIR/tradeoff.csv and writes DIR/tradeoff.png: envelope error against wall time (both
logarithmic), one panel for the filtered acceleration and one for the deflection; Newmark,
modal (with and without static correction) and unit-response rungs in distinct markers; the
Pareto front (no other rung both faster and more accurate) joined by a line. The reference rung,
whose error is zero by definition, is marked on the time axis.
"""
import argparse
import csv
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dir")
    ap.add_argument("--out")
    a = ap.parse_args()
    path = os.path.join(a.dir, "tradeoff.csv")
    if not os.path.exists(path):
        sys.exit(f"plot_tradeoff.py: {path} not found (run viaduct tradeoff first)")
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if len(rows) < 2:
        sys.exit(f"plot_tradeoff.py: {path} has no rungs")
    ref, rungs = rows[0], rows[1:]
    floor = 1e-6  # errors below this are drawn at it (log axis)

    def style(r):
        if r["superposition"] == "unit-response":
            return dict(marker="D", color="tab:purple", label="unit-response")
        if r["method"] == "ida":
            return dict(marker="v", color="tab:red", label="IDA (tolerance ladder)")
        if r["method"] == "newmark":
            return dict(marker="o", color="tab:blue", label="Newmark (dt ladder)")
        if r["static_correction"] == "true":
            return dict(marker="s", color="tab:green", label="modal + static correction")
        return dict(marker="^", color="tab:orange", label="modal")

    fig, axes = plt.subplots(1, 2, figsize=(12, 5), constrained_layout=True)
    for ax, key, title in ((axes[0], "max_acc_error", "filtered acceleration"), (axes[1], "max_disp_error", "deflection")):
        seen = set()
        pts = []
        for r in rungs:
            t, e = float(r["wall_s"]), max(float(r[key]), floor)
            st = style(r)
            lab = st.pop("label")
            ax.loglog(t, e, linestyle="none", markersize=7, label=None if lab in seen else lab, **st)
            seen.add(lab)
            ax.annotate(r["rung"], (t, e), fontsize=6, xytext=(3, 3), textcoords="offset points")
            pts.append((t, e))
        front, best = [], float("inf")
        for t, e in sorted(pts):
            if e < best:
                front.append((t, e))
                best = e
        ax.loglog([p[0] for p in front], [p[1] for p in front], "k--", linewidth=0.8, label="Pareto front")
        ax.axvline(float(ref["wall_s"]), color="grey", linewidth=0.8, linestyle=":")
        ax.text(float(ref["wall_s"]), ax.get_ylim()[0], " reference", rotation=90, fontsize=7, va="bottom", color="grey")
        ax.axhline(0.01, color="red", linewidth=0.6, linestyle=":")
        ax.set_xlabel("wall time of the sweep [s]")
        ax.set_ylabel(f"envelope error, {title} [-]")
        ax.set_title(f"{title}: error against cost")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    out = a.out or os.path.join(a.dir, "tradeoff.png")
    fig.savefig(out, dpi=130)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()

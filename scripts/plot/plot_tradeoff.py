#!/usr/bin/python3
"""Draw the speed/accuracy trade-off written by `viaduct tradeoff`.

Usage: scripts/plot/plot_tradeoff.py DIR [--out FILE]

Reads DIR/tradeoff.csv and writes DIR/tradeoff.png: envelope error against wall time (both
logarithmic), one panel for the filtered acceleration and one for the deflection; Newmark,
modal (with and without static correction) and unit-response rungs in distinct markers; the
Pareto front (no other rung both faster and more accurate) joined by a line. The reference rung,
whose error is zero by definition, is marked on the time axis.
"""
import csv
import os
import sys


import plotlib  # noqa: E402

plt = plotlib.pyplot()


def main():
    ap = plotlib.dir_parser(__doc__)
    ap.add_argument("--out")
    a = plotlib.parse_dir(ap, "plot_tradeoff")
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

    # Points carry numbers (short labels that do not pile up where rungs cost the same); the rungs
    # are listed by number beside the panels.
    number = {r["rung"]: i + 1 for i, r in enumerate(rungs)}
    fig, axes = plt.subplots(1, 3, figsize=(16, 5.4), constrained_layout=True, gridspec_kw={"width_ratios": [1, 1, 0.8]})
    for ax, key, title in ((axes[0], "max_acc_error", "filtered acceleration"), (axes[1], "max_disp_error", "deflection")):
        fig.canvas.draw()
        seen = set()
        pts = []
        for r in rungs:
            err = plotlib.number(r[key])
            if err is None:  # a rung that did not run
                continue
            t, e = float(r["wall_s"]), max(err, floor)
            st = style(r)
            lab = st.pop("label")
            ax.loglog(t, e, linestyle="none", markersize=7, label=None if lab in seen else lab, **st)
            seen.add(lab)
            pts.append((t, e, str(number[r["rung"]])))
        # Labels that do not overlap: each placed at the first of a few offsets whose box (in display
        # pixels) clears the labels already placed.
        fig.canvas.draw()
        placed = []
        for t, e, rung in sorted(pts, key=lambda p: (-p[1], p[0])):
            x, y = ax.transData.transform((t, e)) / (fig.dpi / 72.0)  # in points, as the offsets
            w, h = 4.2 * len(rung) + 2, 8
            for dx, dy in ((4, 3), (4, -11), (-w - 4, 3), (-w - 4, -11), (4, 14), (4, -22), (-w - 4, 14), (-w - 4, -22)):
                box = (x + dx, y + dy, x + dx + w, y + dy + h)
                if all(box[2] < b[0] or box[0] > b[2] or box[3] < b[1] or box[1] > b[3] for b in placed):
                    break
            placed.append(box)
            ax.annotate(rung, (t, e), fontsize=7, xytext=(dx, dy), textcoords="offset points")
        front, best = [], float("inf")
        for t, e, _ in sorted(pts):
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
    listing = axes[2]
    listing.axis("off")
    lines = ["rungs (errors: acceleration, deflection)"]
    for r in rungs:
        ea, ed = plotlib.number(r["max_acc_error"]), plotlib.number(r["max_disp_error"])
        err = "not run" if ea is None or ed is None else "%.2g, %.2g" % (ea, ed)
        lines.append("%2d  %s: %s" % (number[r["rung"]], r["rung"], err))
    listing.text(0.0, 1.0, "\n".join(lines), va="top", ha="left", fontsize=7.5, family="monospace", transform=listing.transAxes)
    fig.suptitle(plotlib.scenario_title(a.dir) + ": accuracy against wall time")
    out = a.out or os.path.join(a.dir, "tradeoff.png")
    plotlib.save(fig, out, "plot_tradeoff", dpi=130)


if __name__ == "__main__":
    main()

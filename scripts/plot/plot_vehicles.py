#!/usr/bin/python3
"""Draw what the vehicles did in a `viaduct run` with train.vehicle = sprung or multibody.

Usage: scripts/plot/plot_vehicles.py DIR [--out FILE]

Reads DIR/vehicles.csv and DIR/contact.csv and writes DIR/vehicles.png: the contact force of
every axle against time over its static load (the axle with the largest unloading drawn out and
named, the zero line marked: below it the wheel would have lifted), the smallest and largest
contact force per axle, and the car bodies' accelerations (the largest named).
"""
import csv
import os


import plotlib  # noqa: E402

plt = plotlib.pyplot()
import numpy as np  # noqa: E402


def label(ax, xlabel, ylabel, title, zero=False, legend=True):
    """An axis's labels, title, legend and grid (and the zero line of a force)."""
    if zero:
        ax.axhline(0.0, color="k", lw=0.8, ls="--")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    if legend:
        ax.legend(fontsize=8, loc="upper right")
    ax.grid(alpha=0.3)


def main():
    ap = plotlib.dir_parser(__doc__)
    ap.add_argument("--out", help="output PNG (default DIR/vehicles.png)")
    a = plotlib.parse_dir(ap, "plot_vehicles")
    path = os.path.join(a.dir, "vehicles.csv")
    header, data = plotlib.numeric_table(path, "plot_vehicles", "viaduct run with train.vehicle = sprung or multibody writes it")
    t = data[:, 0]
    contact = [i for i, n in enumerate(header) if n.endswith("_contact_N")]
    bodies = [i for i, n in enumerate(header) if n.endswith("_acc_mps2")]
    with open(os.path.join(a.dir, "contact.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    static = np.array([float(r["static_N"]) for r in rows])
    lo = np.array([float(r["min_N"]) for r in rows])
    hi = np.array([float(r["max_N"]) for r in rows])
    worst = int(np.argmax((static - lo) / static))
    fig, axes = plt.subplots(3, 1, figsize=(12, 9.5))
    ax = axes[0]
    ratio = data[:, contact] / static[np.newaxis, :]
    ax.plot(t, ratio, lw=0.4, color="0.65")
    ax.plot(t, ratio[:, worst], lw=1.0, color="C3",
            label="%s: min %.2f, max %.2f of its static load" % (rows[worst]["axle"], lo[worst] / static[worst], hi[worst] / static[worst]))
    label(ax, "time [s]", "contact force / static load [-]", "contact force of every axle (grey)", zero=True)
    ax = axes[1]
    k = np.arange(1, len(rows) + 1)
    ax.vlines(k, lo / 1e3, hi / 1e3, color="C0", lw=2.0)
    ax.plot(k, static / 1e3, "k_", ms=10, label="static load")
    lost = lo < 0.0
    if lost.any():
        ax.plot(k[lost], lo[lost] / 1e3, "v", color="C3", label="would have lifted (%d of %d axles)" % (lost.sum(), len(rows)))
    label(ax, "axle (from the head)", "contact force [kN]", "smallest and largest contact force per axle", zero=True)
    ax = axes[2]
    if bodies:
        peak = [np.abs(data[:, i]).max() for i in bodies]
        top = bodies[int(np.argmax(peak))]
        for i in bodies:
            ax.plot(t, data[:, i], lw=0.4, color="0.65")
        ax.plot(t, data[:, top], lw=1.0, color="C2", label="%s: max |a| = %.3f m/s²" % (header[top][: -len("_acc_mps2")], max(peak)))
    label(ax, "time [s]", "car-body acceleration [m/s²]", "car-body vertical acceleration, unfiltered (grey: every body)",
          legend=bool(bodies))
    fig.suptitle(plotlib.scenario_title(a.dir) + plotlib.run_case(a.dir) + " — vehicles")
    fig.tight_layout()
    plotlib.save(fig, a.out or os.path.join(a.dir, "vehicles.png"), "plot_vehicles")


if __name__ == "__main__":
    main()

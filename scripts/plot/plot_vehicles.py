#!/usr/bin/python3
"""Draw what the vehicles did in a `viaduct run` with train.vehicle = sprung or multibody.

Usage: scripts/plot/plot_vehicles.py DIR [--out FILE]

Reads DIR/vehicles.csv and DIR/contact.csv and writes DIR/vehicles.png: the contact force of
every axle against time over its static load (the axle with the largest unloading drawn out and
named, the zero line marked: below it the wheel would have lifted), the smallest and largest
contact force per axle, and the car bodies' accelerations (the largest named).
"""
import argparse
import csv
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import plotlib  # noqa: E402
import numpy as np  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dir")
    ap.add_argument("--out", help="output PNG (default DIR/vehicles.png)")
    a = ap.parse_args()
    plotlib.check_outputs(a.dir, "plot_vehicles")
    path = os.path.join(a.dir, "vehicles.csv")
    if not os.path.exists(path):
        sys.exit("plot_vehicles: %s not found (viaduct run with train.vehicle = sprung or multibody writes it)" % path)
    with open(path, newline="") as f:
        header = next(csv.reader(f))
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
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
    ax.axhline(0.0, color="k", lw=0.8, ls="--")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("contact force / static load [-]")
    ax.set_title("contact force of every axle (grey)")
    ax.legend(fontsize=8, loc="upper right")
    ax.grid(alpha=0.3)
    ax = axes[1]
    k = np.arange(1, len(rows) + 1)
    ax.vlines(k, lo / 1e3, hi / 1e3, color="C0", lw=2.0)
    ax.plot(k, static / 1e3, "k_", ms=10, label="static load")
    lost = lo < 0.0
    if lost.any():
        ax.plot(k[lost], lo[lost] / 1e3, "v", color="C3", label="would have lifted (%d of %d axles)" % (lost.sum(), len(rows)))
    ax.axhline(0.0, color="k", lw=0.8, ls="--")
    ax.set_xlabel("axle (from the head)")
    ax.set_ylabel("contact force [kN]")
    ax.set_title("smallest and largest contact force per axle")
    ax.legend(fontsize=8, loc="upper right")
    ax.grid(alpha=0.3)
    ax = axes[2]
    if bodies:
        peak = [np.abs(data[:, i]).max() for i in bodies]
        top = bodies[int(np.argmax(peak))]
        for i in bodies:
            ax.plot(t, data[:, i], lw=0.4, color="0.65")
        ax.plot(t, data[:, top], lw=1.0, color="C2", label="%s: max |a| = %.3f m/s²" % (header[top][: -len("_acc_mps2")], max(peak)))
        ax.legend(fontsize=8, loc="upper right")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("car-body acceleration [m/s²]")
    ax.set_title("car-body vertical acceleration, unfiltered (grey: every body)")
    ax.grid(alpha=0.3)
    run = plotlib.manifest(a.dir).get("run", {})
    case = ""
    if "train" in run and "speed_kmh" in run:
        case = ": %s at %.1f km/h" % (run["train"], float(run["speed_kmh"]))
    fig.suptitle(plotlib.scenario_title(a.dir) + case + " — vehicles")
    fig.tight_layout()
    plotlib.save(fig, a.out or os.path.join(a.dir, "vehicles.png"), "plot_vehicles")


if __name__ == "__main__":
    main()

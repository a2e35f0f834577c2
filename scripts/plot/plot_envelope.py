#!/usr/bin/python3
"""Draw maximum-response envelopes written by `viaduct sweep`.

Usage: scripts/plot/plot_envelope.py DIR [--quantity acc|disp] [--limit 3.5] [--out FILE]

Reads DIR/envelope.csv (and DIR/failures.csv if present) and writes DIR/envelope.png
(envelope_disp.png for displacements). Layout:
  - parameter variants ("Kp x0.5", ...): one column per varied parameter (the reference curve in
    each), one row per station;
  - several trains and one variant: one panel per station, one curve per train and their envelope.
The ballasted-deck acceleration limit (3.5 m/s², EN 1990 A2) is drawn as a line.
"""
import argparse
import collections
import csv
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def group_of(variant):
    if variant == "reference" or ", " in variant or " x" not in variant:
        return None
    return variant.rsplit(" x", 1)[0]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dir")
    ap.add_argument("--quantity", choices=["acc", "disp"], default="acc")
    ap.add_argument("--limit", type=float, default=3.5, help="acceleration limit line [m/s²] (0: none)")
    ap.add_argument("--out", help="output PNG (default DIR/envelope.png)")
    a = ap.parse_args()
    env = os.path.join(a.dir, "envelope.csv")
    if not os.path.exists(env):
        sys.exit("plot_envelope: %s not found (run viaduct sweep first)" % env)
    rows = read(env)
    if not rows:
        sys.exit("plot_envelope: %s has no rows" % env)
    col = "max_abs_acc_mps2" if a.quantity == "acc" else "max_abs_disp_m"
    scale = 1.0 if a.quantity == "acc" else 1e3
    ylabel = "max |filtered acceleration| [m/s²]" if a.quantity == "acc" else "max |deflection| [mm]"

    stations = list(dict.fromkeys(r["station"] for r in rows))
    variants = list(dict.fromkeys(r["variant"] for r in rows))
    trains = list(dict.fromkeys(r["train"] for r in rows))
    # curve key -> speed -> value (max over trains when curves are variants)
    data = collections.defaultdict(dict)
    by_variant = len(variants) > 1
    for r in rows:
        key = (r["station"], r["variant"] if by_variant else r["train"])
        v = float(r["speed_kmh"])
        data[key][v] = max(data[key].get(v, 0.0), float(r[col]) * scale)

    if by_variant:
        groups = list(dict.fromkeys(g for g in (group_of(v) for v in variants) if g)) or ["variants"]
        members = {g: ["reference"] + [v for v in variants if group_of(v) == g] for g in groups}
        if groups == ["variants"]:
            members = {"variants": variants}
    else:
        groups = ["trains"]
        members = {"trains": trains}

    nr, nc = len(stations), len(groups)
    fig, axes = plt.subplots(nr, nc, figsize=(4.2 * nc + 1, 3.0 * nr + 0.8), squeeze=False, sharex=True, sharey=True)
    ymax = 0.0
    for i, st in enumerate(stations):
        for j, g in enumerate(groups):
            ax = axes[i][j]
            for name in members[g]:
                curve = data.get((st, name))
                if not curve:
                    continue
                xs = sorted(curve)
                ys = [curve[x] for x in xs]
                ymax = max(ymax, max(ys))
                ref = name == "reference"
                # reference underneath (wide, grey) so that variants close to it stay visible
                ax.plot(xs, ys, lw=4.0 if ref else 1.3, color="0.65" if ref else None, label=name, zorder=1 if ref else 2)
            if not by_variant and len(trains) > 1:
                allx = sorted({x for t in trains for x in data.get((st, t), {})})
                envl = [max(data[(st, t)].get(x, 0.0) for t in trains) for x in allx]
                ax.plot(allx, envl, color="k", lw=2.4, label="envelope", zorder=4)
            if a.quantity == "acc" and a.limit > 0:
                ax.axhline(a.limit, color="crimson", ls="--", lw=1.2, label="%.1f m/s² limit" % a.limit)
            ax.grid(alpha=0.3)
            if i == 0:
                ax.set_title(g if by_variant else "trains")
            if j == 0:
                ax.set_ylabel("%s\n%s" % (st, ylabel), fontsize=9)
            if i == nr - 1:
                ax.set_xlabel("speed [km/h]")
            if i == 0:
                ax.legend(fontsize=7, ncol=2 if len(members[g]) > 6 else 1)
    top = ymax * 1.08
    if a.quantity == "acc" and a.limit > 0:
        top = max(top, a.limit * 1.12)
    axes[0][0].set_ylim(0, top)

    fail = os.path.join(a.dir, "failures.csv")
    n_fail = len(read(fail)) if os.path.exists(fail) else 0
    title = "Maximum-response envelopes (%s)" % os.path.basename(os.path.normpath(a.dir))
    if by_variant and len(trains) > 1:
        title += ", max over %d trains" % len(trains)
    if n_fail:
        title += " — %d failed cases, see failures.csv" % n_fail
    fig.suptitle(title)
    fig.tight_layout()
    out = a.out or os.path.join(a.dir, "envelope.png" if a.quantity == "acc" else "envelope_disp.png")
    fig.savefig(out, dpi=110)
    print("wrote", out)


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Figures of a `viaduct assess` report.

Usage: scripts/plot/plot_assess.py DIR [--dpi 110]

Reads DIR/envelope.csv, DIR/phi_dyn.csv and DIR/manifest.toml (the acceleration limit) and writes
  - DIR/acc_vs_speed.png: peak deck acceleration against speed, one curve per train (the worst
    station and mass case at each speed), the limit as a red line with its clause;
  - DIR/envelope.png: the envelope over trains and masses per station, each resonance peak named
    with its governing train, speed and mass case;
  - DIR/phi_dyn.png: the largest dynamic increment phi'dyn per quantity, with its train.
viaduct assess runs it itself when Python with matplotlib is there; report.md links the figures.
"""
import collections
import csv
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plotlib  # noqa: E402

plt = plotlib.pyplot()
from plot_envelope import peaks_of  # noqa: E402


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def acc_limit(directory):
    run = plotlib.manifest(directory).get("run", {})
    try:
        return float(run.get("acceleration_limit_mps2", 3.5))
    except (TypeError, ValueError):
        return 3.5


def acc_vs_speed(rows, limit, title, path, dpi):
    # Per (train, mass case) the worst station at each of its speeds; per train the worst mass case,
    # each case's curve interpolated on the speeds of all (each is refined around its own resonances).
    cases = collections.OrderedDict()
    for r in rows:
        c = cases.setdefault(r["train"], collections.OrderedDict()).setdefault(r["variant"], {})
        v = float(r["speed_kmh"])
        c[v] = max(c.get(v, 0.0), float(r["max_abs_acc_mps2"]))
    per_train = collections.OrderedDict()
    for train, by_mass in cases.items():
        grid = sorted({v for c in by_mass.values() for v in c})
        curve = per_train.setdefault(train, {})
        for c in by_mass.values():
            cx = sorted(c)
            cy = [c[x] for x in cx]
            for v in grid:
                if cx[0] <= v <= cx[-1]:
                    curve[v] = max(curve.get(v, 0.0), float(np.interp(v, cx, cy)))
    fig, ax = plt.subplots(figsize=(10, 5.5))
    cmap = plt.get_cmap("tab20")
    worst = (0.0, None, None)
    for i, (train, curve) in enumerate(per_train.items()):
        xs = sorted(curve)
        ys = [curve[x] for x in xs]
        ax.plot(xs, ys, lw=1.1, color=cmap(i % 20), label=train)
        top = max(ys)
        if top > worst[0]:
            worst = (top, train, xs[ys.index(top)])
    ax.axhline(limit, color="red", lw=1.5, ls="--", label="limit %.1f m/s² (EN 1990 A2.4.4.2.1(4))" % limit)
    if worst[1]:
        ax.annotate("%s: %.2f m/s² at %.0f km/h" % (worst[1], worst[0], worst[2]),
                    xy=(worst[2], worst[0]), xytext=(-6, 6), textcoords="offset points", ha="right", fontsize=9)
    ax.set_xlabel("speed [km/h]")
    ax.set_ylabel("peak deck acceleration [m/s²] (filtered to the cut-off)")
    ax.set_title("%s\npeak deck acceleration, every train (worst station and mass case)" % title)
    ax.grid(alpha=0.3)
    ax.set_ylim(0, max(worst[0], limit) * 1.15)
    ax.legend(fontsize=8, ncol=2, loc="upper left")
    fig.tight_layout()
    plotlib.save(fig, path, "plot_assess", dpi)
    plt.close(fig)


def envelope(rows, limit, title, path, dpi):
    stations = list(collections.OrderedDict.fromkeys(r["station"] for r in rows))
    speeds = np.array(sorted({float(r["speed_kmh"]) for r in rows}))
    fig, axes = plt.subplots(len(stations), 1, figsize=(10, 3.6 * len(stations)), squeeze=False)
    for ax, st in zip(axes[:, 0], stations):
        # Each (train, mass case) curve, then the envelope on every speed of any of them with each
        # curve interpolated there: they run at different speeds (each refined around its own
        # resonances), so a speed one of them skipped is not a dip.
        curves = collections.OrderedDict()
        for r in rows:
            if r["station"] != st:
                continue
            c = curves.setdefault((r["train"], r["variant"]), {})
            c[float(r["speed_kmh"])] = (float(r["max_abs_acc_mps2"]), r["variant"])
        # Each curve on the speeds within its range at once (a call of np.interp per speed and
        # curve took 1.3 s of Old Guadiana's 1.8 s); the first curve to reach a speed, then any
        # larger, holds it, as the curves are taken in order.
        a_best = np.zeros(len(speeds))
        who = np.full(len(speeds), -1)
        keys = list(curves)
        for n, key in enumerate(keys):
            c = curves[key]
            cx = sorted(c)
            cy = [c[x][0] for x in cx]
            inside = (speeds >= cx[0]) & (speeds <= cx[-1])
            a = np.full(len(speeds), np.nan)
            a[inside] = np.interp(speeds[inside], cx, cy)
            take = inside & ((who < 0) | (a > a_best))
            a_best[take], who[take] = a[take], n
        best = {float(v): (float(a_best[i]),) + keys[who[i]] for i, v in enumerate(speeds) if who[i] >= 0}
        xs = sorted(best)
        ys = [best[x][0] for x in xs]
        ax.plot(xs, ys, color="black", lw=1.4, label="envelope over trains and masses")
        for i in peaks_of(xs, ys):
            a, train, variant = best[xs[i]]
            ax.plot(xs[i], a, "o", color="black", ms=4)
            ax.annotate("%s\n%.0f km/h, %s" % (train, xs[i], variant), xy=(xs[i], a), xytext=(0, 6),
                        textcoords="offset points", ha="center", fontsize=8)
        ax.axhline(limit, color="red", lw=1.5, ls="--", label="limit %.1f m/s²" % limit)
        ax.set_ylim(0, max(max(ys), limit) * 1.25)
        ax.set_ylabel("%s: acceleration [m/s²]" % st)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="upper left")
    axes[-1, 0].set_xlabel("speed [km/h]")
    axes[0, 0].set_title("%s\nenvelope of peak deck acceleration, governing train at each peak" % title)
    fig.tight_layout()
    plotlib.save(fig, path, "plot_assess", dpi)
    plt.close(fig)


def phi_dyn(rows, title, path, dpi):
    top = collections.OrderedDict()
    for r in rows:
        phi = plotlib.number(r["phi_dyn"])
        if phi is None:
            continue
        q = r["quantity"]
        if q not in top or phi > top[q][0]:
            top[q] = (phi, r["train"], float(r["speed_kmh"]))
    if not top:
        return
    names = list(top)
    fig, ax = plt.subplots(figsize=(10, 0.45 * len(names) + 1.8))
    ax.barh(range(len(names)), [top[n][0] for n in names], color="#4477aa")
    for i, n in enumerate(names):
        ax.annotate(" %.2f  %s, %.0f km/h" % top[n], xy=(max(top[n][0], 0), i), va="center", fontsize=8)
    ax.set_yticks(range(len(names)))
    ax.set_yticklabels([plotlib.split_unit(n)[0] for n in names], fontsize=8)
    ax.invert_yaxis()
    ax.set_xlabel("φ′dyn = max|dynamic| / max|quasi-static| − 1 (EN 1991-2 6.4.6.5)")
    ax.set_title("%s\nlargest dynamic increment per quantity over trains, speeds and masses" % title)
    ax.set_xlim(min(0, min(v[0] for v in top.values())), max(v[0] for v in top.values()) * 1.45 + 1e-9)
    ax.grid(alpha=0.3, axis="x")
    fig.tight_layout()
    plotlib.save(fig, path, "plot_assess", dpi)
    plt.close(fig)


def main():
    ap = plotlib.dir_parser(__doc__)
    ap.add_argument("--dpi", type=int, default=110)
    a = plotlib.parse_dir(ap, "plot_assess")
    env, phi = os.path.join(a.dir, "envelope.csv"), os.path.join(a.dir, "phi_dyn.csv")
    for p in (env, phi):
        plotlib.need(p, "plot_assess", "assess")
    rows = read(env)
    if not rows:
        sys.exit("plot_assess: %s has no rows (every case failed?)" % env)
    title = plotlib.scenario_title(a.dir)
    limit = acc_limit(a.dir)

    def first():
        envelope(rows, limit, title, os.path.join(a.dir, "envelope.png"), a.dpi)
        phi_dyn(read(phi), title, os.path.join(a.dir, "phi_dyn.png"), a.dpi)

    def second():
        acc_vs_speed(rows, limit, title, os.path.join(a.dir, "acc_vs_speed.png"), a.dpi)
        # Stations along a span (stations[].every_m): M(x) and V(x) with the design effect.
        import plot_load_effects
        plot_load_effects.draw(a.dir, tool="plot_assess")

    in_two(first, second)


def in_two(first, second):
    """first() in a forked process while second() runs here: the report's figures on two cores (on
    Old Guadiana's assessment 1.0 s in one process; matplotlib's import, 0.4 s of it, is shared).
    Where there is no fork, one after the other. Exits non-zero when either failed."""
    if not hasattr(os, "fork"):
        first()
        second()
        return
    sys.stdout.flush()
    pid = os.fork()
    if pid == 0:
        code = 0
        try:
            first()
        except SystemExit as e:  # a script's own error (plotlib.need, sys.exit("..."))
            if e.code not in (None, 0):
                print(e.code if isinstance(e.code, str) else "plot_assess: failed", file=sys.stderr)
                code = 1
        except BaseException:
            import traceback
            traceback.print_exc()
            code = 1
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(code)
    try:
        second()
    finally:
        _, status = os.waitpid(pid, 0)
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit("plot_assess: the envelope or phi_dyn figure failed (above)")


if __name__ == "__main__":
    main()

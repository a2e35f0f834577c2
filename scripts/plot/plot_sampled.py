#!/usr/bin/python3
"""Draw the statistics of a sampled study written by `viaduct sweep` (sweep.mode = "sample").

Usage: scripts/plot/plot_sampled.py DIR [--limit 3.5] [--dpi 110]

Reads DIR/percentiles.csv (and manifest.toml) and writes DIR/sampled.png: one row per station,
  - left: the deck acceleration's percentile band against speed (the outer percentiles shaded,
    the median drawn), per train, with the limit; the largest upper percentile is named with its
    speed and train;
  - right: the probability of exceeding the limit against speed with its 95 % upper bound.
With Sobol indices (sweep.sensitivity = true) also DIR/sensitivity.png from sensitivity.csv and
peak_sensitivity.csv: per station, the total index of each key against speed (where the
acceleration is worth it: its median above a tenth of the largest), and the first-order and total
indices of the peak over the speeds with their bootstrap intervals.
"""
import collections
import csv
import os


import plotlib  # noqa: E402

plt = plotlib.pyplot()

TOOL = "plot_sampled.py"


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def pct_columns(row):
    """The acceleration percentile columns, ascending: [(p, column)]."""
    cols = [(float(c[len("acc_p"):-len("_mps2")]), c) for c in row if c.startswith("acc_p") and c.endswith("_mps2")]
    return sorted(cols)


DESIGNS = {"lhs": "Latin hypercube", "sobol": "Sobol sequence", "random": "random"}


def study_note(directory):
    """'64 samples, Sobol sequence' or '64 x 6 runs (Saltelli), Sobol sequence'."""
    sc = plotlib.manifest(directory).get("scenario", {})
    n = sc.get("sweep.n_samples")
    if not n:
        return ""
    design = DESIGNS.get(sc.get("sweep.sampling", ""), sc.get("sweep.sampling", ""))
    if sc.get("sweep.sensitivity"):
        d = len([k for k in sc if k.startswith("sweep.variants[") and k.endswith("].key")])
        return "%d x %d runs (Saltelli's design: %d independent samples), %s" % (n, d + 2, 2 * n, design)
    return "%d samples, %s" % (n, design)


def plot_percentiles(directory, rows, limit, dpi):
    cols = pct_columns(rows[0])
    by = collections.OrderedDict()
    for r in rows:
        by.setdefault(r["station"], collections.OrderedDict()).setdefault(r["train"], []).append(r)
    fig, axes = plt.subplots(len(by), 2, figsize=(12, 3.6 * len(by)), squeeze=False,
                             gridspec_kw={"width_ratios": [2, 1]})
    for (station, trains), (ax, axp) in zip(by.items(), axes):
        best = None
        for i, (train, rs) in enumerate(trains.items()):
            rs.sort(key=lambda r: float(r["speed_kmh"]))
            v = [float(r["speed_kmh"]) for r in rs]
            lo = [plotlib.number(r[cols[0][1]]) for r in rs]
            hi = [plotlib.number(r[cols[-1][1]]) for r in rs]
            mid = [plotlib.number(r[cols[len(cols) // 2][1]]) for r in rs]
            color = "C%d" % i
            spread = max((h - l for h, l in zip(hi, lo) if h is not None and l is not None), default=0.0)
            ax.fill_between(v, lo, hi, color=color, alpha=0.3, lw=0,
                            label="%s: %g–%g %% (widest %.3g m/s²)" % (train, cols[0][0], cols[-1][0], spread))
            ax.plot(v, mid, color=color, lw=1.6, label="%s: %g %%" % (train, cols[len(cols) // 2][0]))
            for r, h in zip(rs, hi):
                if h is not None and (best is None or h > best[0]):
                    best = (h, float(r["speed_kmh"]), train)
            pe = [plotlib.number(r["p_exceed"]) for r in rs]
            pu = [plotlib.number(r["p_exceed_upper95"]) for r in rs]
            axp.plot(v, pe, color=color, lw=1.4, label="%s: estimate" % train)
            axp.plot(v, pu, color=color, lw=1.0, ls="--", label="%s: 95 %% upper bound" % train)
        if limit > 0:
            ax.axhline(limit, color="red", lw=1.0, ls=":", label="limit %.3g m/s²" % limit)
        if best:
            ax.annotate("largest %g %%: %.2f m/s² at %.0f km/h (%s)" % (cols[-1][0], best[0], best[1], best[2]),
                        (best[1], best[0]), xytext=(0.98, 0.97), textcoords="axes fraction", ha="right", va="top",
                        fontsize=8, arrowprops={"arrowstyle": "->", "lw": 0.8})
            ax.set_ylim(0, 1.25 * max(best[0], limit))
        ax.set_title("%s: deck acceleration over the samples" % station)
        ax.set_xlabel("speed [km/h]")
        ax.set_ylabel("max |acceleration| [m/s²]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper left")
        axp.set_title("%s: P(max |a| > %.3g m/s²)" % (station, limit))
        axp.set_xlabel("speed [km/h]")
        axp.set_ylabel("probability [-]")
        axp.set_ylim(0, 1)
        axp.grid(alpha=0.3)
        axp.legend(fontsize=7, loc="upper left")
    note = study_note(directory)
    fig.suptitle(plotlib.scenario_title(directory) + (" — " + note if note else ""))
    fig.tight_layout()
    plotlib.save(fig, os.path.join(directory, "sampled.png"), TOOL, dpi)
    plt.close(fig)


def plot_sensitivity(directory, rows, peak_rows, dpi):
    acc = [r for r in rows if r["quantity"] == "max_abs_acc_mps2"]
    peak = [r for r in peak_rows if r["quantity"] == "max_abs_acc_mps2"]
    stations = list(collections.OrderedDict.fromkeys(r["station"] for r in acc))
    pct = read(os.path.join(directory, "percentiles.csv"))
    median_col = pct_columns(pct[0])[len(pct_columns(pct[0])) // 2][1]
    fig, axes = plt.subplots(len(stations), 2, figsize=(12, 3.6 * len(stations)), squeeze=False,
                             gridspec_kw={"width_ratios": [2, 1]})
    for station, (ax, axb) in zip(stations, axes):
        train = next(r["train"] for r in acc if r["station"] == station)  # the first train
        med = {float(r["speed_kmh"]): plotlib.number(r[median_col]) or 0.0 for r in pct
               if r["station"] == station and r["train"] == train}
        top = max(med.values()) if med else 0.0
        by_key = collections.OrderedDict()
        for r in acc:
            if r["station"] == station and r["train"] == train:
                by_key.setdefault(r["label"], []).append(r)
        for i, (label, rs) in enumerate(by_key.items()):
            rs = [r for r in rs if med.get(float(r["speed_kmh"]), 0.0) >= 0.1 * top]
            rs.sort(key=lambda r: float(r["speed_kmh"]))
            ax.plot([float(r["speed_kmh"]) for r in rs], [plotlib.number(r["ST"]) for r in rs],
                    color="C%d" % i, lw=1.4, label="%s: total index" % label)
        ax.set_title("%s (%s): which key drives the spread, per speed" % (station, train))
        ax.set_xlabel("speed [km/h]")
        ax.set_ylabel("total Sobol index of max |a| [-]")
        ax.set_ylim(0, 1.05)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
        ps = [r for r in peak if r["station"] == station and r["train"] == train]
        x = range(len(ps))
        for off, (name, lo, hi, color) in zip((-0.18, 0.18), (("S", "S_lo", "S_hi", "C0"), ("ST", "ST_lo", "ST_hi", "C3"))):
            val = [plotlib.number(r[name]) or 0.0 for r in ps]
            err = [[max(0.0, v - (plotlib.number(r[lo]) or v)) for v, r in zip(val, ps)],
                   [max(0.0, (plotlib.number(r[hi]) or v) - v) for v, r in zip(val, ps)]]
            axb.bar([i + off for i in x], val, width=0.36, color=color, yerr=err, capsize=3,
                    label="first order" if name == "S" else "total")
        axb.set_xticks(list(x))
        axb.set_xticklabels([r["label"] for r in ps])
        axb.set_title("%s: peak over the speeds (95 %% CI)" % station)
        axb.set_ylabel("Sobol index [-]")
        axb.set_ylim(0, 1.05)
        axb.grid(alpha=0.3, axis="y")
        axb.legend(fontsize=7)
    note = study_note(directory)
    fig.suptitle(plotlib.scenario_title(directory) + " — Sobol indices" + (" (" + note + ")" if note else ""))
    fig.tight_layout()
    plotlib.save(fig, os.path.join(directory, "sensitivity.png"), TOOL, dpi)
    plt.close(fig)


def main():
    ap = plotlib.dir_parser(__doc__)
    ap.add_argument("--limit", type=float, default=None, help="acceleration limit [m/s²] (default: the study's)")
    ap.add_argument("--dpi", type=int, default=110)
    a = plotlib.parse_dir(ap, "plot_sampled")
    path = os.path.join(a.dir, "percentiles.csv")
    plotlib.need(path, TOOL, "sweep on a sampled study")
    rows = read(path)
    if not rows:
        raise SystemExit("%s: %s has no rows" % (TOOL, path))
    limit = a.limit
    if limit is None:
        limit = float(plotlib.manifest(a.dir).get("scenario", {}).get("sweep.acceleration_limit_mps2", 3.5))
    plot_percentiles(a.dir, rows, limit, a.dpi)
    sens = os.path.join(a.dir, "sensitivity.csv")
    if os.path.exists(sens):
        plot_sensitivity(a.dir, read(sens), read(os.path.join(a.dir, "peak_sensitivity.csv")), a.dpi)


if __name__ == "__main__":
    main()

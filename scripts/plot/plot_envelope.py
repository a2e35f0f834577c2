#!/usr/bin/python3
"""Draw maximum-response envelopes written by `viaduct sweep`.

Usage: scripts/plot/plot_envelope.py DIR [--quantity acc|disp] [--limit 3.5] [--out FILE] [--dpi 110]

Reads DIR/envelope.csv (and failures.csv, manifest.toml if present) and writes DIR/envelope.png
(envelope_disp.png for deflections). Layout, one row of panels per station:
  - several trains, no variants: one curve per train and their envelope (black); each peak of
    the envelope is marked with the train that governs it and its speed;
  - parameter variants varied one at a time: one panel per varied key, the reference (wide,
    grey) and one curve per factor, each the maximum over the trains; the governing train is
    named at the reference's peaks;
  - a grid of variants: one panel per varied key, one curve per factor of that key, each the
    maximum over the trains and every setting of the other keys (said in the title).
The title is the scenario's; the acceleration limit is drawn with its clause (3.5 m/s²,
ballasted track, EN 1990 A2.4.4.2.1; --limit 5 for direct fastening, 0 for none).
"""
import collections
import csv
import os
import sys


import plotlib  # noqa: E402

plt = plotlib.pyplot()


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def peaks_of(xs, ys, share=0.35):
    """Indices of the local maxima of a curve above `share` of its largest value, at least 5 % of
    the speed range apart (the resonance peaks worth naming); an end of the range only when it
    holds the largest value."""
    if not ys:
        return []
    top, span = max(ys), (xs[-1] - xs[0]) or 1.0
    last = len(ys) - 1
    cand = [i for i in range(len(ys)) if ys[i] >= share * top and
            (0 < i < last and ys[i] >= ys[i - 1] and ys[i] >= ys[i + 1] or ys[i] == top)]
    cand.sort(key=lambda i: -ys[i])
    kept = []
    for i in cand:
        if all(abs(xs[i] - xs[k]) > 0.05 * span for k in kept):
            kept.append(i)
    return sorted(kept)


def layout(rows, variants):
    """(panels, title note): panels = [(panel title, [(curve label, set of variants)])]."""
    keys = [c[: -len("_factor")] for c in rows[0] if c.endswith("_factor")]
    if len(variants) < 2 or not keys:
        return None, ""
    factors, label = {}, {}
    for r in rows:
        factors[r["variant"]] = {k: float(r[k + "_factor"]) for k in keys}
    for v, fs in factors.items():  # the label a key was given ("Kp" in "Kp x0.5")
        changed = [k for k, f in fs.items() if f != 1.0]
        if len(changed) == 1 and " x" in v and ", " not in v:
            label.setdefault(changed[0], v.rsplit(" x", 1)[0])
    grid = any(sum(1 for f in fs.values() if f != 1.0) > 1 for fs in factors.values())
    panels = []
    for k in keys:
        values = sorted({fs[k] for fs in factors.values()})
        curves = []
        for val in values:
            if grid:
                members = {v for v, fs in factors.items() if fs[k] == val}
            else:  # one at a time: the variants that change only this key
                members = {v for v, fs in factors.items() if fs[k] == val and all(f == 1.0 for kk, f in fs.items() if kk != k)}
            if members:
                curves.append(("reference" if val == 1.0 and not grid else "x%g" % val, members))
        panels.append(("%s: %s" % (label[k], k) if label.get(k, k) != k else k, curves))
    note = "grid of %d variants: each curve the maximum over every setting of the other keys" % len(variants) if grid else ""
    return panels, note


def main():
    ap = plotlib.dir_parser(__doc__)
    ap.add_argument("--quantity", choices=["acc", "disp"], default="acc")
    ap.add_argument("--limit", type=float, default=3.5, help="acceleration limit line [m/s²] (0: none)")
    ap.add_argument("--out", help="output PNG (default DIR/envelope.png)")
    ap.add_argument("--dpi", type=int, default=110, help="resolution of the PNG")
    a = plotlib.parse_dir(ap, "plot_envelope")
    env = os.path.join(a.dir, "envelope.csv")
    plotlib.need(env, "plot_envelope", "sweep")
    rows = read(env)
    if not rows:
        sys.exit("plot_envelope: %s has no rows" % env)
    col = "max_abs_acc_mps2" if a.quantity == "acc" else "max_abs_disp_m"
    scale, unit = plotlib.split_unit(col)[1:]
    ylabel = ("max |filtered acceleration| [%s]" if a.quantity == "acc" else "max |deflection| [%s]") % unit

    stations = list(dict.fromkeys(r["station"] for r in rows))
    variants = list(dict.fromkeys(r["variant"] for r in rows))
    trains = list(dict.fromkeys(r["train"] for r in rows))
    # (station, variant, train) -> speed -> value
    data = collections.defaultdict(dict)
    for r in rows:
        data[(r["station"], r["variant"], r["train"])][float(r["speed_kmh"])] = float(r[col]) * scale

    def curve(st, members, train_set=None):
        """speed -> (max over members and trains, the train that gives it)."""
        out = {}
        for v in members:
            for t in train_set or trains:
                for x, y in data.get((st, v, t), {}).items():
                    if x not in out or y > out[x][0]:
                        out[x] = (y, t)
        return out

    panels, note = layout(rows, variants)
    if note:
        print(note)
    by_trains = panels is None
    if by_trains:
        panels = [("trains" if len(variants) < 2 else "variants", [(v, {v}) for v in variants] if len(variants) > 1 else [])]

    nr, nc = len(stations), len(panels)
    fig, axes = plt.subplots(nr, nc, figsize=(4.6 * nc + (3.4 if by_trains else 1.0), 3.2 * nr + 1.0), squeeze=False,
                             sharex=True, sharey=True)
    ymax = 0.0
    for i, st in enumerate(stations):
        for j, (pname, curves) in enumerate(panels):
            ax = axes[i][j]
            named = None  # the curve whose peaks get the governing train
            if by_trains and len(variants) < 2:
                for t in trains:
                    c = curve(st, variants, [t])
                    xs = sorted(c)
                    ax.plot(xs, [c[x][0] for x in xs], lw=1.1, label=t, zorder=2)
                named = curve(st, variants)
                if len(trains) > 1:
                    xs = sorted(named)
                    ax.plot(xs, [named[x][0] for x in xs], color="k", lw=2.2, label="envelope", zorder=3)
            else:
                for label, members in curves:
                    c = curve(st, members)
                    xs = sorted(c)
                    ref = label == "reference"
                    ax.plot(xs, [c[x][0] for x in xs], lw=4.0 if ref else 1.3, color="0.65" if ref else None,
                            label=label, zorder=1 if ref else 2)
                    if ref:
                        named = c
            if named:
                xs = sorted(named)
                ys = [named[x][0] for x in xs]
                ymax = max(ymax, max(ys))
                for n, k in enumerate(peaks_of(xs, ys)):
                    ax.plot(xs[k], ys[k], "v", color="k", ms=5, zorder=5)
                    text = ("%s\n" % named[xs[k]][1] if len(trains) > 1 else "") + "%.0f km/h" % xs[k]
                    ax.annotate(text, (xs[k], ys[k]), xytext=(0, 6 + 15 * (n % 3) * (len(trains) > 1)),
                                textcoords="offset points", ha="center", fontsize=6.5, zorder=6)
            for line in ax.get_lines():
                ymax = max([ymax] + list(line.get_ydata()))
            if a.quantity == "acc" and a.limit > 0:
                ax.axhline(a.limit, color="crimson", ls="--", lw=1.2, label="limit")
            ax.grid(alpha=0.3)
            if i == 0 and by_trains:
                ax.set_title("trains" if len(variants) < 2 else "variants", fontsize=10)
            if j == 0:
                ax.set_ylabel("%s\n%s" % (st, ylabel), fontsize=9)
            if i == nr - 1:
                ax.set_xlabel("speed [km/h]")
            if i == 0 and by_trains and j == nc - 1:  # the trains: one legend, outside the panel
                ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0)
            elif i == 0 and not by_trains:  # each key has its own factors: a legend as its title
                handles = [h for h in ax.get_lines() if h.get_label() not in ("limit",) and not h.get_label().startswith("_")]
                ax.legend(handles=handles, title=pname, title_fontsize=9, fontsize=7, loc="lower center",
                          bbox_to_anchor=(0.5, 1.01), ncol=min(5, len(handles)), frameon=False)
    top = ymax * (1.3 if len(trains) > 1 else 1.15)
    if a.quantity == "acc" and a.limit > 0:
        top = max(top, a.limit * 1.12)
    axes[0][0].set_ylim(0, top)

    fail = os.path.join(a.dir, "failures.csv")
    n_fail = len(read(fail)) if os.path.exists(fail) else 0
    title = plotlib.scenario_title(a.dir) + "\nmaximum-response envelopes"
    if len(trains) == 1:
        title += " under %s" % trains[0]
    if note:
        title += "\n" + note + (" and the %d trains" % len(trains) if len(trains) > 1 else "")
    elif not by_trains and len(trains) > 1:
        title += ", each curve the maximum over %d trains" % len(trains)
    if a.quantity == "acc" and a.limit > 0:
        title += "\ndashed: the %g m/s² limit of EN 1990 A2.4.4.2.1 (%s)" % (
            a.limit, "ballasted track" if a.limit == 3.5 else "direct fastening" if a.limit == 5 else "as given")
    if n_fail:
        title += " — %d failed cases, see failures.csv" % n_fail
    fig.suptitle(title, fontsize=11)
    fig.tight_layout()
    out = a.out or os.path.join(a.dir, "envelope.png" if a.quantity == "acc" else "envelope_disp.png")
    plotlib.save(fig, out, "plot_envelope", a.dpi)


if __name__ == "__main__":
    main()

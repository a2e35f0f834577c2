#!/usr/bin/python3
"""Stabilization diagram and tracked modes of `viaduct oma`.

Usage: scripts/plot/plot_oma.py DIR [--window N] [--out-prefix PREFIX]

Reads DIR/stabilization.csv, DIR/fdd.csv, DIR/modes.csv and DIR/tracked.csv. Writes
DIR/oma_stabilization.png: the SSI-COV poles of window N (default: the first) against frequency
and model order (grey: spurious or new; orange: frequency stable; green: stable in frequency
and shape, the poles clustered; filled: also in damping), the modes as lines with f, ζ and their
standard deviations, and the first singular value of the spectral matrix (FDD) behind them;
and, with more than one window, DIR/oma_tracked.png: each tracked mode's frequency and damping
against the windows' start times (± one standard deviation), and against a carried channel
(e.g. temperature) when there is one.
"""
import os
from collections import defaultdict

from matplotlib.ticker import MaxNLocator  # noqa: E402

import plotlib  # noqa: E402

plt = plotlib.pyplot()

FIXED = ["window", "record", "t_start_s", "t_end_s", "track", "frequency_hz", "damping_ratio",
         "frequency_std_hz", "damping_std", "mac_to_previous"]

rows_of = plotlib.rows_reader("plot_oma", "oma")


def stabilization(d, window, out):
    poles = [p for p in rows_of(os.path.join(d, "stabilization.csv")) if p["window"] == window]
    fdd = [r for r in rows_of(os.path.join(d, "fdd.csv")) if r["window"] == window]
    modes = [m for m in rows_of(os.path.join(d, "modes.csv")) if m["window"] == window and m["method"] == "ssi-cov"]
    fig, ax = plt.subplots(figsize=(10, 5.5))
    marks = [("spurious", dict(marker=".", color="0.75", ms=3, label="spurious (band, ζ, MPC, MPD)")),
             ("new", dict(marker="o", mfc="none", color="0.55", ms=3.5, label="new")),
             ("frequency", dict(marker="+", color="tab:orange", ms=6, label="f stable")),
             ("damping", dict(marker="x", color="tab:orange", ms=5, label="f, ζ stable")),
             ("shape", dict(marker="o", mfc="none", color="tab:green", ms=5, label="f, shape stable")),
             ("stable", dict(marker="o", color="tab:green", ms=5, label="f, ζ, shape stable"))]
    for status, kw in marks:
        sel = [p for p in poles if p["status"] == status]
        if sel:
            ax.plot([float(p["frequency_hz"]) for p in sel], [int(p["order"]) for p in sel], ls="none", **kw)
    for i, m in enumerate(modes):
        f = float(m["frequency_hz"])
        sf, z, sz = plotlib.number(m["frequency_std_hz"]), plotlib.number(m["damping_ratio"]), plotlib.number(m["damping_std"])
        label = f"mode {m['mode']}: {f:.4g}" + (f" ± {sf:.2g}" if sf is not None else "") + " Hz, ζ " + \
            (f"{100 * z:.2f}" if z is not None else "?") + (f" ± {100 * sz:.2f}" if sz is not None else "") + " %"
        if m["note"]:
            label += " (!)"
        ax.axvline(f, color=f"C{(i + 3) % 10}", lw=0.9, alpha=0.8, label=label)
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("model order")
    ax.yaxis.set_major_locator(MaxNLocator(integer=True))
    if fdd:
        ax2 = ax.twinx()
        fr = [float(r["frequency_hz"]) for r in fdd]
        sv = [plotlib.number(r["sv1"]) for r in fdd]
        keep = [(a, b) for a, b in zip(fr, sv) if b is not None and b > 0]
        physical = [float(p["frequency_hz"]) for p in poles if p["status"] != "spurious"]
        if physical:  # the band the poles were judged in
            keep = [(a, b) for a, b in keep if 0.9 * min(physical) <= a <= 1.05 * max(physical)]
        if keep:
            ax2.semilogy([a for a, _ in keep], [b for _, b in keep], color="tab:blue", lw=0.9, alpha=0.5)
            ax2.set_ylabel("first singular value of the spectral matrix [unit²/Hz]", color="tab:blue")
    ax.set_zorder(3)
    ax.patch.set_visible(False)
    ax.legend(loc="upper left", fontsize=7, ncol=2, framealpha=0.9)
    ax.grid(True, alpha=0.3)
    rec = f": {os.path.basename(modes[0]['record'])}" if modes else " (no mode found)"
    ax.set_title(f"SSI-COV stabilization diagram, window {window}{rec}")
    fig.tight_layout()
    plotlib.save(fig, out, "plot_oma")


def tracked(d, out):
    rows = rows_of(os.path.join(d, "tracked.csv"))
    windows = sorted({r["window"] for r in rows}, key=int)
    if len(windows) < 2:
        return False
    extra = [c for c in rows[0].keys() if c not in FIXED] if rows else []
    by_track = defaultdict(list)
    for r in rows:
        by_track[int(r["track"])].append(r)
    # Tracks seen in at least a fifth of the windows (the others: noise poles that came and went).
    shown = {t: rs for t, rs in by_track.items() if len(rs) >= max(2, len(windows) / 5)}
    ncol = 2 if extra else 1
    fig, axes = plt.subplots(2, ncol, figsize=(6 * ncol + 3, 7), squeeze=False, sharex="col")
    t0 = min(float(r["t_start_s"]) for r in rows)
    hours = max(float(r["t_start_s"]) for r in rows) - t0 > 3 * 3600
    scale, unit = (3600.0, "h") if hours else (1.0, "s")
    for k, (t, rs) in enumerate(sorted(shown.items())):
        x = [(float(r["t_start_s"]) - t0) / scale for r in rs]
        fhz = [float(r["frequency_hz"]) for r in rs]
        mean = sum(fhz) / len(fhz)
        f = [100 * (v / mean - 1) for v in fhz]  # change from the track's mean [%]: drifts of 0.1 % show
        z = [100 * float(r["damping_ratio"]) for r in rs]
        sf = [100 * (plotlib.number(r["frequency_std_hz"]) or 0.0) / mean for r in rs]
        sz = [100 * (plotlib.number(r["damping_std"]) or 0.0) for r in rs]
        lab = f"track {t}: mean {mean:.4g} Hz ({len(rs)} of {len(windows)} windows)"
        axes[0][0].errorbar(x, f, yerr=sf, marker="o", ms=3, lw=0.8, capsize=2, color=f"C{k % 10}", label=lab)
        axes[1][0].errorbar(x, z, yerr=sz, marker="o", ms=3, lw=0.8, capsize=2, color=f"C{k % 10}")
        if extra:
            c = [plotlib.number(r[extra[0]]) for r in rs]
            pts = [(a, b, e) for a, b, e in zip(c, f, z) if a is not None]
            axes[0][1].plot([p[0] for p in pts], [p[1] for p in pts], "o", ms=3, color=f"C{k % 10}")
            axes[1][1].plot([p[0] for p in pts], [p[2] for p in pts], "o", ms=3, color=f"C{k % 10}")
    axes[0][0].set_ylabel("frequency change from the track's mean [%]")
    axes[1][0].set_ylabel("damping ratio [%]")
    axes[1][0].set_xlabel(f"window start [{unit}] from the first")
    axes[0][0].legend(fontsize=7)
    if extra:
        name, _, u = plotlib.split_unit(extra[0])
        axes[1][1].set_xlabel(f"{name} [{u}] (window mean)" if u else f"{extra[0]} (window mean)")
        axes[0][1].set_title(f"against {name}", fontsize=10)
    for row in axes:
        for a in row:
            a.grid(True, alpha=0.3)
    fig.suptitle(f"Tracked modes over {len(windows)} windows (SSI-COV)")
    fig.tight_layout()
    plotlib.save(fig, out, "plot_oma")
    return True


def main():
    ap = plotlib.dir_parser(__doc__)
    ap.add_argument("--window", default="1")
    ap.add_argument("--out-prefix")
    a = plotlib.parse_dir(ap, "plot_oma")
    prefix = a.out_prefix or os.path.join(a.dir, "oma")
    stabilization(a.dir, a.window, prefix + "_stabilization.png")
    tracked(a.dir, prefix + "_tracked.png")


if __name__ == "__main__":
    main()

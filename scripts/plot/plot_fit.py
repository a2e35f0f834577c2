#!/usr/bin/python3
"""Draw a model-updating result written by `viaduct fit`.

Usage: scripts/plot/plot_fit.py DIR [--out-prefix PREFIX]

Reads DIR/fit_time.csv, fit_trace.csv, fit.csv and fit_modes.csv and writes
DIR/fit_time.png: per record channel the filtered record against the aligned model with the
initial and the fitted values (residual energy of each in the title), and
DIR/fit_trace.png: every parameter against the iteration (each start a line, the spectral
pre-stage then the fit; estimate and +-2 standard errors shaded, bounds dotted) and the cost on a
log scale.
"""
import math
import os
import sys


import plotlib  # noqa: E402

plt = plotlib.pyplot()
import numpy as np  # noqa: E402

rows_of = plotlib.rows_reader("plot_fit", "fit")


def plot_time(d, out):
    rows = rows_of(os.path.join(d, "fit_time.csv"))
    if not rows:
        return None
    keys = []
    for r in rows:
        k = (r["record"], r["channel"])
        if k not in keys:
            keys.append(k)
    fig, axes = plt.subplots(len(keys), 1, figsize=(13, 2.8 * len(keys) + 0.6), squeeze=False)
    for ax, (rec, ch) in zip(axes[:, 0], keys):
        sel = [r for r in rows if r["record"] == rec and r["channel"] == ch]
        t = np.array([float(r["t_s"]) for r in sel])
        y = np.array([float(r["measured"]) for r in sel])
        m0 = np.array([float(r["initial"]) for r in sel])
        m1 = np.array([float(r["fitted"]) for r in sel])
        e0 = np.sum((m0 - y) ** 2) / max(np.sum(y ** 2), 1e-300)
        e1 = np.sum((m1 - y) ** 2) / max(np.sum(y ** 2), 1e-300)
        ax.plot(t, y, lw=0.8, color="0.3", label="record (filtered)")
        ax.plot(t, m0, lw=0.8, color="C0", alpha=0.7, ls="--", label="model, initial values")
        ax.plot(t, m1, lw=0.9, color="C3", alpha=0.85, label="model, fitted values")
        ax.set_title("%s  %s: relative residual energy %.3g -> %.3g" % (os.path.basename(rec), ch, e0, e1), fontsize=9)
        ax.set_ylabel(ch, fontsize=8)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper right")
    axes[-1, 0].set_xlabel("record time [s]")
    fig.tight_layout()
    path = out + "fit_time.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def plot_trace(d, out):
    trace = rows_of(os.path.join(d, "fit_trace.csv"))
    params = rows_of(os.path.join(d, "fit.csv"))
    if not trace:
        return None
    n = len(params)
    fig, axes = plt.subplots(n + 1, 1, figsize=(9, 2.2 * (n + 1) + 0.4), squeeze=False, sharex=True)
    starts = sorted({int(r["start"]) for r in trace})
    for i, p in enumerate(params):
        ax = axes[i, 0]
        key = p["key"]
        for s in starts:
            sel = [r for r in trace if int(r["start"]) == s]
            ax.plot(range(len(sel)), [float(r[key]) for r in sel], marker="o", ms=3, lw=1, label="start %d" % s)
        est, se = float(p["estimate"]), plotlib.number(p["std_error"])  # empty: not determined
        if se is not None and math.isfinite(se):
            ax.axhspan(est - 2 * se, est + 2 * se, color="C3", alpha=0.15, lw=0)
        ax.axhline(est, color="C3", lw=0.8)
        for b in ("lower", "upper"):
            ax.axhline(float(p[b]), color="0.5", ls=":", lw=0.8)
        if p["scale"] == "log":
            ax.set_yscale("log")
        flag = "" if p["determined"] == "true" else "  (flagged: see fit.toml warnings)"
        spread = " ± %.3g" % se if se is not None else " (standard error not determined)"
        ax.set_title("%s = %.6g%s %s%s" % (key, est, spread, p["unit"], flag), fontsize=9)
        ax.grid(alpha=0.3)
        if len(starts) > 1 and i == 0:
            ax.legend(fontsize=7)
    ax = axes[n, 0]
    for s in starts:
        sel = [r for r in trace if int(r["start"]) == s]
        ax.semilogy(range(len(sel)), [max(float(r["cost"]), 1e-300) for r in sel], marker="o", ms=3, lw=1)
        n_spec = sum(1 for r in sel if r.get("stage") == "spectral")
        if n_spec:
            ax.axvline(n_spec - 0.5, color="0.5", ls="--", lw=0.8)
    ax.set_ylabel("cost (stage's objectives)", fontsize=8)
    ax.set_xlabel("iteration (spectral pre-stage left of the dashed line, then the fit)")
    ax.grid(alpha=0.3, which="both")
    fig.tight_layout()
    path = out + "fit_trace.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def main():
    ap = plotlib.dir_parser(__doc__)
    ap.add_argument("--out-prefix", help="path prefix of the PNGs (default: DIR/)")
    a = plotlib.parse_dir(ap, "plot_fit")
    out = a.out_prefix if a.out_prefix else os.path.join(a.dir, "")
    for p in (plot_time(a.dir, out), plot_trace(a.dir, out)):
        if p:
            print("wrote", p)


if __name__ == "__main__":
    main()

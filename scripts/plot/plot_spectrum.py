#!/usr/bin/python3
"""Draw the spectra written by `viaduct spectrum`, with the peaks of `viaduct peaks`.

Usage: scripts/plot/plot_spectrum.py DIR [--peaks PEAKS_DIR] [--f-max HZ] [--out FILE]

Reads DIR/spectrum.csv (amplitude spectra, NAME_amp_UNIT, or Welch densities,
NAME_psd_UNIT2_per_hz) and the frequency peaks of DIR/peaks.csv or PEAKS_DIR/peaks.csv when
present; writes DIR/spectrum.png: one panel per channel, amplitudes in engineering units
(deflection in mm), densities on a log axis, each peak marked with its frequency.
"""
import collections
import csv
import os
import sys

import numpy as np  # noqa: E402

import plotlib  # noqa: E402

plt = plotlib.pyplot()

PSD_UNITS = {"m2": "m²/Hz", "mps22": "(m/s²)²/Hz", "mps2": "(m/s)²/Hz", "N2": "N²/Hz", "kN2": "kN²/Hz"}


def channels_of(header):
    """[(column, channel base, kind 'amp' or 'psd', scale, unit label)] of spectrum.csv."""
    out = []
    for c in header[1:]:
        if "_psd_" in c and c.endswith("_per_hz"):
            base, unit = c.split("_psd_", 1)
            unit = unit[: -len("_per_hz")]
            out.append((c, base, "psd", 1.0, PSD_UNITS.get(unit, unit + "/Hz")))
        elif "_amp_" in c:
            base, unit = c.split("_amp_", 1)
            _, scale, shown = plotlib.split_unit("x_" + unit)
            out.append((c, base, "amp", scale, shown or unit))
    return out


def main():
    ap = plotlib.dir_parser(__doc__)
    ap.add_argument("--peaks", help="directory of a viaduct peaks run (default: DIR if it holds peaks.csv)")
    ap.add_argument("--f-max", type=float, default=0.0, help="highest frequency drawn [Hz] (default: all)")
    ap.add_argument("--out")
    a = plotlib.parse_dir(ap, "plot_spectrum")
    path = os.path.join(a.dir, "spectrum.csv")
    plotlib.need(path, "plot_spectrum", "spectrum")
    header, data = plotlib.numeric_table(path, "plot_spectrum", "run viaduct spectrum first")
    chans = channels_of(header)
    if not chans:
        sys.exit("plot_spectrum: %s has no spectrum columns" % path)
    peaks = collections.defaultdict(list)  # channel base -> [(f, value)]
    pdir = a.peaks or a.dir
    ppath = os.path.join(pdir, "peaks.csv")
    if os.path.exists(ppath):
        with open(ppath, newline="") as f:
            for r in csv.DictReader(f):
                if "frequency_hz" in r:
                    base = r["channel"].rsplit("_", 1)[0] if r["channel"].endswith("_" + r["unit"]) else r["channel"]
                    peaks[base].append((float(r["frequency_hz"]), None))
    f = data[:, 0]
    sel = f <= a.f_max if a.f_max > 0 else np.ones_like(f, dtype=bool)
    fig, axes = plt.subplots(len(chans), 1, figsize=(10, 2.8 * len(chans) + 1.0), squeeze=False, sharex=True)
    for ax, (col, base, kind, scale, unit) in zip(axes[:, 0], chans):
        y = scale * data[:, header.index(col)]
        if kind == "psd":
            ax.semilogy(f[sel], np.maximum(y[sel], 1e-300), lw=1.0, color="C0")
            ax.set_ylabel("%s\nPSD [%s]" % (base, unit), fontsize=9)
        else:
            ax.plot(f[sel], y[sel], lw=1.0, color="C0")
            ax.set_ylabel("%s\namplitude [%s]" % (base, unit), fontsize=9)
            plotlib.no_offset(ax)
        for fp, _ in peaks.get(base, []):
            if a.f_max > 0 and fp > a.f_max:
                continue
            v = float(np.interp(fp, f, y))  # on the curve drawn (the peaks may come from another spectrum kind)
            ax.plot(fp, v, "v", color="crimson", ms=5)
            ax.annotate("%.3f Hz" % fp, (fp, v), xytext=(0, 5), textcoords="offset points", ha="center", fontsize=7,
                        color="crimson")
        ax.grid(alpha=0.3, which="both")
    axes[-1, 0].set_xlabel("frequency [Hz]")
    kind = "Welch power spectral density" if chans[0][2] == "psd" else "amplitude spectrum"
    inputs = plotlib.manifest(a.dir).get("inputs", [])
    record = os.path.basename(inputs[0]["file"]) if inputs and "file" in inputs[0] else "record"
    title = plotlib.scenario_title(a.dir, record) + ": " + kind
    if peaks:
        title += ", peaks of viaduct peaks marked"
    fig.suptitle(title, fontsize=11)
    fig.tight_layout()
    plotlib.save(fig, a.out or os.path.join(a.dir, "spectrum.png"), "plot_spectrum")


if __name__ == "__main__":
    main()

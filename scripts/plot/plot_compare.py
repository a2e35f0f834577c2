#!/usr/bin/python3
"""Draw a model-against-record comparison written by `viaduct compare`.

Usage: scripts/plot/plot_compare.py DIR [--out FILE] [--fmax HZ]

Reads DIR/compare_time.csv, compare_spectrum.csv and compare_metrics.csv and writes
DIR/compare.png: one row per channel, filtered time histories (record and aligned model) on the
left, amplitude spectra on the right, the metrics in each title. Units in engineering form
(deflections in mm, accelerations in m/s²), the scenario's title on top.
"""
import csv
import os


import plotlib  # noqa: E402

plt = plotlib.pyplot()


def table(path):
    return plotlib.numeric_table(path, "plot_compare", "run viaduct compare first")


def val(row, key):
    """A metric; NaN when viaduct could not determine it (an empty cell)."""
    v = plotlib.number(row[key])
    return float("nan") if v is None else v


def main():
    ap = plotlib.dir_parser(__doc__)
    ap.add_argument("--out")
    ap.add_argument("--fmax", type=float, default=0.0, help="upper frequency of the spectra [Hz] (default: 1.5 x highest peak)")
    a = plotlib.parse_dir(ap, "plot_compare")
    th, td = table(os.path.join(a.dir, "compare_time.csv"))
    fh, fd = table(os.path.join(a.dir, "compare_spectrum.csv"))
    with open(os.path.join(a.dir, "compare_metrics.csv"), newline="") as f:
        metrics = list(csv.DictReader(f))
    rows = len(metrics)
    fig, axes = plt.subplots(rows, 2, figsize=(13, 3.0 * rows + 0.6), squeeze=False)
    for i, m in enumerate(metrics):
        ch = m["channel"]
        unit = ch.rsplit("_", 1)[1]
        base = ch[: -len(unit) - 1]
        _, scale, shown = plotlib.split_unit(ch)
        shown = shown or unit
        tr, tm = th.index(base + "_record_" + unit), th.index(base + "_model_" + unit)
        ax = axes[i][0]
        ax.plot(td[:, 0], scale * td[:, tr], lw=0.8, color="0.25", label="record")
        ax.plot(td[:, 0], scale * td[:, tm], lw=0.8, color="C3", alpha=0.85, label="model (shift %.3f s)" % val(m, "shift_s"))
        ax.set_ylabel("%s [%s]" % (base, shown), fontsize=9)
        plotlib.no_offset(ax)
        ax.set_title("%s vs %s: peak ratio %.3f, rms ratio %.3f, r = %.3f" % (ch, m["station"], val(m, "peak_ratio"),
                     val(m, "rms_ratio"), val(m, "correlation")), fontsize=9)
        ax.legend(fontsize=7, loc="upper right")
        ax.grid(alpha=0.3)
        fr, fm = fh.index(base + "_record_amp_" + unit), fh.index(base + "_model_amp_" + unit)
        ax = axes[i][1]
        fmax = a.fmax or 1.5 * max(val(m, "f_peak_record_hz"), val(m, "f_peak_model_hz"), 1.0)
        sel = fd[:, 0] <= fmax
        ax.plot(fd[sel, 0], scale * fd[sel, fr], lw=1.0, color="0.25", label="record (peak %.3f Hz)" % val(m, "f_peak_record_hz"))
        ax.plot(fd[sel, 0], scale * fd[sel, fm], lw=1.0, color="C3", alpha=0.85, label="model (peak %.3f Hz)" % val(m, "f_peak_model_hz"))
        ax.set_ylabel("amplitude [%s]" % shown, fontsize=9)
        plotlib.no_offset(ax)
        ax.set_title("amplitude spectra: spectral correlation %.3f" % val(m, "spectral_correlation"), fontsize=9)
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
    axes[-1][0].set_xlabel("time [s]")
    axes[-1][1].set_xlabel("frequency [Hz]")
    # What was run: the train and the speed compared (--speed-kmh's, identified or the
    # scenario's, as the manifest says), the record and the zero taken.
    run = plotlib.manifest(a.dir).get("run", {})
    what = ""
    if "speed_kmh" in run:
        what = "\n%s at %.1f km/h (%s) against %s" % (run.get("train", "train"), float(run["speed_kmh"]), run.get("speed_source", ""),
                                                    os.path.basename(str(run.get("record", "the record"))))
        if run.get("zero", "keep") != "keep":
            what += ", zero: %s" % run["zero"]
    fig.suptitle(plotlib.scenario_title(a.dir) + ": model against record" + what)
    fig.tight_layout()
    plotlib.save(fig, a.out or os.path.join(a.dir, "compare.png"), "plot_compare")


if __name__ == "__main__":
    main()

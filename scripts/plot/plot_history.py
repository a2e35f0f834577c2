#!/usr/bin/python3
"""Draw the station time histories written by `viaduct run`.

Usage: scripts/plot/plot_history.py DIR [--out FILE] [--raw]

Reads DIR/history.csv and writes DIR/history.png: per station, deck (or rail) deflection in mm
and filtered acceleration (raw acceleration too with --raw), one row per station.
"""
import os


import plotlib  # noqa: E402

plt = plotlib.pyplot()
import numpy as np  # noqa: E402


def main():
    ap = plotlib.dir_parser(__doc__)
    ap.add_argument("--out", help="output PNG (default DIR/history.png)")
    ap.add_argument("--raw", action="store_true", help="also draw the unfiltered acceleration")
    a = plotlib.parse_dir(ap, "plot_history")
    path = os.path.join(a.dir, "history.csv")
    header, data = plotlib.numeric_table(path, "plot_history", "run viaduct run first")
    col = {name: i for i, name in enumerate(header)}
    t = data[:, col["t_s"]]
    stations = []  # deck stations have <st>_acc_mps2, rail stations <st>_rail_acc_mps2
    for name in header[1:]:
        if name.endswith("_rail_acc_mps2"):
            st = name[: -len("_rail_acc_mps2")]
        elif name.endswith("_acc_mps2"):
            st = name[: -len("_acc_mps2")]
        else:
            continue
        if st not in stations:
            stations.append(st)
    fig, axes = plt.subplots(len(stations), 2, figsize=(12, 2.6 * len(stations) + 0.8), squeeze=False, sharex=True)
    for i, st in enumerate(stations):
        rail_only = st + "_rail_acc_mps2" in col
        pre = st + ("_rail_" if rail_only else "_")
        ax = axes[i][0]
        ax.plot(t, 1e3 * data[:, col[pre + "disp_m"]], lw=1.0, label="rail" if rail_only else "deck")
        if not rail_only and st + "_rail_disp_m" in col:
            ax.plot(t, 1e3 * data[:, col[st + "_rail_disp_m"]], lw=0.8, alpha=0.8, label="rail")
        ax.set_ylabel("%s\ndeflection [mm]" % st, fontsize=9)
        ax.invert_yaxis()  # downward deflection drawn downwards
        ax.legend(fontsize=7, loc="lower right")
        ax.grid(alpha=0.3)
        ax = axes[i][1]
        if a.raw or pre + "acc_filt_mps2" not in col:
            ax.plot(t, data[:, col[pre + "acc_mps2"]], lw=0.5, color="0.6", label="raw")
        if pre + "acc_filt_mps2" in col:
            y = data[:, col[pre + "acc_filt_mps2"]]
            ax.plot(t, y, lw=0.9, color="C3", label="filtered, max |a| = %.3f m/s²" % np.abs(y).max())
        ax.set_ylabel("acceleration [m/s²]", fontsize=9)
        ax.legend(fontsize=7, loc="upper right")
        ax.grid(alpha=0.3)
    for ax in axes[-1]:
        ax.set_xlabel("time [s]")
    fig.suptitle(plotlib.scenario_title(a.dir) + plotlib.run_case(a.dir) + " — time histories")
    fig.tight_layout()
    plotlib.save(fig, a.out or os.path.join(a.dir, "history.png"), "plot_history")


if __name__ == "__main__":
    main()

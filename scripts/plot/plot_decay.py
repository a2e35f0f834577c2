#!/usr/bin/python3
"""Damping and frequency against amplitude from `viaduct decay`.

Usage: scripts/plot/plot_decay.py DIR [--out FILE]

Reads DIR/decay_amplitude.csv (windows along each decay), DIR/decay.csv (one row per record,
with the fitted linear laws) and DIR/decay_summary.csv; draws damping ratio and natural
frequency against amplitude, one colour per record, with each record's law as a line, and the
mean ± standard deviation over the records in the title. Writes DIR/decay.png.
"""
import os
import sys


import plotlib  # noqa: E402

plt = plotlib.pyplot()

rows_of = plotlib.rows_reader("plot_decay", "decay")


def main():
    ap = plotlib.dir_parser(__doc__)
    ap.add_argument("--out")
    a = plotlib.parse_dir(ap, "plot_decay")
    pts = rows_of(os.path.join(a.dir, "decay_amplitude.csv"))
    recs = rows_of(os.path.join(a.dir, "decay.csv"))
    if not pts:
        sys.exit("plot_decay.py: no amplitude windows to draw")
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    for i, r in enumerate(recs):
        sel = [p for p in pts if p["record"] == r["record"]]
        amp = [float(p["amplitude"]) for p in sel]
        c = f"C{i % 10}"
        name = os.path.basename(os.path.dirname(r["record"])) or r["record"]
        ax[0].plot(amp, [100 * float(p["damping_ratio"]) for p in sel], "o", ms=3, color=c, label=name)
        ax[1].plot(amp, [float(p["frequency_hz"]) for p in sel], "o", ms=3, color=c)
        law = [plotlib.number(r[k]) for k in ("law_zeta0", "law_zeta_per_amplitude", "law_f0_hz", "law_f_hz_per_amplitude")]
        if amp and None not in law:  # a law viaduct could not fit is an empty cell
            lo, hi = min(amp), max(amp)
            xs = [lo * (hi / lo) ** (k / 50) for k in range(51)] if lo > 0 else [lo, hi]
            z0, z1, f0, f1 = law
            ax[0].plot(xs, [100 * (z0 + z1 * x) for x in xs], "-", color=c, lw=1)
            ax[1].plot(xs, [f0 + f1 * x for x in xs], "-", color=c, lw=1)
    ax[0].set_ylabel("damping ratio [%]")
    ax[1].set_ylabel("natural frequency [Hz]")
    unit = plotlib.split_unit(recs[0]["channel"])[2] if recs and recs[0].get("channel") else ""
    for x in ax:
        x.set_xscale("log")
        x.set_xlabel("amplitude of the band-passed record%s" % (" [%s]" % unit if unit else ""))
        x.grid(True, alpha=0.3)
    ax[0].legend(fontsize=8)
    title = plotlib.scenario_title(a.dir, "Free decay") + ": damping and frequency against amplitude"
    summary = os.path.join(a.dir, "decay_summary.csv")
    if os.path.exists(summary):
        st = {r["estimate"]: r for r in rows_of(summary)}
        if "zeta_hilbert" in st and "frequency_hz" in st:
            z, f = st["zeta_hilbert"], st["frequency_hz"]
            zm, zs, fm, fs = (plotlib.number(z["mean"]), plotlib.number(z["std"]), plotlib.number(f["mean"]),
                              plotlib.number(f["std"]))
            if zm is not None and fm is not None:
                # ± only over several records: one record has no spread to show.
                zt = f"{100 * zm:.3f}" + (f" ± {100 * zs:.3f}" if zs is not None and int(z["n"]) > 1 else "")
                ft = f"{fm:.4f}" + (f" ± {fs:.4f}" if fs is not None and int(f["n"]) > 1 else "")
                n = int(z["n"])
                title += f"\n{n} record{'s' if n != 1 else ''}: ζ = {zt} % (Hilbert), f = {ft} Hz"
    fig.suptitle(title)
    fig.tight_layout()
    out = a.out or os.path.join(a.dir, "decay.png")
    plotlib.save(fig, out, "plot_decay", dpi=120)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""viaduct from Python, as in a notebook: the Old Guadiana bridge under the Talgo Altaria.

1. a speed sweep of the model (the envelope of deck accelerations, per station), plotted;
2. the passage at the record's speed, filtered as the record is, against the record
   (data/records/synthetic-deck.csv: the deck at mid-span 1, 154.8 km/h), plotted with both peaks.

Run from the repository's root with the package importable (PYTHONPATH=build/release/python, or
installed by cmake --install):  python3 examples/python/sweep_and_record.py --out out/python
"""
import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import viaduct  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="out/python", help="folder for envelope.png and record.png")
    ap.add_argument("--step-kmh", type=float, default=5.0, help="speed step of the sweep [km/h]")
    args = ap.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    # 1. The sweep: envelope.csv's columns, as a DataFrame when pandas is there.
    sc = viaduct.load_scenario(ROOT / "scenarios/old-guadiana-talgo.toml", set={"sweep.speed_step_kmh": args.step_kmh})
    env = viaduct.sweep(sc, threads=0, progress=True)
    station = np.asarray(env["station"])
    speed = np.asarray(env["speed_kmh"], dtype=float)
    acc = np.asarray(env["max_abs_acc_mps2"], dtype=float)
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for name in dict.fromkeys(station):
        k = station == name
        ax.plot(speed[k], acc[k], marker=".", label=name)
    worst = int(np.argmax(acc))
    ax.axvline(154.8, color="0.5", ls="--", lw=1, label="record: 154.8 km/h")
    ax.set(xlabel="speed [km/h]", ylabel="max |deck acceleration| [m/s²] (filtered 1–30 Hz)",
           title=f"Old Guadiana, Talgo Altaria: governing {acc[worst]:.3f} m/s² at {station[worst]}, "
                 f"{speed[worst]:.0f} km/h")
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(out / "envelope.png", dpi=150)

    # 2. The passage at the record's speed against the record, both filtered alike.
    rec = viaduct.read_record(ROOT / "data/records/synthetic-deck.csv")
    measured = viaduct.filter(rec["deck_acc_mps2"], rec.fs_hz, low_hz=1.0, high_hz=30.0)
    h = viaduct.run(sc, speed_kmh=154.8)
    t_model = np.asarray(h["t_s"])
    # viaduct compare's metrics: the same filter on both, the model aligned onto the record.
    c = viaduct.compare(rec["deck_acc_mps2"], rec.fs_hz, h["S1_mid_acc_mps2"], 1.0 / (t_model[1] - t_model[0]),
                        t0_record=rec.t0_s, low_hz=1.0, high_hz=30.0)
    fig, ax = plt.subplots(figsize=(8, 4.5))
    ax.plot(rec.t, measured, lw=0.8, label=f"record, peak {c['peak_record']:.3f} m/s²")
    ax.plot(c["t"], c["model"], lw=0.8, ls="--", label=f"model S1_mid, peak {c['peak_model']:.3f} m/s² "
            f"(ratio {c['peak_ratio']:.3f}, correlation {c['correlation']:.4f})")
    ax.set(xlabel="time [s]", ylabel="deck acceleration [m/s²] (filtered 1–30 Hz)",
           title="Talgo Altaria at 154.8 km/h: mid-span 1, record and model")
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(out / "record.png", dpi=150)
    print(f"governing: {acc[worst]:.4f} m/s² at {station[worst]}, {speed[worst]:.1f} km/h; at 154.8 km/h record peak "
          f"{c['peak_record']:.4f} m/s², model {c['peak_model']:.4f} m/s² (ratio {c['peak_ratio']:.4f}, correlation "
          f"{c['correlation']:.5f}); wrote {out}/envelope.png, record.png")


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Generate the committed SciPy reference vectors for viaduct's Chebyshev I design and
zero-phase filtering (tests/unit/signal/test_iir.cpp).

Run with Debian's python3-scipy:  /usr/bin/python3 scripts/generate/gen_filter_reference.py
Writes tests/data/filter_reference/<case>.csv. Regenerate only on purpose (golden files).
"""
import os
import numpy as np
import scipy
from scipy import signal

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tests", "data", "filter_reference")

# name, band, order, ripple_db, low_hz, high_hz, fs_hz, n_samples
CASES = [
    ("bandpass_o3_1_60_fs1000", "bandpass", 3, 0.5, 1.0, 60.0, 1000.0, 3000),
    ("bandpass_o3_1_30_fs4096", "bandpass", 3, 1.0, 1.0, 30.0, 4096.0, 6000),
    ("bandpass_o4_2_45_fs500", "bandpass", 4, 0.1, 2.0, 45.0, 500.0, 1500),
    ("lowpass_o3_45_fs1000", "lowpass", 3, 0.5, 0.0, 45.0, 1000.0, 1500),
    ("lowpass_o4_30_fs1000", "lowpass", 4, 0.5, 0.0, 30.0, 1000.0, 1500),
    ("highpass_o2_2_fs200", "highpass", 2, 0.5, 2.0, 0.0, 200.0, 1200),
    ("highpass_o5_0p5_fs100", "highpass", 5, 0.5, 0.5, 0.0, 100.0, 1200),
]


def main():
    os.makedirs(OUT, exist_ok=True)
    rng = np.random.default_rng(20261122)
    for name, band, order, rp, lo, hi, fs, n in CASES:
        wn = {"bandpass": [lo, hi], "lowpass": hi, "highpass": lo}[band]
        sos = signal.cheby1(order, rp, wn, band, fs=fs, output="sos")
        t = np.arange(n) / fs
        # Offset + drift + in-band and out-of-band sines + noise: exercises padding and edges.
        x = (0.3 + 0.05 * t + np.sin(2 * np.pi * 10.0 * t) + 0.5 * np.sin(2 * np.pi * 0.3 * t)
             + 0.2 * np.sin(2 * np.pi * 0.4 * fs * t) + 0.1 * rng.standard_normal(n))
        y = signal.sosfiltfilt(sos, x)
        with open(os.path.join(OUT, name + ".csv"), "w") as f:
            f.write("# scipy %s: cheby1(%d, %r, %r, %r, fs=%r, output='sos') + sosfiltfilt defaults\n"
                    % (scipy.__version__, order, rp, wn, band, fs))
            f.write("# band,order,ripple_db,low_hz,high_hz,fs_hz\n")
            f.write("%s,%d,%r,%r,%r,%r\n" % (band, order, rp, lo, hi, fs))
            f.write("# sos rows: b0,b1,b2,a0,a1,a2\n")
            for row in sos:
                f.write(",".join("%.17g" % v for v in row) + "\n")
            f.write("# x,y\n")
            for a, b in zip(x, y):
                f.write("%.17g,%.17g\n" % (a, b))
    print("wrote", len(CASES), "cases to", os.path.normpath(OUT))


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Generate the committed SciPy reference vectors for viaduct's Welch PSD and CSD
(tests/unit/signal/test_spectrum.cpp).

Run with Debian's python3-scipy:  /usr/bin/python3 scripts/generate/gen_spectrum_reference.py
Writes tests/data/spectrum_reference/<case>.csv. Regenerate only on purpose (golden files).
"""
import os
import numpy as np
import scipy
from scipy import signal

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tests", "data", "spectrum_reference")

# name, fs, n, nperseg, noverlap, window, detrend
CASES = [
    ("welch_default_fs1000", 1000.0, 4096, 256, None, "hann", "constant"),
    ("welch_odd_fs4096", 4096.0, 5000, 511, 100, "hann", "linear"),
    ("welch_boxcar_nodetrend_fs200", 200.0, 3000, 400, 0, "boxcar", False),
]


def main():
    os.makedirs(OUT, exist_ok=True)
    rng = np.random.default_rng(7)
    for name, fs, n, nperseg, noverlap, window, detrend in CASES:
        t = np.arange(n) / fs
        x = 0.4 + 0.01 * t + np.sin(2 * np.pi * 10.3 * t) + 0.3 * rng.standard_normal(n)
        # y: x delayed by 3 samples, scaled, plus its own noise (a phase that tests conj(X) Y)
        y = 0.7 * np.roll(x, 3) + 0.1 * rng.standard_normal(n)
        kw = dict(fs=fs, nperseg=nperseg, noverlap=noverlap, window=window, detrend=detrend)
        f, pxx = signal.welch(x, **kw)
        _, pxy = signal.csd(x, y, **kw)
        with open(os.path.join(OUT, name + ".csv"), "w") as out:
            out.write("# scipy %s: welch(x, **kw), csd(x, y, **kw), kw = %r\n" % (scipy.__version__, kw))
            out.write("# fs,nperseg,noverlap,window,detrend\n")
            out.write("%r,%d,%d,%s,%s\n" % (fs, nperseg, -1 if noverlap is None else noverlap,
                                            "hann" if window == "hann" else "rectangular",
                                            detrend if detrend else "none"))
            out.write("# x,y\n")
            for a, b in zip(x, y):
                out.write("%.17g,%.17g\n" % (a, b))
            out.write("# f,pxx,re_pxy,im_pxy\n")
            for a, b, c in zip(f, pxx, pxy):
                out.write("%.17g,%.17g,%.17g,%.17g\n" % (a, b, c.real, c.imag))
    print("wrote", len(CASES), "cases to", os.path.normpath(OUT))


if __name__ == "__main__":
    main()

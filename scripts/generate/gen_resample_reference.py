#!/usr/bin/python3
"""Generate the committed SciPy reference vectors for viaduct's decimation and Hilbert envelope
(tests/unit/signal/test_resample.cpp).

Run with Debian's python3-scipy:  /usr/bin/python3 scripts/generate/gen_resample_reference.py
Writes tests/data/resample_reference.csv. Regenerate only on purpose (golden files).
"""
import os
import numpy as np
import scipy
from scipy import signal

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tests", "data", "resample_reference.csv")


def main():
    rng = np.random.default_rng(11)
    n = 2001  # odd, to exercise the odd-length analytic signal
    t = np.arange(n) / 1000.0
    x = (np.sin(2 * np.pi * 12 * t) * np.exp(-2 * t) + 0.3 * np.sin(2 * np.pi * 180 * t)
         + 0.05 * rng.standard_normal(n) + 0.2)
    d4 = signal.decimate(x, 4)
    d10 = signal.decimate(x, 10)
    env = np.abs(signal.hilbert(x))
    env_even = np.abs(signal.hilbert(x[:-1]))
    with open(OUT, "w") as f:
        f.write("# scipy %s: decimate(x, 4), decimate(x, 10), abs(hilbert(x)), abs(hilbert(x[:-1]))\n" % scipy.__version__)
        f.write("# x,env,env_even (last row: env_even empty)\n")
        for i in range(n):
            f.write("%.17g,%.17g,%s\n" % (x[i], env[i], "%.17g" % env_even[i] if i < n - 1 else "nan"))
        f.write("# d4\n")
        f.write(",".join("%.17g" % v for v in d4) + "\n")
        f.write("# d10\n")
        f.write(",".join("%.17g" % v for v in d10) + "\n")
    print("wrote", os.path.normpath(OUT))


if __name__ == "__main__":
    main()

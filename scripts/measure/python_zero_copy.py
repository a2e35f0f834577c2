#!/usr/bin/env python3
"""A long record through the filter from Python and through the CLI: time and memory.

The issue's case (#17): 10 minutes of 18 channels at 4096 Hz (44 million samples, 354 MB of
float64), each channel filtered 1-30 Hz (Chebyshev I, order 3, zero phase).

  python, in place   the record as a Fortran-ordered array (each channel a contiguous column, as
                     viaduct.read_record gives it): viaduct.filter reads each column where it is
                     and hands its result over; nothing is copied on the way in or out.
  python, strided    the same samples C-ordered (a channel is every 18th number): numpy must
                     make each channel contiguous first, a copy per channel, for contrast.
  CLI                the record written as MATLAB .mat (scipy.io.savemat), viaduct filter REC.mat,
                     filtered.csv read back with pandas: what a script did before the package.

Each Python path runs in a fresh process; memory is its peak resident set (VmHWM) above what it
held once the record was built. Usage (Debian's python3, the package importable):

  PYTHONPATH=build/release/python /usr/bin/python3 scripts/measure/python_zero_copy.py build/release/viaduct
"""
import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time

import numpy as np


def vm(field):
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith(field + ":"):
                return int(line.split()[1]) * 1024
    raise RuntimeError(field)


def record(n, k, order):
    rng = np.random.default_rng(1)
    t = np.arange(n) / 4096.0
    x = np.empty((n, k), order=order)
    for j in range(k):
        x[:, j] = np.sin(2 * np.pi * (10.0 + j) * t) + 0.1 * rng.standard_normal(n)
    return x


def python_path(n, k, order):
    import viaduct
    x = record(n, k, order)
    base = vm("VmRSS")
    t0 = time.perf_counter()
    out = [viaduct.filter(x[:, j], 4096.0, low_hz=1.0, high_hz=30.0) for j in range(k)]
    dt = time.perf_counter() - t0
    assert all(not y.flags.owndata for y in out)  # the C++ vectors themselves
    print(f"{dt:.3f} {vm('VmHWM') - base} {float(np.abs(out[0]).max()):.6f}")


def cli_path(viaduct, n, k, tmp):
    import pandas
    import scipy.io
    x = record(n, k, "F")
    t0 = time.perf_counter()
    names = np.array([f"ch{j + 1}_acc_mps2" for j in range(k)], dtype=object)
    scipy.io.savemat(f"{tmp}/rec.mat", {"data": x, "names": names, "fs": 4096.0})
    t1 = time.perf_counter()
    subprocess.run([viaduct, "filter", f"{tmp}/rec.mat", "--low-hz", "1", "--high-hz", "30", "-q", "--out", f"{tmp}/f"],
                   check=True)
    t2 = time.perf_counter()
    y = pandas.read_csv(f"{tmp}/f/filtered.csv", comment="#")
    t3 = time.perf_counter()
    rss = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss * 1024
    size = os.path.getsize(f"{tmp}/f/filtered.csv")
    return t1 - t0, t2 - t1, t3 - t2, rss, size, float(np.abs(y.iloc[:, 1]).max())


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("viaduct", help="the CLI of the same build")
    ap.add_argument("--minutes", type=float, default=10.0)
    ap.add_argument("--channels", type=int, default=18)
    ap.add_argument("--repeat", type=int, default=3, help="Python runs per path (median reported)")
    ap.add_argument("--child", choices=["F", "C"], help=argparse.SUPPRESS)
    a = ap.parse_args()
    n = int(a.minutes * 60 * 4096)
    if a.child:
        python_path(n, a.channels, a.child)
        return
    mb = n * a.channels * 8 / 1e6
    print(f"record: {a.minutes:g} min x {a.channels} channels x 4096 Hz = {n * a.channels / 1e6:.1f} M samples ({mb:.0f} MB)")
    rows = {}
    for order, name in (("F", "python, in place"), ("C", "python, strided")):
        runs = []
        for _ in range(a.repeat):
            p = subprocess.run([sys.executable, __file__, a.viaduct, "--minutes", str(a.minutes), "--channels",
                                str(a.channels), "--child", order], capture_output=True, text=True, check=True)
            runs.append([float(v) for v in p.stdout.split()])
        runs.sort()
        rows[name] = runs[len(runs) // 2]
        print(f"  {name:18s} filter {rows[name][0]:7.2f} s   peak memory above the record {rows[name][1] / 1e6:6.0f} MB "
              f"(median of {a.repeat}; peak |y| {rows[name][2]})")
    with tempfile.TemporaryDirectory() as tmp:
        w, c, r, rss, size, peak = cli_path(a.viaduct, n, a.channels, tmp)
    print(f"  {'CLI':18s} write .mat {w:.2f} s + viaduct filter {c:.2f} s + read filtered.csv ({size / 1e6:.0f} MB) "
          f"{r:.2f} s = {w + c + r:.2f} s; the CLI's peak memory {rss / 1e6:.0f} MB (peak |y| {peak})")
    print(f"  ratio CLI / python in place: {(w + c + r) / rows['python, in place'][0]:.1f}x in time")


if __name__ == "__main__":
    main()

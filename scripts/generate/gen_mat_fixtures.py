#!/usr/bin/python3
"""Regenerates the MATLAB .mat fixtures of tests/unit/io/test_record_mat.cpp with SciPy's
independent writer (scipy.io.savemat, MATLAB v5): what viaduct's reader (libmatio) must read.

Usage: scripts/generate/gen_mat_fixtures.py   (writes tests/data/records/*.mat)
"""
import os

import numpy as np
from scipy.io import savemat

out = os.path.join(os.path.dirname(__file__), "..", "..", "tests", "data", "records")
os.makedirs(out, exist_ok=True)
n = 50
k = np.arange(n)
# vectors.mat: a time vector (0.5 s + k/250), a row vector in g (single precision), a column in
# mm with a NaN at row 11, a rate scalar, a note, a vector of another length (not read).
acc = (0.01 * np.sin(0.3 * k)).astype(np.float32)
disp = 1.5 + 0.25 * k
disp[10] = np.nan
savemat(os.path.join(out, "vectors.mat"), {
    "t": (0.5 + k / 250.0).reshape(-1, 1), "acc_mid_g": acc.reshape(1, -1), "disp_mid_mm": disp.reshape(-1, 1),
    "fs": 250.0, "note": "logger 7, bridge A", "calib": np.arange(3.0)}, oned_as="column")
# matrix.mat (compressed): a 50 x 3 matrix with names and units cell arrays, the rate as Fs, no time.
data = np.column_stack([0.02 * np.cos(0.2 * k), 100.0 + k, 2.0 - 0.01 * k])
names = np.empty((1, 3), dtype=object)
names[0, :] = ["acc1", "strain1", "disp1"]
units = np.empty((1, 3), dtype=object)
units[0, :] = ["g", "µε", "mm"]
savemat(os.path.join(out, "matrix.mat"), {"data": data, "names": names, "units": units, "Fs": 100.0}, do_compression=True)
# int16 counts with a sampling interval: a raw logger dump.
savemat(os.path.join(out, "counts.mat"), {"strain_ue": (np.arange(n, dtype=np.int16) - 20).reshape(-1, 1), "dt": 0.002})
# Only text: nothing to read.
savemat(os.path.join(out, "text.mat"), {"note": "no data"})
print("wrote", out)

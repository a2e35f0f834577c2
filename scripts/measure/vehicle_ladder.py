#!/usr/bin/env python3
"""The vehicle ladder of issue #21 on one scenario: forces, sprung masses, multibody coaches and
multibody coaches on an irregular rail, each on the full model (Newmark) and on the fast path
(modal), with the deck's peaks, the contact's extremes, the car bodies' peak acceleration, the
solver's wall time, and each rung's deck peaks against the richest rung's.

Usage: scripts/measure/vehicle_ladder.py VIADUCT SCENARIO TRAIN_FILE SPEED_KMH [--set k=v ...]
Prints a markdown table (docs/vehicles.md). Uses only the standard library.
"""
import csv
import os
import subprocess
import sys
import tempfile


def run(viaduct, scenario, train, speed, vehicle, method, irregular, extra):
    out = tempfile.mkdtemp(prefix="viaduct-ladder-")
    cmd = [viaduct, "run", scenario, "--out", out, "--quiet", "--speed-kmh", str(speed),
           "--set", 'train.files=["%s"]' % train, "--set", "train.vehicle=" + vehicle,
           "--set", "analysis.method=" + method]
    if method == "modal":
        cmd += ["--set", "modal.max_frequency_hz=200"]
    if irregular:
        cmd += ["--set", "irregularity.spectrum=fra5", "--set", "irregularity.max_wavelength_m=50"]
    else:
        cmd += ["--set", "irregularity.spectrum="]
    cmd += extra  # last: the caller's settings win
    subprocess.run(cmd, check=True)
    with open(os.path.join(out, "history.csv")) as f:
        rows = list(csv.DictReader(f))
    station = [k for k in rows[0] if k.endswith("_acc_filt_mps2")][0][: -len("_acc_filt_mps2")]
    acc = max(abs(float(r[station + "_acc_filt_mps2"])) for r in rows)
    disp = max(abs(float(r[station + "_disp_m"])) for r in rows)
    wall = None
    with open(os.path.join(out, "manifest.toml")) as f:
        for line in f:
            if line.startswith("solver_wall_s"):
                wall = float(line.split("=")[1])
    contact = body = None
    path = os.path.join(out, "contact.csv")
    if os.path.exists(path):
        with open(path) as f:
            c = list(csv.DictReader(f))
        contact = (min(float(r["min_N"]) for r in c), max(float(r["max_N"]) for r in c), float(c[0]["static_N"]))
        with open(os.path.join(out, "vehicles.csv")) as f:
            v = list(csv.DictReader(f))
        body = max(abs(float(r[k])) for r in v for k in r if k.endswith("_acc_mps2"))
    return dict(station=station, acc=acc, disp=disp, wall=wall, contact=contact, body=body)


def main():
    if len(sys.argv) < 5:
        sys.exit(__doc__)
    viaduct, scenario, train, speed = sys.argv[1:5]
    extra = sys.argv[5:]
    rungs = [("forces", False), ("sprung", False), ("multibody", False), ("multibody", True)]
    res = {}
    for vehicle, irregular in rungs:
        for method in ("newmark", "modal"):
            res[(vehicle, irregular, method)] = run(viaduct, scenario, train, speed, vehicle, method, irregular, extra)
    richest = res[("multibody", True, "newmark")]
    smooth = res[("multibody", False, "newmark")]
    st = richest["station"]
    print("| rung | path | %s max acc (filtered) [m/s²] | vs richest | vs multibody smooth | max disp [mm] | contact force [kN] (static) | car body max acc [m/s²] | solver wall [s] |" % st)
    print("|---|---|---|---|---|---|---|---|---|")
    for (vehicle, irregular, method), r in res.items():
        name = vehicle + (" + FRA 5" if irregular else "")
        c = "%.1f to %.1f (%.1f)" % (r["contact"][0] / 1e3, r["contact"][1] / 1e3, r["contact"][2] / 1e3) if r["contact"] else "-"
        b = "%.3f" % r["body"] if r["body"] is not None else "-"
        print("| %s | %s | %.4f | %+.1f %% | %+.1f %% | %.4f | %s | %s | %.2f |" % (
            name, method, r["acc"], 100 * (r["acc"] / richest["acc"] - 1), 100 * (r["acc"] / smooth["acc"] - 1),
            1e3 * r["disp"], c, b, r["wall"]))


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""IDA against the fixed-step fast path with vehicles (issue #21 part 5): the same reduced system
(the structure's modes up to modal.max_frequency_hz, the vehicles physical) integrated by Newmark
at several steps and by IDA at several tolerances, each run's envelopes against a converged
reference (IDA at rtol 1e-10), with the solver's wall time and the contact events.

Envelopes, on a common 1 ms grid: the first station's max |acceleration| (unfiltered: the filter's
response depends on the sampling rate) and max |deflection|, the largest and smallest contact
force over the axles, the largest car-body acceleration; the error of a run is the largest
relative error of the five (the smallest contact force relative to the static load).
Contact: total time in the air over the axles and the earliest loss (contact.csv).

Usage: scripts/measure/vehicle_ida.py VIADUCT SCENARIO SPEED_KMH [--set k=v ...]
Prints a markdown table (docs/accuracy.md). Uses only the standard library.
"""
import csv
import math
import os
import subprocess
import sys
import tempfile

NEWMARK_DT = [2e-3, 1e-3, 5e-4, 2.5e-4, 1e-4, 5e-5]
IDA_RTOL = [1e-3, 1e-4, 1e-5, 1e-6, 1e-7]
REF_RTOL = 1e-10
GRID = 1e-3  # [s] the envelopes' common sampling


def run(viaduct, scenario, speed, method, value, extra):
    out = tempfile.mkdtemp(prefix="viaduct-vida-")
    cmd = [viaduct, "run", scenario, "--out", out, "--quiet", "--speed-kmh", str(speed),
           "--set", 'analysis.method="%s"' % method]
    if method == "ida":
        cmd += ["--set", "ida.rtol=%g" % value, "--set", "analysis.dt=0.001"]
    else:
        cmd += ["--set", "analysis.dt=%g" % value]
    cmd += extra
    subprocess.run(cmd, check=True, stderr=subprocess.DEVNULL)
    # Every path's envelopes on the same 1 ms grid (a finer step records more samples, and the
    # filter's response depends on the sampling rate): the unfiltered deck acceleration.
    def on_grid(path):
        with open(path) as f:
            rows = list(csv.DictReader(f))
        return [r for r in rows if abs(float(r["t_s"]) / GRID - round(float(r["t_s"]) / GRID)) < 1e-6]
    rows = on_grid(os.path.join(out, "history.csv"))
    station = [k for k in rows[0] if k.endswith("_acc_mps2") and not k.endswith("_filt_mps2")][0][: -len("_acc_mps2")]
    acc = max(abs(float(r[station + "_acc_mps2"])) for r in rows)
    disp = max(abs(float(r[station + "_disp_m"])) for r in rows)
    veh = on_grid(os.path.join(out, "vehicles.csv"))
    forces = [float(r[k]) for r in veh for k in r if k.endswith("_contact_N")]
    body = max(abs(float(r[k])) for r in veh for k in r if k.endswith("_acc_mps2"))
    with open(os.path.join(out, "contact.csv")) as f:
        c = list(csv.DictReader(f))
    wall = None
    with open(os.path.join(out, "manifest.toml")) as f:
        for line in f:
            if line.startswith("solver_wall_s"):
                wall = float(line.split("=")[1])
    losses = [float(r["first_loss_s"]) for r in c if r["first_loss_s"]]
    return dict(acc=acc, disp=disp, pmax=max(forces), pmin=min(forces),
                p0=float(c[0]["static_N"]), body=body, wall=wall, air=sum(float(r["airborne_s"]) for r in c),
                first=min(losses) if losses else math.nan, station=station)


def error(r, ref):
    e = [abs(r[k] / ref[k] - 1) for k in ("acc", "disp", "pmax", "body")]
    e.append(abs(r["pmin"] - ref["pmin"]) / ref["p0"])
    return max(e)


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    viaduct, scenario, speed = sys.argv[1:4]
    extra = sys.argv[4:]
    ref = run(viaduct, scenario, speed, "ida", REF_RTOL, extra)
    rows = [("IDA rtol %g (reference)" % REF_RTOL, ref)]
    rows += [("Newmark dt %g ms" % (1e3 * dt), run(viaduct, scenario, speed, "modal", dt, extra)) for dt in NEWMARK_DT]
    rows += [("IDA rtol %g" % tol, run(viaduct, scenario, speed, "ida", tol, extra)) for tol in IDA_RTOL]
    print("| path | %s max acc (unfiltered) [m/s²] | max disp [mm] | contact [kN] | car body [m/s²] | envelope error | in the air (all axles) [ms] | first loss [s] | solver wall [s] |" % ref["station"])
    print("|---|---|---|---|---|---|---|---|---|")
    for name, r in rows:
        first = "-" if math.isnan(r["first"]) else "%.5f" % r["first"]
        print("| %s | %.4f | %.4f | %.1f to %.1f | %.4f | %.2e | %.1f | %s | %.3f |" % (
            name, r["acc"], 1e3 * r["disp"], r["pmin"] / 1e3, r["pmax"] / 1e3, r["body"], error(r, ref), 1e3 * r["air"],
            first, r["wall"]))


if __name__ == "__main__":
    main()

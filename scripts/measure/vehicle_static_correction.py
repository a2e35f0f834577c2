#!/usr/bin/env python3
"""The static correction of the vehicle fast path (issue #21 part 5): the structure's modes up to
each cut-off, with and without modal.static_correction, against the full model (Newmark on every
DOF) at the same step, one run each.

Errors are the largest difference over the whole history, relative to the reference's peak of
that quantity (its worst column): the first station's deflection, the rail's deflection above it
(with a track), the deck acceleration filtered as the scenario says, the bending moment, shear
force and bearing reaction (load effects), and the contact forces relative to the static axle
load. Wall: the solver's (manifest solver_wall_s).

Usage: scripts/measure/vehicle_static_correction.py VIADUCT SCENARIO SPEED_KMH --hz F [F ...]
       [--set k=v ...]
Prints a markdown table (docs/vehicles.md). Uses only the standard library.
"""
import csv
import os
import subprocess
import sys
import tempfile


def run(viaduct, scenario, speed, extra):
    out = tempfile.mkdtemp(prefix="viaduct-vsc-")
    cmd = [viaduct, "run", scenario, "--out", out, "--quiet", "--speed-kmh", str(speed)] + extra
    subprocess.run(cmd, check=True, stderr=subprocess.DEVNULL)
    cols = {}
    for name in ("history.csv", "vehicles.csv"):
        with open(os.path.join(out, name)) as f:
            for row in csv.DictReader(f):
                for k, v in row.items():
                    cols.setdefault(k, []).append(float(v))
    with open(os.path.join(out, "contact.csv")) as f:
        p0 = max(float(r["static_N"]) for r in csv.DictReader(f))
    wall = None
    with open(os.path.join(out, "manifest.toml")) as f:
        for line in f:
            if line.startswith("solver_wall_s"):
                wall = float(line.split("=")[1])
    modes = None
    with open(os.path.join(out, "manifest.toml")) as f:
        for line in f:
            if line.startswith("n_modes"):
                modes = int(line.split("=")[1])
    return dict(cols=cols, p0=p0, wall=wall, modes=modes)


GROUPS = [
    ("deflection", lambda k, first: k == first + "_disp_m"),
    ("rail", lambda k, first: k == first + "_rail_disp_m"),
    ("acc (filtered)", lambda k, first: k == first + "_acc_filt_mps2"),
    ("moment", lambda k, first: k.endswith("_moment_Nm")),
    ("shear", lambda k, first: k.endswith("_shear_N")),
    ("reaction", lambda k, first: k.endswith("_reaction_N")),
]


def errors(r, ref):
    first = [k for k in ref["cols"] if k.endswith("_disp_m") and not k.endswith("_rail_disp_m")][0][: -len("_disp_m")]
    out = []
    for _, match in GROUPS:
        worst = None
        for k, b in ref["cols"].items():
            if not match(k, first):
                continue
            a = r["cols"][k]
            n = min(len(a), len(b))
            peak = max(abs(x) for x in b[:n])
            e = max(abs(a[i] - b[i]) for i in range(n)) / peak if peak > 0 else 0.0
            worst = e if worst is None else max(worst, e)
        out.append(worst)
    worst = 0.0
    for k, b in ref["cols"].items():
        if k.endswith("_contact_N"):
            a = r["cols"][k]
            n = min(len(a), len(b))
            worst = max(worst, max(abs(a[i] - b[i]) for i in range(n)) / ref["p0"])
    out.append(worst)
    return out


def main():
    args = sys.argv[1:]
    if len(args) < 5 or "--hz" not in args:
        sys.exit(__doc__)
    viaduct, scenario, speed = args[:3]
    i = args.index("--hz")
    hz = []
    j = i + 1
    while j < len(args) and not args[j].startswith("--"):
        hz.append(float(args[j]))
        j += 1
    extra = args[3:i] + args[j:]
    ref = run(viaduct, scenario, speed, extra + ["--set", 'analysis.method="newmark"'])
    names = [g for g, _ in GROUPS] + ["contact force (of P0)"]
    print("| path | modes | static correction | " + " | ".join(names) + " | solver wall [s] |")
    print("|---|---|---|" + "---|" * len(names) + "---|")
    print("| full model (reference) | - | - | " + " | ".join("-" for _ in names) + " | %.3f |" % ref["wall"])
    for f in hz:
        for sc in ("true", "false"):
            r = run(viaduct, scenario, speed, extra + ["--set", 'analysis.method="modal"', "--set",
                                                      "modal.max_frequency_hz=%g" % f, "--set", "modal.static_correction=" + sc])
            cells = ["-" if e is None else "%.2f %%" % (100 * e) for e in errors(r, ref)]
            print("| modal to %g Hz | %s | %s | %s | %.3f |" % (f, r["modes"], "yes" if sc == "true" else "no", " | ".join(cells),
                                                            r["wall"]))


if __name__ == "__main__":
    main()

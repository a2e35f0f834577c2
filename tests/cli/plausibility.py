#!/usr/bin/env python3
"""Extreme but valid inputs through run and sweep, each judged by the plausibility oracle of
mutations.py (issue #36): a run either stops with a clear message (exit 1 or 2), or exits 0 with
numbers no physical passage exceeds, or says where the number is read that it is not to be
trusted (a warning on stderr and in the manifest). Never exit 0 with 1e24 m and no word.

  plausibility.py VIADUCT SOURCE_DIR [--summary]

The cases are the adversarial session's classes (2026-12-03): schemes as users set them, coarse
and absurd models (unit slips, one element, soft bearings, long spans), damping, speeds and
steps at their extremes, stiff and soft pads, rigid and stiff contacts.
"""
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mutations import plausibility_problems, outputs_problems  # noqa: E402

HS = "scenarios/hslm-simply-supported.toml"
TA = "scenarios/old-guadiana-talgo.toml"
VS = "scenarios/vehicles-25m.toml"
A1 = 'train.files=["hslm:A1"]'
CASES = [
    ("run", HS, ["analysis.alpha=-0.05"]),
    ("run", HS, ["analysis.alpha=-0.3333"]),
    ("sweep", HS, ["analysis.alpha=-0.05", A1, "sweep.speed_step_kmh=40"]),
    ("run", HS, ["analysis.beta=0.1667"]),                      # conditionally stable: refused beyond its step
    ("run", HS, ["analysis.beta=0.1667", "analysis.dt=0.0001"]),
    ("run", HS, ["bridge.EI=7.694e6"]),                         # EI in kN m^2
    ("run", HS, ["bridge.mass_per_m=15.0"]),                    # mass in t/m
    ("run", HS, ["bridge.element_size=15.0"]),                  # one element per span
    ("run", HS, ["bridge.bearings.rigid=false", "bridge.bearings.k=1e3"]),
    ("run", HS, ["bridge.span_lengths=[200.0]"]),
    ("run", HS, ["bridge.damping.ratio=0.0"]),
    ("sweep", HS, ["bridge.damping.ratio=0.0", A1, "sweep.speed_step_kmh=20"]),
    ("run", HS, ["run.speed_kmh=5.0"]),
    ("run", HS, ["run.speed_kmh=800.0"]),
    ("run", HS, ["analysis.dt=0.02"]),
    ("run", HS, ["analysis.dt=0.00002"]),
    ("run", HS, ['analysis.method="modal"', "modal.n_modes=1"]),
    ("run", HS, ['analysis.method="ida"']),
    ("run", TA, ["track.pad.k=1e12"]),
    ("run", TA, ["track.pad.k=1e4"]),
    ("run", TA, ['analysis.preset="default"', "run.speed_kmh=20.0"]),
    ("run", TA, ["bridge.bearings.k=1e3"]),
    ("run", VS, ["train.contact=rigid"]),
    ("run", VS, ["train.contact=rigid", "analysis.dt=0.0001"]),
    ("run", VS, ["train.contact=rigid", "analysis.alpha=-0.1"]),
    ("run", VS, ["train.contact=rigid", "analysis.alpha=-0.1", "analysis.dt=0.0005"]),
    ("run", VS, ["train.contact=rigid", "run.speed_kmh=360.0"]),
    ("run", VS, ["train.contact_stiffness_N_m=1e12"]),
    ("run", VS, ["train.contact_release=false", "run.speed_kmh=360.0"]),
    ("run", VS, ["analysis.alpha=-0.1", "run.speed_kmh=360.0"]),
]


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    viaduct, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    failures = silent = warned = refused = 0
    with tempfile.TemporaryDirectory(prefix="viaduct-plausibility-") as work:
        for i, (cmd, scenario, sets) in enumerate(CASES):
            out = os.path.join(work, str(i))
            args = [viaduct, cmd, os.path.join(src, scenario), "--out", out, "--quiet", "--threads", "2"]
            if cmd == "run":
                args.remove("--threads"), args.remove("2")
            for s in sets:
                args += ["--set", s]
            r = subprocess.run(args, capture_output=True, timeout=300)
            message = (r.stdout + r.stderr).decode("utf-8", "replace")
            shown = " ".join(args[1:3]) + " " + " ".join("--set " + s for s in sets)
            problems = outputs_problems(out)
            if r.returncode not in (0, 1, 2):
                problems.append(f"exit {r.returncode}")
            elif r.returncode == 0:
                problems += plausibility_problems(out, message)
                warned += "warning" in message
            else:
                refused += 1
                if "error" not in message and "failed" not in message:
                    problems.append(f"exit {r.returncode} without a message")
            if problems:
                failures += 1
                silent += r.returncode == 0
                print(f"FAIL {shown}: {'; '.join(problems)}")
    n = len(CASES)
    print(f"{n} extreme runs: {refused} stopped with a message, {warned} warned, {n - refused - warned} plausible and "
          f"quiet; {failures} failed ({silent} exit 0 with an absurd number and no warning)")
    if "--summary" in sys.argv:
        print(f"| {n} | {refused} | {warned} | {failures} |")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

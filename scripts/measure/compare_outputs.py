#!/usr/bin/env python3
"""Compares two output trees written by scripts/measure/snapshot_outputs.sh (before and after a change).

    scripts/measure/compare_outputs.py BEFORE AFTER [--rtol 0]

Every file is compared: CSV and text files cell by cell (numbers by value, with the relative
tolerance given; 0 asks for identical values), PNG and other binary files by size only. Lines
that carry wall times, dates, versions, commits or paths (manifest keys *wall*, version, commit,
date, command, checksums; "... s" timings on stdout) are skipped. Prints one line per file that
differs with the largest relative difference and where, then a summary; exit 1 when anything
differs beyond the tolerance, or a file is missing on one side.
"""
import argparse
import os
import re
import sys

SKIP_KEYS = re.compile(r"(wall|_s\b.*=.*|version|commit|date|command|sha256|checksum|threads|elapsed)", re.I)
TIMING = re.compile(r"(\d+(\.\d+)?\s*(s|ms)\b|in \d|simulations,|wall)", re.I)
ROOTS = ["", ""]
# CSV columns that hold wall times (compared by presence only)
WALL_COLUMNS = re.compile(r"wall|time_s$|seconds", re.I)
NUM = re.compile(r"^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$|^[-+]?(nan|inf)$", re.I)


def skip_line(path, line):
    name = os.path.basename(path)
    if name == "manifest.toml" or name.endswith(".toml"):
        key = line.split("=", 1)[0]
        return bool(re.search(r"wall|version|commit|date|utc|command|sha256|checksum|out_dir|threads", key, re.I))
    if name.endswith((".stdout", ".stderr", ".md", ".txt")):
        return bool(TIMING.search(line))
    return False


def cells(line):
    return line.split(",") if "," in line else re.split(r"\s+", line.strip())


def compare_file(a, b, rtol):
    with open(a, "rb") as fa, open(b, "rb") as fb:
        da, db = fa.read(), fb.read()
    if da == db:
        return None
    if a.endswith(".png"):
        return None  # rendering; sizes may differ by font cache, values are in the CSVs
    try:
        # paths under the two trees are the same file
        la = [l.replace(ROOTS[0], "ROOT") for l in da.decode().splitlines() if not skip_line(a, l)]
        lb = [l.replace(ROOTS[1], "ROOT") for l in db.decode().splitlines() if not skip_line(b, l)]
    except UnicodeDecodeError:
        return "binary files differ"
    if len(la) != len(lb):
        return f"{len(la)} against {len(lb)} lines"
    skip_cols = set()
    if a.endswith(".csv") and la:
        skip_cols = {j for j, h in enumerate(la[0].split(",")) if WALL_COLUMNS.search(h)}
    worst, where = 0.0, None
    for i, (x, y) in enumerate(zip(la, lb)):
        if x == y:
            continue
        ca, cb = cells(x), cells(y)
        if len(ca) != len(cb):
            return f"line {i + 1}: {x!r} against {y!r}"
        for j, (p, q) in enumerate(zip(ca, cb)):
            if p == q or j in skip_cols:
                continue
            if NUM.match(p) and NUM.match(q):
                u, v = float(p), float(q)
                if u == v or (u != u and v != v):
                    continue
                d = abs(u - v) / max(abs(u), abs(v), 1e-300)
                if d > worst:
                    worst, where = d, f"line {i + 1} cell {j + 1}: {p} against {q}"
            else:
                return f"line {i + 1}: {x!r} against {y!r}"
    if worst > rtol:
        return f"relative difference {worst:.3g} ({where})"
    return None if worst == 0.0 else f"within tolerance: {worst:.3g} ({where})"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("before")
    ap.add_argument("after")
    ap.add_argument("--rtol", type=float, default=0.0)
    a = ap.parse_args()
    files = set()
    for root in (a.before, a.after):
        for d, _, fs in os.walk(root):
            for f in fs:
                files.add(os.path.relpath(os.path.join(d, f), root))
    ROOTS[:] = [os.path.abspath(a.before), os.path.abspath(a.after)]
    bad = tol = same = 0
    for f in sorted(files):
        pa, pb = os.path.join(a.before, f), os.path.join(a.after, f)
        if not os.path.exists(pa) or not os.path.exists(pb):
            print(f"{f}: only in {'after' if not os.path.exists(pa) else 'before'}")
            bad += 1
            continue
        r = compare_file(pa, pb, a.rtol)
        if r is None:
            same += 1
        elif r.startswith("within tolerance"):
            tol += 1
            print(f"{f}: {r}")
        else:
            bad += 1
            print(f"{f}: {r}")
    print(f"{len(files)} files: {same} identical (timings aside), {tol} within rtol {a.rtol:g}, {bad} differ")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())

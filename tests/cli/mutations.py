#!/usr/bin/env python3
"""CLI-level mutation test (issue #18): the shipped inputs, mutated as a hostile user would, run
through the commands that read them.

Each mutation copies one shipped file (a scenario, a bridge, a track, a train, a record, a UFF
file or an FRF table), changes it one to three times (a number replaced by an extreme value,
a line deleted, repeated or swapped, the file cut, bytes inserted, a byte-order mark, a key
misspelt), and runs a command on it. Every run must:
  - exit 0, 1 or 2, within the time limit, with no sanitizer report, no uncaught exception;
  - on exit 2 (bad input), name the file or the option it blames and say "error";
  - leave no output file holding a NaN or an infinity, and no temporary file;
  - on exit 0, hold no finite but absurd number that no warning announced (the plausibility
    oracle: deflections and load effects against the same train crawling, deck deflections against
    L/100, accelerations against 100 g, contact forces against their static loads; issue #36).

  mutations.py VIADUCT SOURCE_DIR [--mutations N] [--seed S] [--timeout SECONDS] [--summary]

A failure prints the mutation's seed and the command that reproduces it (with the mutated file
kept in --keep DIR). Mutation i of seed S is the same on every machine.
"""
import argparse
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile
import time

# The extreme values a number is replaced with: zero and signs, the ends of double, values whose
# squares overflow or underflow, step counts that overflow an integer, non-numbers, fractions
# where counts are due, and text.
EXTREMES = ["0", "-0", "-1", "1e308", "-1e308", "1e-308", "5e-324", "1e154", "1e-154", "1e16",
            "9.2e18", "nan", "inf", "-inf", "0.5", "2.5", "123456789", "", "x", "1e-16", "1e6"]
NUMBER = re.compile(rb"(?<![A-Za-z_0-9.])[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")
KEY = re.compile(rb"^\s*([A-Za-z_][A-Za-z_0-9.]*)\s*=", re.M)
# What a non-finite number looks like in a CSV or TOML output.
NON_FINITE = re.compile(rb"(?<![A-Za-z_])[-+]?(?:nan|inf|infinity)(?![A-Za-z_])", re.I)
NON_FINITE_CELL = re.compile(rb"^[-+]?(?:nan|inf|infinity)$", re.I)
TOML_STRING = re.compile(rb'"(?:[^"\\]|\\.)*"' + rb"|'[^']*'")
# An error names the file it blames (the mutated one, or one it led to) or the option.
NAMED_FILE = re.compile(r"[\w./-]+\.(toml|csv|uff)\b")
BAD_OUTPUT = ("AddressSanitizer", "runtime error:", "LeakSanitizer", "terminate called",
              "Segmentation fault", "what():", "std::bad_alloc")


def mutate_number(data, rng):
    found = list(NUMBER.finditer(data))
    if not found:
        return data
    m = rng.choice(found)
    if rng.random() < 0.75:
        new = rng.choice(EXTREMES).encode()
    else:  # scaled or negated, a plausible mistake
        try:
            value = float(m.group(0))
        except ValueError:
            return data
        new = repr(value * rng.choice([-1.0, 1e3, 1e-3, 1e9, 1e-9, 0.0])).encode()
    return data[:m.start()] + new + data[m.end():]


def split_lines(data):
    return data.split(b"\n")


def delete_line(data, rng):
    lines = split_lines(data)
    if len(lines) > 1:
        del lines[rng.randrange(len(lines))]
    return b"\n".join(lines)


def repeat_line(data, rng):
    lines = split_lines(data)
    i = rng.randrange(len(lines))
    lines[i:i + 1] = [lines[i]] * rng.choice([2, 3, 50])
    return b"\n".join(lines)


def swap_lines(data, rng):
    lines = split_lines(data)
    i, j = rng.randrange(len(lines)), rng.randrange(len(lines))
    lines[i], lines[j] = lines[j], lines[i]
    return b"\n".join(lines)


def cut(data, rng):
    return data[:rng.randrange(len(data) + 1)]


def insert_bytes(data, rng):
    pos = rng.randrange(len(data) + 1)
    junk = rng.choice([b"\0", b"\xff\xfe", b",", b";", b"\t", b"\"", b"[", b"]", b"=", b"\n",
                       b"\r\n", b"#", b"-1\n", b"1,2,3\n", b"\xc3\x28", b" " * 300])
    return data[:pos] + junk + data[pos:]


def byte_order_mark(data, rng):
    return b"\xef\xbb\xbf" + data


def misspell_key(data, rng):
    keys = list(KEY.finditer(data))
    if not keys:
        return flip_byte(data, rng)
    m = rng.choice(keys)
    name = bytearray(m.group(1))
    i = rng.randrange(len(name))
    name[i] = ord(rng.choice("abcxyz_"))
    return data[:m.start(1)] + bytes(name) + data[m.end(1):]


def flip_byte(data, rng):
    if not data:
        return data
    i = rng.randrange(len(data))
    return data[:i] + bytes([rng.randrange(256)]) + data[i + 1:]


OPERATIONS = [(mutate_number, 8), (delete_line, 2), (repeat_line, 1), (swap_lines, 1), (cut, 1),
              (insert_bytes, 1), (byte_order_mark, 1), (misspell_key, 2), (flip_byte, 1)]


def mutate(data, rng):
    ops = [op for op, weight in OPERATIONS for _ in range(weight)]
    for _ in range(rng.choice([1, 1, 2, 3])):
        data = rng.choice(ops)(data, rng)
    return data


# (files that may be mutated, command) with paths relative to the copied source tree; OUT is the
# output directory of the run. The records are cut to their first lines (the commands' work
# grows with the record, the parsing paths do not).
CASES = [
    (["scenarios/hslm-simply-supported.toml"], ["check", "scenarios/hslm-simply-supported.toml"]),
    (["scenarios/old-guadiana-sensitivity.toml", "data/bridges/old-guadiana.toml",
      "data/tracks/old-guadiana-ballasted.toml"], ["check", "scenarios/old-guadiana-sensitivity.toml"]),
    (["scenarios/old-guadiana-talgo.toml", "data/trains/talgo-altaria.csv", "data/bridges/old-guadiana.toml"],
     ["run", "scenarios/old-guadiana-talgo.toml", "--out", "OUT"]),
    (["scenarios/hslm-simply-supported.toml"],
     ["sweep", "scenarios/hslm-simply-supported.toml", "--set", "sweep.speed_step_kmh=140",
      "--set", 'train.files=["hslm:A1"]', "--out", "OUT"]),
    (["scenarios/hslm-simply-supported.toml"], ["modes", "scenarios/hslm-simply-supported.toml", "--out", "OUT"]),
    (["data/trains/artificial-20x210.toml"],
     ["run", "scenarios/hslm-simply-supported.toml", "--set", 'train.files=["data/trains/artificial-20x210.toml"]',
      "--out", "OUT"]),
    (["scenarios/vehicles-25m.toml", "data/trains/ave-s103-8.toml", "data/vehicles/ave-s103.toml"],
     ["run", "scenarios/vehicles-25m.toml", "--set", "run.speed_kmh=300", "--out", "OUT"]),
    (["record.csv"], ["spectrum", "record.csv", "--out", "OUT"]),
    (["record.csv"], ["spectrum", "record.csv", "--welch", "--nperseg", "256", "--out", "OUT"]),
    (["record.csv"], ["peaks", "record.csv", "--out", "OUT"]),
    (["record.csv"], ["filter", "record.csv", "--out", "OUT"]),
    (["record.csv"], ["envelope", "record.csv", "--kind", "hilbert", "--out", "OUT"]),
    (["record.csv"], ["resample", "record.csv", "--fs-hz", "200", "--out", "OUT"]),
    (["passage.csv"], ["decay", "passage.csv", "--channel", "S1_mid_acc_mps2", "--frequency-hz", "10",
                       "--out", "OUT"]),
    (["two-channels.uff"], ["spectrum", "two-channels.uff", "--out", "OUT"]),
    (["frf.csv"], ["modal-fit", "frf.csv", "--out", "OUT"]),
]


def prepare(viaduct, source, tree):
    for d in ("scenarios", "data"):
        shutil.copytree(os.path.join(source, d), os.path.join(tree, d))
    with open(os.path.join(source, "data/records/synthetic-deck.csv"), "rb") as f:
        head = f.read().split(b"\n")[:1200]
    with open(os.path.join(tree, "record.csv"), "wb") as f:
        f.write(b"\n".join(head) + b"\n")
    shutil.copy(os.path.join(source, "tests/fuzz/corpus/uff/two-channels.uff"), tree)
    subprocess.run([viaduct, "frf", "scenarios/old-guadiana-talgo.toml", "--force-at", "6", "--f-min", "5",
                    "--f-max", "15", "--n-freq", "101", "--out", "frf", "-q"], cwd=tree, check=True)
    shutil.copy(os.path.join(tree, "frf/frf.csv"), os.path.join(tree, "frf.csv"))
    # A passage with its free decay, the mid-span acceleration only.
    subprocess.run([viaduct, "run", "scenarios/old-guadiana-talgo.toml", "--set", "analysis.free_vibration_s=2",
                    "--out", "passage", "-q"], cwd=tree, check=True)
    with open(os.path.join(tree, "passage/history.csv")) as f, open(os.path.join(tree, "passage.csv"), "w") as g:
        for line in f:
            g.write(",".join(line.rstrip("\n").split(",")[:3:2]) + "\n")


def check_unmutated(viaduct, tree):
    """Every case runs clean on the files as shipped: otherwise its mutations test nothing."""
    for files, command in CASES:
        out = os.path.join(tree, "out-unmutated")
        args = [viaduct] + [out if a == "OUT" else a for a in command] + ["-q"]
        r = subprocess.run(args, cwd=tree, capture_output=True)
        problems = outputs_problems(out) + plausibility_problems(out, (r.stdout + r.stderr).decode(errors="replace"))
        shutil.rmtree(out, ignore_errors=True)
        if r.returncode != 0 or problems:
            raise SystemExit(f"the unmutated case fails (exit {r.returncode}): {' '.join(args)}\n"
                             f"{(r.stdout + r.stderr).decode(errors='replace')}{'; '.join(problems)}")


def outputs_problems(out):
    problems = []
    if not os.path.isdir(out):
        return problems
    for name in sorted(os.listdir(out)):
        path = os.path.join(out, name)
        if name.startswith(".") and ".tmp-" in name:
            problems.append(f"temporary file left: {name}")
        elif os.path.isfile(path) and (name.endswith(".csv") or name.endswith(".toml")):
            with open(path, "rb") as f:
                data = f.read()
            for line_no, line in enumerate(data.split(b"\n"), 1):
                if name.endswith(".csv"):
                    bad = [c for c in line.split(b",") if NON_FINITE_CELL.match(c.strip())]
                else:  # TOML: the values outside strings (a title may say "nan")
                    bad = NON_FINITE.findall(TOML_STRING.sub(b'""', line))
                if bad:
                    problems.append(f"{name}:{line_no}: non-finite value {bad[0]!r}")
                    break
    return problems


# The plausibility oracle (issue #36): a run that exits 0 must not hold a finite but absurd number
# unless it said so (a warning on stderr, or in the manifest). Bounds, from the run's own
# independent quantities: a deflection or load effect of a passage against the same train
# crawling (the quasi-static response, K⁻¹ f: another code path than the time stepping), an
# acceleration against multiples of g, a wheel-rail force against its static load.
MAX_PHI = 50.0           # |dynamic| / |quasi-static| - 1: resonance of an undamped span under a long train stays below
MAX_ACC_MPS2 = 100 * 9.81
MAX_CONTACT_RATIO = 50.0  # |contact force| / static axle load


def read_table(path):
    import csv
    with open(path, newline="") as f:
        rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    return rows[0], rows[1:]


def cell(x):
    try:
        return abs(float(x))
    except ValueError:
        return 0.0


# What announces each class: a warning that names the implausible input or response (a unit to
# check, a deflection beyond L/100), or, for contact forces, the wheels' loss of contact.
STRUCTURE_WARNINGS = ("L/100", "check the unit")
CONTACT_WARNINGS = ("left the rail", "lost contact", "would have lost contact")


def column_maxima(out, tables, matches):
    """(file, column, its largest value) for every column of the tables (file, pattern) in `out`
    that exist whose name matches(column, pattern)."""
    for name, pattern in tables:
        path = os.path.join(out, name)
        if not os.path.exists(path):
            continue
        head, rows = read_table(path)
        for j, h in enumerate(head):
            if matches(h, pattern):
                yield name, h, max((cell(r[j]) for r in rows if j < len(r)), default=0.0)


def plausibility_problems(out, message):
    """Absurd magnitudes in a run's outputs that no warning announced."""
    text = message
    if os.path.exists(os.path.join(out, "manifest.toml")):
        with open(os.path.join(out, "manifest.toml"), "rb") as f:
            text += f.read().decode("utf-8", "replace")
    problems = []
    if any(w in text for w in STRUCTURE_WARNINGS):
        return problems
    inc = os.path.join(out, "dynamic_increments.csv")
    if os.path.exists(inc):
        head, rows = read_table(inc)
        for r in rows:
            phi = cell(r[head.index("phi_dyn")])
            if not r[0].endswith("_rot_rad") and cell(r[head.index("max_static")]) > 0 and phi > MAX_PHI:
                problems.append(f"dynamic_increments.csv: {r[0]} phi'dyn = {phi:g} (> {MAX_PHI:g}) without a warning")
    for name, h, top in column_maxima(out, (("history.csv", "_acc"), ("governing.csv", "max_abs_acc_mps2")),
                                      lambda h, pattern: pattern in h and h.endswith("mps2")):
        if top > MAX_ACC_MPS2:
            problems.append(f"{name}: {h} reaches {top:g} m/s² (> 100 g) without a warning")
    # A deck deflection beyond the shortest span / 100 (the resolved scenario's spans).
    spans = []
    try:
        import tomllib
        with open(os.path.join(out, "manifest.toml"), "rb") as f:
            spans = tomllib.load(f).get("scenario", {}).get("bridge.span_lengths", [])
    except Exception:  # no manifest, or no tomllib (Python < 3.11): this bound is skipped
        spans = []
    if spans:
        limit = min(spans) / 100.0
        for name, h, top in column_maxima(out, (("history.csv", "_disp_m"), ("governing.csv", "max_abs_disp_m")),
                                          lambda h, pattern: h.endswith(pattern) and "rail" not in h):
            if top > limit:
                problems.append(f"{name}: {h} reaches {top * 1e3:g} mm, beyond L/100 of the shortest span, without a warning")
    contact = os.path.join(out, "contact.csv")
    if os.path.exists(contact) and not any(w in text for w in CONTACT_WARNINGS):
        head, rows = read_table(contact)
        for r in rows:
            static = cell(r[head.index("static_N")])
            top = max(cell(r[head.index("min_N")]), cell(r[head.index("max_N")]))
            if static > 0 and top > MAX_CONTACT_RATIO * static:
                problems.append(f"contact.csv: axle {r[0]} {top:g} N, {top / static:g} x its static load, without a warning")
    return problems


def run_one(viaduct, tree, i, seed, timeout, keep):
    rng = random.Random(seed * 1_000_003 + i)
    files, command = rng.choice(CASES)
    target = rng.choice(files)
    path = os.path.join(tree, target)
    with open(path, "rb") as f:
        original = f.read()
    mutated = mutate(original, rng)
    out = os.path.join(tree, f"out-{i}")
    args = [viaduct] + [out if a == "OUT" else a for a in command] + ["-q"]
    shown = " ".join(args)
    problems, rc, message, took = [], None, "", 0.0
    try:
        with open(path, "wb") as f:
            f.write(mutated)
        start = time.monotonic()
        try:
            r = subprocess.run(args, cwd=tree, capture_output=True, timeout=timeout)
            rc, message = r.returncode, (r.stdout + r.stderr).decode("utf-8", "replace")
        except subprocess.TimeoutExpired:
            rc = "timeout"
        took = time.monotonic() - start
        if rc == "timeout":  # counted and shown, not a failure: a slow valid case is not a crash
            print(f"slow: mutation {i} (seed {seed}) ran over {timeout:g} s: {shown}")
        elif rc not in (0, 1, 2):
            problems.append(f"exit {rc}")
        for bad in BAD_OUTPUT:
            if bad in message:
                problems.append(f"output holds '{bad}'")
        if rc == 2:
            if "error" not in message:
                problems.append("exit 2 without 'error'")
            if not NAMED_FILE.search(message) and "--" not in message:
                problems.append("exit 2 names no file and no option")
        problems += outputs_problems(out)
        if rc == 0:
            problems += plausibility_problems(out, message)
        if (problems or rc == "timeout") and keep:
            os.makedirs(keep, exist_ok=True)
            kept = os.path.join(keep, f"{i}-{os.path.basename(target)}")
            with open(kept, "wb") as f:
                f.write(mutated)
            shown += f"   (mutated {target} kept as {kept})"
    finally:
        with open(path, "wb") as f:
            f.write(original)
        shutil.rmtree(out, ignore_errors=True)
    line_named = rc == 2 and re.search(r":\d+:", message) is not None
    return problems, rc, shown, message, took, line_named


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("viaduct")
    p.add_argument("source")
    p.add_argument("--mutations", type=int, default=300)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--timeout", type=float, default=30.0)
    p.add_argument("--keep", help="directory where the mutated files of failures are kept")
    p.add_argument("--summary", action="store_true", help="print the figures as a Markdown table row")
    a = p.parse_args()
    viaduct = os.path.abspath(a.viaduct)
    tree = tempfile.mkdtemp(prefix="viaduct-mutations-")
    counts = {0: 0, 1: 0, 2: 0, "timeout": 0}
    failures, with_line, start = 0, 0, time.monotonic()
    try:
        prepare(viaduct, os.path.abspath(a.source), tree)
        check_unmutated(viaduct, tree)
        for i in range(a.mutations):
            problems, rc, shown, message, took, line_named = run_one(viaduct, tree, i, a.seed, a.timeout, a.keep)
            counts[rc] = counts.get(rc, 0) + 1
            with_line += line_named
            if problems:
                failures += 1
                print(f"FAIL mutation {i} (seed {a.seed}): {'; '.join(problems)}\n  {shown}")
                print("  " + "\n  ".join(message.strip().splitlines()[-6:]))
    finally:
        shutil.rmtree(tree, ignore_errors=True)
    secs = time.monotonic() - start
    others = {k: v for k, v in counts.items() if k not in (0, 1, 2, "timeout")}
    print(f"{a.mutations} mutated runs in {secs:.0f} s: exit 0: {counts[0]}, exit 1: {counts[1]}, "
          f"exit 2: {counts[2]} ({with_line} with a line number), timeouts ({a.timeout:g} s): "
          f"{counts['timeout']}, other: {others or 0}; {failures} failed")
    if a.summary:
        print(f"| {a.mutations} | {a.seed} | {secs:.0f} | {counts[0]} | {counts[1]} | {counts[2]} | "
              f"{with_line} | {counts['timeout']} | {failures} |")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

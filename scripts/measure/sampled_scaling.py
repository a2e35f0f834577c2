#!/usr/bin/python3
"""Time per case, memory and scaling of a sampled study (docs/sampled.md, docs/benchmarks.md).

Usage: scripts/measure/sampled_scaling.py VIADUCT [--scenario scenarios/old-guadiana-sampled.toml]
           [--samples 25 50 100] [--scaling-samples 64] [--repeat 3] [--no-mpi] [--write PAGE]

1. Samples: one process, --threads 1, n samples of the scenario (60 speeds): wall time, time per
   case (sample x speed x train) and peak resident memory (the child's own, from wait4), for each n.
2. Scaling at --scaling-samples: one process with 1 and 2 threads; 2 shards run at once (1 thread
   each) and merged; mpirun -n 2 (1 thread each) when mpirun is there. Medians of --repeat runs,
   ratios to the one-thread run measured in the same pass.
Prints markdown tables; with --write, the page docs/benchmarks-sampled.md (command, date, machine).
"""
import argparse
import datetime
import os
import platform
import shutil
import statistics
import subprocess
import tempfile
import time

ROOT_ENV = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1", "OMPI_MCA_rmaps_base_oversubscribe": "1"}


def run(cmds):
    """Starts every command at once; returns (wall s, largest peak RSS in MB of the children)."""
    env = dict(os.environ, **ROOT_ENV)
    t0 = time.perf_counter()
    procs = [subprocess.Popen(c, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env) for c in cmds]
    rss = 0
    for p in procs:
        _, status, usage = os.wait4(p.pid, 0)
        p.returncode = os.waitstatus_to_exitcode(status)
        if p.returncode != 0:
            raise SystemExit("failed (%d): %s\n%s" % (p.returncode, " ".join(p.args), p.stderr.read().decode()))
        rss = max(rss, usage.ru_maxrss / 1024.0)
    return time.perf_counter() - t0, rss


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("viaduct")
    ap.add_argument("--scenario", default="scenarios/old-guadiana-sampled.toml")
    ap.add_argument("--samples", type=int, nargs="+", default=[25, 50, 100])
    ap.add_argument("--scaling-samples", type=int, default=64)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--no-mpi", action="store_true")
    ap.add_argument("--write", help="write the tables into this markdown page")
    a = ap.parse_args()
    lines = []

    def out(text):
        print(text)
        lines.append(text)

    tmp = tempfile.mkdtemp(prefix="viaduct-sampled-")
    base = [a.viaduct, "sweep", a.scenario, "--quiet"]
    try:
        out("## Time per case and memory (one process, 1 thread)\n")
        out("| samples | cases | wall s | ms per case | peak RSS MB |\n|---:|---:|---:|---:|---:|")
        for n in a.samples:
            odir = os.path.join(tmp, "n%d" % n)
            wall, rss = run([base + ["--set", "sweep.n_samples=%d" % n, "--threads", "1", "--out", odir]])
            with open(os.path.join(odir, "sample_peaks.csv")) as f:
                peaks = f.readlines()[1:]  # not `lines`: that name holds the page
            rows = len(peaks)
            stations = len({line.split(",")[3] for line in peaks})
            cases = rows // max(1, stations)
            out("| %d | %d | %.1f | %.2f | %.0f |" % (n, cases, wall, 1e3 * wall / cases, rss))
        n = a.scaling_samples
        sset = ["--set", "sweep.n_samples=%d" % n]
        ways = [("1 process, 1 thread", lambda o: [base + sset + ["--threads", "1", "--out", o]]),
                ("1 process, 2 threads", lambda o: [base + sset + ["--threads", "2", "--out", o]]),
                ("2 shards at once, 1 thread each (+ merge)",
                 lambda o: [base + sset + ["--threads", "1", "--shard", "%d/2" % k, "--out", o + "-%d" % k] for k in (1, 2)])]
        if not a.no_mpi and shutil.which("mpirun"):
            ways.append(("mpirun -n 2, 1 thread each",
                         lambda o: [["mpirun", "-n", "2"] + base + sset + ["--threads", "1", "--out", o]]))
        times = {name: [] for name, _ in ways}
        for r in range(a.repeat):
            for name, make in ways:
                odir = os.path.join(tmp, "w%d" % r)
                wall, _ = run(make(odir))
                if name.startswith("2 shards"):
                    t0 = time.perf_counter()
                    subprocess.run([a.viaduct, "merge", odir + "-1", odir + "-2", "--quiet", "--out", odir + "-m"], check=True)
                    wall += time.perf_counter() - t0
                times[name].append(wall)
        ref = statistics.median(times[ways[0][0]])
        out("\n## Scaling: %d samples, medians of %d runs\n\n| run | wall s | speed-up |\n|---|---:|---:|" % (n, a.repeat))
        for name, _ in ways:
            m = statistics.median(times[name])
            out("| %s | %.1f | %.2f |" % (name, m, ref / m))
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    if a.write:
        cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), platform.machine())
        head = ("# Benchmark: sampled studies (`viaduct sweep`, sweep.mode = \"sample\")\n\n"
                "Measured by `scripts/measure/sampled_scaling.py %s --samples %s --scaling-samples %d --repeat %d` "
                "on %s, %d cores (%s), scenario `%s` (60 speeds, analysis.preset = \"default\"). The machine is "
                "shared and noisy: scaling times are medians, ratios from the same pass. Speed is measured here, "
                "never asserted in tests. What the study computes: [sampled.md](sampled.md).\n\n"
                % (a.viaduct, " ".join(map(str, a.samples)), a.scaling_samples, a.repeat,
                   datetime.date.today().isoformat(), os.cpu_count(), cpu, a.scenario))
        with open(a.write, "w") as f:
            f.write(head + "\n".join(lines) + "\n")
        print("wrote", a.write)


if __name__ == "__main__":
    main()

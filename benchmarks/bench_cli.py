"""End-to-end cost per event of ``python -m bounce simulate`` (simulation + netCDF write + summary).

Runs the CLI as a subprocess at a small and a large event count and reports
(T_large - T_small) / (N_large - N_small): interpreter start-up, imports and JIT-cache
loading cancel.  Medians of ``--repeats`` runs, wall and CPU (user + sys) time; the machine
may be shared (then CPU time is the steadier number), so the load average is printed too.  Also measures the written file's size and, with
``--compression``, compares the codecs of bounce.io (size, write speed, and whether
netCDF-C's ``ncdump`` reads the file).

With ``--startup``, the start-up instead (issue 22): wall, CPU and peak RSS of ``simulate --events 1``, and the
same for probes that each import one layer more (bare interpreter, numpy, numba, numba with a cached kernel
loaded, xarray, ...), so that the difference of two rows is what that layer costs and the first rows are floors
no code of bounce can remove.  With ``--logs DIR`` (a finished run's ``results/logs``; alone, or after the start-up
table), the per-job-kind table of the exact ``cpu:`` lines of pipeline.tasks: the smallest job of a kind is an upper
bound of its start-up, and a column gives the CPU the jobs spent saving figures.

    python benchmarks/bench_cli.py                       # 1e5 vs 2e6 events, 3 repeats
    python benchmarks/bench_cli.py --compression         # also the codec table
    python benchmarks/bench_cli.py --startup --repeats 7 --logs results/logs
    python benchmarks/bench_cli.py --logs results/logs   # the table of a finished run only
"""

from __future__ import annotations

import argparse
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ARGS = ["--gamma", "0.01", "--mu", "0.01", "--psi0", "6", "--psidot0", "0", "--xi0", "0", "--xidot0", "0"]


def run_cli(events: int, out: Path, extra=()) -> tuple[float, float]:
    """(wall, CPU = user + sys) seconds of one CLI run."""
    cmd = [sys.executable, "-m", "bounce", "simulate", *ARGS, "--events", str(events), "--out", str(out), *extra]
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    wall = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)


SIMULATE_ONE = [sys.executable, "-m", "bounce", "simulate", "--gamma", "0.01", "--mu", "0.01", "--x0", "1",
                "--xdot0", "0", "--y0", "2", "--ydot0", "0", "--events", "1"]
#: (layer, Python code) for ``python -c``, each importing what the one above it does and one layer more
STARTUP_PROBES = (
    ("interpreter", "pass"),
    ("numpy", "import numpy"),
    ("numba", "import numba"),
    ("numba + one cached kernel (target context: numba.np.arraymath -> scipy.linalg)",
     "import sys; sys.path.insert(0, {tmp!r}); import startup_kernel"),
    ("xarray (pandas)", "import xarray"),
    ("netCDF4", "import netCDF4"),
    ("matplotlib.pyplot (Agg)", "import matplotlib; matplotlib.use('Agg'); import matplotlib.pyplot"),
    ("bounce (numba, kernels decorated)", "import bounce"),
    ("bounce + simulate 1 event (kernels loaded)", "from bounce import Parameters, State, simulate\n"
     "simulate(Parameters(0.01, 0.01), State(1.0, 0.0, 2.0, 0.0), max_events=1)"),
    ("bounce.io (+ xarray)", "import bounce.io"),
    ("pipeline.tasks", "import bounce.pipeline.tasks"),
    ("pipeline.tasks + checks.base", "import bounce.pipeline.tasks, bounce.checks.base"),
    ("pipeline.tasks + sweeps.base", "import bounce.pipeline.tasks, bounce.sweeps.base"),
    ("pipeline.tasks + studies", "import bounce.pipeline.tasks, bounce.studies"),
    ("pipeline.tasks + figures (matplotlib)", "import bounce.pipeline.tasks, bounce.figures"),
)


def run_measured(cmd) -> tuple[float, float, float]:
    """(wall s, CPU = user + sys s, peak RSS MB) of one subprocess."""
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - t0
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode:
        raise subprocess.CalledProcessError(proc.returncode, cmd)
    return wall, usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024


#: the module of the cached-kernel probe (numba caches only kernels defined in a file)
STARTUP_KERNEL = "import numba\n\n\n@numba.njit(cache=True)\ndef f(x):\n    return x + 1.0\n\n\nf(1.0)\n"


def startup_table(out: Path, repeats: int) -> None:
    """Medians of ``repeats`` runs of each probe and of the CLI, interleaved (the load drifts alike for all)."""
    (out.parent / "startup_kernel.py").write_text(STARTUP_KERNEL)
    rows = [(name, [sys.executable, "-c", code.format(tmp=str(out.parent))]) for name, code in STARTUP_PROBES]
    rows.append(("CLI simulate --events 1 (+ netCDF write)", [*SIMULATE_ONE, "--out", str(out)]))
    for _, cmd in rows:  # warm the page cache and the JIT cache
        run_measured(cmd)
    load = os.getloadavg()[0]
    runs = {name: [] for name, _ in rows}
    for _ in range(repeats):
        for name, cmd in rows:
            runs[name].append(run_measured(cmd))
    print(f"start-up, median of {repeats} (load average {load:.1f} -> {os.getloadavg()[0]:.1f}, "
          f"{os.cpu_count()} cores)")
    print(f"  {'':82} {'wall s':>7} {'CPU s':>7} {'RSS MB':>7}")
    for name, _ in rows:
        wall, cpu, rss = (statistics.median(r[i] for r in runs[name]) for i in range(3))
        print(f"  {name:82} {wall:7.3f} {cpu:7.3f} {rss:7.0f}")


def job_kind(log: Path, logs: Path) -> str:
    """checks/<group>/<x>.log -> checks, sweeps/<name>/gather.log -> sweeps gather, ..."""
    parts = log.relative_to(logs).parts
    if parts[0] == "sweeps":
        return "sweeps " + ("shard" if log.stem.startswith("shard") else log.stem)
    if parts[0] == "simulate" and len(parts) > 2:
        return "simulate " + parts[1]
    return parts[0] if len(parts) > 1 else log.stem


def logs_table(logs: Path) -> None:
    """Per job kind: jobs, smallest, median and total CPU of their ``cpu:`` lines (process + workers), and the total
    spent saving figures (matplotlib: layout, drawing, fonts, PNG and PDF; NaN for logs written before it was given)."""
    from bounce.pipeline.tasks import CPU_LINE

    cpus, saving, served = {}, {}, 0
    for log in sorted(logs.rglob("*.log")):
        lines = [m for m in map(CPU_LINE.match, log.read_text(errors="replace").splitlines()) if m]
        if lines:
            own, started_by, workers, figures = lines[-1].groups()
            kind = job_kind(log, logs)
            cpus.setdefault(kind, []).append(float(own) + float(workers))
            saving[kind] = saving.get(kind, 0.0) + float(figures or "nan")
            served += bool(started_by)
    print(f"job CPU from {logs} (cpu: lines; the smallest bounds the kind's start-up; {served} jobs forked by the "
          f"run's task server, whose imports they do not count)")
    print(f"  {'kind':18} {'jobs':>5} {'min s':>7} {'median s':>9} {'total s':>8} {'saving figures s':>17}")
    for kind, values in sorted(cpus.items()):
        print(f"  {kind:18} {len(values):5d} {min(values):7.2f} {statistics.median(values):9.2f} {sum(values):8.1f} "
              f"{saving[kind]:17.1f}")
    every = [v for values in cpus.values() for v in values]
    print(f"  {'all':18} {len(every):5d} {min(every):7.2f} {statistics.median(every):9.2f} {sum(every):8.1f} "
          f"{sum(saving.values()):17.1f}")


def median_time(events: int, out: Path, repeats: int, extra=()) -> tuple[float, float]:
    runs = [run_cli(events, out, extra) for _ in range(repeats)]
    return statistics.median(w for w, _ in runs), statistics.median(c for _, c in runs)


def solver_ns_per_event(small: int, large: int, repeats: int) -> float:
    """CPU ns/event of bounce.simulate alone (the same drop, in this process), large minus small."""
    from bounce import Parameters, State, simulate

    p, s0 = Parameters(0.01, 0.01), State.from_psi_xi(6.0, 0.0, 0.0, 0.0)
    simulate(p, s0, max_events=1000)

    def cpu(n):
        t0 = time.process_time()
        simulate(p, s0, max_events=n)
        return time.process_time() - t0

    return statistics.median((cpu(large) - cpu(small)) / (large - small) * 1e9 for _ in range(repeats))


def ncdump_reads(path: Path) -> str:
    if shutil.which("ncdump") is None:
        return "ncdump not installed"
    r = subprocess.run(["ncdump", "-v", "kind", str(path)], capture_output=True, text=True)
    return "yes" if r.returncode == 0 else "NO: " + (r.stderr.strip().splitlines() or ["?"])[-1][:60]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--small", type=int, default=100_000)
    parser.add_argument("--large", type=int, default=2_000_000)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--compression", action="store_true", help="also compare the codecs")
    parser.add_argument("--startup", action="store_true", help="the start-up table instead (issue 22)")
    parser.add_argument("--logs", type=Path, help="a finished run's results/logs: CPU per job kind (alone, or after "
                        "the --startup table)")
    args = parser.parse_args()
    if args.startup or args.logs:
        if args.startup:
            with tempfile.TemporaryDirectory() as tmp:
                startup_table(Path(tmp) / "run.nc", args.repeats)
        if args.logs:
            logs_table(args.logs)
        return
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "run.nc"
        run_cli(1000, out)  # warm the JIT cache
        codecs = [None]
        if args.compression:
            from bounce.io import CODECS

            codecs = list(CODECS)
        print(f"load average {os.getloadavg()[0]:.1f}; {args.small:.0e} vs {args.large:.0e} events, "
              f"median of {args.repeats}")
        solver = solver_ns_per_event(args.small, args.large, args.repeats)
        print(f"  solver alone (bounce.simulate in-process): {solver:6.0f} ns/event CPU")
        for codec in codecs:
            extra = () if codec is None else ("--compression", codec)
            (w_small, c_small) = median_time(args.small, out, args.repeats, extra)
            (w_large, c_large) = median_time(args.large, out, args.repeats, extra)
            ns_wall = (w_large - w_small) / (args.large - args.small) * 1e9
            ns_cpu = (c_large - c_small) / (args.large - args.small) * 1e9
            size = out.stat().st_size / 1e6
            name = codec or "default"
            print(f"{name:>8}: {ns_wall:6.0f} ns/event wall, {ns_cpu:6.0f} ns/event CPU end to end "
                  f"= {ns_cpu / solver:.1f} x the solver (wall {w_small:.2f} s / {w_large:.2f} s)  file {size:6.1f} MB  "
                  f"ncdump reads: {ncdump_reads(out)}")


if __name__ == "__main__":
    main()

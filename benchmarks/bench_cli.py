"""End-to-end cost per event of ``python -m bounce simulate`` (simulation + netCDF write + summary).

Runs the CLI as a subprocess at a small and a large event count and reports
(T_large - T_small) / (N_large - N_small): interpreter start-up, imports and JIT-cache
loading cancel.  Medians of ``--repeats`` runs, wall and CPU (user + sys) time; the machine
may be shared (then CPU time is the steadier number), so the load average is printed too.  Also measures the written file's size and, with
``--compression``, compares the codecs of bounce.io (size, write speed, and whether
netCDF-C's ``ncdump`` reads the file).

    python benchmarks/bench_cli.py                       # 1e5 vs 2e6 events, 3 repeats
    python benchmarks/bench_cli.py --compression         # also the codec table
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
    args = parser.parse_args()
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

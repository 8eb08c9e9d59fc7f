"""Trajectories per second per core of the contact Monte Carlo (sweep ``contact-monte-carlo``).

    python benchmarks/bench_monte_carlo.py [--samples N] [--events E] [--repeats R]

Runs the sweep's ``compute`` on the first ``--samples`` states of the pipeline's Monte Carlo
(config/config.yaml ``sweeps.contact-monte-carlo``, its seed; ``--events`` per trajectory, the CI
size by default) in this process, after one warm-up batch (numba compilation), and prints the
median trajectories/s over the repeats in process CPU time (the machine may be shared: CPU time is
what one core delivers), the share of that time spent building oscillators
(``oscillator.build_oscillator``, one per new mu and one per new mu/sqrt(2) of the sticky phase),
and the sha256 of the computed arrays: the same digest before and after a speed-up proves the
sweep's output unchanged.  Each repeat starts with empty oscillator caches (every sample has its
own mu, as in the sweep).
"""

from __future__ import annotations

import argparse
import cProfile
import hashlib
import pstats
import time
from pathlib import Path

import numpy as np
import yaml

from bounce.exact import oscillator
from bounce.pipeline.config import validated
from bounce.sweeps import registry

CONFIG = Path(__file__).resolve().parents[1] / "config" / "config.yaml"


def clear_caches() -> None:
    oscillator._cached_oscillator.cache_clear()
    if hasattr(oscillator, "_grid_powers"):
        oscillator._grid_powers.cache_clear()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=300)
    parser.add_argument("--events", type=int, default=100)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    config = validated(yaml.safe_load(CONFIG.read_text()))
    spec = dict(config["sweeps"]["contact-monte-carlo"], events=args.events)
    sweep = registry()["contact-monte-carlo"]
    inputs = sweep.prepare(spec, np.arange(args.samples))
    sweep.compute(spec, {k: v[:3] for k, v in inputs.items()})  # compile
    times, result = [], None
    for _ in range(args.repeats):
        clear_caches()
        t0 = time.process_time()
        result = sweep.compute(spec, inputs)
        times.append(time.process_time() - t0)
    clear_caches()
    profile = cProfile.Profile()
    profile.runcall(sweep.compute, spec, inputs)
    stats = pstats.Stats(profile).stats
    total = max(v[3] for v in stats.values())
    build = sum(v[3] for k, v in stats.items() if k[2] == "build_oscillator")
    digest = hashlib.sha256()
    for name in sorted(result):
        digest.update(name.encode() + np.ascontiguousarray(result[name]).tobytes())
    print(f"contact-monte-carlo: {args.samples} trajectories x {args.events} events, seed {spec['seed']}")
    print(f"  trajectories/s per core (median of {args.repeats}, CPU time): {args.samples / np.median(times):.0f}")
    print(f"  share of the time in build_oscillator (profiled run): {build / total:.0%}")
    print(f"  sha256 of the computed arrays: {digest.hexdigest()}")


if __name__ == "__main__":
    main()

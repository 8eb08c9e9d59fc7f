"""Trajectories per second per core of the contact Monte Carlo (sweep ``contact-monte-carlo``).

    python benchmarks/bench_monte_carlo.py [--samples N] [--events E] [--repeats R]

Runs the sweep's ``compute`` on the first ``--samples`` states of the pipeline's Monte Carlo
(config/config.yaml ``sweeps.contact-monte-carlo``, its seed; ``--events`` per trajectory, the CI
size by default) in this process, after one warm-up batch (numba compilation), and prints the
median trajectories/s over the repeats in process CPU time (the machine may be shared: CPU time is
what one core delivers), the share of that time spent building oscillator tables (measured apart:
the median CPU time of ``oscillator.oscillator_tables`` over the same samples' mu, one table each, as
the sweep's compiled loop builds them; a sample that sticks also builds mu/sqrt(2)'s, counted in the
line "samples with a sticky phase"), and the sha256 of the computed arrays: the same digest before
and after a speed-up proves the sweep's output unchanged.  Nothing is cached between samples or
repeats (every sample has its own mu, as in the sweep).
"""

from __future__ import annotations

import argparse
import hashlib
import time
from pathlib import Path

import numpy as np
import yaml
from numba import njit

from bounce.exact import oscillator
from bounce.kinds import KIND_NAMES
from bounce.pipeline.config import validated
from bounce.sweeps import registry

CONFIG = Path(__file__).resolve().parents[1] / "config" / "config.yaml"


def clear_caches() -> None:
    oscillator._cached_oscillator.cache_clear()  # make_oscillator's (the sweep does not use it)


@njit
def build_all(mu: np.ndarray) -> float:
    """oscillator_tables of every mu, as the sweep's loop builds them."""
    check = 0.0
    for m in mu:
        check += oscillator.oscillator_tables(m)[1][3, 10]
    return check


def median_cpu(run, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        clear_caches()
        t0 = time.process_time()
        run()
        times.append(time.process_time() - t0)
    return float(np.median(times))


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
    build_all(inputs["mu"][:3])
    result = sweep.compute(spec, inputs)
    total = median_cpu(lambda: sweep.compute(spec, inputs), args.repeats)
    build = median_cpu(lambda: build_all(inputs["mu"]), args.repeats)
    sticky = int(np.count_nonzero(result["counts"][:, KIND_NAMES.index("sticky_start")]))
    digest = hashlib.sha256()
    for name in sorted(result):
        digest.update(name.encode() + np.ascontiguousarray(result[name]).tobytes())
    print(f"contact-monte-carlo: {args.samples} trajectories x {args.events} events, seed {spec['seed']}")
    print(f"  trajectories/s per core (median of {args.repeats}, CPU time): {args.samples / total:.0f}")
    print(f"  share of the time in oscillator_tables (one per sample's mu, timed apart): {build / total:.0%}")
    print(f"  samples with a sticky phase (tables of mu/sqrt(2) built too): {sticky}")
    print(f"  sha256 of the computed arrays: {digest.hexdigest()}")


if __name__ == "__main__":
    main()

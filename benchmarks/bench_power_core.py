"""Impacts per second of the power-law solver deep in the asymptotic regime (one core).

    python benchmarks/bench_power_core.py [--impacts N] [--repeats R]

Runs bounce.power_events.run_power_events from a state near the static equilibrium
(xdot = 1e-7, at rest in the spring otherwise; gamma = 0.01, mu = 0.1) for Hertz
(a = b = 1/2) and the linear law through the same code, after one warm-up call
(compilation), and prints the median impacts/s over the repeats, timed in process CPU
time (the machine may be shared; CPU time is what one core delivers).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from bounce.power_events import run_power_events
from bounce.power_series import law_array


def rate(rho, a, b, gamma, mu, n, repeats):
    law = law_array(rho, a, b, mu, gamma)
    out = [np.empty(n) for _ in range(6)]
    kind = np.empty(n, dtype=np.int8)
    run_power_events(0.0, 1e-7, 0.0, 0.0, law, 10, np.inf, 0.0, *out, kind)  # compile
    times = []
    for _ in range(repeats):
        t0 = time.process_time()
        m, stop, _ = run_power_events(0.0, 1e-7, 0.0, 0.0, law, n, np.inf, 0.0, *out, kind)
        times.append(time.process_time() - t0)
        assert m == n and stop == 0 and np.all(kind == 0)
    return n / float(np.median(times)), out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--impacts", type=int, default=1_000_000)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    for name, law in (("hertz", (1.0, 0.5, 0.5)), ("linear", (1.0, 0.0, 0.0)), ("a=1,b=0", (2.0, 1.0, 0.0))):
        r, out = rate(*law, 0.01, 0.1, args.impacts, args.repeats)
        print(f"{name:8s} {r:12.3e} impacts/s  (median of {args.repeats} x {args.impacts} impacts; "
              f"last xdot = {out[2][-1]:.3e})")


if __name__ == "__main__":
    main()

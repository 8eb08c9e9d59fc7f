"""Impacts per second of the power-law solver deep in the asymptotic regime (one core).

    python benchmarks/bench_power_core.py [--impacts N] [--repeats R] [--sticky-only]

Runs bounce.power_events.run_power_events from a state near the static equilibrium
(xdot = 1e-7, at rest in the spring otherwise; gamma = 0.01, mu = 0.1) for Hertz
(a = b = 1/2) and the linear law through the same code, after one warm-up call
(compilation), and prints the median impacts/s over the repeats, timed in process CPU
time (the machine may be shared; CPU time is what one core delivers).

Before that (alone with --sticky-only), the cost of one Hertz sticky phase
(bounce.power_sticky.sticky_phase, to its detach or its never-detach proof) for four starts at
rest on the floor: the median CPU time per phase, and the series steps and step-size trials per
phase, counted by running the kernel's Python function (``py_func``) with counting wrappers
around taylor_coefficients and tail_bounds (the windows through xi = 0 are not series steps).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from bounce import power_sticky
from bounce.flight import FOUND, NEVER
from bounce.power_events import run_power_events
from bounce.power_series import DEGREE_LONG, L_XI_EQ, law_array
from call_counts import counting

#: Hertz sticky phases (gamma, mu, xi, xi'): a detach with xi < 0 throughout, a detach after
#: crossing the rest length xi = 0 (both of tests/test_power_sticky.py), the onset g0.1_mu1 of
#: tests/test_power_sticky_onset.py (F = 0, F' < 0: xi' = (gamma + |xi|^1.5) / (2 mu |xi|^0.5);
#: detaches after crossing xi = 0), and a phase proved infinite
STICKY_STARTS = {
    "detach": (0.01, 0.5, -0.0696, -0.2),
    "crossing": (0.05, 0.3, -0.1, 0.3),
    "onset": (0.1, 1.0, -0.05, 0.24860679774997899),
    "never": (0.01, 0.5, -0.10, 0.0),
}
STATUS = {FOUND: "detach", NEVER: "proved infinite"}


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


def sticky_costs(gamma, mu, xi, v, calls, repeats):
    """(median CPU seconds per phase, series steps, step-size trials, status, duration) of one sticky phase."""
    law = law_array(1.0, 0.5, 0.5, mu, gamma)
    eta = xi - float(law[L_XI_EQ])
    work = [np.empty(DEGREE_LONG + 2) for _ in range(3)]
    status, duration, _, _ = power_sticky.sticky_phase(v, eta, np.inf, law, *work, False)  # compile
    times = []
    for _ in range(repeats):
        t0 = time.process_time()
        for _ in range(calls):
            power_sticky.sticky_phase(v, eta, np.inf, law, *work, False)
        times.append((time.process_time() - t0) / calls)
    with counting(power_sticky, ("taylor_coefficients", "tail_bounds")) as counts:
        again = power_sticky.sticky_phase.py_func(v, eta, np.inf, law, *work, False)
    assert again[:2] == (status, duration), (again, status, duration)
    return float(np.median(times)), counts["taylor_coefficients"], counts["tail_bounds"], status, duration


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--impacts", type=int, default=1_000_000)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--sticky-only", action="store_true", help="only the sticky-phase costs")
    args = parser.parse_args()
    for name, start in STICKY_STARTS.items():
        sec, steps, trials, status, duration = sticky_costs(*start, calls=200, repeats=args.repeats)
        print(f"sticky {name:8s} {sec * 1e6:9.1f} us/phase  {steps:4d} series steps  {trials:4d} step-size trials  "
              f"({STATUS.get(status, status)} after {duration:.6f})")
    if args.sticky_only:
        return
    for name, law in (("hertz", (1.0, 0.5, 0.5)), ("linear", (1.0, 0.0, 0.0)), ("a=1,b=0", (2.0, 1.0, 0.0))):
        r, out = rate(*law, 0.01, 0.1, args.impacts, args.repeats)
        print(f"{name:8s} {r:12.3e} impacts/s  (median of {args.repeats} x {args.impacts} impacts; "
              f"last xdot = {out[2][-1]:.3e})")


if __name__ == "__main__":
    main()

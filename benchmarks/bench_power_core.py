"""Impacts per second of the power-law solver deep in the asymptotic regime (one core).

    python benchmarks/bench_power_core.py [--impacts N] [--repeats R] [--sticky-only | --disc]

Runs bounce.series.events.run_power_events from a state near the static equilibrium
(xdot = 1e-7, at rest in the spring otherwise; gamma = 0.01, mu = 0.1) for Hertz
(a = b = 1/2) and the linear law through the same code, after one warm-up call
(compilation), and prints the median impacts/s over the repeats, timed in process CPU
time (the machine may be shared; CPU time is what one core delivers).

Before that (alone with --sticky-only), the cost of one Hertz sticky phase
(bounce.series.sticky.sticky_phase, to its detach or its never-detach proof) for four starts at
rest on the floor: the median CPU time per phase, and the series steps and step-size trials per
phase, counted by running the kernel's Python function (``py_func``) with counting wrappers
around taylor_coefficients and tail_bounds (the windows through xi = 0 are not series steps).

With --disc instead: the Cauchy disc fraction of bounce.springs.power.disc_fraction (min(0.95, 2/a))
against the fixed 0.95 it replaced, as the median CPU time of 2e4 impacts of two drops (psi = 6 at rest,
the spring at xi = xi_eq or at its rest length xi = 0) for a = 2.5 .. 24, b = 1/2, gamma = mu = 0.01.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from bounce import Parameters, State
from bounce.exact.flight import FOUND, NEVER
from bounce.kinds import IMPACT, STOP_EVENTS
from bounce.series import sticky as series_sticky
from bounce.series.events import run_power_events
from bounce.series.taylor import DEGREE_LONG, L_DISC, L_XI_EQ, law_array
from bounce.springs import SPRING_LAWS
from bounce.springs.power import DISC
from call_counts import counting

#: Hertz sticky phases (gamma, mu, xi, xi'): a detach with xi < 0 throughout, a detach after
#: crossing the rest length xi = 0 (both of tests/series/test_series_sticky.py), the onset g0.1_mu1 of
#: tests/series/test_series_sticky_onset.py (F = 0, F' < 0: xi' = (gamma + |xi|^1.5) / (2 mu |xi|^0.5);
#: detaches after crossing xi = 0), and a phase proved infinite
STICKY_STARTS = {
    "detach": (0.01, 0.5, -0.0696, -0.2),
    "crossing": (0.05, 0.3, -0.1, 0.3),
    "onset": (0.1, 1.0, -0.05, 0.24860679774997899),
    "never": (0.01, 0.5, -0.10, 0.0),
}
STATUS = {FOUND: "detach", NEVER: "proved infinite"}


def timed_events(law, start, n, repeats):
    """(median CPU seconds, event arrays, kinds) of n events of run_power_events from the deviations
    ``start`` = (x, x', xi', eta), after a warm-up call (compilation); every run must record n events."""
    out = [np.empty(n) for _ in range(6)]
    kind = np.empty(n, dtype=np.int8)
    run_power_events(*start, law, 2, np.inf, 0.0, *out, kind)
    times = []
    for _ in range(repeats):
        t0 = time.process_time()
        m, stop, _ = run_power_events(*start, law, n, np.inf, 0.0, *out, kind)
        times.append(time.process_time() - t0)
        assert m == n and stop == STOP_EVENTS, (m, n, stop)  # stopped by the event count
    return float(np.median(times)), out, kind


def rate(rho, a, b, gamma, mu, n, repeats):
    seconds, out, kind = timed_events(law_array(rho, a, b, mu, gamma), (0.0, 1e-7, 0.0, 0.0), n, repeats)
    assert np.all(kind == IMPACT)  # impacts only
    return n / seconds, out


def sticky_costs(gamma, mu, xi, v, calls, repeats):
    """(median CPU seconds per phase, series steps, step-size trials, status, duration) of one sticky phase."""
    law = law_array(1.0, 0.5, 0.5, mu, gamma)
    eta = xi - float(law[L_XI_EQ])
    work = [np.empty(DEGREE_LONG + 2) for _ in range(3)]
    status, duration, _, _ = series_sticky.sticky_phase(v, eta, np.inf, law, *work, False)  # compile
    times = []
    for _ in range(repeats):
        t0 = time.process_time()
        for _ in range(calls):
            series_sticky.sticky_phase(v, eta, np.inf, law, *work, False)
        times.append((time.process_time() - t0) / calls)
    with counting(series_sticky, ("taylor_coefficients", "tail_bounds")) as counts:
        again = series_sticky.sticky_phase.py_func(v, eta, np.inf, law, *work, False)
    assert again[:2] == (status, duration), (again, status, duration)
    return float(np.median(times)), counts["taylor_coefficients"], counts["tail_bounds"], status, duration


def disc_scan(n, repeats):
    """The --disc table: CPU ms of n events with the fixed DISC and with disc_fraction, and their ratio."""
    gamma = mu = 0.01
    print(f"drops of {n} events, b = 0.5, gamma = mu = {gamma}: CPU ms, median of {repeats}")
    print("     a  start        d   fixed 0.95   disc_fraction   ratio")
    for a in (2.5, 3.0, 5.0, 8.0, 12.0, 24.0):
        params = Parameters(gamma, mu, SPRING_LAWS["power"](rho=1.0, a=a, b=0.5))
        new = law_array(1.0, a, 0.5, mu, gamma)
        old = law_array(1.0, a, 0.5, mu, gamma, disc=DISC)
        for name, xi in (("xi_eq", params.xi_eq), ("xi = 0", 0.0)):
            dev = State.from_psi_xi(6.0, 0.0, xi, 0.0).deviations(params)
            start = (dev.x, dev.xdot, dev.xidot, dev.eta)
            t_old, t_new = (timed_events(law, start, n, repeats)[0] for law in (old, new))
            print(f"{a:6.1f}  {name:7s} {new[L_DISC]:6.3f} {t_old * 1e3:12.1f} {t_new * 1e3:15.1f} {t_old / t_new:7.2f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--impacts", type=int, default=1_000_000)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--sticky-only", action="store_true", help="only the sticky-phase costs")
    parser.add_argument("--disc", action="store_true", help="only the Cauchy disc fraction against the fixed 0.95")
    args = parser.parse_args()
    if args.disc:
        disc_scan(20_000, args.repeats)
        return
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

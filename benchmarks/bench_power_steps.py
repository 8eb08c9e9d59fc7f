"""Where the time of the Hertz drop goes: steps per flight of bounce and heyoka, by window of impact index.

    python benchmarks/bench_power_steps.py [--impacts N] [--per-window M]

The drop of benchmarks/bench_power.py (Hertz, gamma = mu = 0.01, psi(0) = 6, xi(0) = xi_eq): bounce's
trajectory over N impacts (default 2e4), and from up to M post-impact states per window of
bench_power's WINDOWS (evenly spread), one flight each:

* bounce: whether the hot path (:func:`bounce.series.flight.short_flight`) takes it (``split``: of those,
  in two or three steps, :func:`bounce.series.flight._split_flight`), else the series
  steps (calls of taylor_coefficients), root-variable crossing attempts (_root_crossing calls) and
  evaluations of eq. (P) per flight, counted by running first_contact's Python function (``py_func``)
  with counting wrappers; the CPU time per impact of bounce on the window (median of 3 runs);
* heyoka: its integrator steps per flight from the same states (``extra["steps"]`` of
  :func:`bounce.methods.heyoka_taylor.run`) and its CPU time per impact in its fastest use
  (:func:`bounce.methods.heyoka_taylor.impacts`, as benchmarks/bench_power.py times it).

Series steps x cost per step against heyoka's steps x cost per step says what limits the ratio
in the transient (long flights swinging through the rest length xi = 0).
"""

from __future__ import annotations

import argparse
import collections
import statistics
import time

import numpy as np

from bounce import Deviations, Parameters, State, simulate
from bounce.series import flight as PF
from bounce.methods import heyoka_taylor as HT
from bounce.series.taylor import DEGREE_LONG, law_array
from bounce.springs import SPRING_LAWS
from call_counts import counting

GAMMA = MU = 0.01
WINDOWS = (0, 10, 100, 1_000, 10_000, 20_000, 100_000)
COUNTED = ("taylor_coefficients", "_root_crossing", "_evaluate")


def counted_flight(start, law, work) -> tuple[bool, bool, collections.Counter]:
    """(hot path?, in 2 or 3 steps?, counts of COUNTED) for one flight from ``start`` = (x, u, xi', eta)."""
    x, u, v, eta = start
    if x == 0.0 and u > 0.0:
        with counting(PF, ("_split_flight",)) as split:
            if PF.short_flight.py_func(u, v, eta, law, *work)[0] != PF.HANDOVER:
                return True, split["_split_flight"] > 0, collections.Counter()
    with counting(PF, COUNTED, {"_minimum": PF._minimum.py_func}) as counts:  # _minimum: compiled against _evaluate
        PF.first_contact.py_func(x, u, v, eta, np.inf, law, *work, False)
    return False, False, counts


def cpu_per_impact(fn, n, repeats=3) -> float:
    times = []
    for _ in range(repeats):
        t0 = time.process_time()
        fn()
        times.append(time.process_time() - t0)
    return statistics.median(times) / n


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--impacts", type=int, default=20_000)
    parser.add_argument("--per-window", type=int, default=60)
    args = parser.parse_args()
    params = Parameters(GAMMA, MU, SPRING_LAWS["power"](rho=1.0, a=0.5, b=0.5))
    law = law_array(1.0, 0.5, 0.5, MU, GAMMA)
    drop = State.from_psi_xi(6.0, 0.0, params.xi_eq, 0.0)
    tr = simulate(params, drop, max_events=args.impacts)
    HT.run(params, drop, {}, max_events=10)  # compile heyoka's integrator once
    work = [np.empty(DEGREE_LONG + 2) for _ in range(3)]
    d0 = drop.deviations(params)
    edges = [w for w in WINDOWS if w < args.impacts] + [args.impacts]
    print(f"Hertz drop, gamma = mu = {GAMMA}; {args.per_window} flights per window "
          "(bounce: per flight not in the hot path; heyoka: per flight)")
    print(f"{'impacts':>15s} {'hot':>5s} {'split':>5s} {'series':>7s} {'root try':>8s} {'evals':>6s} {'us/impact':>9s} | "
          f"{'heyoka steps':>12s} {'us/impact':>9s} {'ratio':>6s}")
    for lo, hi in zip(edges[:-1], edges[1:]):
        idx = np.unique(np.linspace(lo, hi - 1, min(args.per_window, hi - lo)).astype(int))
        hot, split, total, long_flights, h_steps = 0, 0, collections.Counter(), 0, []
        for k in idx:
            start = ((d0.x, d0.xdot, d0.xidot, d0.eta) if k == 0 else
                     (0.0, float(tr.xdot[k - 1]), float(tr.xidot[k - 1]), float(tr.eta[k - 1])))
            is_hot, is_split, counts = counted_flight(start, law, work)
            hot += is_hot
            split += is_split
            long_flights += not is_hot
            total.update(counts)
            r = HT.run(params, Deviations(*start), {}, max_events=1)
            h_steps.append(int(r.extra["steps"]) if len(r.t) else np.nan)
        first = drop if lo == 0 else Deviations(0.0, float(tr.xdot[lo - 1]), float(tr.xidot[lo - 1]),
                                                 float(tr.eta[lo - 1]))
        b_us = 1e6 * cpu_per_impact(lambda: simulate(params, first, max_events=hi - lo), hi - lo)
        t_end = 1.5 * (tr.t[hi - 1] - (tr.t[lo - 1] if lo else 0.0)) + 1.0  # past the window's last impact
        h_us = 1e6 * statistics.median(HT.impacts(params, first, hi - lo, t_end)[4] for _ in range(3)) / (hi - lo)
        per = {name: total[name] / max(long_flights, 1) for name in COUNTED}
        print(f"[{lo:6d}, {hi:6d}) {hot:2d}/{len(idx):2d} {split:5d} {per['taylor_coefficients']:7.1f} "
              f"{per['_root_crossing']:8.1f} {per['_evaluate']:6.1f} {b_us:9.2f} | {np.nanmean(h_steps):12.1f} "
              f"{h_us:9.2f} {h_us / b_us:6.1f}")


if __name__ == "__main__":
    main()

"""Error of a long power-law flight against the mpmath reference, and how it grows (issue 9).

    python benchmarks/bench_power_long_flight.py [--x0 X0] [--points N] [--dps D]
    python benchmarks/bench_power_long_flight.py --realisations N

``--realisations N``: the flight of tests/series/test_series_reference.py's long-flight test (x0 = 5, mu = 1e-6,
~45 crossings) for N values gamma = 1e-5 (1 + 0.0137 k), k < N: independent draws of the rounding
random walk (the spring's motion does not depend on x0, only on gamma through xi_eq), each impact's
eta against the reference, relative to W = |xi_eq|; printed with their rms and largest value, against
the docstring's rms estimate 1.5e-17 n^1.5 (n crossings).  The test checks one draw to 1e-14.  Cost:
~3 s per realisation (the reference).

The Hertz flight (rho = 1, a = b = 1/2) of test_power_core's long-flight test: gamma = 1e-5,
mu = 0, dropped from x = X0 (default 2e4: ~6e4 long) at rest with xi = xi_eq, so the spring swings
through its rest length xi = 0 thousands of times with amplitude W = |xi_eq| and speed V there.
bounce's state at N checkpoints t (:func:`bounce.series.flight.first_contact` with t_limit = t)
against the independent reference ``tests/power_reference.py`` (at D digits, default 30) from the
same start, then the impact.  Printed per checkpoint: the crossings n of xi = 0 so far, the errors
of x (relative to X0), x' (to gamma t), eta (to W), xi' (to V), the spring energy's error (exact
arithmetic on bounce's state; relative to its value) and the bound of series.flight's docstring for
eta, 0.07 eps n^1.5 (eps = 2^-52; the energy's random walk of roundings turned into phase by the
energy-dependent frequency).  The reference needs mu > 0: it runs at mu = 1e-300 (a change of
the flight ~1e-300).  Cost: ~2 min for the default flight (the reference).
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np
from mpmath import mp, mpf

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))
import power_reference as PR  # noqa: E402

from bounce.exact.flight import EPS, FOUND, HORIZON  # noqa: E402
from bounce.series.flight import first_contact  # noqa: E402
from bounce.series.taylor import DEGREE_LONG, L_XI_EQ, law_array  # noqa: E402

GAMMA = 1e-5


def realisations(count: int, dps: int) -> None:
    """eta's error at the impact of the long-flight test's flight over ``count`` values of gamma."""
    mu, x0 = 1e-6, 5.0
    X, P, Q = (np.empty(DEGREE_LONG + 2) for _ in range(3))
    errors = []
    print("#    gamma       n   err eta/W   1.5e-17 n^1.5")
    for k in range(count):
        gamma = 1e-5 * (1.0 + 0.0137 * k)
        law = law_array(1.0, 0.5, 0.5, mu, gamma)
        xi_eq = float(law[L_XI_EQ])
        status, _, _, _, eta, _, _, _ = first_contact(x0, 0.0, 0.0, 0.0, math.inf, law, X, P, Q)
        assert status == FOUND
        with mp.workdps(dps):
            flight = PR.make_flight(gamma, mu, 1.0, 0.5, 0.5, x0, 0.0, 0.0, mpf(xi_eq))
            tau = flight.first_impact()[0]
            _, _, xi, _ = flight.state(tau)
            n = sum(isinstance(s, PR.Crossing) and s.tc <= tau for s in flight.segments)
            err = float((mpf(eta) - (xi - mpf(xi_eq))) / abs(mpf(xi_eq)))
        errors.append(err)
        print(f"{gamma:.4e} {n:5d} {err:11.2e} {1.5e-17 * n**1.5:11.2e}", flush=True)
    e = np.array(errors)
    print(f"# {count} realisations: rms {math.sqrt(np.mean(e * e)):.2e}, largest {np.abs(e).max():.2e}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--x0", type=float, default=2e4)
    parser.add_argument("--points", type=int, default=30)
    parser.add_argument("--dps", type=int, default=30)
    parser.add_argument("--realisations", type=int, default=0)
    args = parser.parse_args()
    if args.realisations:
        realisations(args.realisations, args.dps)
        return
    x0 = args.x0
    law = law_array(1.0, 0.5, 0.5, 0.0, GAMMA)
    xi_eq = float(law[L_XI_EQ])
    X, P, Q = (np.empty(DEGREE_LONG + 2) for _ in range(3))
    status, tau, *_ = first_contact(x0, 0.0, 0.0, 0.0, math.inf, law, X, P, Q)
    assert status == FOUND
    mp.dps = args.dps
    W = abs(mpf(xi_eq))
    E0 = W ** mpf(2.5) / mpf(2.5)
    V = float(mp.sqrt(2 * E0))

    def energy(eta, v):
        return mpf(v) ** 2 / 2 + abs(mpf(xi_eq) + mpf(eta)) ** mpf(2.5) / mpf(2.5)

    started = time.process_time()
    flight = PR.make_flight(GAMMA, 1e-300, 1.0, 0.5, 0.5, x0, 0.0, 0.0, mpf(xi_eq))
    print(f"# Hertz, gamma = {GAMMA}, mu = 0, x0 = {x0}: flight {tau:.1f} long, W = {float(W):.3e}, V = {V:.3e}")
    print("#        t      n    err x/x0  err x'/gt   err eta/W  err xi'/V   err E_s   0.07 eps n^1.5")
    for k in range(1, args.points + 1):
        t = tau * k / (args.points + 1)
        st, _, u, x, eta, v, _, _ = first_contact(x0, 0.0, 0.0, 0.0, t, law, X, P, Q)
        assert st == HORIZON
        xr, psid, xi, xid = flight.state(mpf(t))
        n = sum(isinstance(s, PR.Crossing) and s.tc <= t for s in flight.segments)
        errs = (float((mpf(x) - xr) / x0), float((mpf(u) - (psid - xid)) / (GAMMA * t)),
                float((mpf(eta) - (xi - mpf(xi_eq))) / W), float((mpf(v) - xid) / V), float(energy(eta, v) / E0 - 1))
        print(f"{t:10.1f} {n:6d} " + " ".join(f"{e:10.2e}" for e in errs) + f"   {0.07 * EPS * n**1.5:10.2e}")
    tau_ref = flight.first_impact()[0]
    _, psid, xi, xid = flight.state(tau_ref)
    n = sum(isinstance(s, PR.Crossing) and s.tc <= tau_ref for s in flight.segments)
    _, tau, xd, _, eta, v, _, _ = first_contact(x0, 0.0, 0.0, 0.0, math.inf, law, X, P, Q)
    print(f"# impact after n = {n} crossings: err tau/tau {float((tau - tau_ref) / tau_ref):.2e}, "
          f"x'/x' {float((xd - (psid - xid)) / (psid - xid)):.2e}, eta/W {float((mpf(eta) - (xi - mpf(xi_eq))) / W):.2e}, "
          f"xi'/V {float((mpf(v) - xid) / V):.2e}, E_s {float(energy(eta, v) / E0 - 1):.2e} "
          f"(rms estimate for eta {0.07 * EPS * n**1.5:.1e}); reference {time.process_time() - started:.0f} s CPU")


if __name__ == "__main__":
    main()

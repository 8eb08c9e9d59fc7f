"""The asymptotic law of Theorem main_thm: tau_n ~ 3/(mu n), Xdot_n ~ 3 gamma/(mu n).

Indexing (paper, eqs. time-of-flight and collision-rule-map): t_0 = 0 is the
start, t_n (n >= 1) the n-th impact, tau_n = t_{n+1} - t_n, and Xdot_n the
lower-mass speed just after impact n.  bounce's events are 0-based and event
k is the impact at t_{k+1}; traj.tau[k] is the phase ending at event k, so

    tau_n = traj.tau[n]          (the flight after impact n; tau_0 = the drop)
    Xdot_n = traj.xdot[n - 1]    (the speed after impact n = event n - 1).

n = 10^6 needs traj.tau[10^6], i.e. 10^6 + 1 events (~0.6 s each run).

Why the tolerances are what an exact solver gives.  Rounding does not build
up here: deep in the asymptotic regime the map Xdot_{n+1} = Xdot_n -
(mu/3gamma) Xdot_n^2 + ... (eq. restituzione) contracts relative errors of
Xdot like 1/n, and test_reference.py checks each flight against mpmath to
1e-14.  The distance from 1 is therefore the physics of the exact dynamics
at finite n:

* gamma = mu = 0.01 (under-damped): the next order of the map gives a
  relative correction ~ ln(n)/n ~ 1.4e-5 at n = 10^6 (measured: 1.1e-5 for
  both quantities), and the spring's relaxation, e^{-(mu/2) t_n} with
  t_n ~ (3/mu) ln n, decays like n^{-3/2}; the task's 0.05 % has a wide margin.
* gamma = 1e-5, mu = 2 (over-damped): the spring relaxes only at the slow
  rate lam = (mu - sqrt(mu^2 - 2))/2 = 0.2929 of the sticky oscillator
  w'' + mu w' + w/2 = 0 (eq. y-eq-sticky), and t_n ~ (3/mu) ln n, so the
  corrections decay like n^{-3 lam/mu} = n^{-0.439}, which is slow: at
  n = 10^6 they are -7.2e-4 for n tau_n and -2.1e-3 for n Xdot_n (see
  test_overdamped_relaxation_exponent).  The task's 0.2 % holds for tau; for
  Xdot the limit is checked by extrapolation with the known exponent.
"""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest

from bounce import Parameters, State, simulate

N = 1_000_000


@functools.lru_cache(maxsize=None)
def run(gamma, mu, psi0):
    p = Parameters(gamma, mu)
    tr = simulate(p, State.from_psi_xi(psi0, 0.0, 0.0, 0.0), max_events=N + 1)
    assert tr.stop_reason == "max_events" and (tr.kind == 0).all()
    return tr


def scaled(gamma, mu, psi0, n):
    """(n tau_n mu/3, n Xdot_n mu/(3 gamma)) in the paper's indexing."""
    tr = run(gamma, mu, psi0)
    return n * tr.tau[n] * mu / 3.0, n * tr.xdot[n - 1] * mu / (3.0 * gamma)


CASES = [
    # gamma, mu, psi(0), tolerance (task)
    pytest.param(1e-5, 2.0, 0.25, 2e-3, id="gamma=1e-5,mu=2,psi0=0.25"),
    pytest.param(0.01, 0.01, 6.0, 5e-4, id="gamma=mu=0.01,psi0=6"),
]


@pytest.mark.parametrize("gamma, mu, psi0, tol", CASES)
def test_flight_time_law(gamma, mu, psi0, tol):
    """n tau_n mu/3 -> 1 (Theorem main_thm), at n = 10^6."""
    r_tau, _ = scaled(gamma, mu, psi0, N)
    assert abs(r_tau - 1) <= tol, f"n tau_n mu/3 = {r_tau!r} at n = {N}"


def test_rebound_speed_law_underdamped():
    """n Xdot_n mu/(3 gamma) -> 1 (proof of Theorem main_thm), at n = 10^6, gamma = mu = 0.01:
    the next-order correction ~ ln(n)/n ~ 1.4e-5, so the task's 0.05 % applies as for tau."""
    _, r_x = scaled(0.01, 0.01, 6.0, N)
    assert abs(r_x - 1) <= 5e-4, f"n Xdot_n mu/(3 gamma) = {r_x!r} at n = {N}"


def test_overdamped_limits_by_extrapolation():
    """gamma = 1e-5, mu = 2: both laws' limits, Richardson-extrapolated from n = 10^5 and 10^6
    with the known exponent p = 3 lam/mu (test_overdamped_relaxation_exponent).

    At n = 10^6 n Xdot_n mu/(3 gamma) is still 2.1e-3 from 1 in the exact dynamics (the
    correction decays only like n^-0.439), so its limit is checked, not its value at 10^6.
    Removing the n^-p term leaves the next orders, O(d^2) and O(n^-2p) with d = 6e-3 the
    distance at 10^5: 1e-4 bounds them (measured: 8e-6 for tau, 1.6e-5 for Xdot; from 10^4
    and 10^5 the same extrapolation is 10 times further off, as O(n^-2p) predicts).
    """
    gamma, mu, psi0 = 1e-5, 2.0, 0.25
    p = 3.0 * (mu - math.sqrt(mu * mu - 2.0)) / 2.0 / mu
    r5 = np.array(scaled(gamma, mu, psi0, N // 10))
    r6 = np.array(scaled(gamma, mu, psi0, N))
    limit = (r6 * 10.0**p - r5) / (10.0**p - 1.0)
    assert np.all(np.abs(limit - 1.0) <= 1e-4), f"extrapolated limits (tau, Xdot) = {limit}"


def test_overdamped_relaxation_exponent():
    """For mu = 2 the distance from the law decays like n^{-3 lam/mu},
    lam = (mu - sqrt(mu^2 - 2))/2: the slow rate of the sticky oscillator over
    t_n ~ (3/mu) ln n.  Measured between n = 10^5 and 10^6; the next-order
    terms are relatively O(distance) ~ 0.6 % at 10^5, so the exponent must
    match to 2 %.  This is what keeps n Xdot_n mu/(3 gamma) 2.1e-3 from 1 at
    n = 10^6 in an exact solution."""
    gamma, mu, psi0 = 1e-5, 2.0, 0.25
    lam = (mu - math.sqrt(mu * mu - 2.0)) / 2.0
    expected = 3.0 * lam / mu
    d5 = np.array(scaled(gamma, mu, psi0, N // 10)) - 1.0
    d6 = np.array(scaled(gamma, mu, psi0, N)) - 1.0
    assert (d5 < 0).all() and (d6 < 0).all(), (d5, d6)
    exponents = np.log10(d5 / d6)
    assert np.all(np.abs(exponents / expected - 1) <= 0.02), (
        f"decay exponents (tau, Xdot) {exponents} vs 3 lam/mu = {expected:.4f}"
    )

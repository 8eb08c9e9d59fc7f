"""Claim group sticky-events: its rows can fail, and its bound's D is what the simulator dissipates."""

from __future__ import annotations

import math
from pathlib import Path

from mpmath import mpf

from bounce import Parameters, State, simulate
from bounce.analysis import theory
from bounce.checks import sticky_events as se
from bounce.checks.base import NOT_REPRODUCED, REPRODUCED
from bounce.claims_cli import group_spec
from bounce.kinds import DETACH, STICKY_START

ROOT = Path(__file__).resolve().parents[2]


def _spec(**changes):
    return group_spec("sticky-events", {"mu": [0.1], "n_alpha": 12, **changes}, ROOT)


def test_wrong_flight_time_breaks_the_cycle(monkeypatch):
    """With u off the root of tan u = u the exact flight does not land on a sticky onset: the row flips."""
    assert se.measure(_spec()).rows["conservative-sticky-cycle"].verdict == REPRODUCED
    monkeypatch.setattr(se, "symmetric_flight_root", lambda: mpf("4.5"))
    assert se.measure(_spec()).rows["conservative-sticky-cycle"].verdict == NOT_REPRODUCED


def test_least_dissipation_matches_the_simulator():
    """D (closed form, energy identity) equals the energy the simulator loses in the sticky phase from the minimising onset;
    a D too large by 1 % would exceed it (the per-event check of sticky-count-bound would fail)."""
    g, mu = 0.01, 0.1
    D, alpha, _, _ = theory.least_sticky_dissipation(g, mu, 24.0 * g * g, 12)
    p = Parameters(g, mu)
    tr = simulate(p, State.sticky_ic(p, eps=0.0, ydot0=4 * g * mu - alpha), max_events=3)
    s, d = list(tr.kind).index(STICKY_START), list(tr.kind).index(DETACH)
    drop = tr.energy_excess[s] - tr.energy_excess[d]
    assert abs(drop - D) <= 1e-12 * D  # both exact to ~1e-14 (measured 1.8e-15 here)
    assert drop < 1.01 * D


def test_bound_grows_like_one_over_mu():
    g = 0.01
    d = [theory.least_sticky_dissipation(g, mu, 24.0 * g * g, 12)[0] / mu for mu in (1e-3, 1e-2)]
    assert 0.5 < d[0] / d[1] < 2.0  # D ~ mu: the count bound ~ 1/mu, infinite at mu = 0 (the conservative cycle)
    assert theory.min_sticky_energy(g, 0.0) > theory.E_min(g)


def test_sticky_dissipation_against_an_independent_integration():
    """theory.sticky_dissipation's energy identity against (mu/2) int ydot^2 by mpmath quadrature at 30 digits of
    (w, w')(t) = expm(A t) (w0, w0') with A = [[0, 1], [-1/2, -mu]] (eq. y-eq-sticky; no closed form shared), for mu
    from 1e-3 (the most cancelling) to 1; the docstring's bound 1e-16/(mu t_d) with a factor 10 of slack."""
    from mpmath import expm, matrix, mp, quad

    g = 0.01
    for mu in (1e-3, 1e-2, 0.1, 1.0):
        ydot_s = 4 * g * mu - 2 * theory.eps_star(g, mu)[0]  # alpha_s = 2 eps*: a finite phase (t_d ~ 6-8)
        assert math.isfinite(t_d := theory.sticky_dissipation(g, mu, ydot_s)[0])
        t_d, diss = theory.sticky_dissipation(g, mu, ydot_s)
        with mp.workdps(30):
            A, v = matrix([[0, 1], [mpf(-1) / 2, -mpf(mu)]]), matrix([4 * g - 2 * mu * ydot_s, ydot_s])
            exact = float(mpf(mu) / 2 * quad(lambda t: (expm(A * t) * v)[1] ** 2, [0, mpf(t_d) / 2, t_d]))
        assert abs(diss - exact) <= 10 * 1e-16 / (mu * t_d) * exact, (mu, diss, exact)


def test_count_bound_is_tested_at_its_least_value():
    """Each mu > 0 run starts at the onset of least dissipation: its sticky event dissipates D itself and its bound is 2
    to 1e-3, the least a run's own onset allows (the detach is on the sticky line, E(t_d) >= E_min): one sticky event
    more than the generic one and a third would refute it."""
    m = se.measure(_spec(mu=[1e-3, 0.1]))
    assert all(v.verdict == REPRODUCED for v in m.rows["sticky-count-bound"].values())
    bounds = m.data["count_bound"].values
    assert (m.data["sticky_count"].values == 1).all() and ((bounds >= 2.0) & (bounds < 2.001)).all(), bounds

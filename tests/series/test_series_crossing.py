"""Crossings of the rest length xi = 0 in the root variable (series.flight._root_crossing, eq. (R) of
series.taylor) against the independent mpmath reference (tests/power_reference.py).

One crossing from (xi0, xi') moving towards 0 (or from xi = 0): the solver's duration T, change of
xi and of xi' must be the reference's state at time T to rounding (a few ulps of the magnitudes
they are formed from), for Hertz and laws with b != 1/2 (q = 1, 2, 4; b = 0, 1, 3/2), fast and
moderately slow crossings; a slow crossing (kinetic energy ~ potential) is refused (T = 0) and
left to the windows, which the flight-level test below then exercises.
"""

from __future__ import annotations

import numpy as np
import pytest
from mpmath import mp, mpf

import power_reference as PR
from bounce import Deviations, Parameters
from bounce.series.events import simulate_power
from bounce.series.flight import _root_crossing
from bounce.series.taylor import L_ROOT_Q, L_XI_EQ, law_array, root_denominator
from bounce.springs.power import PowerSpring

ULPS = 8 * np.finfo(float).eps
GAMMA, MU = 0.01, 0.05
LAWS = [PowerSpring(1.0, 0.5, 0.5), PowerSpring(0.5, 0.25, 1.0), PowerSpring(2.0, 1.0, 0.0),
        PowerSpring(1.0, 0.5, 1.5)]
# (xi0, xi'): towards 0 from either side, fast and moderately slow, and from xi = 0
CASES = {"fast_from_below": (-1e-3, 0.3), "fast_from_above": (5e-4, -0.2), "moderate": (-5e-5, 0.02),
         "from_rest_length": (0.0, -0.05)}


def test_root_denominator():
    assert [root_denominator(*ab) for ab in [(0.5, 0.5), (0.25, 1.0), (1.0, 0.0), (0.5, 1.5), (0.0, 0.0)]] == [2, 4, 1, 2, 1]
    assert root_denominator(1 / 3, 0.5) == 0 and root_denominator(0.5, 0.3) == 0  # not dyadic: windows only


@pytest.mark.parametrize("spring", LAWS, ids=lambda s: f"rho{s.rho}_a{s.a}_b{s.b}")
@pytest.mark.parametrize("case", list(CASES), ids=str)
def test_root_crossing_matches_reference(spring, case):
    xi0, v = CASES[case]
    law = law_array(spring.rho, spring.a, spring.b, MU, GAMMA)
    assert law[L_ROOT_Q] > 0
    T, d, dv = _root_crossing(xi0, v, abs(xi0) ** (spring.a + 1.0), law, np.inf)
    assert T > 0.0, "a fast crossing must be taken"
    xi1 = xi0 + d
    assert xi1 * v > 0.0 and abs(xi1) > 0.5 * abs(xi0)  # through 0, well beyond it (the point of the step)
    with mp.workdps(40):
        fl = PR.make_flight(GAMMA, MU, spring.rho, spring.a, spring.b, 10.0, 0.0, v, xi0)
        _, _, xi_ref, xid_ref = fl.state(mpf(T))
        scale_xi = abs(xi0) + abs(xi1) + abs(v) * T
        assert abs(float(xi_ref - mpf(xi0)) - d) <= ULPS * scale_xi, (float(xi_ref), xi1)
        assert abs(float(xid_ref - mpf(v)) - dv) <= ULPS * abs(v), (float(xid_ref), v + dv)


@pytest.mark.parametrize("spring", LAWS[:2], ids=lambda s: f"rho{s.rho}_a{s.a}_b{s.b}")
def test_slow_crossing_is_left_to_the_windows(spring):
    """Kinetic energy below the potential's share: no root-variable step (its tail bound fails)."""
    law = law_array(spring.rho, spring.a, spring.b, MU, GAMMA)
    xi0 = -1e-2
    v = 0.3 * (abs(xi0) ** (spring.a + 2.0)) ** 0.5
    assert _root_crossing(xi0, v, abs(xi0) ** (spring.a + 1.0), law, np.inf)[0] == 0.0


@pytest.mark.parametrize("spring", [PowerSpring(1.0, 0.5, 0.5), PowerSpring(0.5, 0.25, 1.0), PowerSpring(1.0, 0.5, 0.3)],
                         ids=lambda s: f"rho{s.rho}_a{s.a}_b{s.b}")  # b = 0.3: not dyadic, the windows alone
@pytest.mark.parametrize("amplitude", [1e-4, 5e-2], ids=["slow", "fast"])
def test_flight_through_crossings_matches_reference(spring, amplitude):
    """A flight of ~60 time units from the floor with the spring released at rest at xi = amplitude:
    it crosses xi = 0 2-4 times at |xi'| ~ 1e-5 (slow) or 8-9 times at |xi'| ~ 2e-2 (fast; counts
    from an independent ODE solve), each crossing by the root variable where its tail bounds allow,
    else the windows; flight time and post-impact state to 1e-14."""
    gamma, mu, u = 0.01, 0.05, 0.3
    xi_eq = float(law_array(spring.rho, spring.a, spring.b, mu, gamma)[L_XI_EQ])
    eta = amplitude - xi_eq
    tr = simulate_power(Parameters(gamma, mu, spring), spring, Deviations(x=0.0, xdot=u, xidot=0.0, eta=eta),
                        max_events=1)
    with mp.workdps(60):
        xi0 = mpf(xi_eq) + mpf(eta)
    ref = PR.reference_first_impact(gamma, mu, spring.rho, spring.a, spring.b, 0.0, u, 0.0, xi0)
    assert list(tr.kind) == [0]
    tau, rel = float(ref["tau"]), 1e-14
    assert tau > 55.0
    assert abs(tr.tau[0] - tau) <= rel * tau
    assert abs(tr.xdot[0] - float(ref["xdot"])) <= rel * abs(float(ref["xdot"]))
    assert abs(tr.xidot[0] - float(ref["xidot"])) <= rel * (u + gamma * tau), (tr.xidot[0], ref["xidot"])
    with mp.workdps(60):
        eta_ref = float(ref["xi"] - mpf(xi_eq))
    assert abs(tr.eta[0] - eta_ref) <= rel * (abs(eta_ref) + abs(eta_ref - eta)), (tr.eta[0], eta_ref)


def test_root_crossing_underflow_and_deadline():
    """|xi'| ~ 1e-50 at xi = 0 (the majorant radius underflows: refused, found by hypothesis in
    test_power_core); a deadline t_max before xi = 0 refuses, one after it shortens the outgoing part."""
    law = law_array(2.0, 1.0, 0.0, 0.5, 0.0078125)
    assert _root_crossing(0.0, 5.929327452028284e-50, 0.0, law, np.inf)[0] >= 0.0
    hertz = law_array(1.0, 0.5, 0.5, MU, GAMMA)
    T, d, _ = _root_crossing(-1e-3, 0.3, 1e-3**1.5, hertz, np.inf)
    assert T > 1e-3 / 0.3
    assert _root_crossing(-1e-3, 0.3, 1e-3**1.5, hertz, 0.5e-3 / 0.3)[0] == 0.0
    T2, d2, _ = _root_crossing(-1e-3, 0.3, 1e-3**1.5, hertz, 0.5 * (T + 1e-3 / 0.3))
    assert 1e-3 / 0.3 < T2 < 0.5 * (T + 1e-3 / 0.3) and 0.0 < -1e-3 + d2 < -1e-3 + d

"""The hot path of the power-law spring (series.flight.short_flight): a flight from the floor as one
series step, with its root certified or a HANDOVER to the general stepper.

* flights of the Hertz drop of benchmarks/bench_power.py that take the hot path (impacts 2.6e3 ..
  2e4: window from the cubic model, comparison radius from one closed-form evaluation of eq. (C),
  degree up to DEGREE_SHORT; impacts 1e3 .. 2e3: two or three steps) against the mpmath reference
  (tests/power_reference.py) to 1e-14;
* property: from states near equilibrium (three laws, a window of speeds that spans the switch
  between the hot path and the general one), short_flight either hands over or returns the root and
  post-impact state of first_contact (the safe march, which cannot skip a root) to rounding;
* a window far too short costs a HANDOVER, never a wrong root.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import power_reference as PR
from bounce import Parameters, State
from bounce.series import flight as PF
from bounce.exact.flight import FOUND
from bounce.series.taylor import DEGREE_LONG, L_XI_EQ, law_array
from bounce.series.events import simulate_power
from bounce.springs.power import PowerSpring

GAMMA = MU = 0.01
HERTZ = PowerSpring(1.0, 0.5, 0.5)
REL = 1e-14


@pytest.fixture(scope="module")
def drop():
    params = Parameters(GAMMA, MU, HERTZ)
    return simulate_power(params, HERTZ, State.from_psi_xi(6.0, 0.0, params.xi_eq, 0.0), max_events=20_000)


def work():
    return [np.empty(DEGREE_LONG + 2) for _ in range(3)]


def assert_matches_reference(drop, n, tau, law):
    """Flight n of the drop (its time tau from short_flight) and the event loop's post-impact state (x' and
    xi' exchanged, eq. collision-rule) against the mpmath reference from the same start, to REL."""
    start = (0.0, float(drop.xdot[n - 1]), float(drop.xidot[n - 1]), float(drop.eta[n - 1]))
    impact = (tau, float(drop.xdot[n]), float(drop.xidot[n]), float(drop.eta[n]))
    errors = PR.first_impact_errors(GAMMA, MU, 1.0, 0.5, 0.5, start, float(law[L_XI_EQ]), impact)
    assert max(errors) <= REL, errors


@pytest.mark.parametrize("n", [2_600, 3_000, 5_000, 10_000, 19_999])
def test_hot_path_flights_of_the_drop_match_reference(drop, n):
    law = law_array(1.0, 0.5, 0.5, MU, GAMMA)
    u, a, eta = float(drop.xdot[n - 1]), float(drop.xidot[n - 1]), float(drop.eta[n - 1])
    status, tau = PF.short_flight(u, a, eta, law, *work())[:2]
    assert status == FOUND  # the flight takes the hot path
    assert tau == drop.tau[n]  # and the event loop took it too
    assert_matches_reference(drop, n, tau, law)


@pytest.mark.parametrize("n", [1_000, 1_500, 2_000])
def test_split_flights_of_the_drop_match_reference(drop, n, monkeypatch):
    """Flights two or three times the one-step limit: short_flight takes them in 2 or 3 steps
    (_split_flight; the kernel run as Python to see the call), equal to the compiled event loop's,
    against the reference to 1e-14."""
    law = law_array(1.0, 0.5, 0.5, MU, GAMMA)
    u, a, eta = float(drop.xdot[n - 1]), float(drop.xidot[n - 1]), float(drop.eta[n - 1])
    split, kernel = [], PF._split_flight
    monkeypatch.setattr(PF, "_split_flight", lambda *args: split.append(kernel(*args)) or split[-1])
    status, tau = PF.short_flight.py_func(u, a, eta, law, *work())[:2]
    assert len(split) == 1 and status == FOUND and tau == drop.tau[n]
    assert_matches_reference(drop, n, tau, law)


LAWS = {"hertz": (1.0, 0.5, 0.5), "a1/4": (1.5, 0.25, 0.25), "a1_b0": (2.0, 1.0, 0.0)}


@settings(max_examples=150, deadline=None)
@given(name=st.sampled_from(sorted(LAWS)), log_u=st.floats(-5.0, -1.5), v_rel=st.floats(-1.0, 1.0),
       eta_rel=st.floats(-1.0, 1.0), gamma=st.sampled_from([0.01, 0.1]), mu=st.sampled_from([0.01, 0.3]))
def test_hot_path_is_first_contact_or_hands_over(name, log_u, v_rel, eta_rel, gamma, mu):
    """Speeds 1e-5 .. 3e-2 with |xi'| and |eta| up to u and 10 u / sqrt(f'(xi_eq)) (the spring's
    swing for that energy): both sides of the hot path's limits."""
    assert_hot_path_agrees(name, log_u, v_rel, eta_rel, gamma, mu)


@settings(max_examples=150, deadline=None)
@given(name=st.sampled_from(sorted(LAWS)), log_u=st.floats(-2.5, -1.7), v_rel=st.floats(-1.0, 1.0),
       eta_rel=st.floats(-1.0, 1.0), mu=st.sampled_from([0.01, 0.05]))
def test_split_flights_are_first_contact_or_hand_over(name, log_u, v_rel, eta_rel, mu):
    """gamma = 0.01, speeds 3e-3 .. 2e-2: flights around the one-step limit, ~1/3 of them in 2 or 3
    steps (_split_flight), the others in one step or handed over."""
    assert_hot_path_agrees(name, log_u, v_rel, eta_rel, 0.01, mu)


def assert_hot_path_agrees(name, log_u, v_rel, eta_rel, gamma, mu):
    rho, a, b = LAWS[name]
    law = law_array(rho, a, b, mu, gamma)
    u = 10.0**log_u
    omega = math.sqrt(rho * (a + 1.0) * abs(float(law[L_XI_EQ])) ** a)
    v, eta = v_rel * u, eta_rel * 10.0 * u / omega
    hot = PF.short_flight(u, v, eta, law, *work())
    if hot[0] == PF.HANDOVER:
        return
    general = PF.first_contact(0.0, u, v, eta, np.inf, law, *work())
    assert hot[0] == general[0] == FOUND
    tau_h, tau_g = hot[1], general[1]
    assert abs(tau_h - tau_g) <= 4e-15 * tau_g, (tau_h, tau_g)
    assert abs(hot[2] - general[2]) <= 4e-15 * (u + gamma * tau_g), (hot[2], general[2])  # x'
    assert abs(hot[4] - general[4]) <= 4e-15 * (abs(float(law[L_XI_EQ])) + abs(eta)), (hot[4], general[4])  # eta
    assert abs(hot[5] - general[5]) <= 4e-15 * (abs(v) + u + gamma * tau_g), (hot[5], general[5])  # xi'


def test_poor_predictor_hands_over_not_a_wrong_root(monkeypatch):
    """A window far too short (WINDOW 1/2: the root lies beyond it) must give HANDOVER; the
    kernel is run as Python (py_func) with the module constant patched."""
    law = law_array(1.0, 0.5, 0.5, MU, GAMMA)
    u, v, eta = 1.4e-3, -7e-4, 5e-5
    assert PF.short_flight(u, v, eta, law, *work())[0] == FOUND
    monkeypatch.setattr(PF, "WINDOW", 0.5)
    assert PF.short_flight.py_func(u, v, eta, law, *work())[0] == PF.HANDOVER

"""The power-law solver against the independent mpmath reference (tests/power_reference.py), per flight.

Hertz (a = b = 1/2) and two other laws, a moderately excited flight and flights deep near
equilibrium: flight time and post-impact state to 1e-14, each component relative to the
larger of its value and the terms it is summed from (see test_power_core.assert_flight_matches).
"""

from __future__ import annotations

import pytest
from mpmath import mp, mpf

import power_reference as PR
from bounce import Deviations, Parameters, State
from bounce.series.events import simulate_power
from bounce.series.taylor import L_XI_EQ, law_array
from bounce.springs.power import PowerSpring

REL = 1e-14
LAWS = [PowerSpring(1.0, 0.5, 0.5), PowerSpring(2.0, 1.0, 0.0), PowerSpring(0.5, 0.25, 1.0),
        PowerSpring(1.5, 0.25, 0.25)]  # a = b != 1/2: the equal-powers recurrence with Miller's power
# (x, xdot, xidot, eta): from the floor, moderately excited; and deep near equilibrium
STARTS = {
    "excited": (0.0, 0.3, 0.1, 0.02),
    "excited_above": (0.05, -0.1, -0.2, -0.01),
    "deep": (0.0, 1e-8, 3e-9, -2e-9),
    "deeper": (0.0, 1e-11, -1e-12, 5e-12),
}


def event(tr, i):
    """(tau, x', xi', eta) of event i of a trajectory."""
    return float(tr.tau[i]), float(tr.xdot[i]), float(tr.xidot[i]), float(tr.eta[i])


@pytest.mark.parametrize("spring", LAWS, ids=lambda s: f"rho{s.rho}_a{s.a}_b{s.b}")
@pytest.mark.parametrize("start", list(STARTS), ids=str)
@pytest.mark.parametrize("gamma, mu", [(0.01, 0.1), (0.1, 0.5)])
def test_first_impact_matches_reference(spring, start, gamma, mu):
    x, u, a, eta = STARTS[start]
    tr = simulate_power(Parameters(gamma, mu, spring), spring, Deviations(x=x, xdot=u, xidot=a, eta=eta),
                        max_events=1)
    xi_eq = float(law_array(spring.rho, spring.a, spring.b, mu, gamma)[L_XI_EQ])  # the solver's origin of eta
    assert tr.kind[0] == 0  # an impact
    errors = PR.first_impact_errors(gamma, mu, spring.rho, spring.a, spring.b, (x, u, a, eta), xi_eq, event(tr, 0))
    assert max(errors) <= REL, errors


@pytest.mark.parametrize("rho, a, xi0", [(1.0, 0.5, "rest_length"), (1.0, 0.5, "static"), (1e14, 50.0, "rest_length")])
def test_drop_transient_flights_match_reference(rho, a, xi0):
    """The Hertz drop of benchmarks/bench_power.py (gamma = mu = 0.01, psi(0) = 6, xi(0) = 0 or xi_eq):
    its first four flights, long ones through many crossings of xi = 0 among them (~70 time units,
    ~2e3 series steps), each from bounce's own float64 state, against the reference to 1e-14.  And the
    same drop of the stiff law a = 50, b = 1/2, whose spring is nearly free for |xi| < 0.45 and stiff beyond
    (the disc fraction 2/a of springs.power.disc_fraction: with the fixed 0.95 its second flight did not
    end in 14 min); rho = 1e14 holds the ball above the floor, |xi_eq| = 0.49 < 1/2 (the power law's domain,
    bounce.springs.power: with rho = 1, |xi_eq| = 0.91, refused)."""
    gamma = mu = 0.01
    spring = PowerSpring(rho, a, 0.5)
    params = Parameters(gamma, mu, spring)
    xi_eq = float(law_array(rho, a, 0.5, mu, gamma)[L_XI_EQ])
    drop = State.from_psi_xi(6.0, 0.0, 0.0 if xi0 == "rest_length" else params.xi_eq, 0.0)
    tr = simulate_power(params, spring, drop, max_events=4)
    assert list(tr.kind) == [0, 0, 0, 0]
    for i in range(1, 4):
        start = (0.0, float(tr.xdot[i - 1]), float(tr.xidot[i - 1]), float(tr.eta[i - 1]))
        errors = PR.first_impact_errors(gamma, mu, rho, a, 0.5, start, xi_eq, event(tr, i))
        assert max(errors) <= REL, (i, errors)


@pytest.mark.parametrize("spring", [PowerSpring(0.5, 0.25, 1.0), PowerSpring(1.0, 0.0, 0.5), PowerSpring(1.0, 0.5, 1.5),
                                    PowerSpring(2.0, 0.25, 0.25)], ids=lambda s: f"rho{s.rho}_a{s.a}_b{s.b}")
def test_flight_through_many_crossings_matches_reference(spring):
    """A flight of ~15 time units whose spring crosses its rest length xi = 0 3-5 times (the
    crossings of series.flight for b > 0, b <= 1 and b > 1: root variable, windows as fallback), to 1e-14."""
    gamma, mu = 0.05, 0.05
    x, u, a = 0.0, 0.1, 0.3
    xi_eq = float(law_array(spring.rho, spring.a, spring.b, mu, gamma)[L_XI_EQ])
    eta = 0.05 - xi_eq
    tr = simulate_power(Parameters(gamma, mu, spring), spring, Deviations(x=x, xdot=u, xidot=a, eta=eta),
                        max_events=1)
    assert tr.kind[0] == 0
    errors = PR.first_impact_errors(gamma, mu, spring.rho, spring.a, spring.b, (x, u, a, eta), xi_eq, event(tr, 0))
    assert max(errors) <= REL, errors
    assert tr.tau[0] > 10.0  # (the reference's tau agrees to REL)


def test_long_flight_through_many_crossings_matches_reference():
    """A ~1000-long Hertz flight whose nearly undamped spring (gamma = 1e-5, mu = 1e-6) swings through
    its rest length ~45 times (~4e3 series steps): flight time and post-impact state to 1e-14, eta
    relative to the swing W = |xi_eq| (eta sweeps [0, 2W] over and over; it is summed from steps of
    that size).  The bound of series.flight's docstring for long flights: the energy's random walk of
    roundings (~8e-17 per crossing) becomes a phase error ~1.5e-17 n^(3/2) (rms) after n crossings through
    the energy-dependent frequency, 5e-15 here (measured 2.6e-15; 2.3e-14 when the compensation of
    eta, xi' was not folded into the state the series is taken at).  The reference at 30 digits (it
    agrees with its 40-digit run to 1e-25 relative in tau and eta; 50 digits would double the ~2 s)."""
    gamma, mu, x0 = 1e-5, 1e-6, 5.0
    spring = PowerSpring(1.0, 0.5, 0.5)
    xi_eq = float(law_array(1.0, 0.5, 0.5, mu, gamma)[L_XI_EQ])
    tr = simulate_power(Parameters(gamma, mu, spring), spring, Deviations(x=x0, xdot=0.0, xidot=0.0, eta=0.0),
                        max_events=1)
    with mp.workdps(30):
        flight = PR.make_flight(gamma, mu, 1.0, 0.5, 0.5, x0, 0.0, 0.0, mpf(xi_eq))
        tau_ref = flight.first_impact()[0]
        _, psid, xi, xid = flight.state(tau_ref)
        crossings = sum(isinstance(seg, PR.Crossing) for seg in flight.segments)
        eta_ref = float(xi - mpf(xi_eq))
        tau, xdot, xidot = float(tau_ref), float(xid - psid), float(psid)
    assert crossings >= 40 and tau > 900.0
    assert tr.kind[0] == 0
    assert abs(tr.tau[0] - tau) <= REL * tau, (tr.tau[0], tau)
    assert abs(tr.xdot[0] - xdot) <= REL * abs(xdot), (tr.xdot[0], xdot)
    assert abs(tr.xidot[0] - xidot) <= REL * gamma * tau, (tr.xidot[0], xidot)
    assert abs(tr.eta[0] - eta_ref) <= REL * abs(xi_eq), (tr.eta[0], eta_ref, (tr.eta[0] - eta_ref) / xi_eq)

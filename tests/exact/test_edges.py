"""Numerics at the edges of the input domain (issue 12), each against an independent reference.

* the oscillator's small parts 1 - c, t - S, 1 - S' (and c, S, S') against mpmath for mu up to 1e8;
* strong over-damping (mu = 1e6) end to end against the mpmath trajectory;
* the rest-state verdict decided by a floor force of 2.4e-9 gamma (relative noise floor);
* the root finder on inputs it used to fail on, and their energy balance;
* a state below what float64 resolves (x0 = 1e-300) gets a rest verdict, not a loop;
* event times are the correctly rounded sums of the exact durations (time stalls documented);
* the undamped energy balance over many impacts (measured bound, see bounce.exact.events).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st
from mpmath import mp, mpf

from bounce.analysis import reference as R
from bounce import Deviations, Parameters, State, simulate
from bounce.io import EVENT_VARIABLES
from bounce.springs.base import FLIGHT_MAX
from bounce.exact.oscillator import SERIES_Q, fundamental, make_oscillator

EPS = 2.0**-52
MUS = [0.0, 1e-8, 0.01, 0.5, 0.99, 1.0, 1.0 + 1e-9, 1.01, 2.0, 20.0, 1e3, 1e6, 1e8]


@pytest.mark.parametrize("mu", MUS)
def test_fundamental_parts_against_mpmath(mu):
    """1 - c, t - S, 1 - S' keep a few ulps relative to themselves (Taylor series for rho t <= 2;
    over-damped closed forms by expm1 of each rate), at q = rho t from 1e-6 to 1e3; for mu <= 1 the
    closed forms (rho t > 2) form them by subtraction, to a few ulps of 1.

    Bound: 4 ulps of |value| + t (|value'| + (1 + mu) e^{-lam_slow t}), i.e. the error of
    perturbing t by a few ulps: the conditioning of the phase w t and of the decay e^{-mu t} at
    long times (e^{-500} carries 500 ulps from the rounding of its argument); for
    mu >= 1.01 (no phase) the bound is 4 ulps of |value| itself.  c, S, S' are checked with
    the same conditioned bound.  Before the fix 1 - c lost ~mu^2 eps: 4e-4 at mu = 1e6."""
    params, coefs = make_oscillator(mu)
    rho = params[1]
    for q in np.geomspace(1e-6, 1e3, 40):
        t = float(q / rho)
        got = fundamental(t, params, coefs)
        omc, tms, omsd, c, S, Sd = ref = R.fundamental_parts(mu, t)
        envelope = math.exp(-(params[4] if mu >= 1.0 else mu) * t)  # e^{-lam_slow t}: size of c, S, S'
        Sdd = -2.0 * mu * Sd - S
        derivs = (S, omsd, -Sdd, -S, Sd, Sdd)
        for j, name in enumerate(("1-c", "t-S", "1-S'", "c", "S", "S'")):
            phase = 0.0 if (mu >= 1.01 and j < 3) else t * (abs(derivs[j]) + (1.0 + mu) * envelope)
            unit = 1.0 if (mu <= 1.0 and j < 3 and params[1] * t > SERIES_Q) else 0.0  # subtraction from 1
            bound = 4.0 * EPS * (abs(ref[j]) + phase + unit) + 1e-300
            assert abs(got[j] - ref[j]) <= bound, (
                f"{name} at mu={mu!r}, t={t!r}: {got[j]!r} vs {ref[j]!r} (err {abs(got[j] - ref[j]) / bound * 4:.3g} "
                f"ulps of the bound)"
            )


def test_strong_overdamping_first_impacts():
    """gamma = 0.01, mu = 1e6, eq. sticky-ic with eps = 1e-3, Ydot0 = -0.1: the first impacts against
    the mpmath trajectory (before the fix: times wrong by 1e-3 relative, heights by 1.6e-4 of their
    scale).  Tolerance 1e-12 relative: the flights are x ~ 1e-10 displacements of terms ~1e-3."""
    gamma, mu = 0.01, 1e6
    p = Parameters(gamma, mu)
    start = State.sticky_ic(p, 1e-3, -0.1)
    tr = simulate(p, start, max_events=4)
    assert tr.kind_names == ("impact",) * 4
    ts, _, states = R.trajectory(gamma, mu, R.Dev(start.x, start.xdot, start.xidot, start.eta), 4)
    np.testing.assert_allclose(tr.t, [float(t) for t in ts], rtol=1e-12, atol=0)
    np.testing.assert_allclose(tr.xdot, [float(st.u) for st in states], rtol=1e-10, atol=0)


def test_floor_force_noise_is_relative():
    """gamma = 3.69e-7, mu = 1 + 1e-9, at rest on the floor with F = 2.4e-9 gamma > 0 (computed in
    mpmath from the same floats, far above the rounding 8 eps (|eta| + 2 mu |xi'| + 2 gamma) of
    forming it): the lower mass lifts off.  With the former absolute threshold ("+ 1") it was
    declared at rest (sticky_start at t = 0)."""
    gamma, mu = 3.689312427259341e-07, 1.000000001
    d = Deviations(0.0, 0.0, 2.956540581926447e-07, 1.4655436936623255e-07)
    with mp.workdps(50):
        F = mpf(d.eta) + 2 * mpf(mu) * mpf(d.xidot) - 2 * mpf(gamma)
    noise = 8 * EPS * (abs(d.eta) + 2 * mu * abs(d.xidot) + 2 * gamma)
    assert float(F) > 1e3 * noise and float(F) < 1e-8 * gamma
    tr = simulate(Parameters(gamma, mu), d, max_events=3)
    assert tr.kind[0] != 2 and tr.t[0] > 0.0, tr.kind_names


def _energy(gamma, d):
    return 0.5 * (d.xidot**2 + (d.xdot + d.xidot) ** 2 + d.eta**2) + gamma * d.x


@pytest.mark.parametrize(
    "gamma, mu, start, n",
    [
        (0.1, 0.0, State(0.0, 0.0, 1.2, 0.0), 100),  # at rest with F = 0, F' = 0: tangent detach forever
        (0.01, 0.01, State(6.0, -1e-308, 7.0, 0.0), 100),  # subnormal speed: Newton window overflowed
        (0.01, 5e7, State(6.0, 0.0, 7.0, 0.0), 100),  # series coefficients overflowed (rho^k)
        (0.01, 1e8, State(6.0, 0.0, 7.0, 0.0), 100),
        (1e-12, 0.0, Deviations(6.0, 0.0, 0.0, 2e-5), 3),  # ~1e6 spring periods per flight
    ],
    ids=["mu0-rest-tangent", "xdot-subnormal", "mu5e7", "mu1e8", "gamma1e-12"],
)
def test_root_finder_on_former_failures(gamma, mu, start, n):
    """Inputs inside the supported range on which the root finder failed ("please report"): they
    now run to their stop, with finite records and an energy that never rises (16 eps relative,
    the rounding of the recorded sums of squares, as in test_invariants)."""
    p = Parameters(gamma, mu)
    tr = simulate(p, start, max_events=n)
    assert tr.stop_reason in ("max_events", "sticky_forever")
    assert np.all(np.isfinite(tr.t)) and np.all(np.diff(tr.t) >= 0)
    e = np.concatenate([[_energy(gamma, start.deviations(p))], tr.energy_excess])
    assert np.all(np.diff(e) <= 16 * EPS * e[:-1])
    if gamma == 0.1:  # F <= 0 for ever, touching 0 tangentially once per period: sticky for ever
        assert tr.kind_names == ("sticky_start",) and tr.stop_reason == "sticky_forever"


def test_state_below_resolution_comes_to_rest():
    """psi0 = 1e-300 (x0 = 1e-300, spring at rest length): the drop of 1e-300 reaches the floor at
    t = sqrt(2e-300/gamma) with speed 1.4e-151, below the absolute resolution 1e-300 of heights,
    pressed down (x'' = -gamma): a rest verdict (sticky_start, then sticky for ever: the spring's
    envelope gamma stays below 2 gamma), not 1e6 grazings at t = 1.4e-149."""
    gamma = 0.01
    tr = simulate(Parameters(gamma, 0.01), State.from_psi_xi(1e-300, 0.0, 0.0, 0.0), max_events=1000)
    assert tr.kind_names == ("sticky_start",) and tr.stop_reason == "sticky_forever"
    assert tr.t[0] == pytest.approx(math.sqrt(2e-300 / gamma), rel=1e-12)


def test_event_times_are_rounded_sums_of_durations():
    """t[i] is the correctly rounded sum of the exact durations tau[0..i] (compensated sum), so a
    phase below half an ulp of t leaves t unchanged while tau stays exact; the netCDF files say so."""
    p = Parameters(0.01, 0.01)
    tr = simulate(p, State.from_psi_xi(6.0, 0.0, 0.0, 0.0), max_events=3000)
    sums = [math.fsum(tr.tau[: i + 1]) for i in range(0, len(tr), 97)]
    assert np.array_equal(tr.t[::97], np.array(sums))
    assert "half an ulp" in EVENT_VARIABLES["t"][1]


def test_undamped_energy_drift_is_bounded():
    """mu = 0, psi(0) = 6, gamma = 0.01: E - E_m is conserved by the dynamics; the recorded states
    drift by rounding.  Measured (tests of issue 12, 2e4 impacts against the mpmath flight from each
    recorded state): +0.03 eps E per impact of bias, entirely from rounding the spring state in the
    flight map (the contact-time residual contributes nothing significant, c^2 + S^2 - 1 has no
    bias), on top of an unbiased random walk of ~1 eps E per impact.  Asserted bound, with the
    energy of the float states evaluated exactly: |E_n - E_0| <= eps E_0 (0.1 n + 4 sqrt(n)),
    i.e. three times the measured bias plus four standard deviations of the walk."""
    from fractions import Fraction

    p = Parameters(0.01, 0.0)
    start = State.from_psi_xi(6.0, 0.0, 0.0, 0.0)
    n = 50_000
    tr = simulate(p, start, max_events=n)
    assert tr.stop_reason == "max_events" and set(tr.kind_names) == {"impact"}

    def exact(u, a, eta, x=0.0):
        u, a, eta, x = (Fraction(float(v)) for v in (u, a, eta, x))
        return (a * a + (u + a) ** 2 + eta * eta) / 2 + Fraction(0.01) * x

    d = start.deviations(p)
    e0 = exact(d.xdot, d.xidot, d.eta, d.x)
    for k in (n // 10, n // 2, n - 1):
        drift = abs(float(exact(tr.xdot[k], tr.xidot[k], tr.eta[k]) - e0))
        assert drift <= EPS * float(e0) * (0.1 * (k + 1) + 4.0 * math.sqrt(k + 1)), (k, drift / (EPS * float(e0)))


@pytest.mark.parametrize("gamma, mu", [(0.01, 1e3), (0.01, 1e6), (0.3, 1e6)])
def test_sticky_start_strong_overdamping(gamma, mu):
    """eq. sticky-ic with eps = 0 at mu up to 1e6 (which used to fail to converge): sticky_start at
    t = 0, then the reference's detach (1e-12 relative, as in test_sticky) or its proof that the
    sticky phase never ends."""
    p = Parameters(gamma, mu)
    s0 = State.sticky_ic(p, eps=0.0)
    tr = simulate(p, s0, max_events=3)
    assert tr.kind[0] == 2 and tr.t[0] == 0.0, tr.kind_names
    td, _ = R.sticky_detach(gamma, mu, *R.rest_state(gamma, s0.deviations(p)))
    if td is None:
        assert tr.stop_reason == "sticky_forever" and len(tr) == 1, (tr.kind_names, tr.t)
    else:
        assert len(tr) >= 2 and tr.kind[1] == 3, (tr.kind_names, tr.stop_reason)
        assert abs(tr.t[1] - float(td)) <= 1e-12 * float(td)


def test_sticky_phase_with_a_huge_damping_force():
    """mu = 1e7 from rest on the floor with y' = -1 (xi' = -1/2): the reference's verdict (here: never detaches).
    Found by tests/test_fuzz.py: the damping force 2 mu xi' = -1e7 against a floor force of 1e-3 used to detach
    at t = 0.153 (the gap's flight form cancelled ~3e13 to ~1e7, see events._sticky_modes)."""
    gamma, mu = 1e-3, 1e7
    p = Parameters(gamma, mu)
    s0 = State(x=0.0, xdot=0.0, y=1.0, ydot=-1.0)
    tr = simulate(p, s0, max_events=3)
    td, _ = R.sticky_detach(gamma, mu, *R.rest_state(gamma, s0.deviations(p)))
    assert tr.kind[0] == 2 and td is None
    assert tr.stop_reason == "sticky_forever" and len(tr) == 1, (tr.kind_names, tr.t)


def assert_sticky_phase_as_reference(gamma, mu, s0):
    """A start at rest on the floor that the reference calls sticky: sticky_start at t = 0, then the reference's
    verdict, a detach (1e-12 relative, also y - y_eq and ydot there, as in test_sticky) or 'sticky_forever'."""
    p = Parameters(gamma, mu)
    tr = simulate(p, s0, max_events=2)
    td, wd = R.sticky_detach(gamma, mu, *R.rest_state(gamma, s0.deviations(p)))
    assert tr.kind[0] == 2 and tr.t[0] == 0.0, tr.kind_names
    if td is None:
        assert tr.stop_reason == "sticky_forever" and len(tr) == 1, (tr.kind_names, tr.t)
        return
    assert len(tr) == 2 and tr.kind[1] == 3, (tr.kind_names, tr.stop_reason)
    with mp.workdps(R.DPS):
        assert abs(mpf(tr.t[1]) - td) <= 1e-12 * td, (tr.t[1], float(td))
        w, wdot = wd  # x = xdot = 0 at detach: y - y_eq = 2 eta, ydot = 2 xi'
        size = abs(w) + abs(wdot)
        assert abs(2 * mpf(tr.eta[1]) - w) <= 1e-12 * size and abs(2 * mpf(tr.xidot[1]) - wdot) <= 1e-12 * size


#: y' < 0 at rest on the floor, per gamma, down to 1e-4 of the largest start the energy bound allows
#: (model.check_supported: flights <= 1e8, E - E_m = y'^2/4 here)
PRESSING_SPEEDS = {1e-3: [-10.0, -1.0, -0.1, -1e-3], 1e-12: [-5e-5, -5e-6, -5e-7, -5e-9]}


@pytest.mark.parametrize("mu", [1e3, 1e4, 1e5, 1e6, 1e7, 3e7, 1e8])
@pytest.mark.parametrize("gamma, ydot", [(g, v) for g, speeds in PRESSING_SPEEDS.items() for v in speeds])
def test_sticky_phases_under_huge_damping_forces(gamma, ydot, mu):
    """The class of the failure above: rest on the floor at y = 1 with y' < 0 presses the lower mass by the
    damping force 2 mu xi' = mu y' (up to 1e9 against 2 gamma = 2e-3, or 5e3 against 2e-12); every such
    phase is the reference's (before the fix 10 of the 28 at gamma = 1e-3 and 15 of the 28 at gamma = 1e-12
    detached, at t from 3e-7 to 4e7; one gave t = nan)."""
    assert_sticky_phase_as_reference(gamma, mu, State(x=0.0, xdot=0.0, y=1.0, ydot=ydot))


@settings(deadline=None, max_examples=60)
@given(st.floats(-12.0, math.log10(0.4)), st.floats(math.log10(2.0), 8.0), st.floats(-1.0, 1.0),
       st.floats(-6.0, 0.0), st.booleans())
@example(-3.0, 7.0, 1e-3 / 0.9, -1.0 + math.log10(2.0), False)  # the failure above, y = y_eq + 2 gamma, y' = -1
@example(-3.0, math.log10(3.0), -0.4, -6.0, False)  # a detach after the fast mode has died out
def test_sticky_phases_of_over_damped_springs(log_gamma, log_mu, dy_rel, log_speed, upward):
    """Rest on the floor (x = x' = 0) at y = y_eq + dy with |y'| = 10^log_speed V of either sign, at mu from 2
    (the sticky oscillator's damping ratio mu/sqrt(2) from sqrt(2)) to 1e8; dy = dy_rel * min(0.9, 2 V) and
    V = min(10, sqrt(E_max)) keep E - E_m = y'^2/4 + dy^2/8 within the supported range E_max.  Where the
    start is pressed onto the floor beyond rounding, the reference's verdict and detach time."""
    gamma, mu = 10.0**log_gamma, 10.0**log_mu
    speed = min(10.0, math.sqrt((FLIGHT_MAX * gamma) ** 2 / 12))
    dy = dy_rel * min(0.9, 2.0 * speed)
    ydot = (1.0 if upward else -1.0) * 10.0**log_speed * speed
    floor_force = dy / 2 + mu * ydot - 2 * gamma  # eq. force-on-the-floor at rest
    assume(floor_force < -1e-9 * (abs(dy) + mu * abs(ydot) + 2 * gamma))  # pressed beyond rounding
    assert_sticky_phase_as_reference(gamma, mu, State(x=0.0, xdot=0.0, y=1.0 - 2.0 * gamma + dy, ydot=ydot))


def test_flights_beyond_the_root_finder_are_refused_up_front():
    """gamma = 1e-12, mu = 0, psi(0) = 6 with the spring excited (xi(0) = 0.1): ~1e10 spring
    oscillations per flight, which used to exhaust the step cap ("please report").  Refused before
    simulating, naming the initial state and the supported range (longest flight <= 1e8)."""
    from bounce.model import InputError

    with pytest.raises(InputError, match=r"initial state.*supported range: flights <= 1e\+08"):
        simulate(Parameters(1e-12, 0.0), State.from_psi_xi(6.0, 0.0, 0.1, 0.0), max_events=3)

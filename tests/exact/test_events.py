"""bounce.exact.events: what happens at x = 0 (impact, grazing, sticky onset, detach) and why the loop stops.

Protects, against the mpmath reference and the paper's equations:

* the impact rule (eq. collision-rule): psi' and xi' are exchanged, xi is continuous;
* energy (eqs. tot-mech-energy, Emin): an impact conserves E, a flight does not raise it;
* the classification of tangential contacts on constructed states: a grazing (eq. swishes,
  x = x' = 0 < x'') and a sticky onset (eq. sticky-condition, x = x' = x'' = 0 > x'''), and the
  zero-speed windows of _is_tangential / _is_sticky_onset;
* the floor force and its rate (eq. force-on-the-floor, with eq. y-eq-sticky for F');
* the compensated time sum (event times correctly rounded sums of the durations);
* every stop reason of run_events reachable, with its meaning.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, example, given, settings
from hypothesis import strategies as st
from mpmath import mp, mpf

from bounce.analysis import reference as R
from bounce import Deviations, Parameters, State, simulate
from bounce.kinds import GRAZING, IMPACT, STICKY_START, STOP_FAILED, STOP_NAMES
from bounce.exact.events import _is_sticky_onset, _is_tangential, compensated_add, energy_excess, floor_force, run_events
from bounce.exact.oscillator import make_oscillator
from bounce.exact.events import rounding_level as contact_rounding_level
from contacts import constructed_contact, reference_flight, rounding_level

EPS = 2.0**-52
SETTINGS = settings(deadline=None, max_examples=40, suppress_health_check=[HealthCheck.too_slow])

gammas = st.floats(-5.0, math.log10(0.4)).map(lambda e: 10.0**e)
mus = st.one_of(st.sampled_from([0.0, 1.0]), st.floats(0.0, 3.0))
small = st.floats(-0.5, 0.5)
#: products of tiny draws (1e-200 squared) underflow to 0 in float64: an absolute allowance
UNDERFLOW = 1e-290


@SETTINGS
@given(gammas, mus, st.floats(0.0, 1.0), st.floats(-1.0, 1.0), small, small)
@example(0.01, 1e-16, 0.0, 1.0, 0.5, 0.0)  # tau = 139: the frequency's rounding, once 1 ulp off, shows as phase
def test_impact_exchanges_psi_and_xi_velocities(g, mu, x_frac, u_frac, a, eta):
    """After an impact at tau: xi'(tau+) = psi'(tau-) = u + a - g tau, psi'(tau+) = u+ + a+ =
    xi'(tau-), and eta = xi + g continuous; the pre-impact values from the reference at the
    recorded tau.  Energy (xi'^2 + psi'^2 + eta^2)/2 at x = 0 is the same on both sides, and not
    above the start's.  Tolerance 8 ulps of the magnitudes involved (a few roundings each), plus for xi'(tau-) the
    phase error eps tau of a long flight (the frequency's rounding)."""
    x0, u = x_frac * min(1.0, 100 * g), u_frac * min(1.0, 20 * g)  # flights of O(10) (test_flight)
    assume(x0 > 1e-12 or u > 1e-12)
    tr = simulate(Parameters(g, mu), Deviations(x0, u, a, eta), max_events=1)
    assume(tr.kind[0] == IMPACT)
    tau = float(tr.tau[0])
    with mp.workdps(R.DPS):
        fl = reference_flight(g, mu, x0, u, a, eta)
        xi, xid = fl.xi(mpf(tau))
        psid = mpf(u) + mpf(a) - mpf(g) * mpf(tau)
        # xi'(tau) = a S'(tau) - (eta - g) S(tau) - ...: the flight rounds terms of |eta| too (|S| <= 1)
        size = abs(u) + abs(a) + g * tau + abs(float(xid)) + abs(eta)
        # + the phase error of xi at tau: omega to ~1 ulp (oscillator.natural_frequency) times tau, on an
        # amplitude <= |a| + |eta| + g
        phase = EPS * tau * (abs(a) + abs(eta) + g)
        assert abs(tr.xidot[0] - psid) <= 8 * EPS * size, "xi'(tau+) != psi'(tau-)"
        assert abs(tr.xdot[0] + tr.xidot[0] - xid) <= 8 * EPS * size + phase, "psi'(tau+) != xi'(tau-)"
        assert abs(tr.eta[0] - (xi + mpf(g))) <= 8 * EPS * (abs(eta) + abs(a) * tau + g + g * tau * tau)
        before = (xid**2 + psid**2 + (xi + mpf(g)) ** 2) / 2  # E - E_m at tau-, x = 0
        start = R.energy_excess(g, R.Dev(mpf(x0), mpf(u), mpf(a), mpf(eta)))
        assert abs(tr.energy_excess[0] - before) <= 16 * EPS * before
        assert before <= start * (1 + 16 * EPS)


@SETTINGS
@given(gammas, mus, st.floats(-2.0, 2.0), small, small, small)
def test_energy_excess_is_eq_tot_mech_energy(g, mu, x, u, a, eta):
    """E - E_m of eqs. tot-mech-energy and Emin: E = xi'^2/2 + xi^2/2 + psi'^2/2 + g psi with
    psi = x + xi, xi = eta - g, E_m = -g^2/2 (mpmath at 700 digits: g x may be 1e-300 beside g^2),
    to 8 ulps of its terms."""
    with mp.workdps(700):
        G, xi = mpf(g), mpf(eta) - mpf(g)
        psi, psid = mpf(x) + xi, mpf(u) + mpf(a)
        exact = mpf(a) ** 2 / 2 + xi**2 / 2 + psid**2 / 2 + G * psi + G**2 / 2
    got = energy_excess(x, u, a, eta, g)
    assert abs(got - exact) <= 8 * EPS * (a * a + (u + a) ** 2 + eta * eta + g * abs(x)) + UNDERFLOW


@SETTINGS
@given(gammas, mus, small, small)
def test_floor_force_is_eq_force_on_the_floor(g, mu, a, eta):
    """At rest on the floor (x = x' = 0): y = 1 - 2 g + 2 eta, y' = 2 xi' = 2 a and
    F = y/2 + mu y' - g - 1/2 (eq. force-on-the-floor); F' = y'/2 + mu y'' with y'' from
    eq. y-eq-sticky, y'' = -mu y' - y/2 - g + 1/2.  Both in mpmath at 700 digits (y ~ 1 carries
    eta, which may be 1e-300); 8 ulps of the terms."""
    with mp.workdps(700):
        G, m = mpf(g), mpf(mu)
        y, yd = 1 - 2 * G + 2 * mpf(eta), 2 * mpf(a)
        ydd = -m * yd - y / 2 - G + mpf(1) / 2
        F, Fd = y / 2 + m * yd - G - mpf(1) / 2, yd / 2 + m * ydd
    got_F, got_Fd = floor_force(a, eta, g, mu)
    tol_F = 8 * EPS * (abs(eta) + 2 * mu * abs(a) + 2 * g) + UNDERFLOW
    tol_Fd = 8 * EPS * (abs(a) * (1 + 2 * mu * mu) + mu * abs(eta)) + UNDERFLOW
    assert abs(got_F - F) <= tol_F and abs(got_Fd - Fd) <= tol_Fd
    # and the reference sticky phase's own force at its start (w = y - y_eq = 2 eta, w' = 2 a)
    with mp.workdps(40):
        sticky = R.Sticky(g, mu, 2 * mpf(eta), 2 * mpf(a))
        assert abs(got_F - sticky.force(0)) <= tol_F and abs(got_Fd - sticky.force_dot(0)) <= tol_Fd


# --------------------------------------------------------------------------- tangential contacts

@pytest.mark.parametrize("g, mu, T, A", [(0.01, 0.3, 0.1, 0.01), (1e-3, 2.0, 0.1, 0.01), (0.05, 0.0, 0.2, 0.05)])
def test_constructed_grazing(g, mu, T, A):
    """x'' = A > 0 at the touch: recorded as a grazing (eq. swishes), nothing exchanged (x' = 0
    after it, xi' continuous), at T within twice the classifier's window sqrt(2 xn / A)."""
    d = constructed_contact(g, mu, 0.0, A, T)
    assert d.x > 0
    tr = simulate(Parameters(g, mu), d, max_events=1)
    assert tr.kind[0] == GRAZING and tr.xdot[0] == 0.0
    window = math.sqrt(2 * rounding_level(d, g, T) / A)
    assert abs(tr.t[0] - T) <= 2 * window and abs(tr.xidot[0]) <= 2 * window * (g + A)


@pytest.mark.parametrize("g, mu, T", [(0.01, 0.3, 0.4), (1e-3, 1.5, 0.1)])
def test_constructed_sticky_onset(g, mu, T):
    """x'' = 0 and x''' = -xi''' = a - 2 mu g < 0 at the touch (eq. sticky-condition): recorded as
    sticky_start at T (within twice the window (6 xn / |x'''|)^(1/3)), then a detach or a proved infinite
    sticky phase, never an impact inside the sticky phase."""
    a = mu * g  # x''' = -mu g < 0
    d = constructed_contact(g, mu, a, 0.0, T)
    assert d.x > 0
    tr = simulate(Parameters(g, mu), d, max_events=2, t_max=1e3)
    window = (6 * rounding_level(d, g, T) / (mu * g)) ** (1 / 3)
    assert tr.kind[0] == STICKY_START and abs(tr.t[0] - T) <= 2 * window
    assert tr.xdot[0] == 0.0
    assert len(tr) == 1 and tr.stop_reason in ("sticky_forever", "t_max") or tr.kind_names[1] == "detach"


def test_zero_speed_windows():
    """_is_tangential: |v| below 4 |x''| delta2 (v^2 <= 32 |x''| xn) or 4 |x'''| delta3^2 / 2 is
    tangential, twice that is not; _is_sticky_onset: x''^3 <= 384 x'''^2 xn with x''' < 0."""
    xn, acc, jerk = 1e-20, 1e-3, 0.0
    v_lim = math.sqrt(32 * acc * xn)
    assert _is_tangential(-0.5 * v_lim, acc, jerk, xn) and not _is_tangential(-2 * v_lim, acc, jerk, xn)
    assert _is_tangential(0.0, acc, jerk, xn) and _is_tangential(1.0, acc, jerk, xn)
    jerk, acc = -1.0, 0.0
    v_lim = (288 * abs(jerk) * xn * xn) ** (1 / 3)
    assert _is_tangential(-0.5 * v_lim, acc, jerk, xn) and not _is_tangential(-2 * v_lim, acc, jerk, xn)
    acc_lim = (384 * jerk * jerk * xn) ** (1 / 3)
    assert _is_sticky_onset(0.5 * acc_lim, jerk, xn) and not _is_sticky_onset(2 * acc_lim, jerk, xn)
    assert not _is_sticky_onset(0.0, 1.0, xn)  # x''' > 0: the gap opens again, a grazing


# --------------------------------------------------------------------------- time and stops

def test_event_times_are_compensated_sums():
    """1e5 short flights after the drop of fig. rigid-fall: every recorded t is within one ulp of
    the exact sum of the recorded durations (math.fsum); a plain running sum is many ulps off, so
    the comparison can tell them apart."""
    tr = simulate(Parameters(0.01, 0.01), State.from_psi_xi(6.0, 0.0, 0.0, 0.0), max_events=100_000)
    exact = math.fsum(tr.tau)
    assert abs(tr.t[-1] - exact) <= math.ulp(exact)
    naive = 0.0
    for tau in tr.tau:
        naive += tau
    assert abs(naive - exact) > 8 * math.ulp(exact)  # the test is not vacuous
    for k in (10, 1000, 50_000):
        assert abs(tr.t[k] - math.fsum(tr.tau[: k + 1])) <= math.ulp(tr.t[k])


def test_compensated_add_keeps_the_lost_digits():
    """1 + 1e6 terms of 1e-16: a plain sum stays at 1, (hi + lo) gives 1 + 1e-10."""
    hi, lo = 1.0, 0.0
    for _ in range(1_000_000 // 1000):
        for _ in range(1000):
            hi, lo = compensated_add(hi, lo, 1e-16)
    assert hi + lo == pytest.approx(1.0 + 1e-10, rel=2 * EPS)


def test_every_stop_reason_is_reachable():
    """max_events, t_max (in a flight and in a sticky phase), energy, sticky_forever; and
    root_finder_failed, reachable only from a non-finite state the Python front rejects: the
    kernel then reports it instead of looping or recording garbage."""
    p = Parameters(0.01, 0.01)
    drop = State.from_psi_xi(6.0, 0.0, 0.0, 0.0)
    assert simulate(p, drop, max_events=5).stop_reason == "max_events"
    tr = simulate(p, drop, max_events=1000, t_max=100.0)
    assert tr.stop_reason == "t_max" and tr.t[-1] <= 100.0 and len(tr) < 1000
    tr = simulate(p, drop, max_events=100_000, energy_stop=1e-6)
    assert tr.stop_reason == "energy" and tr.energy_excess[-1] < 1e-6 <= tr.energy_excess[-2]
    # pressed on the floor (F < 0) with a stiff over-damped spring: the sticky phase never ends
    g, mu = 0.01, 3.0
    rest = Deviations(0.0, 0.0, 0.0, -0.1)
    tr = simulate(Parameters(g, mu), rest, max_events=5)
    assert tr.kind_names[0] == "sticky_start" and tr.stop_reason == "sticky_forever"
    # an under-damped one detaches later than t_max: t_max inside the sticky phase
    tr = simulate(Parameters(g, 0.01), Deviations(0.0, 0.0, 0.0, -0.1), max_events=5, t_max=0.1)
    assert tr.kind_names == ("sticky_start",) and tr.stop_reason == "t_max"
    params, coefs = make_oscillator(0.01)
    sparams, scoefs = make_oscillator(0.01 / math.sqrt(2))
    out = [np.empty(3) for _ in range(6)] + [np.empty(3, dtype=np.int8)]
    n, stop, _ = run_events(math.nan, 0.0, 0.0, 0.0, 0.01, params, coefs, sparams, scoefs, 3, math.inf, 0.0, *out)
    assert STOP_NAMES[stop] == "root_finder_failed" and stop == STOP_FAILED and n == 0


@pytest.mark.parametrize("speed", [1e-90, 1.3066306367476234e-114, 1e-140])
@pytest.mark.parametrize("mu", [0.0, 0.3])
def test_a_launch_whose_speed_cubed_underflows_still_bounces(speed, mu):
    """From rest at equilibrium (eta = xi' = 0) with x' = u: x'' = -2 gamma, x''' = 0 to rounding, so every
    flight lasts u / gamma and every contact is an impact returning x' = u (E - E_m = u^2/2 throughout).
    |u|^3 underflowed to 0 in _is_tangential and 0 <= 0 made the first contact a sticky start that kept xi'
    and doubled E - E_m (found by the power-law fuzz; the linear law had it too).  Below |u| ~ 1e-150 the contact is
    tangential by the absolute floor 1e-300 of rounding_level, on purpose."""
    gamma = 0.1
    traj = simulate(Parameters(gamma, mu), Deviations(0.0, speed, 0.0, 0.0), max_events=6)
    assert np.all(traj.kind == IMPACT)
    assert np.allclose(traj.tau, speed / gamma, rtol=1e-14, atol=0.0)
    assert np.allclose(traj.xdot, speed, rtol=1e-14, atol=0.0)
    assert np.allclose(traj.energy_excess, 0.5 * speed * speed, rtol=1e-14, atol=0.0)
    xn = contact_rounding_level(speed * speed / gamma)  # the scale of x over the flight
    assert not _is_tangential(-speed, -2.0 * gamma, 0.0, xn)


def test_first_events_in_one_call_are_the_bits_of_one_event_simulations():
    """bounce.exact.events.first_events_linear (the thinned records' gaps, analysis.observables.dataset_series):
    each state's first event equals simulate(..., max_events=1) from it, bit for bit, impacts and the rest."""
    from bounce.exact.events import first_events_linear

    p = Parameters(0.01, 0.05)
    rng = np.random.default_rng(3)
    u = np.concatenate([rng.uniform(1e-6, 0.3, 40), [1e-9, 0.0]])
    a = np.concatenate([rng.uniform(-0.05, 0.05, 40), [0.0, 0.0]])
    eta = np.concatenate([rng.uniform(-0.05, 0.05, 40), [0.0, 0.0]])  # the last: at rest on the floor
    kind, tau, u_after = first_events_linear(p, u, a, eta)
    for i in range(u.size):
        r = simulate(p, Deviations(0.0, u[i], a[i], eta[i]), max_events=1)
        assert (kind[i], tau[i], u_after[i]) == (r.kind[0], r.tau[0], r.xdot[0]), i
    assert set(kind) > {IMPACT}  # not only impacts were compared

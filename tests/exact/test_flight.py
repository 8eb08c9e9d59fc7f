"""bounce.exact.flight: the free flight of eq. (F) and the first-contact root finder.

Protects, against the independent mpmath reference (tests/reference.py):

* eq. (F): the displacement x(t) and x'(t) of :func:`bounce.exact.flight.gap` equal the closed form to the
  rounding its parts allow (4 ulps of ``scale`` plus the oscillator's documented absolute error of
  1 - c, t - S, 1 - S' beyond the Taylor branch); the stronger docstring claim (a few ulps of
  ``scale`` outright) for over-damped long flights is a regression test (fixed with expm1, issue 12);
* :func:`first_contact` returns the *first* root: it never skips a constructed dip below the floor
  deeper than the rounding level (hypothesis), agrees with the reference's non-skipping root search
  on random flights, returns HORIZON before ``t_limit`` and NEVER only with a proof (bounded mode,
  g = 0: the decaying envelope of xi stays below the level it would have to reach);
* :func:`liftoff_time`: x > 0 on (0, s] for a flight from rest on the floor, 0 when there is no
  lift-off (pressed onto the floor beyond the caller's window of F, whatever F');
* :func:`xi_derivatives`, :func:`oscillator_at`, :func:`flight_spring` against derivatives and
  values of the ODE's solution (eq. eq-motion-psi-xi) in mpmath;
* a regression of the Newton polish (near-degenerate sticky onset classified sticky).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, example, given, settings
from hypothesis import strategies as st
from mpmath import mp, mpf

from bounce.analysis import reference as R
from contacts import reference_flight
from bounce import Deviations, Parameters, State, simulate
from bounce.exact.flight import (
    FOUND,
    HORIZON,
    NEVER,
    first_contact,
    flight_spring,
    gap,
    liftoff_time,
    oscillator_at,
    safe_step,
    xi_derivatives,
)
from bounce.exact.oscillator import P_RHO, SERIES_Q, make_oscillator
from test_oscillator import closed_form_abs_tol

EPS = 2.0**-52
STICKY_START = 2
SETTINGS = settings(deadline=None, max_examples=40, suppress_health_check=[HealthCheck.too_slow])

gammas = st.floats(-5.0, math.log10(0.4)).map(lambda e: 10.0**e)
mus = st.one_of(st.sampled_from([0.0, 1.0]), st.floats(0.0, 3.0))
small = st.floats(-0.5, 0.5)
#: 0 or log-uniform in [1e-12, 1] (the reference's digits are sized for this range, see below)
fractions = st.one_of(st.just(0.0), st.floats(-12.0, 0.0).map(lambda e: 10.0**e))
#: the paper's drop from psi(0) = 6 at rest, gamma = mu = 0.01 (fig. rigid-fall)
DROP = State.from_psi_xi(6.0, 0.0, 0.0, 0.0).deviations(Parameters(0.01, 0.01))


def x_tolerance(t, a, eta, g, params, scale):
    """Error bound of x(t) from eq. (F) in float64: 4 ulps of ``scale`` for the sum of five
    products, plus each small part's absolute error (closed_form_abs_tol, t - S: times 1 + t)
    times its coefficient where the parts come from the closed forms (rho t > SERIES_Q)."""
    q = params[P_RHO] * t
    parts = closed_form_abs_tol(q) * (abs(a) * (1 + t) + g + abs(eta)) if q > SERIES_Q else 0.0
    return 4 * EPS * scale + parts


# --------------------------------------------------------------------------- eq. (F)

@SETTINGS
@given(gammas, mus, st.floats(0.0, 1.0), small, small, small,
       st.one_of(st.floats(-9.0, 0.3).map(lambda e: 10.0**e), st.floats(2.0, 40.0)))
@example(0.01, 0.0, 0.0, 0.0, 0.0, 0.3, 2 * math.pi)  # 1 - c = 0 at mu = 0, t = 2 pi
@example(1e-5, 2.0, 0.0, 0.0, 0.0, 0.3, 1.1)  # over-damped, just past the switch
@example(1e-3, 1.0, 0.0, 0.0, 0.0, -0.5, 2.0)  # Taylor branch: S = t - (t - S) is 4 ulps of S off
def test_displacement_matches_closed_form(g, mu, x0, u, a, eta, t):
    """x(t), x'(t) of eq. (F) against x = psi - xi in mpmath (psi'' = -g, xi by its closed form).
    x' = u + a (1 - S') - g (t + S) + eta S: 4 ulps of its terms' magnitudes, plus the parts'
    absolute errors as for x."""
    params, coefs = make_oscillator(mu)
    x, v, scale, omc, tms, omsd, c, S, Sd = gap(t, x0, u, a, eta, g, params, coefs)
    with mp.workdps(R.DPS):
        fl = reference_flight(g, mu, x0, u, a, eta)
        xr, vr = fl.x(mpf(t)), fl.xdot(mpf(t))
    assert abs(x - xr) <= x_tolerance(t, a, eta, g, params, scale), (x, float(xr), scale)
    v_scale = abs(u) + abs(a * omsd) + g * (t + abs(S)) + abs(eta * S)
    # the parts' absolute errors: closed forms (rho t > SERIES_Q) as for x; in the Taylor branch S = t - (t - S)
    # is a few ulps of t (oscillator.fundamental), which eta S carries (found: mu = 1, t = 2, eta = -1/2: 4.6 ulps)
    q = params[P_RHO] * t
    v_parts = closed_form_abs_tol(q) * (abs(a) + g + abs(eta)) if q > SERIES_Q else 2 * EPS * t * abs(eta)
    assert abs(v - vr) <= 4 * EPS * v_scale + v_parts, (v, float(vr))


# before 1 - c was formed with expm1 of each root (issue 12) this lost ~3 mu^2 ulps: 9 ulps of scale at
# mu = 2, 310 at mu = 10
@pytest.mark.parametrize("mu", [2.0, 10.0])
def test_overdamped_long_flight_within_a_few_ulps_of_scale(mu):
    """Reproducer: x0 = u = a = 0, eta = 0.3, g = 1e-5 (x ~ eta (1 - c)) for rho t in (2, 4]."""
    params, coefs = make_oscillator(mu)
    worst = 0.0
    for q in np.linspace(2.0, 4.0, 101)[1:]:
        t = q / params[P_RHO]
        x, _, scale = gap(t, 0.0, 0.0, 0.0, 0.3, 1e-5, params, coefs)[:3]
        with mp.workdps(R.DPS):
            xr = reference_flight(1e-5, mu, 0.0, 0.0, 0.0, 0.3).x(mpf(t))
        worst = max(worst, float(abs(x - xr)) / (EPS * scale))
    assert worst <= 4.0, f"{worst:.1f} ulps of scale"


# --------------------------------------------------------------------------- first_contact

def found_root_tolerance(t, v, scale, a, eta, g, params):
    """A root located to the error of x there: x_tolerance / |x'| + 4 ulps of t (Newton polish
    from a point within rounding of the floor)."""
    return 2 * x_tolerance(t, a, eta, g, params, scale) / abs(v) + 4 * EPS * t


def assert_same_root(status, t, v, scale, ref, state, g, params):
    assert status == FOUND, status
    x0, u, a, eta = state
    tol = found_root_tolerance(t, v, scale, a, eta, g, params)
    assert abs(t - ref) <= tol, f"first_contact {t!r} vs reference {float(ref)!r} (tol {tol:.1e}); state {state}"


@st.composite
def dip_flights(draw):
    """A flight whose first contact is the entry into a dip of depth delta below the floor.

    Built backwards with the reference: at the dip's bottom x = -delta, x' = 0, x'' = A > 0
    (xi = A + g - 2 mu a there), the state a time T earlier is the start (rounded to doubles).
    The draw is kept only if the reference, from those doubles, finds its first root within the
    dip (before its bottom) and the dip is 64 times deeper than the rounding level of x."""
    g, mu = draw(gammas), draw(mus)
    a = draw(st.floats(-0.3, 0.3))
    A = draw(st.floats(-3.0, 0.0).map(lambda e: 10.0**e)) * (g + 0.1)
    delta = draw(st.floats(-13.0, -3.0).map(lambda e: 10.0**e))
    T = draw(st.floats(0.05, 3.0))
    with mp.workdps(R.DPS):
        xi = mpf(A) + mpf(g) - 2 * mpf(mu) * mpf(a)
        bottom = reference_flight(g, mu, -delta, 0.0, a, xi + mpf(g))
        s = mpf(-T)
        xi_s, xid_s = bottom.xi(s)
        state = tuple(float(v) for v in (bottom.x(s), bottom.xdot(s), xid_s, xi_s + mpf(g)))
        assume(state[0] > 0)
        fl = reference_flight(g, mu, *state)
        assume(-fl.x(mpf(T)) >= 64 * EPS * fl.scale(mpf(T)))
        try:
            tau = fl.first_contact()
        except R.RootSearchError:
            assume(False)
        entry = T - math.sqrt(2 * delta / A)
        assume(tau < T and abs(float(tau) - entry) < 0.5 * (T - entry) + 1e-12)
    return g, mu, state, tau, T


@settings(deadline=None, max_examples=30, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(dip_flights())
def test_never_skips_a_shallow_dip(case):
    g, mu, state, tau, T = case
    params, coefs = make_oscillator(mu)
    status, t, v, scale, *_ = first_contact(0.0, math.inf, *state, g, params, coefs)
    assert t < T, f"skipped the dip: contact at {t!r}, dip bottom at {T!r}; g={g!r} mu={mu!r} state={state}"
    assert_same_root(status, t, v, scale, tau, state, g, params)


@settings(deadline=None, max_examples=30, suppress_health_check=[HealthCheck.too_slow])
@given(gammas, mus, fractions, st.sampled_from([-1.0, 1.0]), fractions, small, small)
@example(1e-5, 2.0, 0.0, 1.0, 1e-6 / 20e-5, 0.0, 1e-5)  # a short flight of the asymptotic regime
def test_first_contact_matches_reference(g, mu, x_frac, u_sign, u_frac, a, eta):
    """The first root of eq. (F) equals the reference's (bisection with a rigorous curvature bound,
    sharing no code), to the rounding of x over |x'|; from x0 = 0 a flight must move up.
    Heights and speeds scale with g (x0 <= 100 g, |u| <= 20 g) so that flights last O(10), not
    2 u / g ~ 1e5 oscillations the reference would have to bisect through."""
    x0, u = x_frac * min(DROP.x, 100 * g), u_sign * u_frac * min(1.0, 20 * g)
    assume(x0 > 0 or u > 0)
    try:
        check_against_reference(g, mu, (x0, u, a, eta))
    except R.RootSearchError:  # a tangency below 50 digits: no float64 answer to compare
        assume(False)


def test_drop_contact_matches_reference():
    """The first impact of the paper's drop (fig. rigid-fall, psi(0) = 6, gamma = mu = 0.01)."""
    check_against_reference(0.01, 0.01, (DROP.x, DROP.xdot, DROP.xidot, DROP.eta))


def reference_root(g, mu, state):
    """The reference's first contact.  It forms x as x0 + psi'(0) t - g t^2/2 - (xi(t) - xi(0)):
    for a flight of size max(x0, |u|) << 1 (contact after t ~ that size) it cancels ~ -2 log10 of
    that many digits, which are added to its 50."""
    with mp.workdps(reference_digits(max(state[0], abs(state[1])))):
        return reference_flight(g, mu, *state).first_contact()


def reference_digits(size):
    """The reference's 50 digits plus the ~ -2 log10(size) it cancels in a flight of that size."""
    return R.DPS + max(0, math.ceil(-2 * math.log10(size)))


def check_against_reference(g, mu, state):
    params, coefs = make_oscillator(mu)
    status, t, v, scale, *_ = first_contact(0.0, math.inf, *state, g, params, coefs)
    assert_same_root(status, t, v, scale, reference_root(g, mu, state), state, g, params)


def test_horizon_before_the_contact_and_found_after_it():
    """t_limit just before the contact: HORIZON at t_limit; just after: FOUND, the same root."""
    g, mu, state = 0.01, 0.3, (0.4, 0.2, -0.1, 0.05)
    params, coefs = make_oscillator(mu)
    found = first_contact(0.0, math.inf, *state, g, params, coefs)
    assert found[0] == FOUND
    tau = found[1]
    status, t_end = first_contact(0.0, tau * (1 - 1e-9), *state, g, params, coefs)[:2]
    assert status == HORIZON and t_end == tau * (1 - 1e-9)
    again = first_contact(0.0, tau * (1 + 1e-9), *state, g, params, coefs)
    assert again[0] == FOUND and again[1] == tau
    # a later start inside the flight finds the same root
    assert first_contact(0.5 * tau, math.inf, *state, g, params, coefs)[1] == pytest.approx(tau, rel=1e-14)


@settings(deadline=None, max_examples=30, suppress_health_check=[HealthCheck.too_slow])
@given(st.one_of(st.just(0.0), st.floats(0.05, 2.5)), st.floats(1e-3, 1.0), st.floats(-0.5, 0.5),
       st.floats(-0.5, 0.5))
@example(0.0, 0.5, 0.05, 0.1)  # undamped, envelope below the level from the start: NEVER at once
@example(0.0, 0.05, 0.3, 0.1)  # undamped, envelope above: contact within a period
@example(0.5, 0.1, 0.5, 0.0)  # damped: contact in the first swing
def test_bounded_mode_never_is_proved(mu, x0, a, eta):
    """g = 0, u = -a (the gap of a sticky phase): x = level - xi(t) with level = x0 + xi(0).
    NEVER must come with a proof, evaluated on the exact state at the returned time, that |xi|
    stays below the level from then on, and with no root before it; FOUND must be the
    reference's root."""
    params, coefs = make_oscillator(mu)
    status, t, v, scale, *_ = first_contact(0.0, 1e4, x0, -a, a, eta, 0.0, params, coefs)
    assert status in (FOUND, NEVER), status
    with mp.workdps(R.DPS):
        fl = reference_flight(0.0, mu, x0, -a, a, eta)
        level = mpf(x0) + mpf(eta)
        bound = lambda s: fl.x2_bound(s)  # noqa: E731  (|x''| = |xi''| on [s, inf))
        end = mpf(t) if status == NEVER else mpf(t) * (1 + mpf(10) ** -9) + mpf(10) ** -12
        try:
            root = R.first_root(fl.x, fl.xdot, bound, mpf(0), end)
        except R.RootSearchError:
            assume(False)
        if status == NEVER:
            xi_t, xid_t = fl.xi(mpf(t))
            # |xi| from t on is bounded by the reference's closed-form bound and by the energy
            # sqrt(xi^2 + xi'^2), which never increases (d/dt = -4 mu xi'^2): either proves it
            envelope = min(R.Oscillator(mu, 1).sup_abs(xi_t, xid_t, 0), mp.sqrt(xi_t**2 + xid_t**2))
            # equality is a tangency of the gap (F = F' = 0): no detachment, F'' < 0 there (paper, after
            # eq. cond_di_distacco), so the envelope reaching the level exactly still proves NEVER
            assert envelope <= level, "NEVER without the envelope proof"
            assert root is None, f"NEVER but the reference finds a contact at {float(root)!r}"
        elif root is not None:
            assert_same_root(status, t, v, scale, root, (x0, -a, a, eta), 0.0, params)
        else:  # an exact tangency (x touches 0 without crossing): reported as a contact at the touch
            tol = x_tolerance(t, a, eta, 0.0, params, scale)
            assert abs(fl.x(mpf(t))) <= tol and abs(fl.xdot(mpf(t))) <= mp.sqrt(2 * fl.x2_bound(0) * tol)


def test_bounded_mode_needs_zero_gravity_and_matching_velocities():
    """With g > 0 or u != -a the same envelope argument is invalid: no NEVER there."""
    params, coefs = make_oscillator(0.5)
    assert first_contact(0.0, 1e4, 0.5, -0.05, 0.05, 0.1, 0.0, params, coefs)[0] == NEVER
    assert first_contact(0.0, 1e4, 0.5, -0.05, 0.05, 0.1, 1e-3, params, coefs)[0] == FOUND
    assert first_contact(0.0, 1e4, 0.5, -0.06, 0.05, 0.1, 0.0, params, coefs)[0] == FOUND


# --------------------------------------------------------------------------- liftoff_time

def assert_lifts_off(g, mu, a, eta, s):
    """x > 0 on a log grid of [1e-6 s, s] from rest on the floor, by the reference at 150 digits
    (x ~ F t^2/2 is formed from terms ~ g t^2 and xi0, which may be 1e40 times larger)."""
    with mp.workdps(150):
        fl = reference_flight(g, mu, 0.0, 0.0, a, eta)
        for r in np.geomspace(s * 1e-6, s, 40):
            assert fl.x(mpf(float(r))) > 0, f"x <= 0 at {r!r} <= s = {s!r}"


@settings(deadline=None, max_examples=25, suppress_health_check=[HealthCheck.too_slow])
@given(gammas, mus, small, st.floats(-6.0, 0.0).map(lambda e: 10.0**e))
def test_liftoff_time_is_a_certified_start(g, mu, a, lift):
    """From rest on the floor with x''(0) = F > 0 (eta chosen so that F = lift): s > 0 and x > 0 on
    a fine grid of (0, s] in mpmath.  F = 0 itself: test_liftoff_on_the_sticky_boundary."""
    eta = lift + 2 * g - 2 * mu * a  # F = -g - xi''(0) = eta - 2 g + 2 mu a
    params, coefs = make_oscillator(mu)
    _, z2, _, _ = xi_derivatives(eta - g, a, mu)
    assume(-g - z2 > 0)
    s = liftoff_time(0.0, a, eta, g, params, 0.0)
    assert s > 0
    assert_lifts_off(g, mu, a, eta, s)


@pytest.mark.parametrize("a, expect_lift", [(0.2, True), (-0.2, False), (0.0, False)])
def test_liftoff_on_the_sticky_boundary(a, expect_lift):
    """mu = 0, eta = 2 g: F = x''(0) = 0 exactly and F' = x'''(0) = a: lifts off only for a > 0."""
    g = 0.01
    params, _ = make_oscillator(0.0)
    s = liftoff_time(0.0, a, 2 * g, g, params, 0.0)
    assert (s > 0) == expect_lift
    if expect_lift:
        assert_lifts_off(g, 0.0, a, 2 * g, s)


@pytest.mark.parametrize("a", [-0.3, 0.0])  # F' = x'''(0) = -0.126 < 0, +0.066 > 0
def test_no_liftoff_when_pressed_down(a):
    """F = x''(0) = eta - 2 g + 2 mu a < 0 beyond the caller's window: the lower mass cannot leave the
    floor, liftoff_time says 0 (docstring), whatever the sign of F'."""
    g, mu, eta = 0.01, 0.3, -0.1
    params, _ = make_oscillator(mu)
    F = eta - 2 * g + 2 * mu * a
    assert F < 0
    assert (-xi_derivatives(eta - g, a, mu)[2] > 0) == (a == 0.0)  # the sign of F' = -xi'''(0)
    assert liftoff_time(0.0, a, eta, g, params, 0.0) == 0.0
    assert liftoff_time(0.0, a, eta, g, params, 0.5 * abs(F)) == 0.0


@pytest.mark.parametrize("below", [1e-15, 1e-9])
def test_liftoff_within_the_window_is_the_sticky_boundary(below):
    """F = -below < 0 inside the caller's window (F = 0 to its resolution) with F' > 0: the start of
    test_liftoff_on_the_sticky_boundary (mu = 0, a = 0.2) lifts off as F = 0 does (x > 0 on the grid of
    assert_lifts_off in mpmath; the dip F < 0 leaves lasts 3|F|/F' <= 1.5e-8, the approximation the
    window makes, below the grid's first point 2e-6); outside the window it stays.  The window is what
    separates the two (events passes the classifier's own: the rounding of F at rest, the tangential
    window at a grazing contact)."""
    g, a = 0.01, 0.2
    params, _ = make_oscillator(0.0)
    eta = 2 * g - below  # F = eta - 2 g = -below (to rounding)
    F = -g - xi_derivatives(eta - g, a, 0.0)[1]
    assert F < 0
    s = liftoff_time(0.0, a, eta, g, params, 2 * abs(F))
    assert s > 0
    assert_lifts_off(g, 0.0, a, eta, s)
    assert liftoff_time(0.0, a, eta, g, params, 0.5 * abs(F)) == 0.0


# --------------------------------------------------------------------------- the ODE's helpers

@SETTINGS
@given(mus, small, small)
def test_xi_derivatives_solve_the_ode(mu, xi, xid):
    """xi', xi'', xi''', xi'''' at t = 0 of the solution from (xi, xi'): mpmath's numerical
    derivatives of the reference closed form.  Each recurrence step multiplies magnitudes by at
    most 1 + 2 mu and adds two roundings: 4 eps (1 + 2 mu)^k (|xi| + |xi'|)."""
    got = xi_derivatives(xi, xid, mu)
    with mp.workdps(40):
        osc = R.Oscillator(mpf(mu), 1)
        ref = [mp.diff(lambda s: osc.value(mpf(xi), mpf(xid), s)[0], 0, k) for k in range(1, 5)]
    for k, (g, r) in enumerate(zip(got, ref), start=1):
        assert abs(g - r) <= 4 * EPS * (1 + 2 * mu) ** k * (abs(xi) + abs(xid)) + mpf(10) ** -30, (k, g, r)


@SETTINGS
@given(gammas, mus, small, small, st.one_of(st.floats(-8.0, 0.3).map(lambda e: 10.0**e), st.floats(2.0, 30.0)))
def test_oscillator_at_and_flight_spring(g, mu, a, eta, t):
    """oscillator_at (z, z') and flight_spring (xi + g, xi') at t from the parts of the same t
    equal the reference solution: 4 ulps of the terms, plus the parts' absolute errors beyond the
    Taylor branch times their coefficients."""
    params, coefs = make_oscillator(mu)
    omc, tms, omsd, c, S, Sd = gap(t, 0.0, 0.0, a, eta, g, params, coefs)[3:]
    xi0 = eta - g
    with mp.workdps(R.DPS):
        xi_t, xid_t = R.Oscillator(mpf(mu), 1).value(mpf(eta) - mpf(g), mpf(a), mpf(t))
    part_err = closed_form_abs_tol(params[P_RHO] * t) if params[P_RHO] * t > SERIES_Q else 2 * EPS
    z, zd = oscillator_at(xi0, a, omc, S, Sd)
    terms = abs(xi0) + abs(a)
    assert abs(z - xi_t) <= 4 * EPS * (abs(xi0) + abs(xi0 * omc) + abs(a * S)) + part_err * terms
    assert abs(zd - xid_t) <= 4 * EPS * (abs(xi0 * S) + abs(a * Sd)) + part_err * terms
    eta_t, xid_f = flight_spring(eta, a, g, omc, c, S, Sd)
    assert abs(eta_t - (xi_t + mpf(g))) <= 4 * EPS * (abs(eta * c) + abs(a * S) + g * omc) + part_err * (terms + 2 * g)
    assert abs(xid_f - xid_t) <= 4 * EPS * (abs((g - eta) * S) + abs(a * Sd)) + part_err * (terms + g)


# --------------------------------------------------------------------------- regression

def test_near_degenerate_sticky_onset_is_sticky():
    """Regression: the Newton polish of flight.first_contact once mixed S'(t+dt) with S''(t), giving
    this constructed sticky onset (alpha/gamma ~ 1e-3) a spurious contact speed."""
    g, m = 0.0007304483331670469, 0.45377904525731744
    s = [float.fromhex(h) for h in ("0x1.51d63100bea4dp-51", "-0x1.68701123bf31cp-41", "0x1.5be75c0db7936p-11",
                                    "0x1.c230147d876e1p-11")]
    tr = simulate(Parameters(g, m), Deviations(*s), max_events=1)
    assert tr.kind[0] == STICKY_START


@pytest.mark.parametrize("x", [5e-324, 1e-310, 1e-290])
@pytest.mark.parametrize("v", [0.0, 1e-170, -1e-160])
def test_safe_step_keeps_its_digits_for_subnormal_heights(x, v):
    """safe_step = the smallest positive root of x + v s - B s^2/2; 2 B x underflowed for x = 5e-324, so the step was
    0 and the power-law root finder never advanced from a subnormal height (found by the fuzz)."""
    B = 0.07641346319088663
    mp.dps = 60
    X, V, BB = mpf(x), mpf(v), mpf(B)
    exact = (V + (V * V + 2 * BB * X).sqrt()) / BB
    assert safe_step(x, v, B) > 0.0
    assert abs(safe_step(x, v, B) - exact) <= 4 * 2.0**-52 * exact

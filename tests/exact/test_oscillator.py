"""bounce.exact.oscillator: the fundamental solutions c, S, S' of xi'' + 2 mu xi' + xi = 0 (eq. eq-motion-psi-xi).

Protects the contract of :func:`bounce.exact.oscillator.fundamental` that every flight rests on:

* against an independent mpmath evaluation of the closed forms (tests/reference.py, 80 digits) for
  under-, critically and over-damped mu, mu = 0 included: the small parts 1 - c, t - S, 1 - S' to a
  few ulps *of themselves* on the Taylor branch (rho t <= SERIES_Q), all six values to a few ulps of
  O(1) beyond it;
* continuity across mu = 1 (second differences scale as d^2) and across the Taylor/closed-form
  switch rho t = SERIES_Q;
* the ODE itself (finite-difference residual of c' = -S, S'' = -S - 2 mu S', c = S' + 2 mu S), the
  Wronskian c S' + S^2 = exp(-2 mu t) and the non-increasing energy S^2 + S'^2;
* the truncation rule of the Taylor sums: the coefficient bound |z_k| <= (3k+1) rho^k / k!, the
  stated tail bound really bounding the exact tail, and the tail below 2^-55 of each sum at every
  degree's threshold.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from mpmath import mp, mpf

from bounce.analysis import reference as R
from bounce.exact.oscillator import (
    N_COEFS, P_RHO, SERIES_Q, build_oscillator, fundamental, make_oscillator, natural_frequency,
)

EPS = 2.0**-52
SETTINGS = settings(deadline=None, max_examples=60)

#: mu: zero and critical damping drawn often, under- and over-damped, stiff over-damped up to 100
mus = st.one_of(st.sampled_from([0.0, 1.0]), st.floats(0.0, 3.0), st.floats(3.0, 100.0))
#: q = rho t: log-uniform on the Taylor branch (q <= 2) half of the time, uniform beyond it otherwise
qs = st.one_of(st.floats(-12.0, math.log10(SERIES_Q)).map(lambda e: 10.0**e), st.floats(SERIES_Q, 60.0))


def branch_examples(test):
    """Each damping branch on each side of the switch, whatever hypothesis draws."""
    for mu in (0.0, 0.3, 1.0, 2.5):
        for q in (0.7, 5.0):
            test = example(mu, q)(test)
    return test


def exact_parts(mu, t, dps=80):
    """(1 - c, t - S, 1 - S', c, S, S') at the double t, from the reference's closed forms (mpmath).

    80 digits: at t = 1e-12 the small parts are ~1e-24 and still keep > 50 digits."""
    with mp.workdps(dps):
        osc = R.Oscillator(mpf(mu), 1)
        t = mpf(t)
        c, _ = osc.value(mpf(1), mpf(0), t)
        S, Sd = osc.value(mpf(0), mpf(1), t)
        return [1 - c, t - S, 1 - Sd, c, S, Sd]


def closed_form_abs_tol(q):
    """Absolute error allowed beyond the switch: exp(-mu t) and sin(w t) (sinh) see their argument
    rounded, an error eps * rho t each; t - S loses half an ulp of t.  2 eps (1 + q) bounds both."""
    return 2.0 * EPS * (1.0 + q)


@SETTINGS
@given(mus, qs)
@branch_examples
def test_fundamental_matches_mpmath(mu, q):
    """Taylor branch: the small parts to 4 ulps of themselves (their sums have no cancellation);
    closed-form branch: all six values to closed_form_abs_tol.  c, S, S' on the Taylor branch are
    1 - omc etc., one more rounding: 2 ulps of O(1) + the small part's error."""
    params, coefs = make_oscillator(mu)
    t = q / params[P_RHO]
    got = fundamental(t, params, coefs)
    ref = exact_parts(mu, t)
    if params[P_RHO] * t <= SERIES_Q:
        for name, g, r in zip(("1-c", "t-S", "1-S'"), got[:3], ref[:3]):
            assert abs(mpf(g) - r) <= 4 * EPS * abs(r), f"{name}: {g!r} vs {float(r)!r} (mu={mu!r}, t={t!r})"
        for name, g, r, small in zip(("c", "S", "S'"), got[3:], ref[3:], got[:3]):
            assert abs(mpf(g) - r) <= 2 * EPS * (abs(r) + t) + 4 * EPS * abs(small), (
                f"{name}: {g!r} vs {float(r)!r} (mu={mu!r}, t={t!r})")
    else:
        tol = closed_form_abs_tol(params[P_RHO] * t)
        for name, g, r in zip(("1-c", "t-S", "1-S'", "c", "S", "S'"), got, ref):
            assert abs(mpf(g) - r) <= tol * (1.0 + (name == "t-S") * t), (
                f"{name}: {g!r} vs {float(r)!r} (mu={mu!r}, t={t!r})")


@pytest.mark.parametrize("mu", [0.0, 1.0, 2.0, 10.0])
def test_values_at_known_points(mu):
    """t = 0: (0, 0, 0, 1, 0, 1) exactly; mu = 0 at t = pi/2: c = cos, S = sin, S' = cos."""
    params, coefs = make_oscillator(mu)
    assert tuple(fundamental(0.0, params, coefs)) == (0.0, 0.0, 0.0, 1.0, 0.0, 1.0)
    if mu == 0.0:
        for t in (0.5, math.pi / 2, 3.0, 40.0):
            omc, tms, omsd, c, S, Sd = fundamental(t, params, coefs)
            assert abs(c - math.cos(t)) <= 4 * EPS * (1 + t) and abs(S - math.sin(t)) <= 4 * EPS * (1 + t)
            assert abs(Sd - math.cos(t)) <= 4 * EPS * (1 + t)


@pytest.mark.parametrize("mu", [0.0, 0.3, 0.999, 1.0, 1.001, 2.0, 30.0])
def test_continuous_across_the_series_switch(mu):
    """Across rho t = SERIES_Q the Taylor sums hand over to the closed forms: the jump between the
    last Taylor time and the next double is within the closed form's absolute error (plus the
    change over one ulp of t, |f'| <= rho + 2 mu bounds it)."""
    params, coefs = make_oscillator(mu)
    rho = params[P_RHO]
    t0 = SERIES_Q / rho
    while rho * t0 > SERIES_Q:
        t0 = math.nextafter(t0, 0.0)
    t1 = math.nextafter(t0, math.inf)
    assert rho * t1 > SERIES_Q  # t0 on the Taylor branch, t1 on the closed form
    below, above = fundamental(t0, params, coefs), fundamental(t1, params, coefs)
    tol = closed_form_abs_tol(SERIES_Q) + 4 * EPS + (rho + 2 * mu + 1) * (t1 - t0)
    for name, b, a in zip(("1-c", "t-S", "1-S'", "c", "S", "S'"), below, above):
        assert abs(a - b) <= tol, f"{name} jumps by {a - b!r} at rho t = SERIES_Q (mu={mu!r})"


@pytest.mark.parametrize("d", [2.0**-20, 2.0**-40])
def test_accurate_next_to_critical_damping(d):
    """mu = 1 -+ d: the under-damped sin(w t)/w with w = sqrt(1 - mu^2) ~ 1e-6..1e-12 and the
    over-damped expm1 form keep full accuracy (no 1/w blow-up): same tolerances as above."""
    for mu in (1.0 - d, 1.0, 1.0 + d):
        params, coefs = make_oscillator(mu)
        for t in (1e-3, 1.5, 2.5, 7.0, 30.0):
            got, ref = fundamental(t, params, coefs), exact_parts(mu, t)
            tol = closed_form_abs_tol(params[P_RHO] * t) * (1 + t)
            for g, r in zip(got, ref):
                assert abs(mpf(g) - r) <= tol, (mu, t, g, float(r))


@SETTINGS
@given(st.floats(-8.0, math.log10(40.0)).map(lambda e: 10.0**e))
def test_continuous_in_mu_across_critical_damping(t):
    """A smooth f(mu) has second difference f(1+d) - 2 f(1) + f(1-d) = f'' d^2: it must shrink
    100-fold from d = 1e-3 to d = 1e-4 (a kink would give 10-fold, a jump none), unless it is at
    the rounding level 16 eps (1 + t)."""
    second = []
    for d in (1e-3, 1e-4):
        vals = [np.array(fundamental(t, *make_oscillator(mu))) for mu in (1.0 - d, 1.0, 1.0 + d)]
        second.append(vals[2] - 2 * vals[1] + vals[0])
    coarse, fine = second
    ok = (np.abs(fine) <= 16 * EPS * (1 + t)) | (np.abs(coarse) >= 30 * np.abs(fine))
    assert ok.all(), f"t={t!r}: second differences {coarse} (1e-3) vs {fine} (1e-4)"


@SETTINGS
@given(mus, qs)
@branch_examples
def test_ode_residual(mu, q):
    """The returned functions solve the ODE: five-point differences (h = 1e-3 / rho) give
    (1-c)' = S, (t-S)' = 1-S', S' = d S/dt and S'' = -S - 2 mu S'.  Truncation (rho h)^4 / 30 ~ 3e-14
    and rounding ~ 2 eps / (rho h) ~ 4e-13, both in units of rho (1 + 2 mu): 1e-10 of that is a
    > 100-fold margin; a wrong sign in a closed form gives O(1)."""
    params, coefs = make_oscillator(mu)
    rho = params[P_RHO]
    h = 1e-3 / rho
    t = max(q / rho, 3 * h)
    pts = [np.array(fundamental(t + k * h, params, coefs)) for k in (-2, -1, 1, 2)]
    deriv = (pts[0] - 8 * pts[1] + 8 * pts[2] - pts[3]) / (12 * h)
    omc, tms, omsd, c, S, Sd = fundamental(t, params, coefs)
    tol = 1e-10 * rho * (1 + 2 * mu)
    assert abs(deriv[0] - S) <= tol  # (1 - c)' = -c' = S
    assert abs(deriv[1] - omsd) <= tol  # (t - S)' = 1 - S'
    assert abs(deriv[4] - Sd) <= tol
    assert abs(deriv[5] - (-S - 2 * mu * Sd)) <= tol  # S'' + 2 mu S' + S = 0
    # c = S' + 2 mu S (c' = -S and the ODE), in small parts: 1 - c = (1 - S') - 2 mu S, no cancellation
    assert abs(omc - (omsd - 2 * mu * S)) <= 4 * EPS * (abs(omc) + abs(omsd) + 2 * mu * abs(S)) + 4 * EPS * (
        rho * t > SERIES_Q) * (1 + 2 * mu) * (1 + rho * t)


@SETTINGS
@given(mus, qs)
@branch_examples
def test_wronskian_and_energy(mu, q):
    """Wronskian c S' - c' S = c S' + S^2 = exp(-2 mu t) (Abel), to the absolute errors of c, S, S'
    (closed_form_abs_tol each, times the factors multiplying them); and the energy S^2 + S'^2
    (c^2 + S^2 for c) never increases: d/dt = -4 mu S'^2 <= 0; at mu = 0 both stay 1."""
    params, coefs = make_oscillator(mu)
    t = q / params[P_RHO]
    _, _, _, c, S, Sd = fundamental(t, params, coefs)
    err = closed_form_abs_tol(max(params[P_RHO] * t, SERIES_Q)) * (1 + t)
    w = c * Sd + S * S
    assert abs(w - math.exp(-2 * mu * t)) <= err * (abs(c) + abs(Sd) + 2 * abs(S)) + 4 * EPS * abs(w)
    energies = []
    for s in (t / 2, t):
        _, _, _, c_s, S_s, Sd_s = fundamental(s, params, coefs)
        energies.append((S_s * S_s + Sd_s * Sd_s, c_s * c_s + S_s * S_s))
    for later, earlier in zip(energies[1], energies[0]):
        assert later <= earlier + 6 * err
    assert all(e <= 1 + 6 * err for e in energies[0])
    if mu == 0.0:
        assert all(abs(e - 1) <= 6 * err for e in energies[1])


@settings(deadline=None, max_examples=6)
@given(mus)
@example(0.0)
@example(1.0)
@example(100.0)
def test_taylor_tail_bound(mu):
    """The rule behind the degree table coefs[3]: with exact (mpmath) Taylor coefficients,
    (i) |z_k| <= (3k+1) rho^k / k! for c and S; (ii) at each degree K and its largest allowed
    q = coefs[3, K], the exact tail of each of the three sums after t^K is below the stated bound
    2 (3K+4) q^(K+1) / (K+1)!, and (iii) below 2^-55 of the sum itself, so truncation costs less
    than an ulp.  (The float coefficients' own rounding is covered by test_fundamental_matches_mpmath.)"""
    params, coefs = build_oscillator(mu)
    rho = params[P_RHO]
    n = 80  # q <= 2: the terms after t^80 are below 2^80 / 80! ~ 1e-95, far below 2^-55 of any sum
    with mp.workdps(40):
        m, r = mpf(mu), mpf(rho)

        def series(z0, z1):
            z = [mpf(z0), mpf(z1)]
            for k in range(n):
                z.append((-2 * m * (k + 1) * z[k + 1] - z[k]) / ((k + 2) * (k + 1)))
            return z

        c, s = series(1, 0), series(0, 1)
        for k in range(n):
            bound = (3 * k + 1) * r**k / mp.factorial(k)
            assert abs(c[k]) <= bound and abs(s[k]) <= bound, k
        parts = ([-c[k] for k in range(n)], [-s[k] for k in range(n)], [-(k + 1) * s[k + 1] for k in range(n)])
        checked = 0
        for K in range(2, N_COEFS - 1):
            q = mpf(coefs[3, K])
            if q == 0:
                continue
            t = q / r
            powers = [t**k for k in range(n)]
            stated = 2 * (3 * K + 4) * q ** (K + 1) / mp.factorial(K + 1)
            for j in range(3):
                head = mp.fsum(parts[j][k] * powers[k] for k in range(1, K + 1))
                tail = mp.fsum(parts[j][k] * powers[k] for k in range(K + 1, n))
                assert abs(tail) <= stated, (mu, K, j)
                assert abs(tail) <= mpf(2) ** -55 * abs(head + tail), (mu, K, j)
            checked += 1
    assert checked >= 10 and coefs[3, N_COEFS - 1] == SERIES_Q


@pytest.mark.parametrize(
    "mu",
    # mu = 10 lost a factor ~3 mu^2 (170 ulps) before 1 - c was formed with expm1 (issue 12)
    [0.0, 0.5, 1.0, 2.0, 10.0])
def test_small_parts_beyond_the_switch_lose_at_most_a_factor_4(mu):
    """Module docstring: for q > SERIES_Q the small parts are formed by subtraction, 'which then
    loses at most a factor ~ e^q / q^2 < 4' of relative accuracy: 16 ulps of themselves (4 times
    the 4 ulps of the Taylor branch) just beyond the switch, q in (2, 4]."""
    params, coefs = make_oscillator(mu)
    rho = params[P_RHO]
    for q in np.linspace(2.0, 4.0, 21)[1:]:
        t = q / rho
        got, ref = fundamental(t, params, coefs), exact_parts(mu, t)
        for name, g, r in zip(("1-c", "t-S", "1-S'"), got[:3], ref[:3]):
            ulps = float(abs(mpf(g) - r) / abs(r)) / EPS
            assert ulps <= 16, f"{name}: relative error {ulps:.0f} ulps at q = {q:.2f}"



@settings(deadline=None, max_examples=300)
@given(st.one_of(st.floats(0.0, 1.0, exclude_max=True), st.floats(1.0, 1e8, exclude_min=True),
                 st.floats(-20.0, 0.0).map(lambda e: 10.0**e)))
@example(1e-16)  # the product (1 - mu)(1 + mu) rounded to 1 - eps here: a phase error ~eps t on long flights
@example(0.4999999999999999)
@example(0.5)
@example(7.498942093324558e-09)  # 1 - mu^2 rounds to 1 - 2^-53: 0.75 ulp, within the bound
@example(2.0**-27 * (1 - 2**-52))  # the largest mu with 1 - mu^2 rounding to 1
def test_natural_frequency_within_its_ulp_bound(mu):
    """sqrt(|1 - mu^2|) to 1.25 ulp against mpmath (the bound in its docstring); exactly 1 where 1 - mu^2
    rounds to 1 (mu < 2^-27: mu^2 below half an ulp of 1), so that a flight's phase omega t carries no
    error there.  (Between 2^-27 and ~1.05e-8, 1 - mu^2 rounds to 1 - 2^-53 and omega is 1 - 2^-53, 0.75 ulp
    from the exact value: within the bound, not correctly rounded; found when the derandomized draw moved.)"""
    w = natural_frequency(mu)
    with mp.workdps(40):
        exact = mp.sqrt(abs(1 - mpf(mu) ** 2))
    assert abs(w - exact) <= 1.25 * math.ulp(float(exact))
    if mu < 2.0**-27:
        assert w == 1.0

@pytest.mark.parametrize("mu", [-1.0, math.nan, math.inf])
def test_rejects_unphysical_damping(mu):
    with pytest.raises(ValueError, match="mu must be a finite number >= 0"):
        build_oscillator(mu)

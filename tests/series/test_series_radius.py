"""The series' radius (series.taylor.series_radius and step_radius, its one-shot form for the general
steps of a flight): the comparison equation (C) gives a radius that the Taylor coefficients respect
(Cauchy's estimate |X_k| <= Rz / r^k, |(k+1) X_{k+1}| <= Rp / r^k), never below the first majorant
radius, ~2x it at a turning point of the Hertz spring; e(s) of (C) is an upper bound of its closed
form; the closed-form guess of the root is exact for M1 = 0 and the one-shot radius is within a few
per cent of Newton's over a hypothesis sample of states."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from bounce.series.taylor import (DEGREE_LONG, L_DISC, L_GROW_A, L_GROW_B, cauchy_radius, comparison_guess,
                                 comparison_step, excursion, law_array, powers_at, series_radius, step_radius,
                                 taylor_coefficients)
from bounce.springs.power import DISC, disc_fraction

LAWS = {"hertz": (1.0, 0.5, 0.5), "a1/4_b1": (0.5, 0.25, 1.0), "linear": (1.0, 0.0, 0.0),
        "stiff_a8": (1.0, 8.0, 0.5)}  # the disc fraction d = 2/a = 0.25 < DISC (disc_fraction)
STATES = [(-0.0464, 0.0), (-0.0464, 7e-4), (0.05, -0.01), (-0.1, 0.05), (0.1, 0.0), (-0.3, 0.2), (0.02, 0.1)]


def coefficients_obey_the_radius(radius_of, rho, a, b, mu, xi0, v0):
    """r >= the first radius, and the coefficients taken at radius r within Cauchy's estimate; returns r."""
    law = law_array(rho, a, b, mu, 0.01)
    w0 = abs(xi0)
    p0, q0 = powers_at(w0, law)
    first, _, _ = cauchy_radius(w0, v0, p0, q0, 0.0, rho, mu, law)
    r, Rz, Rp = radius_of(w0, v0, p0, q0, 0.0, rho, mu, law)
    assert r >= first
    K = DEGREE_LONG
    X, P, Q = (np.empty(K + 2) for _ in range(3))
    taylor_coefficients(xi0, w0, v0, p0, q0, rho * (p0 if xi0 >= 0.0 else -p0), rho, mu, law, r, K, X, P, Q)
    # X_k in units of r: Cauchy's estimate for xi - xi0 is |X_k| <= Rz (k >= 1), for xi' - v0
    # |k X_k| <= Rp r (k >= 2); rounding of the recurrence: 1e-9
    for k in range(1, K + 1):
        assert abs(X[k]) <= Rz * (1 + 1e-9), (k, X[k], Rz)
        assert k == 1 or k * abs(X[k]) <= Rp * r * (1 + 1e-9), (k, X[k], Rp * r)
    return r


@pytest.mark.parametrize("radius_of", [series_radius, step_radius])
@pytest.mark.parametrize("name", LAWS)
@pytest.mark.parametrize("xi0, v0", STATES)
def test_coefficients_obey_the_radius(radius_of, name, xi0, v0):
    coefficients_obey_the_radius(radius_of, *LAWS[name], 0.05, xi0, v0)


@pytest.mark.parametrize("a, d", [(0.0, DISC), (0.5, DISC), (2.0, DISC), (2.0 / DISC, DISC), (4.0, 0.5), (50.0, 0.04)])
def test_disc_fraction(a, d):
    """d = min(DISC, 2/a): the laws with a <= 2/DISC (Hertz, linear) keep DISC; the law array's majorant
    factors (1 + d)^(a+1), (1 + d)^b are formed with the same d (for a = 50: 2.7 where 1.95^51 = 6e14)."""
    assert disc_fraction(a) == d
    law = law_array(1.0, a, 0.5, 0.1, 0.01)
    assert law[L_DISC] == d and law[L_GROW_A] == (1.0 + d) ** (a + 1.0) and law[L_GROW_B] == (1.0 + d) ** 0.5
    assert law_array(1.0, a, 0.5, 0.1, 0.01, disc=DISC)[L_DISC] == DISC


@settings(max_examples=300, deadline=None)
@given(st.sampled_from(sorted(LAWS)), st.floats(1e-3, 1.0), st.floats(-3.0, 0.7), st.floats(-5.0, -0.5),
       st.sampled_from([-1.0, 1.0]), st.sampled_from([-1.0, 1.0]))
def test_one_shot_radius_is_a_radius_and_near_newtons(name, mu, log_w, log_v, sign_xi, sign_v):
    """step_radius over states from 1e-3 to 5 |xi_eq| and speeds 1e-5 to 0.3: Cauchy's estimate holds at its
    radius, and for mu <= 0.1 it is within 4% of series_radius's (Newton's root of e = 0.98 Rz) or above
    it (the guess's damping factor 1/(1 + 0.3 M1/lam) costs up to ~10% at mu = 1)."""
    xi0 = sign_xi * 0.0464 * 10**log_w
    v0 = sign_v * 10**log_v
    r = coefficients_obey_the_radius(step_radius, *LAWS[name], mu, xi0, v0)
    rho, a, b = LAWS[name]
    law = law_array(rho, a, b, mu, 0.01)
    w0 = abs(xi0)
    p0, q0 = powers_at(w0, law)
    assert mu > 0.1 or r >= 0.96 * series_radius(w0, v0, p0, q0, 0.0, rho, mu, law)[0]


def test_turning_point_radius_is_twice_the_first():
    law = law_array(1.0, 0.5, 0.5, 0.01, 0.01)
    w0 = 0.0464
    p0, q0 = powers_at(w0, law)
    first = cauchy_radius(w0, 0.0, p0, q0, 0.0, 1.0, 0.01, law)[0]
    better = series_radius(w0, 0.0, p0, q0, 0.0, 1.0, 0.01, law)[0]
    assert 1.9 * first <= better <= 1.45 * w0**-0.25 * 1.5  # below the quarter period ~1.45 W^(-1/4) (with slack)


@pytest.mark.parametrize("av, A0, L", [(0.0, 0.01, 0.3), (0.02, 0.01, 0.3), (1.0, 1e-3, 5.0)])
@pytest.mark.parametrize("s", [0.1, 1.0, 3.0])
def test_excursion_bounds_its_closed_form(av, A0, L, s):
    k = math.sqrt(L)
    exact = A0 / L * (math.cosh(k * s) - 1.0) + av * math.sinh(k * s) / k  # eq. (C) with M1 = 0
    e, de = excursion(s, av, A0, L, 0.0)
    assert exact <= e <= exact * (1 + 1e-11)  # MARGIN = 1 + 1e-12 and the tail bound on top
    assert de == pytest.approx(A0 / k * math.sinh(k * s) + av * math.cosh(k * s), rel=1e-12)


@pytest.mark.parametrize("av, A0, L", [(0.0, 0.01, 0.3), (0.02, 0.01, 0.3), (1.0, 1e-3, 5.0), (0.3, 0.01, 0.4)])
@pytest.mark.parametrize("Rz", [1e-3, 0.04, 1.0])
def test_guess_is_the_closed_form_root_without_damping(av, A0, L, Rz):
    """For M1 = 0 comparison_guess solves e(s) = Rz for the closed form of (C) (to rounding); comparison_step
    then returns an s with the series' upper bound e(s) <= Rz at 0.995 of it."""
    s = comparison_guess(Rz, av, A0, L, 0.0)
    k = math.sqrt(L)
    exact = A0 / L * (math.cosh(k * s) - 1.0) + av * math.sinh(k * s) / k
    assert exact == pytest.approx(Rz, rel=1e-12)
    step, e = comparison_step(Rz, av, A0, L, 0.0)
    assert step == pytest.approx(0.995 * s, rel=1e-15)
    assert e <= Rz and e == excursion(step, av, A0, L, 0.0)[0]


@pytest.mark.parametrize("M1", [1e-3, 0.05, 0.5])
def test_one_shot_step_is_below_the_root_with_damping(M1):
    """With damping (M1 > 0) the proven s of comparison_step lies below the root of e(s) = Rz (bisection on the
    series' upper bound) and not earlier than comparison_guess's damping factor 1/(1 + 0.3 M1/lam) and the
    0.995 of comparison_step allow (lam = M1/2 + sqrt(M1^2/4 + L), the growth rate of (C))."""
    Rz, av, A0, L = 0.04, 0.01, 0.01, 0.4
    s, e = comparison_step(Rz, av, A0, L, M1)
    lo, hi = 0.0, 10.0
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if excursion(mid, av, A0, L, M1)[0] <= Rz else (lo, mid)
    lam = 0.5 * M1 + math.sqrt(0.25 * M1 * M1 + L)
    assert e <= Rz and 0.995 * lo / (1.0 + 0.3 * M1 / lam) <= s <= lo

"""The series' radius (power_series.series_radius): the comparison equation (C) gives a radius that
the Taylor coefficients respect (Cauchy's estimate |X_k| <= Rz / r^k, |(k+1) X_{k+1}| <= Rp / r^k),
never below the first majorant radius, ~2x it at a turning point of the Hertz spring, and e(s) of (C)
is an upper bound of its closed form."""

import math

import numpy as np
import pytest

from bounce.power_series import (DEGREE_LONG, cauchy_radius, excursion, law_array, powers_at, series_radius,
                                 taylor_coefficients)

LAWS = {"hertz": (1.0, 0.5, 0.5), "a1/4_b1": (0.5, 0.25, 1.0), "linear": (1.0, 0.0, 0.0)}
STATES = [(-0.0464, 0.0), (-0.0464, 7e-4), (0.05, -0.01), (-0.1, 0.05), (0.1, 0.0), (-0.3, 0.2), (0.02, 0.1)]


@pytest.mark.parametrize("name", LAWS)
@pytest.mark.parametrize("xi0, v0", STATES)
def test_coefficients_obey_the_radius(name, xi0, v0):
    rho, a, b = LAWS[name]
    mu = 0.05
    law = law_array(rho, a, b, mu, 0.01)
    w0 = abs(xi0)
    p0, q0 = powers_at(w0, law)
    first, _, _ = cauchy_radius(w0, v0, p0, q0, 0.0, rho, mu, law)
    r, Rz, Rp = series_radius(w0, v0, p0, q0, 0.0, rho, mu, law)
    assert r >= first
    K = DEGREE_LONG
    X, P, Q = (np.empty(K + 2) for _ in range(3))
    taylor_coefficients(xi0, w0, v0, p0, q0, rho * (p0 if xi0 >= 0.0 else -p0), rho, mu, law, r, K, X, P, Q)
    # X_k in units of r: Cauchy's estimate for xi - xi0 is |X_k| <= Rz (k >= 1), for xi' - v0
    # |k X_k| <= Rp r (k >= 2); rounding of the recurrence: 1e-9
    for k in range(1, K + 1):
        assert abs(X[k]) <= Rz * (1 + 1e-9), (k, X[k], Rz)
        assert k == 1 or k * abs(X[k]) <= Rp * r * (1 + 1e-9), (k, X[k], Rp * r)


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

"""Short flights from the Taylor series of x(t) at the impact (the hot path).

Late in the asymptotic regime flights are short (tau ~ 3/(mu n)) and the whole
flight is described to rounding by a low-degree polynomial.  With
z_k = xi^(k)(0) (z_{k+2} = -z_k - 2 mu z_{k+1}, xi(0) = eta - g) a flight that
starts on the floor with speed u > 0 has

    x(t)  = u t - (g + z_2) t^2/2 - sum_{k>=3} z_k t^k / k!
    xi(t) - xi(0) = sum_{k>=1} z_k t^k / k!,

the same quantities as eq. (F) of :mod:`bounce.exact.flight`, expanded in t rather than
in fundamental solutions: every term is again a state derivative times a power
of t, so nothing cancels.  The coefficients obey
|z_k/k!| <= (|xi(0)| + |a|) (3k+1) rho^k / k! (see :mod:`bounce.exact.oscillator`), so
truncating after t^K on [0, T] leaves at most
2 (|xi0| + |a|) (3K+4) q^(K+1) / (K+1)!  (q = rho T, K + 1 >= 3q); K is the
smallest degree for which (K+1) times that is below 2^-55 u T, which keeps both
x and x' within rounding of their exact values on [0, T].

Root search: the same safe march as :func:`bounce.exact.flight.first_contact` (the
curvature bound B is a property of the flight, not of its representation), on
the window [0, T] with T = 1.25 times the first safe step.  If the march would
leave the window (a long or unusual flight), the caller continues with the
closed form from the last certified time, so correctness never rests on T.
:func:`short_flight` is compiled without numba's runtime (``_nrt=False``, as the root finder of
:mod:`bounce.exact.flight`): it allocates nothing, so its call counts no references.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .flight import B_MARGIN, EPS, FOUND, derivative_bound, safe_step, xi_derivatives

#: highest degree tried before handing over to the closed form.
MAX_DEGREE = 14
INV_FACT = np.array([1.0 / math.factorial(k) for k in range(MAX_DEGREE + 3)])
INV_FACT_RATIO = np.array([1.0 / max(k, 1) for k in range(MAX_DEGREE + 3)])  # 1/k
#: status: left the series window at a certified time; continue in closed form.
HANDOVER = 4


@njit(cache=True, _nrt=False)
def short_flight(u, a, eta, g, mu, rho, d):
    """First contact of a flight starting on the floor with speed u > 0.

    ``d`` is a work array of length >= MAX_DEGREE + 2 (allocated once by the
    caller: nothing is allocated per impact).
    Returns ``(status, t, v, scale, dxi, xid)``: FOUND with the contact time t,
    x'(t), the rounding scale of x, xi(t) - xi(0) and xi'(t); or HANDOVER with t
    a time up to which x > 0 is certified (the other values unset).

    Everything comes from two Horner sums, D(t) = sum_{k>=2} d_k t^k and D'(t):
    x = u t - g t^2/2 - D, x' = u - g t - D', xi - xi0 = a t + D, xi' = a + D'.

    Fast path: one evaluation at t_p, the root of the cubic Taylor model
    u + A0 t/2 + J0 t^2/6 = 0 (A0, J0 the second and third derivatives of x at 0),
    then Newton steps dt = -x_p/v_p until tau = t_p + dt passes (ii).  Each iterate is certified by
    (i) x > 0 on (0, tau): x(s) >= u s - B s^2/2 > 0 up to 2u/B, and backwards from
    t_p, x(t_p - r) >= x_p + |v_p| r - B r^2/2 > 0 for r between its roots, which lie
    within |dt| (+ the rounding level) of tau and beyond 2|v_p|/B - 2|dt| (x_p < 0) or
    2|v_p|/B (x_p >= 0); the two ranges cover (0, tau) when
    B (t_p + 2|dt| [x_p < 0]) <= 2 (u + |v_p|); (ii) |x(tau)| <= B dt^2/2 (Taylor),
    required to be below the rounding level of x.  Otherwise the safe
    march of :func:`bounce.exact.flight.first_contact` runs on the polynomial.
    """
    xi0 = eta - g
    z1, z2, z3, _ = xi_derivatives(xi0, a, mu)
    # window from a cheap over-estimate of the first safe step (B >= g + |z2|):
    # the degree choice then does not wait for the square root in B
    T = 2.5 * u / (g + abs(z2))
    q = rho * T
    if q > 1.0:
        return HANDOVER, 0.0, 0.0, 0.0, 0.0, 0.0
    # degree: (K+1) * 2 (|xi0|+|a|) (3K+4) q^(K+1)/(K+1)! <= 2^-55 u T
    target = 2.7755575615628914e-17 * u * T / (2.0 * (abs(xi0) + abs(a)) + 1e-300)
    K = 3
    q2 = q * q
    term = q2 * q2 * INV_FACT[4]  # q^(K+1)/(K+1)!
    while (K + 1) * (3 * K + 4) * term > target:
        K += 1
        if K > MAX_DEGREE:
            return HANDOVER, 0.0, 0.0, 0.0, 0.0, 0.0
        term *= q * INV_FACT_RATIO[K + 1]
    # d_k = z_k / k! for k = 2..K+1 (K+1 for xi'(t) to degree K), stored at d[k]
    d[2] = 0.5 * z2
    d[3] = z3 * INV_FACT[3]
    zkm1, zk = z2, z3
    for k in range(4, K + 2):
        zkp1 = -zkm1 - 2.0 * mu * zk
        d[k] = zkp1 * INV_FACT[k]
        zkm1, zk = zk, zkp1
    B = (g + derivative_bound(z1, z2, z3)) * B_MARGIN
    A0 = -g - z2
    disc = 0.25 * A0 * A0 + (2.0 / 3.0) * z3 * u  # J0 = -z3
    if A0 < 0.0 and disc > 0.0:
        t = 2.0 * u / (math.sqrt(disc) - 0.5 * A0)
        for _ in range(4):  # Newton from t_p, each iterate certified as above
            if not 0.0 < t <= T:
                break
            Dn, Dpn = _horner(t, K, d)
            tt = t * t
            x = u * t - (0.5 * g + Dn) * tt
            v = u - (g + Dpn) * t
            scale = u * t + (0.5 * g + abs(Dn)) * tt
            if not v < 0.0:
                break
            dt = -x / v
            # (ii), then (i) with the backward range shortened by 2|dt| when x_p < 0
            if B * dt * dt <= 8.0 * EPS * scale:
                if B * (t - 2.0 * min(dt, 0.0)) <= 2.0 * (u - v):
                    return _finish(t, dt, u, a, g, mu, xi0, Dn, Dpn, scale)
                break
            t += dt
    # general march from the first safe step
    t = 2.0 * u / B
    if t > T:
        return HANDOVER, 0.0, 0.0, 0.0, 0.0, 0.0
    for _ in range(64):
        Dn, Dpn = _horner(t, K, d)
        tt = t * t
        x = u * t - (0.5 * g + Dn) * tt
        v = u - (g + Dpn) * t
        scale = u * t + (0.5 * g + abs(Dn)) * tt
        if x <= 4.0 * EPS * scale:
            break
        if v < 0.0:
            # one-division lower bound of the safe step: sqrt(v^2 + 2Bx) <= |v| + Bx/|v|
            s = 2.0 * x * -v / (2.0 * v * v + B * x)
        else:
            s = safe_step(x, v, B)
        if t + s > T:
            return HANDOVER, t, 0.0, 0.0, 0.0, 0.0
        if t + s == t:
            break
        t += s
    else:
        return HANDOVER, t, 0.0, 0.0, 0.0, 0.0
    if v < 0.0:
        # Newton polish, re-evaluated (near a tangency the step is not negligible)
        t -= x / v
        Dn, Dpn = _horner(t, K, d)
    return FOUND, t, u - (g + Dpn) * t, scale, (a + Dn * t) * t, a + Dpn * t


@njit(cache=True)
def _horner(t, K, d):
    """D/t^2 = d2 + d3 t + ... + d_{K+1} t^(K-1) and D'/t = 2 d2 + 3 d3 t + ..."""
    Dn = d[K + 1]
    Dpn = (K + 1) * d[K + 1]
    for k in range(K, 1, -1):
        Dn = Dn * t + d[k]
        Dpn = Dpn * t + k * d[k]
    return Dn, Dpn


@njit(cache=True)
def _finish(t, dt, u, a, g, mu, xi0, Dn, Dpn, scale):
    """The contact at t + dt (certified: B dt^2 below the rounding level), by a first-order
    update of D, D' (the neglected terms are O(dt^2), below rounding too).

    Returns what :func:`short_flight` returns: x' = u - g t - D', xi - xi0 = a t + D,
    xi' = a + D'.
    """
    D = Dn * t * t
    Dp = Dpn * t
    xidd = -(xi0 + a * t + D) - 2.0 * mu * (a + Dp)  # xi'' = -xi - 2 mu xi'
    t += dt
    D += Dp * dt  # (D)' = D'
    Dp += xidd * dt  # (D')' = xi''
    return FOUND, t, u - g * t - Dp, scale, a * t + D, a + Dp

"""Short flights from the Taylor series of x(t) at the impact (the hot path).

Late in the asymptotic regime flights are short (tau ~ 3/(mu n)) and the whole
flight is described to rounding by a low-degree polynomial.  With
z_k = xi^(k)(0) (z_{k+2} = -z_k - 2 mu z_{k+1}, xi(0) = eta - g) a flight that
starts on the floor with speed u > 0 has

    x(t)  = u t - (g + z_2) t^2/2 - sum_{k>=3} z_k t^k / k!
    xi(t) - xi(0) = sum_{k>=1} z_k t^k / k!,

the same quantities as eq. (F) of :mod:`bounce.flight`, expanded in t rather than
in fundamental solutions: every term is again a state derivative times a power
of t, so nothing cancels.  The coefficients obey
|z_k/k!| <= (|xi(0)| + |a|) (3k+1) rho^k / k! (see :mod:`bounce.oscillator`), so
truncating after t^K on [0, T] leaves at most
2 (|xi0| + |a|) (3K+4) q^(K+1) / (K+1)!  (q = rho T, K + 1 >= 3q); K is the
smallest degree for which (K+1) times that is below 2^-55 u T, which keeps both
x and x' within rounding of their exact values on [0, T].

Root search: the same safe march as :func:`bounce.flight.first_contact` (the
curvature bound B is a property of the flight, not of its representation), on
the window [0, T] with T = 1.25 times the first safe step.  If the march would
leave the window (a long or unusual flight), the caller continues with the
closed form from the last certified time, so correctness never rests on T.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .flight import B_MARGIN, EPS, FOUND, derivative_bound, safe_step

#: highest degree tried before handing over to the closed form.
MAX_DEGREE = 14
INV_FACT = np.array([1.0 / math.factorial(k) for k in range(MAX_DEGREE + 3)])
INV_FACT_RATIO = np.array([1.0 / max(k, 1) for k in range(MAX_DEGREE + 3)])  # 1/k
#: status: left the series window at a certified time; continue in closed form.
HANDOVER = 4


@njit(cache=True)
def short_flight(u, a, eta, g, mu, rho, d):
    """First contact of a flight starting on the floor with speed u > 0.

    ``d`` is a work array of length >= MAX_DEGREE + 2 (allocated once by the
    caller: nothing is allocated per impact).
    Returns ``(status, t, v, scale, dxi, xid)``: FOUND with the contact time t,
    x'(t), the rounding scale of x, xi(t) - xi(0) and xi'(t); or HANDOVER with t
    a time up to which x > 0 is certified (the other values unset).
    """
    xi0 = eta - g
    z1 = a
    z2 = -xi0 - 2.0 * mu * z1
    z3 = -z1 - 2.0 * mu * z2
    B = (g + derivative_bound(z1, z2, z3)) * B_MARGIN
    s1 = 2.0 * u / B  # first safe step from (x, v) = (0, u)
    T = 1.25 * s1
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
    # coefficients d_k = z_k / k!, k = 1..K+1 (K+1 for xi'(t) to degree K)
    d[0] = z1
    d[1] = 0.5 * z2
    d[2] = z3 * INV_FACT[3]
    zkm1, zk = z2, z3
    for k in range(4, K + 2):
        zkp1 = -zkm1 - 2.0 * mu * zk
        d[k - 1] = zkp1 * INV_FACT[k]
        zkm1, zk = zk, zkp1
    # x(t) = t * P(t),  P = u - (g/2 + d2) t - d3 t^2 - ... - dK t^(K-1)
    t = s1
    for _ in range(64):
        # Horner for P and P'
        p = -d[K - 1]
        dp = 0.0
        for k in range(K - 1, 2, -1):
            dp = dp * t + p
            p = p * t - d[k - 1]
        dp = dp * t + p
        p = p * t - (0.5 * g + d[1])
        dp = dp * t + p
        p = p * t + u
        x = t * p
        v = p + t * dp
        scale = u * t + (0.5 * g + abs(d[1])) * t * t + abs(d[2]) * t * t * t
        if x <= 4.0 * EPS * scale:
            break
        s = safe_step(x, v, B)
        if t + s > T:
            return HANDOVER, t, 0.0, 0.0, 0.0, 0.0
        if t + s == t:
            break
        t += s
    else:
        return HANDOVER, t, 0.0, 0.0, 0.0, 0.0
    if v < 0.0:
        t -= x / v  # Newton polish at the rounding level
    # xi(t) - xi0 = sum d_k t^k and xi'(t) - a = sum k d_k t^(k-1), k = 1..K+1
    dxi = d[K]
    dxid = (K + 1) * d[K]
    for k in range(K, 1, -1):
        dxi = dxi * t + d[k - 1]
        dxid = dxid * t + k * d[k - 1]
    dxi = (dxi * t + z1) * t
    dxid *= t
    v = u - g * t - dxid  # x' = psi' - xi' = (u + a - g t) - xi'
    return FOUND, t, v, scale, dxi, z1 + dxid

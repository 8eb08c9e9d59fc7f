"""Taylor series of the power-law spring along a flight, with a rigorous tail bound.

The spring obeys (paper, eq. ``eq-motion-nonlin-psi-xi``; the sticky phase of
:mod:`bounce.series.sticky` has the same form with c0 = gamma/2 and halved r, m)

    xi'' = -c0 - r xi |xi|^a - 2 m xi' |xi|^b.                            (S)

The constant part of the right side at the expansion point, f0 = c0 + r xi0 |xi0|^a,
is passed in whole: in the sticky phase it is (gamma + f(xi0))/2, which vanishes at
the equilibrium and is formed without cancellation by :func:`restoring_excess`.

Coefficients.  Around a point xi0 != 0 with sign sigma, |xi| = sigma xi is analytic
while xi keeps its sign, and with X_k = xi^(k)(t0)/k! the powers P = |xi|^(a+1),
Q = |xi|^b follow from J. C. P. Miller's recurrence for F = G^p
(G F' = p G' F, compared coefficient by coefficient):

    k G_0 F_k = sum_{j=1..k} (p j - (k - j)) G_j F_{k-j},    G_j = sigma X_j,

and (S) gives, with a Cauchy sum for the product xi' Q,

    (k+1)(k+2) X_{k+2} = -c0 [k = 0] - r sigma P_k - 2 m sum_{j=0..k} (j+1) X_{j+1} Q_{k-j}

(for k = 0 the first two terms are f0).

For a = 0 (b = 0) the power is xi itself (1) and is not formed by the recurrence:
the linear law (a = b = 0) is then analytic through xi = 0 and loses no digit to a
division by |xi0|.

Rigorous tail (Cauchy's majorant argument).  Let D be the closed polydisc
|z - xi0| <= Rz, |p - v0| <= Rp in C^2 with Rz = d |xi0|, 0 < d < 1 (so sigma z keeps a
positive real part and (S) is holomorphic in D; any Rz for a = b = 0; d = min(0.95, 2/a),
:func:`bounce.springs.power.disc_fraction`: 0.95 for Hertz).  On D the right side of (S) is bounded by M = M0 + M1 Rp with

    M0 = c0 + r ((1+d) |xi0|)^(a+1) + 2 m |v0| ((1+d) |xi0|)^b,   M1 = 2 m ((1+d) |xi0|)^b

(|w^p| = |w|^p on the principal branch).  Along every complex ray t = s e^(i phi)
the solution cannot leave D before s = r_c = min(Rz / (|v0| + Rp), Rp / M), so it
is holomorphic on |t| < r_c with |xi - xi0| <= Rz and |xi' - v0| <= Rp there; Rp is
chosen to balance the two limits.  Cauchy's estimate gives |X_k| <= Rz / r_c^k and
|(k+1) X_{k+1}| <= Rp / r_c^k, so for |h| <= theta r_c (theta < 1) the series of xi
truncated after h^K is in error by at most Rz theta^(K+1) / (1 - theta), and the
series of xi' (degree K - 1) by at most Rp theta^K / (1 - theta).  These bounds
are what :mod:`bounce.series.flight` compares with the rounding level of x and x'.

A larger r_c from a linear comparison equation (:func:`comparison_radius`; near a turning point
of the spring, v0 ~ 0, it is ~2x the r_c above for Hertz: the bound M is the force at the edge of
D, reached only late).  On the disc |z - xi0| <= Rz the restoring part of (S) is within
L |z - xi0| of its value at xi0, L = r (a+1) ((1+d) |xi0|)^a (mean value theorem on the convex
disc; L = r for a = 0), and the damping is <= M1 |p| with M1 as above, so along a ray
t = s e^(i phi), while xi stays in the disc, e(s) >= |xi - xi0| and e'(s) - |v0| >= |xi' - v0|
for the solution of

    e'' = A0 + L e + M1 e',   e(0) = 0, e'(0) = |v0|,   A0 = c0 + r |xi0|^(a+1)            (C)

(the integral inequalities of (S) have non-negative kernels; Gronwall's comparison).  So for
r_c = s with e(s) <= Rz the solution is holomorphic on |t| < r_c with |xi - xi0| <= Rz, and
|xi' - v0| <= Rp = s (A0 + L e(s) + M1 |v0|) / (1 - M1 s) (e'(s) = |v0| + int_0^s e'' with
e, e' increasing; needs M1 s < 1): the same tail bounds hold with this (r_c, Rz, Rp).
e has non-negative Taylor coefficients (no cancellation), summed with a rigorous tail.
:func:`series_radius` returns the larger of the two radii.

The coefficients themselves carry the usual relative rounding of a recurrence
(a few ulps times the degree); they are not part of the bound.

The root variable (crossings of xi = 0, :func:`root_coefficients`).  For a, b in (1/q) Z with
q in {1, 2, 4, 8} (Hertz: q = 2) write, on one side of xi = 0 with sign s, xi = s sigma^q,
sigma >= 0, and take sigma as the independent variable: with p = xi' and the time t,

    dp/dsigma = -q (r sigma^n_a / p + 2 m s sigma^n_b),   dt/dsigma = s q sigma^(q-1) / p,     (R)

n_a = q (a+2) - 1, n_b = q (b+1) - 1 (eq. ``eq-motion-nonlin-psi-xi`` times dt/dsigma): the
right sides are polynomials in sigma and analytic in p != 0, so p and t are analytic through
sigma = 0 (the non-analytic point of the time series) and their radius in sigma is set by
p -> 0 (the turning point), not by |xi0|.  Coefficients around sigma0: sigma^n in powers of
sigma - sigma0 by the binomial theorem, 1/p by the reciprocal recurrence
R_k = -(1/p_0) sum_{j=1..k} p_j R_{k-j}, then Cauchy sums with the (short) polynomials.
Rigorous tail: on the polydisc |sigma - sigma0| <= Rs, |p - p0| <= Rp = |p0|/2 the right sides
are bounded by Mp = q (r S^n_a / (|p0| - Rp) + 2 m S^n_b) and Mt = q S^(q-1) / (|p0| - Rp),
S = sigma0 + Rs (:func:`root_majorant`), so p, t are holomorphic on |sigma - sigma0| < r =
min(Rs, Rp/Mp) with |p - p0| <= Rp, |t - t0| <= Mt r there; Cauchy's estimate bounds the series
truncated after degree K on |sigma - sigma0| <= theta r by Rp theta^(K+1)/(1 - theta) (p) and
Mt r theta^(K+1)/(1 - theta) (t).  Rs is chosen to maximise r (:func:`root_radius`).
"""

from __future__ import annotations

import math
from decimal import Decimal, localcontext

import numpy as np
from numba import njit

from ..springs.power import disc_fraction  # the law's Cauchy disc fraction (its domain uses it too)

#: highest degree of a general (long-flight) step.
DEGREE_LONG = 32
#: highest degree of the hot path before it hands over to general steps.
DEGREE_SHORT = 32
#: from this degree up the a = b recurrence's Cauchy sums run in four partial sums (below, one is faster; Hertz
#: has its own kernel, :func:`_coefficients_hertz`).
DEGREE_SPLIT = 12
#: relative margin on computed bounds (covers their own rounding).
MARGIN = 1.0 + 1e-12


# layout of the law array (see law_array)
(L_RHO, L_AP1, L_B, L_MU, L_GAMMA, L_XI_EQ, L_GROW_A, L_GROW_B, L_ANALYTIC_A, L_ANALYTIC_B,
 L_EQ_RESIDUAL, L_ROOT_Q, L_DISC) = range(13)
LAW_SIZE = 13
#: degree of the series in the root variable sigma = |xi|^(1/q) across xi = 0 (:func:`root_coefficients`).
ROOT_DEGREE = 64
#: the root variable is used for a, b in (1/ROOT_Q_MAX) Z (dyadic, so q a, q b are exact in float64).
ROOT_Q_MAX = 8
#: terms of the comparison series (:func:`excursion`; ~25 where it is used).
EXCURSION_TERMS = 60
#: 1/k (INV[0] unused)
INV = np.array([0.0] + [1.0 / k for k in range(1, max(DEGREE_LONG, ROOT_DEGREE, EXCURSION_TERMS) + 3)])


def root_denominator(a: float, b: float) -> int:
    """q in (1, 2, 4, 8): the least with q a and q b integers, 0 if none (:func:`root_coefficients`)."""
    for q in (1, 2, 4, ROOT_Q_MAX):
        if float(q * a).is_integer() and float(q * b).is_integer():
            return q
    return 0


def law_array(rho: float, a: float, b: float, mu: float, gamma: float, disc: float | None = None):
    """The spring law and the flight constants as one float array for the kernels.

    Holds rho, a + 1, b, mu, gamma, xi_eq = -(gamma/rho)^(1/(a+1)) (eq.
    ``nonlin-equilibrium-xi``), the factors (1 + d)^(a+1), (1 + d)^b of the
    majorant with the disc fraction d (:func:`bounce.springs.power.disc_fraction` unless ``disc`` gives one, 0 < d < 1; also
    held), whether the restoring (a = 0) and damping (b = 0) terms are analytic, and the
    residual gamma - rho |xi_eq|^(a+1) of the rounded xi_eq (~1 ulp of gamma; 0 for the
    linear law), computed at 50 digits so that the force near equilibrium
    (:func:`restoring_excess`) is that of the double xi_eq + eta, not of a rounded origin.
    """
    xi_eq = -((gamma / rho) ** (1.0 / (a + 1.0)))
    d = disc_fraction(a) if disc is None else disc
    with localcontext() as ctx:
        ctx.prec = 50
        w = Decimal(-xi_eq)
        residual = float(Decimal(gamma) - Decimal(rho) * (Decimal(a + 1.0) * w.ln()).exp())
    return np.array([
        rho, a + 1.0, b, mu, gamma, xi_eq, (1.0 + d) ** (a + 1.0), (1.0 + d) ** b,
        1.0 if a == 0.0 else 0.0, 1.0 if b == 0.0 else 0.0, residual, float(root_denominator(a, b)), d,
    ])


@njit(cache=True)
def restoring_excess(eta, p0, law):
    """gamma + f(xi) for xi = xi_eq + eta, f(xi) = rho xi |xi|^a, without cancellation.

    It vanishes at the equilibrium (eq. ``nonlin-equilibrium-xi``).  For xi < 0, with
    e = eta/|xi_eq| and rho |xi_eq|^(a+1) = gamma - res (res: L_EQ_RESIDUAL),
    gamma + f = res - (gamma - res) expm1((a+1) log1p(-e)): a few ulps of itself.
    For xi >= 0 (p0 = |xi|^(a+1)) the two terms add.
    """
    gamma = law[L_GAMMA]
    w_eq = -law[L_XI_EQ]
    if eta >= w_eq:
        return gamma + law[L_RHO] * p0
    res = law[L_EQ_RESIDUAL]
    return res - (gamma - res) * math.expm1(law[L_AP1] * math.log1p(-eta / w_eq))


@njit(cache=True)
def bregman(eta, law):
    """V(xi_eq + eta) - V(xi_eq) + gamma eta with V = rho |xi|^(a+2)/(a+2) (eq. ``nonlin-energy``).

    The potential part of E - E_m, O(eta^2) and >= 0 (V convex, V'(xi_eq) = -gamma); summed
    as gamma |xi_eq| / (a+2) * sum_{k>=2} C(a+2, k) (-e)^k, e = eta/|xi_eq|, for |e| <= 1/4
    (no cancellation), directly otherwise.
    """
    gamma = law[L_GAMMA]
    w_eq = -law[L_XI_EQ]
    p = law[L_AP1] + 1.0
    e = eta / w_eq
    if abs(e) <= 0.25:
        term = -p * e
        g = 0.0
        for k in range(2, 200):
            term *= (p - k + 1.0) / k * -e
            g += term
            if abs(term) <= 1e-17 * abs(g) or term == 0.0:
                break
    else:
        g = abs(1.0 - e) ** p - 1.0 + p * e
    return gamma * w_eq / p * g


@njit(cache=True)
def powers_at(w0, law):
    """(|xi0|^(a+1), |xi0|^b) at |xi0| = w0 (exact for the analytic cases; Hertz by one sqrt)."""
    if law[L_ANALYTIC_A] == 1.0 and law[L_ANALYTIC_B] == 1.0:
        return w0, 1.0
    if law[L_AP1] == 1.5 and law[L_B] == 0.5:  # Hertz: one square root
        q0 = math.sqrt(w0)
        return w0 * q0, q0
    p0 = w0 if law[L_ANALYTIC_A] == 1.0 else w0 ** law[L_AP1]
    q0 = 1.0 if law[L_ANALYTIC_B] == 1.0 else w0 ** law[L_B]
    return p0, q0


@njit(cache=True)
def taylor_coefficients(xi0, w0, v0, p0, q0, f0, r, m, law, H, K, X, P, Q):
    """Fill X[0..K] with H^k xi^(k)(t0)/k! for eq. (S) from xi(t0) = xi0, xi'(t0) = v0.

    H is the time unit of the coefficients (H = r_c keeps |X_k| <= Rz: no overflow
    when the series is taken close to xi = 0, where r_c ~ |xi0| / |v0| is tiny).

    w0 = |xi0| > 0 unless the law is linear; p0, q0 from :func:`powers_at`; f0 = c0 + r xi0 |xi0|^a
    (module docstring); P, Q are work arrays (length > K) for the coefficients of |xi|^(a+1)
    and |xi|^b.
    """
    ap1 = law[L_AP1]
    b = law[L_B]
    lin_a = law[L_ANALYTIC_A] == 1.0
    lin_b = law[L_ANALYTIC_B] == 1.0
    sigma = 1.0 if xi0 >= 0.0 else -1.0
    inv_xi0 = 1.0 / xi0 if xi0 != 0.0 else 0.0  # used only when xi0 != 0 (singular laws)
    X[0] = xi0
    X[1] = v0 * H
    H2 = H * H
    if ap1 == b + 1.0 and b == 0.5:
        _coefficients_hertz(sigma, q0, f0, r, m, H, K, X, Q, P)
        return
    if ap1 == b + 1.0 and not lin_b:
        if K > DEGREE_SPLIT:
            _equal_powers_split(sigma, inv_xi0, q0, f0, r, m, b, H, K, X, Q, P)
        else:
            _equal_powers_single(sigma, inv_xi0, q0, f0, r, m, b, H, K, X, Q, P)
        return
    P[0] = sigma * p0  # sigma P_k: the coefficients of xi |xi|^a
    Q[0] = q0
    for k in range(0, K - 1):
        if k >= 1:
            if lin_a:
                P[k] = X[k]
            else:
                s = 0.0
                for j in range(1, k + 1):
                    s += (ap1 * j - (k - j)) * X[j] * P[k - j]
                P[k] = s * inv_xi0 * INV[k]  # G_j = sigma X_j, G_0 = sigma xi0, P_k = sigma F_k
            if lin_b:
                Q[k] = 0.0
            else:
                s = 0.0
                for j in range(1, k + 1):
                    s += (b * j - (k - j)) * X[j] * Q[k - j]
                Q[k] = s * inv_xi0 * INV[k]
        if lin_b:
            damp = (k + 1) * X[k + 1] * q0
        else:
            damp = 0.0
            for j in range(0, k + 1):
                damp += (j + 1) * X[j + 1] * Q[k - j]
        force = f0 if k == 0 else r * P[k]
        X[k + 2] = -(H2 * force + 2.0 * m * H * damp) * INV[k + 1] * INV[k + 2]


@njit(cache=True, inline="always")
def _convolution(A, B, lo, hi, k):
    """sum_{j=lo..hi} A[j] B[k-j] in four interleaved partial sums (the recurrences' Cauchy sums are
    latency-bound with one; same value up to the rounding of the sum's order)."""
    s0 = s1 = s2 = s3 = 0.0
    j = lo
    while j + 3 <= hi:
        s0 += A[j] * B[k - j]
        s1 += A[j + 1] * B[k - j - 1]
        s2 += A[j + 2] * B[k - j - 2]
        s3 += A[j + 3] * B[k - j - 3]
        j += 4
    while j <= hi:
        s0 += A[j] * B[k - j]
        j += 1
    return (s0 + s1) + (s2 + s3)


@njit(cache=True)
def _equal_powers_split(sigma, inv_xi0, q0, f0, r, m, b, H, K, X, Q, Y):
    """:func:`_coefficients_equal_powers` with the Cauchy sums in four partial sums (K > DEGREE_SPLIT)."""
    _coefficients_equal_powers(sigma, inv_xi0, q0, f0, r, m, b, H, K, X, Q, Y, True)


@njit(cache=True)
def _equal_powers_single(sigma, inv_xi0, q0, f0, r, m, b, H, K, X, Q, Y):
    """:func:`_coefficients_equal_powers` with one accumulator per sum: low degrees (most of the hot path), where the
    split's setup costs more than it saves (and its code alone, compiled into the same kernel, cost the
    deep regime ~8% of its instructions: a separate kernel per variant)."""
    _coefficients_equal_powers(sigma, inv_xi0, q0, f0, r, m, b, H, K, X, Q, Y, False)


@njit(cache=True, inline="always")
def _coefficients_equal_powers(sigma, inv_xi0, q0, f0, r, m, b, H, K, X, Q, Y, split):
    """:func:`taylor_coefficients` for a = b > 0 (Hertz among them): one power, one product.

    Then r xi |xi|^a + 2 m xi' |xi|^b = (r xi + 2 m xi') Q with Q = |xi|^b, so for k >= 1

        (k+1)(k+2) X_{k+2} = -(1/H) sum_{j=0..k} Y_j Q_{k-j},   Y_j = H^2 r X_j + 2 m H (j+1) X_{j+1}

    (X_k in units of H; for k = 0 the restoring part is f0, as in the general case), one
    Cauchy sum instead of a Miller recurrence for |xi|^(a+1) plus one for the damping.  For
    b = 1/2, Q_k comes from Q^2 = sigma xi, 2 Q_0 Q_k = sigma X_k - sum_{j=1..k-1} Q_j Q_{k-j}
    (a symmetric sum, half the products of Miller's: :func:`_coefficients_hertz`); otherwise from
    Miller's recurrence.  Same coefficients up to the rounding of the sums (a few ulps times the
    degree).  Y is a work array (length > K).  ``split`` (a constant of each caller): the Cauchy sums
    in four partial sums (:func:`_convolution`) or in one.
    """
    H2 = H * H
    Q[0] = q0
    for k in range(0, K - 1):
        if k >= 1:
            s = 0.0
            for j in range(1, k + 1):
                s += (b * j - (k - j)) * X[j] * Q[k - j]
            Q[k] = s * inv_xi0 * INV[k]
            Y[k] = H2 * r * X[k] + 2.0 * m * H * (k + 1) * X[k + 1]
            if split:
                acc = _convolution(Y, Q, 0, k, k)
            else:
                acc = 0.0
                for j in range(0, k + 1):
                    acc += Y[j] * Q[k - j]
        else:
            Y[0] = H2 * r * X[0] + 2.0 * m * H * X[1]
            acc = H2 * f0 + 2.0 * m * H * X[1] * q0
        X[k + 2] = -acc * INV[k + 1] * INV[k + 2]


@njit(cache=True)
def _coefficients_hertz(sigma, q0, f0, r, m, H, K, X, Q, Y):
    """:func:`_coefficients_equal_powers` for a = b = 1/2 (Hertz), its Cauchy sums folded in pairs.

    With Q^2 = sigma xi, for k >= 1 (j over 1 <= j < k - j, and the middle term j = k/2 for even k)

        2 Q_0 Q_k = sigma X_k - 2 sum_j Q_j Q_{k-j} - [Q_{k/2}^2],
        sum_{i=0..k} Y_i Q_{k-i} = Y_0 Q_k + Y_k Q_0 + sum_j (Y_j Q_{k-j} + Y_{k-j} Q_j) + [Y_{k/2} Q_{k/2}]:

    one pass over j < k/2 loads Q_j, Q_{k-j}, Y_j, Y_{k-j} once for three independent sums, ~0.7x the
    time of the two sums taken apart (K = 32: 0.47 us against 0.65 us).  The same coefficients up
    to the rounding of the sums (their order differs).
    """
    H2r = H * H * r
    mH2 = 2.0 * m * H
    Q[0] = q0
    inv_2q0 = 0.5 / q0
    Y[0] = H2r * X[0] + mH2 * X[1]
    X[2] = -(H * H * f0 + mH2 * X[1] * q0) * INV[1] * INV[2]
    for k in range(1, K - 1):
        Y[k] = H2r * X[k] + mH2 * (k + 1) * X[k + 1]
        sq = 0.0
        a0 = 0.0
        a1 = 0.0
        for j in range(1, (k + 1) // 2):
            qj = Q[j]
            qkj = Q[k - j]
            sq += qj * qkj
            a0 += Y[j] * qkj
            a1 += Y[k - j] * qj
        sq *= 2.0
        acc = a0 + a1
        if k % 2 == 0:
            mid = Q[k // 2]
            sq += mid * mid
            acc += Y[k // 2] * mid
        qk = (sigma * X[k] - sq) * inv_2q0
        Q[k] = qk
        acc += Y[0] * qk + Y[k] * q0
        X[k + 2] = -acc * INV[k + 1] * INV[k + 2]


@njit(cache=True)
def cauchy_radius(w0, v0, p0, q0, c0, r, m, law):
    """(r_c, Rz, Rp) of the majorant argument in the module docstring (its first radius: cheap).

    Within |t| < r_c: |xi(t) - xi0| <= Rz and |xi'(t) - v0| <= Rp.
    """
    av = abs(v0)
    if law[L_ANALYTIC_A] == 1.0 and law[L_ANALYTIC_B] == 1.0:
        # any Rz is valid for an entire law: the state's own scale (a larger one shrinks the steps: the tail
        # bound grows with Rz, its tolerance with the state), or at rest at xi = 0 (w0 = v0 = 0: a sticky start
        # from the spring's natural length) the equilibrium's, where 1e-300 made r_c^4 underflow to 0
        Rz = max(w0, av) + 1e-300
        if Rz < 1e-290:
            Rz = -law[L_XI_EQ]
        M0 = c0 + r * (w0 + Rz) + 2.0 * m * av
        M1 = 2.0 * m
    else:
        Rz = law[L_DISC] * w0
        M0 = c0 + r * law[L_GROW_A] * p0 + 2.0 * m * av * law[L_GROW_B] * q0
        M1 = 2.0 * m * law[L_GROW_B] * q0
    M0 *= MARGIN
    M1 *= MARGIN
    # balance Rz / (|v0| + Rp) = Rp / (M0 + M1 Rp):  Rp^2 + (|v0| - M1 Rz) Rp - M0 Rz = 0
    beta = av - M1 * Rz
    disc = math.sqrt(beta * beta + 4.0 * M0 * Rz)
    Rp = 0.5 * (disc - beta) if beta <= 0.0 else 2.0 * M0 * Rz / (disc + beta)
    M = M0 + M1 * Rp
    lim_z = Rz / (av + Rp) if av + Rp > 0.0 else math.inf
    lim_p = Rp / M if M > 0.0 else math.inf
    return min(lim_z, lim_p) / MARGIN, Rz, Rp


@njit(cache=True)
def series_radius(w0, v0, p0, q0, c0, r, m, law):
    """(r_c, Rz, Rp) as :func:`cauchy_radius`, the larger of the module docstring's two radii.

    The comparison radius (eq. (C)) is tried where the first is limited by the force (|v0| r_c <
    0.9 Rz), not by the speed (there it gains little); its root by :func:`comparison_radius`.
    """
    return _larger_radius(w0, v0, p0, q0, c0, r, m, law, False)


@njit(cache=True)
def step_radius(w0, v0, p0, q0, c0, r, m, law):
    """:func:`series_radius` with the comparison radius from :func:`comparison_step` (one evaluation of
    the series of eq. (C), ~0.1 us, where :func:`comparison_radius` takes ~0.3 us): the radius of the
    general steps of a flight, which it takes from 15% to 45% fewer steps than :func:`cauchy_radius`
    (``python benchmarks/bench_power_steps.py``)."""
    return _larger_radius(w0, v0, p0, q0, c0, r, m, law, True)


@njit(cache=True, inline="always")
def _larger_radius(w0, v0, p0, q0, c0, r, m, law, one_shot):
    """The body of :func:`series_radius` (``one_shot`` False) and :func:`step_radius` (True)."""
    radius, Rz, Rp = cauchy_radius(w0, v0, p0, q0, c0, r, m, law)
    av = abs(v0)
    if not (Rz > 0.0 and w0 > 0.0 and av * radius < 0.9 * Rz):
        return radius, Rz, Rp
    if law[L_ANALYTIC_A] == 1.0 and law[L_ANALYTIC_B] == 1.0:
        A0, L, M1 = c0 + r * w0, r, 2.0 * m
    else:  # L = r (a+1) ((1 + d) w0)^a, M1 = 2 m ((1 + d) w0)^b
        A0, L, M1 = (c0 + r * p0, law[L_AP1] * r * law[L_GROW_A] * p0 / ((1.0 + law[L_DISC]) * w0),
                     2.0 * m * law[L_GROW_B] * q0)
    A0 *= MARGIN
    L *= MARGIN
    M1 *= MARGIN
    if one_shot:
        s, e = comparison_step(Rz, av, A0, L, M1)
    else:
        s, e = comparison_radius(Rz, av, A0, L, M1)
    if s > radius and M1 * s < 0.5:
        return s, Rz, s * (A0 + L * e + M1 * av) / (1.0 - M1 * s) * MARGIN  # e'(s) - |v0| (docstring)
    return radius, Rz, Rp


@njit(cache=True)
def excursion(s, av, A0, L, M1):
    """(upper bound of e(s), e'(s) of the truncated sum) for eq. (C) of the module docstring.

    e = sum_k t_k with t_1 = av s, t_2 = (A0 + M1 av) s^2/2, t_{j+2} = (L s^2 t_j + M1 s (j+1) t_{j+1})
    / ((j+1)(j+2)) >= 0, so t_{j+2} <= rho_j max(t_j, t_{j+1}) with rho_j = (L s^2 + M1 s (j+1)) /
    ((j+1)(j+2)) decreasing in j: the terms after t_{j+1}, t_{j+2} sum to <= 2 c rho / (1 - rho),
    c = max(t_{j+1}, t_{j+2}), rho = rho_{j+1} < 1.  Summed until that tail is below 2^-60 of the sum
    (all terms >= 0: relative rounding ~ the number of terms in ulps, covered by MARGIN); inf if not
    within EXCURSION_TERMS terms.  e'(s) (for Newton's method only) omits its tail.
    """
    Ls2 = L * s * s
    M1s = M1 * s
    t0 = av * s
    t1 = 0.5 * (A0 + M1 * av) * s * s
    e = t0 + t1
    de = t0 + 2.0 * t1  # s e'(s)
    for j in range(1, EXCURSION_TERMS):
        t2 = (Ls2 * t0 + M1s * (j + 1) * t1) * (INV[j + 1] * INV[j + 2])
        e += t2
        de += (j + 2) * t2
        rho = (Ls2 + M1s * (j + 2)) * (INV[j + 2] * INV[j + 3])
        if rho < 0.5:
            tail = 2.0 * max(t1, t2) * rho / (1.0 - rho)
            if tail <= 2.0**-60 * e:
                return (e + tail) * MARGIN, de / s
        t0, t1 = t1, t2
    return math.inf, de / s


@njit(cache=True)
def comparison_radius(Rz, av, A0, L, M1):
    """(s, e(s)): the largest s found with e(s) <= Rz for eq. (C), (0, 0) if none.

    Newton's method on e(s) = 0.98 Rz from s = acosh(1 + L Rz / A0) / sqrt(L), the root for
    av = M1 = 0 (larger: e grows faster with av, M1 > 0); e is increasing and convex, so the
    iterates decrease to the root, and the first with e(s) <= Rz is taken.
    """
    s = math.acosh(1.0 + L * Rz / A0) / math.sqrt(L) if A0 > 0.0 else Rz / av
    for _ in range(12):
        e, de = excursion(s, av, A0, L, M1)
        if e <= Rz:
            return s, e
        if not (de > 0.0 and e < math.inf):
            s *= 0.5
            continue
        s += (0.98 * Rz - e) / de
        if not s > 0.0:
            break
    return 0.0, 0.0


@njit(cache=True)
def comparison_guess(Rz, av, A0, L, M1):
    """s with e(s) ~ Rz for eq. (C) in closed form: a guess, not a bound (:func:`comparison_step` checks it).

    With lam = M1/2 + sqrt(M1^2/4 + L), the growth rate of (C) (lam^2 = L + M1 lam), the equation
    e'' = A0 + lam^2 e, e(0) = 0, e'(0) = av ((C) itself for M1 = 0) has e = a (cosh(lam s) - 1) +
    b sinh(lam s), a = A0/lam^2, b = av/lam, and e(s) = Rz is the quadratic (a + b) z^2 - 2 (a + Rz) z +
    (a - b) = 0 in z = exp(lam s): z - 1 = (Rz - b + sqrt(D)) / (a + b), D = Rz (2 a + Rz) + b^2 (for
    b > Rz as 2 Rz / (sqrt(D) + b - Rz): no cancellation).  For M1 > 0 the root of (C) comes earlier:
    measured over five laws ((rho, a, b) = (1, 1/2, 1/2), (1/2, 1/4, 1), (1, 0, 0), (1, 1, 1),
    (1, 1/2, 0)), mu <= 1, |xi0|/|xi_eq| in [1e-3, 5], |v0| in [1e-5, 0.3], this s is late by <= 0.28
    M1/lam relative, hence the factor 1/(1 + 0.3 M1/lam) (the guess then early by up to ~0.3 M1/lam:
    0.3% on the drop of benchmarks/bench_power.py).
    """
    half = 0.5 * M1
    lam = half + math.sqrt(half * half + L)
    a = A0 / (lam * lam)
    b = av / lam
    root = math.sqrt(Rz * (2.0 * a + Rz) + b * b)
    zm1 = 2.0 * Rz / (root + (b - Rz)) if b > Rz else ((Rz - b) + root) / (a + b)
    return math.log1p(zm1) / (lam + 0.3 * M1)


@njit(cache=True)
def comparison_step(Rz, av, A0, L, M1):
    """(s, e(s)) with e(s) <= Rz for eq. (C), proven by :func:`excursion` (an upper bound of e), (0, 0) if
    none is found: 0.995 times :func:`comparison_guess`, then 0.9 times that.

    The one-shot counterpart of :func:`comparison_radius` (Newton's method to 2% of the root): at most
    two evaluations of the series, one where the guess is not late (all the measured cases of
    :func:`comparison_guess`).
    """
    if not (A0 > 0.0 and L > 0.0):
        return 0.0, 0.0
    s = 0.995 * comparison_guess(Rz, av, A0, L, M1)
    for _ in range(2):
        e = excursion(s, av, A0, L, M1)[0]
        if e <= Rz:
            return s, e
        s *= 0.9
    return 0.0, 0.0


@njit(cache=True)
def tail_bounds(theta, K, Rz, Rp):
    """Truncation bounds (xi after h^K, xi' after h^(K-1)) for |h| <= theta r_c."""
    tk = theta**K / (1.0 - theta) * MARGIN
    return Rz * tk * theta, Rp * tk


@njit(cache=True)
def displacement(s, H, K, X):
    """(D, D') at s for D(s) = sum_{k=2..K} X_k (s/H)^k, so that xi(s) = X0 + X1 s/H + D(s)."""
    z = s / H
    d0 = X[K]
    d1 = K * X[K]
    for k in range(K - 1, 1, -1):
        d0 = d0 * z + X[k]
        d1 = d1 * z + k * X[k]
    return d0 * z * z, d1 * z / H


@njit(cache=True)
def curvature(s, H, K, X):
    """(D'', D''') at s: xi'' and xi''' of the truncated series (K >= 3)."""
    z = s / H
    d2 = K * (K - 1) * X[K]
    d3 = K * (K - 1) * (K - 2) * X[K]
    for k in range(K - 1, 1, -1):
        d2 = d2 * z + k * (k - 1) * X[k]
    for k in range(K - 1, 2, -1):
        d3 = d3 * z + k * (k - 1) * (k - 2) * X[k]
    return d2 / (H * H), d3 / (H * H * H)


@njit(cache=True)
def root_exponents(law):
    """(q, n_a, n_b) of the series in the root variable: n_a = q (a+2) - 1, n_b = q (b+1) - 1."""
    q = law[L_ROOT_Q]
    return q, int(round(q * (law[L_AP1] + 1.0))) - 1, int(round(q * (law[L_B] + 1.0))) - 1


@njit(cache=True)
def integer_power(x, n):
    """x^n for an integer n >= 0 by repeated squaring (the root variable's exponents are integers)."""
    result = 1.0
    while n > 0:
        if n & 1:
            result *= x
        x *= x
        n >>= 1
    return result


@njit(cache=True)
def root_majorant(sig0, p0, Rs, law):
    """(r, Rp, Mt) of the majorant argument for the root-variable series (module docstring).

    On |sigma - sig0| <= Rs, |p - p0| <= Rp = |p0|/2 the right sides of (R) are bounded by
    Mp = q (rho S^n_a / (|p0| - Rp) + 2 mu S^n_b) and Mt = q S^(q-1) / (|p0| - Rp), S = sig0 + Rs;
    within |sigma - sig0| < r = min(Rs, Rp / Mp): |p - p0| <= Rp and |t - t0| <= Mt |sigma - sig0|.
    """
    q, na, nb = root_exponents(law)
    ap = abs(p0)
    Rp = 0.5 * ap
    S = sig0 + Rs
    Mp = q * (law[L_RHO] * integer_power(S, na) / (ap - Rp) + 2.0 * law[L_MU] * integer_power(S, nb)) * MARGIN
    Mt = q * integer_power(S, int(q) - 1) / (ap - Rp) * MARGIN
    return min(Rs, Rp / Mp) / MARGIN, Rp, Mt


@njit(cache=True)
def root_radius(sig0, p0, law):
    """(r, Rp, Mt) of :func:`root_majorant` with Rs balanced (Rs = Rp / Mp within 1%): the largest r.

    Bisection in log Rs from the balance of the restoring term alone at sig0 = 0,
    Rs^(n_a+1) = p0^2 / (4 q rho).
    """
    q, na, _ = root_exponents(law)
    Rs = max(sig0, (p0 * p0 / (4.0 * q * law[L_RHO])) ** (1.0 / (na + 1.0)))
    lo, hi = 0.0, math.inf
    for _ in range(200):
        r, Rp, Mt = root_majorant(sig0, p0, Rs, law)
        if r >= Rs / MARGIN:  # Rs <= Rp / Mp: Rs may grow
            lo = Rs
        else:
            hi = Rs
        if hi <= 1.01 * lo:
            break
        Rs = 1.25 * Rs if hi == math.inf else (math.sqrt(lo * hi) if lo > 0.0 else 0.8 * Rs)
    return root_majorant(sig0, p0, lo, law) if lo > 0.0 else root_majorant(sig0, p0, Rs, law)


@njit(cache=True)
def _binomial_power(n, sig0, H, S):
    """S[j] = C(n, j) sig0^(n-j) H^j, j = 0..n: sigma^n in powers of (sigma - sig0)/H (no division by sig0)."""
    S[n] = H**n
    for j in range(n - 1, -1, -1):
        S[j] = S[j + 1] * (sig0 / H) * (j + 1.0) / (n - j)


@njit(cache=True)
def root_coefficients(sig0, p0, side, law, H, K, Pc, Tc, R, S):
    """H^k p^(k)/k! in Pc and H^k t^(k)/k! in Tc (k = 0..K, t(sig0) = 0) for eq. (R) around sig0.

    ``side`` = sign of xi on this side of xi = 0; R, S are work arrays (R: length > K; S: length
    > max(n_a, n_b, q - 1) + 1, three rows).  Cost O(K^2/2) (the reciprocal 1/p).
    """
    q, na, nb = root_exponents(law)
    nt = int(q) - 1
    rho = law[L_RHO]
    mu2 = 2.0 * law[L_MU] * side
    m = S.shape[1]
    _binomial_power(na, sig0, H, S[0])
    _binomial_power(nb, sig0, H, S[1])
    _binomial_power(nt, sig0, H, S[2])
    Pc[0] = p0
    Tc[0] = 0.0
    R[0] = 1.0 / p0
    for k in range(K):
        if k >= 1:
            R[k] = -R[0] * _convolution(Pc, R, 1, k, k)
        fa = 0.0
        for j in range(0, min(k, na) + 1):
            fa += S[0, j] * R[k - j]
        ft = 0.0
        for j in range(0, min(k, nt) + 1):
            ft += S[2, j] * R[k - j]
        fb = S[1, k] if k <= nb and k < m else 0.0
        step = q * H * INV[k + 1]
        Pc[k + 1] = -step * (rho * fa + mu2 * fb)
        Tc[k + 1] = side * step * ft


@njit(cache=True)
def root_series(z, K, C):
    """sum_{k=0..K} C[k] z^k (Horner)."""
    acc = C[K]
    for k in range(K - 1, -1, -1):
        acc = acc * z + C[k]
    return acc

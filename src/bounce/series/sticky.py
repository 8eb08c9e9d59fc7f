"""The sticky phase of the power-law spring: Taylor series to detachment, or a proof that it never ends.

Equation (derived here; the paper writes its linear analogue as eqs. ``force-on-the-floor``,
``cond_di_distacco`` and ``y-eq-sticky``).  With x = psi - xi, y = psi + xi + 1 (eq.
``xi-psi``) and eq. ``eq-motion-nonlin-psi-xi``, the spring pushes the lower mass with
S = f(xi) + 2 mu xi' |xi|^b, f(xi) = rho xi |xi|^a, and the upper one with -S:

    x'' = -gamma + S + R,    y'' = -gamma - S,

R >= 0 the floor's reaction.  While the lower mass rests on the floor (x = x' = 0), x'' = 0
gives R = -F with F = S - gamma, the force of spring and gravity on the lower mass (eq.
``force-on-the-floor`` for a = b = 0, rho = 1: F = y/2 + mu y' - gamma - 1/2), and
xi = (y - 1)/2 moves by y'' / 2:

    xi'' = -(gamma + f(xi) + 2 mu xi' |xi|^b) / 2,        F = -2 (gamma + xi'')         (ST)

(for a = b = 0, rho = 1 this is eq. ``y-eq-sticky``).  (ST) is eq. (S) of
:mod:`bounce.series.taylor` with c0 = gamma/2, r = rho/2, m = mu/2; its equilibrium is the
flight's xi_eq (eq. ``nonlin-equilibrium-xi``), where F = -2 gamma.  The phase lasts while
R >= 0, i.e. F <= 0, and ends at the first F = 0 with F' > 0 (eq. ``cond_di_distacco``).
Its constant part gamma + f(xi0) vanishes at equilibrium and is formed without cancellation
(:func:`bounce.series.taylor.restoring_excess`); xi is carried as eta = xi - xi_eq and every
step is a displacement eta(s) = eta + xi' s + D(s) (Neumaier-compensated over the steps).

Detachment cannot be skipped.  On a step of length h = theta r_c (r_c the Cauchy radius) the
polynomial p(s) = gamma + D''(s) = -F/2 has |p''| <= B_p = sum_k k(k-1)(k-2)(k-3) |X_k| theta^(k-4)
/ r_c^4 and differs from the true gamma + xi'' by at most
tail_p = Rz (K+1) K theta^(K-1) / (r_c^2 (1 - theta (K+2)/K)) (Cauchy's estimate
|X_k| <= Rz, as in :mod:`bounce.series.taylor`); theta is the largest (to 2%) that keeps the tails of
xi, xi' and p below 2^-64 of their scales, solved from their powers theta^(K+1), theta^K, theta^(K-1)
as in :mod:`bounce.series.flight`.  The march steps by the smallest root of
p + p' s - B_p s^2/2 (so p stays positive between points) and stops where p is within
tail_p + noise (noise: 8 eps of its terms) of zero; a root there with p' < 0 is polished by a
Newton step on p, then by Newton steps on F formed from the state at the root
(:func:`bounce.series.flight.floor_force`, as the lift-off forms it: p carries the rounding of
its larger terms, ~1e-17 when gamma << |xi''|).  The only crossings it can miss are dips of F
above zero smaller than its own rounding.  At the start of a phase F >= 0 within the contact's
rounding window counts as F = 0 (as in :func:`bounce.exact.events._sticky_phase`): the phase then
detaches at once if F' > 0, and otherwise starts the march where p has certainly opened up
(p >= p' s - B_p s^2/2, or p >= p'' s^2/2 - B_5 s^3/6 when F' = 0 too).  A minimum of p
within that level is a tangential touch and ends the phase like a root, as in the linear
model; the flight that follows then decides with :func:`bounce.series.flight.at_rest_is_sticky`
whether the mass stays (then a new sticky_start is recorded at the same time).

Never detaching (the linear criterion generalised).  The sticky energy
E_st = xi'^2/2 + (gamma xi + V(xi))/2, V = rho |xi|^(a+2)/(a+2), does not increase
(dE_st/dt = -mu xi'^2 |xi|^b), and E_st - E_st(xi_eq) = (xi'^2 + Bg(eta))/2 with Bg the
Bregman divergence of V (:func:`bounce.series.taylor.bregman`).  So for the rest of the phase
(xi', eta) stays in the sublevel set {xi'^2 + Bg(eta) <= T}, T = xi'^2 + Bg(eta) now, where
eta <= eta_up (Bg(eta_up) = T), |xi| <= W and |xi'| <= sqrt(T); f increases, so there

    F <= f(xi_eq + eta_up) + 2 mu sqrt(T) W^b - gamma.

If this is negative the phase is proved infinite (stop reason ``sticky_forever``).  This is
the linear model's envelope criterion with the energy for the amplitude: for a = b = 0,
rho = 1 (Bg = eta^2/2, eta_up = sqrt(2 T)) it reads (sqrt(2) + 2 mu) sqrt(T) < 2 gamma,
T = xi'^2 + eta^2/2: exact for mu = 0 (sqrt(2 T) is then the amplitude of eta), otherwise a
sufficient condition that the decaying energy (T -> 0, F -> -2 gamma) eventually meets; the
envelope criterion of :mod:`bounce.exact.events` may fire earlier, the records are the same.
eta_up and the lower extent are bracketed by doubling and bisection, rounded outwards.

The non-analytic point xi = 0 (a, b not both 0) is crossed in a window as in
:mod:`bounce.series.flight`, with the motion xi'' = -gamma/2 - m2 xi' solved exactly there
(m2 = mu for b = 0, else 0): xi(T) - xi0 = v T phi1(m2 T) - (gamma/2) T^2 phi2(m2 T),
xi'(T) = v e^(-m2 T) - (gamma/2) T phi1(m2 T), phi1(x) = (1 - e^-x)/x, phi2(x) = (e^-x - 1 + x)/x^2.
Neglected: |f|/2 and (b > 0) mu |xi'| |xi|^b, at most Fn = rho W^(a+1)/2 + mu V W^b on the window
(W = 1.01 delta, V = 2 |v|); the window is taken only if Fn T <= 2^-55 |v| (the neglected change
of xi', and of xi by Fn T^2/2), xi' keeps its sign and at least half its size, and F stays
below zero on it (rho W^(a+1) + 2 mu V W^b < gamma, the damping term with W^b = 1 for b = 0);
otherwise the phase stops with SLOW_CROSSING (stop reason ``slow_crossing``: not simulated
rather than guessed).
"""

from __future__ import annotations

import math

from numba import njit

from ..exact.events import compensated_add
from ..exact.flight import EPS, FAILED, FOUND, HORIZON, NEVER, safe_step
from .flight import SLOW_CROSSING, TOL_LONG, crossing_halfwidth, floor_force
from .taylor import (
    DEGREE_LONG,
    L_ANALYTIC_A,
    L_ANALYTIC_B,
    L_AP1,
    L_B,
    L_GAMMA,
    L_MU,
    L_RHO,
    L_XI_EQ,
    MARGIN,
    bregman,
    cauchy_radius,
    curvature,
    displacement,
    powers_at,
    restoring_excess,
    tail_bounds,
    taylor_coefficients,
)

#: cap on series steps and march evaluations of one sticky phase
MAX_STEPS = 400_000
#: relative margin of the never-detach proof (covers the rounding of its bound)
PROOF_MARGIN = 1e-12


@njit(cache=True)
def _level_extent(total, direction, law):
    """eta on the side ``direction`` (+1, -1) with Bg(eta) >= total, within 2^-30 of the level."""
    c2 = 0.5 * law[L_AP1] * law[L_GAMMA] / -law[L_XI_EQ]  # Bg(eta) ~ c2 eta^2
    lo = 0.0
    hi = direction * math.sqrt(total / c2)
    for _ in range(2000):
        if bregman(hi, law) >= total:
            break
        lo = hi
        hi *= 2.0
    for _ in range(30):
        mid = 0.5 * (lo + hi)
        if bregman(mid, law) >= total:
            hi = mid
        else:
            lo = mid
    return hi


@njit(cache=True)
def never_detaches(v, eta, law):
    """True if F < 0 for the rest of a sticky phase now at (xi' = v, eta) (module docstring)."""
    total = (v * v + bregman(eta, law)) * (1.0 + PROOF_MARGIN)
    if total == 0.0:
        return True  # at the equilibrium: F = -2 gamma for ever
    xi_eq = law[L_XI_EQ]
    eta_up = _level_extent(total, 1.0, law)
    eta_dn = _level_extent(total, -1.0, law)
    W = max(abs(xi_eq + eta_up), abs(xi_eq + eta_dn))
    p_up = powers_at(abs(xi_eq + eta_up), law)[0]
    Wq = 1.0 if law[L_ANALYTIC_B] == 1.0 else W ** law[L_B]
    bound = restoring_excess(eta_up, p_up, law) + 2.0 * law[L_MU] * math.sqrt(total) * Wq
    return bound * (1.0 + PROOF_MARGIN) < 2.0 * law[L_GAMMA]


@njit(cache=True)
def _phi(x):
    """(phi1, phi2)(x) = ((1 - e^-x)/x, (e^-x - 1 + x)/x^2) for x >= 0, without cancellation."""
    if x > 0.5:
        return -math.expm1(-x) / x, (math.expm1(-x) + x) / (x * x)
    p1 = 0.0
    p2 = 0.0
    term = 1.0  # (-x)^k
    fact = 1.0  # (k+1)!
    for k in range(30):
        fact *= k + 1.0
        p1 += term / fact
        p2 += term / (fact * (k + 2.0))
        term *= -x
        if abs(term) < 1e-18:
            break
    return p1, p2


@njit(cache=True)
def _window(T, v, c, m2):
    """(xi(T) - xi0, xi'(T) - v) of xi'' = -c - m2 xi' from xi'(0) = v."""
    p1, p2 = _phi(m2 * T)
    return v * T * p1 - c * T * T * p2, v * math.expm1(-m2 * T) - c * T * p1


@njit(cache=True)
def _tail_p(theta, H, K, Rz):
    """tail_p: bound of the truncated terms of p = gamma + D'' on |s| <= theta H (module docstring)."""
    return Rz * (K + 1.0) * K * theta ** (K - 1) / (H * H * (1.0 - theta * (K + 2.0) / K)) * MARGIN


@njit(cache=True)
def _poly_bound(order, theta, H, K, X):
    """sum_{k>=order} k!/(k-order)! |X_k| theta^(k-order) / H^order: bounds the order-th
    derivative of the truncated series on |s| <= theta H."""
    acc = 0.0
    for k in range(K, order - 1, -1):
        f = 1.0
        for j in range(order):
            f *= k - j
        acc = acc * theta + f * abs(X[k])
    return acc / H**order


@njit(cache=True)
def sticky_phase(v, eta, t_limit, law, X, P, Q, dense):
    """Integrate the sticky phase from (xi' = v, eta) for at most t_limit.

    Returns ``(status, duration, xi', eta)`` at its end: FOUND (detach, eq.
    ``cond_di_distacco``; duration 0 if F = 0 and F' > 0 at the start, where F >= 0 counts as
    F = 0: the phase follows a sticky start, decided by the caller),
    NEVER (proved infinite at that time), HORIZON (still sticky at t_limit: the state there),
    SLOW_CROSSING or FAILED.  ``dense``: integrate to t_limit without the proof and the
    detach search (dense output of a phase whose end is known from the records).
    """
    gamma = law[L_GAMMA]
    rho = law[L_RHO]
    mu = law[L_MU]
    xi_eq = law[L_XI_EQ]
    singular = not (law[L_ANALYTIC_A] == 1.0 and law[L_ANALYTIC_B] == 1.0)
    K = DEGREE_LONG
    t_hi, t_lo = 0.0, 0.0
    el, vl = 0.0, 0.0
    opening = 0  # the phase starts with F = 0 to rounding: 1 F' < 0, 2 F' = 0 too
    if not dense:
        F, Fp, noise_F, noise_Fp = floor_force(v, eta, law)
        if F >= -noise_F:
            # F >= 0 at a sticky start counts as F = 0, as in bounce.exact.events._sticky_phase: an onset
            # classified within the contact's rounding window may carry F ~ |F'| delta3 > 0
            if Fp > noise_Fp:
                return FOUND, 0.0, v, eta  # F = 0, F' > 0: detach at once (eq. cond_di_distacco)
            opening = 1 if Fp < -noise_Fp else 2
    steps = 0
    while steps < MAX_STEPS:
        steps += 1
        t = t_hi + t_lo
        if not dense and opening == 0 and never_detaches(v + vl, eta + el, law):
            return NEVER, t, v + vl, eta + el
        # with the compensation term: near xi = 0 the steps move eta by less than half its ulp, so xi_eq + eta alone
        # froze at ~eps |xi_eq| outside a crossing window narrower than that (b = 1/8: 6.6e-16) and the phase stalled
        xi0 = (xi_eq + eta) + el
        w0 = abs(xi0)
        p0, q0 = powers_at(w0, law)
        if singular:
            delta = crossing_halfwidth(v, 2.0 * v * v, law)  # damping bound V = 2 |v|
            if w0 <= 0.5 * delta:
                if v == 0.0:
                    return SLOW_CROSSING, t, v, eta
                d = (delta if v > 0.0 else -delta) - xi0
                c = 0.5 * gamma
                m2 = mu if law[L_ANALYTIC_B] == 1.0 else 0.0
                T = d / v
                for _ in range(30):  # Newton on xi(T) - xi0 = d (xi'(T) kept near v below)
                    dxi, dv = _window(T, v, c, m2)
                    step = (dxi - d) / (v + dv)
                    T -= step
                    if abs(step) <= 1e-16 * T:
                        break
                dxi, dv = _window(T, v, c, m2)
                W = 1.01 * delta
                damp_w = 1.0 if law[L_ANALYTIC_B] == 1.0 else W ** law[L_B]
                Fn = 0.5 * rho * W ** law[L_AP1] + (0.0 if law[L_ANALYTIC_B] == 1.0 else mu * 2.0 * abs(v) * damp_w)
                if (not T > 0.0 or not (v + dv) * v >= 0.25 * v * v or Fn * T > 2.0**-55 * abs(v)
                        or not rho * W ** law[L_AP1] + 4.0 * mu * abs(v) * damp_w < gamma):
                    return SLOW_CROSSING, t, v, eta
                if t + T > t_limit:
                    T = t_limit - t
                    dxi, dv = _window(T, v, c, m2)
                    return HORIZON, t_limit, (v + dv) + vl, eta + (dxi + (el + vl * T))
                eta, el = compensated_add(eta, el, dxi + vl * T)
                v, vl = compensated_add(v, vl, dv)
                t_hi, t_lo = compensated_add(t_hi, t_lo, T)
                continue
        f0 = 0.5 * restoring_excess(eta, p0, law)  # (gamma + f(xi0)) / 2
        radius, Rz, Rp = cauchy_radius(w0, v, p0, q0, 0.5 * gamma, 0.5 * rho, 0.5 * mu, law)
        xidd0 = abs(f0 + mu * v * q0)  # |xi''(0)|
        theta = 0.5
        for _ in range(200):
            h = theta * radius
            tx, tv = tail_bounds(theta, K, Rz, Rp)
            tp = _tail_p(theta, radius, K, Rz)
            tol_x = TOL_LONG * (abs(eta) + abs(v) * h + 0.5 * xidd0 * h * h)
            tol_v = TOL_LONG * (abs(v) + xidd0 * h)
            tol_p = TOL_LONG * (gamma + xidd0)
            if tx <= tol_x and tv <= tol_v and tp <= tol_p:
                break
            # tx ~ theta^(K+1), tv ~ theta^K, tp ~ theta^(K-1) (their denominators only grow as theta
            # shrinks): shrink to where the failing ones meet this theta's scales (which shrink with
            # theta too, hence the loop), by at least 2% and at most 10x per pass, as series.flight does
            fit = 1.0
            if tx > tol_x:
                fit = min(fit, (tol_x / tx) ** (1.0 / (K + 1.0)))
            if tv > tol_v:
                fit = min(fit, (tol_v / tv) ** (1.0 / K))
            if tp > tol_p:
                fit = min(fit, (tol_p / tp) ** (1.0 / (K - 1.0)))
            theta *= max(min(fit, 0.98), 0.1)
        h = theta * radius
        last = t + h >= t_limit
        if last:
            h = t_limit - t
        taylor_coefficients(xi0, w0, v, p0, q0, f0, 0.5 * rho, 0.5 * mu, law, radius, K, X, P, Q)
        if not dense:
            th = h / radius
            Bp = _poly_bound(4, th, radius, K, X) * MARGIN
            tp = _tail_p(th, radius, K, Rz)
            level = tp + 8.0 * EPS * (abs(f0) + gamma + mu * abs(v) * q0)  # p at zero within it
            s = 0.0
            d2, d3 = curvature(0.0, radius, K, X)
            ps, dps = gamma + d2, d3
            if opening == 1:  # p(0) ~ 0, p'(0) > 0: p >= p' s - Bp s^2/2 > 0 on (0, p'/Bp]
                if not dps > 0.0:
                    return FAILED, t, v, eta
                s = min(dps / Bp, h)
            elif opening == 2:  # p(0) ~ p'(0) ~ 0: p >= p'' s^2/2 - B5 s^3/6 needs p'' > 0
                p2 = 24.0 * X[4] / radius**4
                B5 = _poly_bound(5, th, radius, K, X) * MARGIN
                if not p2 > 0.0:
                    return FAILED, t, v, eta
                s = min(1.5 * p2 / B5, h)
            if opening != 0:
                opening = 0
                d2, d3 = curvature(s, radius, K, X)
                ps, dps = gamma + d2, d3
            while steps < MAX_STEPS and s < h:
                steps += 1
                s_new = min(s + safe_step(max(ps, 0.0), dps, Bp), h)
                s_prev, dp_prev = s, dps
                s = s_new
                d2, d3 = curvature(s, radius, K, X)
                ps, dps = gamma + d2, d3
                found = ps <= level
                if not found and dp_prev < 0.0 <= dps:
                    sm = _minimum(s_prev, s, radius, K, X)
                    pm = gamma + curvature(sm, radius, K, X)[0]
                    if pm <= level:
                        s, found = sm, True
                if found:
                    if dps < 0.0 and ps > 0.0:
                        s -= ps / dps  # Newton polish of the root of p
                    for _ in range(4):
                        # polish on F itself, formed from the state at s as the lift-off forms it
                        # (floor_force): the series' p carries the rounding of its larger terms
                        D, Dp = displacement(s, radius, K, X)
                        v_s, eta_s = (v + Dp) + vl, eta + ((v * s + D) + (el + vl * s))
                        F, Fp, noise_F, _ = floor_force(v_s, eta_s, law)
                        if abs(F) <= noise_F or not Fp > 0.0:
                            break
                        s -= F / Fp
                    else:  # the state recorded is the one at the time recorded
                        D, Dp = displacement(s, radius, K, X)
                        v_s, eta_s = (v + Dp) + vl, eta + ((v * s + D) + (el + vl * s))
                    t_hi, t_lo = compensated_add(t_hi, t_lo, s)
                    return FOUND, t_hi + t_lo, v_s, eta_s
            if s < h:
                return FAILED, t, v, eta  # evaluation cap
        D, Dp = displacement(h, radius, K, X)
        if last:
            return HORIZON, t_limit, (v + Dp) + vl, eta + ((v * h + D) + (el + vl * h))
        eta, el = compensated_add(eta, el, (v * h + D) + vl * h)
        v, vl = compensated_add(v, vl, Dp)
        t_hi, t_lo = compensated_add(t_hi, t_lo, h)
    return FAILED, t_hi + t_lo, v, eta


@njit(cache=True)
def _minimum(s0, s1, H, K, X):
    """The minimum of p = gamma + D'' between s0 (p' < 0) and s1 (p' >= 0): bisection on p'."""
    lo, hi = s0, s1
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if curvature(mid, H, K, X)[1] < 0.0:
            lo = mid
        else:
            hi = mid
        if hi - lo <= 4.0 * EPS * hi:
            break
    return 0.5 * (lo + hi)

"""Free flight in closed form and the first-contact root finder.

Variables (all dimensionless, paper section 2).  A flight starts at a state

    x0 >= 0   height of the lower mass,
    u         its velocity  xdot,
    a         xi' = (ydot - xdot)/2, the spring's velocity,
    eta       xi + gamma = (y - y_eq - x)/2, the spring's deviation from its
              equilibrium value -gamma (y_eq = 1 - 2 gamma),

and, with psi'' = -g and xi'' + 2 mu xi' + xi = 0 (eq. ``eq-motion-psi-xi``), the
height of the lower mass is, *as a displacement from the start state*,

    x(t) = x0 + u t + a (t - S) - g (t^2/2 + 1 - c) + eta (1 - c)          (F)

where c, S are the oscillator's fundamental solutions (:mod:`bounce.exact.oscillator`).
Each term is a state variable times a function evaluated without cancellation,
so x(t) carries an absolute error of a few ulps of ``scale`` (the sum of the
terms' magnitudes) even when x ~ 1e-17 late in the asymptotic regime, where
forming x = psi - xi from O(gamma) values would keep no digit at all.
With g = gamma this is the flight; with g = 0 and u = -a the same formula is the
gap 2 gamma - G of the sticky phase (see :mod:`bounce.exact.events`).

First root without skipping (:func:`first_contact`)
----------------------------------------------------
x'' = -g - xi''.  xi'' solves the same damped equation as xi, and for any
solution z of z'' + 2 mu z' + z = 0 the quantity z^2 + z'^2 never increases
(d/dt = -4 mu z'^2 <= 0).  Hence for every t >= 0 of the flight

    |xi''(t)| <= M2 = min( sqrt(xi''(0)^2 + xi'(0)^2), sqrt(xi''(0)^2 + xi'''(0)^2) )

and x'' >= -B with B = g + M2.  From any point t_k with x_k = x(t_k) > 0 and
v_k = x'(t_k), Taylor's theorem gives x(t_k + s) >= x_k + v_k s - B s^2/2, whose
smallest positive root s_k is therefore a step that cannot cross the floor.
Marching t_{k+1} = t_k + s_k never passes the first root; near a transversal
root the bound is a parabola tangent to x, so the march converges quadratically
(two or three evaluations per impact in the asymptotic regime).  Where |x''| is
far below B (near sticky onsets, chattering) the global bound would crawl, so
each step also tries the local bound x'' >= x''(t_k) - M3 h on a window
[t_k, t_k + h] (M3 bounds |xi'''| as M2 bounds |xi''|), h doubling from the
last step, and takes the larger of the two certified steps (:func:`certified_step`; the
gas engine takes the first step from a pair's origin as a lower bound of the pair's contact
time, :mod:`bounce.gas.dimer`).  When a step passes a
local minimum of x (x' turns from negative to non-negative), the minimum is located
and, if it lies within rounding of the floor, reported as a (tangential) contact.  It stops when
x is within rounding of zero (|x| <= 4 eps scale) and a last Newton step
polishes the root.  The only roots that can be missed are dips of x below the
floor shallower than its rounding error, which no float64 computation can see.

:func:`gap`, :func:`_minimum` and :func:`first_contact` take arrays (the oscillator) but allocate and
keep none: they are compiled without numba's runtime (``_nrt=False``), so a call does not count
references to its arrays (atomic operations that cost as much as an evaluation of the gap).
"""

from __future__ import annotations

import math

from numba import njit

from .oscillator import P_MU, fundamental

EPS = 2.220446049250313e-16
#: relative safety margin on the curvature bound (covers rounding of B itself).
B_MARGIN = 1.0 + 1e-12
#: cap on safe steps per flight besides those paid for by progress (a crawl towards a tangency
#: needs ~1e3).
MAX_STEPS = 200_000
#: steps allowed per unit of flight time on top of MAX_STEPS: a long flight of an oscillating
#: spring needs a few steps per period 2 pi (gamma = 1e-12: ~1e6 periods per flight), so the cap
#: grows with the progress made; only a march that stalls runs out of it.
STEPS_PER_TIME = 8.0
#: steps after which the curvature bounds are refreshed at every step (long marches only)
REFRESH_AFTER = 64

# statuses of first_contact
FOUND, HORIZON, NEVER, FAILED = 0, 1, 2, 3


@njit(cache=True)
def xi_derivatives(xi, xid, mu):
    """xi', xi'', xi''', xi'''' from xi and xi' by xi'' = -xi - 2 mu xi' (eq. eq-motion-psi-xi)."""
    z2 = -xi - 2.0 * mu * xid
    z3 = -xid - 2.0 * mu * z2
    z4 = -z2 - 2.0 * mu * z3
    return xid, z2, z3, z4


@njit(cache=True)
def flight_spring(eta, a, g, omc, c, S, Sd):
    """(eta(t), xi'(t)) of a flight from (a = xi', eta = xi + g) by the oscillator parts at t.

    eta(t) = eta c + a S + g (1 - c): for long flights (1 - c = O(1)) this keeps the
    digits that eta + (xi(t) - xi(0)) would cancel.
    """
    return eta * c + a * S + g * omc, (g - eta) * S + a * Sd


@njit(cache=True)
def oscillator_at(z0, zd0, omc, S, Sd):
    """(z(t), z'(t)) of the unit oscillator from (z0, z0') by its parts at t (z0 c = z0 - z0 (1 - c))."""
    return z0 - z0 * omc + zd0 * S, -z0 * S + zd0 * Sd


@njit(cache=True)
def derivative_bound(zkm1, zk, zkp1):
    """Bound on |z^(k)(t)| for all t >= 0 from the non-increasing energies."""
    return math.sqrt(zk * zk + min(zkm1 * zkm1, zkp1 * zkp1))


@njit(cache=True, inline="always")
def flight_at(t, x0, u, a, eta, g, omc, tms, omsd, S):
    """x(t), x'(t) and the rounding scale of x (eq. (F)) from the oscillator parts at t."""
    x = x0 + u * t + a * tms - g * (0.5 * t * t + omc) + eta * omc
    v = u + a * omsd - g * (t + S) + eta * S
    scale = x0 + abs(u) * t + abs(a * tms) + g * (0.5 * t * t + abs(omc)) + abs(eta * omc)
    return x, v, scale


@njit(cache=True, _nrt=False)
def gap(t, x0, u, a, eta, g, params, coefs):
    """x(t), x'(t), the rounding scale of x, and the oscillator parts at t (eq. (F))."""
    omc, tms, omsd, c, S, Sd = fundamental(t, params, coefs)
    x, v, scale = flight_at(t, x0, u, a, eta, g, omc, tms, omsd, S)
    return x, v, scale, omc, tms, omsd, c, S, Sd


@njit(cache=True)
def safe_step(x, v, B):
    """Smallest positive root of x + v s - B s^2 / 2 (inf if there is none)."""
    if B > 0.0:
        if x < 1e-280:
            # 2 B x underflows (x = 5e-324 gave disc = 0, a zero step, and a root finder that never
            # advanced: found by the power-law fuzz); sqrt(2 B) sqrt(x) keeps its digits
            disc = math.hypot(v, math.sqrt(2.0 * B) * math.sqrt(x))
        else:
            disc = math.sqrt(v * v + 2.0 * B * x)
        if v < 0.0:
            return 2.0 * x / (disc - v)
        return (v + disc) / B
    if v < 0.0:
        return x / (-v)
    return math.inf


@njit(cache=True, inline="always")
def curvature_bounds(xi0, a, g, mu):
    """(xi''(0), B, M3) of a flight from (xi0, a = xi'(0)): |x''| <= B and |xi'''| <= M3 for every t >= 0
    (the energy bounds of the module docstring, with their margin B_MARGIN)."""
    z1, z2, z3, z4 = xi_derivatives(xi0, a, mu)
    return z2, (g + derivative_bound(z1, z2, z3)) * B_MARGIN, derivative_bound(z2, z3, z4) * B_MARGIN


@njit(cache=True, inline="always")
def certified_step(x, v, A, B, M3, s):
    """The march's step from a point with x > 0 (or x = 0 and x' > 0), x' = v, x'' = A, after a step s (0 at the
    start): the larger of the safe steps of the global bound (x'' >= -B) and of the local one on a window h
    (x'' >= A - M3 h), h twice the last step, the Newton distance x/|v| or the global step.  x has no root
    within the step (after its start)."""
    # window of the local bound: twice the last step or the Newton distance
    h = 2.0 * max(s, x / -v if v < 0.0 else 0.0)
    s = safe_step(x, v, B)
    # local bound on [t, t + h]: tighter where |x''| << B
    h = max(h, 2.0 * s)
    if h < math.inf:  # the Newton distance x/|v| of a tiny speed may overflow: global bound only
        s = max(s, min(safe_step(x, v, max(0.0, M3 * h - A) * B_MARGIN), h))
    return s


@njit(cache=True)
def _envelope_below(level, x, v):
    """Bounded mode: xi(t) = level - x, xi'(t) = -v; True if sqrt(xi^2 + xi'^2) <= level,
    so xi (whose envelope never grows) can never come back up to ``level`` except
    tangentially (xi' = 0 there: not a crossing).  An envelope within 8 ulps above
    the level counts as equal: the crossing it would allow lies below the rounding
    of x (approximation at the rounding level, as for tangential contacts)."""
    xi_t = level - x
    return math.sqrt(xi_t * xi_t + v * v) <= level * (1.0 + 8.0 * EPS)


@njit(cache=True, _nrt=False)
def _minimum(t0, v0, A0, t1, x0, u, a, eta, g, mu, xi0, params, coefs):
    """Time of the minimum of x between t0 (x' = v0 < 0, x'' = A0) and t1 (x' >= 0): Newton on x',
    kept inside the bracket (bisection when a step would leave it)."""
    lo, hi = t0, t1
    t = t0 - v0 / A0 if A0 > 0.0 else 0.5 * (t0 + t1)
    for _ in range(40):
        if not lo < t < hi:
            t = 0.5 * (lo + hi)
        _, v, _, omc, tms, omsd, c, S, Sd = gap(t, x0, u, a, eta, g, params, coefs)
        if v < 0.0:
            lo = t
        else:
            hi = t
        xi_t, xid_t = oscillator_at(xi0, a, omc, S, Sd)
        A = -g - xi_derivatives(xi_t, xid_t, mu)[1]  # x'' = -g - xi''
        step = -v / A if A > 0.0 else 0.0
        if step == 0.0 or abs(step) <= 4.0 * EPS * t:
            break
        t += step
    return t


@njit(cache=True, _nrt=False)
def first_contact(t_start, t_limit, x0, u, a, eta, g, params, coefs):
    """First t in (t_start, t_limit] with x(t) = 0, for the flight of eq. (F).

    Requires x > 0 on (0, t_start] (t_start = 0 needs x0 > 0 or u > 0).
    Returns ``(status, t, v, scale, omc, tms, omsd, c, S, Sd, x)``: x'(t), the
    rounding scale of x, the oscillator parts at t and x(t) itself (at FOUND the
    residual of the rounded root: the exact root is t - x/v).  Status FOUND: the
    polished root (one Newton step from the last certified point, everything
    re-evaluated there); HORIZON: no contact before t_limit;
    NEVER: contact proved impossible (bounded mode g = 0, u + a = 0: the
    oscillator's amplitude envelope dropped below the level xi must return to);
    FAILED: the step budget MAX_STEPS + STEPS_PER_TIME (t - t_start) exhausted.
    """
    mu = params[P_MU]
    xi0 = eta - g
    z2, B, M3 = curvature_bounds(xi0, a, g, mu)
    bounded = g == 0.0 and u + a == 0.0
    level = x0 + eta  # bounded mode: contact needs xi(t) = x0 + xi(0)
    t = t_start
    if t == 0.0:
        x, v, scale = x0, u, x0
        omc, tms, omsd, c, S, Sd = 0.0, 0.0, 0.0, 1.0, 0.0, 1.0
    else:
        x, v, scale, omc, tms, omsd, c, S, Sd = gap(t, x0, u, a, eta, g, params, coefs)
        if x <= 4.0 * EPS * scale:
            # a lift-off whose gap is still within rounding of the floor: the contact is here
            return FOUND, t, v, scale, omc, tms, omsd, c, S, Sd, x
        xi_t, xid_t = oscillator_at(xi0, a, omc, S, Sd)
        z1, z2, z3, z4 = xi_derivatives(xi_t, xid_t, mu)  # for x''(t_start) below
    s = 0.0
    it = -1
    while True:
        it += 1
        if not it < MAX_STEPS + STEPS_PER_TIME * (t - t_start):  # also stops a NaN march
            return FAILED, t, v, scale, omc, tms, omsd, c, S, Sd, x
        if bounded and _envelope_below(level, x, v):
            return NEVER, t, v, scale, omc, tms, omsd, c, S, Sd, x
        A = -g - z2  # x''(t)
        s = certified_step(x, v, A, B, M3, s)
        if t + s > t_limit:
            return HORIZON, t_limit, v, scale, omc, tms, omsd, c, S, Sd, x
        t_new = t + s
        if t_new == t:
            break
        t_prev, v_prev, A_prev = t, v, A
        t = t_new
        x, v, scale, omc, tms, omsd, c, S, Sd = gap(t, x0, u, a, eta, g, params, coefs)
        if x <= 4.0 * EPS * scale:
            break
        if v_prev < 0.0 <= v:
            # stepped over a local minimum of x: if it lies within rounding of the floor it is a
            # tangential contact (grazing or sticky onset), indistinguishable from a true one
            tm = _minimum(t_prev, v_prev, A_prev, t, x0, u, a, eta, g, mu, xi0, params, coefs)
            xm, vm, sm, omc_m, tms_m, omsd_m, c_m, S_m, Sd_m = gap(tm, x0, u, a, eta, g, params, coefs)
            if xm <= 4.0 * EPS * sm:
                return FOUND, tm, vm, sm, omc_m, tms_m, omsd_m, c_m, S_m, Sd_m, xm
        xi_t, xid_t = oscillator_at(xi0, a, omc, S, Sd)
        z1, z2, z3, z4 = xi_derivatives(xi_t, xid_t, mu)
        if it < REFRESH_AFTER:
            continue
        # a long march: the energy bounds hold from any time on, so refresh them at t (a stiff
        # oscillator's fast mode dominates the bounds of t = 0 but is gone soon after)
        B = min(B, (g + derivative_bound(z1, z2, z3)) * B_MARGIN)
        M3 = min(M3, derivative_bound(z2, z3, z4) * B_MARGIN)
    if v < 0.0:
        # Newton polish (x is at the rounding level); re-evaluated at the polished time, since
        # near a tangency the step is not negligible (a first-order update would bias x'); a step below
        # half an ulp of t leaves t, and so every value at it, as it is (no evaluation)
        t_polished = t - x / v
        if t_polished != t:
            t = t_polished
            x, v, scale, omc, tms, omsd, c, S, Sd = gap(t, x0, u, a, eta, g, params, coefs)
    return FOUND, t, v, scale, omc, tms, omsd, c, S, Sd, x


@njit(cache=True)
def liftoff_time(u, a, eta, g, params, f_window):
    """A time s > 0 with x > 0 on (0, s] for a flight starting on the floor at rest.

    With x0 = u = 0, x(s) >= s^2 (F/2 + F' s/6 - M4 s^2/24) where F = x''(0),
    F' = x'''(0) and M4 bounds |x''''| = |xi''''| (energy argument).  Returns half
    the positive root of the bracket, or 0 if neither F > 0 nor (F = 0, F' > 0).

    ``f_window`` >= 0: how well the caller's classification of the start resolves F (the
    rounding of F at a start at rest, the tangential window at a grazing contact; inf at a
    detach, where F = 0 to the root finder's accuracy): F in [-f_window, 0] is F = 0 on the
    sticky boundary (approximation at that level), F < -f_window is pressed onto the floor
    (returns 0, whatever F').
    """
    mu = params[P_MU]
    _, z2, z3, z4 = xi_derivatives(eta - g, a, mu)
    F = -g - z2
    Fp = -z3
    z5 = xi_derivatives(z2, z3, mu)[2]  # xi'' solves the same equation: (xi''', xi'''', xi^(5), ...)
    M4 = derivative_bound(z3, z4, z5) * B_MARGIN
    if F < -f_window:
        return 0.0
    F = max(F, 0.0)
    if F == 0.0 and Fp <= 0.0:
        return 0.0
    if M4 == 0.0:
        return 1.0
    q = M4 / 24.0
    p = Fp / 6.0
    root = (p + math.sqrt(p * p + 4.0 * q * 0.5 * F)) / (2.0 * q)
    return 0.5 * root

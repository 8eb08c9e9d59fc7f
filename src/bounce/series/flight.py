"""Flights of the power-law spring and the first-contact root finder that cannot skip an impact.

Variables as in :mod:`bounce.exact.flight`: x >= 0 the height of the lower mass, u = x',
v = xi', and eta = xi - xi_eq, the deviation from the static equilibrium
xi_eq = -(gamma/rho)^(1/(a+1)) (eq. ``nonlin-equilibrium-xi``), so that states
~1e-13 from equilibrium keep their digits.  With psi'' = -gamma and the spring of
eq. ``eq-motion-nonlin-psi-xi``, a flight is computed in *steps*; over a step of
length h from (x, u, v, eta) with the Taylor coefficients X_k of xi
(:mod:`bounce.series.taylor`), D(s) = sum_{k>=2} X_k s^k and, for 0 <= s <= h,

    x(s) = x + u s - gamma s^2/2 - D(s),   x'(s) = u - gamma s - D'(s),
    eta(s) = eta + v s + D(s),             xi'(s) = v + D'(s)                (P)

(x = psi - xi as a displacement from the step's start: nothing of size xi_eq is
ever subtracted).  The degree and the step are chosen so that the rigorous tail
bound of the series is below 2^-64 (hot path: 2^-55) of the rounding scale of x (x + |u| s +
gamma s^2/2) and of x' (|u| + gamma s), and of xi (|xi0| + |v| s + |xi''(0)| s^2/2)
and xi' (|v| + |xi''(0)| s) where those are smaller: the polynomial is then the
flight to rounding (a tolerance relative to x alone would let a systematic
truncation error of the spring build up over the steps of a long flight).  The radius is
:func:`bounce.series.taylor.step_radius` (the comparison radius of eq. (C) of
:mod:`bounce.series.taylor` where the force, not the speed, limits the first one: 20% fewer steps
on the long flights of the Hertz drop, 40% on its flights ~300..1000) and the degree DEGREE_LONG = 32
(measured there: 26 costs 15% more time per flight, 40 the same as 32).  The step's change of eta,
v h + D(h), carries v h exactly (its rounding error by Dekker's product into the compensation term).

No impact is skipped (:func:`first_contact`).  In flight the spring energy
E_s = xi'^2/2 + rho |xi|^(a+2)/(a+2) does not increase (d/dt E_s = -2 mu xi'^2 |xi|^b),
so from any time on |xi| <= W = ((a+2) E_s / rho)^(1/(a+2)), |xi'| <= V = sqrt(2 E_s) and

    |x''| = |gamma + xi''| <= B = gamma + rho W^(a+1) + 2 mu V W^b.

From a point with x > 0, x' = w, Taylor's theorem gives x(s) >= x + w s - B s^2/2,
whose smallest positive root is a step that cannot cross the floor (as in
:func:`bounce.exact.flight.first_contact`); B is refreshed at every series step.  The
march evaluates (P) within rounding, so the only roots it can miss are dips of x
below the floor shallower than its rounding error, which no float64 computation
sees.  A step that passes a minimum of x (x' turns from negative to
non-negative) locates it, and a minimum within rounding of the floor is a
tangential contact.  At the root (|x| <= 4 eps scale) one Newton step polishes it.

The non-analytic point xi = 0 (a, b not both 0).  The series around xi0 has
radius <= |xi0| / |xi'|-ish, so steps shrink geometrically towards xi = 0; once
|xi| <= delta/2 with

    delta = min( (2^-57 v^2 / (rho 1.01^(a+1)))^(1/(a+2)),  (2^-58 v^2 / (mu V 1.01^b))^(1/(b+1)) ),

the crossing is one *window*: from |xi| <= delta/2, xi moves at constant speed v
to the point sign(v) delta (on the other side, or on the same side when moving
away from 0) in T <= 2 delta/|v|, and the series takes over again there.  There |xi''| <= F =
rho (1.01 delta)^(a+1) + 2 mu V (1.01 delta)^b, so the neglected change of xi' is
<= F T <= 2^-55 |v| and that of xi (and of x) <= F T^2/2 <= 2^-56 |v| T: the window
is exact to rounding.  For b = 0 the damping is linear and solved exactly in the
window (xi' = v exp(-2 mu s)); only the restoring force is neglected, and the
second term of delta is dropped.  Approximation: delta is never below 16 ulps of
xi_eq, the resolution of xi in the deviation variable eta.  Where that floor is
active (very slow crossings: for Hertz with mu V ~ 1e-2, |v| below ~1e-4) the
window is taken only if its neglected changes F T and F T^2/2 are still below
2^-55 (|x'| + |v|) (the rounding of x' and psi') and 2 ulps of xi_eq (the
resolution of eta); otherwise the flight stops with status SLOW_CROSSING (the
event loop's stop reason ``slow_crossing``: not simulated rather than guessed; a
crossing expansion in fractional powers, as in tests/power_reference.py, would
lift this limit).  The floor is checked over the window with the safe step; a
window that may contain the floor contact stops the same way (SLOW_CROSSING: for
ordinary crossings the window is at most ~1e-6 long, so this happens only when
the spring creeps through its rest length, e.g. |xi'| ~ 1e-17 at xi = 0).

First-order windows (b > 0; the damping is what makes the window above narrow, ~1e-12 for
Hertz).  Away from the floor, the crossing is taken as one window of half-width delta_1 >= 2|xi|
(doubled while allowed) with the force integrated once and twice along the line
xi0 + v s in closed form (:func:`_wide_window_change`), so only the force's change along the
true path is neglected; :func:`_wide_window_ok` bounds that change (Lipschitz for the restoring
force, Hoelder for |xi|^b, b <= 1, integrated over the sweep of the line through xi = 0) by
2^-56 |v| in xi' and 2^-56 |v| T in xi: exact to rounding like the window above, and ~1e-5 wide
for Hertz at |v| ~ 0.3, which takes ~6 decades of geometric series steps off every crossing.
A first-order window that may contain the floor contact or t_limit is not taken (series steps).

Crossings in the root variable (a, b in (1/q) Z, q in {1, 2, 4, 8}: Hertz, q = 2; tried
first, the windows above are the fallback).  When xi moves towards 0 (or starts at 0) and
the crossing is fast (:func:`_root_crossing`), the crossing is one step of the series of eq. (R)
of :mod:`bounce.series.taylor` (xi = s sigma^q, sigma the independent variable, xi' and t
analytic through sigma = 0): the incoming series around sigma0 = |xi0|^(1/q) evaluated at
sigma = 0 gives the crossing time and V = xi' there, the outgoing series around 0 on the other
side with xi'(0) = V runs to sigma1 = theta r.  Each is truncated at ROOT_DEGREE with its rigorous
tail below TOL_ROOT = 2^-60 of |xi'| (xi') and of a lower bound |xi1 - xi0| / (1.5 |xi'|) of its
duration (t): exact to rounding like the windows above.  For Hertz (mu = 0.05) it spans
|xi| <= 3e-3 before and 6e-3 after the crossing at |v| = 0.03 (2e-2 and 4e-2 at |v| = 0.3); on the
drop of benchmarks/bench_power.py it took the first 10 flights from ~560 to ~200 series steps
per flight (~160 with the comparison radius; the rest lie where |xi| is comparable to the amplitude,
where the time series is the right expansion; heyoka takes ~375 steps on the same flights:
``python benchmarks/bench_power_steps.py``).  Approximations: sigma0 is the
rounded root |xi0|^(1/q) (sigma0^q = |xi0| to q ulps: below the resolution of xi); the state at
sigma1 is xi1 = -s sigma1^q rounded.  The step ends before the floor can be reached (the safe
step of the flight's curvature bound) and before t_limit: sigma1 is taken smaller where needed,
and the crossing is not taken when xi = 0 itself comes too late, nor when a tail bound fails
(slow crossings): then the windows above.

Hot path (:func:`short_flight`): a flight from the floor deep in the asymptotic
regime is one low-degree step, solved like :func:`bounce.exact.short_flight.short_flight`
(cubic predictor, Newton steps certified to keep x > 0 before the root and to be
within rounding of it); its window is 17/16 of the predicted flight (a root beyond it is a
HANDOVER to :func:`first_contact`, never a skipped impact), its radius the cheap one or, where
that needs a degree above ONCE_ABOVE, the one-shot comparison radius of eq. (C)
(:func:`bounce.series.taylor.step_radius`), and the root's last Newton step is applied to second order.  A flight a few times
longer is two or three such steps (:func:`_split_flight`: the steps before the last end before
2u/B, where the curvature bound alone keeps x > 0, so only the last needs a root certificate).
For the Hertz drop of benchmarks/bench_power.py this takes the flights from impact ~1e3 on
(before: ~5e3), with ~0.7 of the instructions per impact there (impacts 1e3 .. 5e3).

Long flights: the error bound.  Each step is exact to rounding, and the state is carried in
hi + lo parts; what remains is the float64 evaluation of each step (the rounded coefficients and
polynomial, the start state rounded to the double the series is taken at), which changes the
spring energy by ~1 ulp, independently from step to step.  Over a flight the energy error is a
random walk, measured for Hertz at sigma_1 = 8e-17 = 0.4 eps (eps = 2^-52) relative per crossing
of xi = 0, plus a bias of ~0.02 eps (exact coefficients and evaluation would leave 0.1 eps, the
rounding of the float coefficients).  The frequency of the nonlinear spring depends on its energy
(omega ~ E^c, c = a/(2(a+2)): 1/10 for Hertz), so the walk turns into a phase error: after n
crossings xi, xi' and eta are off by ~ c pi sigma_1 n^(3/2) / sqrt(3) relative to the swing W (rms;
Hertz: 1.5e-17 n^(3/2), single values within ~3x of it), while tau, x and x' stay within a few
ulps (psi is a parabola).  So 1e-14 holds to ~70 crossings in rms, single values within ~3x
(tests/series/test_series_reference.py: 45 crossings, 4.3e-15 of W; over 40 independent realisations of that
flight, gamma = 1e-5 (1 + 0.0137 k), rms 4.1e-15 and largest 1.1e-14, as before the comparison radius
(3.97e-15, 1.19e-14); its longer steps without the exact v h: 4.9e-15, 1.6e-14, each step's
rounding of v h being larger: ``python benchmarks/bench_power_long_flight.py --realisations 40``), and the ~2800 crossings of a 6e4-long Hertz flight end with xi, xi' ~2e-12 off
(of W and of the speed at xi = 0; the estimate: 2.3e-12) and the energy (mu = 0) within 1e-14
(tests/series/test_series_core.py: 8e-15).  This is the problem's conditioning, not the method's: a
half-ulp rounding of xi at the start of that flight alone moves its end by up to
c pi n (a+2) eps/2 (2e-13 for Hertz, n = 2800), and a march of independent roundings adds them
like sqrt(n).  ``python benchmarks/bench_power_long_flight.py`` prints the error along such a
flight against tests/power_reference.py.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..exact.events import compensated_add
from ..exact.flight import EPS, FAILED, FOUND, HORIZON, safe_step
from .taylor import (
    DEGREE_LONG,
    DEGREE_SHORT,
    L_AP1,
    L_B,
    L_GAMMA,
    L_MU,
    L_RHO,
    L_XI_EQ,
    MARGIN,
    ROOT_DEGREE,
    L_ANALYTIC_A,
    L_ROOT_Q,
    integer_power,
    L_ANALYTIC_B,
    cauchy_radius,
    curvature,
    displacement,
    powers_at,
    restoring_excess,
    root_coefficients,
    root_radius,
    root_series,
    root_exponents,
    step_radius,
    tail_bounds,
    taylor_coefficients,
)

#: truncation target of the hot path (one step per flight) relative to the rounding scale.
TOL = 2.0**-55
#: truncation target of a general step: a truncation error is systematic (the same sign from step
#: to step), so over the ~1e4 steps of a long flight through many xi = 0 crossings 2^-55 per
#: step would add up to ~1e-13; 2^-64 keeps the sum below 2^-50 of the scale.
TOL_LONG = 2.0**-64
#: cap on evaluations within one series step (a crawl towards a tangency needs ~1e3).  The steps of
#: a flight are not capped: psi is a free fall, so a flight is finite, and its series steps number
#: ~1e2 per crossing of xi = 0 (a long flight of a weakly damped spring crosses it thousands of
#: times); a step that does not advance time (or a NaN state) is FAILED.
MAX_EVALS = 400_000
#: truncation target of a crossing in the root variable (relative to xi' and to the crossing's time).
TOL_ROOT = 2.0**-60
#: largest theta = |sigma - sigma0| / r of a root-variable series (ROOT_DEGREE 64: theta^65 / (1 - theta) ~ 2^-60).
THETA_ROOT = 0.53
#: the hot path's window over its predicted flight (short_flight): 1/16 above the cubic model's root.
WINDOW = 17.0 / 16.0
#: the hot path forms the comparison radius of eq. (C) only where the cheap radius needs a degree above this
#: (:func:`_hot_degree`; its one or two evaluations of the series of (C) cost about as much as several degrees
#: of the Hertz series: instructions per impact of the Hertz drop, impacts 5e3 .. 2e4, with 12 / 16 / 20:
#: 7353, 5152 (main, always formed where the cheap one fails) -> 6629, 5154 / 6218, 5036 / 6625, 4838).
ONCE_ABOVE = 16
#: status: the hot path hands over to the general stepper.
HANDOVER = 4
#: status: the flight starts at rest on the floor and the mass stays (at_rest_is_sticky): a sticky state.
AT_REST = 5
#: status: a crossing of xi = 0 too slow for the window to be exact to rounding, or a window that
#: may contain the floor contact (see module docstring).
SLOW_CROSSING = 6


@njit(cache=True)
def spring_energy(w0, v, p0, law):
    """E_s = xi'^2/2 + rho |xi|^(a+2)/(a+2) (the spring part of eq. ``nonlin-energy``)."""
    return 0.5 * v * v + law[L_RHO] * w0 * p0 / (law[L_AP1] + 1.0)


@njit(cache=True)
def curvature_bound(Es, law):
    """B >= |x''| for the rest of the flight from the spring energy Es (module docstring)."""
    gamma = law[L_GAMMA]
    if Es <= 0.0:
        return gamma * MARGIN
    rho = law[L_RHO]
    ap2 = law[L_AP1] + 1.0
    Es *= MARGIN
    W = (ap2 * Es / rho) ** (1.0 / ap2)
    Wq = 1.0 if law[L_ANALYTIC_B] == 1.0 else W ** law[L_B]
    return (gamma + ap2 * Es / W + 2.0 * law[L_MU] * math.sqrt(2.0 * Es) * Wq) * MARGIN  # rho W^(a+1) = ap2 Es / W


@njit(cache=True)
def _curvature_bound_near(w0, v, p0, q0, law):
    """A bound B >= |x''| for the rest of the flight like :func:`curvature_bound`, without powers.

    With E_s = v^2/2 + rho w0 p0/(a+2) and W^(a+2) = (a+2) E_s / rho = w0^(a+2) (1 + e),
    e = (a+2) v^2 / (2 rho w0 p0): W <= w0 (1 + e/(a+2)) (concavity of the root, a + 2 >= 1),
    rho W^(a+1) = (a+2) E_s / W <= (a+2) E_s / w0 and W^b <= q0 exp(b e/(a+2)) <= q0 / (1 - b e/(a+2))
    when b e/(a+2) < 1 (else the general bound).
    """
    ap2 = law[L_AP1] + 1.0
    Es = spring_energy(w0, v, p0, law) * MARGIN
    r = v * v / (2.0 * law[L_RHO] * w0 * p0)  # e / (a + 2)
    be = law[L_B] * r
    if not be < 0.5:
        return curvature_bound(Es, law)
    return (law[L_GAMMA] + ap2 * Es / w0 + 2.0 * law[L_MU] * math.sqrt(2.0 * Es) * q0 / (1.0 - be)) * MARGIN


@njit(cache=True)
def floor_force(v, eta, law):
    """(F, F', noise of F, noise of F') for a state at rest on the floor (x = x' = 0).

    F = f(xi) + 2 mu xi' |xi|^b - gamma is the force of spring and gravity on the lower mass
    (eq. ``force-on-the-floor`` for a = b = 0, rho = 1), i.e. x'' of the free motion there,
    and F' = x''' = d/dt (f(xi) + 2 mu xi' |xi|^b), the same for the free and the sticky
    motion at F = 0 (both have xi'' = -gamma there; :mod:`bounce.series.sticky`):

        F' = f'(xi) xi' + 2 mu b |xi|^(b-1) sign(xi) xi'^2 + 2 mu |xi|^b xi'',  xi'' = -gamma - F/2.

    gamma + f is formed without cancellation (:func:`bounce.series.taylor.restoring_excess`).
    The noises are 8 eps times the magnitudes of the terms (gamma + f, 2 gamma, the damping;
    for a = b = 0, rho = 1 those of :func:`bounce.exact.events._at_rest_is_sticky`):
    within them F, F' count as zero (approximation at the rounding level, as in
    :func:`bounce.exact.events._at_rest_is_sticky`).  At xi = 0 with b > 0, F = -gamma: F' is not
    needed there and its singular term is dropped.
    """
    gamma = law[L_GAMMA]
    rho = law[L_RHO]
    mu = law[L_MU]
    xi = law[L_XI_EQ] + eta
    w = abs(xi)
    p0, q0 = powers_at(w, law)
    excess = restoring_excess(eta, p0, law)  # gamma + f(xi)
    damp = 2.0 * mu * v * q0
    F = (excess - 2.0 * gamma) + damp
    noise_F = 8.0 * EPS * (abs(excess) + 2.0 * gamma + abs(damp))
    if w > 0.0:
        fp = law[L_AP1] * rho * p0 / w
        bend = 2.0 * mu * law[L_B] * q0 / w * v * v * (1.0 if xi > 0.0 else -1.0)
    else:
        fp = rho if law[L_ANALYTIC_A] == 1.0 else 0.0
        bend = 0.0
    # xi = xi_eq + eta carries an absolute rounding of a few eps (|xi_eq| + |eta|), which F feels through
    # dF/dxi = f'(xi) + 2 mu b |xi|^(b-1) sign(xi) xi' (large near xi = 0 for b < 1: a detach polished on F
    # cannot get below it; found by test_sticky_records_follow_the_rules, Hertz, xi = 1.6e-4 at the detach)
    if v != 0.0 and w > 0.0:
        noise_F += 4.0 * EPS * (abs(law[L_XI_EQ]) + abs(eta)) * (abs(fp) + abs(bend / v))
    else:
        noise_F += 4.0 * EPS * (abs(law[L_XI_EQ]) + abs(eta)) * abs(fp)
    xidd = -gamma - 0.5 * F
    Fp = fp * v + bend + 2.0 * mu * q0 * xidd
    noise_Fp = 8.0 * EPS * (abs(fp * v) + abs(bend) + 2.0 * mu * q0 * (gamma + 0.5 * abs(F)))
    return F, Fp, noise_F, noise_Fp


@njit(cache=True)
def at_rest_is_sticky(v, eta, law):
    """For x = x' = 0: does the lower mass stay on the floor (F < 0, or F = 0 and F' <= 0)?

    The decision of :func:`bounce.exact.events._at_rest_is_sticky` for the power law (eq.
    ``cond_di_distacco``: it leaves only if F > 0, or F = 0 and F' > 0), within the noises of
    :func:`floor_force`.  The flight's lift-off and the sticky phase's start both use it, so
    a detach is never followed by an immediate sticky start or the reverse.
    """
    F, Fp, noise_F, noise_Fp = floor_force(v, eta, law)
    if F > noise_F:
        return False
    if F < -noise_F:
        return True
    return Fp <= noise_Fp


@njit(cache=True)
def crossing_halfwidth(v, Es, law):
    """delta of the window through xi = 0 (module docstring); 0 if v = 0."""
    if v == 0.0:
        return 0.0
    v2 = v * v
    delta = (2.0**-57 * v2 / (law[L_RHO] * 1.01 ** law[L_AP1])) ** (1.0 / (law[L_AP1] + 1.0))
    scale = law[L_MU] * math.sqrt(2.0 * Es) * MARGIN * 1.01 ** law[L_B]
    if scale > 0.0 and law[L_ANALYTIC_B] == 0.0:
        delta = min(delta, (2.0**-58 * v2 / scale) ** (1.0 / (law[L_B] + 1.0)))
    # eta = xi - xi_eq resolves xi only to ~ulp(xi_eq): no window narrower than that
    return max(delta, 16.0 * EPS * abs(law[L_XI_EQ]))


@njit(cache=True)
def _wide_window_ok(delta, v, Es, law):
    """Is the first-order crossing window of half-width delta exact to rounding (b > 0; module docstring)?

    On the window |xi| <= W = 1.01 delta, |xi''| <= F = rho W^(a+1) + 2 mu V W^b (V = sqrt(2 E_s)),
    and it lasts T <= 2 delta/|v|, so the true path leaves the line l(s) = xi0 + v s by at most
    E0 = F T^2/2 in xi and E1 = F T in xi' (E0 <= delta/100 keeps |xi| <= W and gives
    E1 <= |v|/100: xi' keeps its sign, the line's sweep is monotone).  The force along the
    true path differs from the one along the line (xi' = v) by at most
    rho (a+1) W^a E0 + 2 mu E1 W^b + 2 mu V ||xi|^b - |l|^b|, and the last term integrated over
    the window (l sweeps [-W, W] at most once at speed |v|) is <= 2 mu V I / |v| with, for b <= 1,
    I = 4 E0^(1+b) (where |l| <= 2 E0: Hoelder, ||x|^b - |y|^b| <= |x - y|^b) + 2^(2-b) E0 W^b
    (elsewhere: b (|l|/2)^(b-1) E0, integrated over l), and for b > 1 I = b W^(b-1) E0 |v| T.
    The neglected change of xi' is then <= DV = (rho (a+1) W^a E0 + 2 mu E1 W^b) T + 2 mu V I/|v|
    and that of xi <= DV T; DV <= 2^-56 |v| makes them <= 2^-56 |v| and 2^-56 |v| T, below
    the zeroth-order window's.
    """
    rho = law[L_RHO]
    mu = law[L_MU]
    a = law[L_AP1] - 1.0
    b = law[L_B]
    av = abs(v)
    if not (av > 0.0 and delta > 0.0):
        return False
    W = 1.01 * delta
    V = math.sqrt(2.0 * Es) * MARGIN
    T = 2.0 * delta / av
    Wa = W**a if a > 0.0 else 1.0
    Wb = W**b
    F = (rho * Wa * W + 2.0 * mu * V * Wb) * MARGIN
    E0 = 0.5 * F * T * T
    E1 = F * T
    if b <= 1.0:
        sweep = 4.0 * E0 * E0**b + 2.0 ** (2.0 - b) * E0 * Wb
    else:
        sweep = b * W ** (b - 1.0) * E0 * av * T
    DV = ((rho * (a + 1.0) * Wa * E0 + 2.0 * mu * E1 * Wb) * T + 2.0 * mu * V * sweep / av) * MARGIN
    return E0 <= 0.01 * delta and DV <= 2.0**-56 * av


@njit(cache=True)
def _near_crossing(w0, v, pw0, law):
    """A necessary condition (no powers) for either window at |xi0| = w0, pw0 = w0^(a+1).

    The window of half-width delta is entered at w0 <= delta/2, delta <= max((2^-57 v^2 / rho)^(1/(a+2)),
    16 eps |xi_eq|), so (2 w0)^(a+2) >= 4 w0 pw0 gives 4 rho w0 pw0 <= 2^-57 v^2 or w0 <= 8 eps |xi_eq|;
    the first-order window at delta = 2 w0 needs E0 <= delta/100 (:func:`_wide_window_ok`), E0 >=
    2 rho delta^(a+3) / v^2, i.e. 800 rho w0 pw0 <= v^2, which the first case implies.
    """
    return 800.0 * law[L_RHO] * w0 * pw0 <= v * v or w0 <= 8.0 * EPS * abs(law[L_XI_EQ])


@njit(cache=True)
def _wide_window_change(T, xi0, v, law):
    """(e, dv): the first-order change of xi beyond xi0 + v T, and of xi', over a window of length T.

    The force r(xi) + 2 mu xi' |xi|^b (r = rho xi |xi|^a) integrated once and twice along the
    line l(s) = xi0 + v s with xi' = v, by the antiderivatives in xi
    R1 = |xi|^(a+2)/(a+2), R2 = xi |xi|^(a+2)/((a+2)(a+3)), G1 = xi |xi|^b/(b+1),
    G2 = |xi|^(b+2)/((b+1)(b+2)):
    dv = -(rho (R1(l_T) - R1(xi0))/v + 2 mu (G1(l_T) - G1(xi0))),
    e = -(rho (R2(l_T) - R2(xi0) - v T R1(xi0))/v^2 + 2 mu (G2(l_T) - G2(xi0) - v T G1(xi0))/v).
    Their error is bounded in :func:`_wide_window_ok`.
    """
    rho = law[L_RHO]
    mu = law[L_MU]
    ap2 = law[L_AP1] + 1.0
    bp1 = law[L_B] + 1.0
    lT = xi0 + v * T
    w0, wT = abs(xi0), abs(lT)
    R1_0, R1_T = w0**ap2 / ap2, wT**ap2 / ap2
    R2_0, R2_T = xi0 * R1_0 / (ap2 + 1.0), lT * R1_T / (ap2 + 1.0)
    G1_0, G1_T = xi0 * w0 ** law[L_B] / bp1, lT * wT ** law[L_B] / bp1
    G2_0, G2_T = w0 * G1_0 * (1.0 if xi0 >= 0.0 else -1.0) / (bp1 + 1.0), wT * G1_T * (1.0 if lT >= 0.0 else -1.0) / (bp1 + 1.0)
    vT = v * T
    dv = -(rho * (R1_T - R1_0) / v + 2.0 * mu * (G1_T - G1_0))
    e = -(rho * ((R2_T - R2_0) - vT * R1_0) / (v * v) + 2.0 * mu * ((G2_T - G2_0) - vT * G1_0) / v)
    return e, dv


@njit(cache=True)
def _root_crossing(xi0, v, pw0, law, t_max):
    """(T, d, dv): the crossing of xi = 0 from (xi0, v), xi0 v <= 0, in the root variable (module docstring).

    T < t_max (the flight's safe step or t_limit): the outgoing series stops at a smaller sigma1
    where needed (its tails only shrink), T = 0 if the crossing itself comes too late.

    Incoming series of eq. (R) around sigma0 = |xi0|^(1/q) evaluated at sigma = 0 (the crossing:
    time t_in, xi' = V), outgoing series around 0 on the other side evaluated at sigma1; T = t_in +
    t_out, d = xi1 - xi0 and dv = the change of xi' (summed from the series' own increments, so
    no ulp of xi' is lost).  T = 0 when a tail bound or the fast-crossing pre-check fails:
    4 q rho |xi0|^(a+2) (1 + 1/THETA_ROOT)^n_a / THETA_ROOT <= v^2 is necessary for sigma0 <= THETA_ROOT r
    (r <= Rp / Mp, Rs >= sigma0 / THETA_ROOT in :func:`bounce.series.taylor.root_majorant`); pw0 = |xi0|^(a+1).
    """
    q, na, nb = root_exponents(law)
    if not (t_max > 0.0 and 4.0 * q * law[L_RHO] * abs(xi0) * pw0 * integer_power(1.0 + 1.0 / THETA_ROOT, na) <= THETA_ROOT * v * v):
        return 0.0, 0.0, 0.0
    K = ROOT_DEGREE
    Pc = np.empty(K + 1)
    Tc = np.empty(K + 1)
    R = np.empty(K + 1)
    S = np.zeros((3, max(na, nb, int(q)) + 1))
    w0 = abs(xi0)
    t_in, dv_in, V = 0.0, 0.0, v
    side = 1.0 if v > 0.0 else -1.0  # the outgoing side
    if w0 > 0.0:
        sig0 = w0 ** (1.0 / q)
        r, Rp, Mt = root_radius(sig0, v, law)
        if not r > 0.0:  # underflow (|v| ~ 1e-50)
            return 0.0, 0.0, 0.0
        theta = sig0 / r
        tail = theta ** (K + 1) / (1.0 - theta) * MARGIN if theta < 1.0 else math.inf
        if not (tail <= TOL_ROOT and Mt * r * tail <= TOL_ROOT * w0 / (1.5 * abs(v))):
            return 0.0, 0.0, 0.0
        root_coefficients(sig0, v, -side, law, r, K, Pc, Tc, R, S)
        Pc[0] = 0.0
        dv_in = root_series(-theta, K, Pc)
        t_in = root_series(-theta, K, Tc)
        V = v + dv_in
        if not (0.0 < t_in < t_max and V * v > 0.0):
            return 0.0, 0.0, 0.0
    r, Rp, Mt = root_radius(0.0, V, law)
    if not r > 0.0:
        return 0.0, 0.0, 0.0
    theta = 0.6
    for _ in range(100):
        tail = theta ** (K + 1) / (1.0 - theta) * MARGIN
        if tail <= TOL_ROOT and Mt * r * tail <= TOL_ROOT * (theta * r) ** q / (1.5 * abs(V)):
            break
        theta *= 0.97
    else:
        return 0.0, 0.0, 0.0
    root_coefficients(0.0, V, side, law, r, K, Pc, Tc, R, S)
    Pc[0] = 0.0
    for _ in range(16):  # t_out ~ sigma1^q / |V|: shrink sigma1 until the crossing ends before t_max
        t_out = root_series(theta, K, Tc)
        if t_in + t_out < t_max:
            break
        if not t_out > 0.0:
            return 0.0, 0.0, 0.0
        theta *= 0.9 * ((t_max - t_in) / t_out) ** (1.0 / q)
    else:
        return 0.0, 0.0, 0.0
    dv_out = root_series(theta, K, Pc)
    xi1 = side * (theta * r) ** q
    return t_in + t_out, xi1 - xi0, dv_in + dv_out


@njit(cache=True)
def _evaluate(s, x, xl, u, ul, gamma, H, K, X):
    """x(s), x'(s) and the rounding scale of x by eq. (P); also D(s), D'(s).

    (x + xl, u + ul) is the step's start state carried with its compensation terms
    (Neumaier sums over the steps of a long flight): the increment is added to x
    first, where near a root it cancels exactly, then the small terms.
    """
    D, Dp = displacement(s, H, K, X)
    xs = (x + (u * s - 0.5 * gamma * s * s - D)) + (xl + ul * s)
    vs = (u + (-gamma * s - Dp)) + ul
    scale = x + abs(u) * s + 0.5 * gamma * s * s + abs(D)
    return xs, vs, scale, D, Dp


@njit(cache=True)
def _minimum(s0, s1, x, xl, u, ul, gamma, H, K, X):
    """Time of the minimum of x between s0 (x' < 0) and s1 (x' >= 0): Newton on x' kept in the bracket."""
    lo, hi = s0, s1
    s = 0.5 * (s0 + s1)
    for _ in range(60):
        if not lo < s < hi:
            s = 0.5 * (lo + hi)
        _, vs, _, _, _ = _evaluate(s, x, xl, u, ul, gamma, H, K, X)
        if vs < 0.0:
            lo = s
        else:
            hi = s
        A = -gamma - curvature(s, H, K, X)[0]
        step = -vs / A if A > 0.0 else 0.0
        if step == 0.0 or abs(step) <= 4.0 * EPS * s or hi - lo <= 4.0 * EPS * hi:
            break
        s += step
    return s


@njit(cache=True)
def _liftoff(acc, jerk, h, radius, Rz, Rp, K, X):
    """S > 0 with x > 0 on (0, S] for a step starting at x = x' = 0 with x''(0) = acc >= 0 and
    x'''(0) = jerk, acc > 0 or jerk > 0 (acc = 0, jerk > 0: a detach, eq. ``cond_di_distacco``).

    With X_k in units of the radius, x(s) >= s^2 (acc/2 + jerk s/6 - R(s)) where
    R(s) = sum_{k>=4} |X_k| s^(k-2) / radius^k + tail(s)/s^2 grows at least like s^2, so the
    concave bracket is positive on (0, S] once it is at S (jerk > 0); for jerk <= 0 the
    X_3 term joins R: acc/2 > sum_{k>=3} |X_k| S^(k-2) / radius^k + tail(S)/S^2.
    S halves until the bracket is positive; 0 if neither acc > 0 nor jerk > 0.
    """
    if not (acc > 0.0 or jerk > 0.0):
        return 0.0
    first = 4 if jerk > 0.0 else 3
    S = h
    for _ in range(400):
        poly = 0.0
        for k in range(K, first - 1, -1):
            poly = poly * (S / radius) + abs(X[k])
        poly *= (S / radius) ** first / (S * S)
        tail = tail_bounds(S / radius, K, Rz, Rp)[0] / (S * S)
        if 0.5 * acc + (jerk * S / 6.0 if jerk > 0.0 else 0.0) > poly + tail:
            return S
        S *= 0.5
    return 0.0


@njit(cache=True)
def first_contact(x, u, v, eta, t_limit, law, X, P, Q, lifting=False):
    """First time tau in (0, t_limit] with x(tau) = 0 for the flight from (x, u, v, eta).

    Requires x > 0 or u > 0 or (x = u = 0 with x'' > 0).  Returns
    ``(status, tau, x'(tau), scale, eta(tau), xi'(tau), x''(tau), x'''(tau))``:
    status FOUND (polished root, or a minimum within rounding of the floor),
    HORIZON (no contact up to t_limit: then the fields are (HORIZON, t_limit,
    x'(t_limit), x(t_limit), eta(t_limit), xi'(t_limit), 0, 0), the state there for the
    dense output of :mod:`bounce.sampling`), AT_REST (x = u = 0 and the mass stays,
    :func:`at_rest_is_sticky`; then the last two fields are F and F') or FAILED
    (evaluation cap within a step, a step that does not advance time, a lift-off not resolved).  The state is carried
    from step to step with Neumaier compensation (x, u, eta, xi' each as hi + lo), so
    that a flight of many steps keeps the accuracy of one evaluation to a few ulps; the lo parts
    of eta and xi' are folded into the hi parts before each step (the series is taken there).
    ``lifting``: the caller knows that a start at rest lifts off (dense output of a recorded
    flight; F, F' within rounding of the at-rest boundary are then taken as a lift-off).
    """
    gamma = law[L_GAMMA]
    rho = law[L_RHO]
    mu = law[L_MU]
    xi_eq = law[L_XI_EQ]
    singular = not (law[L_ANALYTIC_A] == 1.0 and law[L_ANALYTIC_B] == 1.0)
    rooted = singular and law[L_ROOT_Q] > 0.0
    start = (x, u, v, eta)
    K = DEGREE_LONG
    t_hi, t_lo = 0.0, 0.0
    xl, ul, el, vl = 0.0, 0.0, 0.0, 0.0
    B = math.inf
    while True:
        t = t_hi + t_lo
        # fold the compensation of eta, xi' into the leading part (an exact two-sum): the step's series is
        # taken at the leading parts, so an unfolded lo (a running sum of roundings, grown to ~10 ulps over
        # a swing) was a force offset of one sign for many steps: an energy drift 5x the random walk of
        # the module docstring (measured for Hertz: 4e-16 -> 8e-17 relative per crossing of xi = 0)
        eta, el = compensated_add(eta, 0.0, el)
        v, vl = compensated_add(v, 0.0, vl)
        xi0 = xi_eq + eta
        w0 = abs(xi0)
        p0, q0 = powers_at(w0, law)
        Es = spring_energy(w0, v, p0, law)
        B = min(B, curvature_bound(Es, law))
        if Es == 0.0:
            # spring at rest at its rest length: xi stays 0, x is the parabola of free fall
            u += ul
            x += xl
            root = math.sqrt(u * u + 2.0 * gamma * x)
            s = (u + root) / gamma if u >= 0.0 else 2.0 * x / (root - u)
            if t + s > t_limit:
                s = t_limit - t
                return HORIZON, t_limit, u - gamma * s, x + (u * s - 0.5 * gamma * s * s), eta + el, v + vl, 0.0, 0.0
            t_hi, t_lo = compensated_add(t_hi, t_lo, s)
            return FOUND, t_hi + t_lo, -root, x + abs(u) * s + 0.5 * gamma * s * s, eta + el, v + vl, -gamma, 0.0
        if rooted and v != 0.0 and xi0 * v <= 0.0 and not (x == 0.0 and u == 0.0):
            T, d, dv = _root_crossing(xi0, v, p0, law, min(t_limit - t, safe_step(x + xl, u + ul, B)))
            if T > 0.0:
                x, xl = compensated_add(x, xl, (u * T - 0.5 * gamma * T * T) + ((v * T - d) + ul * T))
                u, ul = compensated_add(u, ul, -gamma * T - dv)
                eta, el = compensated_add(eta, el, d + vl * T)
                v, vl = compensated_add(v, vl, dv)
                t_hi, t_lo = compensated_add(t_hi, t_lo, T)
                continue
        # both windows need 800 rho |xi0|^(a+2) <= v^2 or |xi0| <= 8 eps |xi_eq| (_near_crossing)
        near = singular and _near_crossing(w0, v, p0, law)
        delta = crossing_halfwidth(v, Es, law) if near else 0.0
        if (near and law[L_ANALYTIC_B] == 0.0 and w0 > 0.5 * delta and not (x == 0.0 and u == 0.0)
                and _wide_window_ok(2.0 * w0, v, Es, law)):
            wide = 2.0 * w0
            for _ in range(64):
                if not _wide_window_ok(2.0 * wide, v, Es, law):
                    break
                wide *= 2.0
            d = (wide if v > 0.0 else -wide) - xi0
            T = d / v
            if t + T < t_limit and safe_step(x + xl, u + ul, B) > T:
                e, dv = _wide_window_change(T, xi0, v, law)
                x, xl = compensated_add(x, xl, (u * T - 0.5 * gamma * T * T) + (((v * T - d) - e) + ul * T))
                u, ul = compensated_add(u, ul, -gamma * T - dv)
                eta, el = compensated_add(eta, el, (d + e) + vl * T)
                v, vl = compensated_add(v, vl, dv)
                t_hi, t_lo = compensated_add(t_hi, t_lo, T)
                continue
        if near and w0 <= 0.5 * delta:  # enter at delta/2, leave at delta: the next step is a series step
            d = (delta if v > 0.0 else -delta) - xi0  # the window's change of xi
            if law[L_ANALYTIC_B] == 1.0 and mu > 0.0:
                # linear damping solved exactly in the window: xi' = v exp(-2 mu s)
                arg = 2.0 * mu * d / v
                if not arg < 0.5:  # the damping stops xi' before the window's end: a creeping spring
                    return SLOW_CROSSING, t, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
                T = -math.log1p(-arg) / (2.0 * mu)
                dv = v * math.expm1(-2.0 * mu * T)
            else:
                T = d / v
                dv = 0.0
            # the neglected |xi''| <= F on the window (restoring force; damping too unless b = 0)
            W = 1.01 * delta
            F = law[L_RHO] * W ** law[L_AP1]
            if law[L_ANALYTIC_B] == 0.0:
                F += 2.0 * mu * math.sqrt(2.0 * Es) * W ** law[L_B]
            if F * T > 2.0**-55 * abs(v) and (F * T > 2.0**-55 * (abs(u) + abs(v))
                                               or 0.5 * F * T * T > 2.0**-53 * abs(xi_eq)):
                return SLOW_CROSSING, t, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
            if not (x == 0.0 and u == 0.0) and safe_step(x + xl, u + ul, B) <= T:
                return SLOW_CROSSING, t, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0  # the floor may be reached inside
            if t + T > t_limit:  # the state part-way through the window (for dense output)
                T = t_limit - t
                if law[L_ANALYTIC_B] == 1.0 and mu > 0.0:
                    dv = v * math.expm1(-2.0 * mu * T)
                    d = -dv / (2.0 * mu)
                else:
                    d, dv = v * T, 0.0
                xs = (x + (u * T - 0.5 * gamma * T * T) + (v * T - d)) + (xl + ul * T)
                return HORIZON, t_limit, (u - gamma * T - dv) + ul, xs, eta + (d + (el + vl * T)), (v + dv) + vl, 0.0, 0.0
            # x = psi - xi: psi moves by (u + v) T - gamma T^2/2, xi by d
            x, xl = compensated_add(x, xl, (u * T - 0.5 * gamma * T * T) + ((v * T - d) + ul * T))
            u, ul = compensated_add(u, ul, -gamma * T - dv)
            eta, el = compensated_add(eta, el, d + vl * T)
            v, vl = compensated_add(v, vl, dv)
            if not T > 0.0:
                return FAILED, t, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
            t_hi, t_lo = compensated_add(t_hi, t_lo, T)
            continue
        radius, Rz, Rp = step_radius(w0, v, p0, q0, 0.0, rho, mu, law)
        xidd0 = abs(rho * p0 + 2.0 * mu * v * q0 * (1.0 if xi0 >= 0.0 else -1.0))  # |xi''(0)|
        theta = 0.5
        for _ in range(200):
            h = theta * radius
            tx, tv = tail_bounds(theta, K, Rz, Rp)
            # rounding scales of x, x' and of xi, xi' over the step: the tail stays below the smaller
            scale_x = min(x + abs(u) * h + 0.5 * gamma * h * h, w0 + abs(v) * h + 0.5 * xidd0 * h * h)
            scale_v = min(abs(u) + gamma * h, abs(v) + xidd0 * h)
            if tx <= TOL_LONG * scale_x and tv <= TOL_LONG * scale_v:
                break
            # tx ~ theta^(K+1), tv ~ theta^K: shrink to where they meet this theta's scales (which
            # shrink with theta too, hence the loop), by at least 2% and at most 10x per pass
            fit = min((TOL_LONG * scale_x / tx) ** (1.0 / (K + 1.0)), (TOL_LONG * scale_v / tv) ** (1.0 / K))
            theta *= max(min(fit, 0.98), 0.1)
        h = theta * radius
        if not h > 0.0:
            return FAILED, t, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
        last = t + h >= t_limit
        if last:
            h = t_limit - t
        taylor_coefficients(xi0, w0, v, p0, q0, rho * (p0 if xi0 >= 0.0 else -p0), rho, mu, law, radius, K, X, P, Q)
        s = 0.0
        xs, vs = x + xl, u + ul
        if x == 0.0 and u == 0.0:
            # at rest on the floor: x'' = F, x''' = F' (floor_force); F within its noise is 0
            F, Fp, noise_F, _ = floor_force(v, eta, law)
            if not lifting and at_rest_is_sticky(v, eta, law):
                return AT_REST, 0.0, 0.0, 0.0, eta, v, F, Fp
            s = _liftoff(F if F > noise_F else 0.0, Fp, h, radius, Rz, Rp, K, X)
            if s == 0.0:
                return FAILED, t, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
            xs, vs, _, _, _ = _evaluate(s, x, xl, u, ul, gamma, radius, K, X)
        D, Dp = 0.0, 0.0
        for _ in range(MAX_EVALS):
            s_new = s + safe_step(xs, vs, B)
            at_end = s_new >= h
            if at_end:
                s_new = h
            s_prev, v_prev = s, vs
            s = s_new
            xs, vs, scale, D, Dp = _evaluate(s, x, xl, u, ul, gamma, radius, K, X)
            if xs <= 4.0 * EPS * scale:
                if vs < 0.0:  # Newton polish, re-evaluated at the polished time
                    s = s - xs / vs
                    xs, vs, scale, D, Dp = _evaluate(s, x, xl, u, ul, gamma, radius, K, X)
                return _contact(t_hi, t_lo, s, vs, scale, eta, el, v, vl, gamma, D, Dp, radius, K, X, start)
            if v_prev < 0.0 <= vs:
                sm = _minimum(s_prev, s, x, xl, u, ul, gamma, radius, K, X)
                xm, vm, sc_m, Dm, Dpm = _evaluate(sm, x, xl, u, ul, gamma, radius, K, X)
                if xm <= 4.0 * EPS * sc_m:
                    return _contact(t_hi, t_lo, sm, vm, sc_m, eta, el, v, vl, gamma, Dm, Dpm, radius, K, X, start)
            if at_end:
                break
        else:
            return FAILED, t, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
        if last:  # xs, vs, D, Dp are at s = h: the state at t_limit (for dense output)
            return HORIZON, t_limit, vs, xs, eta + ((v * h + D) + (el + vl * h)), (v + Dp) + vl, 0.0, 0.0
        x, xl = compensated_add(x, xl, (u * h - 0.5 * gamma * h * h - D) + ul * h)
        u, ul = compensated_add(u, ul, -gamma * h - Dp)
        vh = v * h
        eta, el = compensated_add(eta, el, vh)
        eta, el = compensated_add(eta, el, D + (vl * h + _product_error(v, h, vh)))
        v, vl = compensated_add(v, vl, Dp)
        t_hi, t_lo = compensated_add(t_hi, t_lo, h)


@njit(cache=True)
def _product_error(a, b, p):
    """a b - p for p = fl(a b) by Dekker's product: exact unless a partial product underflows (|a b| below
    ~1e-280: then off by < 1e-300), 0 where the split could overflow (|p| >= 1e290)."""
    if not abs(p) < 1e290:
        return 0.0
    c = 134217729.0 * a
    ah = c - (c - a)
    al = a - ah
    c = 134217729.0 * b
    bh = c - (c - b)
    bl = b - bh
    return ((ah * bh - p) + ah * bl + al * bh) + al * bl


@njit(cache=True)
def _contact(t_hi, t_lo, s, vs, scale, eta, el, v, vl, gamma, D, Dp, H, K, X, start):
    """FOUND at time s of the current step: (status, tau, x', scale, eta, xi', x'', x''').

    The rounding scale of x at the contact is the larger of the step's and the flight's,
    x0 + |u0| tau + gamma tau^2/2 + |xi(tau) - xi0 - v0 tau| from the flight's start
    ``start`` = (x0, u0, v0, eta0): the terms of eq. (P) over the whole flight, like the linear
    flight's scale (:func:`bounce.exact.flight.gap`), so that the contact classifier
    (:func:`bounce.exact.events.contact`) sees the uncertainty the start state's own rounding leaves.
    """
    D2, D3 = curvature(s, H, K, X)
    t_hi, t_lo = compensated_add(t_hi, t_lo, s)
    tau = t_hi + t_lo
    eta_t = eta + ((v * s + D) + (el + vl * s))
    x0, u0, v0, eta0 = start
    scale = max(scale, x0 + abs(u0) * tau + 0.5 * gamma * tau * tau + abs((eta_t - eta0) - v0 * tau))
    return FOUND, tau, vs, scale, eta_t, (v + Dp) + vl, -gamma - D2, -D3


@njit(cache=True)
def _short_degree(theta, Rz, Rp, tol_x, tol_v, cap):
    """The least degree K <= cap whose tail bounds (:func:`bounce.series.taylor.tail_bounds`) at
    theta <= 1/4 are below tol_x (x) and tol_v (x'); 0 if there is none."""
    if not theta <= 0.25:
        return 0
    K = 3
    tk = theta * theta * theta / (1.0 - theta) * MARGIN  # theta^K / (1 - theta), as in tail_bounds
    while Rz * tk * theta > tol_x or Rp * tk > tol_v:
        K += 1
        tk *= theta
        if K > cap:
            return 0
    return K


@njit(cache=True)
def _root_update(dt, vs, gamma, D, Dp, D2, D3):
    """(d, D, D') at the root t + d from the Newton step dt = -x/x' at t (x'(t) = vs; D and its first
    three derivatives at t).

    Second order: x(t + d) = x + vs d + x'' d^2/2 + O(d^3) with x'' = -gamma - D'' vanishes at
    d = dt (1 - x'' dt / (2 vs)), and D, D' are carried there by their Taylor polynomials of
    degree 2.  The hot path accepts dt with B dt^2 <= 8 eps scale, so a first-order update (d = dt)
    would leave x up to 4 eps scale off the floor (one-step errors ~3x larger deep in the asymptotic
    regime); the neglected terms here are O(B dt^3/|vs|), below rounding.
    """
    d = dt * (1.0 - 0.5 * (-gamma - D2) * dt / vs)
    return d, D + d * (Dp + 0.5 * D2 * d), Dp + d * (D2 + 0.5 * D3 * d)


@njit(cache=True)
def _certified_root(s, s_max, t0, x, w, u, gamma, B, K, X, iterations):
    """The hot path's root in a series step that starts at time t0 of a flight from the floor (x'(0) = u)
    in state (x, w = x'): Newton steps dt = -x/x' from the predictor s (time from the step's start),
    at most ``iterations``, inside (0, s_max].

    Accepted only when certified (as in :func:`bounce.exact.short_flight.short_flight`), with t = t0 + s the
    time from the floor and B the flight's curvature bound: (i) B (t + 2|dt| [x < 0]) <= 2 (u + |x'(t)|),
    so x > 0 on (0, t) (the parabolas x >= u r - B r^2/2 from the floor and x >= x(t) + |x'(t)| r - B r^2/2
    backwards from t cover it), and (ii) B dt^2 <= 8 eps scale, so |x(t + dt)| <= B dt^2/2 is below the
    rounding level of x; the root is then carried there to second order (:func:`_root_update`).  Returns
    (s, scale, D, D', D'', D''') at the root (D'' and D''' at the last Newton point), or s = 0 when no
    step is certified (the caller hands over or marches).
    """
    for _ in range(iterations):
        if not 0.0 < s <= s_max:
            break
        xs, vs, scale, D, Dp = _evaluate(s, x, 0.0, w, 0.0, gamma, 1.0, K, X)
        if not vs < 0.0:
            break
        dt = -xs / vs
        if B * dt * dt <= 8.0 * EPS * scale:
            if B * ((t0 + s) - 2.0 * min(dt, 0.0)) <= 2.0 * (u - vs):
                D2, D3 = curvature(s, 1.0, K, X)
                d, D, Dp = _root_update(dt, vs, gamma, D, Dp, D2, D3)
                return s + d, scale, D, Dp, D2, D3
            break
        s += dt
    return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0


@njit(cache=True)
def _hot_degree(h, w0, v, p0, q0, tol_x, tol_v, law):
    """(K, r_c, Rz, Rp) of a hot-path step of length h (:func:`_short_degree`; K = 0: none, and then
    r_c is the larger radius).

    The cheap first radius (:func:`bounce.series.taylor.cauchy_radius`) first; where it gives no
    degree <= ONCE_ABOVE, the one-shot comparison radius of eq. (C)
    (:func:`bounce.series.taylor.step_radius`, ~2x near the spring's turning point; it costs about
    as much as several degrees of the series, so deep in the asymptotic regime, where the degree is
    low, it is not formed).
    """
    radius, Rz, Rp = cauchy_radius(w0, v, p0, q0, 0.0, law[L_RHO], law[L_MU], law)
    theta = h / radius
    K = _short_degree(theta, Rz, Rp, tol_x, tol_v, ONCE_ABOVE)
    if K > 0:
        return K, radius, Rz, Rp
    r_step, Rz_step, Rp_step = step_radius(w0, v, p0, q0, 0.0, law[L_RHO], law[L_MU], law)
    K_step = _short_degree(h / r_step, Rz_step, Rp_step, tol_x, tol_v, DEGREE_SHORT)
    if K_step == 0 and not r_step > radius:
        return _short_degree(theta, Rz, Rp, tol_x, tol_v, DEGREE_SHORT), radius, Rz, Rp
    return K_step, r_step, Rz_step, Rp_step  # K_step = 0: the larger radius, for _split_flight's steps


@njit(cache=True)
def _split_flight(u, v, eta, law, X, P, Q, T, t_p, B, radius, Rz, Rp):
    """The hot path's flight over [0, T] in m = 2 or 3 equal series steps (:func:`short_flight`), or HANDOVER.

    Used where one step over the window is too long for the series (T/r_c > 1/4 or degree above
    DEGREE_SHORT), i.e. flights a few times longer than the deep regime's (Hertz drop: impacts ~1e3 ..
    2.5e3).  m is the least for which the first step, of length h = T/m, has a degree (its radius
    (radius, Rz, Rp) is the one-step's); each step's series is taken at the state the previous one
    ends in and has its own radius and degree, its tail below 2^-55 u T (x) and 2^-55 u (x') as the
    one step's (<= 3 of them: the state is exact to 3 2^-55 u T, below its rounding).

    No root is skipped.  The steps before the last end before 2u/B (else HANDOVER), where the parabola
    x >= u s - B s^2/2 of the flight's curvature bound B keeps x > 0: they need no evaluation but their
    end.  In the last step the root is found from the cubic model's root t_p and certified by
    :func:`_certified_root` (with the time from the flight's start); otherwise HANDOVER.
    """
    gamma = law[L_GAMMA]
    rho = law[L_RHO]
    mu = law[L_MU]
    tol_x = TOL * u * T
    tol_v = TOL * u
    m = 2
    while _short_degree(T / (m * radius), Rz, Rp, tol_x, tol_v, DEGREE_SHORT) == 0:
        m += 1
        if m > 3:
            return HANDOVER, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    h = T / m
    if not (m - 1) * h < 2.0 * u / B:
        return HANDOVER, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    x, w, vj, ej, tj = 0.0, u, v, eta, 0.0
    for j in range(m):
        xi0 = law[L_XI_EQ] + ej
        w0 = abs(xi0)
        if w0 == 0.0:
            return HANDOVER, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
        p0, q0 = powers_at(w0, law)
        if j == 0:  # the one-step's radius
            K = _short_degree(h / radius, Rz, Rp, tol_x, tol_v, DEGREE_SHORT)
        else:
            K, radius, Rz, Rp = _hot_degree(h, w0, vj, p0, q0, tol_x, tol_v, law)
        if K == 0:
            return HANDOVER, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
        taylor_coefficients(xi0, w0, vj, p0, q0, rho * (p0 if xi0 >= 0.0 else -p0), rho, mu, law, 1.0, K, X, P, Q)
        if j < m - 1:  # x > 0 on this step (it ends before 2u/B): its end state only
            x, w, _, D, Dp = _evaluate(h, x, 0.0, w, 0.0, gamma, 1.0, K, X)
            ej += vj * h + D
            vj += Dp
            tj += h
            continue
        s, scale, D, Dp, _, _ = _certified_root(t_p - tj, T - tj, tj, x, w, u, gamma, B, K, X, 6)
        if s > 0.0:
            return _contact(tj, 0.0, s, w - gamma * s - Dp, scale, ej, 0.0, vj, 0.0, gamma, D, Dp, 1.0, K, X,
                            (0.0, u, v, eta))
    return HANDOVER, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0


@njit(cache=True)
def _cubic_root(u, v, w0, sigma, p0, q0, xidd0, law):
    """t_p: the positive root of the cubic model u t + A t^2/2 + J t^3/6 of x from the floor, 0 if none.

    A = x''(0) = -gamma - xi''(0), J = x'''(0) = -xi'''(0) with, from eq. (S) (|xi|^a = p0/w0,
    |xi|^(b-1) = q0/w0), xi''' = -rho (a+1) |xi|^a xi' - 2 mu (xi'' |xi|^b + b sigma |xi|^(b-1) xi'^2).
    The root of u + A t/2 + J t^2/6 in the cancellation-free form 2u / (sqrt(A^2/4 - 2Ju/3) - A/2)
    needs A < 0 and a positive discriminant.  Only a predictor (:func:`short_flight`).
    """
    A = -law[L_GAMMA] - xidd0
    xiddd = (-(law[L_RHO] * law[L_AP1] * p0 * v + 2.0 * law[L_MU] * law[L_B] * sigma * q0 * v * v) / w0
             - 2.0 * law[L_MU] * xidd0 * q0)
    disc = 0.25 * A * A + (2.0 / 3.0) * xiddd * u
    if not (A < 0.0 and disc > 0.0):
        return 0.0
    return 2.0 * u / (math.sqrt(disc) - 0.5 * A)


@njit(cache=True)
def short_flight(u, v, eta, law, X, P, Q):
    """First contact of a flight from the floor (x = 0, x' = u > 0) as one series step.

    Returns what :func:`first_contact` returns, or status HANDOVER when the flight
    is not one short step (then the caller runs :func:`first_contact`).

    Predictor: the root t_p of the cubic model of x (:func:`_cubic_root`, from eq. (S) at the
    start; for the Hertz drop of benchmarks/bench_power.py the flight is within 0.3% of it from
    impact 3e3 on, 2.4% at impact 1e3).  Window T = WINDOW t_p (no larger than
    2.5 u / (gamma + |xi''(0)|), which is also the window when the model has no root): the window
    only says where the series is valid and evaluated, so a root beyond it is a HANDOVER and a
    poor predictor costs time, never an impact.  Degree K <= DEGREE_SHORT the least for which the
    tail bounds on [0, T] are below 2^-55 u T (x) and 2^-55 u (x'), with the cheap first radius
    or the one-shot comparison radius of eq. (C) (:func:`_hot_degree`); else two or three steps
    (:func:`_split_flight`) or HANDOVER.  From t_p, Newton steps certified as in
    :func:`bounce.exact.short_flight.short_flight` (:func:`_certified_root`).  Otherwise the safe march.
    """
    gamma = law[L_GAMMA]
    rho = law[L_RHO]
    mu = law[L_MU]
    xi0 = law[L_XI_EQ] + eta
    w0 = abs(xi0)
    if w0 == 0.0:
        return HANDOVER, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    p0, q0 = powers_at(w0, law)
    sigma = 1.0 if xi0 > 0.0 else -1.0
    xidd0 = -rho * sigma * p0 - 2.0 * mu * v * q0
    T = 2.5 * u / (gamma + abs(xidd0))
    t_p = _cubic_root(u, v, w0, sigma, p0, q0, xidd0, law)
    if t_p > 0.0:
        T = min(T, WINDOW * t_p)
    tol_x = TOL * u * T
    tol_v = TOL * u
    K, radius, Rz, Rp = _hot_degree(T, w0, v, p0, q0, tol_x, tol_v, law)
    B = _curvature_bound_near(w0, v, p0, q0, law)
    if K == 0:
        if t_p > 0.0:
            return _split_flight(u, v, eta, law, X, P, Q, T, t_p, B, radius, Rz, Rp)
        return HANDOVER, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    taylor_coefficients(xi0, w0, v, p0, q0, rho * sigma * p0, rho, mu, law, 1.0, K, X, P, Q)
    t, scale, D, Dp, D2, D3 = _certified_root(t_p, T, 0.0, 0.0, u, u, gamma, B, K, X, 4)
    if t > 0.0:
        return FOUND, t, u - gamma * t - Dp, scale, eta + v * t + D, v + Dp, -gamma - D2, -D3
    # general march from the first safe step
    s = 2.0 * u / B
    if s > T:
        return HANDOVER, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    for _ in range(64):
        xs, vs, scale, D, Dp = _evaluate(s, 0.0, 0.0, u, 0.0, gamma, 1.0, K, X)
        if xs <= 4.0 * EPS * scale:
            break
        s_new = s + safe_step(xs, vs, B)
        if s_new > T or vs >= 0.0:
            return HANDOVER, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
        if s_new == s:
            break
        s = s_new
    else:
        return HANDOVER, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    if vs < 0.0:
        s -= xs / vs
        xs, vs, scale, D, Dp = _evaluate(s, 0.0, 0.0, u, 0.0, gamma, 1.0, K, X)
    return _contact(0.0, 0.0, s, vs, scale, eta, 0.0, v, 0.0, gamma, D, Dp, 1.0, K, X, (0.0, u, v, eta))

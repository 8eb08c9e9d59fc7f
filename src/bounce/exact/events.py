"""The event loop: flights, impacts, grazings and sticky phases (numba kernel).

State between events, in the deviation variables of :mod:`bounce.exact.flight`:
(x, u = xdot, a = xi', eta = xi + gamma).  At an event x = 0 and

* **impact** (eq. ``collision-rule``): psi' and xi' are exchanged, i.e.
  u -> -x'(tau), a -> psi'(tau^-) = u + a - gamma tau, eta -> xi(tau) + gamma;
* **grazing** (eq. ``swishes``): x = x' = 0 with x'' > 0: nothing is exchanged,
  the flight goes on (recorded, lift-off restart);
* **sticky_start** (eq. ``sticky-condition``): x = x' = x'' = 0; the lower mass
  rests on the floor and y obeys eq. ``y-eq-sticky``.  In eta this is
  eta'' + mu eta' + eta/2 = 0, i.e. the unit oscillator with damping mu/sqrt(2)
  in the time s = t/sqrt(2).  The floor force (eq. ``force-on-the-floor``) is
  F = G - 2 gamma with G = eta + 2 mu eta', which solves the same equation;
* **detach** (eq. ``cond_di_distacco``): the first F = 0 with F' > 0, i.e. the
  first return of G to 2 gamma.  The detach search is the flight root finder on
  the gap 2 gamma - G (g = 0 in eq. (F)); if the amplitude envelope
  sqrt(G^2 + G_s^2), which never increases, falls below 2 gamma, G can never
  return and the sticky phase is proved infinite.  From mu = 2 on (damping ratio
  mu/sqrt(2) >= sqrt(2)) G is followed in its two exponential modes instead: there
  G(0) and G'(0) carry the damping force 2 mu xi' and 2 mu^2 xi', terms that a gap
  of 2 gamma cannot be resolved against (mu = 1e7, xi' = -1/2: ~3e13 cancelling to
  ~1e7 in eq. (F), beside 2 gamma = 2e-3), while the modes are O(F) themselves.

Zero-speed contacts.  Rounding leaves x uncertain by ``xn = 4 eps scale``; near a
tangency this hides a time window delta, and with it a speed.  A contact whose
speed |x'| is below what that window can resolve, 4 max(|x''| delta2, |x'''|
delta3^2 / 2) with delta2 = sqrt(2 xn/|x''|), delta3 = (6 xn/|x'''|)^(1/3), is
treated as tangential (approximation at the rounding level; generic impacts are
many orders of magnitude faster).  It is a sticky onset if also
x'' <= 4 |x'''| delta3, or if x'' < 0 beyond that window (at x = x' = 0, x'' is the
floor force F: the floor holds a mass pressed onto it), and a grazing otherwise.
The rounding level has an absolute floor of 1e-300: heights below it, where
products such as x'' x underflow, are the floor itself.  A state dropped from
x ~ 1e-300 therefore comes to rest (sticky_start) instead of chattering through
1e6 impacts of speed 1e-151 in 1e-143 time units.

Time is accumulated with Neumaier's compensated sum so that t stays correctly
rounded after 1e6+ short flights; the flight durations are stored exactly.  The
one exception is a tie of rounding decided by bits the compensation term lost:
only when the phases span more than 2^53 in size (a first phase of 3e-162, then
phases of order 1), and then t is within 1 ulp of the exact sum.  A
phase shorter than half an ulp of t leaves t unchanged (consecutive event times
coincide, tau stays exact): the netCDF attribute of t says so.

Energy balance without damping (mu = 0): the dynamics conserves E - E_m; the
recorded states carry rounding, an unbiased walk of ~1 eps E per impact plus a
measured bias of +0.03 eps E per impact (psi(0) = 6, gamma = 0.01: +8.3e-13 after
2e6 impacts, growing linearly, i.e. ~4e-12 after 1e7), traced against mpmath to the rounding of
the spring state in the flight map, not to the contact time (whose residual has
no significant bias) nor to c^2 + S^2 (no bias).  tests/exact/test_edges.py bounds it.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..model import check_supported
from ..trajectory import run_into_trajectory, stop_rules
from ..kinds import (DETACH, GRAZING, IMPACT, STICKY_START, STOP_ENERGY, STOP_EVENTS, STOP_FAILED,
                     STOP_STICKY_FOREVER, STOP_TIME)
from .flight import (
    EPS,
    FAILED,
    FOUND,
    HORIZON,
    NEVER,
    first_contact,
    flight_spring,
    liftoff_time,
    oscillator_at,
    xi_derivatives,
)
from .oscillator import OVER, P_BRANCH, P_FREQ, P_LFAST, P_LSLOW, P_MU, P_RHO, make_oscillator, oscillator_tables
from .short_flight import HANDOVER, MAX_DEGREE, short_flight


SQRT2 = math.sqrt(2.0)
#: cap on the Newton steps of :func:`_sticky_modes`: from s = 0 each step gains ~1/L while the fast mode
#: dominates, i.e. ln(|Q| / |P - 2 gamma|) <= ~750 steps (the range of float64), then it converges quadratically
MODE_NEWTON_STEPS = 1000

# zero-speed contacts (module docstring): x is known to xn = XN_ULPS eps scale; a contact is tangential
# if its speed is below WINDOW_FACTOR times what the hidden window resolves, in powers:
# v^2 <= TANGENT_ACC |x''| xn or |v|^3 <= TANGENT_JERK |x'''| xn^2; it is a sticky onset if also
# x''^3 <= STICKY_ONSET x'''^2 xn (x'' <= WINDOW_FACTOR |x'''| delta3)
XN_ULPS = 4.0
WINDOW_FACTOR = 4.0
TANGENT_ACC = 2.0 * WINDOW_FACTOR**2  # (4 |x''| delta2)^2 = 32 |x''| xn
TANGENT_JERK = 4.5 * WINDOW_FACTOR**3  # (4 |x'''| delta3^2/2)^3 = 288 |x'''| xn^2
STICKY_ONSET = 6.0 * WINDOW_FACTOR**3  # (4 |x'''| delta3)^3 = 384 x'''^2 xn

# slots of the loop state carried between chunks (run_events' ``carry``): the state after the last
# event, the compensated time (hi, lo), the pending lift-off delay, whether the lower mass rests on
# the floor, and whether the array holds a state to resume from
C_X, C_U, C_A, C_ETA, C_T_HI, C_T_LO, C_T_START, C_STICKY, C_RESUME = range(9)
CARRY_SIZE = 9


@njit(cache=True)
def energy_excess(x, u, a, eta, gamma):
    """E - E_m = (xi'^2 + psi'^2 + eta^2)/2 + gamma x  (eqs. tot-mech-energy, Emin)."""
    return 0.5 * (a * a + (u + a) * (u + a) + eta * eta) + gamma * x


@njit(cache=True)
def floor_force(a, eta, gamma, mu):
    """F and F' (eq. force-on-the-floor) for a state at rest on the floor."""
    G = eta + 2.0 * mu * a
    # eta'' = -mu eta' - eta/2  =>  G' = a + 2 mu (-mu a - eta/2)
    Gp = a * (1.0 - 2.0 * mu * mu) - mu * eta
    return G - 2.0 * gamma, Gp


@njit(cache=True)
def compensated_add(hi, lo, dt):
    """Neumaier compensated addition (hi, lo) + dt."""
    s = hi + dt
    if abs(hi) >= abs(dt):
        lo += (hi - s) + dt
    else:
        lo += (dt - s) + hi
    return s, lo


@njit(cache=True)
def record_event(i, t, tau, kind, u, a, eta, e, out_t, out_tau, out_u, out_a, out_eta, out_e, out_kind):
    """Write event i of an event loop: time, phase duration, state after it, E - E_m (``e``, of the
    loop's spring law) and kind (shared by every spring law's event loop)."""
    out_t[i] = t
    out_tau[i] = tau
    out_u[i] = u
    out_a[i] = a
    out_eta[i] = eta
    out_e[i] = e
    out_kind[i] = kind


@njit(cache=True)
def _sticky_phase(a, eta, gamma, t_limit, sparams, scoefs):
    """Duration of a sticky phase starting from (a, eta) and the state at detachment.

    Returns ``(status, duration, a_d, eta_d)``; status FOUND (detach), HORIZON
    (still sticky at t_limit) or NEVER (infinite sticky phase, proved).  A strongly
    over-damped sticky oscillator (damping ratio mu/sqrt(2) >= sqrt(2)) is followed
    in its two modes (:func:`_sticky_modes`), any other by the flight root finder on
    the gap 2 gamma - G (module docstring): its terms stay within a few |G0| + |G0'|,
    while those of a stiff one reach 2 mu^2 |xi'| (3e13 at mu = 1e7) and leave the
    sign of a gap of 2 gamma unresolved.
    """
    mu = sparams[P_MU] * SQRT2
    # scaled time s = t / sqrt(2): eta_s = sqrt(2) eta'
    es0 = SQRT2 * a
    G0 = eta + 2.0 * mu * a
    Gs0 = es0 * (1.0 - 2.0 * mu * mu) - SQRT2 * mu * eta
    # F(0) and F'(0) within rounding of zero are zero (approximation at the rounding level)
    x0 = max(0.0, 2.0 * gamma - G0)
    if x0 <= 8.0 * EPS * (abs(eta) + 2.0 * mu * abs(a) + 2.0 * gamma):
        x0 = 0.0
    if abs(Gs0) <= 8.0 * EPS * (abs(es0) * (1.0 + 2.0 * mu * mu) + SQRT2 * mu * abs(eta)):
        Gs0 = 0.0
    if x0 == 0.0 and Gs0 > 0.0:
        return FOUND, 0.0, a, eta  # F = 0, F' > 0: detach at once (eq. cond_di_distacco)
    if sparams[P_BRANCH] == OVER and sparams[P_FREQ] >= 1.0:
        return _sticky_modes(a, eta, gamma, t_limit, sparams)
    s_start = 0.0
    if x0 == 0.0 and Gs0 == 0.0:
        # F = F' = 0: F'' = -G < 0 (paper, after eq. cond_di_distacco), the gap opens like s^2
        s_start = liftoff_time(-Gs0, Gs0, G0, 0.0, sparams, 0.0)  # its F = G0 > 0
    status, s, _, _, omc, _, _, _, S, Sd, _ = first_contact(
        s_start, t_limit / SQRT2, x0, -Gs0, Gs0, G0, 0.0, sparams, scoefs
    )
    if status != FOUND:
        return status, s * SQRT2, a, eta
    eta_d, es_d = oscillator_at(eta, es0, omc, S, Sd)
    return FOUND, s * SQRT2, es_d / SQRT2, eta_d


@njit(cache=True)
def _sticky_modes(a, eta, gamma, t_limit, sparams):
    """:func:`_sticky_phase` of a strongly over-damped sticky oscillator (kappa >= 1), in its modes.

    In s = t/sqrt(2), eta = A e^{-l s} + B e^{-L s} with the slow and fast rates l = 1/L, L = beta + kappa
    (beta = mu/sqrt(2), kappa = sqrt(beta^2 - 1)), A = (eta_s + L eta)/(2 kappa), B = -(eta_s + l eta)/(2 kappa);
    G = eta + 2 beta eta_s = -eta_ss (eq. force-on-the-floor), so

        F(s) = P e^{-l s} + Q e^{-L s} - 2 gamma,    P = -l^2 A,  Q = -L^2 B,

    every term formed from the state (a, eta) without cancellation (kappa >= 1: |A| + |B| <= |eta_s| +
    sqrt(2) |eta|).  F' = -l P e^{-l s} - L Q e^{-L s} vanishes at most once, and F tends to -2 gamma; so
    the phase (F(0) <= 0) ends iff P > 0 > Q and F > 0 at the maximum s* = ln(L |Q| / (l P)) / (2 kappa) > 0,
    and then at the one root in (0, s*), where F is increasing and concave (its inflection lies beyond s*):
    Newton from the left converges monotonically to it.  Invariant: F is never formed from G(0) and G'(0),
    whose terms (2 mu xi' and 2 mu^2 xi') exceed F by up to 1e16 at mu = 1e8.  Error bound: F(s) to a few
    ulps of |P| e^{-l s} (1 + l s) + |Q| e^{-L s} (1 + L s) + 2 gamma (the factors: the rounding of the
    exponents), plus the sensitivity of A and B to the half ulps of a and eta (the input's own); the detach
    time to that over F' there (1e-12 relative against mpmath in tests/exact/test_edges.py).  A maximum within
    8 ulps of its terms counts as F < 0 (a tangency, not a crossing: approximation at the rounding level,
    as for contacts).
    """
    beta = sparams[P_MU]
    kappa = sparams[P_FREQ]
    lam = sparams[P_LSLOW]
    Lam = sparams[P_LFAST]
    es0 = SQRT2 * a
    A = (es0 + Lam * eta) / (2.0 * kappa)
    B = -(es0 + lam * eta) / (2.0 * kappa)
    P = -lam * lam * A
    Q = -Lam * Lam * B
    if not (P > 0.0 and Q < 0.0):
        return NEVER, t_limit, a, eta  # F monotone, or a minimum: below max(F(0), -2 gamma) <= 0
    s_max = (math.log(Lam / lam) + math.log(-Q) - math.log(P)) / (2.0 * kappa)
    if not s_max > 0.0:
        return NEVER, t_limit, a, eta  # F decreasing from F(0) <= 0
    slow, fast = P * math.exp(-lam * s_max), Q * math.exp(-Lam * s_max)
    if slow + fast - 2.0 * gamma <= 8.0 * EPS * (slow - fast + 2.0 * gamma):
        return NEVER, t_limit, a, eta
    s_limit = t_limit / SQRT2
    s = 0.0
    for _ in range(MODE_NEWTON_STEPS):
        slow, fast = P * math.exp(-lam * s), Q * math.exp(-Lam * s)
        F = slow + fast - 2.0 * gamma
        if F >= 0.0:
            break  # a root within rounding: concave F puts every Newton iterate left of it
        step = -F / (-lam * slow - Lam * fast)
        if step <= 2.0 * EPS * s or s > s_limit:
            s = min(s + step, s_max)
            break
        s = min(s + step, s_max)
    else:
        return FAILED, t_limit, a, eta
    if s > s_limit:
        return HORIZON, t_limit, a, eta
    e_slow, e_fast = A * math.exp(-lam * s), B * math.exp(-Lam * s)
    return FOUND, s * SQRT2, (-lam * e_slow - Lam * e_fast) / SQRT2, e_slow + e_fast


@njit(cache=True)
def _floor_force_noise(a, eta, gamma, mu):
    """8 eps of the terms of F = eta + 2 mu xi' - 2 gamma: the rounding of forming it (:func:`_at_rest_is_sticky`)."""
    return 8.0 * EPS * (abs(eta) + 2.0 * mu * abs(a) + 2.0 * gamma)


@njit(cache=True)
def _at_rest_is_sticky(a, eta, gamma, mu):
    """For x = x' = 0: does the lower mass stay on the floor (F < 0, or F = 0, F' <= 0)?

    F = eta + 2 mu xi' - 2 gamma is taken as zero within 8 eps of its terms, F' within
    8 eps of its own: the rounding of forming them (approximation at the rounding level).
    The threshold is relative to the terms' scale, never absolute: a floor force of
    1e-9 gamma decides the motion at every gamma.  A state given as heights converts
    to eta with one rounding relative to eta (y - x - 1 is exact for y - x in [1/2, 2]),
    so this is also the input's own uncertainty.
    """
    F, Fp = floor_force(a, eta, gamma, mu)
    noise = _floor_force_noise(a, eta, gamma, mu)
    if F > noise:
        return False
    if F < -noise:
        return True
    # F = 0: stays if F' < 0, or F' = 0 too (then F'' = -gamma < 0, paper after eq. cond_di_distacco)
    return Fp <= 8.0 * EPS * (abs(a) * (1.0 + 2.0 * mu * mu) + mu * abs(eta))


@njit(cache=True)
def _is_tangential(v, acc, jerk, xn):
    """Is the contact speed |v| below what the rounding level xn of x resolves?

    Near a tangency x ~ acc s^2/2 (or |jerk| s^3/6) stays hidden under xn for a
    window delta2 = sqrt(2 xn/|acc|) (delta3 = (6 xn/|jerk|)^(1/3)), in which the
    speed reaches |acc| delta2 (|jerk| delta3^2/2).  Contacts slower than four
    times either are tangential.  Compared in powers: no root on the hot path.
    """
    if v >= 0.0:
        return True
    v2 = v * v
    if v2 <= TANGENT_ACC * abs(acc) * xn:
        return True
    cube = v2 * abs(v)
    if cube < 1e-290:
        # |v|^3 underflows (|v| < 1e-97): 0 <= 0 made an impact at x' = -1.3e-114 with a zero jerk a sticky
        # start that kept xi' and doubled E - E_m (found by the power-law fuzz); compared scaled by xn^2
        return (v2 / xn) * (abs(v) / xn) <= TANGENT_JERK * abs(jerk)
    return cube <= TANGENT_JERK * abs(jerk) * xn * xn


@njit(cache=True)
def _is_sticky_onset(acc, jerk, xn):
    """Tangential contact with x'' = 0 within the window delta3 and x''' < 0, or with
    x'' = F < 0 beyond that window (pressed onto the floor)."""
    window = STICKY_ONSET * jerk * jerk * xn
    return (jerk < 0.0 and acc * acc * acc <= window) or acc * acc * acc < -window


@njit(cache=True)
def contact(v, acc, jerk, scale, u, a, gamma, tau, eta_t, xid_t):
    """The state just after a contact reached with speed v and x'', x''' = acc, jerk, after a flight
    of duration tau from (u, a) that ends with the spring at (eta_t, xid_t): ``(kind, u, a, eta)``.

    An impact (eq. ``collision-rule``) exchanges psi' and xi': u -> -v, a -> psi'(tau^-) = u + a -
    gamma tau.  A tangential contact (:func:`_is_tangential` at the rounding level of ``scale``)
    exchanges nothing (psi' = xi' there): a sticky onset if :func:`_is_sticky_onset`, a grazing
    otherwise.  Shared by every spring law's event loop (the impact rule does not involve the spring).
    """
    xn = rounding_level(scale)
    if not _is_tangential(v, acc, jerk, xn):
        return IMPACT, -v, u + a - gamma * tau, eta_t
    return (STICKY_START if _is_sticky_onset(acc, jerk, xn) else GRAZING), 0.0, xid_t, eta_t


@njit(cache=True)
def rounding_level(scale):
    """xn = XN_ULPS eps scale: how well x is known at a contact (scale: the magnitudes of eq. (F)'s terms)."""
    return XN_ULPS * EPS * scale + 1e-300


def contact_window(scale: float, acc: float, jerk: float) -> tuple[float, float, float, float]:
    """(xn, v_tol, delta2, delta3) of the contact classifier at a contact with x'' = acc, x''' = jerk.

    Contacts slower than v_tol are tangential (:func:`_is_tangential`); delta2 = sqrt(2 xn/|x''|) and
    delta3 = (6 xn/|x'''|)^(1/3) are the windows in which rounding hides the contact time (inf for a zero
    derivative).  For the claims about the classifier; the loop uses the same constants.
    """
    xn = rounding_level(scale)
    v_tol = max(math.sqrt(TANGENT_ACC * abs(acc) * xn), (TANGENT_JERK * abs(jerk) * xn * xn) ** (1.0 / 3.0))
    d2 = math.sqrt(2.0 * xn / abs(acc)) if acc != 0 else math.inf
    d3 = (6.0 * xn / abs(jerk)) ** (1.0 / 3.0) if jerk != 0 else math.inf
    return xn, v_tol, d2, d3


@njit(cache=True)
def run_events(
    x0, u, a, eta, gamma, params, coefs, sparams, scoefs,
    max_events, t_max, e_stop,
    out_t, out_tau, out_u, out_a, out_eta, out_e, out_kind, carry=None,
):
    """Advance the state (x0, u, a, eta) from t = 0 and record every event.

    Stops after ``max_events`` records, at ``t_max``, once E - E_m < ``e_stop``, or
    when a sticky phase is proved infinite.  Output arrays (length >= max_events)
    receive per event: t, the duration of the phase ending at it, the state just
    after it (u = xdot, a = xi', eta = xi + gamma), E - E_m and the kind.
    Returns ``(n_events, stop_reason, t_end)``.  ``sparams, scoefs`` (the tables of mu/sqrt(2)) may be
    empty (``scoefs.shape[0] == 0``): they are then built at the first sticky phase, once (compiled loops
    over many dampings, whose trajectories rarely stick, save a table build per trajectory).

    ``carry`` (optional, float64[CARRY_SIZE]) chains calls: on return it holds the
    loop's whole state (slots ``C_*``); passed again with ``carry[C_RESUME] = 1`` the
    loop resumes from it (x0, u, a, eta are then ignored), so N calls of n events
    give the bits of one call of N n events (t_max is measured from t = 0).
    """
    mu = params[P_MU]
    rho = params[P_RHO]
    work = np.empty(MAX_DEGREE + 2)
    t_hi = 0.0
    t_lo = 0.0
    n = 0
    sticky = False
    t_start = 0.0
    stop = STOP_EVENTS
    lazy_params = np.empty(0)  # the tables of mu/sqrt(2) when the caller left them to be built (see above)
    lazy_coefs = np.empty((0, 0))
    if carry is not None and carry[C_RESUME] != 0.0:
        x0, u, a, eta = carry[C_X], carry[C_U], carry[C_A], carry[C_ETA]
        t_hi, t_lo, t_start = carry[C_T_HI], carry[C_T_LO], carry[C_T_START]
        sticky = carry[C_STICKY] != 0.0
    elif x0 == 0.0 and u == 0.0:
        if _at_rest_is_sticky(a, eta, gamma, mu):
            sticky = True
            record_event(0, 0.0, 0.0, STICKY_START, u, a, eta, energy_excess(0.0, u, a, eta, gamma),
                         out_t, out_tau, out_u, out_a, out_eta, out_e, out_kind)
            n = 1
        else:
            t_start = liftoff_time(u, a, eta, gamma, params, _floor_force_noise(a, eta, gamma, mu))
    while n < max_events:
        t_limit = t_max - (t_hi + t_lo)
        if sticky:
            if scoefs.shape[0] != 0:
                status, tau, a, eta = _sticky_phase(a, eta, gamma, t_limit, sparams, scoefs)
            else:
                if lazy_coefs.shape[0] == 0:
                    lazy_params, lazy_coefs = oscillator_tables(mu / SQRT2)
                status, tau, a, eta = _sticky_phase(a, eta, gamma, t_limit, lazy_params, lazy_coefs)
            if status != FOUND:
                stop = STOP_STICKY_FOREVER if status == NEVER else (
                    STOP_TIME if status == HORIZON else STOP_FAILED)
                break
            kind = DETACH
            x0 = 0.0
            u = 0.0
            sticky = False
            t_start = liftoff_time(u, a, eta, gamma, params, math.inf)  # F = 0 at the detach root, to its accuracy
        else:
            status = HANDOVER
            if x0 == 0.0 and t_start == 0.0 and u > 0.0:
                status, tau, v, scale, dxi, xid_t = short_flight(u, a, eta, gamma, mu, rho, work)
                if status == HANDOVER:
                    t_start = tau
                elif tau > t_limit:
                    stop = STOP_TIME
                    break
            if status == HANDOVER:
                status, tau, v, scale, omc, tms, omsd, c, S, Sd, _ = first_contact(
                    t_start, t_limit, x0, u, a, eta, gamma, params, coefs
                )
                if status != FOUND:
                    stop = STOP_TIME if status == HORIZON else STOP_FAILED
                    break
                eta_t, xid_t = flight_spring(eta, a, gamma, omc, c, S, Sd)  # xi(tau) + gamma, xi'(tau)
            else:
                eta_t = eta + dxi  # short flight: xi(tau) + gamma from the small displacement
            x0 = 0.0
            t_start = 0.0
            # x'' = -gamma - xi'' and x''' = -xi''' just before the contact
            _, xidd, xiddd, _ = xi_derivatives(eta_t - gamma, xid_t, mu)
            acc = -gamma - xidd
            jerk = -xiddd
            kind, u, a, eta = contact(v, acc, jerk, scale, u, a, gamma, tau, eta_t, xid_t)
            if kind == STICKY_START:
                sticky = True
            elif kind == GRAZING:  # F = acc >= -(STICKY_ONSET jerk^2 xn)^(1/3) (_is_sticky_onset)
                window = (STICKY_ONSET * jerk * jerk * rounding_level(scale)) ** (1.0 / 3.0)
                t_start = liftoff_time(u, a, eta, gamma, params, window)
        t_hi, t_lo = compensated_add(t_hi, t_lo, tau)
        record_event(n, t_hi + t_lo, tau, kind, u, a, eta, energy_excess(0.0, u, a, eta, gamma),
                     out_t, out_tau, out_u, out_a, out_eta, out_e, out_kind)
        n += 1
        if out_e[n - 1] < e_stop:
            stop = STOP_ENERGY
            break
    if carry is not None:
        carry[C_X], carry[C_U], carry[C_A], carry[C_ETA] = x0, u, a, eta
        carry[C_T_HI], carry[C_T_LO], carry[C_T_START] = t_hi, t_lo, t_start
        carry[C_STICKY] = 1.0 if sticky else 0.0
        carry[C_RESUME] = 1.0
    return n, stop, t_hi + t_lo


def _tables(mu: float) -> tuple:
    """The oscillator tables :func:`run_events` takes: those of mu (flights), then of mu/sqrt(2) (sticky phases)."""
    return (*make_oscillator(mu), *make_oscillator(mu / SQRT2))


@njit(cache=True)
def _first_events(u, a, eta, gamma, params, coefs, sparams, scoefs, kind, tau, u_after):
    """:func:`run_events` with max_events = 1 from each state (x = 0, u[i], a[i], eta[i]) at t = 0, into
    ``kind`` (-1: no event), ``tau`` and ``u_after``; returns the index of the first failed search, or -1."""
    out = [np.empty(1) for _ in range(6)]
    out_kind = np.empty(1, dtype=np.int8)
    for i in range(u.size):
        n, stop, _ = run_events(0.0, u[i], a[i], eta[i], gamma, params, coefs, sparams, scoefs, 1, math.inf, 0.0,
                                out[0], out[1], out[2], out[3], out[4], out[5], out_kind)
        if stop == STOP_FAILED:
            return i
        kind[i] = out_kind[0] if n == 1 else -1
        tau[i] = out[1][0]
        u_after[i] = out[2][0]
    return -1


def first_events_linear(params, u, a, eta):
    """The first event after each state (x = 0, x' = u[i], xi' = a[i], xi + gamma = eta[i]) at t = 0: its kind (-1
    if none), duration and x' after it, the bits of ``simulate(params, Deviations(0, u[i], a[i], eta[i]),
    max_events=1)`` (the same loop, :func:`run_events`) in one compiled call.  For states of a supported run's
    records (no domain check here); a failed root search raises, as in :func:`simulate_linear`."""
    u, a, eta = (np.ascontiguousarray(v, dtype=np.float64) for v in (u, a, eta))
    kind, tau, u_after = np.full(u.size, -1, dtype=np.int8), np.full(u.size, np.nan), np.full(u.size, np.nan)
    failed = _first_events(u, a, eta, params.gamma, *_tables(params.mu), kind, tau, u_after)
    if failed >= 0:
        raise RuntimeError(f"root finder did not converge from state {failed} (x' = {u[failed]!r}); please report the "
                           "parameters and initial state")
    return kind, tau, u_after


def simulate_linear(params, initial, max_events: int = 1000, t_max: float = math.inf, energy_stop: float = 0.0):
    """Simulate the paper's linear spring from ``initial`` (a :class:`bounce.model.State`, or
    :class:`bounce.model.Deviations`): validated stop rules and supported domain
    (:func:`bounce.model.check_supported`), the oscillator tables of mu and mu/sqrt(2) (flights, sticky
    phases), then :func:`run_events` into a :class:`bounce.trajectory.Trajectory`."""
    max_events, t_max, energy_stop = stop_rules(max_events, t_max, energy_stop)
    start = initial.deviations(params)
    check_supported(params, start)
    tables = _tables(params.mu)
    return run_into_trajectory(
        lambda *buffers: run_events(start.x, start.xdot, start.xidot, start.eta, params.gamma, *tables,
                                    max_events, t_max, energy_stop, *buffers),
        params, initial, (max_events, t_max, energy_stop), "root finder")

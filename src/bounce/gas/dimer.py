"""The exact event-driven engine of a gas of two-mass grains (dimers): numba kernels.

The model (issue 23; each grain is the paper's ball, section 2).  Grain k has a lower mass x_k and an
upper mass y_k = x_k + 1 + 2 xi_k; in its own variables psi'' = -gamma, xi'' = -xi - 2 mu xi'
(eq. ``eq-motion-psi-xi``), so between events every grain moves in closed form.  Contacts:

* the floor (column, gamma > 0): x_0 = 0, the paper's impact rule (eq. ``collision-rule``),
  applied exactly as the single-ball loop does (:func:`bounce.exact.events.contact`);
* a pair of neighbours, y_k = x_{k+1} (the ring's seam included): an elastic impact of two equal
  point masses, which exchange their velocities.  With w = x_{k+1}' - y_k' < 0 the gap's velocity,
  in the deviation variables this is  xi_k' += w/2, xi_{k+1}' += w/2, x_{k+1}' -= w  (x_k' and
  y_{k+1}' unchanged).  Energy and momentum are conserved: all dissipation is inside the grains.

State, per grain, as the single-ball core carries it (:mod:`bounce.exact.flight`): its local time stamp
(double-double), x = x_k, u = x_k', a = xi_k', eta = xi_k + gamma, so that the floor contact of grain 0
keeps the digits of the single ball deep in its asymptotic regime.  Grains are advanced lazily: only
the grains an event involves, and the neighbours whose predictions it invalidates, are brought to the
event's time (eq. (F) of :mod:`bounce.exact.flight` and :func:`bounce.exact.flight.flight_spring`).

The gap between neighbours is the floor gap's class of function.  With s = xi_k + xi_{k+1}, which
solves the grains' common damped equation (same mu), and Dpsi = psi_{k+1} - psi_k, linear in time (same
gravity),

    x_{k+1} - y_k = (gap at 0) + w t + s'(0) (t - S) + s(0) (1 - c)                       (G)

which is eq. (F) with g = 0, u = w, a = s'(0), eta = s(0).  So the first-contact root finder of the
single ball applies unchanged (:func:`bounce.exact.flight.first_contact`): its curvature bound is
|gap''| = |s''| <= sqrt(s''(0)^2 + min(s'(0)^2, s'''(0)^2)) (the non-increasing energy of any
solution of the damped equation, applied to s'' and its neighbours), so a safe step never passes a
root, and a dip of the gap below zero is missed only if it is shallower than the gap's rounding.  A
pair's search is confined to where a contact can be: with A = sqrt(s^2 + s'^2) (|s(t)| <= A for
t >= 0) the gap lies between (gap at 0) + s(0) + Dpsi' t -/+ A.  With Dpsi' = w + s' > 0 it is
positive beyond T* = (A - s(0) - gap)/Dpsi' (no contact ever if T* <= 0); with Dpsi' < 0 a contact
comes before T* = (gap + s(0) + A)/|Dpsi'| and none before (gap + s(0) - A)/|Dpsi'|, where the
search starts (two grains drifting together at 1e-10 with springs ringing at 0.1 would otherwise
be marched through 4e11 time units, a few steps per spring period); with Dpsi' = 0 the root finder's
bounded mode proves a contact impossible once A drops below the level.  The floor's search
is the single ball's, hot path included (:func:`bounce.exact.short_flight.short_flight` for a flight from
the floor), so one grain on the floor gives the records of :func:`bounce.simulate` bit for bit.

Rounding.  A pair's gap at the start of a prediction is a difference of positions, known to
``4 eps (|x_{k+1}| + ell [seam] + |y_k|)``; a gap within that of zero is zero (approximation at the
rounding level): approaching, the contact is now; separating, the flight starts.  Right after a pair's
own contact its gap is exactly zero and its velocity exactly -w, whatever the positions' rounding.  So
a pair's contacts are resolved to that rounding: the time of a contact approached at speed w to
~8 eps max|x| / w.  On a ring with net momentum the positions grow like the centre of mass's velocity
times t and the resolution degrades with them (start rings with zero total momentum).

Zero-speed contacts.  The floor's are classified as the single ball's (:mod:`bounce.exact.events`):
a grazing exchanges nothing, a sticky onset (eq. ``sticky-condition``) stops the run.  A pair contact
is classified with the same rounding windows (:func:`bounce.exact.events.contact`'s), at the rounding
level of its gap:

* approaching (w < 0): an impact, whatever the speed (a grazing would let the masses pass each other
  by up to 16 times the rounding level, the depth of the dip the window allows), unless the contact
  is tangential with gap'' < 0 (a sticky onset: the masses pressed together at zero speed, eq.
  ``sticky-condition``'s pair analogue), which is non-generic (Theorem ``contact-non-generic``) and
  stops the run (:data:`~bounce.gas.common.STOP_STICKY`): this engine follows no sticky phase;
* not approaching (a tangential minimum of the gap): a grazing, nothing exchanged;
* relaxed: a tangential contact whose springs' sum s has an amplitude sqrt(s^2 + s'^2) below the
  rounding level.  Nothing resolvable moves the two touching masses; it is recorded as a grazing and
  the pair predicts no contact until an event changes one of its grains.  This is how a collision of
  two grains with relaxed springs ends when mu >= 1: the gap is |w| S(t) > 0 (S the oscillator's
  fundamental solution, positive for mu >= 1), decaying to zero without reaching it.

Grains' own masses never pass.  Between its events a grain's spring is a damped oscillator whose
energy (xi^2 + xi'^2)/2 never increases, and y_k - x_k = 1 + 2 xi_k > 0 as long as |xi_k| < 1/2: the
paper's energy condition (eq. ``max-ini-energy``) applied to each grain's internal energy,
xi^2 + xi'^2 < 1/4.  Only events change it (an exchange changes xi'), so it is checked after every
event for the grains involved; the run stops (:data:`~bounce.gas.common.STOP_OVERLAP`, naming the
grain) the first time it fails, before any pass could happen.  It is a sufficient condition: a grain
that fails it may still keep its masses apart.

Queue: one slot per contact (:mod:`bounce.gas.common`) in the tournament tree of
:mod:`bounce.gas.queue`; a pair event invalidates three predictions (its own and its two neighbours'),
a floor event two: O(log n) per event.  A slot's row (14 doubles) keeps what its search ended at: the
duration, by which grains still at the prediction's origin are advanced (others by the difference of the
double-double times), the gap's rounding scale, and for the floor the contact's speed and spring state, which
the impact rule uses as the single ball's loop does (always, for one grain); for a pair, the oscillator's
parts at that duration, with which its grains still at the origin (as a rule both) are moved: the values
the grains' own evaluation would compute, without computing them again.

Lazy predictions.  A pair with a known lower bound > 0 of its contact time
(:func:`_contact_lower_bound`) may be left unsearched when it is predicted: its slot keeps the search's
inputs (the gap's state at the origin, its rounding, the window and whether a horizon proves no contact)
and is queued *pending* at a key strictly before origin + bound (:func:`_lazy_key`: the float sum
lowered by 4 eps of itself, more than the rounding of the double-double keys).  The bound is the
window's start when it is > 0 (the gap is proved positive before it, above), always deferred; else, from
a gap x0 > 0 or one that opens (x0 = 0, gap' > 0: a pair right after its contact), the first step of the
search's march (:func:`bounce.exact.flight.certified_step` from the origin: the root finder's curvature
bounds prove the gap positive over it), deferred only when it ends after the earlier of the two adjacent
slots' keys (after a pair's contact its neighbours are predicted first, so that their new keys are
known), so that a neighbour's event most likely predicts the slot again before its bound comes (a
pending slot that reaches the top costs one queue update more than an eager search: deferring every first
step gained as much at N = 1e3 but nothing measurable at N = 1e5 on the ring of
benchmarks/bench_gas.py).  The true contact comes after the bound; the computed one may precede it by
its rounding (a Newton polish from a point whose gap rounded below zero, a tangential minimum within
rounding).  When a pending slot reaches the top of the queue its deferred search runs (the very search,
with the very inputs, an eager prediction would have run at the origin: a pure function of them, so the
same bits) and the slot is requeued at its true key before anything fires.  Every other key follows the
pending key, so the true key, if before it, comes first too; the events fired since the origin are those
whose keys preceded the pending key, in order, so the engine fires the eager engine's events in the
eager engine's order (:func:`bounce.gas.queue.before`) as long as the true key does not precede the last
event fired: that is checked, and a result before it (a contact's rounding spanning a neighbour's event:
never seen) stops the run as ``root_finder_failed`` rather than fire out of order (at a call's first
event the last event's slot is unknown: an exact tie with its time stops it too).  So the records are
the eager engine's, and no contact is skipped (the contract above holds per search).  Most pending slots
are re-predicted (a neighbour's event changes a grain) before their bound comes, and their search is
never run; a failed search is found when its slot reaches the top.

Call boundaries.  A numba call increments and decrements the reference count of every array it
passes (atomic operations of the runtime, NRT), which cost about as much as a short evaluation.  So
the per-event helpers here (advance, search window, search) are inlined into their few callers
(``inline="always"``: the same operations in the same order, the same bits), and the functions called
per prediction that take arrays but allocate none and keep none (:func:`_predict`,
:func:`_predict_from_state`, :func:`_resolve_pending`, :func:`_overlap`; the root finder's
:func:`~bounce.exact.flight.first_contact`, :func:`~bounce.exact.flight.gap` and
:func:`~bounce.exact.short_flight.short_flight`) are compiled without the runtime (numba's
``_nrt=False``: no reference counting; compiling fails if such a function ever allocates), which
costs no compile time (inlining the root finder into the searches too: +25 % cold compile for ~2 %).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..exact.events import STICKY_ONSET, _is_sticky_onset, _is_tangential, contact, rounding_level
from ..exact.flight import (
    EPS, FAILED, FOUND, HORIZON, NEVER, certified_step, curvature_bounds, first_contact, flight_at, flight_spring, gap,
    liftoff_time, xi_derivatives,
)
from ..exact.oscillator import P_MU, P_RHO
from ..exact.short_flight import HANDOVER, MAX_DEGREE, short_flight
from ..kinds import GRAZING as SB_GRAZING, STICKY_START as SB_STICKY
from .common import (
    C_EVENTS, C_STOP, C_WHERE, COLUMN, FLOOR, FLOOR_PAIR, GRAZING, K_HI, K_LO, PAIR,
    STOP_EVENTS, STOP_FAILED, STOP_OVERLAP, STOP_QUIET, STOP_STICKY, STOP_TIME, above_slot, below_slot,
    slot_grains,
)
from .queue import add_time, build, time_since, top, update

# columns of the grain array: local time stamp (double-double), x, x', xi', xi + gamma
G_TH, G_TL, G_X, G_U, G_A, G_ETA = range(6)
GRAIN_FIELDS = 6
# columns of the slot array: the prediction's origin (double-double) and its type (T_*); then, for a searched
# contact (T_CONTACT, T_STICKY, T_FAILED), its duration, what the search ended at (gap velocity, rounding scale,
# spring state (eta or s, s') at the contact), and for a pair's contact found by the closed-form search the
# oscillator's parts at its duration (1 - c, t - S, 1 - S', c, S, S'), with which the pair's grains still at the
# origin are moved (NaN: not kept, recomputed)
S_T0H, S_T0L, S_TYPE, S_TAU, S_V, S_SCALE, S_ETA, S_XID = range(8)
S_PARTS = 8
# or, in the same columns, for a pending (deferred) search (T_PENDING) its inputs: the gap's state at the origin,
# the classification window, the rounding scale, the search window (start, limit) and whether a HORIZON at limit
# proves none.  One row, 14 doubles, per slot: the fields an event reads and writes share lines (23 doubles
# when the two sets had their own columns)
S_X0, S_U, S_A, S_S0, S_WINDOW, S_SCALE0, S_START, S_LIMIT, S_PROVES = range(3, 12)
SLOT_FIELDS = 14
NO_PARTS = (math.nan,) * 6
# slot types: a contact; a contact that does not open (the run stops there); a failed search (the run
# stops there); a search not run yet, queued at a lower bound of its contact time (module docstring)
T_CONTACT, T_STICKY, T_FAILED, T_PENDING = 0.0, 1.0, 2.0, 3.0

#: the internal energy bound: xi^2 + xi'^2 < 1/4 keeps 1 + 2 xi > 0 until the grain's next event
AMPLITUDE2_MAX = 0.25


@njit(cache=True, inline="always")
def _advance(g, k, t_hi, t_lo, dt, gamma, params, coefs):
    """Grain k moved by dt along its closed-form motion (eq. (F), flight_spring), stamped (t_hi, t_lo)."""
    if dt != 0.0:
        x, v, _, omc, _, _, c, S, Sd = gap(dt, g[k, G_X], g[k, G_U], g[k, G_A], g[k, G_ETA], gamma, params, coefs)
        eta, a = flight_spring(g[k, G_ETA], g[k, G_A], gamma, omc, c, S, Sd)
        g[k, G_X] = x
        g[k, G_U] = v
        g[k, G_A] = a
        g[k, G_ETA] = eta
    g[k, G_TH] = t_hi
    g[k, G_TL] = t_lo


@njit(cache=True, inline="always")
def _advance_to_contact(g, k, t_hi, t_lo, sl, s, gamma, params, coefs):
    """Grain k of pair slot s moved to its contact at (t_hi, t_lo): by the slot's exact duration when the grain is
    at the prediction's origin, with the oscillator's parts the search kept (those of the same duration: the bits of
    :func:`_advance`), else as :func:`_advance` does."""
    if not (g[k, G_TH] == sl[s, S_T0H] and g[k, G_TL] == sl[s, S_T0L]):
        _advance(g, k, t_hi, t_lo, time_since(t_hi, t_lo, g[k, G_TH], g[k, G_TL]), gamma, params, coefs)
        return
    dt = sl[s, S_TAU]
    omc, tms, omsd, c, S, Sd = sl[s, S_PARTS], sl[s, S_PARTS + 1], sl[s, S_PARTS + 2], sl[s, S_PARTS + 3], \
        sl[s, S_PARTS + 4], sl[s, S_PARTS + 5]
    if dt == 0.0 or math.isnan(c):
        _advance(g, k, t_hi, t_lo, dt, gamma, params, coefs)
        return
    eta, a = g[k, G_ETA], g[k, G_A]
    g[k, G_X], g[k, G_U], _ = flight_at(dt, g[k, G_X], g[k, G_U], a, eta, gamma, omc, tms, omsd, S)
    g[k, G_ETA], g[k, G_A] = flight_spring(eta, a, gamma, omc, c, S, Sd)
    g[k, G_TH] = t_hi
    g[k, G_TL] = t_lo


@njit(cache=True, inline="always")
def _bring(g, k, t_hi, t_lo, gamma, params, coefs):
    """Advance grain k to (t_hi, t_lo) if it is not there."""
    if g[k, G_TH] != t_hi or g[k, G_TL] != t_lo:
        _advance(g, k, t_hi, t_lo, time_since(t_hi, t_lo, g[k, G_TH], g[k, G_TL]), gamma, params, coefs)


@njit(cache=True, inline="always")
def _search(x0, u, a, eta, G, window, scale0, t_start, t_limit, params, coefs, work):
    """First contact of a gap of eq. (F) (G = gamma: the floor; G = 0: a pair, eq. (G)) from x0 >= 0.

    Returns ``(status, tau, v, scale, eta_t, xid_t, parts)``: FOUND with the contact time, the gap's velocity,
    its rounding scale (``scale0``, that of x0, plus eq. (F)'s at the contact), the oscillator's state
    (eta or s, and its derivative) at the contact and its parts at tau (:func:`bounce.exact.oscillator.fundamental`,
    NO_PARTS from the series of the hot path or at tau = 0);
    HORIZON, NEVER or FAILED as :func:`bounce.exact.flight.first_contact`; or -1 for a contact at zero speed
    that does not open (x0 = u = 0 and no lift-off beyond ``window``, :func:`bounce.exact.flight.liftoff_time`).
    From x0 > 0 the search starts at ``t_start`` (the caller proves x > 0 before it).  From x0 = 0:
    moving away, the single ball's search (hot path first); at rest, from the lift-off time;
    approaching, the contact is now (tau = 0).
    """
    mu = params[P_MU]
    if x0 == 0.0:
        if u < 0.0:
            return FOUND, 0.0, u, scale0, eta, a, NO_PARTS
        if u == 0.0:
            t_start = liftoff_time(0.0, a, eta, G, params, window)
            if t_start == 0.0:
                return -1, 0.0, 0.0, 0.0, eta, a, NO_PARTS
        elif G + abs(eta - G + 2.0 * mu * a) > 0.0:  # short_flight divides by g + |xi''(0)|
            status, tau, v, scale, dxi, xid_t = short_flight(u, a, eta, G, mu, params[P_RHO], work)
            if status == HANDOVER:
                t_start = tau
            elif tau > t_limit:
                return HORIZON, t_limit, 0.0, 0.0, 0.0, 0.0, NO_PARTS
            else:
                return FOUND, tau, v, scale + scale0, eta + dxi, xid_t, NO_PARTS
    status, tau, v, scale, omc, tms, omsd, c, S, Sd, _ = first_contact(t_start, t_limit, x0, u, a, eta, G, params,
                                                                      coefs)
    if status != FOUND:
        return status, tau, 0.0, 0.0, 0.0, 0.0, NO_PARTS
    eta_t, xid_t = flight_spring(eta, a, G, omc, c, S, Sd)
    return FOUND, tau, v, scale + scale0, eta_t, xid_t, (omc, tms, omsd, c, S, Sd)


@njit(cache=True, inline="always")
def _pair_limits(x0, u, a, eta, room):
    """The window a pair's contact can lie in (module docstring): ``(start, limit, proves)``, the search
    may start at ``start`` (the gap is positive before it) and stop at ``limit`` (T*, or ``room``, the
    time left before t_max, if that is sooner); ``proves``: a HORIZON at ``limit`` proves there is no
    contact.  The bounds carry a relative margin of 1e-12 for their own rounding."""
    dpsi = u + a
    amp = math.sqrt(eta * eta + a * a)
    margin = 1e-12 * (x0 + abs(eta) + amp)
    start = 0.0
    if dpsi > 0.0:
        t_star = (amp - eta - x0 + margin) / dpsi
        if not t_star > 0.0:
            return 0.0, 0.0, True
    elif dpsi < 0.0:
        t_star = (x0 + eta + amp + margin) / -dpsi
        if x0 > 0.0:
            start = max((x0 + eta - amp - margin) / -dpsi, 0.0)
    else:
        t_star = math.inf
    limit = min(t_star, room)
    return min(start, limit), limit, dpsi > 0.0 and limit == t_star


@njit(cache=True, inline="always")
def _contact_lower_bound(x0, u, a, eta, t_start, t_limit, mu):
    """A time before which a pair's search (window from ``t_start`` to ``t_limit``) finds no contact (but for its
    rounding), 0 if none is known: the window's start, or from a start at 0 with a gap x0 > 0 or x0 = 0 opening
    (u > 0), the first step of the march (:func:`bounce.exact.flight.certified_step` from the gap's state at the
    origin, capped at ``t_limit``), over which the curvature bounds of :func:`~bounce.exact.flight.first_contact`
    prove the gap positive."""
    if t_start > 0.0 or not (x0 > 0.0 or u > 0.0):
        return t_start
    z2, B, M3 = curvature_bounds(eta, a, 0.0, mu)
    step = min(certified_step(x0, u, -z2, B, M3, 0.0), t_limit)
    return step if step < math.inf else 0.0


@njit(cache=True, inline="always")
def _lazy_key(t_hi, t_start):
    """A key strictly before every key add_time(t_hi, t_lo, tau) with tau >= t_start > 0 (t_hi >= 0, |t_lo| <=
    ulp(t_hi)/2): fl(t_hi + t_start) lowered by 4 eps of itself, more than the rounding of both sums."""
    k = t_hi + t_start
    return k - 4.0 * EPS * k


@njit(cache=True, _nrt=False)
def _predict(s, x0, u, a, eta, G, window, scale0, t_hi, t_lo, t_max, sl, tree, khi, klo, params, coefs, work,
             t_next):
    """Predict slot s's next contact from (t_hi, t_lo) and queue it (module docstring): a pair with a lower bound
    > 0 of its contact time is queued pending at it (its search deferred, :func:`_resolve_pending`) if the bound is
    its window's start, or if it is the march's first step and ends after ``t_next`` (the earlier of the adjacent
    slots' keys; inf: never); any other search is run now."""
    room = t_max - t_hi - t_lo
    t_start, t_limit, proves = 0.0, room, False
    t_lower = 0.0
    if G == 0.0:
        t_start, t_limit, proves = _pair_limits(x0, u, a, eta, room)
        t_lower = _contact_lower_bound(x0, u, a, eta, t_start, t_limit, params[P_MU])
        if t_start == 0.0 and not t_hi + t_lower > t_next:
            t_lower = 0.0  # a first step that ends before both neighbours' keys: searched now (module docstring)
    if G == 0.0 and t_limit == 0.0 and proves:
        sl[s, S_TYPE] = T_CONTACT
        k_hi, k_lo = math.inf, 0.0
    elif G == 0.0 and t_lower > 0.0:
        sl[s, S_T0H] = t_hi
        sl[s, S_T0L] = t_lo
        sl[s, S_X0] = x0
        sl[s, S_U] = u
        sl[s, S_A] = a
        sl[s, S_S0] = eta
        sl[s, S_WINDOW] = window
        sl[s, S_SCALE0] = scale0
        sl[s, S_START] = t_start
        sl[s, S_LIMIT] = t_limit
        sl[s, S_PROVES] = 1.0 if proves else 0.0
        sl[s, S_TYPE] = T_PENDING
        k_hi, k_lo = _lazy_key(t_hi, t_lower), 0.0
    else:
        k_hi, k_lo = _run_search(s, x0, u, a, eta, G, window, scale0, t_start, t_limit, proves, t_hi, t_lo, t_max, sl,
                                 params, coefs, work)
    update(s, k_hi, k_lo, tree, khi, klo)


@njit(cache=True, _nrt=False)
def _resolve_pending(s, t_max, sl, tree, khi, klo, params, coefs, work, c_hi, c_lo, last):
    """Run pending slot s's deferred search (from its stored inputs: the search an eager prediction would have
    run, bit for bit) and queue its result.  Returns False if the result precedes the last event fired, at
    (c_hi, c_lo) from slot ``last`` (-1: fired before this call), in the order of the queue (module docstring:
    never expected; the caller stops the run)."""
    k_hi, k_lo = _run_search(s, sl[s, S_X0], sl[s, S_U], sl[s, S_A], sl[s, S_S0], 0.0, sl[s, S_WINDOW],
                             sl[s, S_SCALE0], sl[s, S_START], sl[s, S_LIMIT], sl[s, S_PROVES] != 0.0, sl[s, S_T0H],
                             sl[s, S_T0L], t_max, sl, params, coefs, work)
    update(s, k_hi, k_lo, tree, khi, klo)
    if sl[s, S_TYPE] != T_CONTACT:
        return True  # a failed search (or a sticky start): the run stops at the slot's origin
    return k_hi > c_hi or (k_hi == c_hi and (k_lo > c_lo or (k_lo == c_lo and 0 <= last < s)))


@njit(cache=True, inline="always")
def _run_search(s, x0, u, a, eta, G, window, scale0, t_start, t_limit, proves, t_hi, t_lo, t_max, sl, params, coefs,
                work):
    """Search slot s's next contact in (t_start, t_limit] from (t_hi, t_lo): its key (the caller queues it)."""
    status, tau, v, scale, eta_t, xid_t, parts = _search(x0, u, a, eta, G, window, scale0, t_start, t_limit, params,
                                                         coefs, work)
    if status == -1 and G == 0.0 and eta * eta + a * a <= rounding_level(scale0) ** 2:
        # a pair in touch at relative rest with its springs' sum s at rest to rounding: relaxed (module docstring),
        # the gap stays 0 until an event changes a grain; no contact predicted (it was queued as a sticky onset)
        sl[s, S_TYPE] = T_CONTACT
        return math.inf, 0.0
    kind = T_CONTACT
    if status == FOUND or status == -1 or status == FAILED:
        if status == -1:
            kind, tau = T_STICKY, 0.0
        elif status == FAILED:
            kind, tau = T_FAILED, 0.0
        sl[s, S_T0H] = t_hi
        sl[s, S_T0L] = t_lo
        sl[s, S_TAU] = tau
        sl[s, S_V] = v
        sl[s, S_SCALE] = scale
        sl[s, S_ETA] = eta_t
        sl[s, S_XID] = xid_t
        sl[s, S_TYPE] = kind
        for p in range(6):
            sl[s, S_PARTS + p] = parts[p]
        return add_time(t_hi, t_lo, tau)
    sl[s, S_TYPE] = T_CONTACT
    if status == NEVER or (status == HORIZON and proves):
        return math.inf, 0.0
    return t_max, math.inf  # HORIZON at t_max: after every event of the run, never fired


@njit(cache=True, inline="always")
def _pair_gap(g, i, j, seam, ell, gamma):
    """Gap state of eq. (G) for the pair (i, j), both at the same time: (x0, w, s', s, rounding noise)."""
    xi_i = g[i, G_ETA] - gamma
    xi_j = g[j, G_ETA] - gamma
    yi = g[i, G_X] + (1.0 + 2.0 * xi_i)
    xj = g[j, G_X] + ell if seam else g[j, G_X]
    x0 = xj - yi
    w = g[j, G_U] - (g[i, G_U] + 2.0 * g[i, G_A])
    noise = 4.0 * EPS * (abs(xj) + abs(yi))
    return x0, w, g[i, G_A] + g[j, G_A], xi_i + xi_j, noise


@njit(cache=True, _nrt=False)
def _predict_from_state(s, n, geometry, gamma, ell, t_max, g, sl, tree, khi, klo, params, coefs, work, stale):
    """Predict slot s from the grains' states (all involved grains at the same time); slot ``stale`` (-1: none)
    is about to be predicted again, its key is not a neighbour's next event (:func:`_predict`'s ``t_next``)."""
    mu = params[P_MU]
    i, j, seam = slot_grains(s, n, geometry)
    if i < 0:  # the floor
        x0 = max(g[0, G_X], 0.0)  # below the floor only by rounding: the contact is now
        a, eta = g[0, G_A], g[0, G_ETA]
        window = 8.0 * EPS * (abs(eta) + 2.0 * mu * abs(a) + 2.0 * gamma)
        _predict(s, x0, g[0, G_U], a, eta, gamma, window, 0.0, g[0, G_TH], g[0, G_TL], t_max, sl, tree, khi, klo,
                 params, coefs, work, math.inf)
        return
    x0, w, sd, s0, noise = _pair_gap(g, i, j, seam, ell, gamma)
    if x0 <= noise:
        x0 = 0.0
    window = 8.0 * EPS * (abs(s0) + 2.0 * mu * abs(sd))
    sb, sa = below_slot(i, n, geometry), above_slot(j, n, geometry)
    t_next = min(khi[sb] if sb != s and sb != stale else math.inf,
                 khi[sa] if sa >= 0 and sa != s and sa != stale else math.inf)
    _predict(s, x0, w, sd, s0, 0.0, window, noise / (4.0 * EPS), g[i, G_TH], g[i, G_TL], t_max, sl, tree, khi, klo, params, coefs,
             work, t_next)


@njit(cache=True)
def dimer_start(geometry, n, gamma, ell, t_max, params, coefs, g, sl, tree, khi, klo):
    """Predict every slot from the initial state (all grains at t = 0) and build the queue."""
    work = np.empty(MAX_DEGREE + 2)
    khi[:] = math.inf
    klo[:] = 0.0
    for s in range(n):
        _predict_from_state(s, n, geometry, gamma, ell, t_max, g, sl, tree, khi, klo, params, coefs, work, -1)
    build(tree, khi, klo)


@njit(cache=True, _nrt=False)
def _overlap(g, k, gamma):
    """Does grain k break the internal energy bound xi^2 + xi'^2 < 1/4 (module docstring)?"""
    xi = g[k, G_ETA] - gamma
    return not xi * xi + g[k, G_A] * g[k, G_A] < AMPLITUDE2_MAX


@njit(cache=True)
def grain_at(g, k, t_hi, t_lo, gamma, params, coefs):
    """(x, x', xi', eta) of grain k at (t_hi, t_lo), without moving the grain."""
    dt = time_since(t_hi, t_lo, g[k, G_TH], g[k, G_TL])
    if dt == 0.0:
        return g[k, G_X], g[k, G_U], g[k, G_A], g[k, G_ETA]
    x, v, _, omc, _, _, c, S, Sd = gap(dt, g[k, G_X], g[k, G_U], g[k, G_A], g[k, G_ETA], gamma, params, coefs)
    eta, a = flight_spring(g[k, G_ETA], g[k, G_A], gamma, omc, c, S, Sd)
    return x, v, a, eta


@njit(cache=True)
def dimer_snapshot(g, t_hi, t_lo, gamma, params, coefs, out, row):
    """Every grain's (x, x', xi', eta) at (t_hi, t_lo) into out[:, row, :] (the grains are not moved, so
    the records do not depend on the snapshot interval)."""
    for k in range(g.shape[0]):
        x, u, a, eta = grain_at(g, k, t_hi, t_lo, gamma, params, coefs)
        out[0, row, k] = x
        out[1, row, k] = u
        out[2, row, k] = a
        out[3, row, k] = eta


@njit(cache=True)
def dimer_run(geometry, n, gamma, ell, t_max, params, coefs, g, sl, tree, khi, klo, ctl, clock,
              max_events, every, rec_t, rec_kind, rec_pair, rec_speed, snap_t, snap_event, snap):
    """Advance the gas by up to ``max_events`` events from the state in (g, sl, tree, ctl, clock).

    Records per event (rec_*, from index 0 of this call): the time (the double-double clock rounded),
    the kind (FLOOR, PAIR, GRAZING), the slot (FLOOR_PAIR for the floor) and the approach speed; and
    after every ``every``-th event of the run (global count, ``every`` = 0: none) a snapshot of all
    grains (:func:`dimer_snapshot`).  Stops early at t_max, when no contact is left, or at a stop of
    the module docstring (ctl[C_STOP], ctl[C_WHERE] the grain or slot).  Returns
    ``(events recorded, snapshots taken)`` in this call; calls chain (the state is all in the arrays).
    """
    mu = params[P_MU]
    work = np.empty(MAX_DEGREE + 2)
    rec = 0
    snaps = 0
    last = -1  # the slot of the last event fired in this call
    ctl[C_STOP] = STOP_EVENTS
    while rec < max_events:
        s = top(tree, khi)
        if sl[s, S_TYPE] == T_PENDING:
            # a deferred search reached the top: run it, requeue, look again (no event fires before it)
            if not _resolve_pending(s, t_max, sl, tree, khi, klo, params, coefs, work, clock[K_HI], clock[K_LO],
                                    last):
                ctl[C_STOP] = STOP_FAILED
                ctl[C_WHERE] = s
                break
            continue
        t_hi = khi[s]
        t_lo = klo[s]
        if t_hi == math.inf:
            ctl[C_STOP] = STOP_QUIET
            break
        if t_hi > t_max or (t_hi == t_max and t_lo > 0.0):
            ctl[C_STOP] = STOP_TIME
            break
        kind_slot = sl[s, S_TYPE]
        if kind_slot == T_STICKY or kind_slot == T_FAILED:
            ctl[C_STOP] = STOP_STICKY if kind_slot == T_STICKY else STOP_FAILED
            ctl[C_WHERE] = s
            clock[K_HI], clock[K_LO] = t_hi, t_lo
            break
        i, j, seam = slot_grains(s, n, geometry)
        if i < 0:
            # ---------------------------------------------------------------- floor (grain 0)
            u0, a0 = g[0, G_U], g[0, G_A]
            if g[0, G_TH] == sl[s, S_T0H] and g[0, G_TL] == sl[s, S_T0L]:
                dt = sl[s, S_TAU]
                v, scale, eta_t, xid_t = sl[s, S_V], sl[s, S_SCALE], sl[s, S_ETA], sl[s, S_XID]
            else:
                dt = time_since(t_hi, t_lo, g[0, G_TH], g[0, G_TL])
                _, v, scale, omc, _, _, c, S, Sd = gap(dt, g[0, G_X], u0, a0, g[0, G_ETA], gamma, params, coefs)
                eta_t, xid_t = flight_spring(g[0, G_ETA], a0, gamma, omc, c, S, Sd)
            _, xidd, xiddd, _ = xi_derivatives(eta_t - gamma, xid_t, mu)
            acc = -gamma - xidd
            jerk = -xiddd
            sb_kind, u1, a1, eta1 = contact(v, acc, jerk, scale, u0, a0, gamma, dt, eta_t, xid_t)
            g[0, G_TH] = t_hi
            g[0, G_TL] = t_lo
            g[0, G_X] = 0.0
            g[0, G_U] = u1
            g[0, G_A] = a1
            g[0, G_ETA] = eta1
            if sb_kind == SB_STICKY:
                ctl[C_STOP] = STOP_STICKY
                ctl[C_WHERE] = s
                clock[K_HI], clock[K_LO] = t_hi, t_lo
                break
            kind = GRAZING if sb_kind == SB_GRAZING else FLOOR
            window = 0.0
            if kind == GRAZING:
                window = (STICKY_ONSET * jerk * jerk * rounding_level(scale)) ** (1.0 / 3.0)
            rec_t[rec] = t_hi + t_lo
            rec_kind[rec] = kind
            rec_pair[rec] = FLOOR_PAIR
            rec_speed[rec] = max(-v, 0.0)
            _predict(s, 0.0, u1, a1, eta1, gamma, window, 0.0, t_hi, t_lo, t_max, sl, tree, khi, klo, params,
                     coefs, work, math.inf)
            if n > 1:
                _bring(g, 1, t_hi, t_lo, gamma, params, coefs)
                _predict_from_state(0, n, geometry, gamma, ell, t_max, g, sl, tree, khi, klo, params, coefs,
                                    work, -1)
            bad = 0 if _overlap(g, 0, gamma) else -1
        else:
            # ---------------------------------------------------------------- pair (i, j)
            _advance_to_contact(g, i, t_hi, t_lo, sl, s, gamma, params, coefs)
            _advance_to_contact(g, j, t_hi, t_lo, sl, s, gamma, params, coefs)
            w = g[j, G_U] - (g[i, G_U] + 2.0 * g[i, G_A])
            s0 = (g[i, G_ETA] - gamma) + (g[j, G_ETA] - gamma)
            _, z2, z3, _ = xi_derivatives(s0, g[i, G_A] + g[j, G_A], mu)
            acc = -z2
            jerk = -z3
            xn = rounding_level(sl[s, S_SCALE])
            tangential = _is_tangential(w, acc, jerk, xn)
            window = 0.0
            if tangential and s0 * s0 + (g[i, G_A] + g[j, G_A]) ** 2 <= xn * xn:
                kind = GRAZING  # relaxed: nothing resolvable moves the touching masses (module docstring)
                u_new = 0.0
                window = -1.0
            elif w < 0.0 and not (tangential and _is_sticky_onset(acc, jerk, xn)):
                half = 0.5 * w
                g[i, G_A] += half
                g[j, G_A] += half
                g[j, G_U] -= w
                kind = PAIR
                u_new = -w
            elif w < 0.0:
                ctl[C_STOP] = STOP_STICKY
                ctl[C_WHERE] = s
                clock[K_HI], clock[K_LO] = t_hi, t_lo
                break
            else:  # not approaching (a tangential minimum of the gap): nothing exchanged
                kind = GRAZING
                u_new = w
                window = (STICKY_ONSET * jerk * jerk * xn) ** (1.0 / 3.0)
            rec_t[rec] = t_hi + t_lo
            rec_kind[rec] = kind
            rec_pair[rec] = s
            rec_speed[rec] = max(-w, 0.0)
            # the neighbours first (their keys are s's next re-predictions), s's own key is stale meanwhile
            sb = below_slot(i, n, geometry)
            if sb != s:
                if not (geometry == COLUMN and i == 0):
                    _bring(g, i - 1 if i > 0 else n - 1, t_hi, t_lo, gamma, params, coefs)
                _predict_from_state(sb, n, geometry, gamma, ell, t_max, g, sl, tree, khi, klo, params, coefs,
                                    work, s)
            sa = above_slot(j, n, geometry)
            if sa >= 0 and sa != s and sa != sb:
                _bring(g, j + 1 if j + 1 < n else 0, t_hi, t_lo, gamma, params, coefs)
                _predict_from_state(sa, n, geometry, gamma, ell, t_max, g, sl, tree, khi, klo, params, coefs,
                                    work, s)
            if window < 0.0:
                update(s, math.inf, 0.0, tree, khi, klo)
            else:
                t_next = min(khi[sb] if sb != s else math.inf, khi[sa] if sa >= 0 and sa != s else math.inf)
                _predict(s, 0.0, u_new, g[i, G_A] + g[j, G_A], s0, 0.0, window, 0.0, t_hi, t_lo, t_max, sl, tree,
                         khi, klo, params, coefs, work, t_next)
            bad = i if _overlap(g, i, gamma) else (j if _overlap(g, j, gamma) else -1)
        clock[K_HI], clock[K_LO] = t_hi, t_lo
        last = s
        done = ctl[C_EVENTS]
        ctl[C_EVENTS] = done + 1
        rec += 1
        if every > 0 and (done + 1) % every == 0:
            snap_t[snaps] = t_hi + t_lo
            snap_event[snaps] = done
            dimer_snapshot(g, t_hi, t_lo, gamma, params, coefs, snap, snaps)
            snaps += 1
        if bad >= 0:
            ctl[C_STOP] = STOP_OVERLAP
            ctl[C_WHERE] = bad
            break
    return rec, snaps

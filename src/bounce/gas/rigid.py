"""The rigid counterpart of the dimer gas: n rigid grains with a constant restitution (numba kernels).

Grain k is a rigid rod of length ``size`` (0: a point) at [x_k, x_k + size], moving freely,
x'' = -gamma, between events.  Same geometries, slots and queue as the dimer gas
(:mod:`bounce.gas.common`, :mod:`bounce.gas.queue`), same lazy advancing of the grains.  Contacts,
with restitution r in [0, 1] (equal masses):

* a pair (i, j) approaching at w = x_i' - x_j' > 0 (gap x_j - x_i - size, linear in time since both
  fall alike): contact after gap / w; then x_i' -= (1 + r) w / 2, x_j' += (1 + r) w / 2;
* the floor (column): x_0 + x_0' t - gamma t^2 / 2 = 0, the larger root in the form without
  cancellation; then x_0' -> -r x_0'.

TC model (Luding and McNamara): with t_c > 0 a collision is elastic (r = 1, recorded as
``floor_elastic`` / ``pair_elastic``) when either grain collided less than t_c before.

Rounding: a gap within ``4 eps`` of its positions' magnitude is zero (approaching: contact now).

Inelastic collapse (infinitely many collisions in a finite time) is detected, not stalled on.  In
a collapse the gaps and the relative speeds of a cluster shrink geometrically, and so do the times
between its collisions, so float64 stops resolving it in one of two ways: the clock stops advancing
(the time increments fall below half an ulp of t: a ball on the floor, a cluster far from r_c), or
the approach speeds fall below the rounding of the grains' velocities (near the three-grain
threshold r_c = 7 - 4 sqrt(3) the time increments shrink by a factor that tends to 1, the speeds by
~sqrt(r) per collision).  An event is *unresolved* if the float64 clock does not advance over it; a
pair collision is *unresolvable* if its approach speed is at most 8 ulps of the grains' speeds,
8 eps (|x_i'| + |x_j'|).  The run stops (:data:`~bounce.gas.common.STOP_COLLAPSE`) at the first
unresolvable collision or once :data:`COLLAPSE_RUN` unresolved events follow each other; the control
array holds the lowest and highest grain of that run and its length, and the slot of an unresolvable
collision (-1 for a stalled clock), t_end the time of the last event (``bounce.gas.simulate_rigid`` reports them).  Two
consecutive events within one ulp of t are an event of probability ~1e-16 or less in a gas that does not
collapse; a collision 1e-15 slower than its grains is not: a gas that cools without end (Haff's law) drifts
with the rounding residue of its momentum, and its relative speeds reach that residue's rounding.  The front
tells the two apart at such a stop (``GasRun._cooled``: the whole gas as cold, and the intervals between
collisions not shrinking) and reports ``cooled_below_rounding`` instead of a collapse.  Positions are not
wrapped on the ring: a drift of the whole gas by D costs the gaps ~eps D of absolute precision.  Near r_c this decides at the precision float64
allows: a sequence that ends after more collisions (~pi / arg of the complex eigenvalue of the
three-grain map) than it takes to shrink the speeds by 1e16 (~27) is reported as a collapse.

:func:`_advance` and :func:`_predict` are compiled without numba's runtime (``_nrt=False``, as the dimer
engine's per-prediction functions, :mod:`bounce.gas.dimer`): they take arrays but allocate and keep none,
so a call counts no references.
"""

from __future__ import annotations

import math

from numba import njit

from ..exact.flight import EPS
from .common import (
    C_EVENTS, C_HIGH, C_LOW, C_RUN, C_STOP, C_WHERE, COLUMN, FLOOR, FLOOR_ELASTIC, FLOOR_PAIR, K_HI, K_LO, PAIR,
    PAIR_ELASTIC, STOP_COLLAPSE, STOP_EVENTS, STOP_QUIET, STOP_TIME, above_slot, below_slot, slot_grains,
)
from .queue import add_time, build, time_since, top, update

# columns of the grain array: local time stamp (double-double), x, x', time of the last collision
R_TH, R_TL, R_X, R_V, R_LAST = range(5)
RIGID_FIELDS = 5
#: consecutive unresolved events that make a collapse (module docstring)
COLLAPSE_RUN = 64


@njit(cache=True, _nrt=False)
def _advance(g, k, t_hi, t_lo, gamma):
    dt = time_since(t_hi, t_lo, g[k, R_TH], g[k, R_TL])
    if dt != 0.0:
        v = g[k, R_V]
        g[k, R_X] += dt * (v - 0.5 * gamma * dt)
        g[k, R_V] = v - gamma * dt
    g[k, R_TH] = t_hi
    g[k, R_TL] = t_lo


@njit(cache=True, _nrt=False)
def _predict(s, n, geometry, gamma, ell, size, g, tree, khi, klo):
    """Queue slot s's next contact from the grains' states (all involved grains at the same time)."""
    i, j, seam = slot_grains(s, n, geometry)
    if i < 0:
        x0 = max(g[0, R_X], 0.0)  # below the floor only by rounding
        v = g[0, R_V]
        disc = math.sqrt(v * v + 2.0 * gamma * x0)
        tau = (v + disc) / gamma if v > 0.0 else (2.0 * x0 / (disc - v) if x0 > 0.0 else 0.0)
        t_hi, t_lo = g[0, R_TH], g[0, R_TL]
    else:
        xj = g[j, R_X] + ell if seam else g[j, R_X]
        xi = g[i, R_X] + size
        gap = xj - xi
        if gap <= 4.0 * EPS * (abs(xj) + abs(xi)):
            gap = 0.0
        w = g[i, R_V] - g[j, R_V]
        tau = gap / w if w > 0.0 else math.inf
        t_hi, t_lo = g[i, R_TH], g[i, R_TL]
    if tau == math.inf:
        update(s, math.inf, 0.0, tree, khi, klo)
    else:
        k_hi, k_lo = add_time(t_hi, t_lo, tau)
        update(s, k_hi, k_lo, tree, khi, klo)


@njit(cache=True)
def rigid_start(geometry, n, gamma, ell, size, g, tree, khi, klo):
    """Predict every slot from the initial state (all grains at t = 0) and build the queue."""
    khi[:] = math.inf
    klo[:] = 0.0
    for s in range(n):
        _predict(s, n, geometry, gamma, ell, size, g, tree, khi, klo)
    build(tree, khi, klo)


@njit(cache=True)
def rigid_snapshot(g, t_hi, t_lo, gamma, out, row):
    """Every grain's (x, x') at (t_hi, t_lo) into out[:, row, :], the grains not moved."""
    for k in range(g.shape[0]):
        dt = time_since(t_hi, t_lo, g[k, R_TH], g[k, R_TL])
        v = g[k, R_V]
        out[0, row, k] = g[k, R_X] + dt * (v - 0.5 * gamma * dt) if dt != 0.0 else g[k, R_X]
        out[1, row, k] = v - gamma * dt


@njit(cache=True)
def rigid_run(geometry, n, gamma, ell, size, r, t_c, t_max, g, tree, khi, klo, ctl, clock,
              max_events, every, rec_t, rec_kind, rec_pair, rec_speed, snap_t, snap_event, snap):
    """Advance the rigid gas by up to ``max_events`` events: the contract of
    :func:`bounce.gas.dimer.dimer_run` (records, snapshots, chaining), with the collapse stop."""
    rec = 0
    snaps = 0
    ctl[C_STOP] = STOP_EVENTS
    while rec < max_events:
        s = top(tree, khi)
        t_hi = khi[s]
        t_lo = klo[s]
        if t_hi == math.inf:
            ctl[C_STOP] = STOP_QUIET
            break
        if t_hi > t_max or (t_hi == t_max and t_lo > 0.0):
            ctl[C_STOP] = STOP_TIME
            break
        i, j, seam = slot_grains(s, n, geometry)
        t = t_hi + t_lo
        if i < 0:
            _advance(g, 0, t_hi, t_lo, gamma)
            g[0, R_X] = 0.0
            v = g[0, R_V]
            elastic = t - g[0, R_LAST] < t_c
            g[0, R_V] = -v if elastic else -r * v
            g[0, R_LAST] = t
            kind = FLOOR_ELASTIC if elastic else FLOOR
            speed = max(-v, 0.0)
            unresolvable = False
            low = 0
            high = 0
            _predict(s, n, geometry, gamma, ell, size, g, tree, khi, klo)
            if n > 1:
                _advance(g, 1, t_hi, t_lo, gamma)
                _predict(0, n, geometry, gamma, ell, size, g, tree, khi, klo)
        else:
            _advance(g, i, t_hi, t_lo, gamma)
            _advance(g, j, t_hi, t_lo, gamma)
            w = g[i, R_V] - g[j, R_V]
            unresolvable = w <= 8.0 * EPS * (abs(g[i, R_V]) + abs(g[j, R_V]))
            elastic = t - g[i, R_LAST] < t_c or t - g[j, R_LAST] < t_c
            dv = 0.5 * (2.0 if elastic else 1.0 + r) * w
            g[i, R_V] -= dv
            g[j, R_V] += dv
            g[i, R_LAST] = t
            g[j, R_LAST] = t
            kind = PAIR_ELASTIC if elastic else PAIR
            speed = max(w, 0.0)
            low = min(i, j)
            high = max(i, j)
            _predict(s, n, geometry, gamma, ell, size, g, tree, khi, klo)
            sb = below_slot(i, n, geometry)
            if sb != s:
                if not (geometry == COLUMN and i == 0):
                    _advance(g, i - 1 if i > 0 else n - 1, t_hi, t_lo, gamma)
                _predict(sb, n, geometry, gamma, ell, size, g, tree, khi, klo)
            sa = above_slot(j, n, geometry)
            if sa >= 0 and sa != s and sa != sb:
                _advance(g, j + 1 if j + 1 < n else 0, t_hi, t_lo, gamma)
                _predict(sa, n, geometry, gamma, ell, size, g, tree, khi, klo)
        done = ctl[C_EVENTS]
        # collapse detector (module docstring): does the float64 clock advance over this event?
        if unresolvable or (done > 0 and t == clock[K_HI] + clock[K_LO]):
            if ctl[C_RUN] == 0:
                ctl[C_LOW], ctl[C_HIGH] = low, high
            ctl[C_RUN] += 1
            ctl[C_LOW] = min(ctl[C_LOW], low)
            ctl[C_HIGH] = max(ctl[C_HIGH], high)
        else:
            ctl[C_RUN] = 0
        clock[K_HI], clock[K_LO] = t_hi, t_lo
        rec_t[rec] = t
        rec_kind[rec] = kind
        rec_pair[rec] = FLOOR_PAIR if i < 0 else s
        rec_speed[rec] = speed
        ctl[C_EVENTS] = done + 1
        rec += 1
        if every > 0 and (done + 1) % every == 0:
            snap_t[snaps] = t
            snap_event[snaps] = done
            rigid_snapshot(g, t_hi, t_lo, gamma, snap, snaps)
            snaps += 1
        if unresolvable or ctl[C_RUN] >= COLLAPSE_RUN:
            ctl[C_STOP] = STOP_COLLAPSE
            ctl[C_WHERE] = s if unresolvable else -1
            break
    return rec, snaps

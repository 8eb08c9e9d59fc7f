"""The event queue of the gas engines: a tournament tree of per-contact predictions (numba).

Every contact of a gas (the floor, or the pair of neighbours k, k+1, ring wrap included) owns one
*slot*; a slot's key is the time of its predicted next contact as an unevaluated double-double sum
``(hi, lo)`` (:func:`two_sum`), ``(inf, 0)`` when the slot has no contact to come.  All slots are in
the queue at all times, so an event never pops anything: the slot at the top fires, and every slot
whose prediction the event invalidates gets a new key by :func:`update`.  Keys are ordered by
:func:`before` (time hi, then lo, then slot index: equal times fire in slot order, so runs are
reproducible bit for bit); the top is the minimum of that total order, so any correct queue fires the
same slots in the same order.

Layout (the complete binary tree of event-driven molecular dynamics, Marin, Risso and Cordero, J. Comput.
Phys. 109, 306 (1993)): M slots are the leaves M .. 2M-1 of an implicit tree whose node i has the
children 2i, 2i+1; a leaf's key is ``khi[s], klo[s]`` (arrays owned by the caller, indexed by slot), and
inner node i (1 <= i < M) holds its subtree's winner, ``tree[i] = (hi, slot)`` (the winner's lo is
``klo[slot]``, read only when two his tie).  Invariant: every inner node holds the first of its two
children's winners, with the winners' current keys.  :func:`update` replays the slot's matches from its
leaf up, and stops at the first node whose winner is another slot and unchanged (its ancestors are then
unchanged too).  A leaf never moves, so there is no position array, a level costs one comparison with
the sibling beside the node on the path, and the slots an event re-predicts (neighbours: adjacent
leaves) share their paths.  On the cooling ring of benchmarks/bench_gas.py a pair event makes 1.12
(N = 1e3) or 1.49 (N = 1e5) updates of the slot at the top (the fired one, and pending searches
resolved there: 10.0 and 16.7 levels each) and 2 of neighbours (1.4 and 1.5 levels each).  The bench's
replay of the engine's key updates costs 124 ns per event at N = 1e3 and 131 at N = 1e5, against 245
and 290 on the indexed binary heap this replaced (sift up or down, two comparisons a level, the keys
read through the heap's indices, a position array written per move).  Measured and not kept: nodes
holding (hi, lo, slot) (equal within noise); a 4-ary tree with its four children in one cache line
(replay 205 ns per event, the engine 8-10 % slower at both sizes: three comparisons a level).

:func:`update` is inlined into its callers (numba ``inline="always"``): a call passing the three arrays
cost about as much as the update itself; the engines call it from one place per code path.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

# columns of an inner node of the tree: its winner's key hi and slot (the winner's lo is klo[slot])
N_HI, N_SLOT = range(2)
NODE_FIELDS = 2


@njit(cache=True)
def two_sum(a, b):
    """(s, e) with s = fl(a + b) and s + e = a + b exactly (Knuth)."""
    s = a + b
    bb = s - a
    e = (a - (s - bb)) + (b - bb)
    return s, e


@njit(cache=True)
def add_time(hi, lo, dt):
    """Double-double time (hi, lo) + dt, renormalised (|lo| <= ulp(hi)/2); exact to ~eps^2 |hi|."""
    s, e = two_sum(hi, dt)
    e += lo
    return two_sum(s, e) if math.isfinite(s) else (s, 0.0)


@njit(cache=True)
def time_since(hi, lo, t_hi, t_lo):
    """(hi + lo) - (t_hi + t_lo) for two double-double times, to eps of the result plus eps^2 |hi|."""
    return (hi - t_hi) + (lo - t_lo)


@njit(cache=True, inline="always")
def before(h1, l1, s1, h2, l2, s2):
    """Does the key (h1, l1) of slot s1 fire before the key (h2, l2) of slot s2 (time hi, then lo, then slot)?"""
    if h1 != h2:
        return h1 < h2
    if l1 != l2:
        return l1 < l2
    return s1 < s2


@njit(cache=True, inline="always")
def _node(i, tree, khi):
    """(hi, slot) at node i: the winner of an inner node (i < M), else leaf slot i - M and its key's hi."""
    m = khi.size
    if i >= m:
        return khi[i - m], i - m
    return tree[i, N_HI], int(tree[i, N_SLOT])


@njit(cache=True, inline="always")
def _first(h1, s1, h2, s2, klo):
    """Does slot s1 (key hi h1) fire before slot s2 (key hi h2)?  The lo parts are read only on a tie of hi."""
    if h1 != h2:
        return h1 < h2
    return before(h1, klo[s1], s1, h2, klo[s2], s2)


@njit(cache=True)
def build(tree, khi, klo):
    """Every inner node's winner from the leaves' keys (O(M))."""
    for i in range(khi.size - 1, 0, -1):
        h1, s1 = _node(2 * i, tree, khi)
        h2, s2 = _node(2 * i + 1, tree, khi)
        if _first(h2, s2, h1, s1, klo):
            h1, s1 = h2, s2
        tree[i, N_HI] = h1
        tree[i, N_SLOT] = s1


@njit(cache=True, inline="always")
def top(tree, khi):
    """The slot that fires next (the minimum of all keys in the order of :func:`before`)."""
    return int(tree[1, N_SLOT]) if khi.size > 1 else 0


@njit(cache=True, inline="always")
def update(s, hi, lo, tree, khi, klo):
    """Give slot s the key (hi, lo) and replay its matches up the tree, as far as a winner changes."""
    khi[s] = hi
    klo[s] = lo
    i = khi.size + s
    w = s
    while i > 1:
        oh, o = _node(i ^ 1, tree, khi)
        if _first(oh, o, hi, w, klo):
            hi, w = oh, o
        i >>= 1
        if w != s and tree[i, N_SLOT] == w:
            break  # this node's winner is unchanged, and so are its ancestors'
        tree[i, N_HI] = hi
        tree[i, N_SLOT] = w


def empty_queue(m: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(tree, khi, klo)`` for m slots, every key (inf, 0) (call :func:`build` after setting keys)."""
    tree = np.zeros((m, NODE_FIELDS))
    khi = np.full(m, np.inf)
    klo = np.zeros(m)
    build(tree, khi, klo)
    return tree, khi, klo

"""The event queue of the gas engines: an indexed binary min-heap of per-contact predictions (numba).

Every contact of a gas (the floor, or the pair of neighbours k, k+1, ring wrap included) owns one
*slot*; a slot's key is the time of its predicted next contact as an unevaluated double-double sum
``(hi, lo)`` (:func:`two_sum`), ``(inf, 0)`` when the slot has no contact to come.  All slots are in
the heap at all times, so an event never pops anything: the slot at the top fires, and every slot
whose prediction the event invalidates gets a new key by :func:`update`, which restores the heap
property by sifting the slot up or down.  Cost: O(log M) per update for M slots.

Invariants: ``heap[pos[s]] == s`` for every slot s, and no slot's key precedes its parent's in the
order of :func:`before` (time hi, then lo, then slot index: equal times fire in slot order, so runs
are reproducible bit for bit).  The keys live in two arrays ``khi``, ``klo`` owned by the caller.

:func:`update` and its sifts are inlined into their callers (numba ``inline="always"``): a call passing the
four arrays cost about as much as the update itself; the engines call it from one place per code path.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


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
def before(s1, s2, khi, klo):
    """Does slot s1 fire before slot s2 (time hi, then lo, then slot index)?"""
    if khi[s1] != khi[s2]:
        return khi[s1] < khi[s2]
    if klo[s1] != klo[s2]:
        return klo[s1] < klo[s2]
    return s1 < s2


@njit(cache=True, inline="always")
def _sift_up(i, heap, pos, khi, klo):
    s = heap[i]
    while i > 0:
        parent = (i - 1) >> 1
        p = heap[parent]
        if not before(s, p, khi, klo):
            break
        heap[i] = p
        pos[p] = i
        i = parent
    heap[i] = s
    pos[s] = i


@njit(cache=True, inline="always")
def _sift_down(i, heap, pos, khi, klo):
    m = heap.size
    s = heap[i]
    while True:
        child = 2 * i + 1
        if child >= m:
            break
        c = heap[child]
        if child + 1 < m and before(heap[child + 1], c, khi, klo):
            child += 1
            c = heap[child]
        if not before(c, s, khi, klo):
            break
        heap[i] = c
        pos[c] = i
        i = child
    heap[i] = s
    pos[s] = i


@njit(cache=True)
def heapify(heap, pos, khi, klo):
    """Put every slot 0..M-1 in the heap (Floyd's O(M) construction)."""
    m = heap.size
    for i in range(m):
        heap[i] = i
        pos[i] = i
    for i in range(m // 2 - 1, -1, -1):
        _sift_down(i, heap, pos, khi, klo)


@njit(cache=True, inline="always")
def update(s, hi, lo, heap, pos, khi, klo):
    """Give slot s the key (hi, lo) and move it to its place in the heap."""
    old_hi, old_lo = khi[s], klo[s]
    khi[s] = hi
    klo[s] = lo
    if hi < old_hi or (hi == old_hi and lo < old_lo):
        _sift_up(pos[s], heap, pos, khi, klo)
    elif hi != old_hi or lo != old_lo:
        _sift_down(pos[s], heap, pos, khi, klo)


def empty_queue(m: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``(heap, pos, khi, klo)`` for m slots, every key (inf, 0) (call :func:`heapify` after setting keys)."""
    return (np.arange(m, dtype=np.int64), np.arange(m, dtype=np.int64), np.full(m, np.inf), np.zeros(m))

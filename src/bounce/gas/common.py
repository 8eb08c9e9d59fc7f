"""What the two gas engines share: geometries, contact slots, event kinds, stop reasons, record buffers.

Grains are numbered k = 0 .. n-1 from the floor up (column) or along the ring.  Contacts are
numbered by *slot*: slot k (0 <= k < n-1) is the pair of neighbours (k, k+1); slot n-1 is the floor
under grain 0 in the column and the pair (n-1, 0) across the ring's seam on the ring.  A recorded
event names its contact by ``pair``: the slot of a pair contact, :data:`FLOOR_PAIR` for the floor.

On the ring the positions are not wrapped: grains never pass each other, so the whole chain lies in
[x_0, x_0 + ell] at every time, and the seam's gap is x_0 + ell - y_{n-1}.  A ring with net momentum
drifts, and its positions then grow like the centre-of-mass velocity times t (reduce positions
modulo ell to draw them).
"""

from __future__ import annotations

import numpy as np
from numba import njit

COLUMN, RING = 0, 1
GEOMETRY_NAMES = ("column", "ring")

#: event kinds (netCDF flag_values): a floor impact, a pair impact, a zero-speed contact (floor or
#: pair, nothing exchanged), and the rigid TC model's elastic collisions (floor, pair)
FLOOR, PAIR, GRAZING, FLOOR_ELASTIC, PAIR_ELASTIC = range(5)
KIND_NAMES = ("floor", "pair", "grazing", "floor_elastic", "pair_elastic")
#: ``pair`` of a floor event
FLOOR_PAIR = -1

# why a run ended
(STOP_EVENTS, STOP_TIME, STOP_QUIET, STOP_OVERLAP, STOP_STICKY, STOP_COLLAPSE,
 STOP_FAILED, STOP_COOLED) = range(8)
STOP_NAMES = ("max_events", "t_max", "no_more_events", "overlap", "sticky", "collapse", "root_finder_failed",
              "cooled_below_rounding")

# slots of the int64 control array ``ctl`` a run carries between calls (the engines' state beside
# the grain, slot and queue arrays): events recorded so far, why it stopped, the grain or slot the
# stop concerns, and, for the rigid engine's collapse detector, the current run of unresolved events
# and the lowest and highest grain in it
C_EVENTS, C_STOP, C_WHERE, C_RUN, C_LOW, C_HIGH = range(6)
CTL_SIZE = 6
# slots of the float64 control array ``clock``: the time of the last event (double-double)
K_HI, K_LO = range(2)
CLOCK_SIZE = 2


@njit(cache=True)
def below_slot(i, n, geometry):
    """The slot of the contact under grain i: pair (i-1, i), or the floor for i = 0 in the column."""
    if i == 0:
        return n - 1
    return i - 1


@njit(cache=True)
def above_slot(j, n, geometry):
    """The slot of the pair (j, j+1) above grain j; -1 for the top grain of the column."""
    if geometry == COLUMN and j == n - 1:
        return -1
    return j


@njit(cache=True)
def slot_grains(s, n, geometry):
    """(i, j, seam) of slot s: the pair (i, j) and whether it crosses the ring's seam (j = 0);
    (-1, 0, False) for the floor."""
    if s == n - 1:
        if geometry == COLUMN:
            return -1, 0, False
        return n - 1, 0, True
    return s, s + 1, False


class Records:
    """Per-event buffers of one engine call (t, kind, pair, speed) and snapshot buffers.

    ``t``: time of the event (the double-double clock rounded to float64); ``kind``: KIND_NAMES;
    ``pair``: the contact's slot (FLOOR_PAIR for the floor); ``speed``: the approach speed of the two
    masses (or of the lower mass and the floor) just before the event.  Snapshots: the state of every
    grain just after every ``every``-th event (``snap_event`` its index), ``fields`` arrays of shape
    (capacity, n).
    """

    def __init__(self, events: int, n: int, every: int, fields: int):
        self.t = np.empty(events)
        self.kind = np.empty(events, dtype=np.int8)
        self.pair = np.empty(events, dtype=np.int32)
        self.speed = np.empty(events)
        cap = events // every + 1 if every > 0 else 0
        self.snap_t = np.empty(cap)
        self.snap_event = np.empty(cap, dtype=np.int64)
        self.snap = np.empty((fields, cap, n))

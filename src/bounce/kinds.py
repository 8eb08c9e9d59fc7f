"""The vocabulary of the event records, defined once: event kinds and stop reasons.

Every solver writes these codes (:mod:`bounce.exact.events`, :mod:`bounce.series.events`), the
records carry them (:class:`bounce.trajectory.Trajectory`, the netCDF ``kind`` variable with
``flag_values``/``flag_meanings``, :mod:`bounce.io`), and the claims, figures and studies read them
from here, never as literals.

Event kinds (the paper's section 2-3 classification of a contact with the floor, x = 0):

* ``impact`` (eq. ``collision-rule``): psi' and xi' exchanged;
* ``grazing`` (eq. ``swishes``): a tangential contact with x'' > 0, nothing exchanged;
* ``sticky_start`` (eq. ``sticky-condition``): x = x' = x'' = 0, the lower mass stays on the floor;
* ``detach`` (eq. ``cond_di_distacco``): the floor force vanishes and the mass lifts off.

Stop reasons index :data:`STOP_NAMES` (``slow_crossing`` is the series solver's own: a crossing of
the rest length xi = 0 too slow to be computed to rounding).
"""

from __future__ import annotations

#: event kind codes (netCDF flag_values) and their names (flag_meanings)
IMPACT, GRAZING, STICKY_START, DETACH = 0, 1, 2, 3
KIND_NAMES = ("impact", "grazing", "sticky_start", "detach")

#: why an event loop ended: codes and names
STOP_EVENTS, STOP_TIME, STOP_ENERGY, STOP_STICKY_FOREVER, STOP_FAILED, STOP_SLOW_CROSSING = range(6)
STOP_NAMES = ("max_events", "t_max", "energy", "sticky_forever", "root_finder_failed", "slow_crossing")

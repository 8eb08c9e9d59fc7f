"""Random gases on a ring, shared by the sweeps that compare rigid and deformable grains (beyond the paper).

* :func:`ring_points`: n points on a ring of circumference n (unit density), positions uniform and sorted,
  velocities standard normal times ``speed`` minus their mean (the centre-of-mass frame);
* :func:`run_rigid_ring`: those points as rigid grains with constant restitution r until they collapse, cool by a
  factor, or reach a collision cap (:mod:`bounce.sweeps.rigid_gas_collapse` explains the three outcomes);
* :func:`dimer_state` and :func:`mu_of_restitution`: the same gas as dimers (the paper's balls, each of rest length
  1, springs at rest) on a ring of circumference 2n, so that the free length per grain is the points' (a hard rod
  of length 1 on a ring of 2n moves as a point on a ring of n), with the damping whose single-impact restitution
  exp(-mu T_xi) (eq. ``rest-coefficient-function-of-mu``) is r.
* :func:`collision_rate`: the collision rate per grain of points with given velocities at uniform positions;
* :func:`states_at`: every grain's state at given times of a run, exact to rounding (the sweeps that follow a gas in
  time);
* :func:`contacts`, :func:`merge_contacts`, :func:`partner_sides`, :func:`parting`: a run's contacts, the dimers'
  micro-impacts merged into collisions, each grain's ordered partners, and the first collision where two gases' grain
  histories differ (sweep ``rigid-suffices``).
"""

from __future__ import annotations

import math

import numpy as np

from ..gas.model import GasState, RigidParameters, RigidState
from ..gas.simulate import GasRun
from .theory import rest_coefficient_function_of_mu

COLLAPSE, COOLED, CAP = 0, 1, 2
OUTCOMES = ("collapse", "cooled", "cap")


def ring_points(n: int, rng: np.random.Generator, speed: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """(positions, velocities) of n points on a ring of circumference n, drawn by ``rng`` (positions first)."""
    x = np.sort(rng.uniform(0.0, float(n), n))
    v = rng.standard_normal(n)
    v -= v.mean()
    return x, speed * v


def run_rigid_ring(r: float, x: np.ndarray, v: np.ndarray, cooling: float, check_every: int,
                   max_collisions: int) -> tuple[int, float, float]:
    """(outcome, collisions per grain, time of the last collision) of the points (x, v) as rigid grains."""
    n = x.size
    run = GasRun(RigidParameters(n, "ring", 0.0, r, ell=float(n), size=0.0), RigidState(x, v), math.inf, 0)
    start = float(np.sum(v * v))  # (x, v) in the centre-of-mass frame (ring_points)
    while run.events < max_collisions * n:
        run.step(min(check_every * n, max_collisions * n - run.events))
        if run.stop == "collapse":
            return COLLAPSE, run.events / n, run.t_end
        if run.finished:  # no_more_events or cooled_below_rounding: cooled without end
            return COOLED, run.events / n, run.t_end
        w = run.final()["xdot"]
        w = w - w.mean()
        if float(np.sum(w * w)) <= cooling * start:
            return COOLED, run.events / n, run.t_end
    return CAP, run.events / n, run.t_end


def dimer_state(x: np.ndarray, v: np.ndarray) -> GasState:
    """The points (x, v) of a ring of circumference n as dimers on a ring of 2n: grain k's lower mass at x_k + k, its
    spring at rest (xi = xi' = 0), its centre of mass moving at v_k."""
    n = x.size
    return GasState(x + np.arange(n), v, np.zeros(n), np.zeros(n))


def mu_of_restitution(r: float) -> float:
    """The damping mu < 1 with exp(-mu T_xi(mu)) = r, 0 < r < 1 (bisection: r decreases in mu; to 2 ulps of mu)."""
    if not 0.0 < r < 1.0:
        raise ValueError(f"r must be in (0, 1), got {r!r}")
    lo, hi = 0.0, 1.0
    while True:
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):
            return mid
        lo, hi = (mid, hi) if rest_coefficient_function_of_mu(mid) > r else (lo, mid)


def collision_rate(v: np.ndarray, ell: float) -> float:
    """Collisions per grain per unit time of points with velocities v at independent uniform positions on a ring of
    circumference ell: 2 sum_{i<j} |v_i - v_j| / (n ell) (a pair meets once per relative lap ell/|v_i - v_j|; each
    collision counts for two grains).  Elastic points keep it for ever (they exchange velocities: the free gas
    relabelled), so it is the initial rate of any restitution; for standard normal v times s at density 1 it tends to
    2 s/sqrt(pi)."""
    w = np.sort(np.asarray(v, dtype=float))
    n = w.size
    pairs = float(np.sum(w * (2.0 * np.arange(n) - (n - 1))))  # sum_{i<j} (w_j - w_i) of the sorted velocities
    return 2.0 * pairs / (n * ell)


def states_at(run: GasRun, times: np.ndarray, chunk: int) -> tuple[dict[str, np.ndarray], np.ndarray]:
    """(every grain's state at each of the increasing ``times``: the engine's fields as arrays (times, n); the events
    up to each time), exact to rounding.

    The run is stepped ``chunk`` events at a time; a chunk that passes the next time is undone
    (:meth:`~bounce.gas.simulate.GasRun.restore`, bit for bit) and replayed up to the last event at or before that time,
    where the grains are evaluated in closed form (:meth:`~bounce.gas.simulate.GasRun.at`), so each row is the state
    at its time whatever ``chunk`` is (replays cost at most ``chunk`` events per time).  A time after a run that reached
    its t_max or has no event left is the free motion after its last event; a time after any other stop (collapse,
    an engine stop) gets NaN and -1 events.
    """
    times = np.asarray(times, dtype=float)
    out = {name: np.full((times.size, run.params.n), np.nan) for name in run.fields}
    events = np.full(times.size, -1, dtype=np.int64)
    i = 0

    def record(i: int) -> None:
        for name, value in run.at(float(times[i])).items():
            out[name][i] = value
        events[i] = run.events

    while i < times.size and not run.finished:
        saved = run.arrays()
        rec, k, _ = run.step(chunk)
        before = int(np.searchsorted(rec.t[:k], times[i], side="right"))
        if before < k:
            run.restore(saved)
            if before:
                run.step(before)
            record(i)
            i += 1
    while i < times.size and run.stop in ("t_max", "no_more_events") and times[i] <= run.t_max:
        record(i)
        i += 1
    return out, events


def contacts(run: GasRun, max_events: int, chunk: int = 1 << 16) -> tuple[np.ndarray, np.ndarray]:
    """(time, slot) of every contact event of ``run`` until it stops or has ``max_events`` events (slot s: grains s and
    s + 1 mod n, :func:`bounce.gas.common.slot_grains`)."""
    ts, slots = [], []
    while run.events < max_events and not run.finished:
        rec, k, _ = run.step(min(chunk, max_events - run.events))
        ts.append(rec.t[:k].copy())
        slots.append(rec.pair[:k].astype(np.int64))
    if not ts:
        return np.zeros(0), np.zeros(0, dtype=np.int64)
    return np.concatenate(ts), np.concatenate(slots)


def merge_contacts(t: np.ndarray, slot: np.ndarray, window: float) -> tuple[np.ndarray, np.ndarray]:
    """(time, slot) of the collisions made of the micro-impacts (t, slot), in time order: a micro-impact opens a new
    collision of its slot unless the slot's previous micro-impact came less than ``window`` before it.  A collision's
    time is its first micro-impact's (when the two grains first touch).

    Two dimers colliding alone make two micro-impacts T_xi(mu) apart (the masses exchange velocities, the springs
    swing once and the masses meet again: eq. ``rest-coefficient-function-of-mu``'s double impact), so a window above
    T_xi and well below the free time between collisions counts each such collision once."""
    order = np.lexsort((t, slot))
    ts, ss = t[order], slot[order]
    new = np.ones(ts.size, dtype=bool)
    new[1:] = (ss[1:] != ss[:-1]) | (ts[1:] - ts[:-1] >= window)
    keep = np.sort(order[new])
    return t[keep], slot[keep]


def partner_sides(t: np.ndarray, slot: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Every grain's collisions in its own order: (side, time, count), side[g, k] = +1 if grain g's k-th collision is
    with its right neighbour g + 1, -1 with its left neighbour g - 1 (mod n), 0 past its count[g] collisions; time[g, k]
    its time (inf past the count)."""
    grain = np.concatenate([slot, (slot + 1) % n])
    side = np.concatenate([np.ones(slot.size, dtype=np.int8), -np.ones(slot.size, dtype=np.int8)])
    time = np.concatenate([t, t])
    order = np.lexsort((time, grain))
    grain, side, time = grain[order], side[order], time[order]
    count = np.bincount(grain, minlength=n)
    k = np.arange(grain.size) - np.repeat(np.cumsum(count) - count, count)
    sides = np.zeros((n, max(int(count.max(initial=0)), 1)), dtype=np.int8)
    times = np.full(sides.shape, np.inf)
    sides[grain, k], times[grain, k] = side, time
    return sides, times, count


def parting(rigid: tuple[np.ndarray, np.ndarray], dimer: tuple[np.ndarray, np.ndarray], n: int) -> tuple[float, int]:
    """(time, grain) of the first collision of the rigid gas that the dimer gas does not make: the first k-th collision
    of a grain whose partner (left or right neighbour) differs from the dimer grain's k-th, or that the dimer grain
    lacks; (inf, -1) when every grain's rigid collisions are the dimer grain's first ones.  ``rigid`` and ``dimer``:
    the collisions (time, slot) of the two gases, the dimers' recorded past the rigid gas's last."""
    rs, rt, rc = partner_sides(*rigid, n)
    ds, _, dc = partner_sides(*dimer, n)
    width = rs.shape[1]
    ds = np.pad(ds, ((0, 0), (0, max(width - ds.shape[1], 0))))[:, :width]
    k = np.arange(width)[None, :]
    differ = (k < rc[:, None]) & (rs != ds)  # past the dimer's count its side is 0: a missing collision differs
    first = np.where(differ.any(axis=1), differ.argmax(axis=1), width)
    t = np.where(first < width, rt[np.arange(n), np.minimum(first, width - 1)], np.inf)
    g = int(np.argmin(t))
    return (float(t[g]), g) if math.isfinite(t[g]) else (math.inf, -1)

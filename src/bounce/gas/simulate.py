"""Python front of the gas engines: validate, allocate, run in chunks, wrap.

>>> import numpy as np
>>> from bounce.gas import GasParameters, GasState, simulate_gas
>>> p = GasParameters(n=2, geometry="column", gamma=0.01, mu=0.1)
>>> s = GasState(psi=np.array([1.0, 3.0]), psidot=np.zeros(2), xi=np.zeros(2), xidot=np.zeros(2))
>>> res = simulate_gas(p, s, max_events=4)
>>> res.kind_names[:2], res.pair[:2].tolist()
(('pair', 'floor'), [0, -1])

:func:`simulate_gas` runs the dimer gas (:mod:`bounce.gas.dimer`), :func:`simulate_rigid` its rigid
counterpart (:mod:`bounce.gas.rigid`); both return a :class:`GasResult`: per event the time, kind,
contact (``pair``: the slot, -1 the floor) and approach speed; every ``snapshot_every``-th event
the state of all grains; the state after the last event (``final``); why the run stopped, and a
message saying where when that was not the event cap or t_max.  :class:`GasRun` is the chunked driver
(the progress bar and the netCDF stream use it): the kernels keep their whole state in its arrays,
so N calls of m events give the bits of one call of N m events.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ..exact.flight import EPS
from ..exact.oscillator import make_oscillator
from .common import (
    C_EVENTS, C_HIGH, C_LOW, C_RUN, C_STOP, C_WHERE, CLOCK_SIZE, CTL_SIZE, GEOMETRY_NAMES, K_HI, K_LO, KIND_NAMES,
    STOP_COLLAPSE, STOP_COOLED, STOP_NAMES, STOP_OVERLAP, STOP_STICKY, Records, slot_grains,
)
from .dimer import GRAIN_FIELDS, G_A, G_ETA, G_U, G_X, SLOT_FIELDS, dimer_run, dimer_snapshot, dimer_start
from .model import GasParameters, GasState, RigidParameters, RigidState
from .queue import empty_queue
from .rigid import R_LAST, R_V, R_X, RIGID_FIELDS, rigid_run, rigid_snapshot, rigid_start

#: snapshot fields of each model, in the kernels' order
DIMER_FIELDS = ("x", "xdot", "xidot", "eta")
RIGID_FIELDS_NAMES = ("x", "xdot")
#: most events one call records in memory, and the default chunk of the progress bar and the stream
MAX_EVENTS = 10**10
DEFAULT_CHUNK = 1 << 18
#: event times kept for telling a collapse from a gas cooled below rounding (:meth:`GasRun.step`): two windows
TREND_EVENTS = 64
#: the whole gas is "cold" at a speed stop when no neighbouring pair moves apart or together faster than this many
#: times the stop's rounding threshold 8 eps (|x_i'| + |x_j'|)
COLD_FACTOR = 2.0**20


def positive_int(name: str, value, largest: int, smallest: int = 1) -> int:
    try:
        number = float(value)
    except (TypeError, ValueError, OverflowError):
        number = math.nan
    if isinstance(value, bool) or not (number.is_integer() and smallest <= number <= largest):
        raise InputError(f"{name} must be an integer in [{smallest}, {largest:.0e}] (allowed range), got {value!r}")
    return int(number)


def run_settings(max_events, t_max, snapshot_every) -> tuple[int, float, int]:
    """The validated stop rules and snapshot interval: events in [1, MAX_EVENTS], t_max in (0, inf],
    snapshot_every in [0, MAX_EVENTS] (0: no snapshots besides the final state)."""
    max_events = positive_int("max_events", max_events, MAX_EVENTS)
    try:
        t_max = float(t_max)
    except (TypeError, ValueError):
        t_max = math.nan
    if math.isnan(t_max) or not t_max > 0.0:
        raise InputError(f"t_max must be > 0 (allowed range: (0, inf]), got {t_max!r}")
    snapshot_every = positive_int("snapshot_every", snapshot_every, MAX_EVENTS, smallest=0)
    return max_events, t_max, snapshot_every


class GasRun:
    """One run of either engine: its arrays, its kernel calls in chunks, its stop.

    ``step(m)`` advances by up to m events and returns the chunk's :class:`~bounce.gas.common.Records`
    with the numbers recorded; ``final()`` is every grain's state at the last event's time; ``arrays()``
    the engine's whole state, from which ``GasRun(..., arrays=...)`` continues bit for bit.
    """

    def __init__(self, params: GasParameters | RigidParameters, initial: GasState | RigidState, t_max: float,
                 every: int, arrays: dict | None = None):
        initial.check(params)
        self.params, self.initial, self.t_max, self.every = params, initial, t_max, every
        self.rigid = isinstance(params, RigidParameters)
        n = params.n
        self.geometry = GEOMETRY_NAMES.index(params.geometry)
        self.tree, self.khi, self.klo = empty_queue(n)
        self.ctl = np.zeros(CTL_SIZE, dtype=np.int64)
        self.clock = np.zeros(CLOCK_SIZE)
        self.fields = RIGID_FIELDS_NAMES if self.rigid else DIMER_FIELDS
        self.g = np.zeros((n, RIGID_FIELDS if self.rigid else GRAIN_FIELDS))
        if not self.rigid:
            self.osc = make_oscillator(params.mu)
            self.sl = np.zeros((n, SLOT_FIELDS))
        self.records = None
        self.times = np.full(2 * TREND_EVENTS + 1, np.nan)  # the last event times (rigid gas, :meth:`_cooled`)
        if arrays is not None:
            self.restore(arrays)
        elif self.rigid:
            self.g[:, R_X], self.g[:, R_V] = initial.x, initial.xdot
            self.g[:, R_LAST] = -np.inf
            rigid_start(self.geometry, n, params.gamma, params.wrap, params.size, self.g, self.tree,
                        self.khi, self.klo)
        else:
            x, u, a, eta = initial.deviations(params.gamma)
            self.g[:, G_X], self.g[:, G_U], self.g[:, G_A], self.g[:, G_ETA] = x, u, a, eta
            dimer_start(self.geometry, n, params.gamma, params.wrap, t_max, *self.osc, self.g, self.sl, self.tree,
                        self.khi, self.klo)
        self.stop = STOP_NAMES[int(self.ctl[C_STOP])]

    def _state_names(self) -> tuple[str, ...]:
        return ("g", "tree", "khi", "klo", "ctl", "clock") + (("times",) if self.rigid else ("sl",))

    def arrays(self) -> dict[str, np.ndarray]:
        """The engine's whole state (grains, slots, queue, control): copies."""
        return {name: getattr(self, name).copy() for name in self._state_names()}

    def restore(self, arrays: dict) -> None:
        """Back to a state of :meth:`arrays` of this run: the steps taken since are undone bit for bit (the kernels keep
        their whole state in these arrays)."""
        for name in self._state_names():
            mine = getattr(self, name)
            if name not in arrays or np.shape(arrays[name]) != mine.shape:
                raise InputError(f"--resume: the checkpoint's {name!r} does not fit this engine (written by another "
                                 "version of bounce or another run); rerun without --resume")
            mine[...] = arrays[name]
        self.stop = STOP_NAMES[int(self.ctl[C_STOP])]

    @property
    def events(self) -> int:
        return int(self.ctl[C_EVENTS])

    @property
    def t_end(self) -> float:
        """Time of the last event (t_max at a t_max stop, inf when nothing can happen any more)."""
        if self.stop == "t_max":
            return self.t_max
        if self.stop == "no_more_events":
            return math.inf
        return float(self.clock[K_HI] + self.clock[K_LO])

    def step(self, m: int) -> tuple[Records, int, int]:
        """Up to m more events: ``(records, n_events, n_snapshots)`` (records valid until the next step)."""
        if self.records is None or self.records.t.size < m:
            self.records = Records(m, self.params.n, self.every, len(self.fields))
        rec = self.records
        args = (self.every, rec.t, rec.kind, rec.pair, rec.speed, rec.snap_t, rec.snap_event, rec.snap)
        p = self.params
        if self.rigid:
            k, snaps = rigid_run(self.geometry, p.n, p.gamma, p.wrap, p.size, p.r, p.t_c, self.t_max, self.g, self.tree,
                                 self.khi, self.klo, self.ctl, self.clock, m, *args)
        else:
            k, snaps = dimer_run(self.geometry, p.n, p.gamma, p.wrap, self.t_max, *self.osc, self.g, self.sl,
                                 self.tree, self.khi, self.klo, self.ctl, self.clock, m, *args)
        if self.rigid:
            self.times = np.concatenate([self.times, rec.t[:k]])[-self.times.size:]
            if int(self.ctl[C_STOP]) == STOP_COLLAPSE and self.ctl[C_WHERE] >= 0 and self._cooled():
                self.ctl[C_STOP] = STOP_COOLED
        self.stop = STOP_NAMES[int(self.ctl[C_STOP])]
        if self.stop == "root_finder_failed":
            raise RuntimeError(f"the gas engine's root finder did not converge for contact {int(self.ctl[C_WHERE])} "
                               f"after event {self.events} (t = {self.t_end!r}); please report the parameters and "
                               f"initial state")
        return rec, k, snaps

    def _cooled(self) -> bool:
        """At a speed stop of the rigid gas (an approach speed within 8 ulps of its grains' speeds): has the whole
        gas cooled to the rounding of its common velocity, rather than a cluster collapsed?

        A cooling gas (Haff's law) drifts with the rounding residue of its momentum (~eps |x'|) while its relative
        speeds decay without end, so in float64 they reach that residue's rounding, ~1e-16 of the drift, and the speed
        criterion fires although no collapse happens (a 10-grain ring at r = 0.95 after ~700 collisions per grain).
        Cooled: every neighbouring pair's relative speed is within COLD_FACTOR of the stop's threshold (no part of the
        gas is still warm), and the collisions do not accumulate: the last TREND_EVENTS intervals between events sum
        to no less than the TREND_EVENTS before them (in a collapse they shrink geometrically; in cooling they grow,
        as t).  A collapse of the whole gas (every grain in one cluster) is told apart by the second test."""
        v = self.final()["xdot"]
        i, j, _ = slot_grains(int(self.ctl[C_WHERE]), self.params.n, self.geometry)
        threshold = 8.0 * EPS * (abs(v[i]) + abs(v[j]))
        spread = np.abs(np.diff(v)).max() if v.size > 1 else 0.0
        if self.params.geometry == "ring" and v.size > 1:
            spread = max(spread, abs(v[-1] - v[0]))
        if not spread <= COLD_FACTOR * threshold or np.isnan(self.times).any():
            return False
        gaps = np.diff(self.times)
        return gaps[TREND_EVENTS:].sum() >= gaps[:TREND_EVENTS].sum()

    @property
    def finished(self) -> bool:
        return self.stop != "max_events"

    def final(self) -> dict[str, np.ndarray]:
        """Every grain's state at the time of the last event (t = 0 before any)."""
        return self.at(self.clock[K_HI], self.clock[K_LO])

    def at(self, t_hi: float, t_lo: float = 0.0) -> dict[str, np.ndarray]:
        """Every grain's state at time t_hi + t_lo, in closed form from its last event: exact (to rounding) for a time
        between the last event and the next one (not checked: later than the next event it is the free motion through
        that contact)."""
        out = np.empty((len(self.fields), 1, self.params.n))
        if self.rigid:
            rigid_snapshot(self.g, t_hi, t_lo, self.params.gamma, out, 0)
        else:
            dimer_snapshot(self.g, t_hi, t_lo, self.params.gamma, *self.osc, out, 0)
        return {name: out[i, 0] for i, name in enumerate(self.fields)}

    def message(self) -> str:
        """What stopped the run, where, when the stop is not the event cap, t_max or the last contact."""
        t = float(self.clock[K_HI] + self.clock[K_LO])
        where = int(self.ctl[C_WHERE])
        code = int(self.ctl[C_STOP])
        if code == STOP_OVERLAP:
            return (f"grain {where}: its internal energy (xi^2 + xi'^2)/2 reached 1/8 at the event at t = {t!r} "
                    f"(event {self.events - 1}); beyond it its two masses may pass (y - x = 1 + 2 xi <= 0), so the run "
                    f"stops there")
        if code == STOP_STICKY:
            what = "the floor" if self.geometry == 0 and where == self.params.n - 1 else f"pair {where}"
            return (f"{what}: a zero-speed contact that does not open at t = {t!r} (a sticky contact, eq. "
                    f"sticky-condition or its pair analogue; non-generic): the gas engine follows no sticky phase")
        if code == STOP_COOLED:
            return (f"cooled below rounding at t = {t!r}: the grains' relative speeds reached the rounding of their common "
                    f"velocity (8 ulps of the colliding grains' speeds, with no warmer pair and no accumulation of "
                    f"collisions: not a collapse, GasRun._cooled), {self.events} collisions in all")
        if code == STOP_COLLAPSE:
            run = (f"{int(self.ctl[C_RUN])} unresolved collisions in a row among grains {int(self.ctl[C_LOW])}.."
                   f"{int(self.ctl[C_HIGH])}, {self.events} collisions in all")
            if where >= 0:
                return (f"inelastic collapse detected at t = {t!r}: the collision at contact {where} approaches at a "
                        f"speed below the rounding of the grains' speeds (relative speeds shrinking below rounding); "
                        f"{run}")
            return (f"inelastic collapse at t = {t!r}: the float64 clock stopped advancing (collision times "
                    f"accumulating below rounding); {run}")
        return ""

    def collapse(self) -> dict | None:
        if int(self.ctl[C_STOP]) != STOP_COLLAPSE:
            return None
        return {"t": self.t_end, "grains": (int(self.ctl[C_LOW]), int(self.ctl[C_HIGH])), "run": int(self.ctl[C_RUN]),
                "collisions": self.events, "contact": int(self.ctl[C_WHERE]),
                "criterion": "speed" if self.ctl[C_WHERE] >= 0 else "clock"}


@dataclass(frozen=True)
class GasResult:
    """Per-event records, snapshots and the final state of a gas run (module docstring)."""

    params: GasParameters | RigidParameters
    initial: GasState | RigidState
    t: np.ndarray
    kind: np.ndarray
    pair: np.ndarray
    speed: np.ndarray
    snap_t: np.ndarray
    snap_event: np.ndarray
    snapshots: dict
    final: dict
    stop_reason: str
    t_end: float
    message: str = ""
    collapse: dict | None = None
    settings: dict = field(default_factory=dict)

    @property
    def model(self) -> str:
        return "rigid" if isinstance(self.params, RigidParameters) else "dimer"

    @property
    def kind_names(self) -> tuple[str, ...]:
        return tuple(KIND_NAMES[k] for k in self.kind)

    def __len__(self) -> int:
        return len(self.t)


def _bar(total: int, progress: bool | None, initial: int = 0):
    from tqdm import tqdm

    enabled = sys.stderr.isatty() if progress is None else bool(progress)
    return tqdm(total=total, initial=initial, unit="event", unit_scale=True, file=sys.stderr, desc="bounce gas",
                disable=not enabled, mininterval=0.5 if sys.stderr.isatty() else 30.0)


def run_chunks(run: GasRun, max_events: int, chunk: int, progress: bool | None = None, done: int = 0):
    """Yield ``(records, n_events, n_snapshots)`` per chunk of at most ``chunk`` events until the run stops or
    has ``max_events`` events, with a progress bar."""
    with _bar(max_events, progress, done) as bar:
        while run.events < max_events:
            rec, k, snaps = run.step(min(chunk, max_events - run.events))
            bar.update(k)
            yield rec, k, snaps
            if run.finished:
                return


def _simulate(params, initial, max_events, t_max, snapshot_every, chunk, progress) -> GasResult:
    max_events, t_max, every = run_settings(max_events, t_max, snapshot_every)
    chunk = positive_int("chunk", chunk, MAX_EVENTS)
    run = GasRun(params, initial, t_max, every)
    parts = []
    for rec, k, snaps in run_chunks(run, max_events, chunk, progress):
        parts.append((rec.t[:k].copy(), rec.kind[:k].copy(), rec.pair[:k].copy(), rec.speed[:k].copy(),
                      rec.snap_t[:snaps].copy(), rec.snap_event[:snaps].copy(), rec.snap[:, :snaps].copy()))

    def cat(i, empty):
        return np.concatenate([p[i] for p in parts]) if parts else empty

    n = params.n
    snap = (np.concatenate([p[6] for p in parts], axis=1) if parts
            else np.empty((len(run.fields), 0, n)))
    return GasResult(
        params=params, initial=initial, t=cat(0, np.empty(0)), kind=cat(1, np.empty(0, np.int8)),
        pair=cat(2, np.empty(0, np.int32)), speed=cat(3, np.empty(0)), snap_t=cat(4, np.empty(0)),
        snap_event=cat(5, np.empty(0, np.int64)), snapshots={name: snap[i] for i, name in enumerate(run.fields)},
        final=run.final(), stop_reason=run.stop, t_end=run.t_end, message=run.message(), collapse=run.collapse(),
        settings={"max_events": max_events, "t_max": t_max, "snapshot_every": every},
    )


def simulate_gas(params: GasParameters, initial: GasState, max_events: int = 1000, t_max: float = math.inf,
                 snapshot_every: int = 0, chunk: int = DEFAULT_CHUNK, progress: bool | None = False) -> GasResult:
    """Simulate the dimer gas (:mod:`bounce.gas.dimer`) until ``max_events`` events, ``t_max``, no contact
    left, or a stop of the engine (overlap, sticky contact), with snapshots of all grains (x, xdot,
    xidot, eta) every ``snapshot_every`` events.  Every contact time to rounding, none skipped."""
    if not isinstance(params, GasParameters) or not isinstance(initial, GasState):
        raise InputError("simulate_gas takes GasParameters and a GasState (bounce.gas)")
    return _simulate(params, initial, max_events, t_max, snapshot_every, chunk, progress)


def simulate_rigid(params: RigidParameters, initial: RigidState, max_events: int = 1000, t_max: float = math.inf,
                   snapshot_every: int = 0, chunk: int = DEFAULT_CHUNK, progress: bool | None = False) -> GasResult:
    """Simulate the rigid gas (:mod:`bounce.gas.rigid`): as :func:`simulate_gas`, snapshots (x, xdot), and the
    collapse stop (``result.collapse``: time, grains, collisions)."""
    if not isinstance(params, RigidParameters) or not isinstance(initial, RigidState):
        raise InputError("simulate_rigid takes RigidParameters and a RigidState (bounce.gas)")
    return _simulate(params, initial, max_events, t_max, snapshot_every, chunk, progress)


def energy_excess(params: GasParameters, fields: dict) -> np.ndarray:
    """Per-grain E - E_m = (xi'^2 + psi'^2 + eta^2)/2 + gamma x (eqs. tot-mech-energy, Emin; the single ball's
    :func:`bounce.exact.events.energy_excess`) of snapshot fields (any shape); the gas's total is the sum over grains."""
    u, a, eta, x = fields["xdot"], fields["xidot"], fields["eta"], fields["x"]
    return 0.5 * (a * a + (u + a) * (u + a) + eta * eta) + params.gamma * x

"""The record of a simulation: per-event arrays, the stop rules of a run, and the one way a solver's
event loop is run into them.

Every solver (:mod:`bounce.exact.events`, :mod:`bounce.series.events`) fills the same buffers (times,
phase durations, the state just after each event in deviations, E - E_m, the kind code of
:mod:`bounce.kinds`) through :func:`run_into_trajectory`; the front (:mod:`bounce.simulate`), the
streaming driver (:mod:`bounce.stream`) and the netCDF layer (:mod:`bounce.io`) read them as a
:class:`Trajectory`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .kinds import KIND_NAMES, STOP_FAILED, STOP_NAMES
from .model import Deviations, InputError, Parameters, State

#: memory of one event record (six float64 arrays and the int8 kind)
BYTES_PER_EVENT = 6 * 8 + 1
#: most events one call records (the buffers are allocated up front)
MAX_EVENTS = 10**10


@dataclass(frozen=True)
class Trajectory:
    """Per-event records of one simulation (event = impact, grazing, sticky_start, detach).

    ``t`` is the event time, ``tau`` the duration of the phase that ends at it
    (time since the previous event or since t = 0), and ``xdot``, ``xidot``,
    ``eta`` the state just after it (x = 0 at every event): xdot the lower-mass
    velocity, xidot = xi', eta = xi + gamma.  ``energy_excess`` is E - E_m.
    """

    params: Parameters
    initial: State | Deviations
    t: np.ndarray
    tau: np.ndarray
    xdot: np.ndarray
    xidot: np.ndarray
    eta: np.ndarray
    energy_excess: np.ndarray
    kind: np.ndarray
    stop_reason: str
    t_end: float
    settings: dict = field(default_factory=dict)

    @property
    def y_minus_yeq(self) -> np.ndarray:
        """y - y_eq = 2 eta at the events (x = 0), without cancellation."""
        return 2.0 * self.eta

    @property
    def y(self) -> np.ndarray:
        return self.params.y_eq + 2.0 * self.eta

    @property
    def ydot(self) -> np.ndarray:
        return self.xdot + 2.0 * self.xidot

    @property
    def energy(self) -> np.ndarray:
        return self.params.energy_min + self.energy_excess

    @property
    def kind_names(self) -> tuple[str, ...]:
        return tuple(KIND_NAMES[k] for k in self.kind)

    @property
    def t_valid(self) -> float:
        """Last time the records determine the motion up to (see :mod:`bounce.sampling`)."""
        if self.stop_reason in ("t_max", "sticky_forever"):
            return self.settings["t_max"] if self.stop_reason == "t_max" else float("inf")
        return float(self.t[-1]) if len(self.t) else 0.0

    def __len__(self) -> int:
        return len(self.t)


def positive_int(name: str, value, largest: int) -> int:
    try:
        number = float(value)
    except (TypeError, ValueError, OverflowError):
        number = math.nan
    if isinstance(value, bool) or not (number.is_integer() and 1 <= number <= largest):
        raise InputError(f"{name} must be an integer in [1, {largest:.0e}] (allowed range), got {value!r}")
    return int(number)


def stop_rules(max_events, t_max, energy_stop) -> tuple[int, float, float]:
    """The validated stop rules of a run (every spring law's front uses these): an event cap in
    [1, MAX_EVENTS], t_max in (0, inf], energy_stop a finite number >= 0."""
    max_events = positive_int("events", max_events, MAX_EVENTS)
    t_max = float(t_max)
    if math.isnan(t_max) or not t_max > 0.0:
        raise InputError(f"t_max must be > 0 (allowed range: (0, inf]), got {t_max!r}")
    energy_stop = float(energy_stop)
    if not (energy_stop >= 0.0 and math.isfinite(energy_stop)):
        raise InputError(f"energy_stop must be a finite number >= 0 (allowed range: [0, inf)), got {energy_stop!r}")
    return max_events, t_max, energy_stop


def run_into_trajectory(run, params, initial, stop: tuple[int, float, float], solver: str,
                        settings: dict | None = None) -> Trajectory:
    """The event loop ``run(*buffers, kind) -> (n, stop, t_end)`` of a solver, run into
    freshly allocated record buffers and wrapped as a :class:`Trajectory` (views when the buffers are
    full, so no 50 MB copy at 1e6 events; compact copies otherwise).  A failed root search raises, naming
    the ``solver``."""
    max_events, t_max, energy_stop = stop
    out = [np.empty(max_events) for _ in range(6)]
    kind = np.empty(max_events, dtype=np.int8)
    n, reason, t_end = run(*out, kind)
    if reason == STOP_FAILED:
        raise RuntimeError(
            f"{solver} did not converge after event {n} (t = {t_end!r}); "
            "please report the parameters and initial state"
        )
    t, tau, u, a, eta, e = (arr if n == max_events else arr[:n].copy() for arr in out)
    return Trajectory(
        params=params, initial=initial, t=t, tau=tau, xdot=u, xidot=a, eta=eta,
        energy_excess=e, kind=kind if n == max_events else kind[:n].copy(), stop_reason=STOP_NAMES[reason],
        t_end=t_end,
        settings={"max_events": max_events, "t_max": t_max, "energy_stop": energy_stop, **(settings or {})},
    )

"""Thin Python front of the event loop: validate, allocate, run, wrap.

>>> from bounce import Parameters, State, simulate
>>> p = Parameters(gamma=0.01, mu=0.01)
>>> traj = simulate(p, State.from_psi_xi(6.0, 0.0, 0.0, 0.0), max_events=5)
>>> traj.kind_names[:2], round(float(traj.t[0]), 6)
(('impact', 'impact'), 34.641016)
"""

from __future__ import annotations

import math

from .exact.events import simulate_linear
from .model import Deviations, InputError, Parameters, State
from .trajectory import Trajectory

#: spring laws (bounce.springs) the closed-form flights of bounce.exact.flight solve
EXACT_LAWS = ("linear",)
#: spring laws solved by the Taylor-series flights of bounce.series.flight (exact to rounding too)
SERIES_LAWS = ("power",)


def simulate(
    params: Parameters,
    initial: State | Deviations,
    max_events: int = 1000,
    t_max: float = math.inf,
    energy_stop: float = 0.0,
) -> Trajectory:
    """Simulate from ``initial`` (a State, or Deviations for states near equilibrium) until ``max_events`` events, ``t_max`` or E - E_m < ``energy_stop``.

    Exact to rounding: closed-form flights (:mod:`bounce.exact.flight`), a root finder
    that cannot skip an impact, closed-form sticky phases (:mod:`bounce.exact.events`); for the
    power-law spring (``params.spring``), Taylor-series flights and sticky phases with rigorous
    tails (:mod:`bounce.series.events`, :mod:`bounce.series.sticky`; one more stop reason,
    ``slow_crossing``).
    """
    if params.spring.name in SERIES_LAWS:  # no closed form: Taylor-series flights (bounce.series.events)
        from .series.events import simulate_power

        return simulate_power(params, params.spring, initial, max_events, t_max, energy_stop)
    if params.spring.name not in EXACT_LAWS:
        raise InputError(
            f"spring law must be one of {EXACT_LAWS + SERIES_LAWS}, got {params.spring.name!r}"
        )
    return simulate_linear(params, initial, max_events, t_max, energy_stop)

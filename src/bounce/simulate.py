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


def simulate(
    params: Parameters,
    initial: State | Deviations,
    max_events: int = 1000,
    t_max: float = math.inf,
    energy_stop: float = 0.0,
) -> Trajectory:
    """Simulate from ``initial`` (a State, or Deviations for states near equilibrium) until ``max_events`` events, ``t_max`` or E - E_m < ``energy_stop``.

    The solver is the one the law declares (``params.spring.solver``, :mod:`bounce.springs.base`), after the
    same domain check as the CLI (:func:`bounce.model.check_supported`).  Exact to rounding: closed-form flights
    (:mod:`bounce.exact.flight`), a root finder that cannot skip an impact, closed-form sticky phases
    (:mod:`bounce.exact.events`); for the power-law spring, Taylor-series flights and sticky phases with rigorous
    tails (:mod:`bounce.series.events`, :mod:`bounce.series.sticky`; one more stop reason, ``slow_crossing``).  A law
    with no exact solver is refused (run it with a general-purpose method, :mod:`bounce.methods`).
    """
    solver = params.spring.solver
    if solver == "series":  # no closed form: Taylor-series flights (bounce.series.events)
        from .series.events import simulate_power

        return simulate_power(params, params.spring, initial, max_events, t_max, energy_stop)
    if solver != "exact":
        raise InputError(
            f"spring law {params.spring.name!r} has no exact solver (bounce.springs: solver None); simulate it with "
            f"a general-purpose method of bounce.methods (CLI: simulate --method NAME)"
        )
    return simulate_linear(params, initial, max_events, t_max, energy_stop)

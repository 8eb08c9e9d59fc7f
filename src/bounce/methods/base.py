"""One small interface for every way of simulating the drop (speed-vs-accuracy study).

A method module defines ``METHOD = MethodSpec(name, run, settings_doc)``; its
contract:

1. ``run(params, initial, setting, *, max_events, t_max, sample_times) ->
   MethodResult``.  ``setting`` is a dict of the method's knobs (tolerance,
   step, stiffness, ...); ``initial`` a :class:`bounce.model.State`.
2. It reports contacts as it sees them: ``t`` the impact times (for soft-contact
   methods: the start of each contact), ``xdot`` the lower-mass speed just after
   (NaN where the method has no such notion), and, when ``sample_times`` is
   given, ``y`` sampled there (NaN after the method stopped).
3. It never raises on numerical failure: it stops and says how in ``failure``
   (one of FAILURES) with the index of the impact where it happened.
4. ``cpu_time`` is the process time of the run itself (no JIT compile: warm up
   before timing).
5. ``needs`` is the :class:`Capability` a spring law (:mod:`bounce.springs`) must have for the
   method to simulate it (any law: its numba physics; heyoka: a symbolic form; the exact solver
   and the models built on it: an exact solver, or its closed forms); the study drivers never hand it a
   ``params.spring`` without it.  The general-purpose methods call the law's physics
   (``params.spring.physics``, :mod:`bounce.springs.base`), never a right-hand side of their own.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np

#: how a method can fail (the stability map's categories)
FAILURES = (
    "",  # ran to max_events / t_max
    "missed_impact",  # stepped over a dip below the floor (an impact the exact solver has)
    "fell_through",  # x < -tolerance: the lower mass went through the floor
    "stall",  # zero-length flights: event location stuck at the floor
    "energy_gain",  # E - E_m rose by more than rounding
    "collapse",  # accumulation of impacts in finite time (inelastic collapse)
    "endless_contact",  # a contact that never ends (soft floor / time-stepping stuck)
    "budget",  # stopped by its CPU-time budget
)


@dataclass(frozen=True)
class MethodResult:
    method: str
    setting: dict
    t: np.ndarray
    xdot: np.ndarray
    cpu_time: float
    failure: str = ""
    failure_index: int = -1
    t_end: float = float("nan")
    y: np.ndarray | None = None
    extra: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.failure not in FAILURES:
            raise ValueError(f"failure must be one of {FAILURES}, got {self.failure!r}")


@dataclass(frozen=True)
class Capability:
    """What a method needs of a spring law: ``what`` in words (for refusals), ``test(law) -> bool``."""

    what: str
    test: Callable[..., bool]


#: every law: the contract's numba physics (f, f', g, V) is all a general-purpose method calls
ANY_LAW = Capability("a spring law with numba physics (any law of bounce.springs)",
                     lambda law: law.physics is not None)
#: a law with f and g as symbolic expressions (heyoka builds its Taylor integrator from them)
SYMBOLIC_LAW = Capability("a spring law with a symbolic form (SpringLaw.symbolic)",
                          lambda law: type(law).symbolic is not None)
#: a law an exact solver serves (closed forms or Taylor series, bounce.simulate)
EXACT_SOLVER = Capability("a spring law with an exact solver (SpringLaw.solver)", lambda law: law.solver is not None)
#: a law the closed-form solver serves (the models of the paper's linear ball built on its formulas)
CLOSED_FORM = Capability("a spring law of the closed-form exact solver (SpringLaw.solver == 'exact')",
                         lambda law: law.solver == "exact")


@dataclass(frozen=True)
class MethodSpec:
    name: str
    run: Callable[..., MethodResult]
    settings_doc: str = ""
    needs: Capability = CLOSED_FORM

    def supports(self, params) -> bool:
        """Can this method simulate ``params.spring``?"""
        return self.needs.test(params.spring)


def compile_exact_solver() -> None:
    """Compile (or load from numba's cache) the exact solver's kernels and its dense output once, so that a
    method's ``cpu_time`` never includes JIT compilation (contract rule 4)."""
    from ..model import Parameters, State
    from ..sampling import sample_trajectory
    from ..simulate import simulate

    tr = simulate(Parameters(0.01, 0.01), State.from_psi_xi(0.1, 0.0, 0.0, 0.0), max_events=3)
    sample_trajectory(tr, np.array([0.5]))

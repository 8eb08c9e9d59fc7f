"""The paper's linear damped spring (eq. ``dimensionless-eq-motion``): xi'' = -xi - 2 mu xi'.

f(xi) = xi, g(xi) = 1, V(xi) = xi^2/2; static equilibrium xi_eq = -gamma (eq. ``equilibrium``),
E_m = -gamma^2/2 (eq. ``Emin``).  Served by the closed-form exact solver (:mod:`bounce.exact`).

Supported domain (:meth:`LinearSpring.check_supported`, with the model-wide limits of
:func:`bounce.model.check_supported`): gamma in [GAMMA_MIN, 1/2) (the equilibrium y_eq = 1 - 2 gamma
above the floor), mu in [0, MU_MAX], and an initial energy whose longest possible flight is at most
FLIGHT_MAX (:func:`bounce.springs.base.SpringLaw.check_supported`: the root finder resolves every
spring oscillation of a flight).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from numba import njit

from ..errors import InputError
from .base import GAMMA_MIN, XI_EQ_MAX, Physics, SpringLaw


@njit(cache=True)
def force(xi, c):
    return xi


@njit(cache=True)
def stiffness(xi, c):
    return 1.0


@njit(cache=True)
def damping(xi, c):
    return 1.0


@njit(cache=True)
def potential(xi, c):
    return 0.5 * xi * xi


@dataclass(frozen=True)
class LinearSpring(SpringLaw):
    """f(xi) = xi, g(xi) = 1: the power law with rho = 1, a = b = 0."""

    name = "linear"
    summary = "the paper's linear spring xi'' = -xi - 2 mu xi' (closed-form flights)"
    solver = "exact"
    physics = Physics(force, stiffness, damping, potential)

    def xi_eq(self, gamma: float) -> float:
        return -gamma

    def energy_min(self, gamma: float) -> float:
        """E_m = -gamma^2/2 (eq. ``Emin``), exactly as the closed form rounds it."""
        return -0.5 * gamma * gamma

    def divergence(self, eta: float, gamma: float) -> float:
        """eta^2/2 (exact: V is quadratic)."""
        return 0.5 * eta * eta

    def deviation_range(self, excess: float, gamma: float) -> tuple[float, float]:
        """-+sqrt(2 (E - E_m)): eta^2/2 <= E - E_m."""
        v = math.sqrt(2.0 * excess)
        return -v, v

    def amplitude(self, energy: float) -> float:
        return math.sqrt(2.0 * energy) if energy > 0.0 else 0.0

    def check_equilibrium(self, gamma: float) -> None:
        if not gamma < XI_EQ_MAX:
            raise InputError(
                f"gamma must be < {XI_EQ_MAX} (supported range: [{GAMMA_MIN:g}, {XI_EQ_MAX})): for gamma >= 1/2 the "
                f"static equilibrium y_eq = 1 - 2 gamma of the upper mass is at or below the floor), got {gamma!r}"
            )

    def symbolic(self, module, xi):
        return xi, 1.0

    def series_coefficients(self) -> tuple[float, float, float]:
        """(rho, a, b) = (1, 0, 0): the law as the series solver's power law (its tests and benchmarks run the linear
        law through the same code)."""
        return 1.0, 0.0, 0.0


LINEAR = LinearSpring()

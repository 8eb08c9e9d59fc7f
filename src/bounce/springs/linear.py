"""The paper's linear damped spring (eq. ``dimensionless-eq-motion``): xi'' = -xi - 2 mu xi'.

The closed-form exact solver (:mod:`bounce.exact.flight`, :mod:`bounce.exact.events`) supports this law
only.  Static equilibrium xi_eq = -gamma (eq. ``equilibrium``), E_m = -gamma^2/2 (eq. ``Emin``).
"""

from __future__ import annotations

from dataclasses import dataclass

from .base import SpringLaw


@dataclass(frozen=True)
class LinearSpring(SpringLaw):
    """f(xi) = xi, g(xi) = 1: the power law with rho = 1, a = b = 0."""

    name = "linear"

    def restoring(self, xi: float) -> float:
        return xi

    def damping_factor(self, xi: float) -> float:
        return 1.0

    def potential(self, xi: float) -> float:
        return 0.5 * xi * xi

    def xi_eq(self, gamma: float) -> float:
        return -gamma

    def energy_min(self, gamma: float) -> float:
        """E_m = -gamma^2/2 (eq. ``Emin``), exactly as the closed form rounds it."""
        return -0.5 * gamma * gamma


LINEAR = LinearSpring()

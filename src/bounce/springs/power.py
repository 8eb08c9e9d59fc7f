"""The paper's nonlinear spring: a power law (eq. ``eq-motion-nonlin-psi-xi``).

    xi'' = -rho xi |xi|^a - 2 mu xi' |xi|^b,     rho > 0,  a, b >= 0,

so f(xi) = rho xi |xi|^a (restoring force), g(xi) = |xi|^b (damping factor),
V(xi) = rho |xi|^(a+2) / (a+2) (the spring part of eq. ``nonlin-energy``), and the
static equilibrium f(xi_eq) = -gamma is xi_eq = -(gamma/rho)^(1/(a+1)) (eq.
``nonlin-equilibrium-xi``).  Linear: (rho, a, b) = (1, 0, 0); Hertz: a = b = 1/2.
Along a flight the spring energy xi'^2/2 + V(xi) decreases at the rate
-2 mu xi'^2 |xi|^b (the paper prints -mu xi'^2 |xi|^b; the factor 2 follows from
multiplying the equation by xi').  The flights are computed by
:mod:`bounce.series.flight`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import InputError
from .base import SpringLaw


def _parameter(name: str, value, lower: float, strict: bool) -> float:
    """value as a float within (lower, inf) (strict) or [lower, inf); InputError naming name otherwise."""
    allowed = f"({lower:g}, inf)" if strict else f"[{lower:g}, inf)"
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise InputError(f"spring {name} must be a finite number in {allowed}, got {value!r}") from None
    ok = math.isfinite(number) and (number > lower if strict else number >= lower)
    if not ok:
        raise InputError(f"spring {name} must be {'>' if strict else '>='} {lower:g} "
                         f"(allowed range: {allowed}), got {value!r}")
    return number


@dataclass(frozen=True)
class PowerSpring(SpringLaw):
    """f(xi) = rho xi |xi|^a, g(xi) = |xi|^b (eq. ``eq-motion-nonlin-psi-xi``)."""

    name = "power"

    rho: float
    a: float
    b: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "rho", _parameter("rho", self.rho, 0.0, strict=True))
        object.__setattr__(self, "a", _parameter("a", self.a, 0.0, strict=False))
        object.__setattr__(self, "b", _parameter("b", self.b, 0.0, strict=False))

    def restoring(self, xi: float) -> float:
        """f(xi) = rho xi |xi|^a."""
        return self.rho * xi * abs(xi) ** self.a

    def damping_factor(self, xi: float) -> float:
        """g(xi) = |xi|^b (1 at xi = 0 when b = 0)."""
        return abs(xi) ** self.b

    def potential(self, xi: float) -> float:
        """V(xi) = rho |xi|^(a+2) / (a+2), V' = f (eq. ``nonlin-energy``)."""
        return self.rho * abs(xi) ** (self.a + 2.0) / (self.a + 2.0)

    def xi_eq(self, gamma: float) -> float:
        """xi_eq = -(gamma/rho)^(1/(a+1)) (eq. ``nonlin-equilibrium-xi``)."""
        return -((gamma / self.rho) ** (1.0 / (self.a + 1.0)))

    def energy_min(self, gamma: float) -> float:
        """E_m = V(xi_eq) + gamma xi_eq = -gamma |xi_eq| (a+1)/(a+2) (rest on the floor, x = 0)."""
        return -gamma * -self.xi_eq(gamma) * (self.a + 1.0) / (self.a + 2.0)


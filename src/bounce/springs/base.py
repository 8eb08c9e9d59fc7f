"""The contract of a spring law (paper, eq. ``eq-motion-nonlin-psi-xi``).

In flight the centre of mass falls freely, psi'' = -gamma, and the spring obeys

    xi'' = -f(xi) - 2 mu xi' g(xi),

with f the restoring force and g the damping factor of the law (linear: f(xi) = xi,
g = 1, eq. ``dimensionless-eq-motion``).  A law module in :mod:`bounce.springs` defines
one frozen dataclass subclassing :class:`SpringLaw`; its contract:

1. ``restoring(xi)`` = f(xi), odd, increasing, f(0) = 0;
2. ``damping_factor(xi)`` = g(xi) >= 0;
3. ``potential(xi)`` = V(xi) with V' = f, V(0) = 0 (the spring part of the energy,
   eq. ``nonlin-energy``), so that E = psi'^2/2 + xi'^2/2 + V(xi) + gamma psi never
   rises in flight (its rate is -2 mu xi'^2 g(xi));
4. ``xi_eq(gamma)``: the static equilibrium f(xi_eq) = -gamma (eq.
   ``nonlin-equilibrium-xi``), the origin of the core's deviation eta = xi - xi_eq;
5. ``attrs()``: the law and its parameters as netCDF global attributes
   (``spring_law`` plus ``spring_<parameter>``), enough to rebuild it with
   :func:`bounce.springs.spring_from_attrs`.

Parameters are validated on construction: a bad value raises
:class:`bounce.model.InputError` naming the parameter and its allowed range.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import ClassVar


@dataclass(frozen=True)
class SpringLaw:
    """Base of the spring laws; subclasses set ``name`` and implement the contract above."""

    name: ClassVar[str] = ""

    def restoring(self, xi: float) -> float:
        raise NotImplementedError

    def damping_factor(self, xi: float) -> float:
        raise NotImplementedError

    def potential(self, xi: float) -> float:
        raise NotImplementedError

    def xi_eq(self, gamma: float) -> float:
        raise NotImplementedError

    def energy_min(self, gamma: float) -> float:
        """E_m = V(xi_eq) + gamma xi_eq: the energy at rest on the floor (x = 0, psi = xi = xi_eq)."""
        xi = self.xi_eq(gamma)
        return self.potential(xi) + gamma * xi

    def parameters(self) -> dict:
        """The law's parameters, name -> value."""
        return {f.name: getattr(self, f.name) for f in fields(self)}

    def attrs(self) -> dict:
        return {"spring_law": self.name, **{f"spring_{k}": v for k, v in self.parameters().items()}}

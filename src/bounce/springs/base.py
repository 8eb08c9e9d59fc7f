"""The contract of a spring law (paper, eq. ``eq-motion-nonlin-psi-xi``): the physics every solver calls.

In flight the centre of mass falls freely, psi'' = -gamma, and the spring obeys

    xi'' = -f(xi) - 2 mu xi' g(xi),

with f the restoring force and g the damping factor of the law (linear: f(xi) = xi,
g = 1, eq. ``dimensionless-eq-motion``).  With x = psi - xi, y = psi + xi + 1 (eq. ``xi-psi``)
the two masses feel x'' = -gamma + S, y'' = -gamma - S, S = f(xi) + 2 mu xi' g(xi).

A law module in :mod:`bounce.springs` defines one frozen dataclass subclassing
:class:`SpringLaw` and one line of :data:`bounce.springs.SPRING_LAWS`; everything else is derived
from it (the CLI's ``--spring`` options, the config schema's ``spring`` fragment, the netCDF
attributes, which methods can run it).  Its contract:

1. ``physics``: a :class:`Physics` of numba functions of (xi, c), c = :attr:`SpringLaw.coefficients`
   (the parameters as a float64 array, in the order of ``PARAMETERS``): the restoring force f,
   odd and increasing with f(0) = 0; its slope f' >= 0; the damping factor g >= 0; the potential V
   with V' = f, V(0) = 0 (the spring part of the energy, eq. ``nonlin-energy``), so that
   E = psi'^2/2 + xi'^2/2 + V(xi) + gamma psi never rises in flight (rate -2 mu xi'^2 g(xi)).
   These are the law's only definition of its physics: the general-purpose methods
   (:mod:`bounce.methods`) pass them to their numba kernels (specialised per law, as fast as the
   law written inline), and the Python-level :meth:`restoring`, :meth:`stiffness`,
   :meth:`damping_factor`, :meth:`potential` run their Python source (``py_func``: the same
   operations in the same order, so the same float64 results, without compiling them).
2. ``PARAMETERS``: one :class:`Parameter` per field, with its allowed interval; a bad value raises
   :class:`bounce.errors.InputError` naming the parameter and the interval on construction.
3. ``solver``: the exact solver that serves the law: ``"exact"`` (the closed forms of
   :mod:`bounce.exact`), ``"series"`` (the Taylor series with rigorous tails of
   :mod:`bounce.series`), or None: no exact solver (then only the general-purpose methods run it).
4. :meth:`check_supported`: the law's supported domain, refused up front with one line naming the
   parameter (the default: the static equilibrium above the floor).
5. :meth:`symbolic`: f and g as expressions of a symbolic module (heyoka), or None when the law has
   no symbolic form (then heyoka cannot run it).
6. :meth:`attrs`: the law and its parameters as netCDF global attributes (``spring_law`` plus
   ``spring_<parameter>``), enough to rebuild it with :func:`bounce.springs.spring_from_attrs`.

The defaults of :meth:`xi_eq` (f(xi_eq) = -gamma, eq. ``nonlin-equilibrium-xi``, by bisection) and
:meth:`amplitude` (V(X) = E, by bisection) need only the physics; a law with closed forms overrides them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from functools import cached_property
from typing import Any, Callable, ClassVar, NamedTuple

import numpy as np

from ..errors import InputError

#: the largest |xi_eq|: the static equilibrium y_eq = 1 + 2 xi_eq of the upper mass above the floor
XI_EQ_MAX = 0.5
#: smallest gamma simulated: a drop of one rest length lasts sqrt(2/gamma) = 1.4e6 time units there.
GAMMA_MIN = 1e-12
#: longest flight (in units sqrt(m/2k)) an exact solver is asked to follow: it resolves every spring
#: oscillation in a flight, so its work grows with the flight's length.
FLIGHT_MAX = 1e8


def flight_bound(gamma: float, excess: float, eta_max: float) -> float:
    """Upper bound on every flight's duration from E - E_m = ``excess`` (energy never increases).

    Not a bound on the first flight only: an impact exchanges psi' and xi', so a state whose first flight is
    short (a fast spring near the floor) can launch the centre of mass with the spring's energy; flights then
    reach ~0.83 of this bound from the second one on (test_cli.py::test_flight_refusal_is_about_every_flight).

    In flight psi'' = -gamma with |psi'| <= V = sqrt(2 (E - E_m)), gamma x0 <= E - E_m and
    |eta| <= ``eta_max`` (the spring's part of E - E_m, :meth:`SpringLaw.divergence`, is at most E - E_m:
    :meth:`SpringLaw.deviation_range`), so
    x = psi - xi = x0 + eta0 - eta + psi'(0) t - gamma t^2/2 > 0 cannot last beyond
    T = (V + sqrt(V^2 + 2 (E - E_m) + 4 gamma eta_max))/gamma (linear law, eta_max = V:
    (V + sqrt(2 V^2 + 4 gamma V))/gamma).
    """
    v = math.sqrt(2.0 * excess)
    return (v + math.sqrt(v * v + 2.0 * excess + 4.0 * gamma * eta_max)) / gamma


class Physics(NamedTuple):
    """The numba functions of a law, each of (xi, c) with c the law's coefficient array."""

    force: Callable  # f(xi)
    stiffness: Callable  # f'(xi)
    damping: Callable  # g(xi)
    potential: Callable  # V(xi), V' = f, V(0) = 0


@dataclass(frozen=True)
class Parameter:
    """A law parameter: its name (the dataclass field, the CLI option ``--NAME``, the config key and the
    netCDF attribute ``spring_NAME``), what it is, and its allowed interval [lower, upper] (an end
    excluded when ``*_open``; upper = inf: unbounded, the value still finite)."""

    name: str
    doc: str
    lower: float
    upper: float = math.inf
    lower_open: bool = False
    upper_open: bool = False

    def interval(self) -> str:
        return (f"{'(' if self.lower_open else '['}{self.lower:g}, "
                f"{self.upper:g}{')' if self.upper_open or math.isinf(self.upper) else ']'}")

    def contains(self, value: float) -> bool:
        above = value > self.lower if self.lower_open else value >= self.lower
        below = value < self.upper if self.upper_open else value <= self.upper
        return math.isfinite(value) and above and below

    def check(self, value: Any) -> float:
        """``value`` as a float in the interval, else InputError naming the parameter and the interval."""
        try:
            number = float(value)
        except (TypeError, ValueError, OverflowError):
            number = math.nan
        if isinstance(value, bool) or not self.contains(number):
            raise InputError(f"spring {self.name} must be a finite number (allowed range: {self.interval()}; {self.doc}), "
                             f"got {value!r}")
        return number

    def schema(self) -> dict:
        """The JSON-schema fragment of the parameter (config/schema.yaml's ``spring`` is built from these)."""
        out: dict = {"type": "number", "description": f"{self.doc}, in {self.interval()}"}
        out["exclusiveMinimum" if self.lower_open else "minimum"] = self.lower
        if math.isfinite(self.upper):
            out["exclusiveMaximum" if self.upper_open else "maximum"] = self.upper
        return out


@dataclass(frozen=True)
class SpringLaw:
    """Base of the spring laws; subclasses set the class attributes and fields of the contract above."""

    name: ClassVar[str] = ""
    #: one line for the CLI's and the schema's help
    summary: ClassVar[str] = ""
    PARAMETERS: ClassVar[tuple[Parameter, ...]] = ()
    #: the exact solver that serves the law: "exact", "series" or None (contract 3)
    solver: ClassVar[str | None] = None
    physics: ClassVar[Physics]

    def __post_init__(self) -> None:
        for p in self.PARAMETERS:
            object.__setattr__(self, p.name, p.check(getattr(self, p.name)))

    # ------------------------------------------------------------------ physics

    @cached_property
    def coefficients(self) -> np.ndarray:
        """The parameters as a float64 array in the order of PARAMETERS (the c of the physics functions)."""
        return np.array([getattr(self, p.name) for p in self.PARAMETERS], dtype=np.float64)

    def restoring(self, xi: float) -> float:
        """f(xi)."""
        return float(self.physics.force.py_func(float(xi), self.coefficients))

    def stiffness(self, xi: float) -> float:
        """f'(xi)."""
        return float(self.physics.stiffness.py_func(float(xi), self.coefficients))

    def damping_factor(self, xi: float) -> float:
        """g(xi)."""
        return float(self.physics.damping.py_func(float(xi), self.coefficients))

    def potential(self, xi: float) -> float:
        """V(xi), V' = f, V(0) = 0 (eq. ``nonlin-energy``)."""
        return float(self.physics.potential.py_func(float(xi), self.coefficients))

    def xi_eq(self, gamma: float) -> float:
        """The static equilibrium f(xi_eq) = -gamma (eq. ``nonlin-equilibrium-xi``): bisection on the increasing f
        to adjacent floats, the one with the smaller residual."""
        lo, hi = -1.0, 0.0
        while self.restoring(lo) > -gamma:
            lo *= 2.0
            if math.isinf(lo):
                raise InputError(f"spring {self.name}: no static equilibrium f(xi) = -gamma for gamma = {gamma!r}")
        while True:
            mid = 0.5 * (lo + hi)
            if mid in (lo, hi):
                break
            if self.restoring(mid) > -gamma:
                hi = mid
            else:
                lo = mid
        return min((lo, hi), key=lambda xi: abs(self.restoring(xi) + gamma))

    def energy_min(self, gamma: float) -> float:
        """E_m = V(xi_eq) + gamma xi_eq: the energy at rest on the floor (x = 0, psi = xi = xi_eq)."""
        xi = self.xi_eq(gamma)
        return self.potential(xi) + gamma * xi

    def divergence(self, eta: float, gamma: float) -> float:
        """V(xi_eq + eta) - V(xi_eq) + gamma eta >= 0: the spring's part of E - E_m at the floor (the Bregman
        divergence of V at xi_eq, V'(xi_eq) = -gamma).  By its definition here (cancellation: absolute error
        ~eps (|V(xi)| + |V(xi_eq)|)); a law with a closed form overrides it."""
        xi_eq = self.xi_eq(gamma)
        return max(self.potential(xi_eq + eta) - self.potential(xi_eq) + gamma * eta, 0.0)

    def deviation_range(self, excess: float, gamma: float) -> tuple[float, float]:
        """(eta_lo, eta_hi): the range of eta with divergence(eta) <= ``excess`` (the divergence is convex with its
        minimum 0 at eta = 0), rounded outwards, by doubling and bisection on each side."""
        ends = []
        for side in (-1.0, 1.0):
            lo, hi = 0.0, 1.0
            while excess > 0.0 and self.divergence(side * hi, gamma) <= excess:
                lo, hi = hi, 2.0 * hi
                if math.isinf(hi):
                    break
            while excess > 0.0 and math.isfinite(hi):
                mid = 0.5 * (lo + hi)
                if mid in (lo, hi):
                    break
                if self.divergence(side * mid, gamma) <= excess:
                    lo = mid
                else:
                    hi = mid
            ends.append(side * hi if excess > 0.0 else 0.0)
        return ends[0], ends[1]

    def excess(self, gamma: float, start) -> float:
        """E - E_m of the state ``start`` (:class:`bounce.model.Deviations`: x, x', xi', eta = xi - xi_eq):
        (xi'^2 + psi'^2)/2 + divergence(eta) + gamma x (eqs. ``tot-mech-energy``, ``nonlin-energy``); inf for a
        state too large for float64."""
        psidot = start.xdot + start.xidot
        # products, not **: a huge state gives inf (refused by the callers) instead of raising OverflowError
        kinetic = 0.5 * (start.xidot * start.xidot + psidot * psidot)
        total = kinetic + self.divergence(start.eta, gamma) + gamma * start.x
        return total if math.isfinite(total) else math.inf

    def amplitude(self, energy: float) -> float:
        """The largest |xi| with V(xi) <= energy (V is even and increasing in |xi|): an upper bound, by bisection."""
        if not energy > 0.0:
            return 0.0
        lo, hi = 0.0, 1.0
        while self.potential(hi) <= energy:
            lo, hi = hi, 2.0 * hi
            if math.isinf(hi):
                return math.inf
        while True:
            mid = 0.5 * (lo + hi)
            if mid in (lo, hi):
                return hi
            if self.potential(mid) <= energy:
                lo = mid
            else:
                hi = mid

    # ------------------------------------------------------------------ domain, symbolic form, records

    def check_equilibrium(self, gamma: float) -> None:
        """The static equilibrium above the floor: |xi_eq| < 1/2, so that y_eq = 1 + 2 xi_eq > 0."""
        xi_eq = self.xi_eq(gamma)
        if not -xi_eq < XI_EQ_MAX:
            raise InputError(
                f"gamma must put the static equilibrium above the floor (supported range: |xi_eq| < {XI_EQ_MAX:g}): "
                f"the {self.name} spring holds gamma = {gamma!r} at xi_eq = {xi_eq:.6g}, the upper mass at "
                f"y_eq = 1 + 2 xi_eq = {1.0 + 2.0 * xi_eq:.6g} <= 0")

    def check_supported(self, gamma: float, mu: float, start, t_max: float = math.inf) -> None:
        """Refuse, naming the parameter, what lies outside the law's supported domain (contract 4), after
        :meth:`check_equilibrium` (:func:`bounce.model.check_supported` calls both, with the model-wide limits
        between them).  ``start``: the initial :class:`bounce.model.Deviations`; ``t_max``: the run's horizon.
        The default: flights of at most FLIGHT_MAX (:meth:`longest_flight`; this also bounds every height, speed
        and time by ~1e16, far from overflow)."""
        excess, _, longest = self.longest_flight(gamma, start)
        if not longest <= FLIGHT_MAX:
            raise InputError(
                f"initial state (x0 xdot0 y0 ydot0, or psi0 psidot0 xi0 xidot0): its energy E - E_m = {excess:.3g} "
                f"allows flights up to {longest:.3g} time units long at gamma = {gamma!r} (supported range: flights "
                f"<= {FLIGHT_MAX:g}): the solver resolves every spring oscillation of a flight, and a short first "
                f"flight does not keep the later ones short (an impact exchanges psi' and xi': the spring's energy "
                f"launches the centre of mass, for flights up to ~0.8 of this bound)")

    def longest_flight(self, gamma: float, start) -> tuple[float, float, float]:
        """(E - E_m, X, T) of ``start``: its energy excess, the largest |xi| and the longest flight it allows (eta
        within :meth:`deviation_range`, :func:`flight_bound`; inf for a state too large for float64, without numpy's
        overflow warnings: the caller refuses it in one line)."""
        with np.errstate(over="ignore", invalid="ignore"):
            excess = self.excess(gamma, start)
            if not math.isfinite(excess):
                return math.inf, math.inf, math.inf
            eta_lo, eta_hi = self.deviation_range(excess, gamma)
        xi_eq = self.xi_eq(gamma)
        reach = max(abs(xi_eq + eta_lo), abs(xi_eq + eta_hi))
        return excess, reach, flight_bound(gamma, excess, max(-eta_lo, eta_hi))

    #: f and g as symbolic expressions: ``symbolic(self, module, xi) -> (f, g)``, g = 1.0 for a constant damping
    #: factor; None: the law has no symbolic form (contract 5)
    symbolic: ClassVar[Callable | None] = None

    def title(self, number: Callable[[float], str] = "{:g}".format) -> str:
        """The law in words for a figure title (mathtext), its parameters formatted by ``number``."""
        params = ", ".join(f"${p.name}={number(getattr(self, p.name))}$" for p in self.PARAMETERS)
        return f"{self.name} spring" + (f" {params}" if params else "")

    def parameters(self) -> dict:
        """The law's parameters, name -> value."""
        return {f.name: getattr(self, f.name) for f in fields(self)}

    def attrs(self) -> dict:
        return {"spring_law": self.name, **{f"spring_{k}": v for k, v in self.parameters().items()}}

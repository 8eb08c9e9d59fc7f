"""The two-mass ball: parameters, states and their validation (paper, section 2).

Dimensionless units: lengths in L (rest length of the spring), times in
sqrt(m / 2k).  gamma = g m / (2 L k) and mu = nu / sqrt(2 k m) (eq.
``dimensionless-eq-motion``).  A state is (x, xdot, y, ydot): heights and
velocities of the lower and upper mass.  The numerical core works in the
deviation variables of :mod:`bounce.exact.flight`:

    u = xdot,  a = xi' = (ydot - xdot)/2,  eta = xi - xi_eq = (y - y_eq - x)/2,

with psi = (y + x - 1)/2, xi = (y - x - 1)/2 (eq. ``xi-psi``) and the static
equilibrium y_eq = 1 + 2 xi_eq: for the linear spring xi_eq = -gamma, so eta = xi + gamma,
y_eq = 1 - 2 gamma and E_m = -gamma^2/2 (eqs. ``equilibrium``, ``Emin``); other spring laws
(:mod:`bounce.springs`, eq. ``nonlin-equilibrium-xi``) have their own xi_eq and E_m.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from .errors import InputError
from .springs import LINEAR, SpringLaw
from .springs.base import GAMMA_MIN, XI_EQ_MAX


def _finite(name: str, value: float) -> float:
    try:
        value = float(value)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"{name} must be a finite number (allowed range: (-inf, inf)), got {value!r}") from None
    if not math.isfinite(value):
        raise InputError(f"{name} must be a finite number (allowed range: (-inf, inf)), got {value!r}")
    return value


def _check_floor(x: float, xdot: float) -> None:
    """The lower mass starts on or above the floor, and not moving into it."""
    if x < 0.0:
        raise InputError(f"x0 must be >= 0 (allowed range: [0, inf); the lower mass cannot start below the floor), "
                         f"got {x!r}")
    if x == 0.0 and xdot < 0.0:
        raise InputError(
            f"xdot0 must be >= 0 when x0 = 0 (allowed range: [0, inf); a state on the floor moving down is below it "
            f"an instant later), got {xdot!r}"
        )


@dataclass(frozen=True)
class Parameters:
    """gamma > 0 (gravity against spring stiffness), mu >= 0 (damping) and the spring law.

    The law (:mod:`bounce.springs`) defaults to the paper's linear spring; the static
    equilibrium and E_m follow from it (eqs. ``equilibrium``, ``Emin``,
    ``nonlin-equilibrium-xi``).
    """

    gamma: float
    mu: float
    spring: SpringLaw = field(default=LINEAR)

    def __post_init__(self) -> None:
        gamma = _finite("gamma", self.gamma)
        mu = _finite("mu", self.mu)
        if not gamma > 0.0:
            raise InputError(f"gamma must be > 0 (allowed range: (0, inf)), got {gamma!r}")
        if not mu >= 0.0:
            raise InputError(f"mu must be >= 0 (allowed range: [0, inf)), got {mu!r}")
        if not isinstance(self.spring, SpringLaw):
            raise InputError(f"spring must be a spring law of bounce.springs, got {self.spring!r}")
        object.__setattr__(self, "gamma", gamma)
        object.__setattr__(self, "mu", mu)

    @property
    def xi_eq(self) -> float:
        """Static spring deformation at rest on the floor: -gamma for the linear law."""
        return self.spring.xi_eq(self.gamma)

    @property
    def y_eq(self) -> float:
        """Equilibrium height of the upper mass, 1 + 2 xi_eq (1 - 2 gamma for the linear law)."""
        return 1.0 + 2.0 * self.xi_eq

    @property
    def energy_min(self) -> float:
        """E_m, the energy of the static equilibrium (-gamma^2/2 for the linear law)."""
        return self.spring.energy_min(self.gamma)


@dataclass(frozen=True)
class State:
    """Heights and velocities (x, xdot, y, ydot) of the lower and upper mass."""

    x: float
    xdot: float
    y: float
    ydot: float

    def __post_init__(self) -> None:
        for name, suffix in (("x", "x0"), ("xdot", "xdot0"), ("y", "y0"), ("ydot", "ydot0")):
            object.__setattr__(self, name, _finite(suffix, getattr(self, name)))
        _check_floor(self.x, self.xdot)

    @classmethod
    def from_psi_xi(cls, psi: float, psidot: float, xi: float, xidot: float) -> "State":
        """State from the centre-of-mass and spring variables of eq. ``xi-psi``."""
        return cls(x=psi - xi, xdot=psidot - xidot, y=psi + xi + 1.0, ydot=psidot + xidot)

    @classmethod
    def sticky_ic(cls, params: Parameters, eps: float, ydot0: float = -0.1) -> "Deviations":
        """Initial condition eq. ``sticky-ic``: X0 = 0, Xdot0 = eps, Y0 = 1 + 2 gamma - 2 mu Ydot0.

        Returned in the deviation variables, eta = (Y0 - 1)/2 + gamma = 2 gamma - mu Ydot0,
        xi' = (Ydot0 - eps)/2: for eps = 0 the floor force F = eta + 2 mu xi' - 2 gamma is then
        zero to rounding of O(gamma), not of O(1) as it would be through Y0 ~ 1.
        """
        if params.spring.name != "linear":
            raise InputError(f"initial sticky (eq. sticky-ic) is defined for the linear spring only, got {params.spring.name!r}")
        State(0.0, eps, 1.0, ydot0)  # the usual checks and messages
        return Deviations(
            x=0.0, xdot=eps, xidot=0.5 * (float(ydot0) - float(eps)),
            eta=2.0 * params.gamma - params.mu * float(ydot0),
        )

    def deviations(self, params: Parameters) -> "Deviations":
        """The same state in the deviation variables of the numerical core."""
        return Deviations(
            x=self.x, xdot=self.xdot, xidot=0.5 * (self.ydot - self.xdot),
            eta=0.5 * ((self.y - self.x) - 1.0) - params.xi_eq,  # xi - xi_eq, one rounding
        )

    def energy(self, params: Parameters) -> float:
        """Total mechanical energy, eq. ``tot-mech-energy`` (eq. ``nonlin-energy`` for other laws)."""
        psi = 0.5 * (self.y + self.x - 1.0)
        xi = 0.5 * (self.y - self.x - 1.0)
        psidot = 0.5 * (self.ydot + self.xdot)
        xidot = 0.5 * (self.ydot - self.xdot)
        return 0.5 * (xidot**2 + psidot**2) + params.spring.potential(xi) + params.gamma * psi


@dataclass(frozen=True)
class Deviations:
    """A state as the core carries it: x, xdot, xi' and eta = xi - xi_eq (xi + gamma, linear spring).

    Use it to start a simulation from a state deep in the asymptotic regime
    without the rounding of y ~ 1 (y - y_eq = x + 2 eta may be ~1e-12).
    """

    x: float
    xdot: float
    xidot: float
    eta: float

    def __post_init__(self) -> None:
        for name in ("x", "xdot", "xidot", "eta"):
            object.__setattr__(self, name, _finite(name + "0", getattr(self, name)))
        _check_floor(self.x, self.xdot)  # same floor checks as a State

    def deviations(self, params: Parameters) -> "Deviations":
        return self

    def to_state(self, params: Parameters) -> State:
        """Heights and velocities (x, xdot, y, ydot); y is rounded to float64."""
        return State(
            x=self.x, xdot=self.xdot, y=params.y_eq + self.x + 2.0 * self.eta,
            ydot=self.xdot + 2.0 * self.xidot,
        )


# --------------------------------------------------------------------------- supported domain of the simulator

#: gamma < 1/2: the static equilibrium y_eq = 1 - 2 gamma of the upper mass lies above the floor (linear law).
GAMMA_MAX = XI_EQ_MAX
#: largest damping simulated (the stiff oscillator's rates 1/(2 mu) and 2 mu stay 1e16 apart at most).
MU_MAX = 1e8


def check_physical(state: State) -> None:
    """The upper mass above the lower one: y0 > x0 (so y0 > 0), a spring of positive length.

    The linear model itself (and :class:`State`) is defined for every spring length, and
    tests of the paper's remarks use such states; the command line refuses them.
    """
    if not state.y > state.x:
        raise InputError(
            f"y0 must be > x0 = {state.x!r} (allowed range: (x0, inf)): the upper mass sits above the lower "
            f"one, the spring's length y - x = 1 + 2 xi must be positive, got {state.y!r}"
        )


def check_supported(params: Parameters, start: "Deviations", t_max: float = math.inf) -> None:
    """Refuse, with the supported range and why, what the exact solvers cannot follow to rounding.

    The same check for the API (:func:`bounce.simulate`, every spring law) and the CLI, so both refuse with the
    same message.  Every accepted input gives finite results: the static equilibrium above the floor (linear
    law: gamma < GAMMA_MAX = 1/2), gamma >= GAMMA_MIN, mu in [0, MU_MAX], and the law's own domain
    (:meth:`bounce.springs.base.SpringLaw.check_supported`: an initial energy whose longest possible flight is
    at most FLIGHT_MAX, which also bounds every height, speed and time by ~1e16, far from overflow; the power
    law's own bounds, with the run's ``t_max``, in :mod:`bounce.springs.power`).
    """
    gamma, mu = params.gamma, params.mu
    params.spring.check_equilibrium(gamma)
    if not gamma >= GAMMA_MIN:
        raise InputError(
            f"gamma must be >= {GAMMA_MIN:g} (supported range: [{GAMMA_MIN:g}, {GAMMA_MAX})): below it a drop of "
            f"one rest length lasts sqrt(2/gamma) > 1.4e6 time units, over 2e5 spring periods, each of which the "
            f"root finder resolves), got {gamma!r}"
        )
    if not mu <= MU_MAX:
        raise InputError(
            f"mu must be <= {MU_MAX:g} (supported range: [0, {MU_MAX:g}]: the range in which the spring's "
            f"closed forms, whose two rates 1/(2 mu) and 2 mu are then 4e16 apart, are verified against the "
            f"high-precision reference), got {mu!r}"
        )
    params.spring.check_supported(gamma, mu, start, t_max)

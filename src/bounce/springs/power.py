"""The paper's nonlinear spring: a power law (eq. ``eq-motion-nonlin-psi-xi``).

    xi'' = -rho xi |xi|^a - 2 mu xi' |xi|^b,     rho > 0,  a, b >= 0,

so f(xi) = rho xi |xi|^a (restoring force), g(xi) = |xi|^b (damping factor),
V(xi) = rho |xi|^(a+2) / (a+2) (the spring part of eq. ``nonlin-energy``), and the
static equilibrium f(xi_eq) = -gamma is xi_eq = -(gamma/rho)^(1/(a+1)) (eq.
``nonlin-equilibrium-xi``).  Linear: (rho, a, b) = (1, 0, 0); Hertz: a = b = 1/2.
Along a flight the spring energy xi'^2/2 + V(xi) decreases at the rate
-2 mu xi'^2 |xi|^b (the paper prints -mu xi'^2 |xi|^b; the factor 2 follows from
multiplying the equation by xi').  Served by the Taylor-series solver (:mod:`bounce.series`).

Supported domain (refused up front by :meth:`PowerSpring.check_supported`, through
:func:`bounce.model.check_supported`, with one line naming the parameter; the API's
:func:`bounce.simulate` and the CLI run the same check, with the run's t_max).  Inside it a run
progresses: every flight and sticky phase ends (an event, or a stop reason such as ``slow_crossing``
or ``sticky_forever``), or the run reaches t_max, within a bounded amount of work (~10 s of one core).

1. Each parameter alone: rho in (0, inf), a in [0, A_MAX], b in [0, B_MAX].  A_MAX = B_MAX = 50: the
   series' majorant carries the factors (1 + d)^(a+1) and (1 + d)^b (:mod:`bounce.series.taylor`,
   d <= 0.95), finite and at most 1.95^51 ~ 6e14; a = 50 is checked against the mpmath reference
   (tests/series/test_series_reference.py), b = 50 in tests/model/test_power_domain.py.
2. The static equilibrium above the floor: |xi_eq| = (gamma/rho)^(1/(a+1)) < 1/2, i.e.
   rho > gamma 2^(a+1) (the linear law's gamma < 1/2), so that y_eq = 1 + 2 xi_eq > 0.
3. The model-wide limits of :func:`bounce.model.check_supported`: gamma >= GAMMA_MIN, mu <= MU_MAX.
4. Sticky phases that end: near equilibrium the sticky spring (eq. (ST) of :mod:`bounce.series.sticky`)
   is d'' + m d' + k d = 0 with m = mu g(xi_eq), k = f'(xi_eq)/2 = (a+1) gamma / (2 |xi_eq|); over-damped,
   its slow mode decays at ~k/m while the series steps resolve the fast one, ~m, so a phase takes
   ~m^2/k steps per e-fold of its energy (its end: a detach, or the proof that it never comes, which
   waits for the energy to fall).  Refused: Z = m^2/k > OVERDAMPING_MAX, naming mu (its largest value
   is then sqrt(OVERDAMPING_MAX k)/g(xi_eq)).  Measured (Hertz, gamma = 0.01, starts at rest on the
   floor): Z = 7.2e2 (mu = 100) proves ``sticky_forever`` in 0.3 s, Z = 7.2e4 (mu = 1000) ran into the
   phase's 4e5-step cap (series.sticky.MAX_STEPS: a RuntimeError); OVERDAMPING_MAX = 1e3.
5. Phases of bounded work: the series steps are limited by the stiffness and the damping of the spring
   over the |xi| it can reach, X (the largest |xi_eq + eta| whose divergence fits in E - E_m,
   :meth:`bounce.springs.base.SpringLaw.longest_flight`), so a phase of length T costs ~T R with the rate
   R = sqrt(f'(X')) + 2 mu g(X'), X' = (1 + d) X (the factor of the series solver's Cauchy disc,
   :func:`disc_fraction`).  Refused: min(T, t_max) R > WORK_MAX, with T the longest
   flight the energy allows (:func:`bounce.springs.base.flight_bound`; the energy never rises, so this
   holds for every later phase), naming mu (when its damping term makes the difference), else the initial
   state.  Measured on random laws and states (2 cores, load ~2): CPU <= 4e-5 s per unit of T R where the
   stiffness dominates (non-dyadic a or b: the crossings of xi = 0 in geometric steps), ~3e-6 s where the
   damping does; the issue-25 stalls had T R ~ 1e6 .. 1e10.  WORK_MAX = 2.5e5: a phase within ~10 s.
   A run that only needs its first events of a long-flying state passes its t_max (as the sweep
   hertz-restitution does).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from numba import njit

from ..errors import InputError
from .base import XI_EQ_MAX, Parameter, Physics, SpringLaw

#: largest exponents of the restoring force and the damping (domain 1)
A_MAX = B_MAX = 50.0
#: largest Cauchy disc radius of the series solver as a fraction of |xi0| (the singularity xi = 0 is at distance
#: |xi0|): the step near xi = 0 is ~ theta d |xi0| / |xi'| and the majorant grows as (1 + d)^(a+1) with the law's
#: fraction d = min(DISC, 2/a) (:func:`disc_fraction`).
DISC = 0.95
#: largest m^2/k of the sticky spring near equilibrium (domain 4)
OVERDAMPING_MAX = 1e3
#: largest min(T, t_max) R, the work of a phase (domain 5)
WORK_MAX = 2.5e5


@njit(cache=True)
def force(xi, c):
    """f(xi) = rho xi |xi|^a, c = (rho, a, b)."""
    return c[0] * xi * abs(xi) ** c[1]


@njit(cache=True)
def stiffness(xi, c):
    """f'(xi) = rho (a+1) |xi|^a."""
    return c[0] * (c[1] + 1.0) * abs(xi) ** c[1]


@njit(cache=True)
def damping(xi, c):
    """g(xi) = |xi|^b (1 at xi = 0 when b = 0)."""
    return abs(xi) ** c[2]


@njit(cache=True)
def potential(xi, c):
    """V(xi) = rho |xi|^(a+2) / (a+2), V' = f (eq. ``nonlin-energy``)."""
    return c[0] * abs(xi) ** (c[1] + 2.0) / (c[1] + 2.0)


def disc_fraction(a: float) -> float:
    """d = min(DISC, 2/a): the Cauchy disc |z - xi0| <= d |xi0| of the series solver's majorant
    (:mod:`bounce.series.taylor`), kept with the law because its supported domain (domain 5) counts the
    solver's steps with it.

    Any 0 < d < 1 keeps the disc off xi = 0.  Where the restoring force limits the radius,
    r_c^2 ~ d / ((1 + d)^(a+1) |xi0|^a r) is largest at d = 1/a, and the fixed DISC would shrink the steps
    by ~(1.95 / (1 + 1/a))^((a+1)/2) / sqrt(0.95 a) (a = 24: ~500, a = 50: ~2e6: a drop of the a = 50 law
    did not reach its second impact in 14 min); where the speed limits it, r_c ~ d |xi0| / |xi'| wants d large.  2/a
    was the fastest of 1/a, 2/a, 4/a and DISC over a = 1.5 .. 24 (2e4 impacts of the drops from
    xi = xi_eq and xi = 0, b = 0.5, gamma = mu = 0.01: against DISC within 10% for a = 2.5, 3, 1.2x faster
    at a = 5, 1.6x at a = 8, 3.7x at a = 12, 160-200x at a = 24; ``python benchmarks/bench_power_core.py
    --disc``).  The damping's factor
    (1 + d)^b is left to DISC: with b large the damping is weak near equilibrium and a smaller d only
    shortened the steps (b = 12: 4x slower at d = 2/b).  Laws with a <= 2/DISC (Hertz, the linear law)
    keep DISC.
    """
    return min(DISC, 2.0 / a if a > 0.0 else math.inf)


def _power(x: float, p: float) -> float:
    """x^p, inf where it overflows (Python's ** raises there)."""
    try:
        return x ** p
    except OverflowError:
        return math.inf


@dataclass(frozen=True)
class PowerSpring(SpringLaw):
    """f(xi) = rho xi |xi|^a, g(xi) = |xi|^b (eq. ``eq-motion-nonlin-psi-xi``)."""

    name = "power"
    summary = "the Discussion's power law xi'' = -rho xi |xi|^a - 2 mu xi' |xi|^b (Hertz: a = b = 0.5; Taylor-series flights)"
    solver = "series"
    PARAMETERS = (
        Parameter("rho", "stiffness of the power law", 0.0, lower_open=True),
        Parameter("a", "exponent of the restoring force rho xi |xi|^a (Hertz: 0.5)", 0.0, A_MAX),
        Parameter("b", "exponent of the damping 2 mu xi' |xi|^b (Hertz: 0.5)", 0.0, B_MAX),
    )
    physics = Physics(force, stiffness, damping, potential)

    rho: float
    a: float
    b: float

    def xi_eq(self, gamma: float) -> float:
        """xi_eq = -(gamma/rho)^(1/(a+1)) (eq. ``nonlin-equilibrium-xi``)."""
        return -((gamma / self.rho) ** (1.0 / (self.a + 1.0)))

    def energy_min(self, gamma: float) -> float:
        """E_m = V(xi_eq) + gamma xi_eq = -gamma |xi_eq| (a+1)/(a+2) (rest on the floor, x = 0)."""
        return -gamma * -self.xi_eq(gamma) * (self.a + 1.0) / (self.a + 2.0)

    def amplitude(self, energy: float) -> float:
        """((a+2) E / rho)^(1/(a+2)): V(X) = E."""
        return ((self.a + 2.0) * energy / self.rho) ** (1.0 / (self.a + 2.0)) if energy > 0.0 else 0.0

    def check_equilibrium(self, gamma: float) -> None:
        """Domain 2: |xi_eq| < 1/2, named as the least stiffness rho > gamma 2^(a+1)."""
        w = -self.xi_eq(gamma)
        if not w < XI_EQ_MAX:
            least = gamma * 2.0 ** (self.a + 1.0)
            raise InputError(
                f"spring rho must be > gamma 2^(a+1) = {least:.6g} at gamma = {gamma!r}, a = {self.a!r} (supported "
                f"range: ({least:.6g}, inf)): the static equilibrium xi_eq = -(gamma/rho)^(1/(a+1)) = {-w:.6g} puts "
                f"the upper mass at y_eq = 1 + 2 xi_eq = {1.0 - 2.0 * w:.3g} <= 0, at or below the floor, got {self.rho!r}")

    def check_supported(self, gamma: float, mu: float, start, t_max: float = math.inf) -> None:
        """The supported domain of the module docstring, 4 and 5 (1: on construction; 2: check_equilibrium; 3: the
        model, bounce.model.check_supported, which calls this last)."""
        w = -self.xi_eq(gamma)
        k = 0.5 * (self.a + 1.0) * gamma / w  # f'(xi_eq)/2
        g_eq = w ** self.b
        if not (mu * g_eq) ** 2 <= OVERDAMPING_MAX * k:
            largest = math.sqrt(OVERDAMPING_MAX * k) / g_eq
            raise InputError(
                f"mu must be <= {largest:.3g} for this spring at gamma = {gamma!r} (supported range: [0, {largest:.3g}]): "
                f"beyond it the sticky spring near equilibrium is over-damped, (mu g(xi_eq))^2/(f'(xi_eq)/2) > "
                f"{OVERDAMPING_MAX:g}, and its series steps would follow the fast mode over the slow one's whole decay, "
                f"got {mu!r}")
        _, reach, longest = self.longest_flight(gamma, start)
        span = min(longest, t_max)
        stiff, damp = self.rates(mu, reach)
        if not span * (stiff + damp) <= WORK_MAX:
            what = f"mu = {mu!r}" if span * stiff <= WORK_MAX else "initial state (or t_max)"
            raise InputError(
                f"{what}: phases up to {span:.3g} time units long with |xi| up to X = {reach:.3g} take time x R = "
                f"{span * (stiff + damp):.3g}, R = sqrt(f'(X')) + 2 mu g(X') = {stiff + damp:.3g} the series' rate "
                f"(supported range: time x R <= {WORK_MAX:g}, a phase within ~10 s)")

    def rates(self, mu: float, reach: float) -> tuple[float, float]:
        """(sqrt(f'(X')), 2 mu g(X')), X' = (1 + d) ``reach``: the stiffness and damping rates of domain 5."""
        x = (1.0 + disc_fraction(self.a)) * reach
        return math.sqrt(self.rho * (self.a + 1.0)) * _power(x, 0.5 * self.a), 2.0 * mu * _power(x, self.b)

    def symbolic(self, module, xi):
        """f and g with |xi|^p written (xi^2)^(p/2) and dropped when p = 0 (the linear law is then linear)."""
        def abs_pow(p):
            return None if p == 0.0 else (xi * xi) ** (p / 2.0)

        fa, fb = abs_pow(self.a), abs_pow(self.b)
        return (self.rho * xi if fa is None else self.rho * xi * fa), (1.0 if fb is None else fb)

    def series_coefficients(self) -> tuple[float, float, float]:
        """(rho, a, b) of the series solver's law array (:func:`bounce.series.taylor.law_array`)."""
        return self.rho, self.a, self.b

    def title(self, number=None) -> str:
        number = number or "{:g}".format
        name = "Hertz spring" if self.a == self.b == 0.5 else "power-law spring"
        return name + r" $\rho=%s$, $a=%s$, $b=%s$" % (number(self.rho), number(self.a), number(self.b))


__all__ = ["A_MAX", "B_MAX", "DISC", "OVERDAMPING_MAX", "WORK_MAX", "PowerSpring", "disc_fraction"]

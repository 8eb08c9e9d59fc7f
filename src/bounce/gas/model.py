"""Parameters and states of a gas of grains, with their validation (one line naming the parameter).

Dimensionless units of the paper (section 2): lengths in the spring's rest length L, times in
sqrt(m/2k).  Two geometries: ``column``, grains stacked on the floor under gravity (gamma > 0), and
``ring``, a periodic line of circumference ``ell`` without gravity (gamma = 0).

* :class:`GasParameters` and :class:`GasState`: n dimers (the paper's balls), each given by its
  centre of mass and spring, arrays (psi, psi', xi, xi') (eq. ``xi-psi``: x = psi - xi,
  y = psi + xi + 1); the engine carries x, x', xi', eta = xi + gamma (:mod:`bounce.gas.dimer`).
* :class:`RigidParameters` and :class:`RigidState`: n rigid grains of length ``size`` (0: points)
  with a constant restitution r, optionally the TC model (:mod:`bounce.gas.rigid`).

Bad input raises :class:`bounce.errors.InputError` with one line naming the parameter and its
allowed range.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..model import GAMMA_MAX, GAMMA_MIN, MU_MAX

GEOMETRIES = ("column", "ring")
#: most grains a run takes (the state arrays are allocated up front)
N_MAX = 10**8


def _grains(value) -> int:
    try:
        number = float(value)
    except (TypeError, ValueError, OverflowError):
        number = math.nan
    if isinstance(value, bool) or not (number.is_integer() and 1 <= number <= N_MAX):
        raise InputError(f"n must be an integer in [1, {N_MAX:.0e}] (allowed range), got {value!r}")
    return int(number)


def _number(name: str, value, allowed: str) -> float:
    try:
        value = float(value)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"{name} must be a finite number (allowed range: {allowed}), got {value!r}") from None
    if not math.isfinite(value):
        raise InputError(f"{name} must be a finite number (allowed range: {allowed}), got {value!r}")
    return value


def _geometry(n: int, geometry, gamma, ell) -> tuple[str, float, float]:
    """The geometry's checks, shared by both models: (geometry, gamma, ell)."""
    if geometry not in GEOMETRIES:
        raise InputError(f"geometry must be one of {', '.join(GEOMETRIES)} (allowed values), got {geometry!r}")
    if geometry == "column":
        gamma = _number("gamma", gamma, f"[{GAMMA_MIN:g}, {GAMMA_MAX}) for the column")
        if not GAMMA_MIN <= gamma < GAMMA_MAX:
            raise InputError(f"gamma must be in [{GAMMA_MIN:g}, {GAMMA_MAX}) for the column (allowed range: gravity "
                             f"brings the grains back to the floor; the single ball's supported range), got {gamma!r}")
        if ell is not None:
            raise InputError(f"ell is the ring's circumference; the column has none (allowed: None), got {ell!r}")
        return geometry, gamma, 0.0
    gamma = _number("gamma", gamma, "[0, 0] on the ring")
    if gamma != 0.0:
        raise InputError(f"gamma must be 0 on the ring (allowed range: [0, 0]; a periodic line has no floor to fall "
                         f"on), got {gamma!r}")
    if n < 2:
        raise InputError(f"n must be >= 2 on the ring (allowed range: [2, {N_MAX:.0e}]; a lone grain would meet "
                         f"itself across the seam), got {n}")
    if ell is None:
        raise InputError("ell (the ring's circumference) is required on the ring (allowed range: (0, inf))")
    ell = _number("ell", ell, "(0, inf)")
    if not ell > 0.0:
        raise InputError(f"ell must be > 0 (allowed range: (0, inf)), got {ell!r}")
    return geometry, gamma, ell


@dataclass(frozen=True)
class GasParameters:
    """n dimers, the geometry, gamma (> 0 column, 0 ring), mu >= 0 and the ring's circumference ell."""

    n: int
    geometry: str
    gamma: float
    mu: float
    ell: float | None = None

    def __post_init__(self) -> None:
        n = _grains(self.n)
        geometry, gamma, ell = _geometry(n, self.geometry, self.gamma, self.ell)
        mu = _number("mu", self.mu, f"[0, {MU_MAX:g}]")
        if not 0.0 <= mu <= MU_MAX:
            raise InputError(f"mu must be in [0, {MU_MAX:g}] (allowed range), got {mu!r}")
        object.__setattr__(self, "n", n)
        object.__setattr__(self, "gamma", gamma)
        object.__setattr__(self, "mu", mu)
        object.__setattr__(self, "ell", ell if geometry == "ring" else None)

    @property
    def wrap(self) -> float:
        """The seam's shift: ell on the ring, 0 in the column."""
        return self.ell if self.geometry == "ring" else 0.0


@dataclass(frozen=True)
class RigidParameters:
    """n rigid grains of length ``size`` (0: points), restitution r in [0, 1], the TC model's t_c >= 0
    (0: off; a collision is elastic if either grain collided less than t_c before), the geometry."""

    n: int
    geometry: str
    gamma: float
    r: float
    ell: float | None = None
    size: float = 1.0
    t_c: float = 0.0

    def __post_init__(self) -> None:
        n = _grains(self.n)
        geometry, gamma, ell = _geometry(n, self.geometry, self.gamma, self.ell)
        r = _number("r", self.r, "[0, 1]")
        if not 0.0 <= r <= 1.0:
            raise InputError(f"r must be in [0, 1] (allowed range), got {r!r}")
        size = _number("size", self.size, "[0, inf)")
        if not size >= 0.0:
            raise InputError(f"size must be >= 0 (allowed range: [0, inf)), got {size!r}")
        t_c = _number("t_c", self.t_c, "[0, inf)")
        if not t_c >= 0.0:
            raise InputError(f"t_c must be >= 0 (allowed range: [0, inf); 0 turns the TC model off), got {t_c!r}")
        for name, value in (("n", n), ("gamma", gamma), ("r", r), ("size", size), ("t_c", t_c),
                            ("ell", ell if geometry == "ring" else None)):
            object.__setattr__(self, name, value)

    @property
    def wrap(self) -> float:
        return self.ell if self.geometry == "ring" else 0.0


def _arrays(names: tuple[str, ...], values: tuple, n: int | None = None) -> list[np.ndarray]:
    """The state arrays as float64, one-dimensional, of one length (n if given), finite."""
    out = []
    for name, value in zip(names, values):
        try:
            arr = np.array(value, dtype=np.float64).reshape(-1) if np.ndim(value) <= 1 else None
        except (TypeError, ValueError):
            arr = None
        if arr is None:
            raise InputError(f"{name} must be a one-dimensional array of numbers (one per grain), got {value!r:.80}")
        if not np.all(np.isfinite(arr)):
            k = int(np.flatnonzero(~np.isfinite(arr))[0])
            raise InputError(f"{name}[{k}] must be a finite number (allowed range: (-inf, inf)), got {arr[k]!r}")
        out.append(arr)
    lengths = {arr.size for arr in out} | ({n} if n is not None else set())
    if len(lengths) != 1:
        raise InputError(f"{', '.join(names)} must all have one entry per grain (allowed: length n"
                         f"{f' = {n}' if n is not None else ''}), got lengths {[arr.size for arr in out]}")
    return out


def _check_order(x: np.ndarray, top: np.ndarray, geometry: str, wrap: float, names: str) -> None:
    """x_0 >= 0 (column), top_k <= x_{k+1} (no overlap), and on the ring x_0 + ell >= top_{n-1}."""
    if geometry == "column" and not x[0] >= 0.0:
        raise InputError(f"{names}: grain 0 starts below the floor, x_0 = {x[0]!r} (allowed range: x_0 >= 0)")
    gaps = x[1:] - top[:-1]
    if gaps.size and not np.all(gaps >= 0.0):
        k = int(np.flatnonzero(~(gaps >= 0.0))[0])
        raise InputError(f"{names}: grains {k} and {k + 1} overlap, gap x_{k + 1} - y_{k} = {gaps[k]!r} (allowed "
                         f"range: [0, inf); grains are numbered upwards, without passing)")
    if geometry == "ring" and not x[0] + wrap - top[-1] >= 0.0:
        raise InputError(f"ell must be >= y_{x.size - 1} - x_0 = {top[-1] - x[0]!r} for these grains (allowed "
                         f"range: [{top[-1] - x[0]!r}, inf); the last grain overlaps the first across the seam), "
                         f"got {wrap!r}")


@dataclass(frozen=True, eq=False)
class GasState:
    """Per-grain centre of mass psi = (x + y - 1)/2, its velocity, spring xi = (y - x - 1)/2 and its rate."""

    psi: np.ndarray
    psidot: np.ndarray
    xi: np.ndarray
    xidot: np.ndarray

    def __post_init__(self) -> None:
        arrays = _arrays(("psi", "psidot", "xi", "xidot"), (self.psi, self.psidot, self.xi, self.xidot))
        for name, arr in zip(("psi", "psidot", "xi", "xidot"), arrays):
            arr.flags.writeable = False
            object.__setattr__(self, name, arr)

    @classmethod
    def from_heights(cls, x, xdot, y, ydot) -> "GasState":
        """From the masses' heights and velocities (eq. ``xi-psi``)."""
        x, xdot, y, ydot = _arrays(("x", "xdot", "y", "ydot"), (x, xdot, y, ydot))
        return cls(0.5 * (y + x - 1.0), 0.5 * (ydot + xdot), 0.5 * (y - x - 1.0), 0.5 * (ydot - xdot))

    @property
    def n(self) -> int:
        return self.psi.size

    def deviations(self, gamma: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(x, x', xi', eta = xi + gamma) per grain, as the engine carries them."""
        return self.psi - self.xi, self.psidot - self.xidot, self.xidot.copy(), self.xi + gamma

    def check(self, params: GasParameters) -> None:
        """The state fits the parameters: n grains, springs of positive length within the energy bound,
        the floor, order without overlap, the ring's seam."""
        if self.n != params.n:
            raise InputError(f"psi, psidot, xi, xidot must have one entry per grain (allowed: length n = {params.n}), "
                             f"got {self.n}")
        amp2 = self.xi**2 + self.xidot**2
        if not np.all(amp2 < 0.25):
            k = int(np.flatnonzero(~(amp2 < 0.25))[0])
            raise InputError(f"xi, xidot: grain {k} has xi^2 + xi'^2 = {amp2[k]:.6g} (allowed range: [0, 0.25); "
                             f"beyond it the grain's two masses may pass, y - x = 1 + 2 xi <= 0)")
        x, u, _, _ = self.deviations(params.gamma)
        if params.geometry == "column" and x[0] == 0.0 and u[0] < 0.0:
            raise InputError(f"psidot - xidot of grain 0 must be >= 0 when it starts on the floor (allowed range: "
                             f"[0, inf)), got {u[0]!r}")
        _check_order(x, self.psi + self.xi + 1.0, params.geometry, params.wrap, "psi, xi")


@dataclass(frozen=True, eq=False)
class RigidState:
    """Per-grain position x (the grain's lower end) and velocity."""

    x: np.ndarray
    xdot: np.ndarray

    def __post_init__(self) -> None:
        arrays = _arrays(("x", "xdot"), (self.x, self.xdot))
        for name, arr in zip(("x", "xdot"), arrays):
            arr.flags.writeable = False
            object.__setattr__(self, name, arr)

    @property
    def n(self) -> int:
        return self.x.size

    def check(self, params: RigidParameters) -> None:
        if self.n != params.n:
            raise InputError(f"x, xdot must have one entry per grain (allowed: length n = {params.n}), got {self.n}")
        if params.geometry == "column" and self.x[0] == 0.0 and self.xdot[0] < 0.0:
            raise InputError(f"xdot[0] must be >= 0 when grain 0 starts on the floor (allowed range: [0, inf)), "
                             f"got {self.xdot[0]!r}")
        _check_order(self.x, self.x + params.size, params.geometry, params.wrap, "x")


def random_state(params: GasParameters | RigidParameters, speed: float, gap: float, seed: int,
                 prefix: str = "") -> GasState | RigidState:
    """A generated start (the command line's and the gas scenes'): velocities normal with standard deviation
    ``speed`` (``numpy.random.default_rng(seed)``); springs at rest.  On the ring the grains sit at uniformly random
    places (free lengths Dirichlet-distributed over ell - n times the grains' length) with zero total momentum; in the
    column, ``gap`` above the floor and between the grains.  ``prefix`` names the options in messages ("--" for the
    command line)."""
    for name, value, ok, allowed in (("speed", speed, speed >= 0.0, "[0, inf)"), ("gap", gap, gap > 0.0, "(0, inf)"),
                                     ("seed", seed, seed >= 0, "[0, inf), an integer")):
        if not (ok and math.isfinite(value)):
            raise InputError(f"{prefix}{name} must be in {allowed} (allowed range), got {value!r}")
    rigid = isinstance(params, RigidParameters)
    n = params.n
    rng = np.random.default_rng(seed)
    v = rng.normal(0.0, speed, n)
    length = params.size if rigid else 1.0
    if params.geometry == "ring":
        free = params.ell - n * length
        if not free > 0.0:
            raise InputError(f"{prefix}ell must be > n times the grains' length = {n * length!r} to place them "
                             f"(allowed range: ({n * length!r}, inf)), got {params.ell!r}")
        v -= v.mean()
        gaps = rng.dirichlet(np.ones(n)) * free
        x = np.concatenate([[0.0], np.cumsum(gaps[:-1] + length)])
    else:
        x = gap + np.arange(n) * (length + gap)
    if rigid:
        return RigidState(x, v)
    zero = np.zeros(n)
    return GasState(x, v, zero, zero)

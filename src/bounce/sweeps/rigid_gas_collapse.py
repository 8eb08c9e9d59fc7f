"""Sweep ``rigid-gas-collapse``: how many rigid grains a one-dimensional gas needs to collapse, against r.

Beyond the paper (its introduction: rigid models of granular matter collapse; McNamara and Young, Phys. Fluids A 4,
496 (1992): a gas of inelastic points with constant restitution r needs more than N_c(r) grains to collapse,
N_c ~ ln(1/(1-r))/(1-r) as r -> 1, "roughly 88 if r = 0.95" in their cooling runs between inelastic boundaries).

Setting (ours; the engine has rings and columns, not walls): n point grains (:mod:`bounce.gas.rigid`, size 0) on a
ring of circumference n (unit density), positions uniform and sorted, velocities standard normal minus their mean
(the centre-of-mass frame), one state per item drawn from ``numpy.random.default_rng([seed, item])`` so that an item
does not depend on the sharding.  Each run goes on until one of:

* ``collapse``: the engine's collapse stop (an unresolved run of collisions or one approaching at the rounding of its
  grains' speeds, :mod:`bounce.gas.rigid`);
* ``cooled``: the kinetic energy in the centre-of-mass frame has fallen to ``cooling`` times its start (checked every
  ``check_every`` collisions per grain).  The default 1e-16 (speeds 1e-8 of the start) keeps the relative speeds 1e8
  above the rounding of the drift the rounded zero momentum leaves, where a cooling gas stops being resolved
  (``cooled_below_rounding``), so a collapse stop before it is a collapse;
* ``cap``: ``max_collisions`` collisions per grain (a run that neither collapsed nor cooled: counted apart, never as
  either).

A run's outcome is an approximation in one way: a gas that would collapse only after cooling by more than
``cooling`` counts as not collapsing.  ``finish`` turns the outcomes into P(n; r), the fraction of the ``samples``
states that collapsed, and N_c(r), the n at which P crosses 1/2 (linear in log n between the two grid points that
bracket it), with its standard error: the bootstrap over the samples (``bootstrap`` resamples, seeded) and the grid's
resolution (the bracketing cell's width in log n over sqrt(12)) in quadrature; N_c is NaN (not determined) when P
does not cross 1/2 on the grid or a run reached the cap.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from ..analysis.gas_rings import CAP, COLLAPSE, ring_points, run_rigid_ring
from .base import ITEM, Sweep, rn_grid, rn_prepare, rn_size

NAME = "rigid-gas-collapse"


def compute(spec: dict, inputs: dict) -> dict:
    seed, cooling = int(spec["seed"]), float(spec["cooling"])
    every, cap = int(spec["check_every"]), int(spec["max_collisions"])
    m = len(inputs["r"])
    out = {"outcome": np.zeros(m, dtype=np.int8), "collisions": np.zeros(m), "t_end": np.zeros(m)}
    for c in range(m):
        x, v = ring_points(int(inputs["n"][c]), np.random.default_rng([seed, int(inputs["item"][c])]))
        out["outcome"][c], out["collisions"][c], out["t_end"][c] = run_rigid_ring(
            float(inputs["r"][c]), x, v, cooling, every, cap)
    return out


VARIABLES = {
    "outcome": ((ITEM,), "how the run ended: 0 collapse, 1 cooled by the factor cooling, 2 collision cap", "1", None),
    "collisions": ((ITEM,), "collisions per grain when the run ended", "1", None),
    "t_end": ((ITEM,), "time of the last collision", "1", None),
}


def threshold(p: np.ndarray, ns: np.ndarray) -> float:
    """The n at which the collapse fraction p (over the grid ns) first reaches 1/2, linear in log n between the two
    grid points that bracket it; NaN when p does not cross 1/2 from below on the grid."""
    above = np.nonzero(p >= 0.5)[0]
    if above.size == 0 or above[0] == 0:
        return math.nan
    j = int(above[0])
    lo, hi = math.log(ns[j - 1]), math.log(ns[j])
    return math.exp(lo + (0.5 - p[j - 1]) / (p[j] - p[j - 1]) * (hi - lo))


def _bracket_width(p: np.ndarray, ns: np.ndarray) -> float:
    """Width in log n of the grid cell in which p first reaches 1/2 (NaN if it does not cross)."""
    above = np.nonzero(p >= 0.5)[0]
    if above.size == 0 or above[0] == 0:
        return math.nan
    return math.log(ns[above[0]] / ns[above[0] - 1])


def finish(ds: xr.Dataset, spec: dict) -> xr.Dataset:
    """Outcomes on the (r, n, sample) grid, P(n; r), N_c(r) with its bootstrap error, the McNamara-Young scale."""
    r, ns, samples = rn_grid(spec)
    outcome = ds["outcome"].values.reshape(r.size, ns.size, samples)
    collapsed = (outcome == COLLAPSE).astype(float)
    p = collapsed.mean(axis=2)
    capped = (outcome == CAP).any(axis=(1, 2))
    n_c = np.array([math.nan if capped[i] else threshold(p[i], ns) for i in range(r.size)])
    rng = np.random.default_rng(int(spec["seed"]))
    boot = np.full((r.size, int(spec["bootstrap"])), math.nan)
    for b in range(boot.shape[1]):
        pick = rng.integers(0, samples, samples)
        for i in range(r.size):
            boot[i, b] = math.nan if capped[i] else threshold(collapsed[i][:, pick].mean(axis=1), ns)
    determined = np.isfinite(boot).mean(axis=1) >= 0.9
    # the error of log N_c: the bootstrap's spread and the grid's resolution (the bracketing cell's width in log n,
    # as a uniform spread: width / sqrt(12)), in quadrature
    cell = np.array([_bracket_width(p[i], ns) for i in range(r.size)])
    with np.errstate(invalid="ignore"):
        spread = np.sqrt(np.nanvar(np.log(boot), axis=1) + cell**2 / 12.0)
    err = np.where(determined & np.isfinite(n_c), spread * n_c, math.nan)
    out = xr.Dataset(attrs=dict(ds.attrs))
    dims = ("r", "n", "sample")
    out["outcome"] = xr.Variable(dims, outcome, ds["outcome"].attrs)
    out["collisions"] = xr.Variable(dims, ds["collisions"].values.reshape(outcome.shape), ds["collisions"].attrs)
    out["t_end"] = xr.Variable(dims, ds["t_end"].values.reshape(outcome.shape), ds["t_end"].attrs)
    out["p_collapse"] = xr.Variable(("r", "n"), p, {"long_name": "fraction of the samples that collapsed",
                                                    "units": "1"})
    out["n_c"] = xr.Variable(("r",), np.where(determined, n_c, math.nan),
                             {"long_name": "N_c: grains at which half the samples collapse (NaN: not determined)",
                              "units": "1"})
    out["n_c_err"] = xr.Variable(("r",), err, {"long_name": "standard error of N_c (bootstrap over the states and the "
                                                           "grid's resolution, in quadrature)", "units": "1"})
    out["my_scale"] = xr.Variable(("r",), np.log(1.0 / (1.0 - r)) / (1.0 - r),
                                  {"long_name": "McNamara-Young scale ln(1/(1-r))/(1-r)", "units": "1"})
    out = out.assign_coords(
        r=xr.Variable(("r",), r, {"long_name": "restitution coefficient r", "units": "1"}),
        n=xr.Variable(("n",), ns, {"long_name": "number of grains on the ring (circumference n)", "units": "1"}),
        sample=xr.Variable(("sample",), np.arange(samples), {"long_name": "initial state", "units": "1"}))
    out.attrs.update(geometry="ring", samples=samples, seed=int(spec["seed"]), cooling=float(spec["cooling"]),
                     max_collisions=int(spec["max_collisions"]), bootstrap=int(spec["bootstrap"]))
    return out


def plot(ds: xr.Dataset, spec: dict, outputs) -> None:
    """(a) P(collapse) against n, one curve per r; (b) N_c(r) against the McNamara-Young scale."""
    import matplotlib.pyplot as plt

    from ..figures.common import WIDTH, save

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(WIDTH, 2.9), constrained_layout=True)
    for i, r in enumerate(ds["r"].values):
        a1.semilogx(ds["n"].values, ds["p_collapse"].values[i], "o-", ms=3, label=f"r = {r:g}")
    a1.axhline(0.5, color="0.6", lw=0.6, ls="--")
    # headroom above the fractions (<= 1) for the legend, off the curves
    a1.set(xlabel="grains n on the ring", ylabel="fraction of states that collapse", ylim=(-0.05, 1.5),
           yticks=np.linspace(0.0, 1.0, 6))
    a1.set_title(f"(a) collapse against n ({int(ds.attrs['samples'])} random states each)", fontsize=8)
    a1.legend(fontsize=6, loc="upper center", ncols=3, columnspacing=0.8, handlelength=1.5)
    scale, n_c, err = ds["my_scale"].values, ds["n_c"].values, ds["n_c_err"].values
    ok = np.isfinite(n_c)
    a2.errorbar(scale[ok], n_c[ok], yerr=err[ok], fmt="o", ms=3, capsize=2, label=r"$N_c(r)$, this ring")
    for s, n, r in zip(scale[ok], n_c[ok], ds["r"].values[ok]):
        a2.annotate(f"r={r:g}", (s, n), textcoords="offset points", xytext=(4, -8), fontsize=6)
    a2.plot(np.log(20.0) / 0.05, 88.0, "s", mfc="none", color="C3", label="McNamara-Young, r = 0.95: ~88 (walls)")
    a2.set(xscale="log", yscale="log", xlabel=r"$\ln(1/(1-r))/(1-r)$", ylabel=r"$N_c$ (grains)")
    a2.set_title("(b) the collapse number against the McNamara-Young scale", fontsize=8)
    a2.legend(fontsize=6)
    fig.suptitle("rigid points on a ring with constant restitution r: inelastic collapse needs n > N_c(r)", fontsize=8)
    save(fig, outputs)


def estimated_memory_mb(spec: dict) -> int:
    """Grain arrays of at most max(n) grains: the interpreter and numba dominate."""
    return 300


SWEEP = Sweep(NAME, "Rigid gas on a ring: the number of grains N_c(r) above which it collapses (beyond the paper)",
              rn_size, rn_prepare, compute, VARIABLES, finish, plot, estimated_memory_mb)

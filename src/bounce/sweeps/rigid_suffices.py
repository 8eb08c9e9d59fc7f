"""Sweep ``rigid-suffices``: up to when does the rigid gas reproduce the dimer gas, over (r, n)? (beyond the paper)

The gas analogue of the least-model question for the single ball (:mod:`bounce.studies.reduced`): the rigid model
(points, constant restitution r) is the cheaper model; the dimer gas (the paper's balls, exact to rounding) is the
reference.  For every item, one random state of n points on a ring (:func:`bounce.analysis.gas_rings.ring_points`,
rms speed ``speed``, centre-of-mass frame) runs as both:

* rigid points with restitution r on a ring of circumference n, to the horizon ``horizon`` mean free times
  1/omega0 (omega0 the state's initial collision rate per grain, :func:`~bounce.analysis.gas_rings.collision_rate`)
  or its collapse;
* dimers with exp(-mu T_xi) = r (:func:`~bounce.analysis.gas_rings.mu_of_restitution`), springs at rest, on a ring
  of 2n (:func:`~bounce.analysis.gas_rings.dimer_state`).

Why this is a fair twin: a dimer is a rod of rest length 1, so on a ring of 2n it has the points' free length per
grain, and the two gases make their first collision at the same time between the same grains; an isolated dimer
collision (two micro-impacts T_xi = pi/sqrt(1 - mu^2) apart, eq. ``char-times``) sends the centres of mass apart with
exactly the rigid restitution r.  What the rigid model leaves out is what the comparison measures: a dimer collision
lasts T_xi (not an instant), and leaves the springs vibrating.

What is compared, and the parting times (the rigid gas's clock; inf: no parting before the rigid run's end):

* the collision sequence: each gas's collisions as (time, pair), a dimer collision being the micro-impacts of one
  pair that follow each other within 2 T_xi (:func:`~bounce.analysis.gas_rings.merge_contacts`); grain by grain, the
  ordered list of partners (left or right neighbour).  ``t_seq`` is the first rigid collision whose place in a
  grain's list the dimer gas fills with the other partner or not at all
  (:func:`~bounce.analysis.gas_rings.parting`).  Grain by grain, not as one global list: two collisions far apart
  that swap order because a dimer collision took T_xi change nothing physical, and no list is compared past the rigid
  run's end (the dimers are run to twice it, so a lag of contact times is no false parting);
* beside it ``t_unresolved``: the rigid gas's first collision within T_xi of the previous collision of one of its
  grains, a collision that a contact lasting T_xi cannot resolve as binary (the expected cause of the parting);
* the translational granular temperature T = mean (v - <v>)^2 (v the point's or the centre-of-mass velocity psi', as
  in :mod:`bounce.sweeps.ring_cooling`) on ``time.points`` log-spaced times in [``time.min``, ``horizon``] mean free
  times, exact to rounding (:func:`~bounce.analysis.gas_rings.states_at`).  ``t_temp`` is the first grid time from
  which on |T_dimer/T_rigid - 1| > ``temperature_rtol`` at every later grid time (or the rigid gas has collapsed):
  the temperatures part for good, not at a passing dip (a dimer in contact holds part of its kinetic energy in its
  spring for T_xi, so the dimers' T dips by about the fraction of grains in contact, ~omega T_xi).  Resolution:
  one grid step (``t_temp`` is the grid time at or after the parting).

Recorded per item: both parting times in mean free times and as a fraction of the rigid collapse time (NaN where the
rigid gas did not collapse), the rigid collisions per grain before each, the temperatures (over T0) of both gases at
``t_seq``, the temperatures on the grid, the rigid run's stop.  Units: the paper's dimensionless ones (lengths in L,
times in sqrt(m/2k)); T a squared speed in those units.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from ..analysis.gas_rings import (
    collision_rate, contacts, dimer_state, merge_contacts, mu_of_restitution, partner_sides, parting, ring_points,
    states_at,
)
from ..analysis.theory import T_xi
from ..gas.common import STOP_NAMES
from ..gas.model import GasParameters, RigidParameters, RigidState
from ..gas.simulate import GasRun
from .base import ITEM, Sweep, rn_grid, rn_prepare, rn_size

NAME = "rigid-suffices"
TIME = "time"
#: micro-impacts of one pair less than MERGE T_xi apart are one dimer collision (an isolated one: two, T_xi apart)
MERGE = 2.0
#: the dimers run to DIMER_HORIZON x the rigid run's end (a lag of contact times is no false parting)
DIMER_HORIZON = 2.0


def free_times(spec: dict) -> np.ndarray:
    """The temperatures' log-spaced grid, in mean free times 1/omega0."""
    return np.geomspace(float(spec["time"]["min"]), float(spec["horizon"]), int(spec["time"]["points"]))


def first_unresolved(t: np.ndarray, slot: np.ndarray, n: int, window: float) -> float:
    """The first collision (time, slot) within ``window`` of the previous collision of one of its grains; inf if none."""
    _, times, _ = partner_sides(t, slot, n)
    with np.errstate(invalid="ignore"):  # inf - inf past a grain's count: no pair
        close = np.diff(times, axis=1) < window
    return float(np.where(close, times[:, 1:], np.inf).min(initial=np.inf))


def temperature_parting(ratio: np.ndarray, grid: np.ndarray, rtol: float) -> float:
    """The first grid time from which on |ratio - 1| > rtol (NaN: the rigid gas gave no temperature) at every later
    time; inf if the last one is within rtol."""
    within = np.abs(ratio - 1.0) <= rtol  # False for NaN
    if within[-1]:
        return math.inf
    last = np.nonzero(within)[0]
    return float(grid[last[-1] + 1] if last.size else grid[0])


def _rigid(n: int, r: float, x: np.ndarray, v: np.ndarray, t_max: float) -> GasRun:
    return GasRun(RigidParameters(n, "ring", 0.0, r, ell=float(n), size=0.0), RigidState(x, v), t_max, 0)


def _dimer(n: int, mu: float, x: np.ndarray, v: np.ndarray, t_max: float) -> GasRun:
    return GasRun(GasParameters(n, "ring", 0.0, mu, ell=2.0 * n), dimer_state(x, v), t_max, 0)


def _temperature(state: dict, dimer: bool) -> np.ndarray:
    v = state["xdot"] + state["xidot"] if dimer else state["xdot"]  # the dimers' psi' = x' + xi'
    return np.mean((v - v.mean(axis=1, keepdims=True)) ** 2, axis=1)


def one(spec: dict, r: float, x: np.ndarray, v: np.ndarray) -> dict:
    """The parting times and temperatures of one state (module docstring)."""
    n = x.size
    mu = mu_of_restitution(r)
    contact = T_xi(mu)
    omega0 = collision_rate(v, float(n))
    t_max = float(spec["horizon"]) / omega0
    cap = int(spec["max_collisions"]) * n
    rigid = _rigid(n, r, x, v, t_max)
    rigid_t, rigid_slot = contacts(rigid, cap)
    t_end = min(rigid.t_end, t_max)
    collapse = rigid.t_end if rigid.stop == "collapse" else math.nan
    dimer = merge_contacts(*contacts(_dimer(n, mu, x, v, DIMER_HORIZON * t_end), 2 * cap), MERGE * contact)
    t_seq, _ = parting((rigid_t, rigid_slot), dimer, n)
    grid = free_times(spec) / omega0
    at = np.sort(np.append(grid, t_seq if math.isfinite(t_seq) else t_max))
    row = np.searchsorted(at, grid)
    seq_row = int(np.searchsorted(at, t_seq)) if math.isfinite(t_seq) else -1
    T0 = float(np.mean(v * v))
    T = {}
    for name, run in (("rigid", _rigid(n, r, x, v, t_max)), ("dimer", _dimer(n, mu, x, v, t_end))):
        state, _ = states_at(run, at, n)
        T[name] = _temperature(state, name == "dimer") / T0
    t_temp = temperature_parting(T["dimer"][row] / T["rigid"][row], free_times(spec), float(spec["temperature_rtol"]))
    t_unres = first_unresolved(rigid_t, rigid_slot, n, contact)

    def before(t: float) -> float:
        return float(np.searchsorted(rigid_t, t)) / n

    nan = math.nan
    return {"omega0": omega0, "rigid_stop": STOP_NAMES.index(rigid.stop), "rigid_t_end": t_end * omega0,
            "rigid_collisions": rigid_t.size / n, "collapse_time": collapse * omega0,
            "t_seq": t_seq * omega0, "t_seq_collapse": t_seq / collapse, "collisions_seq": before(t_seq),
            "t_unresolved": t_unres * omega0, "t_temp": t_temp, "t_temp_collapse": t_temp / omega0 / collapse,
            "collisions_temp": before(t_temp / omega0),
            "T_rigid_seq": T["rigid"][seq_row] if seq_row >= 0 else nan,
            "T_dimer_seq": T["dimer"][seq_row] if seq_row >= 0 else nan,
            "T_rigid": T["rigid"][row], "T_dimer": T["dimer"][row]}


def compute(spec: dict, inputs: dict) -> dict:
    seed, speed = int(spec["seed"]), float(spec["speed"])
    m = len(inputs["r"])
    points = int(spec["time"]["points"])
    out = {name: np.zeros((m, points)) if dims[1:] else np.zeros(m) for name, (dims, *_) in VARIABLES.items()}
    out["rigid_stop"] = np.zeros(m, dtype=np.int8)
    for c in range(m):
        n = int(inputs["n"][c])
        x, v = ring_points(n, np.random.default_rng([seed, int(inputs["item"][c])]), speed)
        for name, value in one(spec, float(inputs["r"][c]), x, v).items():
            out[name][c] = value
    return out


_FREE = "mean free times 1/omega0"
_STOPS = ", ".join(f"{i} {name}" for i, name in enumerate(STOP_NAMES))
VARIABLES = {
    "omega0": ((ITEM,), "initial collision rate per grain omega0 (its inverse: the mean free time)", "1", None),
    "rigid_stop": ((ITEM,), f"rigid gas: why its run ended ({_STOPS})", "1", None),
    "rigid_t_end": ((ITEM,), f"rigid gas: end of its run (collapse or horizon), in {_FREE}", "1", None),
    "rigid_collisions": ((ITEM,), "rigid gas: collisions per grain in its run", "1", None),
    "collapse_time": ((ITEM,), f"rigid gas: its collapse time in {_FREE} (NaN: no collapse)", "1", None),
    "t_seq": ((ITEM,), f"collision sequences part (first rigid collision the dimers do not make), in {_FREE} "
                       "(inf: none before the rigid run's end)", "1", None),
    "t_seq_collapse": ((ITEM,), "collision sequences part, over the rigid collapse time (NaN: no collapse)", "1", None),
    "collisions_seq": ((ITEM,), "rigid collisions per grain before the collision sequences part", "1", None),
    "t_unresolved": ((ITEM,), f"rigid gas: first collision within T_xi of the previous one of a grain, in {_FREE} "
                              "(inf: none)", "1", None),
    "t_temp": ((ITEM,), f"temperatures part for good (|T_dimer/T_rigid - 1| > temperature_rtol from then on), in "
                        f"{_FREE} (inf: not within the horizon)", "1", "the grid time at or after the parting"),
    "t_temp_collapse": ((ITEM,), "temperatures part, over the rigid collapse time (NaN: no collapse)", "1", None),
    "collisions_temp": ((ITEM,), "rigid collisions per grain before the temperatures part", "1", None),
    "T_rigid_seq": ((ITEM,), "rigid gas: T/T0 when the collision sequences part", "1", None),
    "T_dimer_seq": ((ITEM,), "dimer gas: T/T0 when the collision sequences part", "1", None),
    "T_rigid": ((ITEM, TIME), "rigid gas: T/T0, T = mean (v - <v>)^2 (NaN after its collapse)", "1", None),
    "T_dimer": ((ITEM, TIME), "dimer gas: T/T0, T = mean (psi' - <psi'>)^2 of the centres of mass (NaN after the "
                              "rigid run's end: nothing to compare)", "1", None),
}


def finish(ds: xr.Dataset, spec: dict) -> xr.Dataset:
    """The items on the (r, n, sample) grid, with mu(r), T_xi, the time grid and the settings."""
    r, ns, samples = rn_grid(spec)
    out = xr.Dataset(attrs=dict(ds.attrs))
    for name, var in ds.data_vars.items():
        out[name] = xr.Variable(("r", "n", "sample") + var.dims[1:],
                                var.values.reshape((r.size, ns.size, samples) + var.shape[1:]), var.attrs)
    mu = np.array([mu_of_restitution(float(x)) for x in r])
    out["mu"] = xr.Variable(("r",), mu, {"long_name": "dimer damping mu with exp(-mu T_xi) = r", "units": "1"})
    out["T_xi"] = xr.Variable(("r",), np.array([T_xi(m) for m in mu]),
                              {"long_name": "dimer contact time T_xi = pi/sqrt(1 - mu^2)", "units": "1"})
    out = out.assign_coords(
        r=xr.Variable(("r",), r, {"long_name": "restitution coefficient r", "units": "1"}),
        n=xr.Variable(("n",), ns, {"long_name": "number of grains", "units": "1"}),
        sample=xr.Variable(("sample",), np.arange(samples), {"long_name": "initial state", "units": "1"}),
        time=xr.Variable((TIME,), free_times(spec), {"long_name": f"time in {_FREE}", "units": "1"}))
    out.attrs.update(samples=samples, seed=int(spec["seed"]), speed=float(spec["speed"]),
                     horizon=float(spec["horizon"]), temperature_rtol=float(spec["temperature_rtol"]),
                     merge=MERGE, dimer_horizon=DIMER_HORIZON)
    return out


def cell_medians(ds: xr.Dataset, name: str) -> np.ndarray:
    """Per (r, n): the median over the states of ``name`` (inf counts as above every finite value)."""
    return np.median(ds[name].values, axis=-1)


def plot(ds: xr.Dataset, spec: dict, outputs) -> None:
    """The map over (n, r): median parting times of the collision sequences and of the temperatures, in mean free
    times (cells annotated; '>H': no parting within the horizon H); and each state's t_seq against t_unresolved."""
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm

    from ..figures.common import WIDTH, save

    r, ns, horizon = ds["r"].values, ds["n"].values, float(ds.attrs["horizon"])
    fig, axes = plt.subplots(1, 3, figsize=(WIDTH * 1.3, 3.3), constrained_layout=True)
    maps = [("t_seq", "(a) collision sequences part"),
            ("t_temp", f"(b) temperatures part (by > {100 * ds.attrs['temperature_rtol']:g} %)")]
    norm = LogNorm(float(ds["time"].values[0]), horizon)
    collapsed = np.mean(ds["rigid_stop"].values == STOP_NAMES.index("collapse"), axis=-1) >= 0.5
    for ax, (name, title) in zip(axes, maps):
        med = cell_medians(ds, name)
        shown = np.where(np.isfinite(med), med, horizon)
        mesh = ax.pcolormesh(np.arange(ns.size + 1), np.arange(r.size + 1), shown, norm=norm, cmap="viridis_r")
        for i in range(r.size):
            for j in range(ns.size):
                m = med[i, j]
                text = (f">{horizon:g}" if not np.isfinite(m) else f"{m:.0f}" if m >= 10 else f"{m:.2g}")
                dark = norm(shown[i, j]) > 0.55
                ax.text(j + 0.5, i + 0.5, text + ("\ncollapse" if collapsed[i, j] else ""), ha="center",
                        va="center", fontsize=6.5, color="w" if dark else "k")
        ax.set_xticks(np.arange(ns.size) + 0.5, [str(n) for n in ns])
        ax.set_yticks(np.arange(r.size) + 0.5, [f"{x:g}" for x in r])
        ax.set(xlabel="number of grains n", ylabel="restitution r")
        ax.set_title(title, fontsize=8)
        ax.grid(False)
    fig.colorbar(mesh, ax=axes[:2], location="bottom", shrink=0.6, aspect=40,
                 label=r"median parting time over the states, in mean free times $1/\omega_0$")
    ax = axes[2]
    for i, x in enumerate(r):
        seq, unres = ds["t_seq"].values[i].ravel(), ds["t_unresolved"].values[i].ravel()
        ok = np.isfinite(seq) & np.isfinite(unres)
        ax.loglog(unres[ok], seq[ok], "o", ms=3, mfc="none", label=f"r = {x:g}")
    lo, hi = ax.get_xlim()
    ax.plot([lo, hi], [lo, hi], "k-", lw=0.6, label="equal")
    ax.set(xlabel=r"first two collisions of a grain closer than $T_\xi$ ($1/\omega_0$)",
           ylabel=r"collision sequences part ($1/\omega_0$)")
    ax.set_title("(c) each state: what parts the sequences", fontsize=8)
    ax.legend(fontsize=6)
    fig.suptitle(f"Where the rigid gas (restitution r) reproduces the dimer gas (exp(-mu T_xi) = r) on a ring: "
                 f"{int(ds.attrs['samples'])} states per cell, rms speed {ds.attrs['speed']:g}, horizon "
                 f"{horizon:g} mean free times; 'collapse': the rigid gas collapses in most states", fontsize=7)
    save(fig, outputs)


def estimated_memory_mb(spec: dict) -> int:
    """The contacts of both runs (16 bytes each, the dimers' ~2 per collision, to twice the rigid end) and the per-grain
    tables, at the cap of collisions per grain and the most grains, plus the interpreter."""
    return 300 + int(80 * int(spec["max_collisions"]) * max(spec["n"]) / 2**20)


SWEEP = Sweep(NAME, "Where the rigid gas suffices: parting of its collision sequence and temperature from the dimer "
              "gas's over (r, n) (beyond the paper)", rn_size, rn_prepare, compute, VARIABLES, finish, plot,
              estimated_memory_mb)

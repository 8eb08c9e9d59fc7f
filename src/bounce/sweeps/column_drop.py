"""Sweep ``column-drop``: n dimers dropped onto the floor come to rest without collapse; their rigid twin collapses.

Beyond the paper (issue 24, experiment 5): the single ball's result (no inelastic collapse, Theorem ``main_thm``; the
energy decays to its minimum, Theorem ``static-equilibrium``) carried to a column of n balls.  Each item is one state
of a column at rest above the floor under gravity gamma: grain k's lower mass at
x_k = ``height`` + k + (g_1 + ... + g_k), the gaps g_i uniform in [0, ``gap``) drawn from
``numpy.random.default_rng([seed, item])`` (an item does not depend on the sharding), springs at rest (xi = xi' = 0).
It runs twice:

* as dimers (:mod:`bounce.gas.dimer`, every contact to rounding) whose single-impact restitution exp(-mu T_xi) is r
  (:func:`~bounce.analysis.gas_rings.mu_of_restitution`), until the energy above the column's minimum,
  E - E_min (:func:`rest_energy`), is at most ``rest`` times its start, or ``max_events`` events, or an engine stop
  (overlap, sticky contact).  The time to rest is the time of the first event after which that holds (energy is
  conserved at the contacts and decays between them, so the crossing lies in the flight before it); the impacts are
  the floor and pair impacts up to that event (grazings not counted).  Every event's snapshot is read (in chunks
  of :data:`CHUNK` events), so the time and count are exact, not those of a checkpoint;
* as rigid rods of length 1 (the dimers' rest length, the same positions) with constant restitution r
  (:mod:`bounce.gas.rigid`), until the engine's collapse stop (the float64 clock stops advancing over a run of
  collisions, or an approach at the rounding of its grains' speeds), ``max_events`` collisions, or the end of all
  contacts.  Its collapse time is the time of its last resolved collision; its collisions are those resolved before
  the stop (a count set by float64, the true one is infinite).  For n = 1 the collapse time is the bouncing ball's
  (v_0/gamma)(1 + r)/(1 - r), v_0 = sqrt(2 gamma ``height``) (check ``gas-column``).

``gamma`` must keep the bottom grain's spring short of the engine's overlap bound at rest: the column's minimum has
xi_0 = -gamma (2 n - 1) (:func:`rest_energy`), and |xi| < 1/2 needs n < (1 + 1/(2 gamma))/2 (25 grains at 0.01);
beyond it, or with too much energy dropped, a run ends in the overlap stop and the check says so.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from ..analysis.gas_rings import mu_of_restitution
from ..gas.common import FLOOR, PAIR, STOP_NAMES
from ..gas.model import GasParameters, GasState, RigidParameters, RigidState
from ..gas.simulate import GasRun, energy_excess
from .base import ITEM, Sweep, rn_grid, rn_prepare, rn_size

NAME = "column-drop"
#: events per chunk of a dimer run (every event's snapshot is kept for the chunk: 32 n bytes each)
CHUNK = 1 << 14


def drop_heights(n: int, height: float, gap: float, rng: np.random.Generator) -> np.ndarray:
    """The lower masses' heights x_k = height + k + (g_1 + ... + g_k), gaps g uniform in [0, gap) drawn by ``rng``."""
    gaps = rng.uniform(0.0, gap, n)
    gaps[0] = 0.0
    return height + np.arange(n) + np.cumsum(gaps)


def rest_energy(n: int, gamma: float) -> float:
    """E - E_m summed over the grains (:func:`bounce.gas.simulate.energy_excess`) at the column's static equilibrium,
    its least value: every contact closed (x_0 = 0, x_{k+1} = y_k), no motion, and grain k's spring compressed by the
    weight above its upper mass, xi_k = -gamma (2 (n - k) - 1) (the stationary point of sum xi_k^2/2 + gamma psi_k on
    the closed contacts; the energy is convex and the contact forces positive, so it is the minimum)."""
    k = np.arange(n)
    xi = -gamma * (2.0 * (n - k) - 1.0)
    x = k + 2.0 * np.concatenate([[0.0], np.cumsum(xi)[:-1]])
    zero = np.zeros(n)
    p = GasParameters(n, "column", gamma, 0.0)
    return float(energy_excess(p, {"xdot": zero, "xidot": zero, "eta": xi + gamma, "x": x}).sum())


def run_dimers(n: int, gamma: float, mu: float, x: np.ndarray, rest: float, max_events: int) -> dict:
    """The dimer column from lower masses at x (springs at rest, at rest), to ``rest`` of its energy above the minimum
    (module docstring): stop code, whether it got there, time, impacts and events to it, the least interval between
    successive events (0: within half an ulp of t) and the energy fraction reached."""
    p = GasParameters(n, "column", gamma, mu)
    zero = np.zeros(n)
    state = GasState(x, zero, zero, zero)
    e_min = rest_energy(n, gamma)
    x0, u, a, eta = state.deviations(gamma)
    e_start = float(energy_excess(p, {"x": x0, "xdot": u, "xidot": a, "eta": eta}).sum()) - e_min
    run = GasRun(p, state, math.inf, 1)
    impacts, last, interval, fraction = 0, np.zeros(0), math.inf, 1.0
    while run.events < max_events and not run.finished:
        rec, k, snaps = run.step(min(CHUNK, max_events - run.events))
        e = energy_excess(p, {f: rec.snap[i, :snaps] for i, f in enumerate(run.fields)}).sum(axis=1) - e_min
        hit = np.flatnonzero(e <= rest * e_start)
        end = hit[0] + 1 if hit.size else k
        kinds = rec.kind[:end]
        impacts += int(np.count_nonzero((kinds == FLOOR) | (kinds == PAIR)))
        times = np.concatenate([last, rec.t[:end]])
        if times.size > 1:
            interval = min(interval, float(np.diff(times).min()))
        if end:
            fraction, last = float(e[end - 1] / e_start), rec.t[end - 1:end].copy()
        if hit.size:
            return {"dimer_stop": STOP_NAMES.index(run.stop), "dimer_rested": 1, "dimer_t_rest": float(last[0]),
                    "dimer_impacts": impacts, "dimer_events": run.events - k + end, "dimer_min_interval": interval,
                    "dimer_energy": fraction}
    return {"dimer_stop": STOP_NAMES.index(run.stop), "dimer_rested": 0, "dimer_t_rest": math.nan,
            "dimer_impacts": impacts, "dimer_events": run.events, "dimer_min_interval": interval,
            "dimer_energy": fraction}


def run_rigid(n: int, gamma: float, r: float, x: np.ndarray, max_events: int) -> dict:
    """The rigid twin (rods of length 1 at x, at rest) to its collapse stop, ``max_events`` or the end of contacts."""
    run = GasRun(RigidParameters(n, "column", gamma, r, size=1.0), RigidState(x, np.zeros(n)), math.inf, 0)
    while run.events < max_events and not run.finished:
        run.step(min(CHUNK, max_events - run.events))
    c = run.collapse() or {"grains": (-1, -1)}
    return {"rigid_stop": STOP_NAMES.index(run.stop), "rigid_t_end": run.t_end, "rigid_collisions": run.events,
            "rigid_low": c["grains"][0], "rigid_high": c["grains"][1]}


def compute(spec: dict, inputs: dict) -> dict:
    seed, gamma, height, gap = int(spec["seed"]), float(spec["gamma"]), float(spec["height"]), float(spec["gap"])
    rest, cap = float(spec["rest"]), int(spec["max_events"])
    m = len(inputs["r"])
    out = {name: np.zeros(m, dtype=VARIABLES[name][4]) for name in VARIABLES}
    for c in range(m):
        r, n = float(inputs["r"][c]), int(inputs["n"][c])
        x = drop_heights(n, height, gap, np.random.default_rng([seed, int(inputs["item"][c])]))
        for name, value in {**run_dimers(n, gamma, mu_of_restitution(r), x, rest, cap),
                            **run_rigid(n, gamma, r, x, cap)}.items():
            out[name][c] = value
    return out


_CODES = ", ".join(f"{i} {name}" for i, name in enumerate(STOP_NAMES))
#: name -> (dims, long_name, units, comment, dtype)
VARIABLES = {
    "dimer_stop": ((ITEM,), "dimer column: the engine's state when the run ended (0 max_events: no engine stop)",
                   "1", f"codes: {_CODES}", np.int8),
    "dimer_rested": ((ITEM,), "dimer column: 1 if its energy above the minimum fell to the fraction rest", "1", None,
                     np.int8),
    "dimer_t_rest": ((ITEM,), "dimer column: time to rest (first event with E - E_min <= rest (E - E_min at t = 0))",
                     "1", "dimensionless, in sqrt(m/2k); NaN if not reached", np.float64),
    "dimer_impacts": ((ITEM,), "dimer column: floor and pair impacts up to rest", "1", None, np.int64),
    "dimer_events": ((ITEM,), "dimer column: events up to rest (grazings included)", "1", None, np.int64),
    "dimer_min_interval": ((ITEM,), "dimer column: smallest interval between successive events up to rest", "1",
                           "0: two events within half an ulp of t (different contacts)", np.float64),
    "dimer_energy": ((ITEM,), "dimer column: (E - E_min)/(E - E_min at t = 0) at its last event", "1", None,
                     np.float64),
    "rigid_stop": ((ITEM,), "rigid twin: why its run ended (5 collapse: the engine's collapse stop)", "1",
                   f"codes: {_CODES}", np.int8),
    "rigid_t_end": ((ITEM,), "rigid twin: time of its last resolved collision (its collapse time if it collapsed)",
                    "1", "dimensionless, in sqrt(m/2k)", np.float64),
    "rigid_collisions": ((ITEM,), "rigid twin: collisions resolved before its stop", "1", None, np.int64),
    "rigid_low": ((ITEM,), "rigid twin: lowest grain of the collapsing run of collisions (-1: no collapse)", "1", None,
                  np.int64),
    "rigid_high": ((ITEM,), "rigid twin: highest grain of the collapsing run of collisions (-1: no collapse)", "1",
                   None, np.int64),
}


def finish(ds: xr.Dataset, spec: dict) -> xr.Dataset:
    """The items on the (r, n, sample) grid, with mu(r), the minimum energy of each column and the settings."""
    r, ns, samples = rn_grid(spec)
    gamma = float(spec["gamma"])
    out = xr.Dataset(attrs=dict(ds.attrs))
    for name, var in ds.data_vars.items():
        out[name] = xr.Variable(("r", "n", "sample"), var.values.reshape(r.size, ns.size, samples), var.attrs)
    out["mu"] = xr.Variable(("r",), np.array([mu_of_restitution(float(x)) for x in r]),
                            {"long_name": "dimer damping mu with exp(-mu T_xi) = r", "units": "1"})
    out["e_min"] = xr.Variable(("n",), np.array([rest_energy(int(k), gamma) for k in ns]),
                               {"long_name": "sum of E - E_m over the grains at the column's static equilibrium",
                                "units": "1"})
    out = out.assign_coords(
        r=xr.Variable(("r",), r, {"long_name": "restitution coefficient r (dimers: exp(-mu T_xi))", "units": "1"}),
        n=xr.Variable(("n",), ns, {"long_name": "number of grains in the column", "units": "1"}),
        sample=xr.Variable(("sample",), np.arange(samples), {"long_name": "initial state (random gaps)", "units": "1"}))
    out.attrs.update(samples=samples, seed=int(spec["seed"]), gamma=gamma, height=float(spec["height"]),
                     gap=float(spec["gap"]), rest=float(spec["rest"]), max_events=int(spec["max_events"]))
    return out


def plot(ds: xr.Dataset, spec: dict, outputs) -> None:
    """Against n: (a) the dimers' time to rest and the rigid twin's collapse time, (b) the dimers' impacts to rest;
    every state a dot, the median over the states a line."""
    import matplotlib.pyplot as plt

    from ..figures.common import WIDTH, save

    n = ds["n"].values
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(WIDTH, 3.0), constrained_layout=True)
    for i, r in enumerate(ds["r"].values):
        color = f"C{i}"
        t_rest = np.where(ds["dimer_rested"].values[i] == 1, ds["dimer_t_rest"].values[i], np.nan)
        collapsed = ds["rigid_stop"].values[i] == STOP_NAMES.index("collapse")
        t_col = np.where(collapsed, ds["rigid_t_end"].values[i], np.nan)
        impacts = np.where(ds["dimer_rested"].values[i] == 1, ds["dimer_impacts"].values[i], np.nan).astype(float)
        for ax, values, marker, label in ((a1, t_rest, "o", f"dimers to rest, r = {r:g}"),
                                          (a1, t_col, "s", f"rigid collapse, r = {r:g}"),
                                          (a2, impacts, "o", f"dimers, r = {r:g} (mu = {float(ds['mu'][i]):.3g})")):
            filled = marker == "s"
            ax.plot(np.repeat(n, values.shape[1]), values.ravel(), marker, ms=3, color=color,
                    mfc=color if filled else "none", alpha=0.6)
            ax.plot(n, np.nanmedian(values, axis=1) if np.isfinite(values).any() else values[:, 0], "-" if not filled
                    else "--", color=color, lw=0.9, label=label)
    a1.set(xscale="log", yscale="log", xlabel="grains in the column n",
           ylabel=r"time  [$\sqrt{m/2k}$]")
    a1.set_title(f"(a) dimers: E - E_min down to {ds.attrs['rest']:g} of its start;\nrigid rods: collapse "
                 f"(the engine's stop)", fontsize=8)
    a2.set(xscale="log", yscale="log", xlabel="grains in the column n", ylabel="impacts to rest (floor and pair)")
    a2.set_title("(b) dimers: impacts to rest, finite\n(rigid rods: infinitely many before the collapse)", fontsize=8)
    for ax in (a1, a2):
        ax.set_xticks(n, [str(int(k)) for k in n])
        ax.xaxis.set_minor_locator(plt.matplotlib.ticker.NullLocator())
        ax.legend(fontsize=6)
    # labels at 1, 2, 5 x 10^k only (every minor tick labelled crowded 900 into 1000)
    a1.yaxis.set_major_locator(plt.matplotlib.ticker.LogLocator(subs=(1.0, 2.0, 5.0)))
    a1.yaxis.set_major_formatter(plt.matplotlib.ticker.FormatStrFormatter("%g"))
    a1.yaxis.set_minor_formatter(plt.matplotlib.ticker.NullFormatter())
    fig.suptitle(f"a column of n grains dropped from rest (gamma = {ds.attrs['gamma']:g}, lowest mass at height "
                 f"{ds.attrs['height']:g}, gaps < {ds.attrs['gap']:g}); dots: {int(ds.attrs['samples'])} states, "
                 f"lines: median", fontsize=7)
    save(fig, outputs)


def estimated_memory_mb(spec: dict) -> int:
    """A chunk's records and snapshots (~ CHUNK x (4 n + 3) x 8 bytes, twice with the energies), plus the
    interpreter."""
    return 300 + int(2 * 8 * CHUNK * (4 * max(spec["n"]) + 3) / 2**20)


SWEEP = Sweep(NAME, "A column of dimers on the floor comes to rest without collapse; its rigid twin collapses "
              "(beyond the paper)", rn_size, rn_prepare, compute,
              {k: v[:4] for k, v in VARIABLES.items()}, finish, plot, estimated_memory_mb)

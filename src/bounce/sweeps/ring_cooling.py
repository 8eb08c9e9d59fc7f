"""Sweep ``ring-cooling``: free cooling of three gases on a ring, from the same states (beyond the paper).

Every item is one random state of n points on a ring (:func:`bounce.analysis.gas_rings.ring_points`, velocities
scaled by ``speed``, centre-of-mass frame), run to the horizon ``time.max`` (or its stop) three times:

* ``rigid``: rigid points with constant restitution r (:mod:`bounce.gas.rigid`), to its collapse if it collapses;
* ``tc``: the same with the TC model (a collision within ``t_c`` of a grain's previous one is elastic);
* ``dimer``: dimers (:mod:`bounce.gas.dimer`, exact to rounding) whose single-impact restitution exp(-mu T_xi) is r
  (:func:`~bounce.analysis.gas_rings.mu_of_restitution`), springs at rest, on a ring of 2n
  (:func:`~bounce.analysis.gas_rings.dimer_state`: the points' free length per grain).

Recorded, each at its exact time (:func:`~bounce.analysis.gas_rings.states_at`; NaN after a collapse or an engine stop):

* on the log-spaced grid ``time``: the translational granular temperature T = mean (v - <v>)^2 over the grains
  (v the point's velocity, or the dimer's centre-of-mass velocity psi'), and the dimers' internal energy
  mean (xi'^2 + xi^2) (twice the energy per grain held in the springs: the scale of T);
* Haff's law for each state: T0 and t0 = 2 / ((1 - r^2) omega0), omega0 the state's initial collision rate per grain
  (:func:`~bounce.analysis.gas_rings.collision_rate`).  Haff (molecular chaos, Gaussian velocities):
  dT/dt = -(1 - r^2) omega T / 2 with omega = 2 sqrt(T/pi) at unit density, so T = T0 / (1 + t/t0)^2;
* world lines of every ``worldlines.every``-th grain on ``worldlines.points`` times evenly spaced in
  [0, min(worldlines.t_max, time.max)]:
  its position on the points' ring of circumference n (a dimer's lower mass x_k - k, the length of the k rods
  below it taken out: the map of :func:`~bounce.analysis.gas_rings.dimer_state` inverted), modulo n;
* how each run ended (``bounce.gas.common.STOP_NAMES``) and the time of its last event (the horizon if it reached it).

Units: the paper's dimensionless ones (lengths in the spring's rest length, times in sqrt(m/2k)); T is a squared
speed in those units.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from ..analysis.gas_rings import collision_rate, dimer_state, mu_of_restitution, ring_points, states_at
from ..gas.common import STOP_NAMES
from ..gas.model import GasParameters, RigidParameters, RigidState
from ..gas.simulate import GasRun
from .base import ITEM, Sweep

NAME = "ring-cooling"
MODELS = ("rigid", "tc", "dimer")
TIME, WL_TIME, WL_GRAIN = "time", "wl_time", "wl_grain"


def _grid(spec: dict) -> tuple[np.ndarray, int]:
    return np.asarray(spec["r"], dtype=float), int(spec["samples"])


def times(spec: dict) -> np.ndarray:
    """The log-spaced grid of the temperatures."""
    t = spec["time"]
    return np.geomspace(float(t["min"]), float(t["max"]), int(t["n"]))


def worldline_times(spec: dict) -> np.ndarray:
    w = spec["worldlines"]
    return np.linspace(0.0, min(float(w["t_max"]), float(spec["time"]["max"])), int(w["points"]))


def worldline_grains(spec: dict) -> np.ndarray:
    return np.arange(0, int(spec["n"]), int(spec["worldlines"]["every"]))


def size(spec: dict) -> int:
    r, samples = _grid(spec)
    return r.size * samples


def prepare(spec: dict, items: np.ndarray) -> dict:
    """r of each item: item k is (r_i, sample s) with k = i samples + s."""
    r, samples = _grid(spec)
    items = np.asarray(items, dtype=np.int64)
    return {"r": r[items // samples], "item": items}


def _runs(spec: dict, r: float, x: np.ndarray, v: np.ndarray) -> dict:
    """The three runs of one state, by model, to the horizon."""
    n = x.size
    return {"rigid": GasRun(RigidParameters(n, "ring", 0.0, r, ell=float(n), size=0.0), RigidState(x, v),
                            float(spec["time"]["max"]), 0),
            "tc": GasRun(RigidParameters(n, "ring", 0.0, r, ell=float(n), size=0.0, t_c=float(spec["t_c"])),
                         RigidState(x, v), float(spec["time"]["max"]), 0),
            "dimer": GasRun(GasParameters(n, "ring", 0.0, mu_of_restitution(r), ell=2.0 * n), dimer_state(x, v),
                            float(spec["time"]["max"]), 0)}


def compute(spec: dict, inputs: dict) -> dict:
    seed, speed, n = int(spec["seed"]), float(spec["speed"]), int(spec["n"])
    grid, wl_t, wl_k = times(spec), worldline_times(spec), worldline_grains(spec)
    at = np.concatenate([grid, wl_t])
    order = np.argsort(at, kind="stable")
    rank = np.empty(order.size, dtype=np.int64)  # the row of at[i] among the sorted times
    rank[order] = np.arange(order.size)
    rows = {"grid": rank[:grid.size], "wl": rank[grid.size:]}
    m = len(inputs["r"])
    out = {"T0": np.zeros(m), "t0": np.zeros(m), "omega0": np.zeros(m), "dimer_internal": np.zeros((m, grid.size))}
    for model in MODELS:
        out[f"T_{model}"] = np.zeros((m, grid.size))
        out[f"worldline_{model}"] = np.zeros((m, wl_t.size, wl_k.size))
        out[f"stop_{model}"] = np.zeros(m, dtype=np.int8)
        out[f"t_end_{model}"] = np.zeros(m)
    for c in range(m):
        r = float(inputs["r"][c])
        x, v = ring_points(n, np.random.default_rng([seed, int(inputs["item"][c])]), speed)
        out["T0"][c] = float(np.mean(v * v))
        out["omega0"][c] = collision_rate(v, float(n))
        out["t0"][c] = 2.0 / ((1.0 - r * r) * out["omega0"][c])
        for model, run in _runs(spec, r, x, v).items():
            st, _ = states_at(run, at[order], n)
            velocity = st["xdot"] + st["xidot"] if model == "dimer" else st["xdot"]  # psi' = x' + xi'
            temperature = np.mean((velocity - velocity.mean(axis=1, keepdims=True)) ** 2, axis=1)
            out[f"T_{model}"][c] = temperature[rows["grid"]]
            position = st["x"] - np.arange(n) if model == "dimer" else st["x"]
            out[f"worldline_{model}"][c] = np.mod(position[rows["wl"]][:, wl_k], float(n))
            out[f"stop_{model}"][c] = STOP_NAMES.index(run.stop)
            out[f"t_end_{model}"][c] = min(run.t_end, run.t_max)
            if model == "dimer":
                out["dimer_internal"][c] = np.mean(st["xidot"] ** 2 + st["eta"] ** 2, axis=1)[rows["grid"]]
    return out


_LONG = {"rigid": "rigid points, restitution r", "tc": "rigid points, restitution r, TC model",
         "dimer": "dimers, exp(-mu T_xi) = r"}
_SHORT = {"rigid": "rigid points", "tc": "TC model", "dimer": "dimers"}
_STOPS = ", ".join(f"{i} {name}" for i, name in enumerate(STOP_NAMES))
VARIABLES = {
    "T0": ((ITEM,), "initial granular temperature mean v^2 (centre-of-mass frame)", "1", None),
    "omega0": ((ITEM,), "initial collision rate per grain, 2 sum_{i<j} |v_i - v_j| / n^2", "1", None),
    "t0": ((ITEM,), "Haff's time t0 = 2 / ((1 - r^2) omega0)", "1", None),
    "dimer_internal": ((ITEM, TIME), "dimers: internal energy mean (xi'^2 + xi^2) (NaN after the run stopped)", "1",
                       None),
    **{f"T_{m}": ((ITEM, TIME), f"{_LONG[m]}: granular temperature mean (v - <v>)^2 (NaN after the run stopped)", "1",
                  "dimensionless units: speeds in L / sqrt(m/2k)") for m in MODELS},
    **{f"worldline_{m}": ((ITEM, WL_TIME, WL_GRAIN), f"{_LONG[m]}: position on the points' ring, modulo n", "1",
                          "lengths in L (a dimer's lower mass less the k rods below it)") for m in MODELS},
    **{f"stop_{m}": ((ITEM,), f"{_LONG[m]}: why the run ended ({_STOPS})", "1", None) for m in MODELS},
    **{f"t_end_{m}": ((ITEM,), f"{_LONG[m]}: time of its last event (the horizon if it reached it)", "1", None)
       for m in MODELS},
}


def finish(ds: xr.Dataset, spec: dict) -> xr.Dataset:
    """The items on the (r, sample) grid, with the time axes, mu(r) and the settings."""
    r, samples = _grid(spec)
    out = xr.Dataset(attrs=dict(ds.attrs))
    for name, var in ds.data_vars.items():
        out[name] = xr.Variable(("r", "sample") + var.dims[1:], var.values.reshape((r.size, samples) + var.shape[1:]),
                                var.attrs)
    out["mu"] = xr.Variable(("r",), np.array([mu_of_restitution(float(x)) for x in r]),
                            {"long_name": "dimer damping mu with exp(-mu T_xi) = r", "units": "1"})
    out = out.assign_coords(
        r=xr.Variable(("r",), r, {"long_name": "restitution coefficient r", "units": "1"}),
        sample=xr.Variable(("sample",), np.arange(samples), {"long_name": "initial state", "units": "1"}),
        time=xr.Variable((TIME,), times(spec), {"long_name": "time (dimensionless, in sqrt(m/2k))", "units": "1"}),
        wl_time=xr.Variable((WL_TIME,), worldline_times(spec),
                            {"long_name": "time of the world-line points (dimensionless)", "units": "1"}),
        wl_grain=xr.Variable((WL_GRAIN,), worldline_grains(spec), {"long_name": "grain index", "units": "1"}))
    out.attrs.update(samples=samples, n=int(spec["n"]), seed=int(spec["seed"]), speed=float(spec["speed"]),
                     t_c=float(spec["t_c"]), horizon=float(spec["time"]["max"]), stop_names=" ".join(STOP_NAMES))
    return out


def plot(ds: xr.Dataset, spec: dict, outputs) -> None:
    """Per r: T/T0 against t/t0 (all states, the three models, the dimers' internal energy, Haff's law) on log
    axes, and the space-time diagrams of the first state's world lines for the three models."""
    import matplotlib.pyplot as plt

    from ..figures.common import WIDTH, save

    colours = {"rigid": "C3", "tc": "C0", "dimer": "C2"}
    nr = ds.sizes["r"]
    fig, axes = plt.subplots(nr, 4, figsize=(WIDTH * 1.25, 2.6 * nr), constrained_layout=True, squeeze=False,
                             gridspec_kw={"width_ratios": [1.6, 1, 1, 1]})
    t, n = ds["time"].values, int(ds.attrs["n"])
    for i, r in enumerate(ds["r"].values):
        ax = axes[i, 0]
        t0, T0 = ds["t0"].values[i], ds["T0"].values[i]
        tau = t[None, :] / t0[:, None]
        for model in MODELS:
            y = ds[f"T_{model}"].values[i] / T0[:, None]
            for s in range(y.shape[0]):
                ax.loglog(tau[s], y[s], "-", color=colours[model], lw=0.6, alpha=0.6,
                          label=_LONG[model] if s == 0 else None)
        e = ds["dimer_internal"].values[i] / T0[:, None]
        for s in range(e.shape[0]):
            ax.loglog(tau[s], np.where(e[s] > 0, e[s], np.nan), ":", color="0.35", lw=0.7,
                      label="dimers: internal energy" if s == 0 else None)
        h = np.geomspace(np.nanmin(tau), np.nanmax(tau), 200)
        ax.loglog(h, (1.0 + h) ** -2, "k--", lw=1.0, label=r"Haff: $(1 + t/t_0)^{-2}$")
        lo = min(np.nanmin(ds[f"T_{m}"].values[i] / T0[:, None]) for m in MODELS)
        ax.set_ylim(max(lo / 3.0, 1e-12), 2.0)
        ax.set(xlabel=r"$t/t_0$ (Haff's $t_0$ of each state)", ylabel=r"$T/T_0$, internal energy $/T_0$")
        letters = iter("abcdefghijklmnopqrstuvwxyz"[4 * i:4 * i + 4])
        ax.set_title(f"({next(letters)}) r = {r:g}, n = {n}: temperature, {ds.sizes['sample']} states", fontsize=8)
        for j, model in enumerate(MODELS, start=1):
            ax = axes[i, j]
            w = ds[f"worldline_{model}"].values[i, 0]
            wt = ds["wl_time"].values
            for k in range(w.shape[1]):
                y = w[:, k].copy()
                y[1:][np.abs(np.diff(y)) > 0.5 * n] = np.nan  # the seam: no line across the ring
                ax.plot(y, wt, "-", color=colours[model], lw=0.4)
            end = ds[f"t_end_{model}"].values[i, 0]
            stop = STOP_NAMES[int(ds[f"stop_{model}"].values[i, 0])]
            if stop != "t_max" and end <= wt[-1]:
                ax.axhline(end, color="k", lw=0.8, ls="--")
                ax.annotate(f"{stop} at t = {end:.3g}", (0.02, end), xycoords=("axes fraction", "data"),
                            xytext=(0, 2), textcoords="offset points", fontsize=5.5)
            ax.set(xlim=(0, n), ylim=(0, wt[-1]), xlabel="position (L)")
            if j == 1:
                ax.set_ylabel(r"time (dimensionless, $\sqrt{m/2k}$)")
            ax.set_title(f"({next(letters)}) {_SHORT[model]}, r = {r:g}", fontsize=8)
            ax.grid(False)
    every = int(ds["wl_grain"].values[1] - ds["wl_grain"].values[0]) if ds.sizes["wl_grain"] > 1 else n
    fig.suptitle(f"free cooling on a ring of {n} grains (dimensionless units: lengths in L, times in sqrt(m/2k); "
                 f"rms speed {ds.attrs['speed']:g}, TC model t_c = {ds.attrs['t_c']:g}); world lines: every "
                 f"{every} grain(s), state 0", fontsize=8)
    # one legend under the panels (in the first temperature panel it covered the dimers' internal energy)
    fig.legend(*axes[0, 0].get_legend_handles_labels(), loc="outside lower center", ncols=5, fontsize=7, frameon=False)
    save(fig, outputs)


def estimated_memory_mb(spec: dict) -> int:
    """Three runs' states at every sampled time (8 bytes x 4 fields x n x times), plus the interpreter."""
    points = int(spec["time"]["n"]) + int(spec["worldlines"]["points"])
    return 300 + int(3 * 32 * int(spec["n"]) * points / 2**20)


SWEEP = Sweep(NAME, "Free cooling on a ring: rigid gas (Haff's law, collapse), TC model and dimer gas (beyond the paper)",
              size, prepare, compute, VARIABLES, finish, plot, estimated_memory_mb)

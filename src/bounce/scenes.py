"""Scenes: a config slice (config/config.yaml) -> a simulation -> a netCDF dataset.

The pipeline's only entry to the numerics.  A scene spec is a plain dict::

    {"gamma": 0.01, "mu": 0.01,
     "initial": {"psi": 6.0, "psidot": 0.0, "xi": 0.0, "xidot": 0.0},
     "stop": {"events": 1000, "t_max": 420.0, "energy": 0.0},
     "keep": {"first": 20000, "log_samples": 20000}}

``initial`` may instead give (x, xdot, y, ydot), or ``sticky: {eps, ydot}`` for
eq. ``sticky-ic``.  ``keep`` thins the stored events for long runs (all events
are simulated; the file keeps the first ``first`` and ``log_samples`` log-spaced
indices after them); the coordinate ``event`` keeps the original index.
"""

from __future__ import annotations

import math

import numpy as np

from .model import Deviations, InputError, Parameters, State
from .simulate import simulate
from .trajectory import Trajectory
from .springs import spring_from_spec


def scene_parameters(spec: dict) -> Parameters:
    """gamma, mu and the spring law (``spring: {law: power, rho: .., a: .., b: ..}``, linear when absent)."""
    return Parameters(gamma=spec["gamma"], mu=spec["mu"], spring=spring_from_spec(spec.get("spring")))


def scene_initial(spec: dict, params: Parameters) -> State | Deviations:
    """The initial state of a scene, built without rounding where the paper's variables allow."""
    init = spec["initial"]
    if "sticky" in init:
        return State.sticky_ic(params, eps=init["sticky"]["eps"], ydot0=init["sticky"].get("ydot", -0.1))
    if "psi" in init:
        psi, psidot, xi, xidot = (float(init[k]) for k in ("psi", "psidot", "xi", "xidot"))
        # deviations directly: eta = xi - xi_eq (xi + gamma, linear spring), no detour through y ~ 1
        return Deviations(x=psi - xi, xdot=psidot - xidot, xidot=xidot, eta=xi - params.xi_eq)
    return State(x=init["x"], xdot=init["xdot"], y=init["y"], ydot=init["ydot"])


def scene_stop(spec: dict) -> dict:
    """The scene's stop rule with its absent parts filled in: events (1000), t_max (inf), energy (0: never)."""
    return {"events": 1000, "t_max": math.inf, "energy": 0.0, **spec["stop"]}


def run_scene(spec: dict) -> Trajectory:
    """Simulate a scene until its stop rule."""
    params = scene_parameters(spec)
    stop = scene_stop(spec)
    return simulate(params, scene_initial(spec, params), max_events=stop["events"], t_max=stop["t_max"],
                    energy_stop=stop["energy"])


def kept_events(n_events: int, keep: dict | None) -> np.ndarray:
    """Indices of the events a scene stores (all, or first + log-spaced)."""
    if not keep or n_events <= keep.get("first", n_events):
        return np.arange(n_events)
    first = int(keep["first"])
    n_log = int(keep.get("log_samples", 0))
    if first < 1:
        raise InputError(f"keep.first must be >= 1, got {first}")
    tail = np.unique(np.geomspace(first, n_events - 1, max(n_log, 2)).astype(np.int64))
    return np.unique(np.concatenate([np.arange(first), tail, [n_events - 1]]))


def scene_dataset(spec: dict, name: str = ""):
    """Run a scene and return its xarray Dataset (thinned by ``keep``), with the scene in the attributes."""
    from .io import to_dataset  # the I/O layer; the numerics above know nothing of it

    traj = run_scene(spec)
    ds = to_dataset(traj)
    ds = ds.assign_coords(event=np.arange(ds.sizes["event"]))
    ds["event"].attrs.update(long_name="index of the event in the full simulation (0 = first event after t = 0)", units="1")
    idx = kept_events(ds.sizes["event"], spec.get("keep"))
    if idx.size < ds.sizes["event"]:
        ds = ds.isel(event=idx)
        ds.attrs["events_kept"] = "first {first} and {log_samples} log-spaced after them".format(**spec["keep"])
    ds.attrs["n_events_simulated"] = int(len(traj))
    if name:
        ds.attrs["scene"] = name
    if "description" in spec:
        ds.attrs["scene_description"] = spec["description"]
    return ds


def gas_scene_start(spec: dict):
    """The parameters and generated start of a gas scene (config ``gas_scenes``, beyond the paper), each with the
    gas model's own validation (:mod:`bounce.gas.model`; :func:`bounce.gas.model.random_state`).

    ``{"model": "dimer" | "rigid", "geometry": "ring" | "column", "n": .., "gamma": .. (column), "ell": .. (ring),
    "mu": .. (dimer), "r": .., "size": .., "t_c": .. (rigid), "initial": {"speed", "gap", "seed"},
    "stop": {"events", "t_max"}, "snapshot_every": ..}``."""
    from .gas import GasParameters, RigidParameters
    from .gas.model import random_state

    gamma = spec.get("gamma", 0.0) if spec["geometry"] == "column" else 0.0
    if spec["model"] == "rigid":
        params = RigidParameters(spec["n"], spec["geometry"], gamma, spec["r"], spec.get("ell"),
                                 spec.get("size", 1.0), spec.get("t_c", 0.0))
    else:
        params = GasParameters(spec["n"], spec["geometry"], gamma, spec["mu"], spec.get("ell"))
    init = {"speed": 0.1, "gap": 0.5, "seed": 1, **spec.get("initial", {})}
    initial = random_state(params, init["speed"], init["gap"], init["seed"])
    initial.check(params)
    return params, initial


def gas_scene_run(spec: dict):
    """Run a gas scene (:func:`gas_scene_start`) to its stop rule: a :class:`bounce.gas.GasResult`."""
    from .gas import RigidParameters, simulate_gas, simulate_rigid

    params, initial = gas_scene_start(spec)
    run = simulate_rigid if isinstance(params, RigidParameters) else simulate_gas
    stop = {"events": 1000, "t_max": math.inf, **spec.get("stop", {})}
    return run(params, initial, max_events=stop["events"], t_max=stop["t_max"],
               snapshot_every=spec.get("snapshot_every", 0))


def gas_scene_dataset(spec: dict, name: str = ""):
    """Run a gas scene and return its dataset (:func:`bounce.gas.io.to_dataset`), the scene in the attributes."""
    from .gas.io import to_dataset

    ds = to_dataset(gas_scene_run(spec))
    if name:
        ds.attrs["scene"] = name
    if "description" in spec:
        ds.attrs["scene_description"] = spec["description"]
    return ds

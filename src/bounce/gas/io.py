"""netCDF of gas runs (CF-1.10): in one write, or streamed chunk by chunk for long runs (resumable).

A file holds one run of :mod:`bounce.gas`: per event (dimension ``event``) the time, kind, contact
and approach speed; per snapshot (``snapshot`` x ``grain``) the state of every grain (the dimer's
x, xdot, xidot, eta; the rigid grain's x, xdot); the initial state and the state after the last event
(``initial_*``, ``final_*``, dimension ``grain``); the parameters, settings, stop and provenance as
global attributes.  The house rules of :mod:`bounce.io` hold: units '1' with the paper's scales,
long names, atomic writes (:func:`bounce.io.write_netcdf`), no timestamps.

Streaming (:func:`stream_to_netcdf`): the run goes in chunks of events (:class:`~bounce.gas.GasRun`),
each appended to ``FILE.nc.partial`` (unlimited ``event`` and ``snapshot`` dimensions) and synced;
after each chunk the engine's whole state (grain, slot and queue arrays) is saved atomically to
``FILE.nc.partial.state.npz``.  An interrupted run continues from the last saved state with
``resume=True`` and gives the same records (the engines' state is all in those arrays; the records
past it are overwritten).  At the end the final state and the stop are written, the checkpoint is
removed and the file moved into place.  Memory: the chunk's buffers, whatever the number of events.
"""

from __future__ import annotations

import contextlib
import math
import os
from pathlib import Path

import numpy as np
import xarray as xr

from .._version import __version__
from ..errors import InputError
from ..io import CODECS, REFERENCES, UNITS_COMMENT, cf_variable, git_info
from .common import KIND_NAMES
from .model import GasParameters, GasState, RigidParameters, RigidState
from .simulate import GasResult, GasRun, run_chunks, run_settings, positive_int

#: long names of the snapshot fields
FIELD_NAMES = {
    "x": "height of the grain's lower mass (rigid: of its lower end)",
    "xdot": "velocity of the grain's lower mass (rigid: of the grain)",
    "xidot": "spring deformation rate xi' = (ydot - xdot)/2",
    "eta": "spring deformation from the single ball's static value, eta = xi + gamma = (y - x - 1)/2 + gamma",
}
INITIAL_NAMES = {
    "psi": "centre of mass (x + y - 1)/2 of the grain at t = 0",
    "psidot": "velocity of the centre of mass at t = 0",
    "xi": "spring deformation (y - x - 1)/2 at t = 0",
    "xidot": "spring deformation rate at t = 0",
    "x": "position of the grain's lower end at t = 0",
    "xdot": "velocity of the grain at t = 0",
}
EVENT_NAMES = {
    "t": ("time of the event", "the engines' double-double clock rounded to float64"),
    "kind": ("kind of the event", "floor and pair: impacts; grazing: a zero-speed contact, nothing exchanged; "
             "floor_elastic, pair_elastic: collisions the TC model made elastic (rigid gas)"),
    "pair": ("contact of the event", "k: the neighbours k and k+1 (on the ring, n-1: grains n-1 and 0 across the "
             "seam); -1: the floor under grain 0"),
    "speed": ("approach speed of the touching masses just before the event", "relative to the floor for the floor"),
}
BYTES_PER_EVENT = 8 + 1 + 4 + 8


def _initial(initial) -> dict[str, np.ndarray]:
    if isinstance(initial, RigidState):
        return {"x": initial.x, "xdot": initial.xdot}
    return {"psi": initial.psi, "psidot": initial.psidot, "xi": initial.xi, "xidot": initial.xidot}


def _attrs(params, settings: dict) -> dict:
    rigid = isinstance(params, RigidParameters)
    commit, dirty = git_info()
    attrs = {
        "Conventions": "CF-1.10",
        "title": f"Gas of {'rigid grains' if rigid else 'two-mass grains (dimers)'}: events and snapshots of one run",
        "source": f"bounce {__version__} (bounce.gas)",
        "references": REFERENCES,
        "comment": (UNITS_COMMENT + " Grains are numbered from the floor up (column) or along the ring; a snapshot "
                    "is the state of every grain just after event snapshot_event.  The dimer's upper mass is at "
                    "y = x + 1 + 2 (eta - gamma)."),
        "bounce_version": __version__,
        "git_commit": commit,
        "git_dirty": dirty,
        "model": "rigid" if rigid else "dimer",
        "geometry": params.geometry,
        "n": int(params.n),
        "gamma": float(params.gamma),
        "max_events": int(settings["max_events"]),
        "t_max": float(settings["t_max"]),
        "snapshot_every": int(settings["snapshot_every"]),
    }
    if params.geometry == "ring":
        attrs["ell"] = float(params.ell)
    if rigid:
        attrs.update(r=float(params.r), size=float(params.size), t_c=float(params.t_c))
    else:
        attrs["mu"] = float(params.mu)
    return attrs


def _stop_attrs(stop: str, t_end: float, message: str, n_events: int, collapse: dict | None) -> dict:
    attrs = {"stop_reason": stop, "t_end": float(t_end), "stop_message": message, "n_events": int(n_events)}
    if collapse:
        attrs.update(collapse_t=float(collapse["t"]), collapse_grains=np.array(collapse["grains"], dtype=np.int64),
                     collapse_run=int(collapse["run"]), collapse_criterion=collapse["criterion"],
                     collapse_contact=int(collapse["contact"]))
    return attrs


def _dataset(params, initial, settings, events: dict, snap_t, snap_event, snaps: dict, final: dict) -> xr.Dataset:
    data = {
        "t": cf_variable(("event",), events["t"], *EVENT_NAMES["t"]),
        "kind": cf_variable(("event",), events["kind"], *EVENT_NAMES["kind"], dtype=np.int8,
                     flag_values=np.arange(len(KIND_NAMES), dtype=np.int8), flag_meanings=" ".join(KIND_NAMES)),
        "pair": cf_variable(("event",), events["pair"], *EVENT_NAMES["pair"], dtype=np.int32),
        "speed": cf_variable(("event",), events["speed"], *EVENT_NAMES["speed"]),
        "snapshot_t": cf_variable(("snapshot",), snap_t, "time of the snapshot"),
        "snapshot_event": cf_variable(("snapshot",), snap_event, "index of the event the snapshot follows", dtype=np.int64),
    }
    for name, values in snaps.items():
        data[name] = cf_variable(("snapshot", "grain"), values, FIELD_NAMES[name])
    for name, values in final.items():
        data["final_" + name] = cf_variable(("grain",), values, FIELD_NAMES[name] + ", just after the last event")
    for name, values in _initial(initial).items():
        data["initial_" + name] = cf_variable(("grain",), values, INITIAL_NAMES[name])
    return xr.Dataset(data, attrs=_attrs(params, settings))


def to_dataset(result: GasResult) -> xr.Dataset:
    """The CF dataset of a :class:`~bounce.gas.GasResult` (module docstring)."""
    events = {"t": result.t, "kind": result.kind, "pair": result.pair, "speed": result.speed}
    ds = _dataset(result.params, result.initial, result.settings, events, result.snap_t, result.snap_event,
                  result.snapshots, result.final)
    ds.attrs.update(_stop_attrs(result.stop_reason, result.t_end, result.message, len(result), result.collapse))
    return ds


def from_dataset(ds: xr.Dataset) -> GasResult:
    """The :class:`~bounce.gas.GasResult` a file holds (exactly: parameters, initial state, records)."""
    a = ds.attrs
    missing = [k for k in ("model", "geometry", "n", "gamma", "stop_reason", "t_end") if k not in a]
    if missing:
        raise InputError(f"not a bounce gas dataset: missing attributes {', '.join(missing)}")
    ell = float(a["ell"]) if "ell" in a else None
    init = {name[len("initial_"):]: np.asarray(ds[name].values) for name in ds.variables if name.startswith("initial_")}
    if a["model"] == "rigid":
        params = RigidParameters(int(a["n"]), str(a["geometry"]), float(a["gamma"]), float(a["r"]), ell,
                                 float(a["size"]), float(a["t_c"]))
        initial = RigidState(init["x"], init["xdot"])
    else:
        params = GasParameters(int(a["n"]), str(a["geometry"]), float(a["gamma"]), float(a["mu"]), ell)
        initial = GasState(init["psi"], init["psidot"], init["xi"], init["xidot"])
    fields = [name for name in FIELD_NAMES if name in ds.variables]
    collapse = None
    if "collapse_t" in a:
        low, high = (int(v) for v in np.atleast_1d(a["collapse_grains"]))
        collapse = {"t": float(a["collapse_t"]), "grains": (low, high), "run": int(a["collapse_run"]),
                    "collisions": int(a["n_events"]), "contact": int(a["collapse_contact"]),
                    "criterion": str(a["collapse_criterion"])}
    return GasResult(
        params=params, initial=initial, t=np.asarray(ds["t"].values), kind=np.asarray(ds["kind"].values, np.int8),
        pair=np.asarray(ds["pair"].values, np.int32), speed=np.asarray(ds["speed"].values),
        snap_t=np.asarray(ds["snapshot_t"].values), snap_event=np.asarray(ds["snapshot_event"].values, np.int64),
        snapshots={k: np.asarray(ds[k].values) for k in fields},
        final={k: np.asarray(ds["final_" + k].values) for k in fields}, stop_reason=str(a["stop_reason"]),
        t_end=float(a["t_end"]), message=str(a.get("stop_message", "")), collapse=collapse,
        settings={"max_events": int(a["max_events"]), "t_max": float(a["t_max"]),
                  "snapshot_every": int(a["snapshot_every"])},
    )


# --------------------------------------------------------------------------- streaming

def partial_path(out) -> Path:
    out = Path(out)
    return out.with_name(out.name + ".partial")


def checkpoint_path(out) -> Path:
    return partial_path(out).with_name(partial_path(out).name + ".state.npz")


def _save_checkpoint(path: Path, run: GasRun, snapshots: int) -> None:
    """The engine's arrays, atomically (a temporary file in the same directory, then os.replace)."""
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp.npz")
    try:
        np.savez(tmp, snapshots=np.int64(snapshots), **run.arrays())
        with open(tmp, "rb+") as fh:
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    finally:
        with contextlib.suppress(OSError):
            os.unlink(tmp)


def stream_to_netcdf(params, initial, out, max_events: int, t_max: float = math.inf, snapshot_every: int = 0,
                     chunk: int = 1 << 18, resume: bool = False, progress: bool | None = None,
                     compression: str = "none") -> dict:
    """Run and append the records to ``out`` chunk by chunk (module docstring); return a summary dict.
    ``resume``: continue ``<out>.partial`` from its checkpoint (the same arguments required)."""
    import netCDF4

    max_events, t_max, every = run_settings(max_events, t_max, snapshot_every)
    chunk = positive_int("chunk", chunk, max(max_events, 1))
    out = Path(out)
    part, ckpt = partial_path(out), checkpoint_path(out)
    settings = {"max_events": max_events, "t_max": t_max, "snapshot_every": every}
    if resume:
        if not (part.exists() and ckpt.exists()):
            raise InputError(f"--resume: no interrupted run to resume ({str(part)!r} or its checkpoint is missing)")
        with np.load(ckpt) as saved:
            arrays = {k: saved[k] for k in saved.files}
        run = GasRun(params, initial, t_max, every, arrays=arrays)
        snapshots = int(arrays["snapshots"])
    else:
        run = GasRun(params, initial, t_max, every)
        snapshots = 0
        header = _dataset(params, initial, settings, {k: np.empty(0) for k in EVENT_NAMES}, np.empty(0),
                          np.empty(0), {k: np.empty((0, params.n)) for k in run.fields},
                          {k: np.zeros(params.n) for k in run.fields})
        size = max(1, min(chunk, 1 << 16))
        encoding = {}
        for name, var in header.variables.items():
            enc = {"_FillValue": None, **CODECS[compression]}
            if "event" in var.dims:
                enc["chunksizes"] = (size,)
            elif "snapshot" in var.dims:
                enc["chunksizes"] = (1,) + var.shape[1:] if var.ndim == 2 else (64,)
            encoding[name] = enc
        header.to_netcdf(part, mode="w", format="NETCDF4", engine="netcdf4", encoding=encoding,
                         unlimited_dims=["event", "snapshot"])
        _save_checkpoint(ckpt, run, snapshots)
    mine = _attrs(params, settings)
    with netCDF4.Dataset(part, "a") as nc:
        nc.set_auto_maskandscale(False)
        if resume:
            differ = [k for k in ("model", "geometry", "n", "gamma", "mu", "r", "size", "t_c", "ell", "max_events",
                                  "t_max", "snapshot_every") if str(nc.__dict__.get(k)) != str(mine.get(k))]
            if differ:
                raise InputError(f"--resume: {str(part)!r} is a different run (differs in {', '.join(differ)}); "
                                 "rerun without --resume")
        counts = np.asarray(nc.__dict__.get("stream_kind_counts", np.zeros(len(KIND_NAMES))), dtype=np.int64)
        for first, (rec, k, snaps) in _indexed(run, max_events, chunk, progress):
            counts += np.bincount(rec.kind[:k], minlength=len(KIND_NAMES))
            for name in EVENT_NAMES:
                nc[name][first:first + k] = getattr(rec, name)[:k]
            if snaps:
                nc["snapshot_t"][snapshots:snapshots + snaps] = rec.snap_t[:snaps]
                nc["snapshot_event"][snapshots:snapshots + snaps] = rec.snap_event[:snaps]
                for i, name in enumerate(run.fields):
                    nc[name][snapshots:snapshots + snaps, :] = rec.snap[i, :snaps]
                snapshots += snaps
            nc.setncatts({"stream_kind_counts": counts})
            nc.sync()
            _save_checkpoint(ckpt, run, snapshots)
        for name, values in run.final().items():
            nc["final_" + name][:] = values
        nc.setncatts(_stop_attrs(run.stop, run.t_end, run.message(), run.events, run.collapse()))
        nc.delncattr("stream_kind_counts") if "stream_kind_counts" in nc.ncattrs() else None
    os.replace(part, out)
    with contextlib.suppress(OSError):
        os.unlink(ckpt)
    return {"events": run.events, "snapshots": snapshots, "counts": dict(zip(KIND_NAMES, counts.tolist())),
            "stop_reason": run.stop, "t_end": run.t_end, "message": run.message()}


def _indexed(run: GasRun, max_events: int, chunk: int, progress):
    """run_chunks with the index of each chunk's first event."""
    first = run.events
    for rec, k, snaps in run_chunks(run, max_events, chunk, progress, done=first):
        yield first, (rec, k, snaps)
        first += k

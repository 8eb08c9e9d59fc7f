"""Runs longer than memory: the event loop in chunks, records streamed to netCDF, resumable.

:func:`chunks` drives :func:`bounce.exact.events.run_events` ``chunk`` events at a time, carrying
the loop's whole state between calls (``carry``), so the records are the bits of one call
(tests/test_stream.py).  On top of it:

* :func:`simulate_chunked`: the :class:`~bounce.trajectory.Trajectory` of
  :func:`bounce.simulate.simulate`, in memory, with a progress bar;
* :func:`stream_to_netcdf`: the records appended to a netCDF file with an unlimited
  ``event`` dimension (all of them, or thinned on the fly to the first ``first`` events and
  ``log_samples`` log-spaced indices up to ``max_events``, the rule of
  :func:`bounce.scenes.kept_events`), written to ``<out>.partial`` and moved into place at
  the end.  After every chunk the file is synced and the loop state stored in its attributes:
  an interrupted run continues from there (``resume=True``) and gives the same records.

Memory bound: the chunk buffers, :data:`BYTES_PER_EVENT_STREAM` x ``chunk`` (~105 MB at the
default 2^20), plus the kept-index table when thinning (8 bytes per kept event) and the
interpreter (~250 MB with numba and xarray): independent of the number of events.  The one-shot
path holds every record, :data:`BYTES_PER_EVENT` per event; :func:`check_memory` refuses a run
whose estimate exceeds the memory available, before allocating anything.
"""

from __future__ import annotations

import math
import os
import sys
from pathlib import Path

import numpy as np

from .kinds import KIND_NAMES, STOP_EVENTS, STOP_FAILED, STOP_NAMES
from .exact.events import CARRY_SIZE, SQRT2, run_events
from .model import InputError, Parameters, check_supported
from .exact.oscillator import make_oscillator
from .trajectory import MAX_EVENTS, Trajectory, positive_int

#: one-shot path: 6 float64 records + int8 kind (simulate), 4 derived float64 arrays (netCDF write)
BYTES_PER_EVENT = 6 * 8 + 1 + 4 * 8
#: streaming: the chunk buffers (6 float64 + int8) and the derived arrays of one chunk (4 float64)
BYTES_PER_EVENT_STREAM = BYTES_PER_EVENT + 24
DEFAULT_CHUNK = 1 << 20
#: most events a streamed run takes: memory is bounded by the chunk, time is the user's (1e12 ~ a day)
MAX_STREAM_EVENTS = 10**12
FILE_CHUNK = 1 << 16  # elements per netCDF chunk of a streamed file
CHUNK_CACHE_BYTES = 2 * 8 * FILE_CHUNK  # per variable: the chunk being filled and one more
BASELINE_BYTES = 250 * 2**20  # interpreter, numpy, numba, xarray, netCDF4


def available_memory() -> int:
    """Bytes this process may still allocate: MemAvailable, capped by RLIMIT_AS if set."""
    avail = math.inf
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    avail = int(line.split()[1]) * 1024
    except OSError:
        pass
    try:
        import resource

        soft, _ = resource.getrlimit(resource.RLIMIT_AS)
        if soft != resource.RLIM_INFINITY:
            avail = min(avail, soft)
    except (ImportError, ValueError, OSError):
        pass
    return int(avail) if math.isfinite(avail) else 1 << 62


def check_memory(events: int, bytes_per_event: int = BYTES_PER_EVENT, option: str = "--events") -> None:
    """Refuse up front a run whose records would not fit in memory, with the estimate."""
    need = events * bytes_per_event + BASELINE_BYTES
    have = available_memory()
    if need > have:
        raise InputError(
            f"{option} {events} needs ~{need / 1e9:.3g} GB of memory ({bytes_per_event} bytes per event), "
            f"{have / 1e9:.3g} GB available: use --stream (bounded memory) or at most "
            f"{max((have - BASELINE_BYTES) // bytes_per_event, 0)} events"
        )


# --------------------------------------------------------------------------- the chunked driver

class _Buffers:
    """The output arrays of one run_events call (t, tau, u, a, eta, e, kind)."""

    def __init__(self, size: int):
        self.floats = [np.empty(size) for _ in range(6)]
        self.kind = np.empty(size, dtype=np.int8)


def chunks(params: Parameters, initial, max_events: int, t_max: float = math.inf, energy_stop: float = 0.0,
           chunk: int = DEFAULT_CHUNK, carry: np.ndarray | None = None, done: int = 0, out: list | None = None):
    """Yield ``(first_index, records, stop, t_end, carry)`` per chunk of at most ``chunk`` events.

    ``records`` are views (t, tau, xdot, xidot, eta, energy_excess, kind) valid until the next
    chunk, or, with ``out`` (those seven arrays for all ``max_events``), views of ``out`` filled
    in place.  ``carry`` and ``done`` resume an earlier run after its ``done`` events.  ``stop``
    is a STOP_NAMES entry; the generator ends after the chunk where the run stops.
    """
    max_events = positive_int("events", max_events, MAX_STREAM_EVENTS)
    chunk = positive_int("chunk", chunk, MAX_EVENTS)
    if params.spring.solver != "exact":
        raise InputError(f"chunked runs drive the closed-form event loop; got the {params.spring.name} spring")
    start = initial.deviations(params)
    check_supported(params, start)
    params_arr, coefs = make_oscillator(params.mu)
    sparams, scoefs = make_oscillator(params.mu / SQRT2)
    if carry is None:
        carry = np.zeros(CARRY_SIZE)
    buf = _Buffers(min(chunk, max_events - done) if done < max_events and out is None else 0)
    while done < max_events:
        m = min(chunk, max_events - done)
        floats, kind = (buf.floats, buf.kind) if out is None else ([a[done:done + m] for a in out[:6]], out[6][done:done + m])
        n, stop, t_end = run_events(
            start.x, start.xdot, start.xidot, start.eta, params.gamma, params_arr, coefs, sparams, scoefs,
            m, t_max, energy_stop, *floats, kind, carry,
        )
        if stop == STOP_FAILED:
            raise RuntimeError(
                f"root finder did not converge after event {done + n} (t = {t_end!r}); "
                "please report the parameters and initial state"
            )
        finished = stop != STOP_EVENTS or done + n == max_events
        records = tuple(a[:n] for a in floats) + (kind[:n],)
        yield done, records, STOP_NAMES[stop], t_end, carry
        done += n
        if finished:
            return


def progress_enabled(progress: bool | None) -> bool:
    """The progress bar's default: on when stderr is a terminal."""
    return sys.stderr.isatty() if progress is None else bool(progress)


def _bar(total: int, progress: bool | None, initial: int = 0):
    from tqdm import tqdm

    return tqdm(total=total, initial=initial, unit="event", unit_scale=True, file=sys.stderr, desc="bounce",
                disable=not progress_enabled(progress), mininterval=0.5 if sys.stderr.isatty() else 30.0)


def simulate_chunked(params: Parameters, initial, max_events: int = 1000, t_max: float = math.inf,
                     energy_stop: float = 0.0, chunk: int = DEFAULT_CHUNK, progress: bool | None = None) -> Trajectory:
    """:func:`bounce.simulate.simulate` in chunks (bit for bit the same Trajectory), with a progress bar."""
    max_events = positive_int("events", max_events, MAX_STREAM_EVENTS)
    out = [np.empty(max_events) for _ in range(6)]
    kind = np.empty(max_events, dtype=np.int8)
    n, stop, t_end = 0, STOP_NAMES[STOP_EVENTS], 0.0
    with _bar(max_events, progress) as bar:
        for first, records, stop, t_end, _ in chunks(params, initial, max_events, t_max, energy_stop, chunk,
                                                     out=out + [kind]):
            n = first + len(records[0])
            bar.update(len(records[0]))
    t, tau, u, a, eta, e = (arr if n == max_events else arr[:n].copy() for arr in out)
    return Trajectory(
        params=params, initial=initial, t=t, tau=tau, xdot=u, xidot=a, eta=eta, energy_excess=e,
        kind=kind if n == max_events else kind[:n].copy(), stop_reason=stop, t_end=t_end,
        settings={"max_events": max_events, "t_max": float(t_max), "energy_stop": float(energy_stop)},
    )


# --------------------------------------------------------------------------- streaming to netCDF

def partial_path(out) -> Path:
    out = Path(out)
    return out.with_name(out.name + ".partial")


def kept_indices(max_events: int, keep: dict | None) -> np.ndarray | None:
    """The event indices kept when thinning on the fly (None: keep all); the last event is added at the stop."""
    if not keep:
        return None
    from .scenes import kept_events

    return kept_events(max_events, keep)


def _chunk_trajectory(params, initial, records) -> Trajectory:
    t, tau, u, a, eta, e, kind = records
    return Trajectory(params=params, initial=initial, t=t, tau=tau, xdot=u, xidot=a, eta=eta, energy_excess=e,
                      kind=kind, stop_reason="", t_end=0.0, settings={})


def _create(path: Path, params, initial, settings: dict, keep: dict | None, chunk: int, compression: str) -> None:
    """The file's header: to_dataset's variables and attributes with an unlimited, empty ``event`` dimension."""
    from .io import CODECS, to_dataset

    empty = Trajectory(params=params, initial=initial, t=np.empty(0), tau=np.empty(0), xdot=np.empty(0),
                       xidot=np.empty(0), eta=np.empty(0), energy_excess=np.empty(0),
                       kind=np.empty(0, dtype=np.int8), stop_reason="max_events", t_end=0.0, settings=settings)
    ds = to_dataset(empty)
    if keep:
        ds = ds.assign_coords(event=np.empty(0, dtype=np.int64))
        ds["event"].attrs.update(long_name="index of the event in the full simulation (0 = first event after t = 0)",
                                 units="1")
        ds.attrs["events_kept"] = "first {first} and {log_samples} log-spaced after them".format(**keep)
    ds.attrs.update(stream_done=0, stream_records=0, stream_carry=np.zeros(CARRY_SIZE),
                    stream_chunk=chunk)
    size = min(chunk, FILE_CHUNK)
    encoding = {name: {"_FillValue": None, "chunksizes": (size,), **CODECS[compression]} for name in ds.variables}
    ds.to_netcdf(path, mode="w", format="NETCDF4", engine="netcdf4", encoding=encoding, unlimited_dims=["event"])


def stream_to_netcdf(params: Parameters, initial, out, max_events: int, t_max: float = math.inf,
                     energy_stop: float = 0.0, chunk: int = DEFAULT_CHUNK, keep: dict | None = None,
                     resume: bool = False, progress: bool | None = None, compression: str = "none") -> dict:
    """Simulate and append the records to ``out`` chunk by chunk; return a summary dict.

    ``resume``: continue ``<out>.partial`` from its stored state (same parameters required).
    """
    import netCDF4

    from .io import EVENT_VARIABLES

    max_events = positive_int("events", max_events, MAX_STREAM_EVENTS)
    chunk = positive_int("chunk", chunk, MAX_EVENTS)
    out = Path(out)
    part = partial_path(out)
    settings = {"max_events": max_events, "t_max": float(t_max), "energy_stop": float(energy_stop)}
    if resume:
        if not part.exists():
            raise InputError(f"--resume: no interrupted run to resume ({str(part)!r} does not exist)")
    else:
        _create(part, params, initial, settings, keep, chunk, compression)
    kept = kept_indices(max_events, keep)
    counts = np.zeros(len(KIND_NAMES), dtype=np.int64)
    with netCDF4.Dataset(part, "a") as nc:
        nc.set_auto_maskandscale(False)
        for var in nc.variables.values():  # HDF5's default chunk cache (MBs per variable) would grow with the file
            var.set_var_chunk_cache(size=CHUNK_CACHE_BYTES, nelems=61, preemption=1.0)
        a = nc.__dict__
        if resume:
            mine = {"gamma": params.gamma, "mu": params.mu, "max_events": max_events, "t_max": float(t_max),
                    "energy_stop": float(energy_stop)}
            differ = [k for k, v in mine.items() if float(a[k]) != float(v)]
            if differ or ("event" in nc.variables) != bool(keep):
                raise InputError(f"--resume: {str(part)!r} is a different run (differs in "
                                 f"{', '.join(differ) or 'thinning'}); rerun without --resume")
            counts[:] = np.asarray(a.get("stream_kind_counts", counts))
        done, records_written = int(a["stream_done"]), int(a["stream_records"])
        carry = np.array(a["stream_carry"], dtype=np.float64) if done else None
        stop, t_end = "max_events", float(a["t_end"])
        with _bar(max_events, progress, initial=done) as bar:
            for first, records, stop, t_end, carry in chunks(params, initial, max_events, t_max, energy_stop,
                                                             chunk, carry, done):
                m = len(records[0])
                counts += np.bincount(records[6], minlength=len(KIND_NAMES))
                index = np.arange(first, first + m)
                last = stop != "max_events" or first + m == max_events
                if kept is not None:
                    sel = np.isin(index, kept) | ((index == first + m - 1) & last)
                    records = tuple(r[sel] for r in records)
                    index = index[sel]
                traj = _chunk_trajectory(params, initial, records)
                k = len(index)
                for name in EVENT_VARIABLES:
                    nc[name][records_written:records_written + k] = getattr(traj, name)
                nc["kind"][records_written:records_written + k] = traj.kind
                if kept is not None:
                    nc["event"][records_written:records_written + k] = index
                records_written += k
                nc.setncatts({"stream_done": first + m, "stream_records": records_written, "stream_carry": carry,
                              "stream_kind_counts": counts, "t_end": t_end})
                nc.sync()
                bar.update(m)
        n_events = int(nc.stream_done)
        summary_traj = Trajectory(params=params, initial=initial, t=np.empty(0), tau=np.empty(0),
                                  xdot=np.empty(0), xidot=np.empty(0), eta=np.empty(0), energy_excess=np.empty(0),
                                  kind=np.empty(0, dtype=np.int8), stop_reason=stop, t_end=t_end, settings=settings)
        t_valid = summary_traj.t_valid if stop in ("t_max", "sticky_forever") else (
            float(nc["t"][records_written - 1]) if records_written else 0.0)
        nc.setncatts({"stop_reason": stop, "t_end": float(t_end), "t_valid": float(t_valid),
                      "n_events_simulated": n_events})
        for name in ("stream_done", "stream_records", "stream_carry", "stream_kind_counts", "stream_chunk"):
            nc.delncattr(name)
    os.replace(part, out)
    return {"events": n_events, "records": records_written, "counts": dict(zip(KIND_NAMES, counts.tolist())),
            "stop_reason": stop, "t_end": float(t_end)}

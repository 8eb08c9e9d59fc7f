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

import contextlib
import fcntl
import math
import os
import shutil
import sys
from pathlib import Path

import netCDF4
import numpy as np

from .exact.events import CARRY_SIZE, SQRT2, run_events
from .exact.oscillator import make_oscillator
from .io import (EVENT_VARIABLES, check_output_path, disk_full_error, is_disk_full, signals_deferred, to_dataset,
                 write_netcdf)
from .kinds import KIND_NAMES, STOP_EVENTS, STOP_FAILED, STOP_NAMES
from .model import InputError, Parameters, check_supported
from .springs import spring_from_attrs
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


def free_disk(path: Path) -> int:
    """Bytes free for this user on the file system of ``path``'s directory."""
    return shutil.disk_usage(Path(path).resolve().parent).free


def check_disk(out: Path, events: int, keep: dict | None = None, bytes_per_event: int = BYTES_PER_EVENT) -> None:
    """Refuse up front a streamed run whose records could not fit on the disk of ``out``: ``events`` (the run's
    cap; its other stops may end it sooner, which cannot be known before) or, thinned, the events kept.  A run
    that then meets a full disk anyway ends with exit 1 and removes its partial file (bounce.cli)."""
    stored = events if keep is None else min(events, keep["first"] + keep["log_samples"] + 1)
    need, have = stored * bytes_per_event, free_disk(out)
    if need > have:
        most = max(have // bytes_per_event, 0)
        raise InputError(
            f"--events {events} would write up to ~{need / 1e9:.3g} GB ({bytes_per_event} bytes per event), "
            f"{have / 1e9:.3g} GB free where --out goes (allowed range here: [1, {most}]): fewer --events, or thin "
            "the records with --keep-first/--keep-log"
        )


def check_memory(events: int, bytes_per_event: int = BYTES_PER_EVENT, option: str = "--events",
                 hint: str = "") -> None:
    """Refuse up front a run whose records would not fit in memory, with the estimate (and ``hint``: what to do)."""
    need = events * bytes_per_event + BASELINE_BYTES
    have = available_memory()
    if need > have:
        most = max((have - BASELINE_BYTES) // bytes_per_event, 0)
        hint = hint or ("use --stream (bounded memory)" if option == "--events" else f"use a smaller {option}")
        raise InputError(
            f"{option} {events} needs ~{need / 1e9:.3g} GB of memory ({bytes_per_event} bytes per event), "
            f"{have / 1e9:.3g} GB available (allowed range here: [1, {most}]): {hint}"
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

#: the file a stream appends to, next to its target: ``<out>.partial``
PARTIAL_SUFFIX = ".partial"
#: the lock a stream holds on its partial file: ``.<out>.partial.bounce-lock``
_LOCK_SUFFIX = ".bounce-lock"
#: global attributes that define a streamed run (with its spring law and codec): --resume refuses a difference
RUN_ATTRS = ("gamma", "mu", "initial_form", "x0", "xdot0", "y0", "ydot0", "xidot0", "eta0", "max_events", "t_max",
             "energy_stop", "events_kept")
#: the loop state a partial file carries between chunks (removed when the run ends)
STREAM_ATTRS = ("stream_done", "stream_records", "stream_carry", "stream_kind_counts", "stream_chunk")


def partial_path(out) -> Path:
    out = Path(out)
    return out.with_name(out.name + PARTIAL_SUFFIX)


def check_paths(out) -> tuple[Path, Path]:
    """``(out, partial)`` checked as :func:`bounce.io.check_output_path` checks an output: the partial is
    written like an output, so a symbolic link, FIFO or device there is refused (OSError naming it)."""
    out = check_output_path(out, suffix=PARTIAL_SUFFIX)
    return out, check_output_path(partial_path(out))


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


def _header(params, initial, settings: dict, keep: dict | None, chunk: int):
    """The file's header: to_dataset's variables and attributes with an empty ``event`` dimension."""
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
                    stream_kind_counts=np.zeros(len(KIND_NAMES), dtype=np.int64), stream_chunk=chunk)
    return ds


def _codec(nc) -> str:
    """The codec (:data:`bounce.io.CODECS`) of a streamed file's records."""
    filters = nc["t"].filters() or {}
    return "zstd" if filters.get("zstd") else "zlib" if filters.get("zlib") else "none"


def _differences(nc, header, spring, compression: str) -> list[str]:
    """What differs between the run stored in ``nc`` and the one about to resume it: ``name: file, here``."""
    def same(a, b):
        if a is None or b is None or isinstance(a, str) or isinstance(b, str):
            return a == b
        return float(a) == float(b)

    mine, theirs = header.attrs, nc.__dict__
    out = [f"{k}: {theirs.get(k)!r} in the file, {mine.get(k)!r} here" for k in RUN_ATTRS
           if not same(theirs.get(k), mine.get(k))]
    stored = spring_from_attrs(theirs)
    if stored != spring:
        out.append(f"spring: {stored!r} in the file, {spring!r} here")
    if _codec(nc) != compression:
        out.append(f"compression: {_codec(nc)!r} in the file, {compression!r} here")
    return out


def _open_for_resume(part: Path, header, spring, compression: str):
    """The partial file, open for appending, after checking it holds this very run (InputError if not)."""
    try:
        st = os.stat(part)
    except FileNotFoundError:
        raise InputError(f"--resume: no interrupted run to resume ({str(part)!r} does not exist)") from None
    if st.st_nlink > 1:
        raise InputError(f"--resume: {str(part)!r} has {st.st_nlink} names (hard links): appending to it would change "
                         "the others too; rerun without --resume to start over")
    try:
        nc = netCDF4.Dataset(part, "a")
    except OSError as exc:  # netCDF4 reports a damaged HDF5 file as OSError ("NetCDF: HDF error")
        raise InputError(f"--resume: {str(part)!r} cannot be read as a netCDF file (truncated or damaged: "
                         f"{exc.strerror or exc}); rerun without --resume to start over") from None
    try:
        missing = [k for k in STREAM_ATTRS if k not in nc.ncattrs()]
        if missing or "t" not in nc.variables:
            raise InputError(f"--resume: {str(part)!r} is not the partial file of a bounce --stream run (no "
                             f"{', '.join(missing) or 'records'}); rerun without --resume to start over")
        differ = _differences(nc, header, spring, compression)
        if differ:
            raise InputError(f"--resume: {str(part)!r} holds a different run ({'; '.join(differ)}); resume with the "
                             "arguments of that run, or rerun without --resume to start over")
    except BaseException:
        nc.close()
        raise
    return nc


@contextlib.contextmanager
def _lock(part: Path):
    """Hold ``.<partial>.bounce-lock`` (flock) while a stream writes ``part``: a second run to the same output
    is refused (InputError) instead of truncating the partial file under the first.  The lock file is removed
    at the end; one left by a killed run is taken over by the next."""
    path = part.with_name(f".{part.name}{_LOCK_SUFFIX}")
    while True:
        fd = os.open(path, os.O_CREAT | os.O_RDWR | os.O_NOFOLLOW | os.O_CLOEXEC, 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = os.read(fd, 32).decode(errors="replace").strip() or "?"
            os.close(fd)
            raise InputError(f"--out: another bounce --stream run (pid {holder}) is writing {str(part)!r}; wait for it "
                             "to end (then --resume if it was interrupted) or choose another --out") from None
        try:
            current = os.stat(path)
        except FileNotFoundError:
            current = None
        if current is not None and os.path.samestat(current, os.fstat(fd)):
            break
        os.close(fd)  # the holder removed it after we opened it: take the lock of the file now at that name
    try:
        with contextlib.suppress(OSError):  # the pid only names the holder to a refused run (a full disk is met next)
            os.ftruncate(fd, 0)
            os.write(fd, f"{os.getpid()}\n".encode())
        yield
    finally:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(path)
        os.close(fd)


def stream_to_netcdf(params: Parameters, initial, out, max_events: int, t_max: float = math.inf,
                     energy_stop: float = 0.0, chunk: int = DEFAULT_CHUNK, keep: dict | None = None,
                     resume: bool = False, progress: bool | None = None, compression: str = "none") -> dict:
    """Simulate and append the records to ``out`` chunk by chunk; return a summary dict.

    The records go to ``<out>.partial`` (checked like ``out``; replaced atomically by a new run, so a
    hard link's other name is never written), moved to ``out`` at the end.  One run at a time per
    ``out`` (:func:`_lock`).  ``resume``: continue ``<out>.partial`` from its stored state, after
    checking that it holds this very run (parameters, spring, initial state, stop rules, thinning,
    codec; InputError naming what differs).  A chunk is written with SIGINT and SIGTERM deferred
    (:func:`bounce.io.signals_deferred`), so an interrupted run stops at its last complete chunk.  On
    a full disk the partial file is removed (it holds a damaged chunk) and OSError ENOSPC raised.
    """
    max_events = positive_int("events", max_events, MAX_STREAM_EVENTS)
    chunk = positive_int("chunk", chunk, MAX_EVENTS)
    out, part = check_paths(out)
    settings = {"max_events": max_events, "t_max": float(t_max), "energy_stop": float(energy_stop)}
    header = _header(params, initial, settings, keep, chunk)
    kept = kept_indices(max_events, keep)
    # HDF5 allocates a chunk whole: a run that can write only a few records (the kept events and the last
    # one, or --events) is chunked by that many, not by FILE_CHUNK records per variable
    records = max_events if kept is None else min(len(kept) + 1, max_events)
    with _lock(part):
        if resume:
            nc = _open_for_resume(part, header, params.spring, compression)
        else:
            write_netcdf(header, part, compression, unlimited="event", chunksize=min(chunk, FILE_CHUNK, records))
            nc = netCDF4.Dataset(part, "a")
        try:
            summary, final = _append(nc, params, initial, settings, kept, chunk, progress)
            with signals_deferred():  # the partial file stays resumable until it is the output
                nc.setncatts(final)
                for name in STREAM_ATTRS:
                    nc.delncattr(name)
                nc.close()
                os.replace(part, out)
        except BaseException as exc:
            full = is_disk_full(part.parent, exc)  # asked while the partial file still takes its space
            if nc.isopen():
                with contextlib.suppress(RuntimeError, OSError):
                    nc.close()
            if not full:
                raise
            with contextlib.suppress(OSError):
                os.unlink(part)
            kept = "the old file is kept unchanged" if out.exists() else "no file was written"
            raise disk_full_error(out, f"the partial file was removed; {kept}") from exc
    return summary


def _append(nc, params, initial, settings, kept, chunk, progress) -> tuple[dict, dict]:
    """Run the chunks into the open partial file ``nc`` (see :func:`stream_to_netcdf`), keeping the events
    ``kept`` (:func:`kept_indices`; None: all); return the summary and the file's final attributes."""
    max_events, t_max, energy_stop = settings["max_events"], settings["t_max"], settings["energy_stop"]
    nc.set_auto_maskandscale(False)
    for var in nc.variables.values():  # HDF5's default chunk cache (MBs per variable) would grow with the file
        var.set_var_chunk_cache(size=CHUNK_CACHE_BYTES, nelems=61, preemption=1.0)
    a = nc.__dict__
    counts = np.array(a["stream_kind_counts"], dtype=np.int64)
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
            with signals_deferred():  # a chunk is written whole or not at all
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
    summary = {"events": n_events, "records": records_written, "counts": dict(zip(KIND_NAMES, counts.tolist())),
               "stop_reason": stop, "t_end": float(t_end)}
    return summary, {"stop_reason": stop, "t_end": float(t_end), "t_valid": float(t_valid),
                     "n_events_simulated": n_events}

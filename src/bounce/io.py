"""netCDF I/O of simulated trajectories (CF-1.10).

A file holds the per-event records of one simulation (dimension ``event``) and,
optionally, closed-form samples of the motion at chosen times (dimension
``time``).  The event records are complete: together with the global attributes
(gamma, mu, the initial state and the stop settings) they determine the motion
exactly, so figure code can resample any file without re-running the
simulation::

    ds = read_dataset("run.nc")
    s = sample_dataset(ds, times)      # bit-for-bit sample_trajectory(traj, times)

This module knows nothing of the numerics beyond calling
:func:`bounce.sampling.sample_trajectory`.

Units: dimensionless; lengths in units of the spring rest length L, times in
units of sqrt(m / 2k) (paper, eq. ``dimensionless-eq-motion``).

Files are written atomically (temporary file in the target directory, then
``os.replace``) and reproducibly: no timestamps, so two writes of the same run
give identical bytes.
"""

from __future__ import annotations

import contextlib
import errno
import functools
import json
import os
import re
import signal
import stat
import subprocess
import threading
import uuid
from pathlib import Path

import numpy as np
import xarray as xr

from ._version import __version__
from .kinds import KIND_NAMES
from .model import Deviations, Parameters, State
from .sampling import sample_trajectory
from .trajectory import Trajectory
from .springs import spring_from_attrs

__all__ = [
    "DatasetError",
    "EVENT_VARIABLES",
    "SAMPLED_VARIABLES",
    "check_output_path",
    "complete_prefix",
    "disk_full_error",
    "from_dataset",
    "git_info",
    "is_disk_full",
    "method_dataset",
    "read_dataset",
    "read_trajectory",
    "remove_stale_temporaries",
    "sample_dataset",
    "signals_deferred",
    "to_dataset",
    "write_netcdf",
]

REFERENCES = (
    "A. M. Cherubini, G. Metafune and F. Paparella, "
    '"On the Stopping Time of a Bouncing Ball", Universita di Lecce'
)
UNITS_COMMENT = (
    "Dimensionless (units = '1'): lengths in units of the spring rest length L, "
    "times in units of sqrt(m/2k), velocities in L/sqrt(m/2k), energies in 2kL^2 "
    "(gamma = g m/(2 L k), mu = nu/sqrt(2 k m))."
)
#: codecs of :func:`write_netcdf` (netCDF4 encodings), measured by ``benchmarks/bench_cli.py --compression``
#: at 2e6 events (162 MB of float64): zlib level 4 + shuffle 75 MB at ~2,700 ns/event of CPU, zstd level 1 +
#: shuffle 127 MB at ~700 ns/event, none 162 MB at ~160 ns/event.  The event states are float64 with
#: full mantissas: no codec gains more than 2.2x.  "zlib" (the pipeline's default: small, thinned files)
#: and "none" (the CLI's default: keeps up with the solver) are read by every netCDF-4 reader (ncdump
#: included); "zstd" needs netCDF-C >= 4.9 with the HDF5 zstd filter plugin installed (Debian 12's ncdump cannot read it).
CODECS = {
    "zlib": {"zlib": True, "complevel": 4, "shuffle": True},
    "zstd": {"compression": "zstd", "complevel": 1, "shuffle": True},
    "none": {},
}
COMPRESSION = CODECS["zlib"]

# name -> (long_name, comment or None) of the per-event variables
EVENT_VARIABLES = {
    "t": ("time of the event",
          "correctly rounded sum of the exact durations tau of all phases up to the event (compensated "
          "sum): a phase shorter than half an ulp of t leaves t unchanged, so consecutive event times "
          "may coincide (late in very long runs, or at a chattering sticky onset) while tau stays exact"),
    "tau": ("duration of the phase (flight or sticky phase) ending at the event",
            "time since the previous event, or since t = 0 for the first one; exact, "
            "whereas differences of t are rounded"),
    "xdot": ("velocity of the lower mass just after the event", "the lower mass is at x = 0 at every event"),
    "y": ("height of the upper mass at the event",
          "y = y_eq + 2 eta, rounded to float64; late in the asymptotic regime y ~ 1 hides "
          "the deviations: use y_minus_yeq"),
    "y_minus_yeq": ("height of the upper mass above its static equilibrium y_eq = 1 - 2 gamma, at the event",
                    "computed as 2 eta (x = 0 at events): exact, without cancellation"),
    "ydot": ("velocity of the upper mass just after the event", None),
    "xidot": ("spring deformation rate xi' = (ydot - xdot)/2 just after the event",
              "state variable of the numerical core (with xdot and eta); the dense sampler restarts "
              "exactly from it"),
    "eta": ("spring deformation from its static value, eta = xi + gamma = (y - y_eq - x)/2, just after the event",
            "state variable of the numerical core (with xdot and xidot); the dense sampler restarts "
            "exactly from it"),
    "energy": ("total mechanical energy E just after the event", "E = E_m + energy_excess"),
    "energy_excess": ("mechanical energy above the static equilibrium, E - E_m, just after the event",
                      "E_m = -gamma^2/2; computed from the core state without cancellation"),
}

# name in the file -> (key of the sampler output, long_name)
SAMPLED_VARIABLES = {
    "sampled_x": ("x", "height of the lower mass"),
    "sampled_xdot": ("xdot", "velocity of the lower mass"),
    "sampled_y": ("y", "height of the upper mass"),
    "sampled_ydot": ("ydot", "velocity of the upper mass"),
    "sampled_y_minus_yeq": ("y_minus_yeq", "height of the upper mass above its static equilibrium y_eq = 1 - 2 gamma"),
}
_SAMPLED_COMMENT = "closed-form dense output at the times of coordinate 'time'; NaN after t_valid"

_REQUIRED_ATTRS = ("gamma", "mu", "x0", "xdot0", "xidot0", "eta0", "stop_reason", "t_end",
                   "max_events", "t_max", "energy_stop")


class DatasetError(ValueError):
    """A dataset that is not a bounce trajectory file (missing or inconsistent content)."""


# --------------------------------------------------------------------------- provenance

@functools.lru_cache(maxsize=None)
def git_info() -> tuple[str, str]:
    """``(commit, dirty)`` of the git checkout holding this package's source.

    ``commit`` is the ``git rev-parse HEAD`` hash, ``dirty`` is "true" if the
    package directory has uncommitted changes (untracked files included) and
    "false" otherwise; both are "unknown" when the package is not a tracked part
    of a git checkout (e.g. an installed wheel) or git is unavailable.
    """
    pkg_dir = Path(__file__).resolve().parent

    def git(*args: str) -> str:
        return subprocess.run(
            ["git", "-C", str(pkg_dir), *args], capture_output=True, text=True, timeout=20, check=True,
        ).stdout.strip()

    try:
        commit = git("rev-parse", "HEAD")
        git("ls-files", "--error-unmatch", "--", "__init__.py")  # the package itself is tracked here
        status = git("status", "--porcelain", "--untracked-files=normal", "--", ".")
    except (OSError, subprocess.SubprocessError):
        return "unknown", "unknown"
    return commit, ("true" if status else "false")


# --------------------------------------------------------------------------- Trajectory -> Dataset

def cf_variable(dims, data, long_name, comment=None, dtype=np.float64, **extra):
    """A dimensionless CF variable (units "1", long_name, optional comment and further attributes)."""
    attrs = {"long_name": long_name, "units": "1"}
    if comment:
        attrs["comment"] = comment
    attrs.update(extra)
    return xr.Variable(dims, np.asarray(data, dtype=dtype), attrs)


def _finite_1d(times) -> np.ndarray:
    times = np.asarray(times, dtype=np.float64)
    if times.ndim != 1:
        raise ValueError(f"sample_times must be one-dimensional, got shape {times.shape}")
    if not np.all(np.isfinite(times)):
        raise ValueError("sample_times must be finite")
    return times


def to_dataset(traj: Trajectory, sample_times=None) -> xr.Dataset:
    """The CF-1.10 dataset of a trajectory; with ``sample_times``, also x, y, velocities at those times.

    Event variables (dimension ``event``): t, tau, xdot, y, y_minus_yeq, ydot,
    xidot, eta, energy, energy_excess (float64) and kind (int8, CF flags
    impact/grazing/sticky_start/detach).  Sampled variables (dimension
    ``time``, a float64 coordinate): sampled_x, sampled_y, sampled_xdot,
    sampled_ydot, sampled_y_minus_yeq (NaN after ``t_valid``).  The global
    attributes hold everything :func:`from_dataset` needs to rebuild ``traj``.
    """
    params = traj.params
    event = ("event",)
    data_vars = {
        "t": cf_variable(event, traj.t, *EVENT_VARIABLES["t"]),
        "tau": cf_variable(event, traj.tau, *EVENT_VARIABLES["tau"]),
        "xdot": cf_variable(event, traj.xdot, *EVENT_VARIABLES["xdot"]),
        "y": cf_variable(event, traj.y, *EVENT_VARIABLES["y"]),
        "y_minus_yeq": cf_variable(event, traj.y_minus_yeq, *EVENT_VARIABLES["y_minus_yeq"]),
        "ydot": cf_variable(event, traj.ydot, *EVENT_VARIABLES["ydot"]),
        "xidot": cf_variable(event, traj.xidot, *EVENT_VARIABLES["xidot"]),
        "eta": cf_variable(event, traj.eta, *EVENT_VARIABLES["eta"]),
        "energy": cf_variable(event, traj.energy, *EVENT_VARIABLES["energy"]),
        "energy_excess": cf_variable(event, traj.energy_excess, *EVENT_VARIABLES["energy_excess"]),
        "kind": cf_variable(
            event, traj.kind, "kind of event",
            "impact: collision rule (psi' and xi' exchanged); grazing: tangential contact, "
            "nothing exchanged; sticky_start: the lower mass comes to rest on the floor; "
            "detach: it leaves the floor (floor force back to 0)",
            dtype=np.int8,
            flag_values=np.arange(len(KIND_NAMES), dtype=np.int8),
            flag_meanings=" ".join(KIND_NAMES),
        ),
    }
    coords = {}
    if sample_times is not None:
        times = _finite_1d(sample_times)
        samples = sample_trajectory(traj, times)
        samples["y"] = params.y_eq + samples["y_minus_yeq"]
        coords["time"] = cf_variable(("time",), times, "time of the samples")
        for name, (key, long_name) in SAMPLED_VARIABLES.items():
            data_vars[name] = cf_variable(("time",), samples[key], long_name, _SAMPLED_COMMENT)
    settings = traj.settings
    attrs = {
        **_run_attrs(traj.params, traj.initial, "Two-mass bouncing ball: event records of one simulation", (
            UNITS_COMMENT + " One record per event (impact, grazing, sticky_start, detach) strictly after "
            "t = 0 in time order, except a sticky phase beginning at t = 0, recorded as sticky_start at "
            "t = 0; x = 0 at every event and the state is the one just after it.  The records and the "
            "global attributes determine the motion exactly (bounce.io.sample_dataset)."
        )),
        "stop_reason": traj.stop_reason,
        "t_end": float(traj.t_end),
        "t_valid": float(traj.t_valid),
        "max_events": int(settings["max_events"]),
        "t_max": float(settings["t_max"]),
        "energy_stop": float(settings["energy_stop"]),
    }
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


def _run_attrs(params: Parameters, initial, title: str, comment: str) -> dict:
    """The global attributes of every simulation file: conventions, provenance, gamma, mu, the spring law
    (:meth:`bounce.springs.base.SpringLaw.attrs`), y_eq, E_m and the initial state."""
    dev = initial.deviations(params)
    state = initial if isinstance(initial, State) else dev.to_state(params)
    commit, dirty = git_info()
    return {
        "Conventions": "CF-1.10",
        "title": title,
        "source": f"bounce {__version__}",
        "references": REFERENCES,
        "comment": comment,
        "bounce_version": __version__,
        "git_commit": commit,
        "git_dirty": dirty,
        "gamma": params.gamma,
        "mu": params.mu,
        **params.spring.attrs(),
        "y_eq": params.y_eq,
        "energy_min": params.energy_min,
        "initial_form": "state" if isinstance(initial, State) else "deviations",
        "x0": state.x,
        "xdot0": state.xdot,
        "y0": state.y,
        "ydot0": state.ydot,
        "xidot0": dev.xidot,
        "eta0": dev.eta,
    }


def method_dataset(result, params: Parameters, initial, max_events: int, t_max: float) -> xr.Dataset:
    """The CF-1.10 dataset of a general-purpose method's run (:class:`bounce.methods.base.MethodResult`): its
    impacts as it sees them (dimension ``event``: t, xdot, and energy_excess where the method reports it),
    the law and the initial state as in :func:`to_dataset`, the method, its setting and how it stopped.  No
    CPU time (results carry none).  An approximation: the records do not determine the motion exactly."""
    event = ("event",)
    data_vars = {
        "t": cf_variable(event, result.t, "time of the impact (soft-contact methods: the start of the contact)"),
        "xdot": cf_variable(event, result.xdot, EVENT_VARIABLES["xdot"][0]),
    }
    excess = result.extra.get("energy_excess")
    if excess is not None and np.shape(excess) == np.shape(result.t):
        data_vars["energy_excess"] = cf_variable(event, excess, EVENT_VARIABLES["energy_excess"][0])
    attrs = {
        **_run_attrs(params, initial, "Two-mass bouncing ball: impacts of one run of a general-purpose method", (
            UNITS_COMMENT + " One record per impact the method reports (bounce.methods.base), in time order; "
            "an approximation of the exact dynamics, to the method's own accuracy.")),
        "method": result.method,
        "setting": json.dumps(result.setting, sort_keys=True, default=float),
        "failure": result.failure or "none",
        "failure_index": int(result.failure_index),
        "t_end": float(result.t_end),
        "max_events": int(max_events),
        "t_max": float(t_max),
    }
    return xr.Dataset(data_vars, attrs=attrs)


# --------------------------------------------------------------------------- Dataset -> Trajectory

def complete_prefix(ds: xr.Dataset) -> int:
    """How many leading event records of ``ds`` are the consecutive events 0, 1, ... of the simulation.

    Equal to the number of records unless the dataset was thinned (an ``event``
    coordinate holding the index of each kept event in the full simulation,
    e.g. ``ds.isel(event=...)`` of scenes that keep the first events and a
    log-spaced selection after them).  The motion is determined by the records
    only up to the last event of that prefix.
    """
    n = int(ds.sizes.get("event", 0))
    if "event" in ds.coords:
        ok = np.asarray(ds["event"].values) == np.arange(n)
        return n if ok.all() else int(np.argmin(ok))
    total = ds.attrs.get("n_events_simulated")
    if total is not None and int(total) != n:
        raise DatasetError(
            f"the dataset keeps {n} of {int(total)} events but has no 'event' coordinate telling which"
        )
    return n


def _trajectory(ds: xr.Dataset, n: int | None = None, check_t_valid: bool = True) -> Trajectory:
    """The Trajectory of the first ``n`` (default all) event records of ``ds``."""
    missing = [name for name in _REQUIRED_ATTRS if name not in ds.attrs]
    missing += [name for name in ("t", "tau", "xdot", "xidot", "eta", "energy_excess", "kind")
                if name not in ds.variables]
    if missing:
        raise DatasetError(f"not a bounce trajectory dataset: missing {', '.join(missing)}")
    a = ds.attrs
    params = Parameters(float(a["gamma"]), float(a["mu"]), spring_from_attrs(a))
    dev = Deviations(float(a["x0"]), float(a["xdot0"]), float(a["xidot0"]), float(a["eta0"]))
    form = str(a.get("initial_form", "deviations"))
    if form == "state":
        initial = State(float(a["x0"]), float(a["xdot0"]), float(a["y0"]), float(a["ydot0"]))
        if initial.deviations(params) != dev:
            raise DatasetError("inconsistent initial state: (x0, xdot0, y0, ydot0) does not give (xidot0, eta0)")
    elif form == "deviations":
        initial = dev
    else:
        raise DatasetError(f"initial_form must be 'state' or 'deviations', got {form!r}")

    def arr(name, dtype=np.float64):
        values = np.asarray(ds[name].values)
        if values.ndim != 1:
            raise DatasetError(f"variable {name!r} must be one-dimensional")
        return np.array(values[:n], dtype=dtype)  # a copy, independent of the dataset

    kind = arr("kind", np.int8)
    if kind.size and not (kind.min() >= 0 and kind.max() < len(KIND_NAMES)):
        raise DatasetError(f"kind must be in 0..{len(KIND_NAMES) - 1}")
    traj = Trajectory(
        params=params, initial=initial, t=arr("t"), tau=arr("tau"), xdot=arr("xdot"), xidot=arr("xidot"),
        eta=arr("eta"), energy_excess=arr("energy_excess"), kind=kind, stop_reason=str(a["stop_reason"]),
        t_end=float(a["t_end"]),
        settings={"max_events": int(a["max_events"]), "t_max": float(a["t_max"]),
                  "energy_stop": float(a["energy_stop"])},
    )
    if check_t_valid and "t_valid" in a and float(a["t_valid"]) != traj.t_valid:
        raise DatasetError(f"inconsistent t_valid: attribute {float(a['t_valid'])!r}, records give {traj.t_valid!r}")
    return traj


def from_dataset(ds: xr.Dataset) -> Trajectory:
    """Rebuild the :class:`~bounce.trajectory.Trajectory` stored in ``ds`` (exactly: same parameters,
    initial state and event arrays), e.g. for :func:`bounce.sampling.sample_trajectory`.

    Raises :class:`DatasetError` if ``ds`` is not a complete trajectory dataset
    (missing content, or thinned records: see :func:`complete_prefix`).
    """
    n = int(ds.sizes.get("event", 0))
    prefix = complete_prefix(ds)
    if prefix < n:
        raise DatasetError(
            f"the event records are thinned (record {prefix} is event {int(ds['event'].values[prefix])}): "
            f"the motion is determined only up to event {prefix - 1}; sample_dataset samples that part"
        )
    return _trajectory(ds)


def split_timings(ds: xr.Dataset) -> tuple[xr.Dataset, xr.Dataset]:
    """``(result, timings)``: the variables measured in seconds (CPU or wall time) go to ``timings``.

    Results must be byte-identical across reruns; timings never are.  The pipeline writes the two to
    separate files (``results/methods/<study>.nc`` and ``results/timing/methods/<study>-cpu.nc``).
    """
    timed = [name for name, var in ds.data_vars.items() if var.attrs.get("units") == "s"]
    timings = ds[timed]
    timings.attrs = {"title": f"timings of: {ds.attrs.get('title', '')}", "Conventions": "CF-1.10",
                     "comment": "CPU (process) or wall seconds on a shared machine: not reproducible by design"}
    return ds.drop_vars(timed), timings


def read_dataset(path) -> xr.Dataset:
    """Open a bounce netCDF file, load it into memory and close it."""
    with xr.open_dataset(path, engine="netcdf4") as ds:
        return ds.load()


def read_trajectory(path) -> Trajectory:
    """:func:`from_dataset` of the file at ``path``."""
    return from_dataset(read_dataset(path))


def sample_dataset(ds: xr.Dataset, times) -> dict:
    """x, xdot, y, y_minus_yeq, ydot at ``times`` from a trajectory dataset alone.

    Bit-for-bit equal to :func:`bounce.sampling.sample_trajectory` of the
    simulated trajectory (plus ``y = y_eq + y_minus_yeq``); NaN outside
    [0, t_valid].  For a thinned dataset (see :func:`complete_prefix`) the
    samples are exact up to the last event of the complete prefix and NaN after it.
    """
    n = int(ds.sizes.get("event", 0))
    prefix = complete_prefix(ds)
    if prefix == n:
        traj = _trajectory(ds)
        out = sample_trajectory(traj, times)
    else:
        traj = _trajectory(ds, prefix, check_t_valid=False)
        out = sample_trajectory(traj, times)
        limit = float(traj.t[-1]) if prefix else 0.0
        beyond = ~(np.asarray(times, dtype=np.float64) <= limit)
        for value in out.values():
            value[beyond] = np.nan
    out["y"] = traj.params.y_eq + out["y_minus_yeq"]
    return out


# --------------------------------------------------------------------------- writing

def _probe_writable(directory: Path) -> None:
    """Create and remove a file in ``directory``: the only reliable writability test (root, ACLs, ro mounts)."""
    probe = directory / f".bounce-probe-{os.getpid()}-{uuid.uuid4().hex}"
    fd = os.open(probe, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o600)
    os.close(fd)
    os.unlink(probe)


def check_output_path(path, suffix: str = "") -> Path:
    """Check that a file can be written at ``path``; return it as a Path.

    Only two kinds of target are accepted: a new name in an existing, writable
    directory, or an existing regular file (replaced atomically).  Raises
    FileNotFoundError (the directory does not exist), NotADirectoryError (its
    parent is not a directory), IsADirectoryError (``path`` is, or is spelled
    as, a directory: ``dir/``, ``dir/.``), FileExistsError (``path`` is a
    symbolic link, dangling or not, a FIFO, a device or a socket: replacing it
    by a regular file would destroy it, and a link would be replaced rather than
    its target), PermissionError (the directory is not writable) or OSError
    (the name, with ``suffix`` appended as a caller may do, e.g. a stream's
    ``.partial``, leaves no room for the temporary file's longer name within the
    file system's limit), each with a message naming the path.
    """
    text = os.fspath(path)
    path = Path(text)
    tail = os.path.basename(text.rstrip("/")) if text.endswith("/") else os.path.basename(text)
    spelled_as_directory = text.endswith("/") or tail in ("", ".", "..")
    if not spelled_as_directory:
        _check_name_length(path, suffix)
    if spelled_as_directory or path.is_dir():
        raise IsADirectoryError(f"output path {text!r} is a directory, not a file")
    parent = path.parent
    if not parent.exists():
        raise FileNotFoundError(f"output directory {str(parent)!r} does not exist")
    if not parent.is_dir():
        raise NotADirectoryError(f"output directory {str(parent)!r} is not a directory")
    try:
        mode = os.lstat(path).st_mode
    except FileNotFoundError:
        mode = None
    if mode is not None and not stat.S_ISREG(mode):
        what = "a symbolic link" if stat.S_ISLNK(mode) else "not a regular file (a FIFO, device or socket)"
        raise FileExistsError(
            f"output path {text!r} exists and is {what}: only a new file or an existing regular file is replaced"
        )
    try:
        _probe_writable(parent)
    except OSError as exc:
        raise PermissionError(
            f"output directory {str(parent)!r} is not writable ({exc.strerror or exc})"
        ) from None
    return path


def _check_name_length(path: Path, suffix: str) -> None:
    """The longest name written for ``path`` (its temporary file, after ``suffix``) fits the file system."""
    try:
        name_max = os.pathconf(path.parent, "PC_NAME_MAX")
        path_max = os.pathconf(path.parent, "PC_PATH_MAX")
    except (OSError, ValueError):  # the directory is missing (refused next), or the file system does not say
        name_max, path_max = 255, 4096
    longest = _tmp_path(Path(f"{path}{suffix}"))
    size = len(os.fsencode(path.name))
    extra = len(os.fsencode(longest.name)) - size
    if size + extra > name_max:
        raise OSError(
            f"output name {path.name!r} is {size} bytes long: at most {name_max - extra} bytes fit (allowed range: "
            f"[1, {name_max - extra}] bytes; the file system allows {name_max} per name and the temporary file "
            f"written next to it adds {extra})"
        )
    if len(os.fsencode(str(longest))) >= path_max:
        raise OSError(
            f"output path {str(path)!r} is too long: with its temporary file's name it exceeds the file system's "
            f"limit of {path_max - 1} bytes per path (allowed range: [1, {path_max - 1}] bytes)"
        )


#: temporary files are ``.NAME.<pid>.<12 hex>.bounce-tmp`` next to the target
_TMP_SUFFIX = ".bounce-tmp"


def _tmp_path(path: Path) -> Path:
    """A fresh temporary file name for ``path``: ``.NAME.<pid>.<12 hex>.bounce-tmp`` in its directory."""
    return path.parent / f".{path.name}.{os.getpid()}.{uuid.uuid4().hex[:12]}{_TMP_SUFFIX}"


def _tmp_pattern(path: Path) -> re.Pattern:
    return re.compile(re.escape(f".{path.name}.") + r"(\d+)\.[0-9a-f]{12}" + re.escape(_TMP_SUFFIX) + "$")


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # exists, owned by someone else
        return True
    return True


def remove_stale_temporaries(path) -> list[Path]:
    """Remove temporary files of earlier writes to ``path`` whose process is gone (killed by SIGKILL,
    power loss); a temporary of a live process (a concurrent write) is kept.  Returns those removed."""
    path = Path(path)
    pattern = _tmp_pattern(path)
    removed = []
    with contextlib.suppress(OSError):
        for entry in os.scandir(path.parent):
            match = pattern.match(entry.name)
            if match and entry.is_file(follow_symlinks=False) and not _pid_alive(int(match.group(1))):
                with contextlib.suppress(OSError):
                    os.unlink(entry.path)
                    removed.append(Path(entry.path))
    return removed


def _free_bytes(directory: Path) -> int:
    st = os.statvfs(directory)
    return st.f_bavail * st.f_frsize


def is_disk_full(directory: Path, exc: BaseException) -> bool:
    """Was the failure a full disk?  ENOSPC/EDQUOT, or a library error (netCDF reports the bare
    "NetCDF: HDF error") while the file system has (almost) no space left.  Asked while the failed
    file still takes its space (once it is removed, the space is free again)."""
    if isinstance(exc, OSError) and exc.errno in (errno.ENOSPC, errno.EDQUOT):
        return True
    if not isinstance(exc, (OSError, RuntimeError)):
        return False
    try:
        return _free_bytes(directory) < 1 << 20
    except OSError:
        return False


def disk_full_error(path: Path, kept: str) -> OSError:
    """The error of a write to ``path`` that failed on a full disk; ``kept`` says what is left."""
    return OSError(errno.ENOSPC, f"No space left on device (disk full) in {str(path.parent)!r} while writing "
                                 f"{str(path)!r}; {kept}")


#: the signals a write defers (:func:`signals_deferred`)
DEFERRED_SIGNALS = (signal.SIGINT, signal.SIGTERM)


@contextlib.contextmanager
def signals_deferred(cleanup=lambda: None):
    """SIGINT and SIGTERM arriving inside the block are recorded and act when it ends.

    xarray writes through netCDF4 holding a non-reentrant lock; the interpreter runs a signal's
    handler when the write's C call returns, in the lock's ``__exit__`` before it releases the lock,
    and the handler's exception (KeyboardInterrupt, the CLI's Terminated) then skips the release:
    xarray's ``finally: close()`` waits on that lock for ever (a futex, with the temporary file left).
    Here a signal only sets a flag; on leaving the block the previous handlers are restored and every
    signal received is raised again, so its handler runs outside any lock (KeyboardInterrupt, the
    CLI's handler, or the default action, which ends the process: ``cleanup()`` runs first then).
    A signal the process ignores stays ignored.  Python runs signal handlers in the main thread only,
    so in another thread the block defers nothing and nothing raises inside it.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    received: list[int] = []
    previous = {}
    for signum in DEFERRED_SIGNALS:
        handler = signal.getsignal(signum)
        if handler is not None and handler is not signal.SIG_IGN:  # None: set outside Python, not restorable
            previous[signum] = signal.signal(signum, lambda number, frame: received.append(number))
    try:
        yield
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)
        for signum in dict.fromkeys(received):
            if previous[signum] is signal.SIG_DFL:
                cleanup()
            signal.raise_signal(signum)


def _encoding(ds: xr.Dataset, compression: str = "zlib", chunksizes: tuple | None = None) -> dict:
    """float64 (or int8 flags) with the codec ``compression`` of :data:`CODECS`, no fill values."""
    codec = dict(CODECS[compression], **({} if chunksizes is None else {"chunksizes": chunksizes}))
    encoding = {}
    for name, var in ds.variables.items():
        if np.issubdtype(var.dtype, np.floating):
            encoding[name] = {"dtype": "float64", "_FillValue": None, **codec}
        elif np.issubdtype(var.dtype, np.integer):
            encoding[name] = {"dtype": var.dtype.name, "_FillValue": None, **codec}
    return encoding


def write_netcdf(ds: xr.Dataset, path, compression: str = "zlib", unlimited: str | None = None,
                 chunksize: int | None = None) -> Path:
    """Write ``ds`` to ``path`` atomically (netCDF4/HDF5, float64, codec ``compression``); return the path.

    The file is written to a temporary file ``.NAME.<pid>.<hex>.bounce-tmp`` in
    the same directory, flushed to disk and moved into place with
    ``os.replace``: readers see either the old file or the complete new one, and
    on any failure no temporary file is left behind.  SIGINT and SIGTERM wait
    until the temporary file is closed (:func:`signals_deferred`), then act: the
    temporary is removed, the old file kept.  A temporary left by a process
    killed outright (SIGKILL) is recognised by its name and dead pid and removed
    by the next write to the same target.  A full disk is reported as such
    (OSError ENOSPC, saying the old file is kept).  The target must pass
    :func:`check_output_path`.  ``unlimited``: a dimension left unlimited, its
    variables in chunks of ``chunksize`` elements (a file appended to later).
    """
    path = check_output_path(path)
    remove_stale_temporaries(path)
    tmp = _tmp_path(path)
    try:
        with signals_deferred(cleanup=lambda: _unlink(tmp)):
            ds.to_netcdf(tmp, mode="w", format="NETCDF4", engine="netcdf4",
                         encoding=_encoding(ds, compression, None if chunksize is None else (chunksize,)),
                         unlimited_dims=() if unlimited is None else (unlimited,))
            with open(tmp, "rb+") as fh:
                os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException as exc:
        full = is_disk_full(path.parent, exc)
        _unlink(tmp)
        if full:
            raise disk_full_error(path, "the old file is kept unchanged" if path.exists()
                                  else "no file was written") from exc
        raise
    with contextlib.suppress(OSError):  # persist the rename (best effort)
        dir_fd = os.open(path.parent, os.O_RDONLY)
        try:
            os.fsync(dir_fd)
        finally:
            os.close(dir_fd)
    return path


def _unlink(path: Path) -> None:
    with contextlib.suppress(OSError):
        os.unlink(path)

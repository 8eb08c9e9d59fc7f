"""The contract of a sweep: independent items, sharded, run on every core of a job, gathered.

A sweep module in ``bounce.sweeps`` defines ``SWEEP = Sweep(...)``:

* ``size(spec)``: how many items (grid cells, Monte-Carlo samples) the sweep has;
* ``prepare(spec, items)``: the per-item inputs of the items ``items`` (arrays over
  the items, e.g. their (mu, gamma) or their random initial state, drawn once for
  the whole sweep so that a sample does not depend on the sharding);
* ``compute(spec, inputs)``: the results of a batch of items, a dict of arrays.
  Arrays whose first dimension in ``variables`` is ``item`` hold one row per item;
  every other array is a count over the batch (a histogram) and is *added* when
  batches and shards are combined.  It runs in a worker process;
* ``finish(ds, spec)``: the gathered dataset -> the sweep's dataset (reshaped to its
  grid, pooled numbers);
* ``plot(ds, spec, outputs)``: the figure, from the gathered dataset alone;
* ``memory_mb(spec)``: the peak memory of one worker (the rules request workers x that).

An item's result depends on nothing but the spec and its index, so the gathered file is
the same bytes whatever the number of shards, workers or machines (checked in
tests/sweeps/test_sweeps.py and tests/pipeline/test_slurm.py).  The Snakemake rules
(``workflow/rules/sweeps.smk``) run one job per shard and one gather job.
"""

from __future__ import annotations

import math
import multiprocessing
import os
import sys
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass
from typing import Callable

import numpy as np
import xarray as xr

from .._version import __version__
from ..model import InputError

ITEM = "item"
#: environment of the worker processes: one BLAS thread each (the parallelism is over items), so a
#: result does not depend on how many workers ran it
WORKER_ENV = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1",
              "NUMBA_NUM_THREADS": "1"}
#: how worker processes start: fork on Linux (CPython then starts every worker before the pool's own thread, and a
#: worker inherits this process's BLAS set-up, the one the first batch ran with: the pipeline's sweep jobs run with
#: one BLAS thread, workflow/rules/sweeps.smk), spawn elsewhere (fork is unsafe on macOS)
START_METHOD = "fork" if sys.platform.startswith("linux") else "spawn"


@dataclass(frozen=True)
class Sweep:
    name: str
    title: str
    size: Callable[[dict], int]
    prepare: Callable[[dict, np.ndarray], dict]
    compute: Callable[[dict, dict], dict]
    variables: dict  # name -> (dims, long_name, units, comment or None)
    finish: Callable[[xr.Dataset, dict], xr.Dataset]
    plot: Callable[[xr.Dataset, dict, list], None]
    memory_mb: Callable[[dict], int]  # peak memory of one worker process, for the cluster's mem_mb


def shard_items(n_items: int, shard: int, shards: int) -> np.ndarray:
    """Item indices of shard ``shard`` (0-based) of ``shards``: every ``shards``-th item from ``shard`` on, sizes
    differing by at most 1.  Strided, not contiguous: the sweeps' items grow in cost along their grids (more grains,
    r nearer 1), and contiguous blocks left the last shard with most of the work (rigid-gas-collapse: 5.6 s against
    42.6 s of wall time in a whole pipeline run).  :func:`gather` puts the items back in order."""
    if not 1 <= shards <= n_items:
        raise InputError(f"shards must be in [1, {n_items}] (the number of items), got {shards}")
    if not 0 <= shard < shards:
        raise InputError(f"shard must be in [0, {shards - 1}], got {shard}")
    return np.arange(shard, n_items, shards, dtype=np.int64)


def _slice(inputs: dict, lo: int, hi: int) -> dict:
    return {k: v[lo:hi] for k, v in inputs.items()}


def combine(parts: list[dict], variables: dict) -> dict:
    """Per-item arrays concatenated in order, counts added (batches of a shard, shards of a sweep)."""
    out = {}
    for name, (dims, *_) in variables.items():
        arrays = [p[name] for p in parts]
        out[name] = np.concatenate(arrays) if dims[:1] == (ITEM,) else np.sum(arrays, axis=0)
    return out


def run_items(sweep: Sweep, spec: dict, items: np.ndarray, workers: int = 1, progress: bool | None = None) -> dict:
    """``sweep.compute`` over ``items`` on ``workers`` processes, in batches, with a progress bar.

    The first batch runs in this process (compiling numba's kernels, or loading them from the
    on-disk cache, once); with one worker so do all the others (no pool), with more they run in
    :data:`START_METHOD` worker processes: forked on Linux, so that a worker starts with this
    process's modules and compiled kernels (a spawned worker spent ~1 s of CPU importing and
    loading them, more than a shard of the contact Monte Carlo takes to compute), spawned
    elsewhere, with one BLAS thread each (:data:`WORKER_ENV`).  An item's numbers do not depend on
    which process ran it (tests/sweeps/test_sweeps.py).  ``progress``: a tqdm bar on stderr
    (default: when stderr is a terminal; in a log file it is redrawn every 30 s).
    """
    from tqdm import tqdm

    inputs = sweep.prepare(spec, items)
    n = len(items)
    batch = max(1, min(int(spec.get("batch", 64)), math.ceil(n / max(workers, 1))))
    bounds = [(lo, min(lo + batch, n)) for lo in range(0, n, batch)]
    tty = sys.stderr.isatty()
    bar = tqdm(total=n, desc=sweep.name, unit="item", file=sys.stderr, mininterval=0.5 if tty else 30.0,
               disable=(not tty) if progress is None else not progress)
    results: list = [None] * len(bounds)
    saved = {k: os.environ.get(k) for k in WORKER_ENV}
    os.environ.update(WORKER_ENV)  # inherited by spawned workers at start-up (forked ones keep this process's BLAS)
    try:
        # the first batch here: it fills numba's on-disk cache once, before the workers start and load it
        results[0] = sweep.compute(spec, _slice(inputs, *bounds[0]))
        bar.update(bounds[0][1] - bounds[0][0])
        if len(bounds) > 1 and workers <= 1:
            for i, (lo, hi) in enumerate(bounds[1:], start=1):
                results[i] = sweep.compute(spec, _slice(inputs, lo, hi))
                bar.update(hi - lo)
        elif len(bounds) > 1:
            with ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context(START_METHOD)) as pool:
                futures = {pool.submit(sweep.compute, spec, _slice(inputs, lo, hi)): i
                           for i, (lo, hi) in enumerate(bounds) if i > 0}
                for future in as_completed(futures):
                    i = futures[future]
                    results[i] = future.result()
                    bar.update(bounds[i][1] - bounds[i][0])
    finally:
        bar.close()
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v
    return combine(results, sweep.variables)


def to_dataset(sweep: Sweep, spec: dict, arrays: dict, items: np.ndarray, attrs: dict | None = None) -> xr.Dataset:
    """The shard dataset: the sweep's variables with their units and long names, the item index as coordinate."""
    data_vars = {}
    for name, (dims, long_name, units, comment) in sweep.variables.items():
        va = {"long_name": long_name, "units": units}
        if comment:
            va["comment"] = comment
        data_vars[name] = xr.Variable(dims, arrays[name], va)
    coords = {ITEM: xr.Variable((ITEM,), np.asarray(items, dtype=np.int64),
                                {"long_name": "index of the item in the whole sweep", "units": "1"})}
    from ..io import git_info

    commit, dirty = git_info()
    base = {"Conventions": "CF-1.10", "title": sweep.title, "source": f"bounce {__version__}",
            "git_commit": commit, "git_dirty": dirty, "sweep": sweep.name}
    return xr.Dataset(data_vars, coords=coords, attrs={**base, **(attrs or {})})


def run_shard(sweep: Sweep, spec: dict, shard: int, workers: int = 1, progress: bool | None = None) -> xr.Dataset:
    """The dataset of shard ``shard`` of ``spec['shards']``."""
    shards = int(spec["shards"])
    items = shard_items(sweep.size(spec), shard, shards)
    arrays = run_items(sweep, spec, items, workers, progress)
    return to_dataset(sweep, spec, arrays, items, {"shard": shard, "shards": shards})


def gather(sweep: Sweep, spec: dict, shards: list[xr.Dataset]) -> xr.Dataset:
    """Combine every shard (in any order) into the sweep's dataset; refuses missing or repeated items."""
    shards = sorted(shards, key=lambda ds: int(ds.attrs["shard"]))
    items = np.concatenate([ds[ITEM].values for ds in shards])
    n = sweep.size(spec)
    order = np.argsort(items, kind="stable")
    if not np.array_equal(items[order], np.arange(n)):
        raise InputError(f"sweep {sweep.name}: the shards do not hold items 0..{n - 1} exactly once")
    arrays = combine([{k: ds[k].values for k in sweep.variables} for ds in shards], sweep.variables)
    arrays = {k: v[order] if sweep.variables[k][0][:1] == (ITEM,) else v for k, v in arrays.items()}
    ds = to_dataset(sweep, spec, arrays, items[order])
    return sweep.finish(ds, spec)


# --------------------------------------------------------------------------- grids shared by the sweeps

def axis(spec: dict) -> np.ndarray:
    """A log-spaced axis {min, max, n} (n = 1: just min)."""
    n = int(spec["n"])
    return np.geomspace(float(spec["min"]), float(spec["max"]), n) if n > 1 else np.array([float(spec["min"])])


def log_edges(v: np.ndarray) -> np.ndarray:
    """Cell edges of a log-spaced axis: geometric midpoints, the ends mirrored (a decade wide if one value)."""
    if v.size == 1:
        return np.array([v[0] / 10**0.5, v[0] * 10**0.5])
    mid = np.sqrt(v[1:] * v[:-1])
    return np.concatenate([[v[0] ** 2 / mid[0]], mid, [v[-1] ** 2 / mid[-1]]])


def rn_grid(spec: dict) -> tuple[np.ndarray, np.ndarray, int]:
    """The gas sweeps' grid: restitutions ``r``, grain numbers ``n`` (a list, or a log axis {min, max, n} rounded to
    distinct integers) and ``samples`` random states per (r, n)."""
    n = spec["n"]
    ns = np.unique(np.rint(axis(n)).astype(np.int64)) if isinstance(n, dict) else np.asarray(n, dtype=np.int64)
    return np.asarray(spec["r"], dtype=float), ns, int(spec["samples"])


def rn_size(spec: dict) -> int:
    """Items of a sweep over (r, n, sample) (:func:`rn_grid`)."""
    r, ns, samples = rn_grid(spec)
    return r.size * ns.size * samples


def rn_prepare(spec: dict, items: np.ndarray) -> dict:
    """(r, n) of each item of a sweep over (r, n, sample), in C order: item k = (i n_n + j) samples + s."""
    r, ns, samples = rn_grid(spec)
    items = np.asarray(items, dtype=np.int64)
    i, j, _ = np.unravel_index(items, (r.size, ns.size, samples))
    return {"r": r[i], "n": ns[j], "item": items}

"""bounce.sweeps.rigid_gas_collapse: the collapse fraction, N_c(r) from it, and the runs' outcomes."""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr

from bounce.analysis.gas_rings import CAP, COLLAPSE, COOLED, ring_points, run_rigid_ring
from bounce.sweeps.rigid_gas_collapse import SWEEP, threshold


def run_one(r, n, rng, cooling, check_every, max_collisions):
    return run_rigid_ring(r, *ring_points(n, rng), cooling, check_every, max_collisions)

SPEC = {"r": [0.5, 0.8], "n": {"min": 4, "max": 48, "n": 9}, "samples": 4, "seed": 24, "cooling": 1e-16,
        "check_every": 50, "max_collisions": 20000, "bootstrap": 50}


def test_threshold_interpolates_in_log_n():
    ns = np.array([10, 20, 40])
    assert threshold(np.array([0.0, 0.5, 1.0]), ns) == pytest.approx(20.0)
    assert threshold(np.array([0.0, 0.0, 1.0]), ns) == pytest.approx(math.sqrt(20 * 40))
    assert threshold(np.array([0.0, 0.25, 0.75]), ns) == pytest.approx(math.exp(0.5 * (math.log(20) + math.log(40))))
    assert math.isnan(threshold(np.array([0.0, 0.0, 0.25]), ns))  # never reaches 1/2
    assert math.isnan(threshold(np.array([0.75, 1.0, 1.0]), ns))  # already above at the first point


def test_a_few_grains_cool_and_many_collapse():
    """r = 0.5: five points cool without collapsing (n < N_c ~ 9), forty collapse, each within its bounds."""
    few = run_one(0.5, 5, np.random.default_rng([24, 0]), 1e-16, 50, 20000)
    many = run_one(0.5, 40, np.random.default_rng([24, 1]), 1e-16, 50, 20000)
    assert few[0] == COOLED and many[0] == COLLAPSE, (few, many)
    assert run_one(0.5, 5, np.random.default_rng([24, 0]), 1e-16, 50, 1)[0] == CAP  # one collision per grain: cut


def test_items_do_not_depend_on_the_batches():
    items = np.arange(SWEEP.size(SPEC))
    whole = SWEEP.compute(SPEC, SWEEP.prepare(SPEC, items))
    parts = [SWEEP.compute(SPEC, SWEEP.prepare(SPEC, chunk)) for chunk in np.array_split(items, 3)]
    for name in whole:
        assert np.array_equal(whole[name], np.concatenate([p[name] for p in parts])), name


def test_finish_gives_a_sharp_threshold_with_its_error():
    items = np.arange(SWEEP.size(SPEC))
    out = SWEEP.compute(SPEC, SWEEP.prepare(SPEC, items))
    ds = SWEEP.finish(xr.Dataset({k: (("item",), v) for k, v in out.items()}), SPEC)
    p = ds["p_collapse"].values
    assert np.all(p[:, 0] == 0.0) and np.all(p[:, -1] == 1.0)
    n_c, err = ds["n_c"].values, ds["n_c_err"].values
    assert np.all(np.isfinite(n_c)) and np.all(err > 0.0)
    assert n_c[1] > n_c[0]  # more grains are needed as r -> 1
    # the error is at least the grid's resolution: the bracketing cell's width in log n / sqrt(12)
    ns = ds["n"].values
    assert np.all(err / n_c >= np.log(ns[1:] / ns[:-1]).min() / math.sqrt(12.0) * (1 - 1e-12))

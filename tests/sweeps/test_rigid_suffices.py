"""bounce.sweeps.rigid_suffices and its helpers in bounce.analysis.gas_rings: dimer collisions merged from their
micro-impacts, partner sequences grain by grain, the parting times, the sweep's twin and its file."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bounce.analysis.gas_rings import contacts, dimer_state, merge_contacts, mu_of_restitution, parting, ring_points
from bounce.analysis.theory import T_xi
from bounce.gas.model import GasParameters
from bounce.gas.simulate import GasRun
from bounce.sweeps.base import to_dataset
from bounce.sweeps.rigid_suffices import SWEEP, first_unresolved, one, temperature_parting

SPEC = {"r": [0.95], "n": [12], "samples": 2, "seed": 28, "speed": 0.01, "horizon": 60.0,
        "time": {"min": 0.1, "points": 10}, "temperature_rtol": 0.1, "max_collisions": 2000}


def test_an_isolated_dimer_collision_is_two_micro_impacts_t_xi_apart_merged_into_one():
    r = 0.8
    mu = mu_of_restitution(r)
    run = GasRun(GasParameters(2, "ring", 0.0, mu, ell=400.0), dimer_state(np.array([0.0, 0.5]),
                                                                        np.array([0.005, -0.005])), 200.0, 0)
    t, slot = contacts(run, 100)
    assert t.size == 2 and np.array_equal(slot, [0, 0]) and t[1] - t[0] == pytest.approx(T_xi(mu), rel=1e-2)
    mt, ms = merge_contacts(t, slot, 2.0 * T_xi(mu))
    assert np.array_equal(mt, t[:1]) and np.array_equal(ms, [0])
    psidot = run.final()["xdot"] + run.final()["xidot"]
    assert psidot[1] - psidot[0] == pytest.approx(r * 0.01, rel=1e-9)  # the rigid restitution, exactly


def test_parting_is_grain_by_grain():
    rigid = (np.array([1.0, 2.0, 3.0]), np.array([0, 2, 1]))  # 4 grains: slots (0,1), (2,3), (1,2)
    assert parting(rigid, rigid, 4) == (math.inf, -1)
    swapped = (np.array([1.0, 1.9, 3.5]), np.array([2, 0, 1]))  # far-apart collisions in the other order, lagged
    assert parting(rigid, swapped, 4) == (math.inf, -1)
    other = (np.array([1.0, 2.0, 3.0]), np.array([0, 2, 3]))  # the third collision with another partner
    assert parting(rigid, other, 4)[0] == 3.0
    missing = (rigid[0][:2], rigid[1][:2])
    assert parting(rigid, missing, 4)[0] == 3.0
    assert first_unresolved(np.array([1.0, 2.0, 2.5]), np.array([0, 2, 1]), 4, 1.0) == 2.5
    assert first_unresolved(*rigid, 4, 0.5) == math.inf


def test_temperatures_part_for_good_not_at_a_dip():
    grid = np.arange(1.0, 7.0)
    assert temperature_parting(np.array([1.0, 0.8, 1.0, 1.05, 1.3, np.nan]), grid, 0.1) == 5.0
    assert temperature_parting(np.array([1.0, 0.8, 1.0, 1.05, 1.0, 1.0]), grid, 0.1) == math.inf
    assert temperature_parting(np.full(6, 2.0), grid, 0.1) == 1.0


def test_the_twin_starts_together_and_the_sweep_writes_its_map():
    x, v = ring_points(12, np.random.default_rng([28, 0]), 0.01)
    out = one(SPEC, 0.95, x, v)
    assert np.all(np.diff(out["T_rigid"]) <= 1e-12) and out["T_rigid"][0] <= 1.0 + 1e-12  # rigid points only cool
    assert 0.0 < out["t_seq"] <= out["rigid_t_end"] and out["collisions_seq"] > 0
    assert out["t_seq"] < out["t_temp"]
    items = np.arange(SWEEP.size(SPEC))
    arrays = SWEEP.compute(SPEC, SWEEP.prepare(SPEC, items))
    ds = SWEEP.finish(to_dataset(SWEEP, SPEC, arrays, items), SPEC)
    assert ds["t_seq"].dims == ("r", "n", "sample") and ds["T_dimer"].dims == ("r", "n", "sample", "time")
    assert np.array_equal(ds["t_seq"].values[0, 0, 0], out["t_seq"])
    for var in ds.variables.values():
        assert "units" in var.attrs and "long_name" in var.attrs, var.name

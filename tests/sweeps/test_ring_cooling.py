"""bounce.sweeps.ring_cooling and its helpers in bounce.analysis.gas_rings: states at given times, the initial rate."""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr

from bounce.analysis.gas_rings import collision_rate, ring_points, states_at
from bounce.gas.model import RigidParameters, RigidState
from bounce.gas.simulate import GasRun
from bounce.sweeps.base import to_dataset
from bounce.sweeps.ring_cooling import SWEEP

SPEC = {"r": [0.5, 0.95], "n": 40, "samples": 2, "seed": 26, "speed": 0.01, "t_c": 3.14,
        "time": {"min": 1.0, "max": 2.0e4, "n": 25}, "worldlines": {"t_max": 1.0e4, "points": 60, "every": 2}}


def test_collision_rate_is_the_pair_sum_and_tends_to_haffs():
    v = np.random.default_rng(1).standard_normal(7)
    brute = 2.0 * sum(abs(a - b) for i, a in enumerate(v) for b in v[i + 1:]) / (7 * 3.0)
    assert collision_rate(v, 3.0) == pytest.approx(brute, rel=1e-14)
    _, w = ring_points(20000, np.random.default_rng(2), 0.01)
    assert collision_rate(w, 20000.0) == pytest.approx(2.0 * 0.01 / math.sqrt(math.pi), rel=0.02)


def rigid_run(r, n=30, t_max=5e4):
    x, v = ring_points(n, np.random.default_rng([26, 0]), 0.01)
    return GasRun(RigidParameters(n, "ring", 0.0, r, ell=float(n), size=0.0), RigidState(x, v), t_max, 0)


def test_states_at_do_not_depend_on_the_chunk_and_end_at_a_collapse():
    times = np.geomspace(1.0, 5e4, 30)
    a, ea = states_at(rigid_run(0.5), times, 30)
    b, eb = states_at(rigid_run(0.5), times, 7)
    assert np.array_equal(ea, eb) and all(np.array_equal(a[k], b[k], equal_nan=True) for k in a)
    run = rigid_run(0.5)
    states_at(run, times, 30)
    assert run.stop == "collapse"  # 30 points at r = 0.5 (N_c(0.5) ~ 9)
    after = times > run.t_end
    assert after.any() and np.isnan(a["xdot"][after]).all() and (ea[after] == -1).all()
    assert np.isfinite(a["xdot"][~after]).all() and np.all(np.diff(ea[~after]) >= 0)


def test_a_state_at_a_time_is_the_free_motion_after_the_last_event_before_it():
    run = rigid_run(0.9)
    t = 3000.0
    s, e = states_at(run, np.array([t]), 30)
    direct = rigid_run(0.9)
    direct.step(int(e[0]))
    f = direct.final()
    assert np.array_equal(s["xdot"][0], f["xdot"])
    assert np.allclose(s["x"][0], f["x"] + f["xdot"] * (t - direct.t_end), rtol=0, atol=1e-12)
    direct.step(1)
    assert direct.t_end > t  # the next event is after t


def test_sweep_rigid_collapses_tc_and_dimers_reach_past_it():
    out = SWEEP.compute(SPEC, SWEEP.prepare(SPEC, np.arange(SWEEP.size(SPEC))))
    ds = SWEEP.finish(to_dataset(SWEEP, SPEC, out, np.arange(SWEEP.size(SPEC))), SPEC)
    names = ds.attrs["stop_names"].split()
    rigid = np.array([[names[k] for k in row] for row in ds["stop_rigid"].values])
    assert (rigid[0] == "collapse").all() and (rigid[1] == "t_max").all()  # 40 points: above N_c(0.5), below N_c(0.95)
    assert all(names[k] == "t_max" for k in ds["stop_tc"].values.ravel())
    assert np.all(ds["t_end_dimer"].values[0] > ds["t_end_rigid"].values[0])
    T = ds["T_rigid"].values[1] / ds["T0"].values[1][:, None]
    assert T[:, 0] == pytest.approx(1.0, abs=1e-2) and np.all(np.diff(T, axis=1) <= 0)  # cooling, never warming
    assert np.all(ds["dimer_internal"].values[1] >= 0) and np.all(ds["worldline_dimer"].values[1] >= 0)
    assert np.all(ds["worldline_dimer"].values[1] < SPEC["n"])
    for var in ds.variables.values():
        assert "units" in var.attrs and "long_name" in var.attrs, var.name


def test_figure_from_the_dataset_alone(tmp_path):
    spec = dict(SPEC, r=[0.5], time={"min": 1.0, "max": 2000.0, "n": 5}, worldlines={"t_max": 2000.0, "points": 5,
                                                                                       "every": 10})
    out = SWEEP.compute(spec, SWEEP.prepare(spec, np.arange(SWEEP.size(spec))))
    ds = SWEEP.finish(to_dataset(SWEEP, spec, out, np.arange(SWEEP.size(spec))), spec)
    path = tmp_path / "ds.nc"
    ds.to_netcdf(path)
    SWEEP.plot(xr.open_dataset(path), {}, [tmp_path / "fig.png"])
    assert (tmp_path / "fig.png").stat().st_size > 1000

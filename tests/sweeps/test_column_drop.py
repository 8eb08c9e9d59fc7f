"""bounce.sweeps.column_drop: the column's minimum energy, the drop, and dimers at rest where rigid rods collapse."""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr

from bounce.gas import GasParameters
from bounce.gas.common import STOP_COLLAPSE, STOP_EVENTS
from bounce.gas.simulate import energy_excess
from bounce.sweeps.column_drop import SWEEP, drop_heights, rest_energy, run_dimers

SPEC = {"r": [0.9], "n": [1, 3], "samples": 2, "seed": 26, "gamma": 0.001, "height": 1.0, "gap": 1.0, "rest": 0.03,
        "max_events": 100000}


def _column_energy(n: int, gamma: float, xi: np.ndarray) -> float:
    """sum of E - E_m of a column at rest with every contact closed and springs xi (x_0 = 0, x_{k+1} = y_k)."""
    x = np.arange(n) + 2.0 * np.concatenate([[0.0], np.cumsum(xi)[:-1]])
    zero = np.zeros(n)
    return float(energy_excess(GasParameters(n, "column", gamma, 0.0),
                               {"xdot": zero, "xidot": zero, "eta": xi + gamma, "x": x}).sum())


@pytest.mark.parametrize("n", [1, 2, 5])
def test_rest_energy_is_the_least_energy_of_the_closed_column(n):
    """The springs xi_k = -gamma (2 (n - k) - 1) are the stationary point: any change of the springs raises the
    energy by its square (the energy is a convex quadratic in them); n = 1 is the single ball's E_m (0 here)."""
    gamma = 0.01
    xi = -gamma * (2.0 * (n - np.arange(n)) - 1.0)
    e = rest_energy(n, gamma)
    assert e == pytest.approx(_column_energy(n, gamma, xi), abs=1e-15)
    rng = np.random.default_rng(1)
    for _ in range(5):
        d = 1e-3 * rng.standard_normal(n)
        assert _column_energy(n, gamma, xi + d) - e == pytest.approx(0.5 * float(d @ d), rel=1e-6)
    if n == 1:
        assert e == pytest.approx(0.0, abs=1e-18)


def test_drop_leaves_gaps_below_the_bound():
    x = drop_heights(6, 2.0, 0.5, np.random.default_rng(0))
    gaps = np.diff(x) - 1.0  # rods of length 1: y_k = x_k + 1
    assert x[0] == 2.0 and np.all(gaps >= 0.0) and np.all(gaps < 0.5)


def test_dimer_energy_fraction_is_read_at_every_event():
    """The time to rest is the first event at or below the threshold: the run cut one event earlier is above it,
    not at rest, with no more impacts."""
    x = drop_heights(3, 1.0, 1.0, np.random.default_rng(2))
    mu = 0.03
    a = run_dimers(3, 0.001, mu, x, 0.03, 100000)
    assert a["dimer_rested"] == 1 and a["dimer_stop"] == STOP_EVENTS and a["dimer_energy"] <= 0.03
    b = run_dimers(3, 0.001, mu, x, 0.03, a["dimer_events"] - 1)  # one event short of rest
    assert b["dimer_rested"] == 0 and b["dimer_energy"] > 0.03 and b["dimer_impacts"] <= a["dimer_impacts"]
    assert math.isnan(b["dimer_t_rest"])


def test_dimer_column_rests_where_the_rigid_column_collapses():
    out = SWEEP.compute(SPEC, SWEEP.prepare(SPEC, np.arange(SWEEP.size(SPEC))))
    ds = SWEEP.finish(xr.Dataset({k: (("item",), v) for k, v in out.items()}), SPEC)
    assert ds["dimer_rested"].shape == (1, 2, 2)
    assert np.all(ds["dimer_rested"].values == 1) and np.all(ds["dimer_stop"].values == STOP_EVENTS)
    assert np.all(ds["dimer_t_rest"].values > 0.0) and np.all(ds["dimer_min_interval"].values > 0.0)
    assert np.all(ds["rigid_stop"].values == STOP_COLLAPSE) and np.all(ds["rigid_low"].values == 0)
    v0 = math.sqrt(2.0 * 0.001)
    assert ds["rigid_t_end"].values[0, 0] == pytest.approx(v0 / 0.001 * 1.9 / 0.1, rel=1e-12)  # one ball
    assert np.all(ds["rigid_t_end"].values[0, 1] < ds["rigid_t_end"].values[0, 0])  # three: sooner
    assert ds["e_min"].values[0] == 0.0 and ds["e_min"].values[1] == pytest.approx(rest_energy(3, 0.001))

"""bounce.sweeps.dimer_gas_collapse and bounce.analysis.gas_rings: the dimer twin of a rigid ring."""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr

from bounce.analysis.gas_rings import dimer_state, mu_of_restitution, ring_points
from bounce.analysis.theory import rest_coefficient_function_of_mu
from bounce.sweeps.dimer_gas_collapse import SWEEP

SPEC = {"r": [0.5], "n": [60], "samples": 2, "seed": 25, "speed": 0.01, "collisions": 200, "cooling": 1e-16,
        "check_every": 50, "max_collisions": 20000}


@pytest.mark.parametrize("r", [0.1, 0.5, 0.8, 0.95, 0.999])
def test_mu_of_restitution_inverts_eq_rest_coefficient(r):
    mu = mu_of_restitution(r)
    assert rest_coefficient_function_of_mu(mu) == pytest.approx(r, rel=1e-14)
    assert rest_coefficient_function_of_mu(math.nextafter(mu, 0.0)) >= r >= rest_coefficient_function_of_mu(
        math.nextafter(mu, 1.0))


def test_dimers_sit_on_the_ring_as_rods_of_length_one():
    x, v = ring_points(50, np.random.default_rng(3), 0.01)
    s = dimer_state(x, v)
    lower, upper = s.psi - s.xi, s.psi + s.xi + 1.0  # eq. xi-psi: x = psi - xi, y = psi + xi + 1
    assert np.all(upper[:-1] < lower[1:]) and upper[-1] < lower[0] + 100.0  # ordered, the seam on a ring of 2n
    assert np.array_equal(s.psidot, v) and not s.xi.any() and not s.xidot.any()
    assert abs(v.mean()) < 1e-17 and v.std() == pytest.approx(0.01, rel=0.3)


def test_where_the_rigid_twin_collapses_the_dimers_go_on():
    out = SWEEP.compute(SPEC, SWEEP.prepare(SPEC, np.arange(SWEEP.size(SPEC))))
    ds = SWEEP.finish(xr.Dataset({k: (("item",), v) for k, v in out.items()}), SPEC)
    assert np.all(ds["rigid_outcome"].values == 0)  # 60 points at r = 0.5 collapse (N_c(0.5) ~ 9)
    assert np.all(ds["dimer_stop"].values == 0) and np.all(ds["dimer_collisions"].values == 200.0)
    assert np.all(ds["dimer_t_end"].values > ds["rigid_t_end"].values)
    assert np.all(np.isfinite(ds["dimer_rate_late"].values))

"""bounce.checks.gas_collapse: its claims flip when the data say otherwise (the falsifiers)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
import xarray as xr

from bounce.checks import gas_collapse as G
from bounce.checks.base import NOT_CHECKABLE, NOT_REPRODUCED, REPRODUCED

SPEC = {"scaling_r_min": 0.8, "sigmas": 3.0, "threshold_rtol": 0.02}
R = np.array([0.5, 0.7, 0.8, 0.85, 0.9, 0.95, 0.97, 0.98, 0.99])


def sweep_like(n_c, rel_err=0.05, p=None):
    """A gathered rigid-gas-collapse dataset with these N_c (errors rel_err N_c) and collapse fractions p."""
    p = np.tile([0.0, 0.5, 1.0], (R.size, 1)) if p is None else p
    ds = xr.Dataset({"n_c": ("r", n_c), "n_c_err": ("r", rel_err * n_c), "p_collapse": (("r", "n"), p)},
                    coords={"r": R, "n": [4, 64, 1024]})
    ds.attrs.update(samples=16, sweep="rigid-gas-collapse")
    return ds


def dimers_like(stop=0, dimer_t=10.0, dimer_collisions=2000.0, outcome=0):
    """A gathered dimer-gas-collapse dataset of two states whose rigid twins collapsed at t = 5 after 500
    collisions per grain."""
    shape = (1, 1, 2)
    full = lambda v: np.full(shape, v)  # noqa: E731
    ds = xr.Dataset({"rigid_outcome": (("r", "n", "sample"), full(outcome).astype(np.int8)),
                     "rigid_t_end": (("r", "n", "sample"), full(5.0)), "rigid_collisions": (("r", "n", "sample"), full(500.0)),
                     "dimer_stop": (("r", "n", "sample"), np.array([[[0, stop]]], dtype=np.int8)),
                     "dimer_t_end": (("r", "n", "sample"), np.array([[[10.0, dimer_t]]])),
                     "dimer_collisions": (("r", "n", "sample"), np.array([[[2000.0, dimer_collisions]]])),
                     "dimer_rate_early": (("r", "n", "sample"), full(1.0)), "dimer_rate_late": (("r", "n", "sample"), full(50.0))},
                    coords={"r": [0.8], "n": [300], "sample": [0, 1]})
    ds.attrs.update(sweep="dimer-gas-collapse", collisions=2000)
    return ds


@pytest.mark.parametrize("beta", [1.0, 0.0, 2.0])
def test_fit_recovers_the_exponent(beta):
    n_c = 5.0 / (1.0 - R) * np.log(1.0 / (1.0 - R)) ** beta
    b, b_err, c, points = G.fit_scaling(R, n_c, 0.05 * n_c)
    assert b == pytest.approx(beta, abs=1e-9) and c == pytest.approx(5.0) and points == R.size


@pytest.mark.parametrize("beta, verdict", [(1.0, REPRODUCED), (0.0, NOT_REPRODUCED), (2.0, NOT_REPRODUCED)])
def test_scaling_claim_flips_with_the_law(beta, verdict):
    """McNamara and Young's ln(1/(1-r))/(1-r) passes; the plain 1/(1-r) law (beta = 0) or a squared log fails."""
    rng = np.random.default_rng(1)
    n_c = 5.0 / (1.0 - R) * np.log(1.0 / (1.0 - R)) ** beta * np.exp(0.05 * rng.standard_normal(R.size))
    m = G.measure(SPEC, [sweep_like(n_c)])
    assert G.collapse_number_scaling(m, SPEC).verdict == verdict


def test_scaling_claim_not_checkable_with_too_few_points():
    n_c = np.where(R >= 0.98, 100.0, np.nan)  # two values of r: no fit of two parameters with an error
    m = G.measure(SPEC, [sweep_like(n_c)])
    assert G.collapse_number_scaling(m, SPEC).verdict == NOT_CHECKABLE


def test_many_grains_claim_flips_when_the_fewest_collapse_or_the_most_do_not():
    n_c = 5.0 / (1.0 - R)
    assert G.collapse_needs_many_grains(G.measure(SPEC, [sweep_like(n_c)]), SPEC).verdict == REPRODUCED
    p = np.tile([0.0, 0.5, 1.0], (R.size, 1))
    p[3, 0] = 0.25  # a state of the fewest grains collapsed
    assert G.collapse_needs_many_grains(G.measure(SPEC, [sweep_like(n_c, p=p)]), SPEC).verdict == NOT_REPRODUCED
    p = np.tile([0.0, 0.5, 0.75], (R.size, 1))  # not every state of the most grains collapsed
    assert G.collapse_needs_many_grains(G.measure(SPEC, [sweep_like(n_c, p=p)]), SPEC).verdict == NOT_REPRODUCED


def test_three_points_switch_at_r_c():
    assert G.three_points(0.97 * G.R_C) and not G.three_points(1.03 * G.R_C)
    m = SimpleNamespace()
    assert G.three_point_threshold(m, SPEC).verdict == REPRODUCED
    assert G.three_point_threshold(m, dict(SPEC, threshold_rtol=1e-6)).verdict == NOT_REPRODUCED


@pytest.mark.parametrize("changes, verdict", [
    ({}, REPRODUCED),
    ({"stop": 3}, NOT_REPRODUCED),  # an engine stop (overlap) in one dimer run
    ({"dimer_t": 4.0}, NOT_REPRODUCED),  # its time did not pass the twin's collapse
    ({"dimer_collisions": 400.0}, NOT_REPRODUCED),  # fewer collisions per grain than the twin made
    ({"outcome": 1}, NOT_CHECKABLE),  # no rigid twin collapsed: nothing to compare with
])
def test_dimer_claim_flips_when_the_dimers_stop_or_fall_short(changes, verdict):
    n_c = 5.0 / (1.0 - R)
    m = G.measure(SPEC, [sweep_like(n_c), dimers_like(**changes)])
    assert G.dimer_gas_no_collapse(m, SPEC).verdict == verdict

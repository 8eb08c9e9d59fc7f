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
    ({"stop": 5}, NOT_REPRODUCED),  # a collapse stop
    ({"stop": 4}, REPRODUCED),  # a sticky pair contact past the twin's collapse: the engine's limit, not a failure
    ({"stop": 4, "dimer_t": 4.0}, NOT_REPRODUCED),  # ... but before the twin's collapse it does not show the claim
    ({"dimer_t": 4.0}, NOT_REPRODUCED),  # its time did not pass the twin's collapse
    ({"dimer_collisions": 400.0}, NOT_REPRODUCED),  # fewer collisions per grain than the twin made
    ({"outcome": 1}, NOT_CHECKABLE),  # no rigid twin collapsed: nothing to compare with
])
def test_dimer_claim_flips_when_the_dimers_stop_or_fall_short(changes, verdict):
    n_c = 5.0 / (1.0 - R)
    m = G.measure(SPEC, [sweep_like(n_c), dimers_like(**changes)])
    assert G.dimer_gas_no_collapse(m, SPEC).verdict == verdict


SPEC_COOLING = dict(SPEC, haff_r_min=0.95, haff_window=[0.1, 4.0])
TIMES = np.geomspace(1.0, 1e5, 41)
NAMES = "max_events t_max no_more_events overlap sticky collapse root_finder_failed cooled_below_rounding"


def cooling_like(law=-2.0, t0_factor=1.0, dimer_stop="t_max", dimer_t_end=1e5, dimer_warms=False, tc_stop="t_max"):
    """A gathered ring-cooling dataset: r = 0.8 (rigid points collapse at t = 1e4) and 0.95 (they cool), 8 states
    each with T_rigid = T0 (1 + t/t0)^law times a scatter of 2 % per state (t0 of the state, recorded as t0_factor
    x t0); the dimers cool as t^-1 to dimer_t_end (or warm after the rigid collapse)."""
    rng = np.random.default_rng(3)
    shape = (2, 8)
    t0 = 1000.0 * np.exp(0.1 * rng.standard_normal(shape))
    T0 = np.full(shape, 1e-4)
    tau = TIMES / t0[..., None]
    rigid = T0[..., None] * (1.0 + tau) ** law * np.exp(0.02 * rng.standard_normal(shape + (1,)) * np.log1p(tau))
    t_end_rigid = np.where(np.arange(2)[:, None] == 0, 1e4, 1e5) * np.ones(shape)
    rigid[0][:, TIMES > 1e4] = np.nan
    dimer = T0[..., None] / (1.0 + TIMES / 1000.0)
    if dimer_warms:
        dimer[..., TIMES > 1e4] *= 1e3
    dimer[..., TIMES > dimer_t_end] = np.nan
    code = NAMES.split().index
    ds = xr.Dataset({"T0": (("r", "sample"), T0), "t0": (("r", "sample"), t0_factor * t0),
                     "T_rigid": (("r", "sample", "time"), rigid), "T_dimer": (("r", "sample", "time"), dimer),
                     "T_tc": (("r", "sample", "time"), T0[..., None] * (1.0 + tau) ** -1.5),
                     "stop_rigid": (("r", "sample"), np.where(np.arange(2)[:, None] == 0, code("collapse"),
                                                              code("t_max")) * np.ones(shape, dtype=np.int8)),
                     "t_end_rigid": (("r", "sample"), t_end_rigid),
                     "stop_dimer": (("r", "sample"), np.full(shape, code(dimer_stop), dtype=np.int8)),
                     "t_end_dimer": (("r", "sample"), np.full(shape, dimer_t_end)),
                     "stop_tc": (("r", "sample"), np.array([[code(tc_stop)] + [code("t_max")] * 7] * 2, dtype=np.int8)),
                     "t_end_tc": (("r", "sample"), np.full(shape, 1e5))},
                    coords={"r": [0.8, 0.95], "sample": np.arange(8), "time": TIMES})
    ds.attrs.update(sweep="ring-cooling", n=100, t_c=3.14, horizon=1e5, stop_names=NAMES)
    return ds


def cooling_measure(**changes):
    return G.measure(SPEC_COOLING, [sweep_like(5.0 / (1.0 - R)), cooling_like(**changes)])


@pytest.mark.parametrize("changes, verdict", [
    ({}, REPRODUCED),
    ({"law": -1.0}, NOT_REPRODUCED),  # the wrong law: T ~ 1/t
    ({"law": -2.0 / 3.0}, NOT_REPRODUCED),  # the sticky-gas law of late 1-D cooling
    ({"t0_factor": 2.0}, NOT_REPRODUCED),  # Haff's t0 shifted: the law with the wrong parameter
])
def test_haff_claim_flips_with_the_law_or_its_t0(changes, verdict):
    rows = G.haff_law(cooling_measure(**changes), SPEC_COOLING)
    assert rows["r=0.95"].verdict == verdict
    assert rows["r=0.8"].verdict == NOT_CHECKABLE  # below haff_r_min: reported, not judged


def test_haff_exponents_recover_the_law():
    alpha = G.haff_exponents(cooling_like(law=-2.0), [0.1, 4.0])
    assert alpha.shape == (2, 8) and np.all(np.abs(alpha + 2.0) < 0.1)


@pytest.mark.parametrize("changes, verdict", [
    ({}, REPRODUCED),
    ({"dimer_stop": "sticky", "dimer_t_end": 5e4}, REPRODUCED),  # a sticky stop past the rigid collapse: no failure
    ({"dimer_stop": "overlap", "dimer_t_end": 5e4}, NOT_REPRODUCED),  # an engine stop
    ({"dimer_stop": "sticky", "dimer_t_end": 5e3}, NOT_REPRODUCED),  # stopped before the rigid collapse
    ({"dimer_warms": True}, NOT_REPRODUCED),  # a corrupted record: warmer after the rigid collapse
])
def test_dimer_cooling_claim_flips_on_a_stop_or_a_corrupted_record(changes, verdict):
    assert G.dimer_gas_keeps_cooling(cooling_measure(**changes), SPEC_COOLING).verdict == verdict


@pytest.mark.parametrize("tc_stop, verdict", [("t_max", REPRODUCED), ("collapse", NOT_REPRODUCED),
                                              ("sticky", NOT_REPRODUCED)])
def test_tc_claim_flips_when_a_run_stops_short(tc_stop, verdict):
    assert G.tc_model_reaches_horizon(cooling_measure(tc_stop=tc_stop), SPEC_COOLING).verdict == verdict


def test_cooling_claims_not_checkable_without_the_sweep():
    m = G.measure(SPEC_COOLING, [sweep_like(5.0 / (1.0 - R))])
    assert G.haff_law(m, SPEC_COOLING).verdict == NOT_CHECKABLE
    assert G.dimer_gas_keeps_cooling(m, SPEC_COOLING).verdict == NOT_CHECKABLE
    assert G.tc_model_reaches_horizon(m, SPEC_COOLING).verdict == NOT_CHECKABLE

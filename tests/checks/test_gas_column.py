"""bounce.checks.gas_column: its claims flip when the data say otherwise (the falsifiers)."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from bounce.checks import gas_column as G
from bounce.checks.base import NOT_CHECKABLE, NOT_REPRODUCED, REPRODUCED
from bounce.gas.common import STOP_COLLAPSE, STOP_COOLED, STOP_EVENTS, STOP_OVERLAP

SPEC = {"collapse_rtol": 1e-12}
GAMMA, HEIGHT, R = 0.001, 1.0, np.array([0.9, 0.95])


def column_like(n=(1, 2, 4), samples=2, **cells):
    """A gathered column-drop dataset in which every dimer column rested and every rigid twin collapsed, one rigid
    ball at the bouncing ball's time; ``cells`` overrides variable -> (index, value) for corrupted records."""
    shape = (R.size, len(n), samples)
    law = np.array([G.single_ball_collapse(GAMMA, HEIGHT, r) for r in R])
    t_rigid = law[:, None, None] * np.ones(shape) / np.arange(1, len(n) + 1)[None, :, None]
    values = {"dimer_stop": np.full(shape, STOP_EVENTS, np.int8), "dimer_rested": np.ones(shape, np.int8),
              "dimer_t_rest": np.full(shape, 500.0), "dimer_impacts": np.full(shape, 100),
              "dimer_events": np.full(shape, 100), "dimer_min_interval": np.full(shape, 1e-6),
              "dimer_energy": np.full(shape, 0.029), "rigid_stop": np.full(shape, STOP_COLLAPSE, np.int8),
              "rigid_t_end": t_rigid, "rigid_collisions": np.full(shape, 300), "rigid_low": np.zeros(shape, int),
              "rigid_high": np.zeros(shape, int)}
    for name, (index, value) in cells.items():
        values[name] = values[name].copy()
        values[name][index] = value
    dims = ("r", "n", "sample")
    ds = xr.Dataset({k: (dims, v) for k, v in values.items()},
                    coords={"r": R, "n": np.array(n), "sample": np.arange(samples)})
    ds.attrs.update(sweep="column-drop", gamma=GAMMA, height=HEIGHT, gap=1.0, rest=0.03, samples=samples,
                    max_events=1000000)
    return ds


def verdict(fn, ds, spec=SPEC):
    return fn(G.measure(spec, [ds]), spec).verdict


@pytest.mark.parametrize("cells, expected", [
    ({}, REPRODUCED),
    ({"dimer_stop": ((1, 2, 0), STOP_OVERLAP), "dimer_rested": ((1, 2, 0), 0)}, NOT_REPRODUCED),  # an engine stop
    ({"dimer_rested": ((0, 1, 1), 0), "dimer_energy": ((0, 1, 1), 0.06)}, NOT_REPRODUCED),  # cap before rest
    ({"dimer_t_rest": ((0, 0, 0), np.nan)}, NOT_REPRODUCED),  # corrupted record: at rest without a time
    ({"dimer_impacts": ((1, 1, 1), 0)}, NOT_REPRODUCED),  # at rest without an impact
])
def test_dimer_claim_flips_on_a_stop_a_cap_or_a_corrupted_record(cells, expected):
    assert verdict(G.dimer_column_rests, column_like(**cells)) == expected


@pytest.mark.parametrize("cells, expected", [
    ({}, REPRODUCED),
    ({"rigid_stop": ((0, 2, 1), STOP_COOLED)}, NOT_REPRODUCED),  # cooled, not collapsed
    ({"rigid_stop": ((1, 1, 0), STOP_EVENTS)}, NOT_REPRODUCED),  # cut by the event cap
    ({"rigid_t_end": ((1, 1, 0), np.inf)}, NOT_REPRODUCED),  # corrupted record: no finite collapse time
])
def test_rigid_claim_flips_when_a_twin_does_not_collapse(cells, expected):
    assert verdict(G.rigid_column_collapses, column_like(**cells)) == expected


def test_single_ball_claim_flips_with_a_shifted_parameter_or_a_wrong_law():
    assert verdict(G.rigid_column_single_ball, column_like()) == REPRODUCED
    shifted = column_like()
    shifted.attrs["height"] = HEIGHT * (1.0 + 1e-9)  # the data of another drop height
    assert verdict(G.rigid_column_single_ball, shifted) == NOT_REPRODUCED
    law = np.array([G.single_ball_collapse(GAMMA, HEIGHT, r) for r in R])
    wrong = column_like(rigid_t_end=((slice(None), 0, slice(None)), (law * (1.0 + R) / 2.0)[:, None]))  # (1+r)^2/2/(1-r)
    assert verdict(G.rigid_column_single_ball, wrong) == NOT_REPRODUCED
    assert verdict(G.rigid_column_single_ball, column_like(n=(2, 4))) == NOT_CHECKABLE  # no lone grain


def test_single_ball_law_is_the_fall_plus_the_flights():
    gamma, h, r = 0.01, 3.0, 0.7
    v0 = (2.0 * gamma * h) ** 0.5
    flights = v0 / gamma + sum(2.0 * r**k * v0 / gamma for k in range(1, 200))
    assert G.single_ball_collapse(gamma, h, r) == pytest.approx(flights, rel=1e-14)

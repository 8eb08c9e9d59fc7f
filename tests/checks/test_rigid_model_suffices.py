"""Check rigid-model-suffices: each claim's verdict on a synthetic rigid-suffices file, and its falsifier."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from bounce.checks import registry
from bounce.checks.base import NOT_CHECKABLE, NOT_REPRODUCED, REPRODUCED

G = registry()["rigid-model-suffices"]
SPEC = {"inputs": ["rigid-suffices"], "sigmas": 3.0, "sign_alpha": 1e-3}


def sweep_like(power=-1.0, temp_over_collapse=1.1, temp_over_seq=30.0):
    """r = 0.5 (collapses at n >= 30) and 0.95 (does not), n = 10, 30, 100, 300, 8 states: collisions per grain
    before the sequences part 30 n^power with a 30 % scatter; temperatures part at temp_over_seq x t_seq, or at
    temp_over_collapse x the collapse time where the rigid gas collapses."""
    rng = np.random.default_rng(5)
    n = np.array([10, 30, 100, 300])
    shape = (2, 4, 8)
    c = 30.0 * n[None, :, None] ** power * np.exp(0.3 * rng.standard_normal(shape))
    omega0 = np.full(shape, 0.0113)
    t_seq = c * 1.0  # one collision per grain per mean free time
    collapse = np.where((np.arange(2)[:, None, None] == 0) & (n[None, :, None] >= 30), 50.0, np.nan) * np.ones(shape)
    t_temp = np.where(np.isfinite(collapse), temp_over_collapse * collapse, np.inf)
    t_temp[1, :, :4] = temp_over_seq * t_seq[1, :, :4]
    ds = xr.Dataset({"t_seq": (("r", "n", "sample"), t_seq), "collisions_seq": (("r", "n", "sample"), c),
                     "omega0": (("r", "n", "sample"), omega0), "T_xi": (("r",), [3.25, 3.14]),
                     "collapse_time": (("r", "n", "sample"), collapse),
                     "t_temp_collapse": (("r", "n", "sample"), t_temp / collapse),
                     "t_temp": (("r", "n", "sample"), t_temp)},
                    coords={"r": [0.5, 0.95], "n": n, "sample": np.arange(8), "time": np.geomspace(0.1, 300.0, 40)})
    ds.attrs.update(sweep="rigid-suffices", samples=8, speed=0.01, horizon=300.0, temperature_rtol=0.1)
    return ds


def verdict(claim, **changes):
    rows = G.verdicts(G.measure(SPEC, [sweep_like(**changes)]), SPEC, only=claim)
    return {v.verdict for v in rows}


@pytest.mark.parametrize("changes, expected", [
    ({}, REPRODUCED),
    ({"power": -0.5}, NOT_REPRODUCED),  # parting after a number of collisions per grain falling as 1/sqrt(n)
    ({"power": 0.0}, NOT_REPRODUCED),  # ... or after a fixed number per grain
])
def test_sequence_parting_1_over_n(changes, expected):
    assert verdict("sequence-parting-1-over-n", **changes) == {expected}


@pytest.mark.parametrize("changes, expected", [
    ({}, REPRODUCED),
    ({"temp_over_collapse": 0.9}, REPRODUCED),  # within the grid step (1.23) by which t_temp is resolved
    ({"temp_over_collapse": 0.5}, NOT_REPRODUCED),  # the temperatures part at half the collapse time
])
def test_temperature_holds_to_collapse(changes, expected):
    assert verdict("temperature-holds-to-collapse", **changes) == {expected}


@pytest.mark.parametrize("changes, expected", [
    ({}, REPRODUCED),
    ({"temp_over_seq": 0.5}, NOT_REPRODUCED),  # temperatures part before the sequences
])
def test_temperature_outlasts_sequence(changes, expected):
    assert verdict("temperature-outlasts-sequence", **changes) == {expected}


def test_temperature_outlasts_sequence_is_a_sign_test():
    """Most states, not every state: one counterexample among 40 keeps the verdict (p ~ 4e-11); with 8 states even
    8 of 8 cannot reach p <= 1e-3 (2^-8 = 4e-3): not checkable rather than a verdict without power."""
    ds = sweep_like()
    t_temp = ds["t_temp"].values.copy()
    t_temp[1, 0, 0] = 0.5 * ds["t_seq"].values[1, 0, 0]
    ds["t_temp"] = (ds["t_temp"].dims, t_temp)
    rows = G.verdicts(G.measure(SPEC, [ds]), SPEC, only="temperature-outlasts-sequence")
    assert {v.verdict for v in rows} == {REPRODUCED} and "39 of 40" in rows[0].measured
    few = sweep_like().isel(r=[1], n=[0])
    few["t_temp"] = xr.where(np.isfinite(few["t_temp"]), few["t_temp"], 30.0 * few["t_seq"])
    rows = G.verdicts(G.measure(SPEC, [few]), SPEC, only="temperature-outlasts-sequence")
    assert {v.verdict for v in rows} == {NOT_CHECKABLE}


@pytest.mark.parametrize("claim", [c.id for c in G.claims])
def test_falsifier_flips_on_the_synthetic_sweep(claim):
    """Each claim's falsifier (bounce.checks.base.Falsifier) flips its rows on the synthetic file (4 n over 1.5
    decades, 8 states): a sweep the claims can decide."""
    from bounce.checks.base import falsify, unflipped

    true_rows = G.verdicts(G.measure(SPEC, [sweep_like()]), SPEC, only=claim)
    doctored = falsify(G, claim, SPEC, [sweep_like()])
    assert not unflipped(true_rows, doctored)


def test_sequence_parting_needs_the_power_to_refute_a_fixed_count_per_grain():
    """Two n a factor 3 apart, 4 states each, scattered by a factor e (as the CI-sized sweep): 3 x the standard error of
    s exceeds 1, so s = 0 would pass as well as s = -1, and the row is not checkable rather than reproduced."""
    few = sweep_like().isel(n=[0, 1], sample=slice(0, 4))
    c = few["collisions_seq"].values * np.exp(np.random.default_rng(1).standard_normal(few["collisions_seq"].shape))
    few["collisions_seq"] = (few["collisions_seq"].dims, c)
    few.attrs["samples"] = 4
    assert verdict_of(few, "sequence-parting-1-over-n") == {NOT_CHECKABLE}


def verdict_of(ds, claim):
    return {v.verdict for v in G.verdicts(G.measure(SPEC, [ds]), SPEC, only=claim)}

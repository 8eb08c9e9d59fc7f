"""Sweeps (bounce.sweeps): sharding, the gathered file's independence of shards and workers, the numbers
each sweep claims, and the CI-sized sweeps through the pipeline's task entry points."""

from __future__ import annotations

import copy
import functools
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import yaml

from bounce.io import read_dataset
from bounce.pipeline.config import validated
from bounce.model import InputError
from snakemake.utils import update_config
from bounce.sweeps import registry
from bounce.sweeps.base import gather, run_shard, shard_items
from bounce.pipeline.tasks import main as task

ROOT = Path(__file__).resolve().parents[2]
FULL = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())


#: the small sweeps of these tests, as the pipeline hands a sweep its spec: checked by the config contract, schema
#: defaults filled (all five in one validation: it reads the schema and checks the whole config)
_SMALL = {
    "contact-monte-carlo": {"shards": 1, "seed": 5, "n_samples": 24, "events": 60, "gamma": [1e-4, 0.2],
                            "mu_under": [1e-3, 0.95], "mu_over": [1.05, 5.0], "energy_over_gamma2": [0.1, 1000.0],
                            "batch": 5},
    "asymptotic-atlas": {"shards": 1, "mu": {"min": 0.3, "max": 2.0, "n": 2}, "gamma": {"min": 1e-3, "max": 1e-3, "n": 1},
                         "psi0": 0.25, "events": 20000, "transient": 0.1, "fit": {"n_min": 1000}, "batch": 1},
    "our-r-band": {"shards": 1, "mu": {"min": 0.01, "max": 0.1, "n": 2}, "u_over_uc": {"min": 0.1, "max": 30.0, "n": 8},
                   "gamma": 1e-5, "psi0": 0.25, "events": 5000, "batch": 1},
    "hertz-restitution": {"shards": 1, "u": {"min": 1e-7, "max": 1e-2, "n": 6}, "gamma": [1e-12, 1e-6], "batch": 3},
    "alpha-atlas": {"shards": 1, "a": [0.0, 0.5], "b": [0.5], "constants": [{"rho": 1.0, "gamma": 0.01, "mu": 0.3}],
                    "events": 30000, "batch": 1},
}
_SPECS = validated({**copy.deepcopy(FULL), "sweeps": {**FULL["sweeps"], **copy.deepcopy(_SMALL)}})["sweeps"]
MC, ATLAS, BAND, HERTZ, ALPHA = (_SPECS[name] for name in _SMALL)


def _ci_spec(name: str) -> dict:
    """The sweep's slice of config.yaml merged with config/ci.yaml (as snakemake merges them), validated."""
    cfg = copy.deepcopy(FULL)
    update_config(cfg, yaml.safe_load((ROOT / "config" / "ci.yaml").read_text()))
    spec = validated(cfg)["sweeps"][name]
    spec.pop("threads", None)
    return spec


@pytest.mark.parametrize("n", [1, 2, 7, 100])
def test_shards_partition_the_items(n):
    for shards in range(1, n + 1):
        parts = [shard_items(n, k, shards) for k in range(shards)]
        assert np.array_equal(np.sort(np.concatenate(parts)), np.arange(n))
        sizes = [p.size for p in parts]
        assert max(sizes) - min(sizes) <= 1


def test_bad_shard_counts_are_refused():
    with pytest.raises(InputError, match=r"shards must be in \[1, 5\]"):
        shard_items(5, 0, 6)
    with pytest.raises(InputError, match=r"shard must be in \[0, 1\]"):
        shard_items(5, 2, 2)


def _gathered(name, spec, shards, workers):
    sweep = registry()[name]
    spec = dict(spec, shards=shards)
    parts = [run_shard(sweep, spec, k, workers=workers, progress=False) for k in range(shards)]
    return gather(sweep, spec, parts[::-1])  # any order


@pytest.mark.parametrize("name, spec", [("contact-monte-carlo", MC), ("asymptotic-atlas", ATLAS), ("our-r-band", BAND),
                                        ("hertz-restitution", HERTZ), ("alpha-atlas", ALPHA)])
def test_gathered_dataset_does_not_depend_on_shards_or_workers(name, spec):
    one = _gathered(name, spec, shards=1, workers=1)
    many = _gathered(name, spec, shards=2, workers=2)
    xr.testing.assert_identical(one, many)
    if name == "contact-monte-carlo":  # batches of one item, three shards (one worker each: workers are `many`'s)
        three = _gathered(name, dict(spec, batch=1), shards=3, workers=1)
        xr.testing.assert_identical(one, three)


def test_gather_refuses_missing_shards():
    sweep = registry()["contact-monte-carlo"]
    spec = dict(MC, shards=2)
    with pytest.raises(InputError, match="do not hold items 0..23 exactly once"):
        gather(sweep, spec, [run_shard(sweep, spec, 0, progress=False)])


def test_monte_carlo_accounts_for_every_impact_and_finds_no_zero_speed_contact():
    ds = _gathered("contact-monte-carlo", MC, shards=1, workers=1)
    counts = ds["counts"].values
    assert counts.shape == (24, 4) and np.all(counts.sum(axis=1) <= MC["events"])
    n_impacts = int(counts[:, 0].sum())
    assert ds["ratio_hist"].values.sum() == ds["margin_hist"].values.sum() == n_impacts == ds.attrs["n_impacts"]
    assert np.array_equal(np.bincount(ds["damping_regime"].values, minlength=3), [8, 8, 8])
    assert ds.attrs["n_grazing"] == ds.attrs["n_sticky_start"] == ds.attrs["n_inside_classifier_window"] == 0
    assert np.all((ds["min_ratio"].values > 0) & (ds["min_ratio"].values <= 1))
    # the pooled fractions are the histogram's cumulative sums
    below = ds["ratio_hist"].values[:, : np.searchsorted(ds["ratio_edges"].values, 1e-2)].sum(axis=1)
    np.testing.assert_array_equal(ds["fraction_below"].sel(threshold=1e-2).values,
                                  below / ds["ratio_hist"].values.sum(axis=1))


def test_atlas_reproduces_the_main_theorem_limits():
    ds = _gathered("asymptotic-atlas", ATLAS, shards=1, workers=1)
    assert ds["limit"].dims == ("mu", "gamma", "quantity") and ds["limit"].shape == (2, 1, 6)  # main-theorem's q_n
    np.testing.assert_allclose(ds["mu"].values, [0.3, 2.0])
    ds = ds.sel(quantity=["tau", "xdot"])
    L, err = ds["limit"].values, ds["limit_err"].values
    assert np.all(np.isfinite(L)) and np.all(err < 1e-3)
    # Theorem main_thm: L = 1, within 3 x the fit's error or the rounding floor (the check's rule)
    assert np.all(np.abs(L - 1.0) <= np.maximum(3.0 * err, 1e-8))
    assert np.all(np.isfinite(ds["transient"].values)) and np.all(ds["transient"].values < 1000)


def test_our_r_band_is_a_band_around_u_c():
    """Eq. our-r (check our-r, claim our-r-band): 1 - r = 1 - e^{-mu T_xi} holds for the macroscopic bounces
    well above u_c (sec. 8; within the threshold, here u/u_c ~ 30, the drop's first landings at mu = 0.01) and fails
    at the stitch u = u_c, where the dimer's 1 - r is neither branch's.  The band's upper edge lies between them."""
    ds = _gathered("our-r-band", BAND, shards=1, workers=1)
    assert ds["median_err"].dims == ("mu", "u_bin") and ds["median_err"].shape == (2, 8)
    thr = ds.attrs["our_r_threshold"]
    low_mu = ds.sel(mu=0.01)
    assert float(low_mu["median_err"].sel(u_bin=30.0)) < thr
    assert float(low_mu["median_err"].sel(u_bin=1.0, method="nearest")) > thr
    assert 1.0 < float(low_mu["u2"] / low_mu["u_c"]) < 30.0
    # every measured bounce is in some cell or outside the grid, none twice
    assert np.all(ds["bounces"].values.sum(axis=1) > 0) and np.all(ds["double_bounces"].values > 0)
    # the predicted edges per mu (check our-r's band-across-mu): u2 from gamma (ln(1/thr) -+ 1)/(2 mu), u1's
    # range ordered; the bounces beyond the band counted on each side
    ell, g, mu = np.log(1.0 / thr), ds.attrs["gamma"], ds["mu"].values
    np.testing.assert_allclose(ds["u2_predicted_low"].values, g * (ell - 1.0) / (2.0 * mu), rtol=1e-12)
    np.testing.assert_allclose(ds["u2_predicted_high"].values, g * (ell + 1.0) / (2.0 * mu), rtol=1e-12)
    lo, at, hi = (ds[f"u1_predicted{k}"].values for k in ("_low", "", "_high"))
    assert np.all(lo <= at) and np.all(at <= hi)
    assert np.all(ds["bounces_above_band"].values > 0) and np.all(ds["bounces_below_band"].values >= 0)
    # fig. rest-coeff's phases per mu (check restitution's same-behaviour-across-mu): at mu = 0.01 the scene
    # rest-coeff's drop (its first 5000 events hold the plateau of 25 bounces and r = exp(-mu T_xi) to ~2e-4)
    np.testing.assert_allclose(ds["r_theory"].values, np.exp(-mu * np.pi / np.sqrt(1.0 - mu**2)), rtol=1e-14)
    assert int(low_mu["plateau_bounces"]) == 25 and abs(float(low_mu["plateau_mean"] - low_mu["r_theory"])) < 5e-4
    assert np.all(ds["plateau_standard_error"].values < ds["plateau_std"].values)
    assert 0.0 <= float(low_mu["fluctuation_turns"]) <= 1.0 and float(low_mu["decline_drop"]) > 0.0


def test_hertz_single_impact_follows_the_first_order_cycle_loss_without_gravity():
    """Gravity-free row: 1 - r -> theory.nonlin_cycle_loss as u -> 0, with a relative gap O(1 - r) (the next order
    of eq. onefifth-rest-coeff); with gravity the spring is left moving at xi'/u = -gamma T_c/u exactly
    (the centre of mass falls for T_c while the spring swings back to rest length)."""
    ds = _gathered("hertz-restitution", HERTZ, shards=1, workers=1)
    assert ds["r"].dims == ("u", "gamma") and np.all(ds["complete"].values == 1)
    free = ds.sel(gamma=1e-12)
    loss, first = 1.0 - free["r"].values, free["loss_first_order"].values
    gap = np.abs(loss / first - 1.0)
    assert np.all(gap <= loss) and np.all(np.diff(gap) > 0)  # O(1 - r), shrinking as u -> 0
    gravity = (ds["gamma"] * ds["contact_time"] / ds["arrival"]).transpose("u", "gamma")
    np.testing.assert_allclose(-ds["residual"].values, gravity.values, rtol=1e-6)


def test_alpha_atlas_limits_are_one_in_every_cell():
    ds = _gathered("alpha-atlas", ALPHA, shards=1, workers=1)
    assert ds["limit"].dims == ("a", "b", "constants", "quantity") and ds["limit"].shape == (2, 1, 1, 2)
    assert np.all(ds["complete"].values == 1)
    L, err = ds["limit"].values, np.maximum(ds["limit_err"].values, np.abs(ds["limit"] - ds["tail_limit"]).values)
    assert np.all(np.isfinite(L)) and np.all(err < 1e-3)
    assert np.all(np.abs(L - 1.0) <= 3.0 * err)  # the Discussion: alpha_n -> alpha; Xdot_n/tau_n -> gamma
    assert np.all(np.abs(ds["exponent"].values - 1.0) < 0.3)  # Lemma Giorgio's: corrections ~ ln n/n


@pytest.mark.slow
@pytest.mark.parametrize("name", ["contact-monte-carlo", "asymptotic-atlas", "our-r-band", "hertz-restitution",
                                  "alpha-atlas"])
def test_ci_sized_sweep_through_the_task_entry_points(name, ci_results):
    """The CI-sized sweep as the pipeline made it (tests/conftest.py: ci_results; workflow/rules/sweeps.smk calls
    bounce.pipeline.tasks sweep-shard with the rule's 2 workers, sweep-gather with its figure): every shard, the
    gathered file with its attributes, units and long names, the figure.  (It ran the three entry points itself
    on the same CI-sized spec; the pipeline's run is the same calls, so CI no longer computes the sweeps twice.)"""
    spec = _ci_spec(name)
    for k in range(spec["shards"]):
        shard = read_dataset(ci_results / "sweeps" / name / f"shard-{k}-of-{spec['shards']}.nc")
        assert shard.attrs["sweep"] == name and (shard.attrs["shard"], shard.attrs["shards"]) == (k, spec["shards"])
    ds = read_dataset(ci_results / "sweeps" / f"{name}.nc")
    assert ds.attrs["sweep"] == name and ds.attrs["git_commit"]
    for var in ds.data_vars.values():
        assert var.attrs.get("long_name") and "units" in var.attrs
    png, pdf = ci_results / "sweeps" / f"fig-{name}.png", ci_results / "sweeps" / f"fig-{name}.pdf"
    assert png.stat().st_size > 10_000 and pdf.stat().st_size > 5_000


def test_task_entry_points_run_a_sweep(tmp_path):
    """bounce.pipeline.tasks sweep-shard and sweep-gather (with the figure) on a small sweep in two shards, in this process
    (no worker processes: they are test_gathered_dataset_does_not_depend_on_shards_or_workers'): exit status 0, the
    attributes, units and long names, the figure, and the gathered file equal to gather's here."""
    import json

    name, spec = "contact-monte-carlo", dict(MC, shards=2, batch=100)  # one batch a shard: no worker process
    text = json.dumps(spec)
    shards = [tmp_path / f"shard-{k}.nc" for k in range(2)]
    for k, path in enumerate(shards):
        assert task(["sweep-shard", "--name", name, "--spec", text, "--shard", str(k), "--workers", "1",
                     "--out", str(path)]) == 0
    out, png, pdf = tmp_path / f"{name}.nc", tmp_path / f"fig-{name}.png", tmp_path / f"fig-{name}.pdf"
    assert task(["sweep-gather", "--name", name, "--spec", text, "--inputs", *map(str, shards),
                 "--out", str(out), str(png), str(pdf)]) == 0
    ds = read_dataset(out)
    assert ds.attrs["sweep"] == name and ds.attrs["git_commit"]
    for var in ds.data_vars.values():
        assert var.attrs.get("long_name") and "units" in var.attrs
    assert png.stat().st_size > 10_000 and pdf.stat().st_size > 5_000
    xr.testing.assert_identical(ds, _gathered(name, spec, shards=2, workers=1))


@pytest.mark.parametrize("edit, key", [
    (lambda s: s["asymptotic-atlas"].update(shards=0), "shards"),
    (lambda s: s["asymptotic-atlas"]["mu"].update(min=-1.0), "min"),
    (lambda s: s["asymptotic-atlas"].update(event=10), "event"),
    (lambda s: s["contact-monte-carlo"].update(gamma=[1e-4, float("inf")]), "inf"),
    (lambda s: s["contact-monte-carlo"].update(n_samples=2.5), "2.5"),
    (lambda s: s.update(unknown_sweep={}), "unknown_sweep"),
    (lambda s: s["our-r-band"]["mu"].update(max=1.5), "1.5"),
    (lambda s: s["hertz-restitution"].update(gamma=[0.6]), "0.6"),
    (lambda s: s["alpha-atlas"]["constants"][0].update(rho=0.0), "0.0"),
    (lambda s: s["alpha-atlas"].update(a=[-1.0]), "-1.0"),
])
def test_schema_rejects_bad_sweep_settings(edit, key):
    import jsonschema

    config = copy.deepcopy(FULL)
    edit(config["sweeps"])
    with pytest.raises(jsonschema.ValidationError, match=key):
        jsonschema.validate(config, _raw_schema())


@functools.cache
def _raw_schema() -> dict:
    return yaml.safe_load((ROOT / "config" / "schema.yaml").read_text())


def test_schema_accepts_the_shipped_sweeps():
    """The shipped config is valid against the schema file as written (each refusal above edits it; this was
    checked once in each of them)."""
    import jsonschema

    jsonschema.validate(FULL, _raw_schema())

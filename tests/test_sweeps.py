"""Sweeps (bounce.sweeps): sharding, the gathered file's independence of shards and workers, the numbers
each sweep claims, and the CI-sized sweeps through the pipeline's task entry points."""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import yaml

from bounce.io import read_dataset
from bounce.config import validated
from bounce.model import InputError
from snakemake.utils import update_config
from bounce.sweeps import registry
from bounce.sweeps.base import gather, run_shard, shard_items
from bounce.tasks import main as task

ROOT = Path(__file__).resolve().parents[1]
FULL = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())


def _validated(name: str, spec: dict) -> dict:
    """``spec`` as the pipeline hands it to the sweep: checked by the config contract, schema defaults filled."""
    cfg = copy.deepcopy(FULL)
    cfg["sweeps"][name] = spec
    return validated(cfg)["sweeps"][name]


MC = _validated("contact-monte-carlo", {
    "shards": 1, "seed": 5, "n_samples": 24, "events": 60, "gamma": [1e-4, 0.2], "mu_under": [1e-3, 0.95],
    "mu_over": [1.05, 5.0], "energy_over_gamma2": [0.1, 1000.0], "batch": 5})
ATLAS = _validated("asymptotic-atlas", {
    "shards": 1, "mu": {"min": 0.3, "max": 2.0, "n": 2}, "gamma": {"min": 1e-3, "max": 1e-3, "n": 1},
    "psi0": 0.25, "events": 20000, "transient": 0.1, "fit": {"n_min": 1000}, "batch": 1})


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
        assert np.array_equal(np.concatenate(parts), np.arange(n))
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


@pytest.mark.parametrize("name, spec", [("contact-monte-carlo", MC), ("asymptotic-atlas", ATLAS)])
def test_gathered_dataset_does_not_depend_on_shards_or_workers(name, spec):
    one = _gathered(name, spec, shards=1, workers=1)
    many = _gathered(name, spec, shards=2, workers=2)
    xr.testing.assert_identical(one, many)
    if name == "contact-monte-carlo":
        three = _gathered(name, dict(spec, batch=1), shards=3, workers=2)
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


@pytest.mark.parametrize("name", ["contact-monte-carlo", "asymptotic-atlas"])
def test_ci_sized_sweep_through_the_task_entry_points(name, tmp_path):
    import json

    spec = _ci_spec(name)
    text = json.dumps(spec)
    shards = [tmp_path / f"shard-{k}.nc" for k in range(spec["shards"])]
    for k, path in enumerate(shards):
        assert task(["sweep-shard", "--name", name, "--spec", text, "--shard", str(k), "--workers", "2",
                     "--out", str(path)]) == 0
    out = tmp_path / f"{name}.nc"
    assert task(["sweep-gather", "--name", name, "--spec", text, "--inputs", *map(str, shards), "--out", str(out)]) == 0
    png, pdf = tmp_path / f"fig-{name}.png", tmp_path / f"fig-{name}.pdf"
    assert task(["sweep-figure", "--name", name, "--spec", text, "--inputs", str(out), "--out", str(png), str(pdf)]) == 0
    ds = read_dataset(out)
    assert ds.attrs["sweep"] == name and ds.attrs["git_commit"]
    for var in ds.data_vars.values():
        assert var.attrs.get("long_name") and "units" in var.attrs
    assert png.stat().st_size > 10_000 and pdf.stat().st_size > 5_000


@pytest.mark.parametrize("edit, key", [
    (lambda s: s["asymptotic-atlas"].update(shards=0), "shards"),
    (lambda s: s["asymptotic-atlas"]["mu"].update(min=-1.0), "min"),
    (lambda s: s["asymptotic-atlas"].update(event=10), "event"),
    (lambda s: s["contact-monte-carlo"].update(gamma=[1e-4, float("inf")]), "inf"),
    (lambda s: s["contact-monte-carlo"].update(n_samples=2.5), "2.5"),
    (lambda s: s.update(unknown_sweep={}), "unknown_sweep"),
])
def test_schema_rejects_bad_sweep_settings(edit, key):
    import jsonschema

    config = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    schema = yaml.safe_load((ROOT / "config" / "schema.yaml").read_text())
    jsonschema.validate(config, schema)  # the shipped config is valid
    edit(config["sweeps"])
    with pytest.raises(jsonschema.ValidationError, match=key):
        jsonschema.validate(config, schema)

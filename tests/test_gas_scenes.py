"""Gas scenes (config ``gas_scenes``, bounce.scenes.gas_scene_run): one generator with the command line."""

from __future__ import annotations

import numpy as np
import xarray as xr

from bounce.cli import main
from bounce.scenes import gas_scene_dataset

RING = {"model": "dimer", "geometry": "ring", "n": 12, "ell": 20.0, "mu": 0.05, "initial": {"speed": 0.1, "seed": 3},
        "stop": {"events": 400}, "snapshot_every": 100}


def test_a_gas_scene_is_the_command_lines_run(tmp_path, capsys):
    """The scene and ``python -m bounce gas`` with the same numbers start from the same generated state
    (bounce.gas.model.random_state) and give the same records, bit for bit."""
    ds = gas_scene_dataset(RING, name="ring")
    assert main(["gas", "--n", "12", "--geometry", "ring", "--ell", "20", "--mu", "0.05", "--speed", "0.1", "--seed",
                 "3", "--events", "400", "--snapshot-every", "100", "--no-progress", "--out",
                 str(tmp_path / "cli.nc")]) == 0
    capsys.readouterr()
    with xr.open_dataset(tmp_path / "cli.nc", engine="netcdf4") as cli:
        for name in ("t", "kind", "pair", "speed", "x", "xdot", "xidot", "eta", "initial_psi", "initial_psidot"):
            np.testing.assert_array_equal(ds[name].values, cli[name].values, err_msg=name)
    assert ds.attrs["scene"] == "ring" and ds.sizes["snapshot"] == 4


def test_a_rigid_column_scene_runs_to_its_stop():
    spec = {"model": "rigid", "geometry": "column", "n": 3, "gamma": 0.01, "r": 0.5, "initial": {"speed": 0.0},
            "stop": {"events": 10000}}
    ds = gas_scene_dataset(spec)
    assert ds.attrs["stop_reason"] in ("collapse", "cooled_below_rounding", "max_events")
    assert np.all(np.diff(ds["t"].values) >= 0.0)

"""bounce.gas.io and ``python -m bounce gas``: the netCDF contract, streaming, resuming, the command line.

* a result's dataset has CF attributes (units, long names, flags), provenance and the stop, and reads
  back to the same result, bit for bit (dimer and rigid);
* a streamed run writes the records of the one-shot run, bit for bit, in bounded chunks; an interrupted
  stream resumed from its checkpoint gives them too;
* the command line: good input writes a readable file and one summary line; bad input is one line
  ``error: ...`` naming the parameter, exit status 2, and no file.
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
import xarray as xr

from bounce.cli import main as cli_main
from bounce.errors import InputError
from bounce.gas import GasParameters, GasRun, GasState, RigidParameters, RigidState, simulate_gas, simulate_rigid
from bounce.gas.io import checkpoint_path, from_dataset, partial_path, stream_to_netcdf, to_dataset
from bounce.io import write_netcdf


def _ring(n=8):
    k = np.arange(n)
    v = 0.1 * np.sin(1.3 * k)
    return GasParameters(n, "ring", 0.0, 0.05, 12.0), GasState(0.2 + 1.5 * k, v - v.mean(), 0.02 * np.cos(k),
                                                               np.zeros(n))


def _rigid():
    return RigidParameters(3, "ring", 0.0, 0.05, ell=1e6, size=0.0), RigidState([0.0, 0.0, 1.0], [-0.1, 0.0, -1.0])


def _same(a, b):
    for name in ("t", "kind", "pair", "speed", "snap_t", "snap_event"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    for name in a.snapshots:
        assert np.array_equal(a.snapshots[name], b.snapshots[name]), name
        assert np.array_equal(a.final[name], b.final[name]), name
    assert (a.stop_reason, a.t_end, a.message, a.collapse, a.settings) == (b.stop_reason, b.t_end, b.message,
                                                                            b.collapse, b.settings)


@pytest.mark.parametrize("make, run", [(_ring, simulate_gas), (_rigid, simulate_rigid)])
def test_round_trip(tmp_path, make, run):
    p, s = make()
    res = run(p, s, max_events=500, snapshot_every=50)
    path = write_netcdf(to_dataset(res), tmp_path / "run.nc", compression="none")
    with xr.open_dataset(path, engine="netcdf4") as ds:
        ds.load()
    assert ds.attrs["Conventions"] == "CF-1.10" and ds.attrs["model"] == res.model
    assert ds.attrs["git_commit"] and ds.attrs["stop_reason"] == res.stop_reason
    for name, var in ds.variables.items():
        assert var.attrs["units"] == "1" and var.attrs["long_name"], name
    assert ds["kind"].attrs["flag_meanings"].split()[:2] == ["floor", "pair"]
    back = from_dataset(ds)
    _same(res, back)
    assert back.params == p
    assert all(np.array_equal(getattr(back.initial, k), getattr(s, k)) for k in vars(s))


@pytest.mark.parametrize("make, run", [(_ring, simulate_gas), (_rigid, simulate_rigid)])
def test_stream_equals_one_shot(tmp_path, make, run):
    p, s = make()
    one = run(p, s, max_events=1000, snapshot_every=70)
    out = tmp_path / "stream.nc"
    summary = stream_to_netcdf(p, s, out, 1000, snapshot_every=70, chunk=97)
    assert summary["events"] == len(one) and not partial_path(out).exists() and not checkpoint_path(out).exists()
    with xr.open_dataset(out, engine="netcdf4") as ds:
        _same(one, from_dataset(ds.load()))


def test_interrupted_stream_resumes_to_the_same_records(tmp_path, monkeypatch):
    p, s = _ring()
    out = tmp_path / "stream.nc"
    one = simulate_gas(p, s, max_events=1000, snapshot_every=70)
    step = GasRun.step
    calls = {"n": 0}

    def interrupted(self, m):
        calls["n"] += 1
        if calls["n"] == 4:
            raise KeyboardInterrupt
        return step(self, m)

    monkeypatch.setattr(GasRun, "step", interrupted)
    with pytest.raises(KeyboardInterrupt):
        stream_to_netcdf(p, s, out, 1000, snapshot_every=70, chunk=97)
    monkeypatch.setattr(GasRun, "step", step)
    assert partial_path(out).exists() and checkpoint_path(out).exists() and not out.exists()
    stream_to_netcdf(p, s, out, 1000, snapshot_every=70, chunk=97, resume=True)
    with xr.open_dataset(out, engine="netcdf4") as ds:
        _same(one, from_dataset(ds.load()))


def test_a_checkpoint_of_another_engine_layout_is_refused_in_one_line(tmp_path):
    """A checkpoint whose slot table has another width (an older engine) stops the resume with the parameter named."""
    p, s = _ring()
    out = tmp_path / "stream.nc"
    stream_to_netcdf(p, s, out, 100, snapshot_every=70, chunk=97)
    out.rename(partial_path(out))
    arrays = GasRun(p, s, np.inf, 70).arrays()
    arrays["sl"] = arrays["sl"][:, :8]
    np.savez(checkpoint_path(out), snapshots=np.int64(0), **arrays)
    with pytest.raises(InputError, match="^--resume: the checkpoint's 'sl' does not fit this engine"):
        stream_to_netcdf(p, s, out, 100, snapshot_every=70, chunk=97, resume=True)
    assert not out.exists() and partial_path(out).exists() and checkpoint_path(out).exists()  # nothing clobbered


def _run(tmp_path, *args):
    return subprocess.run([sys.executable, "-m", "bounce", "gas", *args], capture_output=True, text=True,
                          cwd=tmp_path, timeout=600)


def test_cli_writes_a_file(tmp_path):
    proc = _run(tmp_path, "--n", "20", "--geometry", "ring", "--ell", "30", "--events", "300", "--snapshot-every",
                "100", "--out", "ring.nc")
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.startswith("bounce gas: 300 events (300 pair), stop: max_events")
    with xr.open_dataset(tmp_path / "ring.nc", engine="netcdf4") as ds:
        assert ds.sizes["event"] == 300 and ds.sizes["snapshot"] == 3 and ds.sizes["grain"] == 20
        assert float(ds["initial_psidot"].sum()) == pytest.approx(0.0, abs=1e-15)


@pytest.mark.parametrize("args, words", [
    (["--n", "0", "--geometry", "ring", "--ell", "5"], "n must be an integer in [1, 1e+08]"),
    (["--n", "10", "--geometry", "ring", "--ell", "5"], "--ell must be > n times the grains' length"),
    (["--n", "10", "--geometry", "ring"], "--ell is required with --geometry ring"),
    (["--n", "10", "--geometry", "ring", "--ell", "50", "--gamma", "0.01"], "--gamma must be 0 on the ring"),
    (["--n", "10", "--geometry", "column", "--gamma", "-1"], "gamma must be in [1e-12, 0.5) for the column"),
    (["--n", "10", "--geometry", "column", "--r", "0.5"], "--r: only with --model rigid"),
    (["--n", "10", "--geometry", "column", "--model", "rigid"], "--r is required with --model rigid"),
    (["--n", "10", "--geometry", "column", "--model", "rigid", "--r", "2"], "r must be in [0, 1]"),
    (["--n", "10", "--geometry", "column", "--mu", "0.1", "--mu", "0.2"], "--mu is given more than once"),
    (["--n", "10", "--geometry", "column", "--mu", "abc"], "argument --mu: invalid float value"),
    (["--n", "10", "--geometry", "column", "--events", "0"], "max_events must be an integer in [1,"),
    (["--n", "10", "--geometry", "column", "--speed", "-1"], "--speed must be in [0, inf)"),
    (["--n", "3", "--geometry", "column", "--state", "missing.npz"], "--state must be an .npz file"),
    (["--n", "10", "--geometry", "box"], "argument --geometry: invalid choice"),
])
def test_cli_bad_input_is_one_line_and_no_file(tmp_path, capsys, args, words):
    status = cli_main(["gas", *args, "--out", str(tmp_path / "bad.nc")])
    err = capsys.readouterr().err
    assert status == 2 and err.startswith("error: ") and err.count("\n") == 1 and words in err, err
    assert list(tmp_path.iterdir()) == []


def test_cli_state_file_and_overlapping_grains(tmp_path, capsys):
    np.savez(tmp_path / "s.npz", psi=[1.0, 1.5], psidot=[0.0, 0.0], xi=[0.0, 0.0], xidot=[0.0, 0.0])
    status = cli_main(["gas", "--n", "2", "--geometry", "column", "--state", str(tmp_path / "s.npz"), "--out",
                       str(tmp_path / "o.nc")])
    err = capsys.readouterr().err
    assert status == 2 and "grains 0 and 1 overlap" in err and not (tmp_path / "o.nc").exists()

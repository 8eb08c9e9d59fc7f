"""netCDF I/O: contract of the dataset, exact round trip, atomic and reproducible writes."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
import xarray as xr

import bounce
import bounce.io as bio
from bounce import Deviations, Parameters, State, simulate
from bounce.kinds import KIND_NAMES
from bounce.sampling import sample_trajectory

P = Parameters(gamma=0.01, mu=0.01)

EVENT_VARS = ("t", "tau", "xdot", "y", "y_minus_yeq", "ydot", "xidot", "eta", "energy", "energy_excess", "kind")


def _runs():
    return {
        "impacts": simulate(P, State.from_psi_xi(6.0, 0.0, 0.0, 0.0), max_events=40),
        "sticky": simulate(P, State.sticky_ic(P, 0.0), max_events=40),
        "deviations": simulate(P, Deviations(0.0, 0.02, -0.01, 1e-3), max_events=40),
        "sticky_forever": simulate(P, State(0.0, 0.0, P.y_eq, 0.0), max_events=10),
        "t_max": simulate(P, State.from_psi_xi(6.0, 0.0, 0.0, 0.0), max_events=40, t_max=100.0),
        "no_events": simulate(P, State.from_psi_xi(6.0, 0.0, 0.0, 0.0), max_events=40, t_max=10.0),
    }


RUNS = _runs()


def _times(traj):
    end = traj.t_valid if math.isfinite(traj.t_valid) else 50.0
    # beyond t_valid too (NaN there), and exactly at the event times
    return np.sort(np.concatenate([np.linspace(0.0, 1.1 * end + 1.0, 301), traj.t]))


def _same_bits(a, b):
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    return a.shape == b.shape and np.array_equal(a.view(np.uint64), b.view(np.uint64))


@pytest.fixture(params=sorted(RUNS))
def traj(request):
    return RUNS[request.param]


def test_round_trip_is_bit_exact(traj, tmp_path):
    times = _times(traj)
    ds = bio.to_dataset(traj, times)
    path = bio.write_netcdf(ds, tmp_path / "run.nc")
    back = bio.read_dataset(path)
    assert back.identical(ds)
    expected = sample_trajectory(traj, times)
    got = bio.sample_dataset(back, times)
    for key, value in expected.items():
        assert _same_bits(got[key], value), key
    assert _same_bits(got["y"], traj.params.y_eq + expected["y_minus_yeq"])
    for name, (key, _) in bio.SAMPLED_VARIABLES.items():
        assert _same_bits(back[name].values, got[key]), name
    # the rebuilt trajectory is the simulated one
    rebuilt = bio.read_trajectory(path)
    assert rebuilt.params == traj.params and rebuilt.initial == traj.initial
    assert type(rebuilt.initial) is type(traj.initial)
    for name in ("t", "tau", "xdot", "xidot", "eta", "energy_excess"):
        assert _same_bits(getattr(rebuilt, name), getattr(traj, name)), name
    assert np.array_equal(rebuilt.kind, traj.kind) and rebuilt.kind.dtype == np.int8
    assert (rebuilt.stop_reason, rebuilt.t_end, rebuilt.settings, rebuilt.t_valid) == (
        traj.stop_reason, traj.t_end, traj.settings, traj.t_valid)
    assert bio.to_dataset(rebuilt, times).identical(ds)


def test_event_variables(traj):
    ds = bio.to_dataset(traj)
    assert "time" not in ds.dims
    for name in EVENT_VARS:
        assert ds[name].dims == ("event",), name
        assert ds[name].dtype == (np.int8 if name == "kind" else np.float64), name
    assert ds.sizes["event"] == len(traj)
    assert _same_bits(ds.y_minus_yeq, 2.0 * traj.eta)
    assert _same_bits(ds.y, traj.params.y_eq + 2.0 * traj.eta)
    assert _same_bits(ds.ydot, traj.xdot + 2.0 * traj.xidot)
    assert _same_bits(ds.energy, traj.params.energy_min + traj.energy_excess)
    t = ds.t.values
    if len(t):
        assert np.all(np.diff(t) > 0)
        assert t[0] > 0 or ds.kind.values[0] == KIND_NAMES.index("sticky_start")


def test_attributes(traj):
    ds = bio.to_dataset(traj, _times(traj))
    for name, var in ds.variables.items():
        assert var.attrs.get("units") == "1", name
        assert isinstance(var.attrs.get("long_name"), str) and var.attrs["long_name"], name
    a = ds.attrs
    assert a["Conventions"] == "CF-1.10"
    assert a["source"] == f"bounce {bounce.__version__}" and a["bounce_version"] == bounce.__version__
    assert "Cherubini" in a["references"] and "Stopping Time" in a["references"]
    assert "rest length" in a["comment"] and "sqrt(m/2k)" in a["comment"]
    assert a["title"]
    assert re.fullmatch(r"[0-9a-f]{40}|unknown", a["git_commit"])
    assert a["git_dirty"] in ("true", "false", "unknown")
    assert (a["gamma"], a["mu"]) == (traj.params.gamma, traj.params.mu)
    dev = traj.initial.deviations(traj.params)
    state = traj.initial if isinstance(traj.initial, State) else dev.to_state(traj.params)
    assert (a["x0"], a["xdot0"], a["y0"], a["ydot0"]) == (state.x, state.xdot, state.y, state.ydot)
    assert (a["xidot0"], a["eta0"]) == (dev.xidot, dev.eta)
    assert a["stop_reason"] == traj.stop_reason
    assert a["t_end"] == traj.t_end and a["t_valid"] == traj.t_valid
    assert (a["max_events"], a["t_max"], a["energy_stop"]) == (
        traj.settings["max_events"], traj.settings["t_max"], traj.settings["energy_stop"])


def test_no_timestamps():
    ds = bio.to_dataset(RUNS["sticky"], np.linspace(0.0, 10.0, 11))
    date = re.compile(r"\d{4}-\d{2}-\d{2}|\d{2}:\d{2}:\d{2}")
    attrs = [ds.attrs] + [v.attrs for v in ds.variables.values()]
    for d in attrs:
        for key, value in d.items():
            assert not re.search(r"date|time_|history|created|timestamp", key, re.I), key
            assert not (isinstance(value, str) and date.search(value)), (key, value)


def test_kind_flags(tmp_path):
    traj = RUNS["sticky"]
    path = bio.write_netcdf(bio.to_dataset(traj), tmp_path / "k.nc")
    back = bio.read_dataset(path)
    kind = back.kind
    assert kind.dtype == np.int8
    assert kind.attrs["flag_meanings"] == "impact grazing sticky_start detach"
    assert kind.attrs["flag_meanings"].split() == list(KIND_NAMES)
    np.testing.assert_array_equal(kind.attrs["flag_values"], [0, 1, 2, 3])
    assert np.asarray(kind.attrs["flag_values"]).dtype == np.int8
    names = [KIND_NAMES[k] for k in kind.values]
    assert names[:2] == ["sticky_start", "detach"] and "impact" in names
    assert back.t.values[0] == 0.0


def test_file_format(tmp_path):
    import netCDF4

    path = bio.write_netcdf(bio.to_dataset(RUNS["impacts"], np.linspace(0, 5, 6)), tmp_path / "f.nc")
    with netCDF4.Dataset(path) as nc:
        assert nc.data_model == "NETCDF4"
        for name in EVENT_VARS:
            var = nc[name]
            assert var.dtype == (np.int8 if name == "kind" else np.float64)
            assert var.filters()["zlib"], name
            assert "_FillValue" not in var.ncattrs(), name
        assert nc["time"].dtype == np.float64


def test_two_writes_identical(tmp_path):
    traj = RUNS["sticky"]
    times = np.linspace(0.0, 100.0, 201)
    a = bio.write_netcdf(bio.to_dataset(traj, times), tmp_path / "a.nc")
    b = bio.write_netcdf(bio.to_dataset(traj, times), tmp_path / "b.nc")
    assert a.read_bytes() == b.read_bytes()
    assert bio.read_dataset(a).identical(bio.read_dataset(b))


def test_overwrite_replaces(tmp_path):
    path = tmp_path / "run.nc"
    bio.write_netcdf(bio.to_dataset(RUNS["impacts"]), path)
    bio.write_netcdf(bio.to_dataset(RUNS["sticky"]), path)
    assert bio.read_dataset(path).identical(bio.to_dataset(RUNS["sticky"]))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.nc"]


class Boom(RuntimeError):
    pass


def _failing_to_netcdf(self, path, *args, **kwargs):
    """Start a real file, then fail midway."""
    with open(path, "wb") as fh:
        fh.write(b"\x89HDF\r\n\x1a\npartial")
    raise Boom("disk full")


def test_failed_write_leaves_nothing(tmp_path, monkeypatch):
    monkeypatch.setattr(xr.Dataset, "to_netcdf", _failing_to_netcdf)
    with pytest.raises(Boom):
        bio.write_netcdf(bio.to_dataset(RUNS["impacts"]), tmp_path / "run.nc")
    assert list(tmp_path.iterdir()) == []


def test_failed_write_keeps_old_file(tmp_path, monkeypatch):
    path = bio.write_netcdf(bio.to_dataset(RUNS["impacts"]), tmp_path / "run.nc")
    before = path.read_bytes()
    monkeypatch.setattr(xr.Dataset, "to_netcdf", _failing_to_netcdf)
    with pytest.raises(Boom):
        bio.write_netcdf(bio.to_dataset(RUNS["sticky"]), path)
    assert path.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.nc"]


def test_failed_replace_leaves_nothing(tmp_path, monkeypatch):
    def fail(src, dst):
        raise OSError("rename failed")

    monkeypatch.setattr(bio.os, "replace", fail)
    with pytest.raises(OSError, match="rename failed"):
        bio.write_netcdf(bio.to_dataset(RUNS["impacts"]), tmp_path / "run.nc")
    assert list(tmp_path.iterdir()) == []


def test_interrupted_write_leaves_nothing(tmp_path, monkeypatch):
    def interrupt(self, path, *args, **kwargs):
        open(path, "wb").close()
        raise KeyboardInterrupt

    monkeypatch.setattr(xr.Dataset, "to_netcdf", interrupt)
    with pytest.raises(KeyboardInterrupt):
        bio.write_netcdf(bio.to_dataset(RUNS["impacts"]), tmp_path / "run.nc")
    assert list(tmp_path.iterdir()) == []


def test_bad_output_paths(tmp_path):
    ds = bio.to_dataset(RUNS["impacts"])
    with pytest.raises(FileNotFoundError, match="does not exist"):
        bio.write_netcdf(ds, tmp_path / "missing" / "run.nc")
    (tmp_path / "file").write_text("x")
    with pytest.raises(NotADirectoryError, match="not a directory"):
        bio.write_netcdf(ds, tmp_path / "file" / "run.nc")
    with pytest.raises(IsADirectoryError):
        bio.write_netcdf(ds, tmp_path)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file"]


def test_unwritable_directory(tmp_path, monkeypatch):
    def denied(directory):
        raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(bio, "_probe_writable", denied)
    with pytest.raises(PermissionError, match="not writable"):
        bio.write_netcdf(bio.to_dataset(RUNS["impacts"]), tmp_path / "run.nc")
    assert list(tmp_path.iterdir()) == []


def test_from_dataset_rejects_foreign_data():
    with pytest.raises(bio.DatasetError, match="missing"):
        bio.from_dataset(xr.Dataset({"t": ("event", [1.0])}))
    ds = bio.to_dataset(RUNS["impacts"])
    ds.attrs["eta0"] = ds.attrs["eta0"] + 1e-3
    with pytest.raises(bio.DatasetError, match="inconsistent"):
        bio.from_dataset(ds)


def test_bad_sample_times():
    with pytest.raises(ValueError, match="finite"):
        bio.to_dataset(RUNS["impacts"], [0.0, np.nan])
    with pytest.raises(ValueError, match="one-dimensional"):
        bio.to_dataset(RUNS["impacts"], np.zeros((2, 2)))


def test_thinned_dataset(tmp_path):
    """Scenes keep the first events and a log-spaced selection: exact samples up to the prefix, NaN after."""
    traj = RUNS["impacts"]
    ds = bio.to_dataset(traj)
    ds = ds.assign_coords(event=np.arange(ds.sizes["event"]))
    ds.attrs["n_events_simulated"] = len(traj)
    keep = [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 15, 25, len(traj) - 1]
    thin = bio.read_dataset(bio.write_netcdf(ds.isel(event=keep), tmp_path / "thin.nc"))
    assert bio.complete_prefix(thin) == 10 and bio.complete_prefix(ds) == len(traj)
    with pytest.raises(bio.DatasetError, match="thinned"):
        bio.from_dataset(thin)
    times = _times(traj)
    got = bio.sample_dataset(thin, times)
    expected = sample_trajectory(traj, times)
    inside = times <= traj.t[9]
    for key, value in expected.items():
        assert _same_bits(got[key][inside], value[inside]), key
        assert np.isnan(got[key][~inside]).all(), key
    # the full dataset with an event coordinate is complete
    full = bio.sample_dataset(ds, times)
    for key, value in expected.items():
        assert _same_bits(full[key], value), key
    # thinned without saying which events were kept
    anonymous = ds.drop_vars("event").isel(event=keep)
    with pytest.raises(bio.DatasetError, match="no 'event' coordinate"):
        bio.sample_dataset(anonymous, times)

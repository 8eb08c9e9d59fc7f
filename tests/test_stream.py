"""Runs in chunks (bounce.stream): bit for bit the one-shot run, streamed to netCDF, thinned, resumed,
and the memory refusal of the CLI."""

from __future__ import annotations

import math

import numpy as np
import pytest

import bounce.stream as stream
from bounce import Parameters, State, simulate
from bounce.cli import main
from bounce.io import read_dataset, read_trajectory, to_dataset
from bounce.model import InputError
from bounce.scenes import kept_events

FIELDS = ("t", "tau", "xdot", "xidot", "eta", "energy_excess", "kind")

# (params, initial, stop): the chaotic drop, a sticky start at t = 0 with detachments (eq. sticky-ic),
# an over-damped drop stopped by energy, a drop stopped by t_max
CASES = {
    "drop": (Parameters(0.01, 0.01), State.from_psi_xi(6.0, 0.0, 0.0, 0.0), {"max_events": 5000}),
    "sticky": (Parameters(0.01, 0.01), None, {"max_events": 3000, "t_max": 400.0}),
    "energy": (Parameters(1e-5, 2.0), State.from_psi_xi(0.25, 0.0, 0.0, 0.0), {"max_events": 4000, "energy_stop": 3e-11}),
    "t_max": (Parameters(0.01, 0.3), State.from_psi_xi(2.0, 0.0, 0.0, 0.0), {"max_events": 10**6, "t_max": 150.0}),
}


def _case(name):
    params, initial, stop = CASES[name]
    if initial is None:
        initial = State.sticky_ic(params, eps=0.0, ydot0=-0.1)
    return params, initial, stop


def _assert_same(a, b):
    for f in FIELDS:
        x, y = getattr(a, f), getattr(b, f)
        assert x.dtype == y.dtype and np.array_equal(x, y), f
    assert (a.stop_reason, a.t_end) == (b.stop_reason, b.t_end)


@pytest.mark.parametrize("name", sorted(CASES))
@pytest.mark.parametrize("chunk", [1, 7, 1000])
def test_chunked_equals_one_shot(name, chunk):
    params, initial, stop = _case(name)
    one = simulate(params, initial, **stop)
    assert len(one) > 50
    _assert_same(stream.simulate_chunked(params, initial, chunk=chunk, progress=False, **stop), one)


def test_cases_cover_every_kind_and_stop():
    kinds, stops = set(), set()
    for name in CASES:
        params, initial, stop = _case(name)
        traj = simulate(params, initial, **stop)
        kinds |= set(traj.kind_names)
        stops.add(traj.stop_reason)
    assert {"impact", "sticky_start", "detach"} <= kinds
    assert {"max_events", "energy", "t_max"} <= stops


@pytest.mark.parametrize("name", sorted(CASES))
def test_streamed_file_equals_one_shot_dataset(name, tmp_path):
    params, initial, stop = _case(name)
    one = simulate(params, initial, **stop)
    out = tmp_path / "s.nc"
    summary = stream.stream_to_netcdf(params, initial, out, chunk=333, progress=False, **{
        "max_events": stop["max_events"], "t_max": stop.get("t_max", math.inf),
        "energy_stop": stop.get("energy_stop", 0.0)})
    assert summary["events"] == summary["records"] == len(one)
    assert summary["counts"]["impact"] == int(np.sum(one.kind == 0))
    assert not stream.partial_path(out).exists()
    ds, ref = read_dataset(out), to_dataset(one)
    for var in ref.data_vars:
        assert np.array_equal(ds[var].values, ref[var].values), var
    for key in ("stop_reason", "t_end", "t_valid", "gamma", "mu", "eta0", "max_events"):
        assert ds.attrs[key] == ref.attrs[key], key
    assert not [k for k in ds.attrs if k.startswith("stream_")]
    _assert_same(read_trajectory(out), one)


def test_thinned_on_the_fly_keeps_the_scene_rule(tmp_path):
    params, initial, _ = _case("drop")
    n, keep = 20000, {"first": 500, "log_samples": 300}
    one = simulate(params, initial, max_events=n)
    out = tmp_path / "thin.nc"
    stream.stream_to_netcdf(params, initial, out, n, chunk=4096, keep=keep, progress=False)
    ds = read_dataset(out)
    idx = kept_events(n, keep)
    assert np.array_equal(ds["event"].values, idx)
    assert np.array_equal(ds["t"].values, one.t[idx]) and np.array_equal(ds["kind"].values, one.kind[idx])
    assert ds.attrs["n_events_simulated"] == n


@pytest.mark.parametrize("n, keep", [(20000, {"first": 1000, "log_samples": 1000}), (2000, None)])
def test_short_streamed_file_is_not_a_whole_file_chunk(n, keep, tmp_path):
    """HDF5 allocates a chunk whole: a stream that writes at most ~2,000 records (thinned, or --events 2000) is
    chunked by that bound, not by FILE_CHUNK records per variable (65,536 x 8 bytes each: 5.9 MB before)."""
    params, initial, _ = _case("drop")
    out = tmp_path / "short.nc"
    stream.stream_to_netcdf(params, initial, out, n, keep=keep, progress=False)
    ds = read_dataset(out)
    records, variables = ds.sizes["event"], len(ds.variables)
    assert records <= 2001
    assert out.stat().st_size < 1.5 * records * variables * 8 + 50_000, out.stat().st_size


class _Interrupt(Exception):
    pass


def test_resume_after_interruption_gives_the_same_records(tmp_path, monkeypatch):
    params, initial, _ = _case("sticky")
    n = 3000
    one = simulate(params, initial, max_events=n, t_max=400.0)
    out = tmp_path / "r.nc"
    real = stream.run_events
    calls = {"n": 0}

    def interrupted(*args):
        calls["n"] += 1
        if calls["n"] == 4:
            raise _Interrupt
        return real(*args)

    monkeypatch.setattr(stream, "run_events", interrupted)
    with pytest.raises(_Interrupt):
        stream.stream_to_netcdf(params, initial, out, n, t_max=400.0, chunk=40, progress=False)
    monkeypatch.setattr(stream, "run_events", real)
    assert not out.exists() and stream.partial_path(out).exists()
    with pytest.raises(InputError, match="different run"):
        stream.stream_to_netcdf(params, initial, out, n + 1, t_max=400.0, chunk=40, resume=True, progress=False)
    summary = stream.stream_to_netcdf(params, initial, out, n, t_max=400.0, chunk=40, resume=True, progress=False)
    assert summary["events"] == len(one)
    _assert_same(read_trajectory(out), one)


def test_resume_without_a_partial_file_is_refused(tmp_path):
    params, initial, _ = _case("drop")
    with pytest.raises(InputError, match="no interrupted run"):
        stream.stream_to_netcdf(params, initial, tmp_path / "x.nc", 10, resume=True, progress=False)


def test_memory_estimate_refuses_up_front(monkeypatch):
    monkeypatch.setattr(stream, "available_memory", lambda: 2 * 2**30)
    stream.check_memory(10_000_000)  # ~1 GB: fits
    with pytest.raises(InputError, match=r"--events 300000000 needs ~2\d\.\d GB .*--stream"):
        stream.check_memory(300_000_000)


def test_cli_refuses_too_many_events_before_simulating(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(stream, "available_memory", lambda: 2 * 2**30)
    out = tmp_path / "big.nc"
    code = main(["simulate", "--gamma", "0.01", "--mu", "0.01", "--psi0", "6", "--psidot0", "0", "--xi0", "0",
                 "--xidot0", "0", "--events", "3e8", "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("error: --events 300000000 needs ~") and "--stream" in err
    assert len(err.strip().splitlines()) == 1 and not list(tmp_path.iterdir())


def test_cli_stream_takes_more_events_than_memory_and_checks_the_chunk(tmp_path, capsys, monkeypatch):
    """--stream: --events is not bounded by memory (a chunk is), up to MAX_STREAM_EVENTS; a --chunk that does
    not fit is refused up front, with its estimate (the same check, 105 bytes per event of a chunk)."""
    monkeypatch.setattr(stream, "available_memory", lambda: 2 * 2**30)
    args = ["simulate", "--gamma", "0.01", "--mu", "0.01", "--psi0", "6", "--psidot0", "0", "--xi0", "0",
            "--xidot0", "0", "--stream", "--no-progress"]
    assert main([*args, "--events", "1e11", "--t-max", "50", "--out", str(tmp_path / "long.nc")]) == 0
    assert "stop: t_max" in capsys.readouterr().out
    code = main([*args, "--events", "1e11", "--chunk", "1e9", "--out", str(tmp_path / "big.nc")])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("error: --chunk 1000000000 needs ~") and "smaller --chunk" in err, err
    assert len(err.strip().splitlines()) == 1 and sorted(p.name for p in tmp_path.iterdir()) == ["long.nc"]


def test_cli_stream_equals_cli_one_shot(tmp_path, capsys):
    args = ["simulate", "--gamma", "0.01", "--mu", "0.01", "--psi0", "6", "--psidot0", "0", "--xi0", "0",
            "--xidot0", "0", "--events", "5000"]
    assert main([*args, "--out", str(tmp_path / "a.nc")]) == 0
    assert main([*args, "--out", str(tmp_path / "b.nc"), "--stream", "--chunk", "999", "--no-progress"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].split(";")[0] == lines[1].split(";")[0] == (
        "bounce: 5000 events (5000 impact), stop: max_events, t_end = " + lines[0].split("t_end = ")[1].split(";")[0])
    a, b = read_dataset(tmp_path / "a.nc"), read_dataset(tmp_path / "b.nc")
    for var in a.data_vars:
        assert np.array_equal(a[var].values, b[var].values), var


@pytest.mark.parametrize("extra, message", [
    (["--resume"], "--resume continues a --stream run"),
    (["--keep-first", "10"], "--keep-first and --keep-log go together"),
    (["--keep-first", "10", "--keep-log", "5"], "add --stream"),
    (["--stream", "--dt-sample", "0.1"], "does not combine with --stream"),
])
def test_cli_stream_usage_errors(extra, message, tmp_path, capsys):
    code = main(["simulate", "--gamma", "0.01", "--mu", "0.01", "--psi0", "6", "--psidot0", "0", "--xi0", "0",
                 "--xidot0", "0", "--events", "100", "--out", str(tmp_path / "u.nc"), *extra])
    assert code == 2 and message in capsys.readouterr().err
    assert not list(tmp_path.iterdir())


def test_cli_progress_bar_on_request_only(tmp_path, capsys):
    args = ["simulate", "--gamma", "0.01", "--mu", "0.01", "--psi0", "6", "--psidot0", "0", "--xi0", "0",
            "--xidot0", "0", "--events", "3000", "--chunk", "1000"]
    assert main([*args, "--out", str(tmp_path / "a.nc"), "--progress"]) == 0
    err = capsys.readouterr().err
    assert "100%" in err and "3.00k/3.00k" in err
    assert main([*args, "--out", str(tmp_path / "b.nc")]) == 0  # stderr is not a terminal here: no bar
    assert capsys.readouterr().err == ""
    a, b = read_dataset(tmp_path / "a.nc"), read_dataset(tmp_path / "b.nc")
    assert all(np.array_equal(a[v].values, b[v].values) for v in a.data_vars)


def test_cli_interrupted_stream_resumes(tmp_path, capsys, monkeypatch):
    args = ["simulate", "--gamma", "0.01", "--mu", "0.01", "--psi0", "6", "--psidot0", "0", "--xi0", "0",
            "--xidot0", "0", "--events", "5000", "--stream", "--chunk", "1000"]
    real = stream.run_events
    calls = {"n": 0}

    def interrupted(*a):
        calls["n"] += 1
        if calls["n"] == 3:
            raise KeyboardInterrupt
        return real(*a)

    monkeypatch.setattr(stream, "run_events", interrupted)
    out = tmp_path / "i.nc"
    assert main([*args, "--out", str(out)]) == 130
    err = capsys.readouterr().err
    assert err.startswith("error: interrupted;") and "--resume" in err and len(err.strip().splitlines()) == 1
    assert not out.exists() and stream.partial_path(out).exists()
    monkeypatch.setattr(stream, "run_events", real)
    assert main([*args, "--out", str(out), "--resume"]) == 0
    one = simulate(Parameters(0.01, 0.01), State.from_psi_xi(6.0, 0.0, 0.0, 0.0), max_events=5000)
    _assert_same(read_trajectory(out), one)

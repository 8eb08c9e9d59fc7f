"""Runs in chunks (bounce.stream): bit for bit the one-shot run, streamed to netCDF, thinned, resumed,
and the memory refusal of the CLI."""

from __future__ import annotations

import contextlib
import math
import os
import signal
import subprocess
import sys
import time

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
    """A run that needs every record in memory (--dt-sample) is refused up front when they would not fit."""
    monkeypatch.setattr(stream, "available_memory", lambda: 2 * 2**30)
    out = tmp_path / "big.nc"
    code = main(["simulate", "--gamma", "0.01", "--mu", "0.01", "--psi0", "6", "--psidot0", "0", "--xi0", "0",
                 "--xidot0", "0", "--events", "3e8", "--dt-sample", "1", "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("error: --events 300000000 needs ~") and "no --dt-sample" in err
    assert len(err.strip().splitlines()) == 1 and not list(tmp_path.iterdir())


def test_cli_streams_by_default_past_one_chunk(tmp_path, capsys, monkeypatch):
    """Memory is bounded by default (issue 22): without --stream a closed-form run of more events than --chunk
    streams (here where its one-shot records would not fit), gives the one-shot run's records, and an interrupted
    one resumes with the same command and --resume; up to one chunk it runs in one call, as before."""
    monkeypatch.setattr(stream, "available_memory", lambda: 2 * 2**30)
    monkeypatch.setattr(stream, "free_disk", lambda path: 10**12)
    args = ["simulate", "--gamma", "0.01", "--mu", "0.01", "--psi0", "6", "--psidot0", "0", "--xi0", "0",
            "--xidot0", "0", "--no-progress"]
    assert main([*args, "--events", "3e8", "--t-max", "30", "--out", str(tmp_path / "long.nc")]) == 0
    assert "stop: t_max" in capsys.readouterr().out
    assert main([*args, "--events", "5000", "--chunk", "1000", "--out", str(tmp_path / "auto.nc")]) == 0
    assert "(5000 records)" in capsys.readouterr().out  # the stream's summary
    assert main([*args, "--events", "5000", "--out", str(tmp_path / "one.nc")]) == 0
    assert "records)" not in capsys.readouterr().out
    auto, one = (read_dataset(tmp_path / name) for name in ("auto.nc", "one.nc"))
    for name in ("t", "tau", "xdot", "xidot", "eta", "energy_excess", "kind"):
        np.testing.assert_array_equal(auto[name].values, one[name].values)
    code = main([*args, "--events", "100", "--resume", "--out", str(tmp_path / "short.nc")])
    assert code == 2 and "--resume continues a streamed run" in capsys.readouterr().err


def test_cli_stream_takes_more_events_than_memory_and_checks_the_chunk(tmp_path, capsys, monkeypatch):
    """--stream: --events is not bounded by memory (a chunk is), up to MAX_STREAM_EVENTS; a --chunk that does
    not fit is refused up front, with its estimate (the same check, 105 bytes per event of a chunk)."""
    monkeypatch.setattr(stream, "available_memory", lambda: 2 * 2**30)
    monkeypatch.setattr(stream, "free_disk", lambda path: 10**16)  # 1e11 records would fit (check_disk)
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
    (["--resume"], "--resume continues a streamed run"),
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


@pytest.mark.parametrize("flag", [["--stream"], []], ids=["stream", "default"])
def test_cli_interrupted_stream_resumes(flag, tmp_path, capsys, monkeypatch):
    """Also without --stream: a run of more events than --chunk streams by default and resumes alike."""
    args = ["simulate", "--gamma", "0.01", "--mu", "0.01", "--psi0", "6", "--psidot0", "0", "--xi0", "0",
            "--xidot0", "0", "--events", "5000", *flag, "--chunk", "1000"]
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
    assert err.startswith("error: interrupted (SIGINT);") and "--resume" in err and len(err.strip().splitlines()) == 1
    assert not out.exists() and stream.partial_path(out).exists()
    monkeypatch.setattr(stream, "run_events", real)
    assert main([*args, "--out", str(out), "--resume"]) == 0
    one = simulate(Parameters(0.01, 0.01), State.from_psi_xi(6.0, 0.0, 0.0, 0.0), max_events=5000)
    _assert_same(read_trajectory(out), one)


# --------------------------------------------------------------------------- the partial file (issue 25)

DROP = ["simulate", "--gamma", "0.01", "--mu", "0.01", "--psi0", "6", "--psidot0", "0", "--xi0", "0", "--xidot0", "0"]


def _cli(argv, capsys):
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


def _one_line_error(err, *words):
    lines = err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and "Traceback" not in err, err
    assert all(w in lines[0] for w in words), err


def _interrupted_partial(tmp_path, capsys, monkeypatch, at_call, extra=()):
    """``tmp_path/run.nc.partial`` of the drop (5000 events, chunks of 1000) interrupted at its
    ``at_call``-th chunk (1: only the header written); returns the out path and the partial's bytes."""
    real = stream.run_events
    calls = {"n": 0}

    def interrupted(*a):
        calls["n"] += 1
        if calls["n"] == at_call:
            raise KeyboardInterrupt
        return real(*a)

    monkeypatch.setattr(stream, "run_events", interrupted)
    out = tmp_path / "run.nc"
    code, _, err = _cli([*DROP, "--events", "5000", "--stream", "--chunk", "1000", *extra, "--out", str(out)], capsys)
    monkeypatch.setattr(stream, "run_events", real)
    assert code == 130 and "--resume" in err
    part = stream.partial_path(out)
    return out, part.read_bytes()


@pytest.mark.parametrize("kind", ["symlink_to_file", "dangling_symlink"])
def test_partial_that_is_a_link_is_refused(kind, tmp_path, capsys):
    """Issue 25 item 3: --out is refused when it is a symbolic link; so is its partial file, which used to be
    followed (the link's target overwritten) or, dangling, to create a file where it pointed."""
    target = tmp_path / "elsewhere.nc"
    if kind == "symlink_to_file":
        target.write_bytes(b"keep")
    stream.partial_path(tmp_path / "run.nc").symlink_to(target)
    before = sorted(p.name for p in tmp_path.iterdir())
    code, out, err = _cli([*DROP, "--events", "3000", "--stream", "--out", str(tmp_path / "run.nc")], capsys)
    assert code == 2 and out == ""
    _one_line_error(err, "--out", "symbolic link", "run.nc.partial")
    assert sorted(p.name for p in tmp_path.iterdir()) == before
    assert stream.partial_path(tmp_path / "run.nc").is_symlink()
    assert target.read_bytes() == b"keep" if kind == "symlink_to_file" else not target.exists()


def test_partial_that_is_a_fifo_is_refused(tmp_path):
    """Issue 25 item 3: a FIFO at the partial file's name is refused at once (the run used to hang on it once
    the pipe's buffer was full); in a real process, so that a hang fails the test instead of holding it."""
    part = stream.partial_path(tmp_path / "run.nc")
    os.mkfifo(part)
    env = {**os.environ, "PYTHONWARNINGS": "ignore"}
    try:
        done = subprocess.run([sys.executable, "-m", "bounce", *DROP, "--events", "3000", "--stream",
                               "--out", str(tmp_path / "run.nc")], capture_output=True, text=True, env=env, timeout=60)
    finally:
        os.unlink(part)  # a hung writer blocks in open() no more once the FIFO is gone
    assert done.returncode == 2 and done.stdout == ""
    _one_line_error(done.stderr, "--out", "FIFO", "run.nc.partial")
    assert list(tmp_path.iterdir()) == []


def test_partial_hard_link_keeps_its_other_name(tmp_path, capsys):
    """Issue 25 item 3: a new run replaces an existing partial file (an atomic header); it used to write into
    it, through every other name of the same file.  Resuming a partial file with another name is refused:
    appending would change both."""
    other = tmp_path / "other.nc"
    other.write_bytes(b"keep")
    os.link(other, stream.partial_path(tmp_path / "run.nc"))
    code, _, err = _cli([*DROP, "--events", "3000", "--stream", "--chunk", "1000", "--out", str(tmp_path / "run.nc"),
                         "--resume"], capsys)
    assert code == 2
    _one_line_error(err, "--resume", "hard links")
    assert other.read_bytes() == b"keep"
    assert _cli([*DROP, "--events", "3000", "--stream", "--out", str(tmp_path / "run.nc")], capsys)[0] == 0
    assert other.read_bytes() == b"keep"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["other.nc", "run.nc"]
    assert read_dataset(tmp_path / "run.nc").sizes["event"] == 3000


@pytest.mark.parametrize("at_call", [1, 3], ids=["header-only", "two-chunks"])
@pytest.mark.parametrize("change, named", [
    (["--psi0", "7"], "x0"),
    (["--mu", "0.02"], "mu"),
    (["--events", "6000"], "max_events"),
    (["--compression", "zlib"], "compression"),
    (["--keep-first", "100", "--keep-log", "50"], "events_kept"),
])
def test_resume_refuses_another_run(change, named, at_call, tmp_path, capsys, monkeypatch):
    """Issue 25 item 7: --resume checks every parameter, the initial state, the stop rules, the thinning and
    the codec against the partial file and names what differs; the partial file is left as it was.  A
    changed state or codec used to be resumed silently: the records of one run under the attributes of the
    other (header only), or the old run under the new command (two chunks)."""
    out, before = _interrupted_partial(tmp_path, capsys, monkeypatch, at_call)
    argv = dict(zip(DROP[1::2], DROP[2::2]))
    argv.update({"--events": "5000", **dict(zip(change[::2], change[1::2]))})
    code, stdout, err = _cli(["simulate", *[x for kv in argv.items() for x in kv], "--stream", "--chunk", "1000",
                              "--resume", "--out", str(out)], capsys)
    assert code == 2 and stdout == ""
    _one_line_error(err, "--resume", "different run", named)
    assert stream.partial_path(out).read_bytes() == before and not out.exists()


def test_resume_of_a_damaged_partial_is_refused(tmp_path, capsys, monkeypatch):
    """Issue 25 item 10: a truncated partial file gives one line saying so (it gave "NetCDF: HDF error")."""
    out, before = _interrupted_partial(tmp_path, capsys, monkeypatch, 3)
    part = stream.partial_path(out)
    part.write_bytes(before[: len(before) // 2])
    code, _, err = _cli([*DROP, "--events", "5000", "--stream", "--chunk", "1000", "--resume", "--out", str(out)],
                        capsys)
    assert code == 2
    _one_line_error(err, "--resume", "truncated or damaged", "without --resume")
    assert part.read_bytes() == before[: len(before) // 2] and not out.exists()


def test_full_disk_removes_the_partial(small_disk, capsys, monkeypatch):
    """Issue 25 item 2: a stream filling a 2 MiB file system says the disk is full and removes the partial
    file (it said "NetCDF: HDF error" and left the partial file filling the disk).  The disk is made to look free
    to the up-front check (check_disk), as when another process fills it during the run."""
    monkeypatch.setattr(stream, "free_disk", lambda path: 10**12)
    code, out, err = _cli([*DROP, "--events", "1e5", "--stream", "--chunk", "10000",
                           "--out", str(small_disk / "run.nc")], capsys)
    assert code == 1 and out == ""
    _one_line_error(err, "disk full", "partial file was removed", "no file was written")
    assert list(small_disk.iterdir()) == []


def test_stream_on_a_full_disk(small_disk, capsys, monkeypatch):
    """Issue 25 item 2: with no space left at all it said "Permission denied" (or "NetCDF: HDF error"); the disk
    looks free to the up-front check, as above, and the up-front check itself refuses it (exit 2)."""
    with open(small_disk / "fill", "wb", buffering=0) as fh, contextlib.suppress(OSError):
        while True:
            fh.write(b"\0" * 4096)
    code, out, err = _cli([*DROP, "--events", "1000", "--stream", "--out", str(small_disk / "run.nc")], capsys)
    assert code == 2 and "--events 1000 would write up to" in err and [p.name for p in small_disk.iterdir()] == ["fill"]
    monkeypatch.setattr(stream, "free_disk", lambda path: 10**12)
    code, out, err = _cli([*DROP, "--events", "1000", "--stream", "--out", str(small_disk / "run.nc")], capsys)
    assert code == 1 and out == ""
    _one_line_error(err, "disk full", "no file was written")
    assert [p.name for p in small_disk.iterdir()] == ["fill"]


_STREAM_RUN = [sys.executable, "-m", "bounce", *DROP, "--events", "1e6", "--stream", "--chunk", "100000"]


@pytest.mark.slow
def test_second_stream_to_the_same_out_is_refused(tmp_path):
    """Issue 25 item 8: while a --stream run writes FILE.nc.partial (stopped by SIGSTOP meanwhile, so that it
    is still there), a second run to the same --out, or a --resume of it, is refused with one line naming the
    first's pid; the first, continued, completes its file.  Both used to fail and leave a damaged partial file
    (the second truncated it under the first)."""
    out = tmp_path / "run.nc"
    env = {**os.environ, "PYTHONWARNINGS": "ignore"}
    first = subprocess.Popen([*_STREAM_RUN, "--out", str(out)], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True, env=env)
    try:
        deadline = time.monotonic() + 120
        while not stream.partial_path(out).exists():
            assert first.poll() is None and time.monotonic() < deadline, first.communicate()
            time.sleep(0.01)
        first.send_signal(signal.SIGSTOP)
        for extra in ([], ["--resume"]):
            second = subprocess.run([*_STREAM_RUN, "--out", str(out), *extra], capture_output=True, text=True,
                                    env=env, timeout=120)
            assert second.returncode == 2 and second.stdout == ""
            _one_line_error(second.stderr, "--out", "another bounce --stream run", f"pid {first.pid}")
        first.send_signal(signal.SIGCONT)
        stdout, stderr = first.communicate(timeout=300)
    finally:
        first.kill()
    assert first.returncode == 0, stderr
    assert "1000000 events" in stdout
    assert read_dataset(out).sizes["event"] == 1_000_000
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.nc"]


def test_streamed_run_that_could_not_fit_on_the_disk_is_refused_up_front(tmp_path, capsys, monkeypatch):
    """A streamed run (by default past one chunk) is refused before simulating when its --events could not fit on
    the disk of --out (81 bytes per event); thinned, only the kept events count.  Found when the default stream let
    the fuzz's --events 1e10 write 26 GB to /tmp."""
    monkeypatch.setattr(stream, "free_disk", lambda path: 10**9)
    args = ["simulate", "--gamma", "0.01", "--mu", "0.01", "--psi0", "6", "--psidot0", "0", "--xi0", "0",
            "--xidot0", "0", "--no-progress"]
    code = main([*args, "--events", "1e8", "--out", str(tmp_path / "big.nc")])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("error: --events 100000000 would write up to ~8.1 GB") and "--keep-first" in err
    assert len(err.strip().splitlines()) == 1 and not list(tmp_path.iterdir())
    assert main([*args, "--events", "1e8", "--t-max", "30", "--stream", "--keep-first", "100", "--keep-log", "100",
                 "--out", str(tmp_path / "thin.nc")]) == 0
    assert "stop: t_max" in capsys.readouterr().out

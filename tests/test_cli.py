"""Command line: one-line errors naming the parameter, no file on failure, valid files on success."""

from __future__ import annotations

import os
import pathlib
import re
import signal
import stat
import subprocess
import sys
import time

import numpy as np
import pytest

import bounce.io as bio
from bounce import Parameters, State, simulate
from bounce.cli import main

GOOD = ["--gamma", "0.01", "--mu", "0.01", "--x0", "6", "--xdot0", "0", "--y0", "7", "--ydot0", "0"]
PSI = ["--psi0", "6", "--psidot0", "0", "--xi0", "0", "--xidot0", "0"]


def _with(**changes):
    """GOOD with some options replaced (value None removes the option)."""
    opts = dict(zip(GOOD[::2], GOOD[1::2]))
    for key, value in changes.items():
        opts["--" + key] = value
    return [x for k, v in opts.items() if v is not None for x in (k, v)]


BAD = {
    "gamma_negative": (_with(gamma="-1"), "gamma"),
    "gamma_zero": (_with(gamma="0"), "gamma"),
    "gamma_nan": (_with(gamma="nan"), "gamma"),
    "gamma_inf": (_with(gamma="inf"), "gamma"),
    "gamma_text": (_with(gamma="abc"), "gamma"),
    "gamma_minus_inf": (_with(gamma="-inf"), "gamma"),
    "gamma_minus_exponent": (_with(gamma="-1e-3"), "gamma"),
    "gamma_missing": (_with(gamma=None), "gamma"),
    "mu_negative": (_with(mu="-0.5"), "mu"),
    "mu_nan": (_with(mu="nan"), "mu"),
    "x0_negative": (_with(x0="-1"), "x0"),
    "x0_nan": (_with(x0="nan"), "x0"),
    "ydot0_inf": (_with(ydot0="inf"), "ydot0"),
    "down_on_floor": (_with(x0="0", xdot0="-1"), "xdot0"),
    "psi_below_floor": (GOOD[:4] + ["--psi0", "0", "--psidot0", "0", "--xi0", "1", "--xidot0", "0"], "x0"),
    "psi_overflow": (GOOD[:4] + ["--psi0", "1e308", "--psidot0", "0", "--xi0", "-1e308", "--xidot0", "0"], "psi0"),
    "psi0_nan": (GOOD[:4] + ["--psi0", "nan", "--psidot0", "0", "--xi0", "0", "--xidot0", "0"], "psi0"),
    "forms_mixed": (GOOD + ["--psi0", "6"], "psi0"),
    "state_incomplete": (_with(ydot0=None), "ydot0"),
    "psi_incomplete": (GOOD[:4] + PSI[:6], "xidot0"),
    "state_missing": (GOOD[:4], "x0"),
    "events_zero": (GOOD + ["--events", "0"], "events"),
    "events_fraction": (GOOD + ["--events", "1.5"], "events"),
    "events_text": (GOOD + ["--events", "many"], "events"),
    "t_max_zero": (GOOD + ["--t-max", "0"], "t-max"),
    "t_max_nan": (GOOD + ["--t-max", "nan"], "t-max"),
    "energy_stop_negative": (GOOD + ["--energy-stop", "-1"], "energy-stop"),
    "dt_zero": (GOOD + ["--dt-sample", "0"], "dt-sample"),
    "dt_negative": (GOOD + ["--dt-sample", "-0.1"], "dt-sample"),
    "dt_nan": (GOOD + ["--dt-sample", "nan"], "dt-sample"),
    "dt_too_small": (GOOD + ["--t-max", "100", "--dt-sample", "1e-9"], "dt-sample"),
    "unknown_option": (GOOD + ["--bogus", "1"], "--bogus"),
}


def _run(argv, capsys):
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


def _check_error(code, err, name):
    assert code != 0
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("error: ") and name in lines[0], err
    assert "Traceback" not in err


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_input(case, tmp_path, capsys):
    argv, name = BAD[case]
    out = tmp_path / "run.nc"
    code, stdout, err = _run(["simulate", *argv, "--out", str(out)], capsys)
    _check_error(code, err, name)
    assert stdout == ""
    assert list(tmp_path.iterdir()) == []


def test_missing_out(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, _, err = _run(["simulate", *GOOD], capsys)
    _check_error(code, err, "--out")
    assert list(tmp_path.iterdir()) == []


def test_missing_command(capsys):
    code, _, err = _run([], capsys)
    _check_error(code, err, "COMMAND")


def test_every_command_is_listed(capsys):
    """--help and the unknown-command error name both commands (`check` is dispatched before argparse)."""
    assert main(["--help"]) == 0
    out = capsys.readouterr().out
    assert "simulate" in out and "check" in out, out
    code, _, err = _run(["frobnicate"], capsys)
    _check_error(code, err, "COMMAND")
    assert "'check'" in err and "'simulate'" in err, err


@pytest.mark.parametrize("where", ["missing_dir", "parent_is_file", "is_directory"])
def test_bad_output_path(where, tmp_path, capsys):
    (tmp_path / "file").write_text("x")
    target = {"missing_dir": tmp_path / "missing" / "run.nc",
              "parent_is_file": tmp_path / "file" / "run.nc",
              "is_directory": tmp_path}[where]
    code, _, err = _run(["simulate", *GOOD, "--out", str(target)], capsys)
    _check_error(code, err, "--out")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file"]


def test_unwritable_directory(tmp_path, capsys, monkeypatch):
    calls = []
    monkeypatch.setattr("bounce.cli.simulate", lambda *a, **k: calls.append(a))  # must not be reached

    def denied(directory):
        raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(bio, "_probe_writable", denied)
    code, _, err = _run(["simulate", *GOOD, "--out", str(tmp_path / "run.nc")], capsys)
    _check_error(code, err, "--out")
    assert "not writable" in err and calls == []
    assert list(tmp_path.iterdir()) == []


@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() == 0, reason="root can write anywhere")
def test_read_only_directory(tmp_path, capsys):
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o555)
    try:
        code, _, err = _run(["simulate", *GOOD, "--out", str(ro / "run.nc")], capsys)
        _check_error(code, err, "--out")
        assert list(ro.iterdir()) == []
    finally:
        ro.chmod(0o755)


def test_failed_write_exits_nonzero(tmp_path, capsys, monkeypatch):
    def fail(self, path, *args, **kwargs):
        open(path, "wb").close()
        raise OSError(28, "No space left on device")

    monkeypatch.setattr("xarray.Dataset.to_netcdf", fail)
    code, out, err = _run(["simulate", *GOOD, "--events", "5", "--out", str(tmp_path / "run.nc")], capsys)
    _check_error(code, err, "No space left")
    assert out == "" and list(tmp_path.iterdir()) == []


def test_good_run(tmp_path, capsys):
    path = tmp_path / "run.nc"
    code, out, err = _run(["simulate", *GOOD, "--events", "20", "--out", str(path)], capsys)
    assert code == 0 and err == ""
    assert len(out.splitlines()) == 1
    assert "20 events" in out and "max_events" in out and str(path) in out
    ds = bio.read_dataset(path)
    assert ds.sizes["event"] == 20 and "time" not in ds.dims
    assert (ds.attrs["gamma"], ds.attrs["mu"], ds.attrs["x0"], ds.attrs["y0"]) == (0.01, 0.01, 6.0, 7.0)
    assert ds.attrs["stop_reason"] == "max_events" and ds.attrs["max_events"] == 20
    assert list(tmp_path.iterdir()) == [path]


def test_summary_is_one_line_whatever_the_name(tmp_path, capsys):
    """Issue 25 item 10: a newline in --out (a legal file name) split the summary line; such a name is
    printed quoted, with escapes."""
    path = tmp_path / "two\nlines.nc"
    code, out, err = _run(["simulate", *GOOD, "--events", "3", "--out", str(path)], capsys)
    assert code == 0 and err == "" and path.exists()
    assert len(out.splitlines()) == 1 and out.rstrip("\n").endswith(f"wrote {str(path)!r}")


def test_psi_form_equals_xy_form(tmp_path, capsys):
    a, b = tmp_path / "xy.nc", tmp_path / "psi.nc"
    assert main(["simulate", *GOOD, "--events", "20", "--out", str(a)]) == 0
    assert main(["simulate", *GOOD[:4], *PSI, "--events", "20", "--out", str(b)]) == 0
    capsys.readouterr()
    assert a.read_bytes() == b.read_bytes()


def test_negative_exponent_values(tmp_path, capsys):
    path = tmp_path / "run.nc"
    argv = ["simulate", "--gamma", "1e-2", "--mu", "1e-2", "--x0", "6", "--xdot0", "-1e-1", "--y0", "7",
            "--ydot0", "-2E-1", "--events", "3", "--out", str(path)]
    assert main(argv) == 0
    capsys.readouterr()
    a = bio.read_dataset(path).attrs
    assert (a["xdot0"], a["ydot0"]) == (-0.1, -0.2)


def test_dt_sample(tmp_path, capsys):
    path = tmp_path / "run.nc"
    argv = ["simulate", *GOOD, "--events", "30", "--energy-stop", "0", "--dt-sample", "0.5", "--out", str(path)]
    code, out, _ = _run(argv, capsys)
    assert code == 0 and "samples" in out
    ds = bio.read_dataset(path)
    t_valid = ds.attrs["t_valid"]
    times = ds.time.values
    assert times[0] == 0.0 and times[-1] <= t_valid < times[-1] + 0.5
    np.testing.assert_array_equal(times, np.arange(len(times)) * 0.5)
    for name in bio.SAMPLED_VARIABLES:
        assert ds[name].dims == ("time",) and not np.isnan(ds[name].values).any()
    assert ds.sampled_x.values[0] == 6.0 and ds.sampled_y.values[0] == 7.0
    s = bio.sample_dataset(ds, times)
    np.testing.assert_array_equal(s["x"], ds.sampled_x.values)


def test_dt_sample_t_max(tmp_path, capsys):
    path = tmp_path / "run.nc"
    argv = ["simulate", *GOOD, "--t-max", "50", "--dt-sample", "1", "--out", str(path)]
    assert main(argv) == 0
    capsys.readouterr()
    ds = bio.read_dataset(path)
    assert ds.attrs["stop_reason"] == "t_max" and ds.attrs["t_valid"] == 50.0
    np.testing.assert_array_equal(ds.time.values, np.arange(51.0))


def test_dt_sample_at_rest(tmp_path, capsys):
    # at rest on the floor at equilibrium: sticky from t = 0 on
    rest = ["simulate", "--gamma", "0.01", "--mu", "0.01", "--x0", "0", "--xdot0", "0", "--y0", "0.98",
            "--ydot0", "0", "--dt-sample", "1"]
    a, b = tmp_path / "a.nc", tmp_path / "b.nc"
    assert main([*rest, "--out", str(a)]) == 0
    assert main([*rest, "--t-max", "3", "--out", str(b)]) == 0
    capsys.readouterr()
    ds = bio.read_dataset(a)  # sticky forever, no t_max: samples up to the last event
    assert ds.attrs["stop_reason"] == "sticky_forever" and ds.attrs["t_valid"] == np.inf
    np.testing.assert_array_equal(ds.time.values, [0.0])
    ds = bio.read_dataset(b)
    np.testing.assert_array_equal(ds.time.values, [0.0, 1.0, 2.0, 3.0])
    np.testing.assert_array_equal(ds.sampled_x.values, 0.0)
    np.testing.assert_allclose(ds.sampled_y_minus_yeq.values, 0.0, atol=1e-15)  # y0 = 0.98 is rounded


@pytest.mark.parametrize("argv, name", [(["--bogus"], "--bogus"), (["a", "b"], "b"), (["--data"], "--data")])
def test_check_command_bad_arguments_one_line(argv, name, capsys):
    """Issue 25 item 10: ``bounce check`` with bad arguments printed argparse's 4-line usage."""
    code, out, err = _run(["check", *argv], capsys)
    _check_error(code, err, name)
    assert code == 2 and out == ""


def test_help(capsys):
    assert main(["simulate", "--help"]) == 0
    assert "--psi0" in capsys.readouterr().out


def test_module_entry_point(tmp_path):
    env = {**os.environ, "PYTHONWARNINGS": "ignore"}
    path = tmp_path / "run.nc"
    good = subprocess.run(
        [sys.executable, "-m", "bounce", "simulate", *GOOD, "--events", "10", "--out", str(path)],
        capture_output=True, text=True, env=env, timeout=120,
    )
    assert good.returncode == 0, good.stderr
    assert len(good.stdout.splitlines()) == 1 and good.stderr == ""
    assert bio.read_dataset(path).sizes["event"] == 10
    bad = subprocess.run(
        [sys.executable, "-m", "bounce", "simulate", *_with(gamma="-1"), "--out", str(tmp_path / "bad.nc")],
        capture_output=True, text=True, env=env, timeout=120,
    )
    assert bad.returncode == 2 and bad.stdout == ""
    assert bad.stderr.splitlines() == ["error: gamma must be > 0 (allowed range: (0, inf)), got -1.0"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.nc"]


# --------------------------------------------------------------------------- edges (issue 12)

EDGE_BAD = {
    "gamma_subnormal": (_with(gamma="1e-320"), "gamma"),  # was: exit 0 with NaN times
    "gamma_below_supported": (_with(gamma="1e-13"), "gamma"),
    "gamma_half": (_with(gamma="0.5"), "gamma"),  # y_eq = 0: equilibrium on the floor
    "gamma_large": (_with(gamma="100"), "gamma"),
    "mu_huge": (_with(mu="1e308"), "mu"),  # was: exit 0 with NaN
    "mu_above_supported": (_with(mu="2e8"), "mu"),
    "psi0_huge": (GOOD[:4] + ["--psi0", "1e308", "--psidot0", "0", "--xi0", "0", "--xidot0", "0"], "psi0"),
    "y0_below_x0": (_with(y0="5"), "y0"),
    "y0_equal_x0": (_with(y0="6"), "y0"),
    "y0_negative": (_with(x0="0", xdot0="1", y0="-1"), "y0"),
    "energy_huge": (_with(y0="1e200"), "initial state"),
    "speed_huge": (_with(ydot0="1e30"), "initial state"),
    "events_huge": (GOOD + ["--events", "1e19"], "events"),  # was: OverflowError traceback
    "events_memory": (GOOD + ["--events", "1e10", "--dt-sample", "1"], "events"),  # without it: streams
    "events_disk": (GOOD + ["--events", "1e12"], "events"),  # streamed: 81 TB of records
    "dt_subnormal": (GOOD + ["--dt-sample", "1e-320"], "dt-sample"),  # was: OverflowError traceback
    "dt_dense_no_t_max": (GOOD + ["--dt-sample", "1e-12"], "dt-sample"),
    "repeated_gamma": (GOOD + ["--gamma", "0.02"], "--gamma"),  # was: silently the last value
    "repeated_out": (GOOD + ["--out=a.nc"], "--out"),
}


@pytest.mark.parametrize("case", sorted(EDGE_BAD))
def test_edge_input_refused(case, tmp_path, capsys):
    """One line naming the parameter and its allowed/supported range, status 2, nothing written."""
    argv, name = EDGE_BAD[case]
    code, stdout, err = _run(["simulate", *argv, "--out", str(tmp_path / "run.nc")], capsys)
    _check_error(code, err, name)
    assert code == 2 and stdout == ""
    assert "range" in err or case.startswith("repeated"), err
    assert list(tmp_path.iterdir()) == []


def _spy_on_simulate(monkeypatch):
    """The trajectories bounce.cli's simulate returns, recorded."""
    import bounce.cli as cli

    returned = []
    real = cli.simulate

    def spy(*args, **kwargs):
        returned.append(real(*args, **kwargs))
        return returned[-1]

    monkeypatch.setattr(cli, "simulate", spy)
    return returned


def test_flight_refusal_is_about_every_flight(tmp_path, capsys):
    """Issue 25 item 10: the refusal of long flights judges the run by its energy, not by its first flight.
    This state's first flight lasts 0.02, its second 999 (every other one ~1000), 0.83 of the bound its
    energy gives (1210): an impact exchanges psi' and xi', and the spring's energy launches the centre of
    mass.  Scaled to a bound beyond 1e8, the state is refused with that reason."""
    params, state = Parameters(0.01, 0.0), State.from_psi_xi(0.3, 0.0, 0.2, 5.0)
    traj = simulate(params, state, max_events=10)
    _, _, bound = params.spring.longest_flight(params.gamma, state.deviations(params))
    assert traj.tau[0] < 0.1 and 0.8 * bound < traj.tau.max() <= bound
    code, out, err = _run(["simulate", "--gamma", "0.01", "--mu", "0", "--psi0", "0.3", "--psidot0", "0", "--xi0",
                           "0.2", "--xidot0", "5e5", "--out", str(tmp_path / "run.nc")], capsys)
    _check_error(code, err, "initial state")
    assert code == 2 and "range" in err and "exchanges psi' and xi'" in err and list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("dt", ["1e-12", "1e-5"])
def test_dense_sampling_refused_where_the_run_passes_the_limit(dt, tmp_path, capsys, monkeypatch):
    """Issue 25 item 4: --dt-sample is checked against the whole run, which is not known before simulating
    it: the run stops where its samples would exceed MAX_SAMPLES (1e7 dt) and is refused there.  With 1e-5
    the first flight (34.6) fits in that span (1e7 dt = 100): the check of the first flight passed, and
    the run simulated all of its 1e6 events (1.5 s) before being refused."""
    returned = _spy_on_simulate(monkeypatch)
    code, _, err = _run(["simulate", *GOOD, "--events", "1e6", "--dt-sample", dt,
                         "--out", str(tmp_path / "run.nc")], capsys)
    _check_error(code, err, "dt-sample")
    assert code == 2 and "range" in err and list(tmp_path.iterdir()) == []
    limit = 1e7 * float(dt)
    assert returned and all(traj.stop_reason == "t_max" and traj.settings["t_max"] == limit for traj in returned)
    assert sum(len(traj) for traj in returned) < 1000


def test_sampled_run_has_the_records_of_the_run(tmp_path, capsys):
    """The sampled run stops at the sampling limit only if it gets there: otherwise it is the run itself,
    records and attributes (t_max included) as without --dt-sample."""
    a, b = tmp_path / "a.nc", tmp_path / "b.nc"
    assert main(["simulate", *GOOD, "--events", "3000", "--out", str(a)]) == 0
    assert main(["simulate", *GOOD, "--events", "3000", "--dt-sample", "0.01", "--out", str(b)]) == 0
    capsys.readouterr()
    plain, sampled = bio.read_dataset(a), bio.read_dataset(b)
    assert sampled.sizes["time"] > 1000
    for name in plain.data_vars:
        assert np.array_equal(plain[name].values, sampled[name].values), name
    assert plain.attrs == sampled.attrs


def _name_limit(tmp_path, capsys, extra):
    """The longest --out name accepted, read from the refusal of a name of 300 bytes."""
    code, _, err = _run(["simulate", *GOOD, "--events", "3", *extra, "--out", str(tmp_path / ("n" * 300))], capsys)
    _check_error(code, err, "--out")
    return int(re.search(r"allowed range: \[1, (\d+)\] bytes", err).group(1))


@pytest.mark.parametrize("extra", [[], ["--stream"]], ids=["one-shot", "stream"])
def test_long_out_name_refused_before_simulating(extra, tmp_path, capsys, monkeypatch):
    """Issue 25 item 4: a name that fits but whose temporary file's name (or the partial file's, with
    --stream) does not is refused up front, naming --out and the allowed length; it used to simulate the
    whole run, then fail with 'Permission denied'.  The longest allowed name is written."""
    returned = _spy_on_simulate(monkeypatch)
    limit = _name_limit(tmp_path, capsys, extra)
    assert 200 < limit < 255
    code, _, err = _run(["simulate", *GOOD, "--events", "3", *extra, "--out", str(tmp_path / ("n" * (limit + 1)))],
                        capsys)
    _check_error(code, err, "--out")
    assert code == 2 and f"{limit + 1} bytes long" in err
    assert returned == [] and list(tmp_path.iterdir()) == []
    longest = tmp_path / ("n" * limit)
    code, out, err = _run(["simulate", *GOOD, "--events", "3", *extra, "--out", str(longest)], capsys)
    assert code == 0 and err == "" and out.startswith("bounce: 3 events")
    assert sorted(tmp_path.iterdir()) == [longest]


def _existing(tmp_path, capsys):
    old = tmp_path / "run.nc"
    assert main(["simulate", *GOOD, "--events", "3", "--out", str(old)]) == 0
    capsys.readouterr()
    return old, old.read_bytes()


@pytest.mark.parametrize("kind", ["fifo", "dangling_symlink", "symlink_to_file", "dir_dot", "dir_slash"])
def test_out_refuses_what_is_not_a_regular_file(kind, tmp_path, capsys):
    """--out accepts a new name in an existing directory or an existing regular file; a FIFO, a
    device, a symbolic link (dangling or not) would be destroyed or bypassed, and "nosuch/." names a
    directory (it used to write a file called "nosuch")."""
    target = tmp_path / "target.nc"
    if kind == "fifo":
        os.mkfifo(target)
    elif kind == "dangling_symlink":
        target.symlink_to(tmp_path / "nowhere.nc")
    elif kind == "symlink_to_file":
        (tmp_path / "real.nc").write_bytes(b"keep")
        target.symlink_to(tmp_path / "real.nc")
    before = sorted(p.name for p in tmp_path.iterdir())
    spelled = {"dir_dot": str(tmp_path / "nosuch") + "/.", "dir_slash": str(tmp_path / "nosuch") + "/"}
    out = spelled.get(kind, str(target))
    code, _, err = _run(["simulate", *GOOD, "--events", "3", "--out", out], capsys)
    _check_error(code, err, "--out")
    assert sorted(p.name for p in tmp_path.iterdir()) == before
    if kind == "fifo":
        assert stat.S_ISFIFO(os.lstat(target).st_mode)
    if kind.endswith("symlink") or kind == "symlink_to_file":
        assert target.is_symlink()
    if kind == "symlink_to_file":
        assert (tmp_path / "real.nc").read_bytes() == b"keep"


def test_out_refuses_character_device():
    """/dev/null is refused by the check (as root it used to be replaced by a regular file)."""
    with pytest.raises(FileExistsError, match="not a regular file"):
        bio.check_output_path("/dev/null")
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode)


def test_disk_full_is_reported_and_old_file_kept(tmp_path, capsys, monkeypatch):
    """netCDF reports a full disk as the bare "NetCDF: HDF error": the message says the disk is full
    and that the old file is kept, and it is."""
    old, before = _existing(tmp_path, capsys)

    def hdf_error(self, path, *args, **kwargs):
        open(path, "wb").close()
        raise RuntimeError("NetCDF: HDF error")

    monkeypatch.setattr("xarray.Dataset.to_netcdf", hdf_error)
    monkeypatch.setattr(bio, "_free_bytes", lambda directory: 0)
    code, out, err = _run(["simulate", *GOOD, "--events", "5", "--out", str(old)], capsys)
    _check_error(code, err, "disk full")
    assert code == 1 and "old file is kept" in err and "HDF" not in err
    assert old.read_bytes() == before and sorted(p.name for p in tmp_path.iterdir()) == ["run.nc"]


def test_full_disk_is_reported_and_old_file_kept(small_disk, capsys):
    """Issue 25 item 2, on a real 2 MiB file system: 1e5 events (8 MB) do not fit.  The free space was
    measured after the temporary file was removed, when the space was free again, so a full disk was
    reported as "NetCDF: HDF error"."""
    old = small_disk / "run.nc"
    assert main(["simulate", *GOOD, "--events", "3", "--out", str(old)]) == 0
    before = old.read_bytes()
    capsys.readouterr()
    code, out, err = _run(["simulate", *GOOD, "--events", "1e5", "--out", str(old)], capsys)
    _check_error(code, err, "disk full")
    assert code == 1 and out == "" and "old file is kept" in err and "HDF" not in err
    assert old.read_bytes() == before and sorted(p.name for p in small_disk.iterdir()) == ["run.nc"]


@pytest.mark.parametrize("signum, status", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_signal_during_write_in_process(signum, status, tmp_path, capsys, monkeypatch, request):
    """SIGINT (KeyboardInterrupt) or SIGTERM during the write acts once the temporary file is closed: one
    line, status 128 + signal, the temporary removed, the old file kept (SIGINT used to print a 19-line
    traceback)."""
    old, before = _existing(tmp_path, capsys)

    def interrupted(self, path, *args, **kwargs):
        with open(path, "wb") as fh:
            fh.write(b"partial")
        os.kill(os.getpid(), signum)  # its handler must not run inside the write (xarray's lock)

    monkeypatch.setattr("xarray.Dataset.to_netcdf", interrupted)
    if signum == signal.SIGINT and signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
        # started in the background (the shell ignores SIGINT there): act as the interactive process would
        previous = signal.signal(signal.SIGINT, signal.default_int_handler)
        request.addfinalizer(lambda: signal.signal(signal.SIGINT, previous))
    code, out, err = _run(["simulate", *GOOD, "--events", "5", "--out", str(old)], capsys)
    assert code == status and out == ""
    assert len(err.splitlines()) == 1 and err.startswith("error: ") and "Traceback" not in err
    assert old.read_bytes() == before and sorted(p.name for p in tmp_path.iterdir()) == ["run.nc"]


_SLOW_WRITER = """
import sys, time, xarray
from bounce.cli import main
def slow(self, path, *args, **kwargs):
    with open(path, "wb") as fh:
        fh.write(b"partial" * 1000)
    time.sleep(120)
xarray.Dataset.to_netcdf = slow
sys.exit(main(sys.argv[1:]))
"""


def _spawn(*args):
    """``python *args`` as a user's terminal would start it."""
    env = {**os.environ, "PYTHONWARNINGS": "ignore"}
    # a user's terminal delivers SIGINT: restore its default in the child even when this test process was
    # started in the background, where the shell leaves SIGINT ignored (and Python then installs no handler)
    return subprocess.Popen([sys.executable, *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, env=env, preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))


def _wait_for_temporary(proc, directory):
    deadline = time.monotonic() + 120
    while not [p for p in directory.iterdir() if p.name.endswith(".bounce-tmp")]:
        assert proc.poll() is None and time.monotonic() < deadline, proc.communicate()
        time.sleep(0.02)


def _start_slow_write(tmp_path, out):
    proc = _spawn("-c", _SLOW_WRITER, "simulate", *GOOD, "--events", "5", "--out", str(out))
    _wait_for_temporary(proc, tmp_path)
    return proc


def _communicate(proc, timeout):
    """stdout, stderr of ``proc`` once it ends within ``timeout`` s; killed (and the test failed) otherwise."""
    try:
        return proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.communicate()
        raise


@pytest.mark.slow
@pytest.mark.parametrize("signum, status", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_real_signal_during_a_real_write(signum, status, tmp_path, capsys):
    """Issue 25 item 1: a real signal while xarray writes the real file (3 s of zlib at 1e6 events) ends
    the run once the temporary file is closed, within the write's time: status 128 + signal, one line, the
    temporary removed, the old file kept.  The handler's exception used to skip the release of xarray's
    netCDF lock, and the write's own cleanup then waited on that lock for ever."""
    old, before = _existing(tmp_path, capsys)
    proc = _spawn("-m", "bounce", "simulate", *GOOD, "--events", "1e6", "--compression", "zlib", "--out", str(old))
    _wait_for_temporary(proc, tmp_path)
    time.sleep(0.2)
    assert proc.poll() is None
    proc.send_signal(signum)
    stdout, stderr = _communicate(proc, timeout=30)
    assert proc.returncode == status, stderr
    assert stdout == "" and len(stderr.splitlines()) == 1 and stderr.startswith("error: ")
    assert old.read_bytes() == before and sorted(p.name for p in tmp_path.iterdir()) == ["run.nc"]


_SLOW_SIMULATION = """
import sys, bounce.cli as cli
simulate = cli.simulate
def marked(*args, **kwargs):
    open(sys.argv[-1] + ".computing", "w").close()
    return simulate(*args, **kwargs)
cli.simulate = marked
sys.exit(cli.main(sys.argv[1:-1]))
"""


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_signal_while_a_kernel_computes_ends_the_process(signum, tmp_path):
    """SIGINT or SIGTERM while a compiled kernel runs ends the process at once, nothing written: the
    interpreter's handlers run only when the kernel returns, so a power-law run of ~2 min (b = 12: weak
    damping near equilibrium, long flights) used to go on to its end."""
    out = tmp_path / "run.nc"
    marker = tmp_path / "m"
    args = ["simulate", "--gamma", "0.01", "--mu", "0.01", "--spring", "power", "--rho", "1", "--a", "0.5",
            "--b", "12", "--psi0", "6", "--psidot0", "0", "--xi0", "-0.05", "--xidot0", "0", "--events", "200000",
            "--out", str(out), str(marker)]
    proc = _spawn("-c", _SLOW_SIMULATION, *args)
    computing = pathlib.Path(str(marker) + ".computing")
    deadline = time.monotonic() + 300  # a cold numba cache compiles the power-law kernels first
    while not computing.exists():
        assert proc.poll() is None and time.monotonic() < deadline, proc.communicate()
        time.sleep(0.05)
    time.sleep(2.0)  # inside the kernel (or still compiling it): both run without returning to Python
    proc.send_signal(signum)
    stdout, stderr = proc.communicate(timeout=30)
    assert proc.returncode == -signum, (proc.returncode, stderr)
    assert stdout == "" and not out.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.computing"]


def test_signal_while_starting_gives_one_line(tmp_path):
    """Issue 25 item 10: SIGINT while ``python -m bounce`` imports numba, xarray and netCDF4 (the first second)
    printed a traceback of 20 to 33 lines; now one line, status 130 (or the process ends by SIGINT, which a
    shell reports as 130 too).  Four runs at once, interrupted 0.1 to 0.7 s after they start (after the
    interpreter's own first ~30 ms, which no package can reach)."""
    delays = (0.1, 0.3, 0.5, 0.7)
    procs = [_spawn("-m", "bounce", "simulate", *GOOD, "--events", "10", "--out", str(tmp_path / f"{k}.nc"))
             for k in range(len(delays))]
    start = time.monotonic()
    for proc, delay in zip(procs, delays):
        time.sleep(max(0.0, start + delay - time.monotonic()))
        proc.send_signal(signal.SIGINT)
    for proc in procs:
        stdout, stderr = _communicate(proc, timeout=60)
        assert proc.returncode in (130, -signal.SIGINT) and stdout == "", (proc.returncode, stderr)
        assert "Traceback" not in stderr and len(stderr.splitlines()) <= 1, stderr
        assert stderr == "" or stderr.startswith("error: interrupted (SIGINT)"), stderr
    assert list(tmp_path.iterdir()) == []


def test_sigkill_leftover_removed_by_next_run(tmp_path, capsys):
    """SIGKILL cannot be caught: the temporary stays, named .NAME.<pid>.<hex>.bounce-tmp; the next run
    writing the same target removes it (its pid is dead) and leaves only the new file."""
    out = tmp_path / "run.nc"
    proc = _start_slow_write(tmp_path, out)
    proc.kill()
    proc.communicate(timeout=60)
    left = [p.name for p in tmp_path.iterdir()]
    assert len(left) == 1 and left[0].startswith(".run.nc.") and left[0].endswith(".bounce-tmp")
    assert main(["simulate", *GOOD, "--events", "3", "--out", str(out)]) == 0
    capsys.readouterr()
    assert [p.name for p in tmp_path.iterdir()] == ["run.nc"]


def test_state_below_resolution_gets_a_rest_verdict(tmp_path, capsys):
    """--psi0 1e-300 --psidot0 0 --xi0 0 --xidot0 0 --events 1e6 used to exit 0 with 1e6 grazings all
    at t = 1.4e-149; the drop of 1e-300 is below the resolution of heights: one sticky_start, then the
    sticky phase is proved never to end."""
    path = tmp_path / "run.nc"
    code, out, err = _run(["simulate", "--gamma", "0.01", "--mu", "0.01", "--psi0", "1e-300", "--psidot0", "0",
                           "--xi0", "0", "--xidot0", "0", "--events", "1e6", "--out", str(path)], capsys)
    assert code == 0 and err == "" and "sticky_forever" in out
    ds = bio.read_dataset(path)
    assert ds.sizes["event"] == 1 and int(ds.kind.values[0]) == 2

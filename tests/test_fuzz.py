"""Property-based fuzz of the command line and of ``simulate`` over the whole input domain (issue 12).

Every number may be NaN, +-inf, +-0, a subnormal, huge, or a plausible value (so that accepted runs
are common too); the initial state comes in both forms (heights, or the paper's psi/xi variables on
the command line; State or Deviations in Python).  The contract checked on every example:

* accepted (exit 0 / no exception): the records are finite and physically valid -- event times
  non-decreasing and the correctly rounded sums of the durations, durations >= 0, E - E_m >= 0 and
  never rising (16 eps relative, the rounding of the recorded sums of squares, as in
  test_invariants), the lower mass moving up (or at rest) after every event, samples finite with
  x >= 0; exactly the output file in the directory;
* refused: one line ``error: ...`` (or one InputError) naming the parameter and its allowed or
  supported range, exit status 2, no traceback, no file left behind (not even a temporary).

Size: BOUNCE_FUZZ_EXAMPLES examples per test, set by tests/conftest.py when not given: 100 in the default
``python -m pytest`` (~3 s of CPU for both), 400 with ``--all`` (CI; ~12 s); ``benchmarks/fuzz_cli.py`` runs
the same properties with many more.
"""

from __future__ import annotations

import math
import os
import shutil
import tempfile
from collections import Counter

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import bounce.cli as cli
import bounce.io as bio
from bounce import Deviations, Parameters, State, simulate
from bounce.model import InputError

EPS = 2.0**-52
MAX_EXAMPLES = int(os.environ.get("BOUNCE_FUZZ_EXAMPLES", "400"))
#: under pytest a fixed example sequence (tests/conftest.py); benchmarks/fuzz_cli.py draws fresh ones
SETTINGS = settings(deadline=None, max_examples=MAX_EXAMPLES, database=None,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
#: outcome counts (accepted / refused by parameter), read by benchmarks/fuzz_cli.py
OUTCOMES: Counter = Counter()

#: every parameter a refusal may name
NAMES = ("gamma", "mu", "x0", "xdot0", "y0", "ydot0", "psi0", "psidot0", "xi0", "xidot0", "eta0",
         "events", "t-max", "t_max", "energy-stop", "energy_stop", "dt-sample", "initial state")

SPECIAL = [math.nan, math.inf, -math.inf, 0.0, -0.0, 5e-324, -5e-324, 1e-320, 2.2250738585072014e-308, 1e-300,
           1e-150, 1e-16, 1.0, -1.0, 0.5, 1e16, 1e150, 1e300, 1.7976931348623157e308, -1.7976931348623157e308]


def log_uniform(lo: float, hi: float, signed: bool = False):
    mags = st.floats(math.log10(lo), math.log10(hi)).map(lambda e: 10.0**e)
    if not signed:
        return mags
    return st.tuples(mags, st.booleans()).map(lambda v: -v[0] if v[1] else v[0])


anywhere = st.one_of(
    st.sampled_from(SPECIAL),
    st.floats(allow_nan=True, allow_infinity=True, allow_subnormal=True),
    log_uniform(1e-320, 1e308, signed=True),
)


gammas = st.one_of(log_uniform(1e-13, 0.6), log_uniform(1e-6, 0.3), st.sampled_from([0.5, 1e-12, 0.4999999999999999]))
mus = st.one_of(st.sampled_from([0.0, 1.0]), log_uniform(1e-9, 3e8))
heights = st.one_of(st.just(0.0), st.floats(0.0, 10.0))
speeds = st.one_of(st.just(0.0), st.floats(-3.0, 3.0))
spring = st.floats(-0.6, 0.6)
counts = st.integers(1, 40)
t_maxes = st.one_of(st.just(math.inf), st.floats(1.0, 500.0))
energy_stops = log_uniform(1e-12, 1e-2)
dt_samples = st.floats(0.05, 20.0)


@st.composite
def corrupted(draw, plausible: dict) -> dict:
    """Plausible values for every field (so that accepted runs are common), then none (1 in 3),
    one, two or all of them replaced by anything (NaN, inf, subnormal, huge, ...)."""
    values = {name: draw(strategy) for name, strategy in plausible.items()}
    names = sorted(values)
    how_many = draw(st.sampled_from([0, 1, 1, 2, len(names)]))
    for name in draw(st.permutations(names))[:how_many]:
        values[name] = draw(anywhere)
    return values


def _xy(v: dict) -> tuple:
    """(x0, xdot0, y0, ydot0); y0 = x0 + dy when both are plausible (the spring near rest length)."""
    x0 = v["x0"]
    y0 = x0 + v["dy"] if math.isfinite(x0) and abs(v["dy"]) <= 2.0 else v["dy"]
    return x0, v["xdot0"], y0, v["ydot0"]


STATE_FIELDS = {"x0": heights, "xdot0": speeds, "dy": st.one_of(st.floats(-0.5, 1.5), st.floats(0.5, 1.5)),
                "ydot0": speeds, "psi0": st.one_of(heights, st.floats(0.6, 10.0)), "psidot0": speeds,
                "xi0": spring, "xidot0": speeds, "eta0": spring}


def _text(v: float) -> str:
    return repr(float(v))


@st.composite
def command_lines(draw):
    """argv of ``bounce simulate`` without --out."""
    v = draw(corrupted({"gamma": gammas, "mu": mus, **STATE_FIELDS, "t-max": t_maxes,
                        "energy-stop": energy_stops, "dt-sample": dt_samples}))
    argv = ["--gamma", _text(v["gamma"]), "--mu", _text(v["mu"])]
    if draw(st.booleans()):
        values = dict(zip(cli.XY_FORM, _xy(v)))
    else:
        values = {name: v[name] for name in cli.PSI_FORM}
    for name, x in values.items():
        argv += ["--" + name, _text(x)]
    argv += ["--events", draw(st.one_of(st.integers(1, 40).map(str), st.integers(1, 40).map(str),
                                        st.sampled_from(["0", "1.5", "-3", "1e19", "1e10", "nan", "inf", "1e-320"])))]
    for option in ("t-max", "energy-stop", "dt-sample"):
        if draw(st.booleans()):
            argv += ["--" + option, _text(v[option])]
    return argv


def _check_refusal(message: str) -> None:
    lines = message.splitlines()
    assert len(lines) == 1, message
    assert "Traceback" not in message
    assert any(name in lines[0] for name in NAMES), message
    assert "range" in lines[0], message


def _check_records(t, tau, xdot, energy_excess, e0):
    """Finite, physically valid event records (see the module docstring)."""
    for name, arr in (("t", t), ("tau", tau), ("xdot", xdot), ("energy_excess", energy_excess)):
        assert np.all(np.isfinite(arr)), name
    assert np.all(tau >= 0.0) and np.all(np.diff(t) >= 0.0)
    if len(t):
        assert t[-1] == math.fsum(tau)
    assert np.all(xdot >= 0.0)
    e = np.concatenate([[e0], energy_excess])
    assert np.all(e >= 0.0)
    assert np.all(np.diff(e) <= 16.0 * EPS * e[:-1] + 1e-300), np.diff(e).max()


def _initial_excess(ds) -> float:
    a = ds.attrs
    d = Deviations(a["x0"], a["xdot0"], a["xidot0"], a["eta0"])
    psidot = d.xdot + d.xidot
    return 0.5 * (d.xidot * d.xidot + psidot * psidot + d.eta * d.eta) + a["gamma"] * d.x


def run_cli_case(argv: list[str]) -> str:
    """Run ``bounce simulate argv --out DIR/run.nc`` in a fresh directory; check the contract.
    Returns the outcome ("accepted" or the refused parameter's message head)."""
    import contextlib
    import io

    tmp = tempfile.mkdtemp(prefix="bounce-fuzz-")
    try:
        out = os.path.join(tmp, "run.nc")
        stdout, stderr = io.StringIO(), io.StringIO()
        with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
            code = cli.main(["simulate", *argv, "--out", out])
        files = sorted(os.listdir(tmp))
        if code != 0:
            assert code == cli.EXIT_USAGE, (code, stderr.getvalue(), argv)
            assert stdout.getvalue() == "" and files == [], (files, argv)
            _check_refusal(stderr.getvalue())
            return stderr.getvalue().split(" ")[1]
        assert stderr.getvalue() == "" and files == ["run.nc"], (stderr.getvalue(), files, argv)
        ds = bio.read_dataset(out)
        _check_records(ds.t.values, ds.tau.values, ds.xdot.values, ds.energy_excess.values, _initial_excess(ds))
        for name in bio.SAMPLED_VARIABLES:
            if name in ds:
                assert np.all(np.isfinite(ds[name].values)), (name, argv)
        if "sampled_x" in ds:
            assert np.all(ds.sampled_x.values >= 0.0)
        return "accepted"
    finally:
        shutil.rmtree(tmp)


@SETTINGS
@given(command_lines())
def test_cli_fuzz(argv):
    """Exit 0 only with finite, physically valid output; otherwise one line naming the parameter
    and its range, status 2, nothing left in the directory."""
    saved = cli.MAX_SAMPLES
    cli.MAX_SAMPLES = 20_000  # keeps accepted sampling runs small; larger requests take the refusal path
    try:
        OUTCOMES["cli " + run_cli_case(argv)] += 1
    finally:
        cli.MAX_SAMPLES = saved


@st.composite
def api_cases(draw):
    """(gamma, mu, form, state values, max_events, t_max) for ``simulate``."""
    v = draw(corrupted({"gamma": gammas, "mu": mus, **STATE_FIELDS, "t_max": t_maxes}))
    form = draw(st.sampled_from(["state", "psi", "deviations"]))
    if form == "state":
        values = _xy(v)
    elif form == "psi":
        values = tuple(v[name] for name in cli.PSI_FORM)
    else:
        values = (v["x0"], v["xdot0"], v["xidot0"], v["eta0"])
    return v["gamma"], v["mu"], form, values, draw(counts), v["t_max"]


MAKE = {"state": State, "psi": State.from_psi_xi, "deviations": Deviations}


@SETTINGS
@given(api_cases())
def test_simulate_fuzz(case):
    """``simulate`` over the same domain: an InputError naming the parameter and its range, or a
    trajectory whose records are finite and physically valid."""
    gamma, mu, form, values, n, t_max = case
    try:
        params = Parameters(gamma, mu)
        initial = MAKE[form](*values)
        tr = simulate(params, initial, max_events=n, t_max=t_max)
    except InputError as exc:
        _check_refusal(str(exc))
        OUTCOMES["api " + str(exc).split(" ")[0]] += 1
        return
    d = initial.deviations(params)
    psidot = d.xdot + d.xidot
    e0 = 0.5 * (d.xidot * d.xidot + psidot * psidot + d.eta * d.eta) + gamma * d.x
    _check_records(tr.t, tr.tau, tr.xdot, tr.energy_excess, e0)
    assert math.isfinite(tr.t_end) or tr.stop_reason == "sticky_forever"
    OUTCOMES["api accepted"] += 1

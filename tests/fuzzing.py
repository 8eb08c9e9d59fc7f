"""The fuzz of the command line and of ``simulate`` (issues 12 and 25): its cases, their contract, and a
runner that gives every case a time bound.  Not a test: ``test_fuzz.py`` runs it under pytest,
``benchmarks/fuzz_cli.py`` at scale.

Cases.  A CLI case is the argument vector of ``bounce simulate`` without ``--out``; an API case is a call
``simulate(Parameters(gamma, mu, law), initial, max_events, t_max)``.  Both draw every number from a
plausible range (so that accepted runs are common) and then replace none, one, two or all of them by
anything (NaN, +-inf, +-0, subnormals, huge values); the initial state comes in both forms (heights, or the
paper's psi/xi variables; State or Deviations in Python); the spring is linear or the power law.  Two
ranges of power laws: :data:`POWER_SUPPORTED`, plausible values only (the equilibrium above the floor
with a margin, moderate stiffness, exponents and damping, flights of at most ~100 spring periods: where
the power law runs today), and :data:`POWER_WIDE`, corrupted like the rest, for the large fuzz: beyond
it the power law's domain is yet to be stated and enforced, by the CLI and the API (issue 25 items 5
and 6), and what the fuzz finds there is counted apart.

Contract.  Accepted (exit 0, or no exception): the records are finite and physically valid -- event times
non-decreasing and the correctly rounded sums of the durations, durations >= 0, E - E_m >= 0 and never
rising (linear law: 16 eps relative, the rounding of the recorded sums of squares, as in test_invariants;
power law: 1e-13 relative, the series solver's own bound in tests/series/test_series_core.py, whose
states are exact to ~1e-14: with mu = 0 and a = b = 0 its impacts move E - E_m by ~28 eps; plus, for long
flights, the error bound of bounce.series.flight: a bias of ~0.02 eps and a random walk of 0.4 eps of the
spring's energy per crossing of xi = 0, :func:`series_flight_allowance`), the lower
mass moving up (or at rest) after every event, the static equilibrium above the floor (y_eq > 0), samples
finite with x >= 0; nothing printed on stderr; exactly the output file in the directory.  Refused: one line
``error: ...`` (or one InputError) naming the parameter and its allowed or supported range, exit status 2,
no traceback, no file left behind (not even a temporary).  Anything else is a defect, and so is a case
that does not end within the runner's time bound.
"""

from __future__ import annotations

import contextlib
import io
import math
import multiprocessing
import os
import shutil
import tempfile
from dataclasses import dataclass

import numpy as np
from hypothesis import strategies as st

EPS = 2.0**-52
#: the power-law (series) solver's rounding of E - E_m from one event to the next, relative (its own energy test)
SERIES_ENERGY_RISE = 1e-13
VALID, REFUSED, DEFECT = "valid run", "clean refusal", "defect"

#: every parameter a refusal may name
NAMES = ("gamma", "mu", "x0", "xdot0", "y0", "ydot0", "psi0", "psidot0", "xi0", "xidot0", "eta0",
         "events", "t-max", "t_max", "energy-stop", "energy_stop", "dt-sample", "initial state",
         "--spring", "--rho", "--a", "--b", "spring rho", "spring a", "spring b")

SPECIAL = [math.nan, math.inf, -math.inf, 0.0, -0.0, 5e-324, -5e-324, 1e-320, 2.2250738585072014e-308, 1e-300,
           1e-150, 1e-16, 1.0, -1.0, 0.5, 1e16, 1e150, 1e300, 1.7976931348623157e308, -1.7976931348623157e308]


# --------------------------------------------------------------------------- strategies

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

STATE_FIELDS = {"x0": heights, "xdot0": speeds, "dy": st.one_of(st.floats(-0.5, 1.5), st.floats(0.5, 1.5)),
                "ydot0": speeds, "psi0": st.one_of(heights, st.floats(0.6, 10.0)), "psidot0": speeds,
                "xi0": spring, "xidot0": speeds, "eta0": spring}
XY_FORM = ("x0", "xdot0", "y0", "ydot0")
PSI_FORM = ("psi0", "psidot0", "xi0", "xidot0")

#: the power laws of the fuzz under pytest: (gamma/rho)^(1/(a+1)) < 0.45 (the equilibrium above the floor,
#: y_eq > 0.1), rho in [0.1, 10], a and b in [0, 3], mu <= 10, gamma >= 0.01 (with speeds <= 3, flights of
#: at most 2 x 3/gamma = 600, ~100 spring periods: a flight of gamma 1e-6 took over 20 s): where the power
#: law runs today, with plausible states only (a corrupted state reaches the API's missing domain check)
POWER_SUPPORTED = {"gamma": log_uniform(0.01, 0.3), "mu": st.one_of(st.just(0.0), log_uniform(1e-6, 10.0)),
                   "rho": log_uniform(0.1, 10.0), "a": st.floats(0.0, 3.0), "b": st.floats(0.0, 3.0)}
#: the power laws of the large fuzz: any stiffness, exponents and damping, the equilibrium anywhere
POWER_WIDE = {"gamma": gammas, "mu": mus, "rho": st.one_of(log_uniform(1e-8, 1e8), st.just(1.0)),
              "a": st.one_of(st.floats(0.0, 8.0), st.sampled_from([0.0, 0.5, 1.0])),
              "b": st.one_of(st.floats(0.0, 8.0), st.sampled_from([0.0, 0.5, 1.0]))}
LAW_FIELDS = ("rho", "a", "b")


def equilibrium_depth(gamma: float, rho: float, a: float) -> float:
    """|xi_eq| = (gamma/rho)^(1/(a+1)) of the power law: the equilibrium is above the floor iff it is < 1/2
    (inf where the law has no such equilibrium: rho <= 0, a <= -1, or values that are not numbers)."""
    try:
        depth = (gamma / rho) ** (1.0 / (a + 1.0))
    except (ZeroDivisionError, OverflowError, TypeError):
        return math.inf
    return depth if isinstance(depth, float) and math.isfinite(depth) else math.inf


@st.composite
def corrupted(draw, plausible: dict, corrupt: bool = True) -> dict:
    """Plausible values for every field (so that accepted runs are common), then (``corrupt``) none (1 in 3),
    one, two or all of them replaced by anything (NaN, inf, subnormal, huge, ...)."""
    values = {name: draw(strategy) for name, strategy in plausible.items()}
    names = sorted(values)
    how_many = draw(st.sampled_from([0, 1, 1, 2, len(names)])) if corrupt else 0
    for name in draw(st.permutations(names))[:how_many]:
        values[name] = draw(anywhere)
    return values


@st.composite
def laws(draw, power: dict | None) -> dict:
    """gamma, mu and, with ``power`` (the plausible ranges of a power law), rho, a, b."""
    if power is None:
        return {"gamma": draw(gammas), "mu": draw(mus)}
    while True:
        law = {name: draw(strategy) for name, strategy in power.items()}
        if power is not POWER_SUPPORTED or equilibrium_depth(law["gamma"], law["rho"], law["a"]) < 0.45:
            return law


def _xy(v: dict) -> tuple:
    """(x0, xdot0, y0, ydot0); y0 = x0 + dy when both are plausible (the spring near rest length)."""
    x0 = v["x0"]
    y0 = x0 + v["dy"] if math.isfinite(x0) and abs(v["dy"]) <= 2.0 else v["dy"]
    return x0, v["xdot0"], y0, v["ydot0"]


def _text(v: float) -> str:
    return repr(float(v))


@st.composite
def command_lines(draw, power: dict | None = None):
    """argv of ``bounce simulate`` without --out: the linear spring, or (``power``) a power law drawn from those
    ranges (:data:`POWER_SUPPORTED`: plausible values only)."""
    law = draw(laws(power))
    fields = {name: st.just(value) for name, value in law.items()}
    v = draw(corrupted({**fields, **STATE_FIELDS, "t-max": t_maxes, "energy-stop": energy_stops,
                        "dt-sample": dt_samples}, corrupt=power is not POWER_SUPPORTED))
    argv = ["--gamma", _text(v["gamma"]), "--mu", _text(v["mu"])]
    if power is not None:
        argv += ["--spring", "power", *[x for name in LAW_FIELDS for x in ("--" + name, _text(v[name]))]]
    values = dict(zip(XY_FORM, _xy(v))) if draw(st.booleans()) else {name: v[name] for name in PSI_FORM}
    for name, x in values.items():
        argv += ["--" + name, _text(x)]
    argv += ["--events", draw(st.one_of(st.integers(1, 40).map(str), st.integers(1, 40).map(str),
                                        st.sampled_from(["0", "1.5", "-3", "1e19", "1e10", "nan", "inf", "1e-320"])))]
    for option in ("t-max", "energy-stop", "dt-sample"):
        if draw(st.booleans()):
            argv += ["--" + option, _text(v[option])]
    return argv


@st.composite
def api_cases(draw, power: dict | None = None):
    """(gamma, mu, law spec or None, form, state values, max_events, t_max) for ``simulate`` (``power`` as in
    :func:`command_lines`)."""
    law = draw(laws(power))
    fields = {name: st.just(value) for name, value in law.items()}
    v = draw(corrupted({**fields, **STATE_FIELDS, "t_max": t_maxes}, corrupt=power is not POWER_SUPPORTED))
    form = draw(st.sampled_from(["state", "psi", "deviations"]))
    if form == "state":
        values = _xy(v)
    elif form == "psi":
        values = tuple(v[name] for name in PSI_FORM)
    else:
        values = (v["x0"], v["xdot0"], v["xidot0"], v["eta0"])
    spec = None if power is None else {"law": "power", **{name: v[name] for name in LAW_FIELDS}}
    return v["gamma"], v["mu"], spec, form, values, draw(counts), v["t_max"]


# --------------------------------------------------------------------------- the contract

def _check_refusal(message: str) -> None:
    lines = message.splitlines()
    assert len(lines) == 1, message
    assert "Traceback" not in message
    assert any(name in lines[0] for name in NAMES), message
    assert "range" in lines[0], message


def _span_of_phases(tau) -> float:
    """max tau / min positive tau: past 2^53 the compensated time sum may miss a tie of rounding by 1 ulp
    (bounce.exact.events, "Time is accumulated ...")."""
    positive = tau[tau > 0.0]
    return float(positive.max() / positive.min()) if len(positive) else 1.0


def series_flight_allowance(params, initial, tau, xidot, eta) -> np.ndarray:
    """How much the series solver's E - E_m may rise over each phase beyond SERIES_ENERGY_RISE, absolute: the long-flight
    error bound of :mod:`bounce.series.flight` (a bias of ~0.02 eps and a random walk of sigma_1 = 0.4 eps of the
    spring's energy E_s per crossing of xi = 0; taken as 0.05 n + 3 sigma_1 sqrt(n) eps E_s) for n crossings.  n is
    bounded by the spring's frequency at its largest swing W = ((a+2) E_s / rho)^(1/(a+2)), at most
    2 sqrt(rho) W^(a/2) (the power oscillator's omega/(sqrt(rho) W^(a/2)) is 1 at a = 0 and falls below pi/2):
    n <= 2 omega tau / pi + 2.  E_s is the phase's starting one (it does not grow in flight).  A 5.8e4-long flight
    of the linear restoring force (a = 0, mu = 0, gamma = 2.7e-6) raised E - E_m by 8e-14 relative, ~1.8e4 crossings:
    the bias (found by the fuzz, seed 31)."""
    law = params.spring.parameters()
    rho, a = float(law["rho"]), float(law["a"])
    start = initial.deviations(params)
    a_prev = np.concatenate([[start.xidot], xidot[:-1]])
    eta_prev = np.concatenate([[start.eta], eta[:-1]])
    xi = params.xi_eq + eta_prev
    e_spring = 0.5 * a_prev * a_prev + rho * np.abs(xi) ** (a + 2.0) / (a + 2.0)
    swing = ((a + 2.0) * e_spring / rho) ** (1.0 / (a + 2.0))
    crossings = 2.0 * (2.0 * math.sqrt(rho) * swing ** (a / 2.0)) * tau / math.pi + 2.0
    return (0.05 * crossings + 1.2 * np.sqrt(crossings)) * EPS * e_spring


def _check_records(t, tau, xdot, energy_excess, e0, rise: float = 16.0 * EPS, allowance=0.0):
    """Finite, physically valid event records (see the module docstring); ``rise``: how much E - E_m may rise,
    relative, by rounding; ``allowance``: and absolute, per event (long series flights)."""
    for name, arr in (("t", t), ("tau", tau), ("xdot", xdot), ("energy_excess", energy_excess)):
        assert np.all(np.isfinite(arr)), name
    assert np.all(tau >= 0.0) and np.all(np.diff(t) >= 0.0)
    if len(t):
        exact = math.fsum(tau)
        assert t[-1] == exact or (abs(t[-1] - exact) <= math.ulp(exact) and _span_of_phases(tau) > 2.0**53), \
            (t[-1], exact)
    assert np.all(xdot >= 0.0)
    e = np.concatenate([[e0], energy_excess])
    assert np.all(e >= 0.0)
    assert np.all(np.diff(e) <= rise * e[:-1] + allowance + 1e-300), np.diff(e).max()


def initial_excess(params, initial) -> float:
    """E - E_m of the initial state, computed as the solver computes it at the events (no cancellation)."""
    d = initial.deviations(params)
    if params.spring.name == "linear":
        psidot = d.xdot + d.xidot
        return 0.5 * (d.xidot * d.xidot + psidot * psidot + d.eta * d.eta) + params.gamma * d.x
    from bounce.series.events import energy_excess
    from bounce.series.taylor import law_array

    law = params.spring.parameters()
    array = law_array(law["rho"], law["a"], law["b"], params.mu, params.gamma)
    return float(energy_excess(d.xdot, d.xidot, d.eta, array)) + params.gamma * d.x


def _check_trajectory(traj) -> None:
    assert traj.params.y_eq > 0.0, f"accepted with the equilibrium below the floor: y_eq = {traj.params.y_eq!r}"
    e0 = initial_excess(traj.params, traj.initial)
    if traj.params.spring.name == "linear":
        _check_records(traj.t, traj.tau, traj.xdot, traj.energy_excess, e0)
    else:
        _check_records(traj.t, traj.tau, traj.xdot, traj.energy_excess, e0, SERIES_ENERGY_RISE,
                       series_flight_allowance(traj.params, traj.initial, traj.tau, traj.xidot, traj.eta))
    assert math.isfinite(traj.t_end) or traj.stop_reason == "sticky_forever"


def cli_outcome(argv: list[str]) -> tuple[str, str]:
    """Run ``bounce simulate argv --out DIR/run.nc`` in a fresh directory and check the contract; returns
    (VALID or REFUSED, what) or raises AssertionError."""
    import bounce.cli as cli
    import bounce.io as bio

    tmp = tempfile.mkdtemp(prefix="bounce-fuzz-")
    try:
        out = os.path.join(tmp, "run.nc")
        stdout, stderr = io.StringIO(), io.StringIO()
        with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
            code = cli.main(["simulate", *argv, "--out", out])
        files = sorted(os.listdir(tmp))
        if code != 0:
            assert code == cli.EXIT_USAGE, (code, stderr.getvalue())
            assert stdout.getvalue() == "" and files == [], files
            _check_refusal(stderr.getvalue())
            return REFUSED, stderr.getvalue().split(" ")[1]
        assert stderr.getvalue() == "" and files == ["run.nc"], (stderr.getvalue(), files)
        ds = bio.read_dataset(out)
        _check_trajectory(bio.from_dataset(ds))
        for name in bio.SAMPLED_VARIABLES:
            if name in ds:
                assert np.all(np.isfinite(ds[name].values)), name
        if "sampled_x" in ds:
            assert np.all(ds.sampled_x.values >= 0.0)
        return VALID, ds.attrs["spring_law"]
    finally:
        shutil.rmtree(tmp)


def api_outcome(case) -> tuple[str, str]:
    """``simulate`` on an API case: an InputError naming the parameter and its range, or a trajectory whose
    records are finite and physically valid; returns (VALID or REFUSED, what) or raises AssertionError."""
    from bounce import Deviations, InputError, Parameters, State, simulate
    from bounce.springs import spring_from_spec

    gamma, mu, spec, form, values, n, t_max = case
    make = {"state": State, "psi": State.from_psi_xi, "deviations": Deviations}[form]
    try:
        params = Parameters(gamma, mu, spring_from_spec(spec))
        traj = simulate(params, make(*values), max_events=n, t_max=t_max)
    except InputError as exc:
        _check_refusal(str(exc))
        return REFUSED, str(exc).split(" ")[0]
    _check_trajectory(traj)
    return VALID, traj.params.spring.name


# --------------------------------------------------------------------------- the runner

@dataclass(frozen=True)
class Outcome:
    """How one case fell: VALID, REFUSED or DEFECT, with what (the refused parameter, the law, the defect)."""

    verdict: str
    what: str
    seconds: float


def _outcome(kind: str, case) -> tuple[str, str]:
    try:
        return (cli_outcome if kind == "cli" else api_outcome)(case)
    except AssertionError as exc:
        return DEFECT, f"contract broken: {' '.join(str(exc).split())[:300]}"
    except Exception as exc:  # noqa: BLE001 (any other exception is the defect being looked for)
        return DEFECT, f"{type(exc).__name__}: {' '.join(str(exc).split())[:300]}"


def _serve(conn, scratch: str) -> None:
    """The worker: answer (kind, case) with its outcome until None; its temporary folders go under ``scratch``,
    which the runner empties when it kills the worker (a killed run cannot remove its own)."""
    import time

    import bounce.cli as cli

    tempfile.tempdir = scratch

    cli.MAX_SAMPLES = 20_000  # keeps accepted sampling runs small; larger requests take the refusal path
    for kind, case in (("api", (0.01, 0.01, None, "psi", (6.0, 0.0, 0.0, 0.0), 3, math.inf)),
                       ("api", (0.01, 0.01, {"law": "power", "rho": 1.0, "a": 0.5, "b": 0.5}, "psi",
                                (6.0, 0.0, 0.0, 0.0), 3, math.inf))):
        _outcome(kind, case)  # load the compiled kernels before the first timed case
    conn.send("ready")
    while (job := conn.recv()) is not None:
        start = time.perf_counter()
        verdict, what = _outcome(*job)
        conn.send((verdict, what, time.perf_counter() - start))


class Runner:
    """Runs cases in a worker process, each within ``timeout`` seconds: a case still running then is a
    defect ("no result within ..."), and the worker is killed and started again (so is one that dies)."""

    def __init__(self, timeout: float):
        self.timeout = timeout
        self._context = multiprocessing.get_context("spawn")
        self._scratch = tempfile.mkdtemp(prefix="bounce-fuzz-runner-")
        self._start()

    def _start(self) -> None:
        self._conn, child = self._context.Pipe()
        self._worker = self._context.Process(target=_serve, args=(child, self._scratch), daemon=True)
        self._worker.start()
        child.close()
        if not self._conn.poll(600) or self._conn.recv() != "ready":  # imports and the kernels' cache
            raise RuntimeError("the fuzz worker did not start")

    def _restart(self) -> None:
        self._worker.kill()
        self._worker.join()
        self._conn.close()
        shutil.rmtree(self._scratch, ignore_errors=True)  # what the killed case was writing
        os.makedirs(self._scratch, exist_ok=True)
        self._start()

    def run(self, kind: str, case) -> Outcome:
        """The outcome of a "cli" or "api" case."""
        self._conn.send((kind, case))
        try:
            if self._conn.poll(self.timeout):
                return Outcome(*self._conn.recv())
            what = f"no result within {self.timeout:g} s"
        except EOFError:
            what = f"the worker died (exit {self._worker.exitcode})"
        self._restart()
        return Outcome(DEFECT, what, self.timeout)

    def close(self) -> None:
        with contextlib.suppress(OSError, BrokenPipeError):
            self._conn.send(None)
        self._worker.join(10)
        if self._worker.is_alive():
            self._worker.kill()
            self._worker.join()
        shutil.rmtree(self._scratch, ignore_errors=True)


def power_law(kind: str, case):
    """(gamma, rho, a) of a power-law case, or None for the linear spring (also when not parseable)."""
    if kind == "api":
        gamma, _, spec = case[:3]
        return None if spec is None else (gamma, spec["rho"], spec["a"])
    if "power" not in case:
        return None
    opts = dict(zip(case[::2], case[1::2]))
    return float(opts["--gamma"]), float(opts["--rho"]), float(opts["--a"])

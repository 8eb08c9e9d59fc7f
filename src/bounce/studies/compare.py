"""Measurement layer of the speed-vs-accuracy study: run methods over settings sweeps, score them
against the exact solver, build xarray datasets, draw the work-precision and stability-map charts.

Every spring law with an exact solver: on a scene with ``spring: {law: power, ...}`` (eq.
``eq-motion-nonlin-psi-xi``) the reference is bounce's power-law solver (Taylor-series flights, exact to
rounding); a method runs a scene whose law has what the method ``needs`` (:mod:`bounce.methods.base`: the
general-purpose methods any law, heyoka a symbolic form; a sweep naming another is refused with its name).

Why error metrics need care: the transient of the drop gamma = mu = 0.01 from
psi(0) = 6 is chaotic (near-grazing flights multiply state errors by orders of
magnitude within ~20 impacts), so "impact time n of method M minus impact time
n of the exact solver" is meaningless for large n.  The metrics kept here stay
meaningful:

1. ``err_impact_times``: max relative error of the first ``n_h`` impact times
   (n_h inside the predictability horizon; the regular double-impact regime of
   the first ~10 impacts), and ``n_tracked``, the number of leading impacts
   whose times agree to ``track_tol`` relative;
2. one-step errors: from exact post-impact states at chosen impact indices (the
   same float64 State fed to the exact solver and to the method), one flight:
   relative error of the flight time and of the next post-impact speed;
3. ``err_y_rms``: RMS error of y(t) over a fixed window (inside the horizon; only
   with ``y_window``: the exact solver's dense output, :mod:`bounce.sampling`, of either law);
4. the asymptotic constant n tau_n c (c = mu g(xi_eq)/3: mu/3 on the linear spring, Theorem
   main_thm: -> 1; alpha gamma on the power law, :func:`asymptotic_scale`),
   median over the last ``window`` flights before each requested n and at the
   largest n the method reached, against the exact solver at the same n: the law
   is a property of the dynamics, not of one trajectory, so it survives chaos.

Spec (a study's slice of the ``methods`` section of config/config.yaml, validated and
defaulted by config/schema.yaml: :func:`bounce.studies.study_slice`)::

    scenes:  {name: {gamma, mu, spring, initial: {...}}}  # the one scene the study names
    work_precision: {scene, n_h, track_tol, y_window: {t: [a, b], samples} (optional),
                     one_step: {impacts: [...]}, long: {events, cpu_budget},
                     transient_budget, asymptotic: {n: [...], window, n_min, spread_runs, spread_eps},
                     timing: {min_total, max_repeats}, sweeps: [...]}
    stability_map:  {scene, events, starts, flights, cpu_budget, track_tol, window, sweeps: [...]}

A sweep is ``{method, fixed: {...}, curves: {key: [values]}, vary: {key: [values], ...}}``:
one curve per combination of the ``curves`` values, along each curve the zipped
``vary`` lists (the first ``vary`` key is the curve's abscissa in the stability map).
The exact method is always measured too (one run, label "exact").

Pipeline entry points: :func:`work_precision` and :func:`stability_map`
(``(spec) -> xr.Dataset``), :func:`plot_work_precision` and
:func:`plot_stability_map` (``(ds, spec, outputs)``); :func:`headline` gives the
summary numbers.
"""

from __future__ import annotations

import itertools
import json
import logging
import math

import numpy as np
import xarray as xr

from ..kinds import IMPACT
from ..methods import registry
from ..methods.base import FAILURES, MethodResult
from ..model import Deviations, Parameters, State
from ..scenes import scene_initial, scene_parameters
from ..simulate import simulate
from ..springs import spring_from_attrs
from .base import Study, study_slice

log = logging.getLogger(__name__)

CATEGORY_COLORS = {
    "": "0.75", "missed_impact": "C3", "fell_through": "C1", "stall": "C4", "energy_gain": "C0",
    "collapse": "C5", "endless_contact": "C2", "budget": "0.2",
}


# --------------------------------------------------------------------------- settings

def _number(v):
    """YAML 1.1 (PyYAML, snakemake) reads 1.0e4 -- no exponent sign -- as a string: take it as the number."""
    if isinstance(v, str):
        try:
            return float(v)
        except ValueError:
            return v
    return v


def expand_sweeps(sweeps: list[dict]) -> list[dict]:
    """Runs of a list of sweeps: dicts with method, setting, label (curve), key and value (abscissa)."""
    runs = []
    for sw in sweeps:
        method = sw["method"]
        fixed = {k: _number(v) for k, v in sw["fixed"].items()}
        curves = {k: [_number(v) for v in vals] for k, vals in sw["curves"].items()}
        vary = {k: [_number(v) for v in vals] for k, vals in sw["vary"].items()}
        lengths = {len(v) for v in vary.values()}
        if len(lengths) > 1:
            raise ValueError(f"sweep of {method}: the vary lists must have equal lengths, got {lengths}")
        n = lengths.pop() if lengths else 1
        keys = list(curves)
        for combo in itertools.product(*(curves[k] for k in keys)) if keys else [()]:
            cur = dict(zip(keys, combo))
            named = {**{k: v for k, v in fixed.items() if k == "solver"}, **cur}
            bits = [str(v) if isinstance(v, str) else f"{k}={v:.3g}" for k, v in named.items()]
            label = " ".join([method] + bits)
            for i in range(n):
                var = {k: vals[i] for k, vals in vary.items()}
                key = next(iter(vary)) if vary else ""
                runs.append({
                    "method": method, "setting": {**fixed, **cur, **var}, "label": label,
                    "key": key, "value": float(var[key]) if key else math.nan,
                })
    return runs


def _scene(spec: dict, name: str):
    scene = spec["scenes"][name]
    params = scene_parameters(scene)
    return params, scene_initial(scene, params)


def _law_attrs(params: Parameters, ref: "Reference") -> dict:
    """gamma, mu, the spring law and the normalisation c of the asymptotic constant, as dataset attributes."""
    return {"gamma": params.gamma, "mu": params.mu, "spring_law": params.spring.name,
            **{f"spring_{k}": float(v) for k, v in params.spring.parameters().items()},
            "asym_scale": ref.asym_scale,
            "asym_scale_note": "c with n tau_n c -> 1: mu g(xi_eq)/3, mu/3 for the linear spring (Theorem main_thm), "
                               "alpha gamma for the power law (alpha of the Discussion's map)"}


def _json(setting: dict) -> str:
    return json.dumps(setting, sort_keys=True, default=float)


# --------------------------------------------------------------------------- references

class Reference:
    """The exact solution of a scene: impacts (times, post-impact states) and closed-form y samples."""

    def __init__(self, params: Parameters, initial, events: int, sample_times=None, spread_runs: int = 0,
                 spread_eps: float = 1e-9):
        self.params = params
        self.initial = initial
        traj = simulate(params, initial, max_events=max(int(events), 1))
        imp = traj.kind == IMPACT
        self.t = traj.t[imp]
        self.xdot = traj.xdot[imp]
        self.xidot = traj.xidot[imp]
        self.eta = traj.eta[imp]
        self.only_impacts = bool(imp.all())
        self.sample_times = None if sample_times is None else np.asarray(sample_times, dtype=float)
        self.y = None
        if self.sample_times is not None:
            from ..methods.exact import run as exact_run

            self.y = exact_run(params, initial, max_events=max(int(events), 1),
                               t_max=float(self.sample_times.max()) * (1 + 1e-12) + 1e-12,
                               sample_times=self.sample_times).y
        self.tau = np.diff(np.concatenate([[0.0], self.t]))
        self.asym_scale = asymptotic_scale(params)
        # exact runs from initial states perturbed by spread_eps (relative): the trajectory-to-trajectory
        # spread of n tau_n c is the floor below which metric (4) cannot tell methods apart (chaos)
        self.perturbed = []
        rng = np.random.default_rng(12345)
        for _ in range(int(spread_runs)):
            f = 1.0 + spread_eps * rng.uniform(-1.0, 1.0, 2)
            if isinstance(initial, Deviations):
                init = Deviations(x=initial.x * f[0], xdot=initial.xdot, xidot=initial.xidot, eta=initial.eta * f[1])
            else:
                init = State(x=initial.x * f[0], xdot=initial.xdot, y=initial.y * f[1], ydot=initial.ydot)
            tr = simulate(params, init, max_events=max(int(events), 1))
            self.perturbed.append(tr.t[tr.kind == IMPACT])

    def asym_spread(self, n_at: int, window: int) -> float:
        """Relative standard deviation of n tau_n c at impact n_at over the perturbed exact runs."""
        c = np.array([asymptotic_constant(t, self.asym_scale, n_at, window) for t in self.perturbed])
        c = c[np.isfinite(c)]
        return float(np.std(c) / abs(np.mean(c))) if c.size > 1 else math.nan

    def post_state(self, k: int) -> State:
        """The exact state just after impact k (0-based), rounded to a float64 State."""
        return Deviations(x=0.0, xdot=float(self.xdot[k]), xidot=float(self.xidot[k]),
                          eta=float(self.eta[k])).to_state(self.params)


def asymptotic_scale(params: Parameters) -> float:
    """c with n tau_n c -> 1: c = mu g(xi_eq)/3, the damping of the law at its equilibrium.  The linear spring
    (g = 1): mu/3 (Theorem main_thm); the power law: alpha gamma, alpha = mu (3 gamma)^-1 (gamma/rho)^(b/(a+1)) =
    mu |xi_eq|^b/(3 gamma), the limit of the Discussion's map (:func:`bounce.analysis.theory.nonlin_alpha_limit`;
    tau_n ~ Xdot_n/gamma assumed as in the linear case).  Only a normalisation: every error of metric (4) is
    relative to the exact solver's value at the same n, in which c cancels."""
    return params.mu * params.spring.damping_factor(params.xi_eq) / 3.0


def asymptotic_constant(t: np.ndarray, scale: float, n_at: int, window: int, n0: int = 0) -> float:
    """Median of n tau_n c over the ``window`` flights ending at impact n_at (1-based n), c = ``scale``
    (:func:`asymptotic_scale`; mu/3 on the linear spring).

    ``t[k]`` is the time of impact n0 + k + 1 (any time origin): n0 > 0 for a run started from the
    state after impact n0."""
    k_at = n_at - n0
    if k_at < 2 or t.size < k_at:
        return math.nan
    lo = max(k_at - window, 1)
    n = n0 + np.arange(lo + 1, k_at + 1)
    tau = t[lo:k_at] - t[lo - 1:k_at - 1]
    return float(np.median(n * tau * scale))


# --------------------------------------------------------------------------- running

def _warm_up(spec_run, params, initial, setting):
    """One tiny run so that JIT compilation (numba) stays out of every timed run."""
    try:
        spec_run(params, initial, setting, max_events=1, t_max=1.0)
    except Exception:  # noqa: BLE001 - warm-up must not decide anything
        pass


def _timed(run, params, initial, setting, timing, **kw) -> MethodResult:
    """Run; if it took less than timing['min_total'] CPU seconds, repeat and keep the fastest CPU time."""
    res = run(params, initial, setting, **kw)
    total, best, reps = res.cpu_time, res.cpu_time, 1
    while total < timing["min_total"] and reps < timing["max_repeats"]:
        again = run(params, initial, setting, **kw)
        total += again.cpu_time
        best = min(best, again.cpu_time)
        reps += 1
    return MethodResult(method=res.method, setting=res.setting, t=res.t, xdot=res.xdot, cpu_time=best,
                        failure=res.failure, failure_index=res.failure_index, t_end=res.t_end, y=res.y,
                        extra={**res.extra, "repeats": reps})


def _n_tracked(t: np.ndarray, t_ref: np.ndarray, tol: float) -> int:
    n = min(t.size, t_ref.size)
    bad = np.nonzero(~(np.abs(t[:n] - t_ref[:n]) <= tol * np.abs(t_ref[:n])))[0]
    return int(bad[0]) if bad.size else n


def _with_budget(setting: dict, budget: float) -> dict:
    """The setting with the study's CPU budget unless it sets its own."""
    return {"cpu_budget": float(budget), **setting}


def _check_laws(runs: list, params, study: str) -> None:
    """Every method of the sweeps simulates the scene's spring law (contract 5 of bounce.methods.base)."""
    methods = registry()
    for method in dict.fromkeys(r["method"] for r in runs):
        if not methods[method].supports(params):
            raise ValueError(f"{study}.sweeps: method {method!r} does not simulate the {params.spring.name!r} spring "
                             f"of the scene (it needs {methods[method].needs.what})")


def measure_run(method: str, setting: dict, params, initial, ref: Reference, wp: dict) -> dict:
    """All work-precision numbers of one (method, setting)."""
    methods = registry()
    run = methods[method].run
    timing = wp["timing"]
    n_h = int(wp["n_h"])
    track_tol = float(wp["track_tol"])
    samples = ref.sample_times
    # past impact n_h with margin: a method whose impacts lag the exact ones must still reach n_h
    t_stop = 1.2 * float(ref.t[n_h - 1])
    if samples is not None:
        t_stop = max(t_stop, float(samples[-1]))
    base = dict(setting) if method != "exact" else {}
    _warm_up(run, params, initial, base)
    out: dict = {}

    # (1) + (3): the transient, to the end of the y window and past impact n_h
    tr = _timed(run, params, initial, _with_budget(base, wp["transient_budget"]), timing,
                max_events=10 * n_h + 1000, t_max=t_stop, sample_times=samples)
    out["cpu_transient"] = tr.cpu_time
    k = min(tr.t.size, n_h)
    rel = np.abs(tr.t[:k] - ref.t[:k]) / ref.t[:k]
    out["err_impact_times"] = float(rel.max()) if k == n_h else math.nan
    out["n_tracked"] = _n_tracked(tr.t, ref.t, track_tol)
    y = tr.y
    out["err_y_rms"] = (float(np.sqrt(np.mean((y - ref.y) ** 2)))
                        if ref.y is not None and y is not None and np.all(np.isfinite(y)) else math.nan)
    out["transient_failure"] = tr.failure

    # (2) one flight from exact post-impact states
    idx = [int(j) for j in wp["one_step"]["impacts"]]
    e_tau, e_v, c_one = [], [], []
    for j in idx:
        if j + 1 >= ref.t.size:
            e_tau.append(math.nan), e_v.append(math.nan), c_one.append(math.nan)
            continue
        st = ref.post_state(j)
        one_ref = simulate(params, st, max_events=1)
        tau_ref, v_ref = float(one_ref.t[0]), float(one_ref.xdot[0])
        r1 = _timed(run, params, st, _with_budget(base, wp["transient_budget"]), timing,
                    max_events=1, t_max=20.0 * tau_ref + 1.0)
        if r1.t.size and np.isfinite(r1.xdot[0]):
            e_tau.append(abs(float(r1.t[0]) - tau_ref) / tau_ref)
            e_v.append(abs(float(r1.xdot[0]) - v_ref) / v_ref)
        else:
            e_tau.append(math.nan), e_v.append(math.nan)
        c_one.append(r1.cpu_time)
    out["err_flight_time"], out["err_speed"], out["cpu_one_step"] = e_tau, e_v, c_one

    # (4) the long run: impacts per CPU second, asymptotic constant, failure
    long = wp["long"]
    lr = run(params, initial, _with_budget(base, long["cpu_budget"]), max_events=int(long["events"]))
    n_done = int(lr.t.size)
    out["n_impacts"] = n_done
    out["cpu_long"] = lr.cpu_time
    out["t_end"] = float(lr.t_end)
    out["failure"] = lr.failure
    out["failure_index"] = int(lr.failure_index)
    out["n_tracked_long"] = _n_tracked(lr.t, ref.t, track_tol)
    asym = wp["asymptotic"]
    window = int(asym["window"])
    scale = ref.asym_scale
    out["asym_constant"] = [asymptotic_constant(lr.t, scale, int(n), window) for n in asym["n"]]
    usable = int(asym["n_min"]) <= n_done <= ref.t.size
    out["asym_constant_last"] = asymptotic_constant(lr.t, scale, n_done, window) if usable else math.nan
    out["asym_n_last"] = n_done
    out["asym_constant_last_ref"] = asymptotic_constant(ref.t, scale, n_done, window) if usable else math.nan
    out["asym_spread_last"] = ref.asym_spread(n_done, window) if usable else math.nan
    return out


# --------------------------------------------------------------------------- datasets

def _attrs(long_name: str, units: str, **extra) -> dict:
    return {"long_name": long_name, "units": units, **extra}


def work_precision(spec: dict) -> xr.Dataset:
    """Work-precision dataset (dimension ``run``; one-step errors also over ``ref_impact``,
    asymptotic constants over ``asym_n``) for the sweeps of ``spec['work_precision']``."""
    wp = spec["work_precision"]
    params, initial = _scene(spec, wp["scene"])
    samples = None
    if "y_window" in wp:  # optional: the exact solver's dense output (bounce.sampling), either law
        win = wp["y_window"]
        samples = np.linspace(float(win["t"][0]), float(win["t"][1]), int(win["samples"]))
    asym = wp["asymptotic"]
    asym_n = [int(n) for n in asym["n"]]
    idx = [int(j) for j in wp["one_step"]["impacts"]]
    ref_events = max([int(wp["n_h"]) + 1, int(wp["long"]["events"]), *(j + 2 for j in idx), *asym_n])
    ref = Reference(params, initial, ref_events, samples, spread_runs=int(asym["spread_runs"]),
                    spread_eps=float(asym["spread_eps"]))
    runs = [{"method": "exact", "setting": {}, "label": "exact", "key": "", "value": math.nan}]
    runs += expand_sweeps(wp["sweeps"])
    _check_laws(runs, params, "work_precision")
    rows = []
    for i, r in enumerate(runs):
        rows.append(measure_run(r["method"], r["setting"], params, initial, ref, wp))
        log.info("work-precision %d/%d %s %s: err %.3g, cpu %.3g s, %d impacts, failure %r", i + 1, len(runs),
                 r["label"], _json(r["setting"]), rows[-1]["err_impact_times"], rows[-1]["cpu_transient"],
                 rows[-1]["n_impacts"], rows[-1]["failure"])
    return _assemble_wp(runs, rows, ref, params, spec, idx, asym_n)


def _assemble_wp(runs, rows, ref, params, spec, idx, asym_n) -> xr.Dataset:
    wp = spec["work_precision"]
    window = int(wp["asymptotic"]["window"])
    nr = len(runs)

    def col(name, dtype=float):
        return np.array([r[name] for r in rows], dtype=dtype)

    run_dim = ("run",)
    ds = xr.Dataset(
        {
            "cpu_transient": (run_dim, col("cpu_transient"), _attrs(
                "CPU (process) time of the transient run: to the end of the y window and past impact n_h", "s")),
            "err_impact_times": (run_dim, col("err_impact_times"), _attrs(
                "max relative error of the first n_h impact times against the exact solver", "1")),
            "n_tracked": (run_dim, col("n_tracked", np.int64), _attrs(
                "number of leading impacts whose times agree with the exact solver to track_tol (transient run)", "1")),
            "err_y_rms": (run_dim, col("err_y_rms"), _attrs(
                "RMS error of the upper-mass height y(t) over the window y_window", "L (spring rest length)")),
            "err_flight_time": (("run", "ref_impact"), np.array([r["err_flight_time"] for r in rows]).reshape(nr, len(idx)),
                                _attrs("one-step relative error of the flight time from the exact post-impact state", "1")),
            "err_speed": (("run", "ref_impact"), np.array([r["err_speed"] for r in rows]).reshape(nr, len(idx)),
                          _attrs("one-step relative error of the next post-impact speed of the lower mass", "1")),
            "cpu_one_step": (("run", "ref_impact"), np.array([r["cpu_one_step"] for r in rows]).reshape(nr, len(idx)),
                             _attrs("CPU (process) time of the one-flight run", "s")),
            "n_impacts": (run_dim, col("n_impacts", np.int64), _attrs("impacts (contacts) done in the long run", "1")),
            "cpu_long": (run_dim, col("cpu_long"), _attrs("CPU (process) time of the long run", "s")),
            "cpu_per_impact": (run_dim, col("cpu_long") / np.maximum(col("n_impacts"), 1), _attrs(
                "CPU time per impact in the long run", "s")),
            "t_end": (run_dim, col("t_end"), _attrs("time reached by the long run", "sqrt(m/2k)")),
            "failure": (run_dim, col("failure", str), _attrs(
                "failure category of the long run (empty: ran to the event budget)", "",
                categories=" ".join(f or "none" for f in FAILURES))),
            "failure_index": (run_dim, col("failure_index", np.int64), _attrs(
                "0-based index of the impact where the long run failed (-1: none)", "1")),
            "transient_failure": (run_dim, col("transient_failure", str), _attrs(
                "failure category of the transient run", "")),
            "n_tracked_long": (run_dim, col("n_tracked_long", np.int64), _attrs(
                "number of leading impacts tracked to track_tol in the long run", "1")),
            "asym_constant": (("run", "asym_n"), np.array([r["asym_constant"] for r in rows]).reshape(nr, len(asym_n)),
                              _attrs("median of n tau_n c over the window of flights ending at impact n (c: attribute asym_scale)", "1")),
            "asym_constant_ref": (("asym_n",), np.array([asymptotic_constant(ref.t, ref.asym_scale, n, window) for n in asym_n]),
                                  _attrs("n tau_n c of the exact solver (same window)", "1")),
            "asym_constant_last": (run_dim, col("asym_constant_last"), _attrs(
                "median of n tau_n c over the last window of flights of the long run", "1")),
            "asym_constant_last_ref": (run_dim, col("asym_constant_last_ref"), _attrs(
                "exact solver's n tau_n c at the same n as asym_constant_last", "1")),
            "asym_n_last": (run_dim, col("asym_n_last", np.int64), _attrs("largest impact index n reached (1-based)", "1")),
            "asym_spread_last": (run_dim, col("asym_spread_last"), _attrs(
                "chaos floor of metric (4) at asym_n_last: relative std of n tau_n c over exact runs from "
                "initial states perturbed by spread_eps", "1")),
            "asym_spread": (("asym_n",), np.array([ref.asym_spread(n, window) for n in asym_n]),
                            _attrs("chaos floor of metric (4) at asym_n (relative std over perturbed exact runs)", "1")),
        },
        coords={
            "run": ("run", np.arange(nr), _attrs("run index (one method and setting)", "1")),
            "method": ("run", np.array([r["method"] for r in runs], dtype=str), _attrs("method name", "")),
            "label": ("run", np.array([r["label"] for r in runs], dtype=str), _attrs("curve label (method and fixed settings)", "")),
            "setting": ("run", np.array([_json(r["setting"]) for r in runs], dtype=str), _attrs("setting as JSON", "")),
            "sweep_key": ("run", np.array([r["key"] for r in runs], dtype=str), _attrs("setting varied along the curve", "")),
            "sweep_value": ("run", np.array([r["value"] for r in runs], dtype=float), _attrs("value of sweep_key", "as the setting")),
            "ref_impact": ("ref_impact", np.array(idx, dtype=np.int64), _attrs(
                "0-based index of the exact impact whose post-impact state starts the one-step run", "1")),
            "asym_n": ("asym_n", np.array(asym_n, dtype=np.int64), _attrs("impact index n (1-based) of the asymptotic constant", "1")),
        },
    )
    ds["err_asym_constant"] = (("run", "asym_n"), np.abs(ds["asym_constant"].values / ds["asym_constant_ref"].values - 1.0),
                               _attrs("relative error of n tau_n c against the exact solver", "1"))
    ds["err_flight_time_max"] = ds["err_flight_time"].max("ref_impact", skipna=False)
    ds["err_flight_time_max"].attrs = _attrs("max over ref_impact of the one-step flight-time relative error", "1")
    ds["err_one_step_max"] = np.fmax(ds["err_flight_time"], ds["err_speed"]).max("ref_impact", skipna=False)
    ds["err_one_step_max"].attrs = _attrs(
        "max over ref_impact of the one-step relative errors of flight time and post-impact speed", "1")
    ds["cpu_per_flight"] = ds["cpu_one_step"].mean("ref_impact")
    ds["cpu_per_flight"].attrs = _attrs("mean CPU time of one flight (one-step runs)", "s")
    ds.attrs.update({
        "title": "Work-precision of general-purpose methods against the exact event-driven solver",
        **_law_attrs(params, ref), "scene": wp["scene"],
        "initial": _json(spec["scenes"][wp["scene"]]["initial"]), "n_h": int(wp["n_h"]),
        "track_tol": float(wp["track_tol"]),
        "y_window": _json({"t": list(map(float, wp["y_window"]["t"]))} if "y_window" in wp else {}),
        "reference_impacts": int(ref.t.size), "spec": _json(wp),
        "Conventions": "CF-1.10", "units_note": "dimensionless: lengths in L, times in sqrt(m/2k)",
    })
    return ds


def stability_map(spec: dict) -> xr.Dataset:
    """Failure category and index over settings sweeps (``spec['stability_map']``), dimensions (run, start).

    ``starts`` (default [0]) are impact counts n0: n0 = 0 runs from the scene's initial state for
    ``events`` impacts; n0 > 0 starts from the exact state just after impact n0 (1-based) and runs
    ``flights`` impacts -- so methods too slow to get there from t = 0 are still mapped at the small
    flight times (~3/(mu n0)) of the asymptotic regime.  Indices in the dataset are absolute (n0 + ...).
    """
    sm = spec["stability_map"]
    params, initial = _scene(spec, sm["scene"])
    events = int(sm["events"])
    starts = sorted(int(n0) for n0 in sm["starts"])
    flights = int(sm["flights"])
    window = int(sm["window"])
    ref = Reference(params, initial, max(events, starts[-1] + flights + 1))
    track_tol = float(sm["track_tol"])
    runs = expand_sweeps(sm["sweeps"])
    _check_laws(runs, params, "stability_map")
    methods = registry()
    names = ("failure", "failure_index", "n_impacts", "cpu", "t_end", "n_tracked", "tau_last", "tau_ref_at_stop",
             "asym_last", "asym_last_ref")
    rows = {k: [] for k in names}
    for r in runs:
        run = methods[r["method"]].run
        _warm_up(run, params, initial, r["setting"])
        for n0 in starts:
            init = initial if n0 == 0 else ref.post_state(n0 - 1)
            res = run(params, init, _with_budget(r["setting"], sm["cpu_budget"]),
                      max_events=events if n0 == 0 else flights)
            n = int(res.t.size)
            stop = n0 + (int(res.failure_index) if res.failure else n)  # absolute 0-based index of the stop
            t_origin = ref.t[n0 - 1] if n0 > 0 else 0.0
            n_abs = n0 + n
            ok = 0 < n_abs <= ref.t.size and n >= min(window, 2)
            vals = {
                "failure": res.failure, "failure_index": n0 + int(res.failure_index) if res.failure else -1,
                "n_impacts": n_abs, "cpu": res.cpu_time, "t_end": t_origin + float(res.t_end),
                "n_tracked": n0 + _n_tracked(res.t, ref.t[n0:] - t_origin, track_tol),
                "tau_last": float(res.t[-1] - res.t[-2]) if n > 1 else math.nan,
                "tau_ref_at_stop": float(ref.tau[min(stop, ref.t.size - 1)]),
                "asym_last": asymptotic_constant(res.t, ref.asym_scale, n_abs, window, n0=n0) if ok else math.nan,
                "asym_last_ref": asymptotic_constant(ref.t, ref.asym_scale, n_abs, window) if ok else math.nan,
            }
            for k in names:
                rows[k].append(vals[k])
            log.info("stability %s %s from n0=%d: %d impacts, failure %r at %d, cpu %.3g s", r["label"],
                     _json(r["setting"]), n0, n, res.failure, vals["failure_index"], res.cpu_time)
    nr, ns = len(runs), len(starts)

    def col(name, dtype=float):
        return np.array(rows[name], dtype=dtype).reshape(nr, ns)

    dims = ("run", "start")
    ds = xr.Dataset(
        {
            "failure": (dims, col("failure", str), _attrs(
                "failure category (empty: reached the event budget)", "", categories=" ".join(f or "none" for f in FAILURES))),
            "failure_index": (dims, col("failure_index", np.int64), _attrs(
                "absolute 0-based impact index of the failure (-1: none)", "1")),
            "n_impacts": (dims, col("n_impacts", np.int64), _attrs(
                "absolute impact index reached (n0 + impacts done in this run)", "1")),
            "cpu": (dims, col("cpu"), _attrs("CPU (process) time of the run", "s")),
            "t_end": (dims, col("t_end"), _attrs("time reached (exact impact time of the start + run time)", "sqrt(m/2k)")),
            "n_tracked": (dims, col("n_tracked", np.int64), _attrs(
                "absolute number of leading impacts whose times (from the start) agree with the exact solver to track_tol",
                "1")),
            "tau_last": (dims, col("tau_last"), _attrs("last flight time of the method", "sqrt(m/2k)")),
            "tau_ref_at_stop": (dims, col("tau_ref_at_stop"), _attrs(
                "exact flight time at the impact index where the run stopped (the time scale the method could not resolve)",
                "sqrt(m/2k)")),
            "asym_last": (dims, col("asym_last"), _attrs("median n tau_n c over the last window of flights (c: attribute asym_scale)", "1")),
            "asym_last_ref": (dims, col("asym_last_ref"), _attrs("exact n tau_n c at the same n (same window)", "1")),
        },
        coords={
            "run": ("run", np.arange(nr), _attrs("run index", "1")),
            "start": ("start", np.array(starts, dtype=np.int64), _attrs(
                "impact count n0 at the start (0: the scene's initial state; else the exact state after impact n0)", "1")),
            "method": ("run", np.array([r["method"] for r in runs], dtype=str), _attrs("method name", "")),
            "label": ("run", np.array([r["label"] for r in runs], dtype=str), _attrs("curve label", "")),
            "setting": ("run", np.array([_json(r["setting"]) for r in runs], dtype=str), _attrs("setting as JSON", "")),
            "sweep_key": ("run", np.array([r["key"] for r in runs], dtype=str), _attrs("setting varied along the curve", "")),
            "sweep_value": ("run", np.array([r["value"] for r in runs], dtype=float), _attrs("value of sweep_key", "as the setting")),
        },
    )
    ds.attrs.update({
        "title": "Stability map: where general-purpose methods fail on the bouncing ball",
        **_law_attrs(params, ref), "scene": sm["scene"], "initial": _json(spec["scenes"][sm["scene"]]["initial"]),
        "events": events, "flights": flights,
        "track_tol": track_tol, "spec": _json(sm), "Conventions": "CF-1.10",
    })
    return ds


# --------------------------------------------------------------------------- summaries

def headline(ds: xr.Dataset, target: float = 1e-8) -> dict:
    """Exact vs the cheapest run of every other method reaching ``target`` in err_impact_times."""
    ex = ds.where(ds["method"] == "exact", drop=True)
    out = {"exact_cpu_transient": float(ex["cpu_transient"][0]), "exact_cpu_per_impact": float(ex["cpu_per_impact"][0]),
           "target": target}
    for m in np.unique(ds["method"].values):
        if m == "exact":
            continue
        sub = ds.where((ds["method"] == m) & (ds["err_impact_times"] <= target), drop=True)
        if sub.sizes.get("run", 0) == 0:
            out[m] = None
            continue
        i = int(np.argmin(sub["cpu_transient"].values))
        out[m] = {
            "label": str(sub["label"].values[i]), "setting": str(sub["setting"].values[i]),
            "err_impact_times": float(sub["err_impact_times"].values[i]),
            "cpu_transient": float(sub["cpu_transient"].values[i]),
            "cpu_ratio_transient": float(sub["cpu_transient"].values[i]) / out["exact_cpu_transient"],
            "cpu_per_impact": float(sub["cpu_per_impact"].values[i]),
            "cpu_ratio_per_impact": float(sub["cpu_per_impact"].values[i]) / out["exact_cpu_per_impact"],
        }
    return out


# --------------------------------------------------------------------------- figures

def _curves(ds):
    """(label, method, indices sorted along the sweep) for every curve."""
    labels = list(dict.fromkeys(ds["label"].values.tolist()))
    for lab in labels:
        idx = np.nonzero(ds["label"].values == lab)[0]
        order = np.argsort(ds["sweep_value"].values[idx])
        yield lab, str(ds["method"].values[idx[0]]), idx[order]


_MARKERS = {"scipy": "o", "penalty": "s", "moreau-jean": "^", "heyoka": "D", "exact": "*"}


def _decades(ax) -> None:
    """Log axes spanning whole decades, labelled at the decades only (no crowded minor labels)."""
    from matplotlib.ticker import NullFormatter

    ax.set_xscale("log")
    ax.set_yscale("log")
    for axis, (lo, hi) in ((ax.xaxis, ax.get_xlim()), (ax.yaxis, ax.get_ylim())):
        lo, hi = 10.0 ** math.floor(math.log10(lo)), 10.0 ** math.ceil(math.log10(hi))
        (ax.set_xlim if axis is ax.xaxis else ax.set_ylim)(lo, hi)
        axis.set_minor_formatter(NullFormatter())


def _scene_text(ds: xr.Dataset) -> str:
    """The scene in words for a title: spring law, gamma, mu and the drop height (mathtext)."""
    from ..figures.common import tex_num

    law = spring_from_attrs(ds.attrs).title(tex_num)
    initial = json.loads(ds.attrs["initial"])
    if "psi" in initial:
        drop = r"drop from $\psi(0)=%s$" % tex_num(initial["psi"])
        drop += r", $\xi(0)=%s$" % tex_num(initial["xi"]) if initial["xi"] != 0.0 else ""
    else:
        drop = "scene " + ds.attrs["scene"]
    return r"%s, $\gamma=%s$, $\mu=%s$, %s" % (law, tex_num(ds.attrs["gamma"]), tex_num(ds.attrs["mu"]), drop)


def _asym_symbol(ds: xr.Dataset) -> str:
    """mathtext of the normalisation c of n tau_n c (mu/3 linear, alpha gamma power law)."""
    return r"\mu/3" if ds.attrs["spring_law"] == "linear" else r"\alpha\gamma"


def plot_work_precision(ds: xr.Dataset, spec: dict, outputs) -> None:
    """Log-log panels of error against CPU time, one curve per method and fixed setting (colour; marker:
    the method), the exact solver as a dashed vertical line (its CPU time; its error is 0: it is the
    reference).  Panel (b), y(t), only when the study has a y window; without it the legend takes its place.

    Panel (d) reads the long run: a hollow marker there is a run that failed before its last impact
    (the stability map says why); a run cut by its CPU budget is not a failure.  Every error of (d) is
    taken at the largest n the run reached.  The dotted line of (d) is the chaos floor: the relative
    spread of n tau_n c among exact runs from initial states perturbed by spread_eps -- beyond the
    predictability horizon no method can be closer to the reference than that."""
    from ..figures.common import WIDTH, plt, save, tex_num

    n_h = int(ds.attrs["n_h"])
    asym = json.loads(ds.attrs["spec"])["asymptotic"]
    window = json.loads(ds.attrs["y_window"])
    c = _asym_symbol(ds)
    panel_a = ("cpu_transient", "err_impact_times", "CPU time, transient run [s]",
               r"max rel. error of the impact times $t_1,\dots,t_{%d}$" % n_h,
               r"(a) the first $n_h=%d$ impacts (inside the predictability horizon)" % n_h)
    panel_b = ("cpu_transient", "err_y_rms", "CPU time, transient run [s]", r"RMS error of $y(t)$  [$L$]",
               r"(b) height of the upper mass on $t\in[%s]$" % ", ".join(f"{v:g}" for v in window.get("t", [])))
    panel_c = ("cpu_per_flight", "err_one_step_max", "CPU time per flight [s]",
               "max rel. error of flight time and next speed", "(c) one flight from an exact post-impact state")
    panel_d = ("cpu_per_impact", "err_asym_last", "CPU time per impact, long run [s]",
               r"rel. error of $n\tau_n %s$ (exact: $\to 1$)" % c,
               "(d) asymptotic constant at the largest $n$ reached")
    panels = [panel_a, panel_b if window else None, panel_c, panel_d]
    ds = ds.copy()
    ds["err_asym_last"] = np.abs(ds["asym_constant_last"] / ds["asym_constant_last_ref"] - 1.0)
    fig, axes = plt.subplots(2, 2, figsize=(WIDTH, 6.0))
    colors = {}
    handles = []
    for ax, panel in zip(axes.flat, panels):
        if panel is None:
            continue
        xv, yv, xl, yl, title = panel
        long_run = yv == "err_asym_last"
        for lab, method, idx in _curves(ds):
            if method == "exact":
                line = ax.axvline(float(ds[xv].values[idx[0]]), color="k", ls="--", lw=0.8)
                if ax is axes.flat[0]:
                    handles.append((line, "exact solver (the reference): its CPU time"))
                continue
            col = colors.setdefault(lab, f"C{len(colors) % 10}")
            x, y = ds[xv].values[idx], ds[yv].values[idx]
            ok = np.isfinite(x) & np.isfinite(y) & (y > 0) & (x > 0)
            failed = np.isin(ds["failure"].values[idx], ["", "budget"], invert=True) if long_run \
                else np.zeros(idx.size, dtype=bool)
            mk = _MARKERS.get(method, "o")
            line, = ax.plot(x[ok], y[ok], "-", marker=mk, color=col, lw=0.8, ms=3.5)
            ax.plot(x[ok & failed], y[ok & failed], mk, mfc="w", color=col, ms=3.5)
            if ax is axes.flat[0]:
                key = ds["sweep_key"].values[idx[0]]
                handles.append((line, f"{lab} (along the line: {key})" if key else lab))
        _decades(ax)
        ax.set_xlabel(xl, fontsize=7)
        ax.set_ylabel(yl, fontsize=7)
        ax.set_title(title, fontsize=7, loc="left")
        ax.tick_params(labelsize=6)
    floor = ds["asym_spread_last"].values
    floor = floor[np.isfinite(floor)]
    d = axes.flat[3]
    if floor.size:
        d.axhline(float(np.median(floor)), color="0.4", ls=":", lw=1.0)
    notes = [f"(d): ${c}$ normalises $n\\tau_n$ to 1, its limit; hollow marker: the long run failed",
             "before its last impact (the stability map says why); dotted: the chaos floor,",
             r"the spread of $n\tau_n$ among exact runs from initial states perturbed by $%s$:"
             % tex_num(asym["spread_eps"]), "no method can be closer to the reference than that"]
    lines, labels = zip(*handles)
    if window:
        fig.legend(lines, labels, loc="lower center", ncol=3, fontsize=6, frameon=False, bbox_to_anchor=(0.5, 0.045))
        fig.text(0.5, 0.005, " ".join(notes[:2]) + "\n" + " ".join(notes[2:]), ha="center", va="bottom", fontsize=5.5)
        bottom = 0.15
    else:
        slot = axes.flat[1]
        slot.axis("off")
        slot.legend(lines, labels, loc="upper left", fontsize=6, frameon=False)
        slot.text(0.0, 0.0, "\n".join(notes), transform=slot.transAxes, fontsize=5.5, va="bottom")
        bottom = 0.0
    fig.suptitle("Work-precision, %s: error against CPU time" % _scene_text(ds), fontsize=8)
    fig.tight_layout(rect=(0, bottom, 1, 1))
    save(fig, outputs)


#: the stability map's outcome of a run, in words (the one encoding of the figure: colour)
OUTCOMES = {
    "": "completed: every requested impact",
    "missed_impact": "stopped: missed an impact",
    "fell_through": "stopped: fell through the floor",
    "stall": "stopped: stalled at the floor",
    "energy_gain": "stopped: energy grew",
    "collapse": "stopped: inelastic collapse",
    "endless_contact": "stopped: contact never ends",
    "budget": "stopped: CPU-time budget used up",
}


def _setting_text(setting_json: str) -> str:
    """A run's settings for a label: {"rtol": 1e-06, "solver": "RK45"} -> "RK45, rtol=1e-06"."""
    setting = json.loads(setting_json)
    words = [str(v) for v in setting.values() if isinstance(v, str)]
    words += [f"{k}={_short(_number(v))}" for k, v in setting.items() if not isinstance(v, str)]
    return ", ".join(words)


def _short(v: float) -> str:
    """0.5 -> 0.5, 1e-06 -> 1e-6, 10000.0 -> 1e4."""
    return f"{v:g}" if 1e-2 <= abs(v) < 1e3 else f"{v:.0e}".replace("e-0", "e-").replace("e+0", "e").replace("e+", "e")


def plot_stability_map(ds: xr.Dataset, spec: dict, outputs) -> None:
    """One row per method and setting; for each start index n0 (one line each, n0 ticked on the top
    axis) a bar over the impact indices the run simulated, coloured by why it stopped; top axis also
    gives the asymptotic flight time 1/(c n) at that index (c = mu/3 linear, alpha gamma power law: the
    time scale a method must resolve)."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    from ..figures.common import WIDTH, plt, save, tex_num

    scale = float(ds.attrs["asym_scale"])
    starts = [int(v) for v in ds["start"].values]
    rows = [(str(ds["method"].values[i]), _setting_text(str(ds["setting"].values[i])), i) for lab, m, idx in
            _curves(ds) for i in idx]
    height = 0.8 / len(starts)
    used = set(ds["failure"].values.ravel().tolist())
    legend_in = 0.16 * (len(used) + 2)
    fig, ax = plt.subplots(figsize=(WIDTH, 1.4 + legend_in + max(1.0, 0.11 * len(rows) * max(1.5, len(starts) / 2))))
    for r, (method, text, i) in enumerate(rows):
        for k, n0 in enumerate(starts):
            y = r - 0.4 + height * (k + 0.5)
            n_end = max(int(ds["n_impacts"].values[i, k]), 1)
            f = str(ds["failure"].values[i, k])
            ax.plot([max(n0, 1), n_end], [y, y], "-", color=CATEGORY_COLORS.get(f, "k"), lw=7.0 * height,
                    solid_capstyle="butt")
            ax.plot([max(n0, 1)], [y], "|", color="k", ms=8 * height, mew=0.6)
    ax.set_yticks(range(len(rows)))
    ax.set_yticklabels([f"{m}: {t}" for m, t, _ in rows], fontsize=6)
    ax.set_ylim(len(rows) - 0.5, -0.5)
    for r in range(1, len(rows)):
        if rows[r][0] != rows[r - 1][0]:
            ax.axhline(r - 0.5, color="k", lw=0.6)
    ax.set_xscale("log")
    top = float(ds["n_impacts"].max()) * 2
    ax.set_xlim(0.8, top)
    ax.set_xlabel(r"impact index $n$")
    for n0 in starts:
        ax.axvline(max(n0, 1), color="0.5", lw=0.5, ls=":")
    sec = ax.secondary_xaxis("top", functions=(lambda n: 1.0 / (scale * np.maximum(n, 1e-30)),
                                                lambda tau: 1.0 / (scale * np.maximum(tau, 1e-30))))
    law = r"$3/(\mu n)$" if ds.attrs["spring_law"] == "linear" else (
        r"$1/(\alpha\gamma n)$, $\alpha=%s$" % tex_num(ds.attrs["asym_scale"] / ds.attrs["gamma"]))
    sec.set_xlabel(r"asymptotic flight time %s at that index  [$\sqrt{m/2k}$]" % law, fontsize=7)
    sec.tick_params(labelsize=6)
    handles = [Patch(color="w", label="bar: the impacts a run simulated, from its start to where it stopped; "
                                      "colour: why it stopped")]
    handles += [Patch(color=CATEGORY_COLORS[f], label=OUTCOMES[f]) for f in OUTCOMES if f in used]
    handles.append(Line2D([], [], color="k", marker="|", lw=0, ms=6,
                          label="start $n_0$ = " + ", ".join(f"${tex_num(n)}$" for n in starts)
                          + " (exact state there; one bar each, top to bottom)"))
    fig.legend(handles=handles, loc="lower center", ncol=1, fontsize=6.5, frameon=False)
    fig.suptitle("Stability map, %s:\nhow far each method gets and why it stops" % _scene_text(ds), fontsize=8)
    fig.tight_layout(rect=(0, (legend_in + 0.1) / fig.get_figheight(), 1, 1))
    save(fig, outputs)


STUDIES = (
    Study("work-precision", work_precision, plot_work_precision, lambda c: study_slice(c["methods"], "work_precision"),
          timed=True, caption=("Work-precision of general-purpose methods (solve_ivp, penalty DEM, Moreau-Jean, heyoka)"
                               " on the fig. rigid-fall drop.")),
    Study("stability-map", stability_map, plot_stability_map, lambda c: study_slice(c["methods"], "stability_map"),
          timed=True, caption="Where each general-purpose method stops on the fig. rigid-fall drop, and why."),
    Study("work-precision-hertz", work_precision, plot_work_precision,
          lambda c: study_slice(c["methods"], "work_precision", "work_precision_hertz"), timed=True,
          caption=("Work-precision of scipy's DOP853, Moreau-Jean and heyoka against bounce's power-law solver on "
                   "the Hertz drop (a = b = 1/2).")),
    Study("stability-map-hertz", stability_map, plot_stability_map,
          lambda c: study_slice(c["methods"], "stability_map", "stability_map_hertz"), timed=True,
          caption="Where scipy's DOP853, Moreau-Jean and heyoka stop on the Hertz drop (a = b = 1/2), and why."),
)

"""Peer benchmark for the nonlinear spring (issue 9): bounce against heyoka in ONE run, one core.

Law: Hertz (rho = 1, a = b = 1/2) of eq. ``eq-motion-nonlin-psi-xi``, gamma = mu = 0.01 (``--law
linear`` runs the same on a = b = 0).  Both solvers get the same float64 start states in the same
deviation variables (x, x', xi', eta = xi - xi_eq, eq. ``nonlin-equilibrium-xi``); heyoka is set up
as :mod:`bounce.methods.heyoka_taylor` (compiled once and reused, terminal event x = 0 with direction
negative, tolerance 2^-52).  Scenes:

* ``paper drop``: psi(0) = 6, xi = xi' = psi' = 0 (the spring at rest length; Hertz only);
* ``drop``: the same drop with the spring at its static compression xi(0) = xi_eq;
* ``deep``: bounce's post-impact state after ``DEEP_INDEX`` = 1e6 impacts of the drop (x' ~ 1e-5).

Measured per scene, in this run:

1. impacts/s, median (min, max) of ``--repeats`` runs in process CPU time, both solvers over the
   same ``--heyoka-events`` impacts from the same start (the ratio is taken there; heyoka in its
   fastest use, :func:`bounce.methods.heyoka_taylor.impacts`: one propagation with the impact rule in
   its event callback, all impacts found; heyoka through
   ``heyoka_taylor.run``, with its failure checks, is printed beside it: ~1 us more per impact deep, 1.25x;
   and heyoka at its most accurate setting ``ACCURATE``, tol 1e-18 with high_accuracy), and bounce alone
   over ``--events`` impacts (after a warm-up call: no JIT compile in any timing); and along the
   drop by windows of impact indices ``WINDOWS`` (both from bounce's exact state at the window's
   start): the transient (long flights through the rest length xi = 0) and the asymptotic regime
   cost differently;
2. one-step error: from the scene's start and bounce's post-impact states at ``ONE_STEP`` indices
   of it, each solver does one flight from the same float64 state; the largest relative error of
   tau, x', xi' after the impact and eta (relative to max(|eta|, 1e-6 |xi_eq|): eta is xi - xi_eq,
   a difference whose float64 floor is ~eps |xi_eq|) against the independent 50-digit mpmath
   reference ``tests/power_reference.py`` started from exactly that state (heyoka also at ``ACCURATE``);
3. skipped impacts, bounce (``--long N``, default 1e7): the drop continued in chunks of 1e6 impacts
   (each chunk from the last post-impact state: bounded memory), every event must be an impact
   and every chunk complete; the first flight of every chunk is checked against the mpmath
   reference (same tau to 1e-12 relative: the reference's root search returns the first root, so
   a skipped impact would show as a whole flight of difference);
4. heyoka's event cooldown (its default, automatic, and each of ``COOLDOWNS``): (a) along the real
   trajectory: from bounce's exact states after n = 1e4, 1e5, 1e6 (and the end of the long run)
   ``CHECK_FLIGHTS`` impacts, compared with bounce from the same state: the first index where the
   impact times differ by more than 1e-9 relative, and heyoka's own failure report; (b) beyond
   reach, a depth scan: post-impact states x' = u (u = 1e-6 ... 1e-13) with the deep state's
   ratio xi'/x' and eta = 0, 200 impacts each; the first u where heyoka fails, with its reason,
   and the impact index it corresponds to on the drop, n ~ 1/(alpha u) with alpha of the
   Discussion's map (:func:`bounce.analysis.theory.nonlin_alpha_limit`).  The best setting is the one
   clean to the smallest u (ties: the faster on the deep scene);
5. what heyoka's CPU per impact is made of (issue 22, "honest peer numbers"), per scene where it finds the
   same impacts, in ``--repeats`` interleaved rounds (medians): bounce over those impacts; heyoka's fastest
   Python use (:func:`bounce.methods.heyoka_taylor.impacts`: what a Python user gets, the impact rule in a
   Python callback) with its Taylor steps per impact; the cost of a Taylor step alone
   (:func:`bounce.methods.heyoka_taylor.step_cost`: the same ODE, tolerance and Taylor order, no event, no
   Python on its path; also with the floor checked every step, finding no root); heyoka's event handling in C++
   per impact (:func:`bounce.methods.heyoka_taylor.event_cost`: a step() loop with the floor as a terminal event
   without callback minus a matched loop of bare steps: the root search every step, the root's isolation and the
   step's truncation at each impact, the cooldown).  Hence heyoka's CPU per impact = steps + events + the Python
   callback (the rest), and bounce's speed-up three ways: against the Python use, against steps + events (what a
   C++ user with a C++ event callback would pay, give or take the few ns of that callback and the event loop's
   0.1 us of Python-side mismatch, see event_cost) and against the Taylor steps alone (a strict lower bound).
   ``--cost-only`` runs only this (``--law hertz linear``: ~20 s).

Run (results printed as a table and written as JSON, default ``results/timing/bench_power.json``)::

    python benchmarks/bench_power.py                       # Hertz, 1e7 impacts for the skip check
    python benchmarks/bench_power.py --long 0 --repeats 3  # quick: no long run
    python benchmarks/bench_power.py --windows-only 1000   # only the transient windows of both drops
    python benchmarks/bench_power.py --cost-only --law hertz linear  # only item 5, both laws (~20 s)
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
from mpmath import mp, mpf

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))
import power_reference as PR  # noqa: E402

from bounce import Deviations, Parameters, State, simulate  # noqa: E402
from bounce.kinds import IMPACT
from bounce.methods import heyoka_taylor as HT  # noqa: E402
from bounce.springs import SPRING_LAWS  # noqa: E402
from bounce.analysis.theory import nonlin_alpha_limit  # noqa: E402

GAMMA = MU = 0.01
LAWS = {"linear": (1.0, 0.0, 0.0), "hertz": (1.0, 0.5, 0.5)}
COOLDOWNS = (None, 0.0, 1e-15, 1e-12, 1e-9)
DEPTHS = (1e-6, 1e-7, 3e-8, 1e-8, 3e-9, 1e-9, 1e-10, 1e-11, 1e-12, 1e-13)
DEEP_INDEX = 1_000_000
CHECKPOINTS = (10_000, 100_000, 1_000_000)
WINDOWS = (0, 10, 100, 1_000, 10_000, 100_000)
CHECK_FLIGHTS = 2000
ONE_STEP = (0, 9, 99, 999)
CHUNK = 1_000_000
DIVERGE_REL = 1e-9
SKIP_REL = 1e-12
#: heyoka's most accurate setting tried (item 2): one-step errors ~1e-15 on the drop's flights through xi = 0
ACCURATE = {"tol": 1e-18, "high_accuracy": True}
#: Taylor steps per step_cost timing at least (item 5)
STEP_SAMPLE = 20_000


def pin_to_one_core() -> str:
    if not hasattr(os, "sched_setaffinity"):
        return "not pinned (os.sched_setaffinity unavailable)"
    allowed = sorted(os.sched_getaffinity(0))
    os.sched_setaffinity(0, {allowed[-1]})
    return f"pinned to core {allowed[-1]} of {allowed}"


def law_parameters(name: str) -> Parameters:
    rho, a, b = LAWS[name]
    if name == "linear":
        return Parameters(GAMMA, MU)
    return Parameters(GAMMA, MU, SPRING_LAWS["power"](rho=rho, a=a, b=b))


def post_impact(tr, k: int) -> Deviations:
    """bounce's state just after impact k (0-based) of trajectory ``tr``."""
    return Deviations(0.0, float(tr.xdot[k]), float(tr.xidot[k]), float(tr.eta[k]))


def scenes(name: str, params: Parameters) -> dict:
    drop = State.from_psi_xi(6.0, 0.0, params.xi_eq, 0.0)
    out = {} if name == "linear" else {"paper drop": State.from_psi_xi(6.0, 0.0, 0.0, 0.0)}
    out["drop"] = drop if name != "linear" else State.from_psi_xi(6.0, 0.0, 0.0, 0.0)
    tr = simulate(params, out["drop"], max_events=DEEP_INDEX)
    out["deep"] = post_impact(tr, DEEP_INDEX - 1)
    return out


def rates(fn, repeats: int) -> list:
    """[median, min, max] of impacts/s over ``repeats`` calls of fn() -> (impacts, CPU seconds)."""
    r = []
    for _ in range(repeats):
        n, cpu = fn()
        r.append(n / cpu if cpu > 0 else math.inf)
    return [statistics.median(r), min(r), max(r)]


def bounce_timed(params, initial, events):
    start = time.process_time()
    tr = simulate(params, initial, max_events=events)
    return len(tr.t), time.process_time() - start


def heyoka_timed(params, initial, bounce_t, setting=None):
    """(impacts, CPU s) of heyoka's fastest use (:func:`bounce.methods.heyoka_taylor.impacts`: one
    propagation, the impact rule in its event callback) over as many impacts as bounce finds from the
    same start by ``bounce_t[-1]``.  It must find them all by 1.5 times that: after a skipped impact x
    stays below the floor (psi falls like a parabola, |xi| is bounded) and no event follows, so a
    timing of fewer impacts stops the benchmark.  (Where the trajectories part by more than DIVERGE_REL,
    the transient's sensitivity to heyoka's one-step errors, is reported by the scene rows.)"""
    n = len(bounce_t)
    t, _, _, _, cpu, _ = HT.impacts(params, initial, n, 1.5 * bounce_t[-1] + 1.0, setting)
    if len(t) < n:
        raise SystemExit(f"heyoka's timed run found {len(t)} of {n} impacts: an impact was skipped")
    return n, cpu


def cost_split(params, initial, bounce_t, repeats) -> dict:
    """heyoka's CPU per impact split into its Taylor steps, its event handling and its Python callback (module
    docstring, item 5), with bounce over the same impacts: ``repeats`` rounds, each timing in turn bounce, heyoka's
    :func:`~bounce.methods.heyoka_taylor.impacts` (what a Python user gets: its CPU and Taylor steps),
    :func:`~bounce.methods.heyoka_taylor.step_cost` without events and with the floor checked (as many steps as
    impacts() took, at least STEP_SAMPLE, from bounce's state after the scene's first impact) and
    :func:`~bounce.methods.heyoka_taylor.event_cost` (the event handling in C++, from the scene's start); medians
    per quantity, ratios of the medians.  Times in us."""
    n = len(bounce_t)
    med = statistics.median
    load = os.getloadavg()[0]
    tr = simulate(params, initial, max_events=1)
    moving = post_impact(tr, 0)  # step_cost's start: the spring moves after an impact (its docstring)
    for check in (False, True):
        HT.step_cost(params, moving, 10, floor_check=check)  # compile its integrators once
    HT.event_cost(params, initial, 1)
    cols = {k: [] for k in ("bounce", "python", "steps", "bare", "floor", "events", "event_steps")}
    cpu_total = 0.0
    for _ in range(repeats):
        _, cpu_b = bounce_timed(params, initial, n)
        t, _, _, _, cpu_h, steps = HT.impacts(params, initial, n, 1.5 * bounce_t[-1] + 1.0)
        if len(t) < n:
            raise SystemExit(f"heyoka's timed run found {len(t)} of {n} impacts: an impact was skipped")
        cols["bounce"].append(1e6 * cpu_b / n)
        cols["python"].append(1e6 * cpu_h / n)
        cols["steps"].append(steps)
        cpu_total += cpu_b + cpu_h
        for key, check in (("bare", False), ("floor", True)):
            k, cpu_s, _ = HT.step_cost(params, moving, max(steps, STEP_SAMPLE), floor_check=check)
            cols[key].append(1e6 * cpu_s / k)
            cpu_total += cpu_s
        ev = HT.event_cost(params, initial, n)
        cols["events"].append(1e6 * (ev["cpu_events"] - ev["cpu_matched"]) / n)
        cols["event_steps"].append(ev["steps"])
        cpu_total += ev["cpu_events"] + ev["cpu_matched"]
    spi = med(cols["steps"]) / n
    b, py, bare, floor, events = (med(cols[k]) for k in ("bounce", "python", "bare", "floor", "events"))
    cpp = spi * bare + events
    return {"impacts": n, "steps_per_impact": spi, "steps": cols["steps"],
            "steps_per_impact_step_loop": med(cols["event_steps"]) / n,
            "us_per_impact_bounce": b, "us_per_impact_heyoka_python": py,
            "us_per_step_bare": bare, "us_per_step_floor_check": floor,
            "us_per_impact_steps_alone": spi * bare, "us_per_impact_events": events,
            "us_per_impact_cpp_estimate": cpp, "us_per_impact_python_callback": py - cpp,
            "share_not_steps": 1.0 - spi * bare / py, "share_events": events / py, "share_callback": 1.0 - cpp / py,
            "ratio_python": py / b, "ratio_cpp_estimate": cpp / b, "ratio_steps_alone": spi * bare / b,
            "samples_us": {k: cols[k] for k in ("bounce", "python", "bare", "floor", "events")},
            "repeats": repeats, "cpu_s": cpu_total, "load_1min": [load, os.getloadavg()[0]]}


def heyoka_run_timed(params, initial, events):
    """(impacts, CPU s) of :func:`bounce.methods.heyoka_taylor.run`: heyoka with the method's failure checks
    (upward crossings, zero-length flights, the flight bound between propagations)."""
    r = HT.run(params, initial, {}, max_events=events)
    return len(r.t), r.cpu_time


def reference_error(law, start: Deviations, xi_eq: float, out: dict) -> float:
    """Largest relative error of one flight's (tau, x', xi', eta) against the mpmath reference."""
    rho, a, b = law
    with mp.workdps(PR.DPS + 10):
        xi = mpf(xi_eq) + mpf(start.eta)  # exactly the state both solvers started from
    ref = PR.reference_first_impact(GAMMA, MU, rho, a, b, start.x, start.xdot, start.xidot, xi)
    with mp.workdps(PR.DPS):
        eta_ref = ref["xi"] - mpf(xi_eq)
        errs = [abs((mpf(out[k]) - ref[k]) / ref[k]) for k in ("tau", "xdot", "xidot")]
        errs.append(abs(mpf(out["eta"]) - eta_ref) / max(abs(eta_ref), mpf(1e-6) * abs(mpf(xi_eq))))
        return float(max(errs))


def one_flight_bounce(params, start):
    tr = simulate(params, start, max_events=1)
    return {"tau": tr.tau[0], "xdot": tr.xdot[0], "xidot": tr.xidot[0], "eta": tr.eta[0]}


def one_flight_heyoka(params, start, setting):
    res = HT.run(params, start, setting, max_events=1)
    if res.failure:
        return None, f"{res.failure}: {res.extra['reason']}"
    return {"tau": res.t[0], "xdot": res.xdot[0], "xidot": res.extra["xidot"][0], "eta": res.extra["eta"][0]}, ""


def one_step_errors(name, params, initial) -> dict:
    """Max one-step errors of both solvers from the scene's start and bounce's states at ONE_STEP."""
    law = LAWS[name]
    tr = simulate(params, initial, max_events=max(ONE_STEP) + 1)
    starts = [initial.deviations(params)] + [post_impact(tr, k) for k in ONE_STEP]
    errs = {"bounce": [], "heyoka": [], "heyoka_accurate": []}
    heyoka_fail = ""
    for st in starts:
        errs["bounce"].append(reference_error(law, st, params.xi_eq, one_flight_bounce(params, st)))
        for key, setting in (("heyoka", {}), ("heyoka_accurate", ACCURATE)):
            h, why = one_flight_heyoka(params, st, setting)
            if h is None:
                heyoka_fail = heyoka_fail or why
                errs[key].append(math.nan)
            else:
                errs[key].append(reference_error(law, st, params.xi_eq, h))
    out = {"states": ["start"] + [f"after impact {k + 1}" for k in ONE_STEP], **errs,
           "bounce_max": max(errs["bounce"]), "heyoka_failure": heyoka_fail}
    for key in ("heyoka", "heyoka_accurate"):
        out[f"{key}_max"] = None if all(map(math.isnan, errs[key])) else float(np.nanmax(errs[key]))
    return out


def scene_row(name, params, scene, initial, args) -> dict:
    HT.run(params, initial, {}, max_events=10)  # compile heyoka's integrator once (reused after)
    HT.impacts(params, initial, 10, 1.0)  # ... and impacts()' (step_cost's: cost_split)
    simulate(params, initial, max_events=10)  # numba: loaded from cache, warmed
    first = HT.run(params, initial, {}, max_events=args.heyoka_events)
    row = {"heyoka": {"failure": first.failure, "index": first.failure_index, "reason": first.extra["reason"],
                      "impacts": len(first.t), "cooldown_used": first.extra["cooldown"]}}
    n_same = len(first.t) if first.failure else args.heyoka_events
    row["same_impacts"] = n_same
    if n_same > 0:
        row["cost"] = cost_split(params, initial, simulate(params, initial, max_events=n_same).t, args.repeats)
    if args.cost_only:
        return row
    tr = simulate(params, initial, max_events=args.events)
    row["bounce"] = {
        "impacts_per_s": rates(lambda: bounce_timed(params, initial, args.events), args.repeats),
        "stop": tr.stop_reason, "all_impacts": bool((tr.kind == IMPACT).all()), "impacts": len(tr.t)}
    if n_same > 0:  # same start, same impacts
        bounce_t = simulate(params, initial, max_events=n_same).t
        row["heyoka"]["impacts_per_s"] = rates(lambda: heyoka_timed(params, initial, bounce_t), args.repeats)
        row["heyoka"]["impacts_per_s_checked"] = rates(lambda: heyoka_run_timed(params, initial, n_same),
                                                       args.repeats)
        row["heyoka"]["impacts_per_s_accurate"] = rates(lambda: heyoka_timed(params, initial, bounce_t, ACCURATE),
                                                        args.repeats)
        row["bounce"]["impacts_per_s_same"] = rates(lambda: bounce_timed(params, initial, n_same), args.repeats)
        row["ratio"] = row["bounce"]["impacts_per_s_same"][0] / row["heyoka"]["impacts_per_s"][0]
        n = min(len(first.t), len(tr.t))
        off = np.nonzero(np.abs(first.t[:n] - tr.t[:n]) > DIVERGE_REL * np.abs(tr.t[:n]))[0]
        row["heyoka_leaves_bounce_at"] = int(off[0]) if off.size else -1
    row["one_step"] = one_step_errors(name, params, initial)
    return row


def drop_windows(params, drop, repeats, last=WINDOWS[-1]) -> list:
    """impacts/s of both solvers on the windows [WINDOWS[i], WINDOWS[i+1]) of the drop up to impact
    ``last`` (docstring, item 1)."""
    edges = [w for w in WINDOWS if w <= last]
    tr = simulate(params, drop, max_events=edges[-1])
    HT.run(params, drop, {}, max_events=10)  # compile heyoka's integrator once (reused after)
    simulate(params, drop, max_events=10)  # numba: loaded from cache, warmed
    out = []
    for lo, hi in zip(edges[:-1], edges[1:]):
        start = drop if lo == 0 else post_impact(tr, lo - 1)
        r = HT.run(params, start, {}, max_events=hi - lo)
        row = {"from": lo, "to": hi, "x_dot_at_start": float(tr.xdot[max(lo - 1, 0)]),
               "bounce": rates(lambda: bounce_timed(params, start, hi - lo), repeats),
               "heyoka_failure": r.failure}
        if not r.failure:
            bounce_t = simulate(params, start, max_events=hi - lo).t
            row["heyoka"] = rates(lambda: heyoka_timed(params, start, bounce_t), repeats)
            row["ratio"] = row["bounce"][0] / row["heyoka"][0]
        out.append(row)
    return out


def long_run(name, params, initial, total) -> dict:
    """bounce over ``total`` impacts of the drop in chunks (module docstring, item 3)."""
    law = LAWS[name]
    state, done, cpu, worst, bad = initial, 0, 0.0, 0.0, []
    checkpoints = {}
    while done < total:
        n = min(CHUNK, total - done)
        start = time.process_time()
        tr = simulate(params, state, max_events=n)
        cpu += time.process_time() - start
        if len(tr.t) != n or not (tr.kind == IMPACT).all():
            bad.append({"chunk_start": done, "stop": tr.stop_reason, "events": len(tr.t),
                        "non_impacts": int((tr.kind != IMPACT).sum())})
            break
        st0 = state.deviations(params)
        with mp.workdps(PR.DPS + 10):
            xi = mpf(params.xi_eq) + mpf(st0.eta)
        ref = PR.reference_first_impact(GAMMA, MU, *law, st0.x, st0.xdot, st0.xidot, xi)
        worst = max(worst, float(abs((mpf(tr.tau[0]) - ref["tau"]) / ref["tau"])))
        done += n
        state = post_impact(tr, n - 1)
        checkpoints[done] = state
    return {"impacts": done, "requested": total, "cpu_s": cpu, "impacts_per_s": done / cpu if cpu else None,
            "all_impacts": not bad, "problems": bad, "first_flight_of_chunk_max_rel_err_tau": worst,
            "skipped": 0 if (not bad and worst <= SKIP_REL) else None}, checkpoints


def heyoka_along(params, start, cooldown) -> dict:
    """heyoka from bounce's exact state ``start`` for CHECK_FLIGHTS impacts against bounce from the same state."""
    r = HT.run(params, start, {"cooldown": cooldown}, max_events=CHECK_FLIGHTS)
    tr = simulate(params, start, max_events=CHECK_FLIGHTS)
    n = min(len(r.t), len(tr.t))
    off = np.nonzero(np.abs(r.t[:n] - tr.t[:n]) > DIVERGE_REL * np.abs(tr.t[:n]))[0]
    return {"failure": r.failure, "index": r.failure_index, "reason": r.extra["reason"],
            "leaves_bounce_at": int(off[0]) if off.size else -1, "impacts": len(r.t),
            "x_dot": start.xdot}


def depth_scan(params, cooldown, ratio) -> dict | None:
    """First x' = u of DEPTHS where heyoka fails within 200 impacts (module docstring, item 4b)."""
    for u in DEPTHS:
        res = HT.run(params, Deviations(0.0, u, ratio * u, 0.0), {"cooldown": cooldown}, max_events=200)
        if res.failure:
            return {"u": u, "failure": res.failure, "index": res.failure_index, "reason": res.extra["reason"]}
    return None


def run_law(name, args) -> dict:
    params = law_parameters(name)
    rho, a, b = LAWS[name]
    alpha = nonlin_alpha_limit(GAMMA, MU, rho, a, b)
    if args.windows_only:
        drops = {"drop": State.from_psi_xi(6.0, 0.0, params.xi_eq if name != "linear" else 0.0, 0.0)}
        if name != "linear":
            drops["paper drop"] = State.from_psi_xi(6.0, 0.0, 0.0, 0.0)
        return {"law": {"rho": rho, "a": a, "b": b}, "alpha": alpha, "rows": {}, "long": None, "cooldown": {},
                "drop_windows": drop_windows(params, drops["drop"], args.repeats, args.windows_only),
                "paper_drop_windows": (drop_windows(params, drops["paper drop"], args.repeats, args.windows_only)
                                       if "paper drop" in drops else [])}
    all_scenes = scenes(name, params)
    rows = {scene: scene_row(name, params, scene, init, args) for scene, init in all_scenes.items()}
    if args.cost_only:
        return {"law": {"rho": rho, "a": a, "b": b}, "alpha": alpha, "rows": rows, "long": None, "cooldown": {}}
    drop = all_scenes["drop"]
    windows = drop_windows(params, drop, args.repeats)
    tr = simulate(params, drop, max_events=max(CHECKPOINTS))
    checkpoints = {n: post_impact(tr, n - 1) for n in CHECKPOINTS}
    long = None
    if args.long:
        long, more = long_run(name, params, drop, args.long)
        if long["impacts"] > max(CHECKPOINTS):
            checkpoints[long["impacts"]] = more[long["impacts"]]
    deep = all_scenes["deep"]
    ratio = deep.xidot / deep.xdot
    cool = {}
    for c in COOLDOWNS:
        along = {str(n): heyoka_along(params, st, c) for n, st in sorted(checkpoints.items())}
        scan = depth_scan(params, c, ratio)
        if scan is not None:
            scan["drop_impact_index"] = 1.0 / (alpha * scan["u"])
        r = HT.run(params, deep, {"cooldown": c}, max_events=args.heyoka_events)
        cool[repr(c)] = {"along": along, "depth_scan": scan,
                         "deep_impacts_per_s": len(r.t) / r.cpu_time if r.cpu_time > 0 else None}
    clean_to = {k: (v["depth_scan"]["u"] if v["depth_scan"] else 0.0) for k, v in cool.items()}
    best = min(cool, key=lambda k: (clean_to[k], -(cool[k]["deep_impacts_per_s"] or 0.0)))
    return {"law": {"rho": rho, "a": a, "b": b}, "alpha": alpha, "rows": rows, "drop_windows": windows, "long": long,
            "cooldown": cool, "best_cooldown": best}


def _e(v):
    return "  n/a  " if v is None or (isinstance(v, float) and math.isnan(v)) else f"{v:.1e}"


def _r(v):
    return "  n/a  " if v is None else f"{v[0]:.2e} [{v[1]:.2e}, {v[2]:.2e}]"


def print_cost(rows: dict) -> None:
    """The split of heyoka's CPU per impact (module docstring, item 5)."""
    rows = {k: v["cost"] for k, v in rows.items() if "cost" in v}
    if not rows:
        return
    r0 = next(iter(rows.values()))
    print(f"heyoka's CPU per impact split (item 5): us of process CPU, medians of {r0['repeats']} interleaved rounds; "
          "'steps' = steps/impact x us/step (Taylor steps alone), 'events' = its event handling in C++ (root search "
          "every step, root isolation and step truncation at the impact, cooldown), 'C++' = steps + events (a C++ "
          "user with a C++ callback: + a few ns), 'callback' = Python - C++ (the Python callback, its calls in and out)")
    print(f"{'scene':11s} {'impacts':>7s} {'bounce':>7s} {'Python':>7s} {'steps/imp':>9s} {'us/step':>7s} "
          f"{'steps':>6s} {'events':>6s} {'C++':>6s} {'callback':>8s} | {'bounce faster: Python':>21s} {'C++':>6s} "
          f"{'steps':>6s} | {'CPU s':>5s} {'load 1-min':>10s}")
    for scene, c in rows.items():
        print(f"{scene:11s} {c['impacts']:7d} {c['us_per_impact_bounce']:7.3f} {c['us_per_impact_heyoka_python']:7.3f} "
              f"{c['steps_per_impact']:9.3f} {c['us_per_step_bare']:7.3f} {c['us_per_impact_steps_alone']:6.3f} "
              f"{c['us_per_impact_events']:6.3f} {c['us_per_impact_cpp_estimate']:6.3f} "
              f"{c['us_per_impact_python_callback']:8.3f} | {c['ratio_python']:20.1f}x {c['ratio_cpp_estimate']:5.2f}x "
              f"{c['ratio_steps_alone']:5.2f}x | {c['cpu_s']:5.2f} {c['load_1min'][0]:4.2f}-{c['load_1min'][1]:4.2f}")
    print("  shares of the Python user's cost (steps / events / callback): " + "; ".join(
        f"{scene} {100 * (1 - c['share_not_steps']):.0f} / {100 * c['share_events']:.0f} / "
        f"{100 * c['share_callback']:.0f} %" for scene, c in rows.items())
          + "; us/step with the floor's event checked every step (no root): " + ", ".join(
        f"{scene} {c['us_per_step_floor_check']:.3f}" for scene, c in rows.items()))


def print_report(res: dict, notes: list) -> None:
    print("\n".join(notes))
    for name, r in res.items():
        print(f"\n== {name}: rho, a, b = {r['law']['rho']:g}, {r['law']['a']:g}, {r['law']['b']:g}; "
              f"alpha = {r['alpha']:.4g} ==")
        print_cost(r["rows"])
        if any("impacts_per_s" not in row["bounce"] for row in r["rows"].values() if "bounce" in row) or all(
                "bounce" not in row for row in r["rows"].values()):
            continue  # --cost-only
        print(f"{'scene':11s} {'impacts':>7s} {'bounce impacts/s med [min, max]':33s} "
              f"{'heyoka impacts/s med [min, max]':33s} {'ratio':>6s} {'err bounce':>10s} {'err heyoka':>10s}"
              f"  heyoka outcome")
        for scene, row in r["rows"].items():
            h, b, o = row["heyoka"], row["bounce"], row["one_step"]
            out = (f"{h['failure']}@{h['index']}: {h['reason'][:70]}" if h["failure"] else "clean")
            print(f"{scene:11s} {row['same_impacts']:7d} {_r(b.get('impacts_per_s_same')):33s} "
                  f"{_r(h.get('impacts_per_s')):33s} {row.get('ratio', math.nan):6.1f} "
                  f"{_e(o['bounce_max']):>10s} {_e(o['heyoka_max']):>10s}  {out}")
        for scene, row in r["rows"].items():
            if row["heyoka"].get("impacts_per_s_checked"):
                h, o = row["heyoka"], row["one_step"]
                print(f"  {scene}: heyoka at {ACCURATE}: {_r(h['impacts_per_s_accurate'])} impacts/s, ratio "
                      f"{row['bounce']['impacts_per_s_same'][0] / h['impacts_per_s_accurate'][0]:.1f}, one-step error "
                      f"{_e(o['heyoka_accurate_max'])}; heyoka through bounce.methods.heyoka_taylor.run (per-flight "
                      f"failure checks): {_r(h['impacts_per_s_checked'])} impacts/s")
        for key in ("drop_windows", "paper_drop_windows"):
            if r.get(key):
                print(f"{key.replace('_windows', '')} by windows of impact index (both from bounce's exact state "
                      "at the window's start):")
            for w in r.get(key, []):
                print(f"  impacts [{w['from']:6d}, {w['to']:6d}) x' at start {w['x_dot_at_start']:.1e}: bounce "
                      f"{_r(w['bounce'])}, heyoka {_r(w.get('heyoka'))}, ratio {w.get('ratio', math.nan):.2g}"
                      + (f" (heyoka {w['heyoka_failure']})" if w["heyoka_failure"] else ""))
        for scene, row in r["rows"].items():
            b = row["bounce"]
            print(f"bounce alone, {scene}: {b['impacts']} impacts, {_r(b['impacts_per_s'])} impacts/s, "
                  f"stop {b['stop']}, all impacts {b['all_impacts']}")
        lr = r["long"]
        if lr:
            print(f"long run: {lr['impacts']} of {lr['requested']} impacts in {lr['cpu_s']:.1f} s CPU "
                  f"({lr['impacts_per_s']:.3g}/s), all impacts {lr['all_impacts']}, first flight per chunk vs mpmath "
                  f"max rel. err {lr['first_flight_of_chunk_max_rel_err_tau']:.1e}, skipped: {lr['skipped']}")
        for c, v in r["cooldown"].items():
            along = "; ".join(f"n={n}: " + (f"{a['failure']}@+{a['index']}" if a["failure"] else "clean")
                              + (f" (leaves bounce @+{a['leaves_bounce_at']})" if a["leaves_bounce_at"] >= 0 else "")
                              for n, a in v["along"].items())
            s = v["depth_scan"]
            scan = f"clean to x' = {DEPTHS[-1]:g}" if s is None else (
                f"fails at x' = {s['u']:g} (drop impact n ~ {s['drop_impact_index']:.1e}): "
                f"{s['failure']}@{s['index']} {s['reason'][:80]}")
            print(f"cooldown {c:>6s}: {along}\n{'':17s}depth scan: {scan}")
        if r["cooldown"]:
            print(f"best cooldown setting: {r['best_cooldown']}")


def main(argv=None):
    ap = argparse.ArgumentParser(description="bounce vs heyoka on the Hertz spring, same run (module docstring).")
    ap.add_argument("--law", nargs="+", default=["hertz"], choices=list(LAWS))
    ap.add_argument("--events", type=int, default=1_000_000, help="impacts of bounce alone (default 1e6)")
    ap.add_argument("--heyoka-events", type=int, default=20_000, help="impacts timed for both (default 2e4)")
    ap.add_argument("--repeats", type=int, default=5, help="timing repeats (default 5)")
    ap.add_argument("--long", type=int, default=10_000_000, help="bounce impacts of the skip check (0: none)")
    ap.add_argument("--windows-only", type=int, default=0, metavar="N",
                    help="only the drop windows (both drops) up to impact N, e.g. 1000 (default 0: full run)")
    ap.add_argument("--cost-only", action="store_true",
                    help="only the split of heyoka's cost per impact (item 5) on each scene, ~10 s a law")
    ap.add_argument("--json", type=Path, default=None,
                    help="default results/timing/bench_power.json (--cost-only: bench_power_cost.json)")
    args = ap.parse_args(argv)
    if args.json is None:
        args.json = ROOT / "results" / "timing" / ("bench_power_cost.json" if args.cost_only else "bench_power.json")
    wall = time.time()
    load = os.getloadavg()
    commit = subprocess.run(["git", "rev-parse", "--short=12", "HEAD"], cwd=ROOT, capture_output=True,
                            text=True).stdout.strip()
    notes = [pin_to_one_core(), f"heyoka {__import__('heyoka').__version__}, tol 2^-52; Python {platform.python_version()}; "
             f"commit {commit}; load average at start {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}",
             f"timings: process CPU time, medians of {args.repeats}; command: {' '.join(sys.argv)}"]
    res = {name: run_law(name, args) for name in args.law}
    load_end = os.getloadavg()
    notes.append(f"load average at end {load_end[0]:.2f} {load_end[1]:.2f} {load_end[2]:.2f}; "
                 f"wall time {time.time() - wall:.0f} s")
    print_report(res, notes)
    args.json.parent.mkdir(parents=True, exist_ok=True)
    tmp = args.json.with_suffix(".tmp")
    tmp.write_text(json.dumps({"notes": notes, "results": res}, indent=1, default=str))
    tmp.replace(args.json)
    print(f"written {args.json}")


if __name__ == "__main__":
    main()

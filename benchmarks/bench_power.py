"""Peer benchmark for the power-law spring (issue 9): bounce against heyoka, same run, one core.

Laws (gamma = mu = 0.01, rho = 1): ``linear`` (a = b = 0) and ``hertz`` (a = b = 1/2) of eq.
``eq-motion-nonlin-psi-xi``.  Scenes per law:

* ``drop``: linear: the paper's drop psi(0) = 6, xi = xi' = psi' = 0.  Hertz: the same drop with
  the spring at its static compression xi(0) = xi_eq, because with xi(0) = 0 heyoka cannot start
  (the Taylor coefficients of |xi|^(1/2) are not finite there); the paper's drop is its own row
  (``paper drop, xi(0) = 0``);
* ``deep``: a post-impact state deep in the asymptotic regime: bounce's state after 1e5 impacts of
  the drop where bounce simulates the law, else x = 0, x' = 1e-8, xi' = 2e-9, eta = 1e-13.

Measured for each (law, scene), in the same run:

* impacts/s: median (min, max) of ``--repeats`` runs; bounce over ``--events`` impacts (after a
  warm-up call: no JIT compile), heyoka over ``--heyoka-events`` (integrator compiled once and
  reused); ratio bounce / heyoka of the medians;
* one-step error: from the same float64 post-impact states (the scene's start and the first
  ``--one-step`` states of heyoka's run), each solver does one flight; the largest relative error
  of tau, x', xi' after the impact (eta against max(|eta|, 1e-6 |xi_eq|)) against the independent
  mpmath reference ``tests/power_reference.py`` (50 digits) given exactly the state the solver
  started from;
* skipped impacts: bounce: every event an impact and the run complete (its root finder cannot
  skip one); heyoka: its own failure report (missed impact / stall, index and reason), and the
  first impact where its times leave bounce's by more than 1e-9 relative (in the drop that is the
  chaos of the transient, not a skip; in the deep scene a skip);
* heyoka's event cooldown: its default (automatic) and each of ``COOLDOWNS``, along the deep
  scene, and a depth scan: deep states with x' = u (u = 1e-6 ... 1e-11), 200 impacts each; the
  first u where it fails, with the reason, and the asymptotic impact index it corresponds to,
  n ~ 1/(alpha u) with alpha = mu (3 gamma)^-1 (gamma/rho)^(b/(a+1)) (paper, Discussion).  The
  best setting is the one clean to the smallest u (ties: the faster).

The bounce side is :func:`bounce_run`: ``bounce.simulate`` for the linear law and the power-law
solver (``bounce.power_events.simulate_power``) once it is on main; until then the Hertz rows
show heyoka alone.

Run::

    python benchmarks/bench_power.py                     # defaults: 1e6 / 2e4 impacts, 5 repeats
    python benchmarks/bench_power.py --json results/bench_power.json
"""

from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np
from mpmath import mp, mpf

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))
import power_reference as PR  # noqa: E402

from bounce import Deviations, Parameters, State, simulate  # noqa: E402
from bounce.methods import heyoka_taylor as HT  # noqa: E402
from bounce.simulate import EXACT_LAWS  # noqa: E402
from bounce.springs import SPRING_LAWS  # noqa: E402

GAMMA = MU = 0.01
LAWS = {"linear": (1.0, 0.0, 0.0), "hertz": (1.0, 0.5, 0.5)}
COOLDOWNS = (None, 0.0, 1e-15, 1e-12, 1e-9)
DEPTHS = (1e-6, 1e-7, 3e-8, 1e-8, 3e-9, 1e-9, 1e-10, 1e-11)
DEEP_INDEX = 100_000
DIVERGE_REL = 1e-9


def pin_to_one_core():
    if not hasattr(os, "sched_setaffinity"):
        return "not pinned (os.sched_setaffinity unavailable)"
    allowed = sorted(os.sched_getaffinity(0))
    os.sched_setaffinity(0, {allowed[-1]})
    return f"pinned to core {allowed[-1]} of {allowed}"


def law_setup(name):
    """(params, heyoka setting): the power law through Parameters once bounce registers it,
    else heyoka's own law setting on top of linear Parameters."""
    rho, a, b = LAWS[name]
    if name == "linear":
        return Parameters(GAMMA, MU), {}
    power = SPRING_LAWS.get("power")
    if power is None:
        return Parameters(GAMMA, MU), {"rho": rho, "a": a, "b": b}
    return Parameters(GAMMA, MU, power(rho=rho, a=a, b=b)), {}


def bounce_run(params, initial, events, law="linear"):
    """bounce's exact solver for the law (the one call that selects the power-law solver), or None
    while the power-law solver (and the law in ``params.spring``) is not available."""
    if law == "linear":
        return simulate(params, initial, max_events=events)
    if params.spring.name != "power":
        return None
    if "power" in EXACT_LAWS:
        return simulate(params, initial, max_events=events)
    try:
        from bounce.power_events import simulate_power
    except ImportError:
        return None
    return simulate_power(params, params.spring, initial, max_events=events)


def deviations(params, xi_eq, x, u, a, eta):
    """Deviations for ``params`` of the state (x, u, a, xi = xi_eq + eta) (eta re-referenced if needed)."""
    return Deviations(x, u, a, eta if xi_eq == params.xi_eq else (xi_eq - params.xi_eq) + eta)


def scenes(name, params, setting):
    """name -> initial state of the law's scenes (module docstring)."""
    xi_eq = HT.spring_law(params, setting)[3]
    paper_drop = State.from_psi_xi(6.0, 0.0, 0.0, 0.0)
    out = {"drop": paper_drop} if name == "linear" else {
        "paper drop, xi(0) = 0": paper_drop, "drop": State.from_psi_xi(6.0, 0.0, xi_eq, 0.0)}
    tr = bounce_run(params, out["drop"], DEEP_INDEX, name)
    if tr is not None:
        k = DEEP_INDEX - 1
        out["deep"] = Deviations(0.0, float(tr.xdot[k]), float(tr.xidot[k]), float(tr.eta[k]))
    else:
        out["deep"] = deviations(params, xi_eq, 0.0, 1e-8, 2e-9, 1e-13)
    return out


def timed(fn, repeats):
    """(median, min, max) of impacts/s over ``repeats`` calls of fn() -> (impacts, cpu seconds)."""
    rates = []
    for _ in range(repeats):
        n, cpu = fn()
        rates.append(n / cpu if cpu > 0 else math.inf)
    return statistics.median(rates), min(rates), max(rates)


def reference_error(start, out, law):
    """Largest relative error of one flight's (tau, x', xi', eta) against the mpmath reference."""
    rho, a, b = law
    with mp.workdps(PR.DPS + 10):
        xi = mpf(start["xi_eq"]) + mpf(start["eta"])
    ref = PR.reference_first_impact(GAMMA, MU, rho, a, b, start["x"], start["xdot"], start["xidot"], xi)
    with mp.workdps(PR.DPS):
        eta_ref = ref["xi"] - mpf(start["xi_eq"])
        errs = [abs((mpf(out[k]) - ref[k]) / ref[k]) for k in ("tau", "xdot", "xidot")]
        errs.append(abs(mpf(out["eta"]) - eta_ref) / max(abs(eta_ref), mpf(1e-6) * abs(mpf(start["xi_eq"]))))
        return float(max(errs))


def heyoka_one(params, setting, initial):
    res = HT.run(params, initial, setting, max_events=1)
    if res.failure:
        return res.extra["start"], None
    return res.extra["start"], {"tau": res.t[0], "xdot": res.xdot[0], "xidot": res.extra["xidot"][0],
                                "eta": res.extra["eta"][0]}


def bounce_one(params, initial, law):
    tr = bounce_run(params, initial, 1, law)
    if tr is None:
        return None
    return {"tau": tr.tau[0], "xdot": tr.xdot[0], "xidot": tr.xidot[0], "eta": tr.eta[0]}


def depth_scan(params, setting, xi_eq, cooldown):
    """First x' = u of DEPTHS where heyoka fails within 200 impacts: (u, failure, index, reason) or None."""
    for u in DEPTHS:
        init = deviations(params, xi_eq, 0.0, u, 0.2 * u, 0.0)
        res = HT.run(params, init, {**setting, "cooldown": cooldown}, max_events=200)
        if res.failure:
            return u, res.failure, res.failure_index, res.extra["reason"]
    return None


def run_law(name, args, out):
    params, setting = law_setup(name)
    law = LAWS[name]
    rho, a, b = law
    xi_eq = HT.spring_law(params, setting)[3]
    alpha = MU / (3 * GAMMA) * (GAMMA / rho) ** (b / (a + 1))
    rows = {}
    all_scenes = scenes(name, params, setting)
    for scene, init in all_scenes.items():
        row = {}
        HT.run(params, init, setting, max_events=10)  # compile once
        first = HT.run(params, init, setting, max_events=args.heyoka_events)
        row["heyoka"] = {"failure": first.failure, "index": first.failure_index, "reason": first.extra["reason"],
                         "impacts": len(first.t), "cooldown_used": first.extra["cooldown"]}

        def heyoka_timing():
            r = HT.run(params, init, setting, max_events=args.heyoka_events)
            return len(r.t), r.cpu_time

        row["heyoka"]["impacts_per_s"] = timed(heyoka_timing, args.repeats)
        tr = bounce_run(params, init, args.events, name)
        if tr is not None:
            def bounce_timing():
                start = time.process_time()
                t = bounce_run(params, init, args.events, name)
                return len(t.t), time.process_time() - start

            row["bounce"] = {"impacts_per_s": timed(bounce_timing, args.repeats), "stop": tr.stop_reason,
                             "all_impacts": bool((tr.kind == 0).all()), "impacts": len(tr.t)}
            h_rate = row["heyoka"]["impacts_per_s"][0]
            row["ratio"] = row["bounce"]["impacts_per_s"][0] / h_rate if h_rate > 0 else math.inf
            n = min(len(first.t), len(tr.t))
            off = np.nonzero(np.abs(first.t[:n] - tr.t[:n]) > DIVERGE_REL * np.abs(tr.t[:n]))[0]
            row["heyoka_leaves_bounce_at"] = int(off[0]) if off.size else -1
        # one-step errors from the same float64 states
        states = [init] + [deviations(params, first.extra["start"]["xi_eq"], 0.0, first.xdot[k],
                                      first.extra["xidot"][k], first.extra["eta"][k])
                           for k in range(min(args.one_step, len(first.t)))]
        errs_h, errs_b = [], []
        for st in states:
            start, res_h = heyoka_one(params, setting, st)
            if res_h is not None:
                errs_h.append(reference_error(start, res_h, law))
            res_b = bounce_one(params, st, name)
            if res_b is not None:
                dev = st.deviations(params)
                errs_b.append(reference_error({"x": dev.x, "xdot": dev.xdot, "xidot": dev.xidot, "eta": dev.eta,
                                               "xi_eq": params.xi_eq}, res_b, law))
        row["heyoka"]["one_step_error"] = max(errs_h) if errs_h else None
        if errs_b:
            row.setdefault("bounce", {})["one_step_error"] = max(errs_b)
        rows[scene] = row
    # heyoka's cooldown: along the deep scene and by depth
    cool = {}
    deep = all_scenes["deep"]
    for c in COOLDOWNS:
        setting_c = {**setting, "cooldown": c}
        r = HT.run(params, deep, setting_c, max_events=args.heyoka_events)
        scan = depth_scan(params, setting, xi_eq, c)
        cool[repr(c)] = {
            "deep": {"failure": r.failure, "index": r.failure_index, "reason": r.extra["reason"],
                     "impacts_per_s": len(r.t) / r.cpu_time if r.cpu_time > 0 else None},
            "depth_scan": None if scan is None else {
                "u": scan[0], "failure": scan[1], "index": scan[2], "reason": scan[3],
                "asymptotic_impact_index": 1.0 / (alpha * scan[0])},
        }
    clean_to = {k: (v["depth_scan"]["u"] if v["depth_scan"] else 0.0) for k, v in cool.items()}
    best = min(cool, key=lambda k: (clean_to[k], -(cool[k]["deep"]["impacts_per_s"] or 0.0)))
    out[name] = {"rows": rows, "cooldown": cool, "best_cooldown": best, "alpha": alpha}


def _e(v):
    return "n/a" if v is None else f"{v:.2e}"


def print_report(res, notes):
    print("\n".join(notes))
    for name, r in res.items():
        print(f"\n== {name} (alpha = {r['alpha']:.4g}) ==")
        for scene, row in r["rows"].items():
            h = row["heyoka"]
            line = f"{scene:22s} heyoka: "
            if "impacts_per_s" in h:
                med, lo, hi = h["impacts_per_s"]
                line += f"{med:.3g} impacts/s [{lo:.3g}, {hi:.3g}], one-step err {_e(h['one_step_error'])}"
            line += f", failure {h['failure'] or 'none'}@{h['index']} {h['reason']}"
            print(line)
            b = row.get("bounce")
            if b and "impacts_per_s" in b:
                med, lo, hi = b["impacts_per_s"]
                print(f"{'':22s} bounce: {med:.3g} impacts/s [{lo:.3g}, {hi:.3g}], one-step err "
                      f"{_e(b.get('one_step_error'))}, stop {b['stop']}, all impacts {b['all_impacts']}; "
                      f"ratio {row['ratio']:.3g}; heyoka leaves bounce at impact {row['heyoka_leaves_bounce_at']}")
            elif "impacts_per_s" in h:
                print(f"{'':22s} bounce: power-law solver not available on this branch")
        for c, v in r["cooldown"].items():
            d, s = v["deep"], v["depth_scan"]
            scan = "clean to u = %g" % DEPTHS[-1] if s is None else (
                f"fails at u = {s['u']:g} (asymptotic n ~ {s['asymptotic_impact_index']:.2g}): "
                f"{s['failure']}@{s['index']} {s['reason'][:90]}")
            print(f"cooldown {c:>7s}: deep run {d['failure'] or 'clean'}@{d['index']}; depth scan: {scan}")
        print(f"best cooldown setting: {r['best_cooldown']}")


def main(argv=None):
    ap = argparse.ArgumentParser(description="bounce vs heyoka on the linear and Hertz springs (module docstring).")
    ap.add_argument("--events", type=int, default=1_000_000, help="impacts per bounce run (default 1e6)")
    ap.add_argument("--heyoka-events", type=int, default=20_000, help="impacts per heyoka run (default 2e4)")
    ap.add_argument("--repeats", type=int, default=5, help="timing repeats (default 5)")
    ap.add_argument("--one-step", type=int, default=2, help="post-impact states per scene for one-step errors")
    ap.add_argument("--laws", nargs="+", default=list(LAWS), choices=list(LAWS))
    ap.add_argument("--json", type=Path, help="also write the results here")
    args = ap.parse_args(argv)
    notes = [pin_to_one_core(), f"heyoka {__import__('heyoka').__version__}, tol 2^-52; "
             f"bounce impacts/s over {args.events}, heyoka over {args.heyoka_events}, medians of {args.repeats}"]
    res = {}
    for name in args.laws:
        run_law(name, args, res)
    print_report(res, notes)
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        tmp = args.json.with_suffix(".tmp")
        tmp.write_text(json.dumps({"notes": notes, "results": res}, indent=1, default=str))
        tmp.replace(args.json)


if __name__ == "__main__":
    main()

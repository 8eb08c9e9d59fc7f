"""Speed benchmark of ``bounce.simulate`` against a scipy ``solve_ivp`` baseline.

What is measured, for the two scenes of the paper (section 2 model,
eq. ``dimensionless-eq-motion``; psi' = xi = xi' = 0 at t = 0):

  A  gamma = mu = 0.01,       psi(0) = 6      (the chaotic transient figure)
  B  gamma = 1e-5, mu = 2,    psi(0) = 0.25   (the overdamped example)

* ``bounce``: wall time of ``simulate(Parameters(gamma, mu),
  State.from_psi_xi(psi0, 0, 0, 0), max_events=N)`` (N = 1e6 by default), after
  a warm-up call, ``--repeats`` times; median, min and max of impacts/s.
* ``scipy``: the method ``scipy`` of :mod:`bounce.methods.scipy_ivp` (the one solve_ivp driver:
  DOP853, rtol = atol = 1e-12, terminal event x = 0 crossed downwards, restart after every
  impact with x' -> -x').  It is orders of magnitude slower, so it gets a CPU
  budget: one *long* run with its failure checks on (``--scipy-seconds``, default 20 s,
  or until it loses an impact) gives how far it got and how accurate it was;
  its speed is then timed ``--repeats`` times, checks off, on the first K
  impacts, K = what a run with checks on does in ``--scipy-timing-seconds``
  (default 3 s).  ``bounce`` is timed on the same K impacts as well
  (row "bounce, same K"), which is the like-for-like ratio; the 1e6-impact row
  covers later (shorter) flights too.
* ratio = median impacts/s of the row / median impacts/s of scipy, same scene,
  same run of this script.
* error: relative error of the first impact time t1 against the exact
  sqrt(2 psi0 / gamma) (free fall of the centre of mass with the spring at
  rest), and the largest relative error of t1..t10 against an independent
  mpmath computation (:mod:`bounce.analysis.reference`: closed-form flights -- psi'' = -gamma,
  xi'' + 2 mu xi' + xi = 0 -- with the impact rule psi' <-> xi', 50 digits).
* lost impact (scipy, see :mod:`bounce.methods.scipy_ivp` for the rules): the first failure of the
  long run (missed_impact: a step over a dip of x below the floor; fell_through; stall: zero-length
  flights; energy_gain; collapse); and separately the first impact whose time differs from
  bounce's by more than 1e-6 relative (the transient of A is chaotic, so this happens after a few
  tens of impacts whatever the method).
* numba JIT: in a fresh process with NUMBA_CACHE_DIR set to a new temporary
  directory, the time of ``import bounce`` and of the first
  ``simulate(..., max_events=10)`` (= compile time); then the same in a second
  fresh process with that cache now filled (warm cache).

The process (and its subprocesses) is pinned to one core with
``os.sched_setaffinity`` when available.  The machine may be shared: quote the
medians and the ratios, not single runs.

Run::

    python benchmarks/bench_simulator.py --events 1000000 --repeats 5
    python benchmarks/bench_simulator.py --json results/bench.json
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
import tempfile
import time
from pathlib import Path

import numpy as np

#: the solve_ivp setting of the benchmark (bounce.methods.scipy_ivp): DOP853 at rtol = atol = 1e-12
SCIPY = {"solver": "DOP853", "rtol": 1e-12, "atol": 1e-12}
#: failures of bounce.methods.scipy_ivp that lose an impact (not the CPU budget)
LOST = ("missed_impact", "fell_through", "stall", "energy_gain", "collapse")

SCENES = {
    "A": dict(gamma=0.01, mu=0.01, psi0=6.0),
    "B": dict(gamma=1e-5, mu=2.0, psi0=0.25),
}
N_REF = 10  # impacts checked against the mpmath reference
DIVERGE_REL = 1e-6


# --------------------------------------------------------------------------
# independent high-precision reference for the first impacts
# --------------------------------------------------------------------------

def reference_impacts(gamma, mu, psi0, n=N_REF):
    """First ``n`` impact times (mpf) from psi(0) = psi0, xi = psi' = xi' = 0, by :mod:`bounce.analysis.reference`
    (50 digits; its root search cannot skip an impact).  In its deviation variables the start is
    x = psi0, xdot = xi' = 0, eta = xi + gamma = gamma."""
    from bounce.analysis import reference

    times, _, _ = reference.trajectory(gamma, mu, reference.Dev(psi0, 0.0, 0.0, gamma), n)
    return times


def errors_vs_reference(t, ref, t1_exact):
    """(relative error of t1 vs the exact sqrt, max relative error of t1..t_n vs mpmath)."""
    import mpmath

    n = min(len(t), len(ref))
    if n == 0:
        return math.nan, math.nan
    e1 = float(abs((mpmath.mpf(float(t[0])) - t1_exact) / t1_exact))
    en = max(float(abs((mpmath.mpf(float(t[k])) - ref[k]) / ref[k])) for k in range(n))
    return e1, en


# --------------------------------------------------------------------------
# timing helpers
# --------------------------------------------------------------------------

def pin_to_one_core():
    if not hasattr(os, "sched_setaffinity"):
        return "not pinned (os.sched_setaffinity unavailable)"
    allowed = sorted(os.sched_getaffinity(0))
    core = allowed[-1]
    os.sched_setaffinity(0, {core})
    return f"pinned to core {core} of {allowed} with os.sched_setaffinity (subprocesses inherit it)"


def time_bounce(params, state, n_events, repeats):
    """Wall times of ``repeats`` calls (each a loop of calls lasting >= 0.2 s if one call is short)."""
    from bounce import simulate

    tr = simulate(params, state, max_events=n_events)  # warm-up (cache load / compile)
    t0 = time.perf_counter()
    simulate(params, state, max_events=n_events)
    once = time.perf_counter() - t0
    inner = max(1, int(math.ceil(0.2 / max(once, 1e-6)))) if once < 0.2 else 1
    walls = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        for _ in range(inner):
            simulate(params, state, max_events=n_events)
        walls.append((time.perf_counter() - t0) / inner)
    return tr, walls, inner


def jit_times(repeats):
    """Cold-cache and warm-cache import + first call, each in a fresh subprocess.

    The cache is redirected to a new temporary directory through both
    NUMBA_CACHE_DIR and BOUNCE_NUMBA_CACHE_DIR (bounce points numba's cache at
    a subdirectory of the latter, keyed by the core's source, see
    bounce/_jit_cache.py).  Checks: the subprocess reports numba's CACHE_DIR,
    which must lie in the temporary directory; the cold run must have written
    cache files there; the warm run must not have written new ones (else the
    source changed in between or the cache missed, and the run is flagged).
    """
    code = (
        "import json, time\n"
        "t0 = time.perf_counter()\n"
        "from bounce import Parameters, State, simulate\n"
        "t1 = time.perf_counter()\n"
        "simulate(Parameters(0.01, 0.01), State.from_psi_xi(6.0, 0.0, 0.0, 0.0), max_events=10)\n"
        "t2 = time.perf_counter()\n"
        "simulate(Parameters(0.01, 0.01), State.from_psi_xi(6.0, 0.0, 0.0, 0.0), max_events=10)\n"
        "t3 = time.perf_counter()\n"
        "import numba\n"
        "print(json.dumps({'import': t1 - t0, 'first_call': t2 - t1, 'second_call': t3 - t2,\n"
        "                  'cache_dir': str(numba.config.CACHE_DIR)}))\n"
    )

    def files(root):
        return {(p.name, p.stat().st_mtime_ns) for p in Path(root).rglob("*") if p.is_file()}

    out = {"cold": [], "warm": []}
    for _ in range(repeats):
        with tempfile.TemporaryDirectory(prefix="bounce-numba-cache-") as cache:
            env = dict(os.environ, NUMBA_CACHE_DIR=cache, BOUNCE_NUMBA_CACHE_DIR=cache)
            env.pop("NUMBA_DISABLE_JIT", None)
            for which in ("cold", "warm"):
                before = files(cache)
                r = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
                d = json.loads(r.stdout.strip().splitlines()[-1])
                after = files(cache)
                d["cache_in_tmp"] = d["cache_dir"].startswith(cache)
                d["files_written"] = len(after - before)
                d["ok"] = d["cache_in_tmp"] and (d["files_written"] > 0 if which == "cold" else d["files_written"] == 0)
                out[which].append(d)
    return out


def _list(runs, key):
    return ", ".join(f"{d[key]:.2f}" for d in runs)


def _first_over(a, b, thr):
    n = min(len(a), len(b))
    if n == 0:
        return None
    rel = np.abs(a[:n] - b[:n]) / np.abs(b[:n])
    idx = np.nonzero(rel > thr)[0]
    return int(idx[0]) if idx.size else None


# --------------------------------------------------------------------------

def run_scene(name, cfg, args, notes):
    import mpmath
    from bounce import Parameters, State
    from bounce.kinds import IMPACT
    from bounce.methods import scipy_ivp

    gamma, mu, psi0 = cfg["gamma"], cfg["mu"], cfg["psi0"]
    params = Parameters(gamma, mu)
    state = State.from_psi_xi(psi0, 0.0, 0.0, 0.0)
    label = f"{name} (g={gamma:g}, mu={mu:g}, psi0={psi0:g})"

    # reference
    ref = reference_impacts(gamma, mu, psi0)
    mpmath.mp.dps = 40
    t1_exact = mpmath.sqrt(2 * mpmath.mpf(psi0) / mpmath.mpf(gamma))
    if abs(ref[0] - t1_exact) / t1_exact > mpmath.mpf(10) ** -30:
        raise RuntimeError("reference t1 disagrees with the closed form")

    # bounce, N events
    tr, walls, _ = time_bounce(params, state, args.events, args.repeats)
    imp = tr.kind == IMPACT
    n_imp = int(imp.sum())
    t_imp = tr.t[imp]
    rates = [n_imp / w for w in walls]
    err_b = errors_vs_reference(t_imp, ref, t1_exact)

    # scipy long run (checks on), and K = what it does in the timing budget
    long = scipy_ivp.run(params, state, dict(SCIPY, cpu_budget=args.scipy_seconds), max_events=args.events)
    lost_index = long.failure_index if long.failure in LOST else None
    probe = scipy_ivp.run(params, state, dict(SCIPY, cpu_budget=args.scipy_timing_seconds), max_events=args.events)
    K = len(probe.t)
    if lost_index is not None:
        K = min(K, lost_index)
    K = min(max(K, 1), len(long.t))
    err_s = errors_vs_reference(long.t, ref, t1_exact)
    div = _first_over(long.t, t_imp, DIVERGE_REL)
    tau_b = np.diff(np.concatenate(([0.0], t_imp)))
    tau_s = np.diff(np.concatenate(([0.0], long.t)))
    div_tau = _first_over(tau_s, tau_b, DIVERGE_REL)

    # scipy timing runs (checks off), first K impacts
    s_walls = []
    for _ in range(args.repeats):
        r = scipy_ivp.run(params, state, dict(SCIPY, check=False, cpu_budget=10 * args.scipy_seconds), max_events=K)
        if len(r.t) != K:
            raise RuntimeError(f"scipy timing run stopped early: {r.failure}")
        s_walls.append(r.cpu_time)
    s_rates = [K / w for w in s_walls]
    s_med = statistics.median(s_rates)

    # bounce on the same K impacts
    trK, wallsK, innerK = time_bounce(params, state, K, args.repeats)
    ratesK = [int((trK.kind == IMPACT).sum()) / w for w in wallsK]

    # naive restart (event g = x after impacts too): how soon does it stall?
    naive = scipy_ivp.run(params, state, dict(SCIPY, check=False, restart="plain", cpu_budget=args.naive_seconds),
                          max_events=args.events)
    naive_lost = naive.failure_index if naive.failure in LOST else None

    rows = []
    for method, n, ws, rs, err in (
        ("bounce", n_imp, walls, rates, err_b),
        ("bounce, same K", K, wallsK, ratesK, err_b),
        ("scipy DOP853 1e-12", K, s_walls, s_rates, err_s),
    ):
        rows.append({
            "scene": label, "method": method, "impacts": n,
            "median_wall_s": statistics.median(ws), "rate_median": statistics.median(rs),
            "rate_min": min(rs), "rate_max": max(rs), "err_t1": err[0], f"err_t1_t{N_REF}": err[1],
            "ratio_to_scipy": statistics.median(rs) / s_med,
        })

    n_long = len(long.t)
    long_info = {
        "impacts": n_long, "cpu_s": long.cpu_time, "rate": n_long / long.cpu_time if long.cpu_time else math.nan,
        "stop_reason": long.failure or "max_events", "steps": long.extra["nsteps"], "rhs_calls": long.extra["nfev"],
        "lost_index": lost_index, "lost_reason": long.failure if lost_index is not None else None,
        "first_rel_time_diff_gt_1e-6": div, "first_rel_tau_diff_gt_1e-6": div_tau,
        "naive_restart": {"impacts": len(naive.t), "stop_reason": naive.failure or "max_events",
                          "lost_index": naive_lost, "cpu_s": naive.cpu_time},
        "bounce_stop_reason": tr.stop_reason, "bounce_events": len(tr),
        "bounce_t_end": float(tr.t[-1]),
    }
    lost = ("none within the budget" if lost_index is None
            else f"at impact #{lost_index + 1} ({long.failure}, t = {long.t_end:.10g})")
    notes.append(
        f"{name}: scipy long run (failure checks on): {n_long} impacts in {long.cpu_time:.1f} s "
        f"= {long_info['rate']:.3g}/s, {long_info['steps']} steps, {long_info['rhs_calls']} rhs calls, stop: "
        f"{long_info['stop_reason']}; reached t = {long.t[-1] if n_long else 0:.8g} (bounce's {len(tr):,} events "
        f"reach t = {tr.t[-1]:.8g})"
    )
    notes.append(f"{name}: scipy lost an impact (missed impact / fell through / stall / energy gain / collapse): {lost}")
    notes.append(
        f"{name}: first impact whose time differs from bounce's by > 1e-6 relative: "
        f"{'#' + str(div + 1) if div is not None else 'none'} "
        f"(flight duration tau > 1e-6 relative: {'#' + str(div_tau + 1) if div_tau is not None else 'none'}; "
        f"of {min(n_long, n_imp)} compared)"
    )
    notes.append(
        f"{name}: naive restart (event g = x after an impact too): "
        + (f"{naive.failure} at impact #{naive_lost + 1} after {naive.cpu_time:.1f} s"
           if naive_lost is not None else
           f"no stall in {len(naive.t)} impacts ({naive.cpu_time:.1f} s, {naive.failure or 'max_events'})")
    )
    return rows, long_info


def main(argv=None):
    ap = argparse.ArgumentParser(description="Speed benchmark of bounce.simulate vs scipy solve_ivp (see module docstring).")
    ap.add_argument("--events", type=float, default=1e6, help="impacts per bounce run (default 1e6)")
    ap.add_argument("--repeats", type=int, default=5, help="timing repeats (default 5)")
    ap.add_argument("--scipy-seconds", type=float, default=20.0, help="budget of the long scipy run per scene (default 20)")
    ap.add_argument("--scipy-timing-seconds", type=float, default=3.0,
                    help="K = impacts of the long scipy run within this time; scipy is timed on K (default 3)")
    ap.add_argument("--naive-seconds", type=float, default=10.0, help="budget of the naive-restart scipy run (default 10)")
    ap.add_argument("--jit-repeats", type=int, default=3, help="cold/warm JIT subprocess pairs (default 3)")
    ap.add_argument("--scenes", default="AB", help="subset of scenes, e.g. A")
    ap.add_argument("--json", metavar="FILE", help="also save the table and details as JSON")
    args = ap.parse_args(argv)
    args.events = int(args.events)

    pin = pin_to_one_core()
    load0 = os.getloadavg() if hasattr(os, "getloadavg") else None
    started = time.perf_counter()
    import numba
    import scipy

    import bounce

    jit = jit_times(args.jit_repeats)
    rows, details, notes = [], {}, []
    for name in args.scenes:
        r, d = run_scene(name, SCENES[name], args, notes)
        rows += r
        details[name] = d
    load1 = os.getloadavg() if hasattr(os, "getloadavg") else None

    # ---- print
    head = ["scene", "method", "impacts", "median wall [s]", "impacts/s median (min-max)",
            "rel err t1", f"max rel err t1..t{N_REF}", "ratio vs scipy"]
    body = [[r["scene"], r["method"], f"{r['impacts']:,}", f"{r['median_wall_s']:.4g}",
             f"{r['rate_median']:.3g} ({r['rate_min']:.3g}-{r['rate_max']:.3g})",
             f"{r['err_t1']:.1e}", f"{r[f'err_t1_t{N_REF}']:.1e}", f"{r['ratio_to_scipy']:.3g}"] for r in rows]
    widths = [max(len(h), *(len(b[i]) for b in body)) for i, h in enumerate(head)]
    lines = [
        f"bounce {bounce.__version__} speed benchmark -- python {platform.python_version()}, numpy {np.__version__}, "
        f"scipy {scipy.__version__}, numba {numba.__version__}, {platform.machine()}, {os.cpu_count()} cpus",
        f"{pin}; load average {load0[0]:.2f} at start, {load1[0]:.2f} at end" if load0 else pin,
        f"repeats = {args.repeats}; bounce N = {args.events:,} events; scipy: long run {args.scipy_seconds:g} s, "
        f"timed on the first K impacts (K = what it did in {args.scipy_timing_seconds:g} s)",
        "",
        "  ".join(h.ljust(w) for h, w in zip(head, widths)),
        "  ".join("-" * w for w in widths),
    ]
    lines += ["  ".join(c.ljust(w) for c, w in zip(b, widths)) for b in body]
    lines.append("")
    lines += notes
    cold, warm = jit["cold"], jit["warm"]
    med = lambda lst, k: statistics.median(d[k] for d in lst)  # noqa: E731
    lines.append(
        f"numba JIT, fresh process, empty cache dir (x{len(cold)}): import {med(cold, 'import'):.2f} s, "
        f"first simulate(max_events=10) = compile {med(cold, 'first_call'):.2f} s "
        f"({_list(cold, 'first_call')}), second call {med(cold, 'second_call') * 1e6:.0f} us"
        + ("" if all(d["ok"] for d in cold) else "  [WARNING: cache not redirected/written, not a cold compile]")
    )
    lines.append(
        f"numba JIT, fresh process, warm cache dir (x{len(warm)}): import {med(warm, 'import'):.2f} s, "
        f"first call {med(warm, 'first_call'):.2f} s ({_list(warm, 'first_call')}), "
        f"import + first call {statistics.median(d['import'] + d['first_call'] for d in warm):.2f} s"
        + ("" if all(d["ok"] for d in warm) else "  [WARNING: the warm run wrote cache files: it recompiled]")
    )
    lines.append(f"total benchmark time {time.perf_counter() - started:.0f} s")
    text = "\n".join(lines)
    print(text)

    if args.json:
        Path(args.json).parent.mkdir(parents=True, exist_ok=True)
        payload = {
            "args": vars(args), "pinning": pin, "loadavg_start": load0, "loadavg_end": load1,
            "versions": {"python": platform.python_version(), "numpy": np.__version__, "scipy": scipy.__version__,
                         "numba": numba.__version__, "bounce": bounce.__version__},
            "rows": rows, "scipy_details": details, "jit": jit, "notes": notes, "text": text,
        }
        Path(args.json).write_text(json.dumps(payload, indent=2, default=str))


if __name__ == "__main__":
    main()

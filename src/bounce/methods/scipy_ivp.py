"""Method "scipy": ``scipy.integrate.solve_ivp`` with a terminal floor event, restarted at each impact.

The obvious way to simulate the ball (paper, section 2): integrate the
first-order system in s = (x, x', y, y') of the spring law's physics (:mod:`bounce.springs.base`),

    x'' = -gamma + S,   y'' = -gamma - S,   S = f(xi) + mu g(xi) (y' - x'),   xi = (y - x - 1)/2

(:func:`dynamics`; the linear law, f(xi) = xi and g = 1, gives eq. ``dimensionless-eq-motion``,
x'' = -mu x' - x/2 - gamma - 1/2 + y/2 + mu y'), stop at the terminal event "x crosses 0 downwards",
apply the impact rule x' -> -x' (y, y' unchanged) and call ``solve_ivp`` again from the post-impact
state.  Radau/BDF/LSODA get the Jacobian from the law's f' and g (the term of g' left out: exact for the
linear law, whose Jacobian is constant; otherwise an approximation, which only slows the implicit
solvers' Newton iterations, not their accuracy).

The one solve_ivp driver of the project (the speed benchmark ``benchmarks/bench_simulator.py`` uses it
too).  Lessons learnt:

* the restart trap: with the event g = x, a first step after the restart that
  overshoots the whole (short) flight is flagged and brentq on [t_r, t_1] with
  g(t_r) = 0 returns t_r itself -- a zero-length flight, x' flipped back, and
  the run stalls.  After an impact the event is therefore the divided
  difference g = x / (t - t_r) (= x'(t_r) > 0 at the restart), which has the
  zeros of x for t > t_r and a genuine sign change in every flagged step.
  ``restart: plain`` keeps the naive g = x (to show the trap).
* the event function is evaluated only at step ends, so a step can jump over a
  shallow dip of x below the floor: an impact the exact solution has.

Failure detection (inside the method, from the integrator's own output only):

``missed_impact``  on every step [t_i, t_i+1] of a flight (the last one ending
    at the located event) x is interpolated by the quintic Hermite polynomial
    through x, x', x'' at both ends (the solver's own values; x'' from the right-hand side),
    sampled at 16 interior points and refined by a parabola through the
    smallest sample: an interior local minimum below -``dip_tol`` (default
    ``atol``, the solver's own accuracy claim for x) is a crossing of the floor
    the event location stepped over.  This costs no right-hand-side calls, so
    CPU times are those of a plain solve_ivp loop plus a few vector operations.
``fell_through``   a step end with x < -``floor_tol`` (default 1e-9) that no
    event stopped (e.g. a restart with x' <= 0).
``stall``          more than 50 consecutive flights shorter than 1e-12 relative to
    max(1, t) (the restart re-triggering: at t ~ 1e3 such flights are a few ulps
    of t, i.e. zero; an absolute threshold let 5-ulp flights through), or
    solve_ivp reporting failure (step size underflow: the integrator is stuck).
``energy_gain``    E - E_m at an impact (x = 0) exceeds its running minimum over
    the previous impacts by more than ``energy_tol`` (relative, default 1e-3):
    the exact flow strictly dissipates (dE/dt = -2 mu xi'^2) and impacts conserve E.
``collapse``       the last 100 flights strictly decreasing with tau_last/tau_first
    < 1e-3 (geometric accumulation; the true asymptotics tau_n ~ 3/(mu n) shrink
    by at most 2 over 100 flights once n > 100).
``budget``         process time over ``cpu_budget`` seconds (checked between calls).

Measured on the drop gamma = mu = 0.01 from psi(0) = 6 (see tests/methods/test_integrators.py and
:mod:`bounce.studies.compare`): ~0.5 ms of CPU per impact whatever the tolerance (solve_ivp's per-call
overhead dominates: ~3 steps and ~45 right-hand-side calls per impact at DOP853 rtol 1e-10; the checks
above add ~10%); LSODA's interpolant does not pass through the restart state at loose tolerances, giving
zero-length flights (stall) or geometrically shrinking ones (collapse) even with the divided-difference
event; DOP853 at rtol >= 1e-6 can take a 30-unit step over the exactly parabolic first flight (the spring
mode is dormant, so the error estimate sees only rounding) and misplace the first impact by ~1e-4
relative.

E - E_m is computed as xi'^2/2 + psi'^2/2 + D(eta) + gamma x with eta = xi - xi_eq and D the law's
divergence (:meth:`bounce.springs.base.SpringLaw.divergence`; eta^2/2 for the linear law, an exact rewrite of
eq. ``tot-mech-energy`` minus eq. ``Emin``, which avoids the cancellation of E - E_m when both are ~ -gamma^2/2).
"""

from __future__ import annotations

import math
import time

import numpy as np
from scipy.integrate import solve_ivp

from .base import ANY_LAW, MethodResult, MethodSpec

SOLVERS = ("RK23", "RK45", "DOP853", "LSODA", "Radau", "BDF")
IMPLICIT = ("LSODA", "Radau", "BDF")
DEFAULTS = {
    "solver": "DOP853", "rtol": 1e-10, "atol": 1e-12, "cpu_budget": math.inf, "restart": "divided",
    "dip_tol": None, "floor_tol": 1e-9, "energy_tol": 1e-3, "check": True, "span": 1.0e4,
    "max_step": math.inf,
}
STALL_DT = 1e-12  # relative to max(1, t): a flight shorter than that is a stalled restart
STALL_COUNT = 50
COLLAPSE_COUNT = 100
COLLAPSE_RATIO = 1e-3
_S = np.linspace(0.0, 1.0, 18)  # sample points of a step for the dip test


def _hermite_basis(s):
    """Quintic Hermite basis on [0, 1]: weights of x, h x', h^2 x'' at 0 and at 1."""
    s2, s3 = s * s, s * s * s
    s4, s5 = s3 * s, s3 * s2
    return np.array([
        1 - 10 * s3 + 15 * s4 - 6 * s5, s - 6 * s3 + 8 * s4 - 3 * s5, 0.5 * s2 - 1.5 * s3 + 1.5 * s4 - 0.5 * s5,
        10 * s3 - 15 * s4 + 6 * s5, -4 * s3 + 7 * s4 - 3 * s5, 0.5 * s3 - s4 + 0.5 * s5,
    ])


_H = _hermite_basis(_S)[:, None, :]  # (6, 1, samples)


def dynamics(params):
    """(rhs, jac, x_acceleration) of s' = F(s), s = (x, x', y, y'), from the law's physics (module docstring):
    ``rhs(t, s)`` and ``jac(t, s)`` as solve_ivp calls them, ``x_acceleration(states)`` x'' at each column of a
    (4, n) array of states (the missed-impact check's Hermite data).  The law's functions run as Python (their ``py_func``, the same
    arithmetic as the compiled ones), bound once here: two calls per right-hand side, cheaper than the dispatch
    of a compiled right-hand side taking them as arguments (measured: ~4x)."""
    law = params.spring
    force, stiffness, damping = (fn.py_func for fn in law.physics[:3])
    c = law.coefficients
    gamma, mu = params.gamma, params.mu

    def rhs(t, s):
        x, u, y, v = s
        xi = 0.5 * ((y - x) - 1.0)
        spring = force(xi, c) + mu * damping(xi, c) * (v - u)
        return np.array([u, -gamma + spring, v, -gamma - spring])

    def jac(t, s):
        x, u, y, v = s
        xi = 0.5 * ((y - x) - 1.0)
        k, m = 0.5 * stiffness(xi, c), mu * damping(xi, c)
        return np.array([[0.0, 1.0, 0.0, 0.0], [-k, -m, k, m], [0.0, 0.0, 0.0, 1.0], [k, m, -k, -m]])

    def x_acceleration(states):
        xi = (0.5 * ((states[2] - states[0]) - 1.0)).tolist()
        rel = (states[3] - states[1]).tolist()
        return np.array([-gamma + force(z, c) + mu * damping(z, c) * w for z, w in zip(xi, rel)])

    return rhs, jac, x_acceleration


def energy_excess(s, params) -> float:
    """E - E_m of state s = (x, x', y, y') (module docstring)."""
    x, u, y, v = s
    a = 0.5 * (v - u)  # xi'
    p = 0.5 * (v + u)  # psi'
    eta = 0.5 * ((y - x) - 1.0) - params.xi_eq
    return 0.5 * (a * a + p * p) + params.spring.divergence(eta, params.gamma) + params.gamma * x


class _OverBudget(Exception):
    pass


def floor_event(t_restart: float | None, deadline: float = math.inf):
    """Terminal event "x crosses 0 downwards"; divided difference after a restart at the floor.

    The event function is called once per solver step (plus the root search), so it also
    enforces the CPU deadline (process time) inside long solve_ivp calls.
    """
    clock = time.process_time
    if t_restart is None:
        def g(t, s):
            if clock() > deadline:
                raise _OverBudget
            return s[0]
    else:
        def g(t, s):
            if clock() > deadline:
                raise _OverBudget
            dt = t - t_restart
            return s[0] / dt if dt > 0.0 else s[1]
    g.terminal = True
    g.direction = -1
    return g


def _hermite_min(t, y, x_acceleration):
    """Smallest interior local minimum of x over the steps t[i]..t[i+1] (quintic Hermite in x, x', x'').

    Returns (x_min, t_min), or (inf, nan) if no step has a sampled minimum strictly inside.
    """
    if t.size < 2:
        return math.inf, math.nan
    h = np.diff(t)
    acc = x_acceleration(y)
    x0, x1 = y[0, :-1, None], y[0, 1:, None]
    d0, d1 = (y[1, :-1] * h)[:, None], (y[1, 1:] * h)[:, None]
    c0, c1 = (acc[:-1] * h * h)[:, None], (acc[1:] * h * h)[:, None]
    X = x0 * _H[0] + d0 * _H[1] + c0 * _H[2] + x1 * _H[3] + d1 * _H[4] + c1 * _H[5]
    j = np.argmin(X, axis=1)
    rows = np.nonzero((j > 0) & (j < X.shape[1] - 1))[0]
    if rows.size == 0:
        return math.inf, math.nan
    j = j[rows]
    xl, xm, xr = X[rows, j - 1], X[rows, j], X[rows, j + 1]
    den = xl - 2.0 * xm + xr
    off = np.where(den > 0.0, 0.5 * (xl - xr) / np.where(den > 0.0, den, 1.0), 0.0)
    xmin = xm - 0.25 * (xl - xr) * off  # vertex of the parabola through the three samples
    k = int(np.argmin(xmin))
    i = rows[k]
    return float(xmin[k]), float(t[i] + h[i] * (_S[j[k]] + off[k] * (_S[1] - _S[0])))


def _setting(setting: dict | None) -> dict:
    cfg = dict(DEFAULTS)
    cfg.update(setting or {})
    if cfg["solver"] not in SOLVERS:
        raise ValueError(f"solver must be one of {SOLVERS}, got {cfg['solver']!r}")
    if cfg["restart"] not in ("divided", "plain"):
        raise ValueError(f"restart must be 'divided' or 'plain', got {cfg['restart']!r}")
    if cfg["dip_tol"] is None:
        cfg["dip_tol"] = float(cfg["atol"])
    return cfg


def run(params, initial, setting=None, *, max_events=1000, t_max=math.inf, sample_times=None) -> MethodResult:
    """solve_ivp restart loop; see the module docstring for the setting keys and failure rules."""
    cfg = _setting(setting)
    st = initial.to_state(params) if hasattr(initial, "to_state") else initial
    rhs, jac, x_acceleration = dynamics(params)
    kw = {"jac": jac} if cfg["solver"] in IMPLICIT else {}
    samples = None if sample_times is None else np.asarray(sample_times, dtype=float)
    y_out = None if samples is None else np.full(samples.shape, np.nan)
    t_imp, v_imp, e_imp = [], [], []
    s0 = np.array([st.x, st.xdot, st.y, st.ydot], dtype=float)
    t0 = 0.0
    flight_start = 0.0
    on_floor = s0[0] == 0.0  # the start is a restart from the floor (e.g. a post-impact state)
    e_min = energy_excess(s0, params)
    failure, failure_index = "", -1
    n_short = 0
    nfev = nsteps = ncalls = 0
    solver_message = ""
    budget = float(cfg["cpu_budget"])
    start = time.process_time()
    while len(t_imp) < max_events:
        if time.process_time() - start > budget:
            failure, failure_index = "budget", len(t_imp)
            break
        t_bound = min(t0 + float(cfg["span"]), float(t_max))
        if not t_bound > t0:
            break
        restart = on_floor and t0 == flight_start and cfg["restart"] == "divided"
        event = floor_event(t0 if restart else None, start + budget)
        dense = samples is not None and bool(np.any((samples >= t0) & (samples <= t_bound)))
        try:
            sol = solve_ivp(rhs, (t0, t_bound), s0, method=cfg["solver"], rtol=cfg["rtol"], atol=cfg["atol"],
                            events=event, dense_output=dense, max_step=cfg["max_step"], **kw)
        except _OverBudget:
            failure, failure_index = "budget", len(t_imp)
            break
        ncalls += 1
        nfev += sol.nfev
        nsteps += max(len(sol.t) - 1, 0)
        if sol.status == -1:
            failure, failure_index = "stall", len(t_imp)
            solver_message = sol.message
            break
        hit = sol.t_events[0].size > 0
        t_end = float(sol.t_events[0][0]) if hit else float(sol.t[-1])
        if dense:
            m = (samples >= t0) & ((samples < t_end) if hit else (samples <= t_end))
            if m.any():
                y_out[m] = sol.sol(samples[m])[2]
        if cfg["check"]:
            xmin, _ = _hermite_min(sol.t, sol.y, x_acceleration)
            if xmin < -cfg["dip_tol"]:
                failure, failure_index = "missed_impact", len(t_imp)
                break
            if sol.y.shape[1] > 1 and float(np.min(sol.y[0, 1:])) < -cfg["floor_tol"]:
                failure, failure_index = "fell_through", len(t_imp)
                break
        if not hit:  # flight longer than the span, or t_max reached
            t0, s0 = t_end, sol.y[:, -1].copy()
            if t_end >= t_max:
                break
            continue
        se = sol.y_events[0][0]
        s0 = np.array([0.0, abs(se[1]), se[2], se[3]])  # impact: x = 0, x' -> -x' (x' <= 0 at a downward crossing)
        tau = t_end - flight_start
        t_imp.append(t_end)
        v_imp.append(s0[1])
        e = energy_excess(s0, params)
        e_imp.append(e)
        k = len(t_imp) - 1
        n_short = n_short + 1 if tau < STALL_DT * max(1.0, t_end) else 0
        if n_short > STALL_COUNT:
            failure, failure_index = "stall", k
            break
        if e - e_min > cfg["energy_tol"] * e_min:
            failure, failure_index = "energy_gain", k
            break
        e_min = min(e_min, e)
        if len(t_imp) > COLLAPSE_COUNT + 1:
            taus = np.diff(t_imp[-COLLAPSE_COUNT - 2:])
            if np.all(np.diff(taus) < 0.0) and taus[-1] < COLLAPSE_RATIO * taus[0]:
                failure, failure_index = "collapse", k
                break
        t0 = flight_start = t_end
        on_floor = True
    cpu = time.process_time() - start
    return MethodResult(
        method="scipy", setting=dict(setting or {}), t=np.array(t_imp), xdot=np.array(v_imp), cpu_time=cpu,
        failure=failure, failure_index=failure_index, t_end=t0,
        y=y_out, extra={"nfev": nfev, "nsteps": nsteps, "ncalls": ncalls, "solver_message": solver_message, "energy_excess": np.array(e_imp)},
    )


METHOD = MethodSpec(
    name="scipy",
    run=run,
    settings_doc=(
        "solver: RK23|RK45|DOP853|LSODA|Radau|BDF (default DOP853); rtol (1e-10), atol (1e-12); "
        "cpu_budget: process seconds (inf); restart: divided|plain (divided: event x/(t - t_restart) after an impact); "
        "check: dip/fell-through tests on (True); dip_tol (atol), floor_tol (1e-9), energy_tol (1e-3, relative rise of "
        "E - E_m above its running minimum); span: longest single solve_ivp call (1e4); max_step (inf)"
    ),
    needs=ANY_LAW,
)

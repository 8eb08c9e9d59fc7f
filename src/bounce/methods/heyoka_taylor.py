"""Method "heyoka": heyoka's adaptive Taylor integrator with event detection, the strongest
general-purpose peer (issue 9), for the linear and the power-law spring.

The flight of eq. ``eq-motion-nonlin-psi-xi`` (linear: eq. ``eq-motion-psi-xi``) in the core's
deviation variables s = (x, u = x', v = xi', eta = xi - xi_eq) (``a`` in the core; here a is the
exponent):

    x' = u,  u' = -gamma - xi'',  v' = xi'',  eta' = v,
    xi'' = -rho xi |xi|^a - 2 mu v |xi|^b,   xi = xi_eq + eta,   xi_eq = -(gamma/rho)^(1/(a+1))

(eq. ``nonlin-equilibrium-xi``), with |xi|^p written (xi^2)^(p/2) and dropped when p = 0 (the
linear law is then the linear system, no powers).  Set up as the issue asks for a fair peer:

* compiled once per (a, b, tol, cooldown, high_accuracy) and reused (``functools.cache``);
  gamma, mu, rho, xi_eq are runtime parameters, the state and time are reset per run;
* a terminal event on x = 0 with direction negative (no callback: it stops ``propagate_until``);
  at each stop the impact rule (eq. ``collision-rule``: psi' and xi' exchanged) is applied in
  place: x -> 0, u -> -u, v -> u + v, eta unchanged; the event's cooldown is heyoka's own unless
  the ``cooldown`` setting gives one;
* tolerance 2^-52 (machine precision) unless ``tol`` says otherwise.

Failure detection (from the integrator's own output):

``missed_impact``  (a) the flight outlives a bound it cannot outlive: x = psi - xi <= psi(t0)
    + psi'(t0) (t - t0) - gamma (t - t0)^2/2 + X_m, with X_m >= |xi| from the spring energy
    xi'^2/2 + rho |xi|^(a+2)/(a+2), which does not increase in flight (eq. ``nonlin-energy``),
    so x < 0 after that time: a propagation reaching it without an event has stepped over an
    impact (in practice: one that fell inside the event's cooldown); (b) a non-terminal event on
    x = 0 with direction positive fires strictly inside a flight: x came back up through the
    floor, so the dip below it was an impact the event detection skipped.
``stall``          the integrator's state became non-finite (``err_nf_state``: the Taylor
    coefficients of (xi^2)^(p/2) divide by xi^2, so a flight with the spring exactly at rest
    length, e.g. the paper's drop with xi(0) = xi'(0) = 0, fails at once for a, b > 0), a
    propagation ended by heyoka's step limit, or more than 50 consecutive flights shorter than
    1e-12 (zero-length flights: the restart re-triggering).
``budget``         process time over ``cpu_budget`` seconds (checked between flights).

``extra`` carries the post-impact ``xidot`` and ``eta`` (for one-step errors against the
references), ``steps`` per flight, the cooldown heyoka used, ``start`` (the state it integrated
from: x, xdot, xidot, eta, xi_eq, with xi = xi_eq + eta exactly) and ``reason`` (one line) on failure.
heyoka (~2.4 s to import) loads at its first use (:func:`bounce._registry.lazy_import`), so listing the methods
does not load it.

Measured (``python benchmarks/bench_power.py``, heyoka 7.13.2, Hertz a = b = 1/2, gamma = mu = 0.01, one
core of a shared machine, load 1.8-3.2, medians of 5; numbers in results/timing/bench_power.json), heyoka
in its fastest use (:func:`impacts`: one propagation, the impact rule in the event callback): 2.5e5
impacts/s in the asymptotic regime (bounce 2.6e6, 10.5x), 3e3-3e5 in the drop's first 1e4 impacts, whose
long flights cross the rest length xi = 0 (there bounce is 0.9-1.8x heyoka: both take Taylor steps of
similar cost, bounce about half as many; over the first 2e4 impacts 1.8x); through :func:`run`, which
returns to Python after every flight for the failure checks below, heyoka does 5.5e4 impacts/s (the
checks cost ~13 us per impact, three times heyoka's own work deep);
one-step errors against the mpmath reference ~4e-16 deep, up to 3e-13 on flights that pass xi = 0
(bounce: 1e-14).  The paper's drop (xi(0) = 0) stalls at impact 0 (``err_nf_state``, above).  With its
automatic cooldown heyoka follows bounce's exact trajectory from the states after 1e4 ... 1e7 impacts
without a skip and first skips an impact at x' = 3e-9 after an impact: its cooldown, measured 10 eps/x' =
2.2e-15/x', outlasts the flight, ~x'/gamma, once x' < sqrt(10 eps gamma) = 4.7e-9, i.e. from impact
n ~ 1/(alpha x') ~ 3-5e9 of the drop on (alpha: bounce.theory.nonlin_alpha_limit); a fixed cooldown of
1e-15 or 1e-12 stays clean to x' = 1e-13 (the best setting), 1e-9 fails at x' = 1e-11, and 0 skips the
first impact after the restart at every depth tried (measured: without a cooldown heyoka's event
detection does not restart cleanly on the event surface x = 0, see :func:`_start`).
"""

from __future__ import annotations

import functools
import math
import time

import numpy as np

from .._registry import lazy_import
from ..theory import nonlin_equilibrium_xi
from .base import MethodResult, MethodSpec

hy = lazy_import("heyoka")

DEFAULTS = {"rho": None, "a": None, "b": None, "tol": 2.0**-52, "cooldown": None, "high_accuracy": False,
            "cpu_budget": math.inf}
STALL_DT = 1e-12
STALL_COUNT = 50
EVENT_STOP = -1  # heyoka's outcome for "stopped by terminal event 0" (stopping events report -1 - index)


def spring_law(params, cfg) -> tuple[float, float, float, float]:
    """(rho, a, b, xi_eq): the setting's law when it names one, else ``params.spring``'s (linear: 1, 0, 0),
    whose own xi_eq is then kept (the core's eta is measured from it)."""
    spring = params.spring
    law = {"rho": 1.0, "a": 0.0, "b": 0.0}
    if spring.name != "linear":
        law.update({k: float(v) for k, v in spring.parameters().items() if k in law})
    override = {k: float(cfg[k]) for k in law if cfg[k] is not None}
    law.update(override)
    rho, a, b = law["rho"], law["a"], law["b"]
    if not (rho > 0.0 and math.isfinite(rho)):
        raise ValueError(f"rho must be > 0 (allowed range: (0, inf)), got {rho!r}")
    for name, v in (("a", a), ("b", b)):
        if not (v >= 0.0 and math.isfinite(v)):
            raise ValueError(f"{name} must be >= 0 (allowed range: [0, inf)), got {v!r}")
    xi_eq = nonlin_equilibrium_xi(params.gamma, rho, a) if override else params.xi_eq
    return rho, a, b, xi_eq


@functools.cache
def integrator(a: float, b: float, tol: float, cooldown: float | None, high_accuracy: bool):
    """The compiled heyoka integrator for exponents (a, b) (built once per process and setting).

    Returns ``(ta, upward)``: the integrator and the list its non-terminal event appends the
    times of upward crossings of x = 0 to (cleared by the caller)."""
    x, u, v, eta = hy.make_vars("x", "u", "v", "eta")
    gamma, mu, rho, xi_eq = (hy.par[i] for i in range(4))
    xi = xi_eq + eta

    def abs_pow(p):
        return None if p == 0.0 else (xi * xi) ** (p / 2.0)

    fa, fb = abs_pow(a), abs_pow(b)
    force = rho * xi if fa is None else rho * xi * fa
    damping = 2.0 * mu * v if fb is None else 2.0 * mu * v * fb
    xi2 = -force - damping
    upward = []

    def on_upward(ta, t, d_sgn):
        upward.append(t)

    kw = {} if cooldown is None else {"cooldown": float(cooldown)}
    floor = hy.t_event(x, direction=hy.event_direction.negative, **kw)
    rise = hy.nt_event(x, on_upward, direction=hy.event_direction.positive)
    ta = hy.taylor_adaptive([(x, u), (u, -gamma - xi2), (v, xi2), (eta, v)], [0.0] * 4,
                            t_events=[floor], nt_events=[rise], pars=[0.0] * 4, tol=tol,
                            high_accuracy=high_accuracy)
    return ta, upward  # heyoka deep-copies callbacks, but a function deep-copies to itself: same list


class _ImpactRule:
    """Terminal-event callback of :func:`impacts`: applies the impact rule in place and records the
    impact, so heyoka continues the integration without returning to Python between impacts; it
    stops the propagation (returns False) once ``limit`` impacts are recorded."""

    def __init__(self):
        self.limit = 0
        self.t, self.u, self.v, self.eta = [], [], [], []

    def __call__(self, ta, d_sgn):
        s = ta.state
        u, v = s[1], s[2]
        s[0] = 0.0
        s[1] = -u
        s[2] = u + v
        self.t.append(ta.time)
        self.u.append(-u)
        self.v.append(u + v)
        self.eta.append(s[3])
        return len(self.t) < self.limit


@functools.cache
def _callback_integrator(a: float, b: float, tol: float, cooldown: float | None, high_accuracy: bool):
    """As :func:`integrator`, with the impact rule in the floor event's callback and no upward event."""
    x, u, v, eta = hy.make_vars("x", "u", "v", "eta")
    gamma, mu, rho, xi_eq = (hy.par[i] for i in range(4))
    xi = xi_eq + eta
    fa = None if a == 0.0 else (xi * xi) ** (a / 2.0)
    fb = None if b == 0.0 else (xi * xi) ** (b / 2.0)
    xi2 = -(rho * xi if fa is None else rho * xi * fa) - (2.0 * mu * v if fb is None else 2.0 * mu * v * fb)
    kw = {} if cooldown is None else {"cooldown": float(cooldown)}
    floor = hy.t_event(x, callback=_ImpactRule(), direction=hy.event_direction.negative, **kw)
    ta = hy.taylor_adaptive([(x, u), (u, -gamma - xi2), (v, xi2), (eta, v)], [0.0] * 4,
                            t_events=[floor], pars=[0.0] * 4, tol=tol, high_accuracy=high_accuracy)
    return ta, ta.t_events[0].callback  # heyoka deep-copies the callback: this is the copy it calls


def impacts(params, initial, max_events, t_end, setting=None):
    """heyoka's fastest use for a sequence of impacts, for speed measurements: ``(t, xdot, xidot, eta, cpu)``.

    One ``propagate_until(t_end)`` call; the impact rule runs in the floor event's callback
    (:class:`_ImpactRule`), which stops the propagation after ``max_events`` impacts.  :func:`run`
    returns to Python after every flight for its failure checks (flight bound, upward crossings),
    which cost ~13 us per impact, three times heyoka's own work in the asymptotic regime (measured:
    18 against 4.2-4.9 us per Hertz impact from impact 1e3 on, ``python benchmarks/bench_power.py``).
    Here nothing is checked: a skipped impact shows as fewer than ``max_events`` impacts by
    ``t_end`` (x stays below the floor after it) or as impact times that differ from a reference,
    which the caller compares.  ``cpu`` is the process time of the propagation alone.
    """
    cfg = _setting(setting)
    rho, pa, pb, xi_eq = spring_law(params, cfg)
    dev = initial.deviations(params)
    eta0 = dev.eta if xi_eq == params.xi_eq else (params.xi_eq - xi_eq) + dev.eta
    ta, rule = _callback_integrator(pa, pb, float(cfg["tol"]), cfg["cooldown"], bool(cfg["high_accuracy"]))
    ta.pars[:] = [params.gamma, params.mu, rho, xi_eq]
    ta.time = 0.0
    ta.reset_cooldowns()
    rule.limit = 1  # _start's own event at t = 0 (a restart from the floor) must not count
    _start(ta, dev.x, dev.xdot, dev.xidot, eta0)
    for column in (rule.t, rule.u, rule.v, rule.eta):
        column.clear()
    rule.limit = max_events
    start = time.process_time()
    ta.propagate_until(t_end)
    cpu = time.process_time() - start
    return np.array(rule.t), np.array(rule.u), np.array(rule.v), np.array(rule.eta), cpu


def _setting(setting):
    cfg = dict(DEFAULTS)
    unknown = set(setting or {}) - set(DEFAULTS)
    if unknown:
        raise ValueError(f"unknown heyoka settings {sorted(unknown)}; allowed: {sorted(DEFAULTS)}")
    cfg.update(setting or {})
    if not (cfg["tol"] > 0.0):
        raise ValueError(f"tol must be > 0, got {cfg['tol']!r}")
    if cfg["cooldown"] is not None and not cfg["cooldown"] >= 0.0:
        raise ValueError(f"cooldown must be >= 0 or None (heyoka's default), got {cfg['cooldown']!r}")
    return cfg


def flight_bound(x, u, v, xi, gamma, rho, pa) -> float:
    """A time after which x < 0 whatever the spring does (module docstring, missed_impact (a))."""
    es = 0.5 * v * v + rho * abs(xi) ** (pa + 2.0) / (pa + 2.0)
    xm = ((pa + 2.0) * es / rho) ** (1.0 / (pa + 2.0))
    psi, p = x + xi, u + v
    c = max(psi + xm, 0.0) + 8.0 * 2.0**-52 * (abs(psi) + xm)  # psi + X_m >= 0, rounded up
    return 1.01 * (p + math.sqrt(p * p + 2.0 * gamma * c)) / gamma + 1e-9


def _start(ta, x, u, v, eta):
    """Put the initial state into ``ta``.  A start on the floor (x = 0, x' > 0) is a restart after an
    impact: heyoka's event detection misses the next root when the event function starts at exactly 0
    without an active cooldown, so the pre-impact state (x' = -u, xi' = v + u, the rule inverted) is
    propagated instead; heyoka's own event then fires at t = 0, arms its cooldown, and the rule
    gives back the initial state, as after every impact."""
    if x == 0.0 and u > 0.0:
        ta.state[:] = [0.0, -u, v + u, eta]
        outcome = ta.propagate_until(1e-300)[0]
        if int(outcome) == EVENT_STOP and ta.time == 0.0:
            ta.state[:] = [0.0, u, v, eta]
            return
        ta.time = 0.0
        ta.reset_cooldowns()
    ta.state[:] = [x, u, v, eta]


def _active_cooldown(ta):
    """The cooldown of the floor event after the last impact (heyoka's automatic one unless set), or None."""
    c = ta.te_cooldowns[0]
    return None if c is None else float(c[1])


def run(params, initial, setting=None, *, max_events=1000, t_max=math.inf, sample_times=None) -> MethodResult:
    """heyoka restart loop; see the module docstring for the settings and failure rules."""
    cfg = _setting(setting)
    rho, pa, pb, xi_eq = spring_law(params, cfg)
    gamma, mu = params.gamma, params.mu
    dev = initial.deviations(params)
    # the core's eta is xi - params.xi_eq; re-reference it if the setting chose another law
    eta0 = dev.eta if xi_eq == params.xi_eq else (params.xi_eq - xi_eq) + dev.eta
    ta, upward = integrator(pa, pb, float(cfg["tol"]), cfg["cooldown"], bool(cfg["high_accuracy"]))
    ta.pars[:] = [gamma, mu, rho, xi_eq]
    ta.time = 0.0
    ta.reset_cooldowns()
    _start(ta, dev.x, dev.xdot, dev.xidot, eta0)
    upward.clear()
    samples = None if sample_times is None else np.asarray(sample_times, dtype=float)
    y_out = None if samples is None else np.full(samples.shape, np.nan)
    t_imp, u_after, v_after, e_imp, steps = [], [], [], [], []
    failure, failure_index, reason = "", -1, ""
    n_short = 0
    t_prev = 0.0
    budget = float(cfg["cpu_budget"])
    start = time.process_time()
    while len(t_imp) < max_events:
        if time.process_time() - start > budget:
            failure, failure_index, reason = "budget", len(t_imp), "CPU budget exhausted"
            break
        x, u, v, eta = ta.state
        bound = t_prev + flight_bound(x, u, v, xi_eq + eta, gamma, rho, pa)
        t_stop = min(bound, t_max)
        dense = samples is not None and bool(np.any((samples >= t_prev) & (samples <= t_stop)))
        outcome, _, _, nsteps, c_out, _ = ta.propagate_until(t_stop, c_output=dense)
        steps.append(nsteps)
        code = int(outcome)
        if dense and c_out is not None:
            m = (samples >= t_prev) & (samples <= ta.time)
            if m.any():
                s = c_out(samples[m])
                y_out[m] = 1.0 + 2.0 * xi_eq + s[:, 0] + 2.0 * s[:, 3]
        inside = [t for t in upward if t > t_prev]
        upward.clear()
        if inside:
            failure, failure_index = "missed_impact", len(t_imp)
            reason = f"x rose through the floor at t = {inside[0]!r} inside a flight: a dip below it was skipped"
            break
        if code == EVENT_STOP:
            x, u, v, eta = ta.state
            ta.state[:] = [0.0, -u, u + v, eta]  # impact: psi' <-> xi' (x' < 0 at a downward crossing)
            tau = ta.time - t_prev
            t_prev = ta.time
            t_imp.append(t_prev)
            u_after.append(-u)
            v_after.append(u + v)
            e_imp.append(eta)
            n_short = n_short + 1 if tau < STALL_DT else 0
            if n_short > STALL_COUNT:
                failure, failure_index, reason = "stall", len(t_imp) - 1, "zero-length flights: the event re-triggers"
                break
            continue
        if outcome == hy.taylor_outcome.time_limit:
            if t_stop == t_max and t_max < bound:
                break  # reached t_max
            failure, failure_index = "missed_impact", len(t_imp)
            reason = f"no event before the flight bound t = {bound!r} (x = {ta.state[0]!r}): an impact was skipped"
            break
        failure, failure_index = "stall", len(t_imp)
        reason = f"heyoka stopped with {outcome!r} at t = {ta.time!r} (state {list(ta.state)!r})"
        break
    cpu = time.process_time() - start
    return MethodResult(
        method="heyoka", setting=dict(setting or {}), t=np.array(t_imp), xdot=np.array(u_after), cpu_time=cpu,
        failure=failure, failure_index=failure_index, t_end=t_prev, y=y_out,
        extra={"xidot": np.array(v_after), "eta": np.array(e_imp), "steps": np.array(steps), "reason": reason,
               "law": {"rho": rho, "a": pa, "b": pb}, "cooldown": _active_cooldown(ta),
               "start": {"x": dev.x, "xdot": dev.xdot, "xidot": dev.xidot, "eta": eta0, "xi_eq": xi_eq}},
    )


METHOD = MethodSpec(
    name="heyoka",
    run=run,
    settings_doc=(
        "rho, a, b: power-law spring xi'' = -rho xi|xi|^a - 2 mu xi'|xi|^b (default: params.spring; linear 1, 0, 0); "
        "tol (2^-52); cooldown: terminal-event cooldown (None: heyoka's automatic one); high_accuracy (False); "
        "cpu_budget: process seconds (inf)"
    ),
    laws=("linear", "power"),
)

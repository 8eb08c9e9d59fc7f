"""Method "heyoka": heyoka's adaptive Taylor integrator with event detection, the strongest
general-purpose peer (issue 9), for every spring law with a symbolic form (the linear law, the power law).

The flight of eq. ``eq-motion-nonlin-psi-xi`` (linear: eq. ``eq-motion-psi-xi``) in the core's
deviation variables s = (x, u = x', v = xi', eta = xi - xi_eq):

    x' = u,  u' = -gamma - xi'',  v' = xi'',  eta' = v,
    xi'' = -f(xi) - 2 mu v g(xi),   xi = xi_eq + eta,

with f and g the law's symbolic form (:meth:`bounce.springs.base.SpringLaw.symbolic`; the power law
writes |xi|^p as (xi^2)^(p/2) and drops it when p = 0, so the linear law is the linear system, no
powers) and xi_eq its static equilibrium (eq. ``nonlin-equilibrium-xi``).  Set up as the issue asks for
a fair peer:

* compiled once per (law, tol, cooldown, high_accuracy) and reused (``functools.cache``);
  gamma, mu, xi_eq are runtime parameters, the state and time are reset per run;
* a terminal event on x = 0 with direction negative whose callback applies the impact rule
  (eq. ``collision-rule``: psi' and xi' exchanged) in place, x -> 0, u -> -u, v -> u + v, eta
  unchanged, and returns True, so heyoka goes on to the next flight without returning to Python;
  the event's cooldown is heyoka's own unless the ``cooldown`` setting gives one;
* tolerance 2^-52 (machine precision) unless ``tol`` says otherwise.

Failure detection (from the integrator's own output):

``missed_impact``  (a) the flight outlives a bound it cannot outlive: x = psi - xi <= psi(t0)
    + psi'(t0) (t - t0) - gamma (t - t0)^2/2 + X_m, with X_m >= |xi| from the spring energy
    xi'^2/2 + V(xi), which does not increase in flight (eq. ``nonlin-energy``; X_m: the law's
    :meth:`bounce.springs.base.SpringLaw.amplitude`),
    so x < 0 after that time: checked at the end of every propagation (each runs CHUNK_FLIGHTS = 64
#: step_cost restarts from its state every RESTART_STEPS steps (its docstring)
RESTART_STEPS = 1000
    flight bounds ahead), a flight still under way past it has stepped over an impact (in
    practice: one that fell inside the event's cooldown); (b) x has a minimum below the floor inside a
    flight: a non-terminal event on x' = u = 0 with direction positive (an interior minimum of x) whose
    callback finds x < 0 there (x at that time from heyoka's dense output): x went down through the floor
    and turned, so the downward crossing before it was an impact the event detection skipped (noted at the
    flight's terminal event or at the end of the propagation, there before (a)).  At least as
    strong as the event on x = 0 upwards it replaces (which fired at the restart after every impact, x = 0
    with x' > 0: one Python callback per impact): a dip that comes back up through the floor has its minimum
    below the floor first, in the same flight (the same impact index is reported, earlier); a dip that turns
    below the floor and falls again is caught here, there only by (a); a dip that never turns (x falls on)
    is left to (a) by both.  Weaker only where heyoka's root finder would miss the root of x' at the
    minimum (there the old one would miss the root of x at the crossing alike) or where the dense output
    rounds a dip ~eps |x| deep to x >= 0 (and a graze of the floor within rounding may be flagged).  It
    never fires at a restart (x' > 0) nor in the asymptotic regime (x' falls monotonically there:
    x'' = -gamma - xi'' with |xi''| << gamma), so deep it costs no Python callback, only heyoka's root search.
``stall``          the integrator's state became non-finite (``err_nf_state``: the Taylor
    coefficients of (xi^2)^(p/2) divide by xi^2, so a flight with the spring exactly at rest
    length, e.g. the paper's drop with xi(0) = xi'(0) = 0, fails at once for a, b > 0), a
    propagation ended by heyoka's step limit, or more than 50 consecutive flights shorter than
    1e-12 (zero-length flights: the restart re-triggering).
``budget``         process time over ``cpu_budget`` seconds (checked at every impact when finite).

``extra`` carries the post-impact ``xidot`` and ``eta`` (for one-step errors against the
references), ``steps`` (heyoka's steps in all), the cooldown heyoka used, ``start`` (the state it integrated
from: x, xdot, xidot, eta, xi_eq, with xi = xi_eq + eta exactly) and ``reason`` (one line) on failure.
heyoka (~2.4 s to import) loads at its first use (:func:`bounce._registry.lazy_import`), so listing the methods
does not load it.

Measured (``python benchmarks/bench_power.py --law hertz --long 0``, heyoka 7.13.2, Hertz a = b = 1/2,
gamma = mu = 0.01, one core of a shared machine, load 1.3-1.6, medians of 5, commit aa060cb; numbers in
results/timing/bench_power.json), heyoka in its fastest use (:func:`impacts`: one propagation, the impact
rule in the event callback): 2.1e5 impacts/s in the asymptotic regime (bounce 2.9e6, 13.9x), 3e3-2.6e5 in
the drop's first 1e4 impacts, whose long flights cross the rest length xi = 0 (there bounce is 1.2-2.6x
heyoka: both take Taylor steps of similar cost, bounce about half as many; over the first 2e4 impacts
3.4x); through :func:`run`, with the failure checks above, 1.25x impacts()' CPU per impact deep and over
the drop's first 2e4 impacts (5.9 against 4.7 us deep, 7.3 against 5.9 on the drop: interleaved medians of
11, load 1.9; the benchmark: 1.7e5 against 2.1e5 impacts/s deep); with the event on x = 0 upwards that (b)
replaced, a Python callback at every restart, 1.5x, and 18 us per impact deep when run returned to Python
after every flight.
What heyoka's CPU per impact is made of (item 5 of bench_power: ``python benchmarks/bench_power.py --cost-only
--law hertz linear --repeats 7``, commit 84c42b1, one core pinned, the other busy: load 3.1; medians of 7 interleaved
rounds of 2e4 impacts; numbers in results/timing/bench_power_cost.json; three more runs at load 3.4-5.2 within
~10 %): heyoka takes 1.000 Taylor steps per impact deep and 2.79 over the drop's first 2e4 impacts (linear law:
1.000 and 1.04; :func:`impacts` counts them); a step of this ODE costs 0.44 us (linear 0.24) alone
(:func:`step_cost`; 0.61 us, linear 0.42, with the floor's event checked every step and no root found), and
heyoka's event handling in C++ costs 1.25 us per impact deep, 1.4 on the drop (linear 1.3 and 1.2;
:func:`event_cost`: the root search every step, the root's isolation and the step's truncation at the impact,
the cooldown).  Of the 3.4 us per impact a Python user pays deep (Hertz), 13 % is Taylor steps, 37 % event
handling and 50 % the Python callback with its calls in and out (1.7 us); on the drop 29 / 34 / 37 % of 4.2 us;
linear deep 8 / 42 / 50 % of 3.1 us.  bounce (0.35 us per impact deep, 1.7 on the drop; linear 0.09 and 0.18) is
faster than heyoka by 9.6x as a Python user gets it deep, 4.8x against steps + event handling (what a C++ user with a
C++ event callback would pay, within the ~0.1 us of :func:`event_cost`'s matching) and 1.25x against the Taylor steps
alone (a strict lower bound); on the drop's first 2e4 impacts 2.4x, 1.5x and 0.71x (heyoka's steps alone are cheaper
than bounce's flights there); linear law 34x, 17x, 2.6x deep and 16x, 8.3x, 1.4x on the drop.  (heyoka's Python use
took 3.4 us per impact deep in this run, 4.8 us (2.1e5/s) in the earlier one quoted first: the 13.9x there is 9.6x
here, with bounce at 0.34-0.35 us in both.)
One-step errors against the mpmath reference ~4e-16 deep, up to 3e-13 on flights that pass xi = 0
(bounce: 1e-14).  The paper's drop (xi(0) = 0) stalls at impact 0 (``err_nf_state``, above).  With its
automatic cooldown heyoka follows bounce's exact trajectory from the states after 1e4 ... 1e7 impacts
without a skip and first skips an impact at x' = 3e-9 after an impact: its cooldown, measured 10 eps/x' =
2.2e-15/x', outlasts the flight, ~x'/gamma, once x' < sqrt(10 eps gamma) = 4.7e-9, i.e. from impact
n ~ 1/(alpha x') ~ 3-5e9 of the drop on (alpha: bounce.analysis.theory.nonlin_alpha_limit); a fixed cooldown of
1e-15 or 1e-12 stays clean to x' = 1e-13 (the best setting), 1e-9 fails at x' = 1e-11, and 0 skips the
first impact after the restart at every depth tried (measured: without a cooldown heyoka's event
detection does not restart cleanly on the event surface x = 0, see :func:`_start`).
"""

from __future__ import annotations

import bisect
import functools
import math
import time

import numpy as np

from .._registry import lazy_import
from .base import SYMBOLIC_LAW, MethodResult, MethodSpec

hy = lazy_import("heyoka")

DEFAULTS = {"tol": 2.0**-52, "cooldown": None, "high_accuracy": False, "cpu_budget": math.inf}
STALL_DT = 1e-12
STALL_COUNT = 50
EVENT_STOP = -1  # heyoka's outcome for "stopped by terminal event 0" (stopping events report -1 - index)
#: a propagation of run() ends 64 flight bounds ahead: the flight bound is checked there, and no heyoka step
#: is longer (its event detection fails on steps ~1e8 long, :func:`impacts`)
CHUNK_FLIGHTS = 64
#: step_cost restarts from its state every RESTART_STEPS steps (its docstring)
RESTART_STEPS = 1000


@functools.cache
def integrator(law, tol: float, cooldown: float | None, high_accuracy: bool, checked: bool = True):
    """The compiled heyoka integrator for the spring ``law`` (built once per process, law and setting).

    The floor x = 0 downwards is a terminal event whose callback applies the impact rule, so heyoka
    goes from flight to flight without returning to Python: for :func:`run` (``checked``) a
    :class:`_Flights`, with a non-terminal event on x' = u = 0 upwards (a minimum of x) appending its time to
    the list ``dips`` when x < 0 there (missed_impact (b)); for :func:`impacts` an :class:`_ImpactRule` and no
    other event.  Returns ``(ta, callback)``, the callback heyoka calls (it deep-copies callbacks at
    construction; the copy is given the shared ``dips`` list)."""
    system, x, u = _flight_system(law)
    dips = []

    def on_minimum(ta, t, d_sgn):
        if ta.update_d_output(t)[0] < 0.0:  # heyoka's state is the step's end: x at t from the dense output
            dips.append(t)

    kw = {} if cooldown is None else {"cooldown": float(cooldown)}
    floor = hy.t_event(x, callback=_Flights() if checked else _ImpactRule(), direction=hy.event_direction.negative,
                       **kw)
    minimum = [hy.nt_event(u, on_minimum, direction=hy.event_direction.positive)] if checked else []
    ta = hy.taylor_adaptive(system, [0.0] * 4, t_events=[floor], nt_events=minimum, pars=[0.0] * 3, tol=tol,
                            high_accuracy=high_accuracy)
    callback = ta.t_events[0].callback
    callback.dips = dips  # a function deep-copies to itself: on_minimum appends to this list
    return ta, callback


def _flight_system(law):
    """(system, x, u): heyoka's form of the flight ODE (module docstring) for ``law``, pars (gamma, mu, xi_eq)."""
    x, u, v, eta = hy.make_vars("x", "u", "v", "eta")
    gamma, mu, xi_eq = (hy.par[i] for i in range(3))
    force, factor = law.symbolic(hy, xi_eq + eta)
    damping = 2.0 * mu * v if isinstance(factor, float) and factor == 1.0 else 2.0 * mu * v * factor
    xi2 = -force - damping
    return [(x, u), (u, -gamma - xi2), (v, xi2), (eta, v)], x, u


@functools.cache
def bare_integrator(law, tol: float, high_accuracy: bool, floor_check: bool):
    """heyoka's integrator of the same flight ODE as :func:`integrator` (same law, tolerance, Taylor order) with
    no impact rule, for :func:`step_cost`: no event at all, or (``floor_check``) the floor x = 0 downwards as a
    non-terminal event whose callback only counts its calls.  Returns ``(ta, calls)``, ``calls`` a one-item list."""
    system, x, _ = _flight_system(law)
    calls = [0]

    def count(ta, t, d_sgn):
        calls[0] += 1

    events = [hy.nt_event(x, count, direction=hy.event_direction.negative)] if floor_check else []
    ta = hy.taylor_adaptive(system, [0.0] * 4, nt_events=events, pars=[0.0] * 3, tol=tol,
                            high_accuracy=high_accuracy)
    return ta, calls  # heyoka deep-copies callbacks, a function to itself: count's closure is this list


def step_cost(params, initial, n_steps, setting=None, floor_check=False):
    """heyoka's integrator-only cost, for speed measurements: ``(steps, cpu, calls)``, ``n_steps`` Taylor steps of
    the flight ODE of :func:`impacts` (same law, parameters, tolerance and Taylor order: :func:`bare_integrator`)
    from ``initial`` with no impact rule, in ``propagate_until`` calls of RESTART_STEPS steps (``max_steps``), each
    from ``initial`` again: the ball falls through the floor and away, so no Python callback runs on the path
    (with ``floor_check``: the floor event's counting callback, ``calls`` times, at most once or twice per call, at
    the first crossing).  ``cpu`` is the process time of those calls alone (the restarts: under 1 % of it).  The
    restarts keep the flight near its start, where the spring still moves: a spring at rest in flight (the
    linear law at xi = 0, xi' = 0; the spring relaxes to that over a long flight) makes x an exact polynomial, and
    heyoka then takes steps as long as the span (~1e300 here: x overflows).  Start from a state whose spring
    moves, e.g. a post-impact one (xi' jumps by x' at every impact).  What a step costs (the Taylor coefficients to the integrator's order, the step size, the
    state update; with ``floor_check`` also the event polynomial of x and its root check, which finds none) does
    not depend on the state, so ``cpu / steps`` is heyoka's cost per step in :func:`impacts` WITHOUT: the
    isolation and refinement of the root at each impact, truncating the step there, and the Python callback
    (:class:`_ImpactRule`) with its calls into and out of Python.  Raises when heyoka stops short of
    ``n_steps`` (a non-finite state: the power law with the spring exactly at rest length)."""
    cfg = _setting(setting)
    ta, calls = bare_integrator(params.spring, float(cfg["tol"]), bool(cfg["high_accuracy"]), bool(floor_check))
    dev = initial.deviations(params)
    ta.pars[:] = [params.gamma, params.mu, params.xi_eq]
    calls[0] = 0
    done, cpu = 0, 0.0
    while done < n_steps:
        ta.time = 0.0
        ta.state[:] = [dev.x, dev.xdot, dev.xidot, dev.eta]
        m = min(RESTART_STEPS, int(n_steps) - done)
        start = time.process_time()
        outcome, _, _, steps, _, _ = ta.propagate_until(1e300, max_steps=m)
        cpu += time.process_time() - start
        if steps != m or not np.isfinite(ta.state).all():
            raise RuntimeError(f"heyoka took {done + steps} of {n_steps} steps ({outcome!r}, state {list(ta.state)!r})")
        done += m
    return done, cpu, calls[0]


class _ImpactRule:
    """Terminal-event callback of :func:`impacts`: at every downward crossing of x = 0 it applies the impact
    rule (eq. ``collision-rule``: x -> 0, x' -> -x', xi' -> x' + xi', eta kept) in place and records
    the impact; it stops the propagation (returns False) at ``limit`` impacts."""

    def __init__(self):
        self.reset(0)

    def reset(self, limit):
        self.limit = limit
        self.t, self.u, self.v, self.eta = [], [], [], []
        self.priming = False  # True during _start's restart at t = 0: that event is not an impact

    def impact(self, ta):
        """Apply the rule to ta's state (x' < 0 at a downward crossing: psi' <-> xi'); (x', xi', eta) after it.
        ``ta.state`` is read once: each read makes a numpy view (measured: a second read cost ~0.3 us per impact)."""
        s = ta.state
        u, v = s[1], s[2]
        s[0] = 0.0
        s[1] = -u
        s[2] = u + v
        return -u, u + v, s[3]

    def record(self, t, u, v, eta):
        self.t.append(t)
        self.u.append(u)
        self.v.append(v)
        self.eta.append(eta)

    def __call__(self, ta, d_sgn):
        u, v, eta = self.impact(ta)
        if self.priming:
            self.priming = False
            return False
        self.record(ta.time, u, v, eta)
        return len(self.t) < self.limit


class _Flights(_ImpactRule):
    """The floor event's callback in :func:`run`: the impact rule and its record (:class:`_ImpactRule`), and
    the per-flight checks of the module docstring: it stops the propagation (returns False) at
    ``limit`` impacts or on a failure, which it notes in ``failure``, ``index``, ``reason``: a minimum of x
    below the floor inside the flight, too many zero-length flights, the CPU budget."""

    def __init__(self):
        self.dips = []
        self.reset(0)

    def reset(self, limit, budget=math.inf, start=0.0):
        super().reset(limit)
        self.t_prev, self.budget, self.start = 0.0, budget, start
        self.note("", -1, "")
        self.n_short = 0

    def __call__(self, ta, d_sgn):
        u, v, eta = self.impact(ta)
        if self.priming:
            self.priming = False
            return False
        if self.dips and self.inside():
            return False
        t = ta.time
        tau = t - self.t_prev
        self.t_prev = t
        self.record(t, u, v, eta)
        n = len(self.t)
        self.n_short = self.n_short + 1 if tau < STALL_DT else 0
        if self.n_short > STALL_COUNT:
            self.note("stall", n - 1, "zero-length flights: the event re-triggers")
            return False
        if n >= self.limit:
            return False
        if self.budget < math.inf and time.process_time() - self.start > self.budget:
            self.note("budget", n, "CPU budget exhausted")
            return False
        return True

    def note(self, failure, index, reason):
        self.failure, self.index, self.reason = failure, index, reason

    def inside(self):
        """missed_impact (b): x had a minimum below the floor inside a flight (noted; the impacts from the end of
        the flight that holds it on are dropped).  heyoka calls a step's non-terminal callbacks before its
        terminal one and drops those after the terminal event, so that flight is the one under way: the
        impact whose callback sees the dip is not recorded.  Checked at every impact and after every propagation."""
        if not self.dips:
            return False
        t_dip = self.dips[0]
        self.dips.clear()
        k = bisect.bisect_left(self.t, t_dip)
        for column in (self.t, self.u, self.v, self.eta):
            del column[k:]
        self.note("missed_impact", k,
                  f"x had a minimum below the floor at t = {t_dip!r} inside a flight: the dip into it was skipped")
        return True


@functools.cache
def event_integrator(law, tol: float, cooldown: float | None, high_accuracy: bool):
    """heyoka's integrator of :func:`integrator` with the floor x = 0 downwards as a terminal event WITHOUT a
    callback (for :func:`event_cost`): each ``step()`` that reaches the floor ends there and returns
    EVENT_STOP, with heyoka's event bookkeeping (cooldown) as in :func:`impacts`."""
    system, x, _ = _flight_system(law)
    kw = {} if cooldown is None else {"cooldown": float(cooldown)}
    floor = hy.t_event(x, direction=hy.event_direction.negative, **kw)
    return hy.taylor_adaptive(system, [0.0] * 4, t_events=[floor], pars=[0.0] * 3, tol=tol,
                              high_accuracy=high_accuracy)


def event_cost(params, initial, n_impacts, setting=None):
    """What heyoka's event handling costs without a Python callback, for speed measurements: a dict with
    ``impacts``, ``steps``, ``t`` (the impact times), ``cpu_events`` and ``cpu_matched`` (process seconds).

    Two Python loops of ``ta.step()`` calls with the same Python work per call: (1) :func:`event_integrator` from
    ``initial`` (a restart on the floor as in :func:`_start`: from the pre-impact state, the event at t = 0 not
    counted), each step at most CHUNK_FLIGHTS flight bounds of the start long (as :func:`run`'s propagations: a
    flight whose x is an exact polynomial, the linear spring at rest, is otherwise one step of unbounded length),
    applying the impact rule to ``ta.state`` in the loop at every step that ends on the floor, until
    ``n_impacts`` impacts: the trajectory of :func:`impacts`, with the rule in Python between heyoka calls instead
    of in a callback; (2) as many steps (same bound) of :func:`bare_integrator` (no events; restarts every RESTART_STEPS steps
    from ``initial``, outside the timing, as in :func:`step_cost`), running the same rule on a scratch array and
    recording a time as often.  ``cpu_events - cpu_matched`` is then heyoka's event handling in C++ alone: the
    event polynomial and its root search on every step, the isolation and refinement of the root at each impact,
    the step's truncation there and the cooldown, which a C++ user of a terminal event pays too (the Python loop
    and the rule's Python body cancel, up to the loops' small differences: measured with stand-in objects for
    the integrators, loop (1)'s Python side is 0.06-0.1 us per impact cheaper, so the difference errs low by
    that).  Raises when
    heyoka stops with an error or takes 1000 steps per impact."""
    cfg = _setting(setting)
    ta = event_integrator(params.spring, float(cfg["tol"]), cfg["cooldown"], bool(cfg["high_accuracy"]))
    bare, _ = bare_integrator(params.spring, float(cfg["tol"]), bool(cfg["high_accuracy"]), False)
    dev = initial.deviations(params)
    n_impacts = int(n_impacts)
    times = np.empty(n_impacts)
    ta.pars[:] = bare.pars[:] = [params.gamma, params.mu, params.xi_eq]
    ta.time = 0.0
    ta.reset_cooldowns()
    restart = dev.x == 0.0 and dev.xdot > 0.0
    ta.state[:] = [0.0, -dev.xdot, dev.xidot + dev.xdot, dev.eta] if restart else [dev.x, dev.xdot, dev.xidot,
                                                                                     dev.eta]
    n, k, n_skip, limit = -1 if restart else 0, 0, 1 if restart else 0, 1000 * n_impacts + 1000
    step, ok = ta.step, (int(hy.taylor_outcome.success), int(hy.taylor_outcome.time_limit))
    h_max = CHUNK_FLIGHTS * flight_bound(dev.x, dev.xdot, dev.xidot, params.xi_eq + dev.eta, params.gamma,
                                         params.spring)
    start = time.process_time()
    while n < n_impacts and k < limit:
        outcome = int(step(h_max)[0])
        k += 1
        if outcome == EVENT_STOP:
            s = ta.state
            u, v = s[1], s[2]
            s[0] = 0.0
            s[1] = -u
            s[2] = u + v
            if n >= 0:
                times[n] = ta.time
            n += 1
        elif outcome not in ok:
            break
    cpu_events = time.process_time() - start
    if n < n_impacts:
        raise RuntimeError(f"heyoka's step loop found {max(n, 0)} of {n_impacts} impacts in {k} steps "
                           f"(last outcome {outcome}, state {list(ta.state)!r})")
    scratch, scratch_t = np.zeros(4), np.empty(n_impacts + n_skip)
    done, m_rule, cpu_matched = 0, 0, 0.0
    total = n_impacts + n_skip
    while done < k:
        bare.time = 0.0
        bare.state[:] = [dev.x, dev.xdot, dev.xidot, dev.eta]
        m = min(RESTART_STEPS, k - done)
        j = 0
        step = bare.step
        start = time.process_time()
        while j < m:
            outcome = int(step(h_max)[0])
            j += 1
            if m_rule * k < total * (done + j):  # the rule as often as in loop (1), spread over the steps
                s = bare.state
                u, v = scratch[1], scratch[2]
                scratch[0] = 0.0
                scratch[1] = -u
                scratch[2] = u + v
                scratch_t[m_rule] = bare.time
                m_rule += 1
        cpu_matched += time.process_time() - start
        done += m
    return {"impacts": n_impacts, "steps": k, "t": times, "cpu_events": cpu_events, "cpu_matched": cpu_matched,
            "rules_matched": m_rule}


def _started(params, initial, setting, checked):
    """(ta, callback, cfg, dev): the integrator of :func:`integrator` for ``params.spring``, with its parameters,
    time 0, its callback reset, at the start state ``dev`` (:func:`_start`; eta = xi - params.xi_eq)."""
    cfg = _setting(setting)
    dev = initial.deviations(params)
    ta, callback = integrator(params.spring, float(cfg["tol"]), cfg["cooldown"], bool(cfg["high_accuracy"]), checked)
    ta.pars[:] = [params.gamma, params.mu, params.xi_eq]
    ta.time = 0.0
    ta.reset_cooldowns()
    callback.reset(0)
    callback.priming = True
    _start(ta, dev.x, dev.xdot, dev.xidot, dev.eta)
    callback.priming = False
    callback.dips.clear()
    return ta, callback, cfg, dev


def impacts(params, initial, max_events, t_end, setting=None):
    """heyoka's fastest use for a sequence of impacts, for speed measurements: ``(t, xdot, xidot, eta, cpu,
    steps)``.

    One ``propagate_until(t_end)`` call; the impact rule runs in the floor event's callback
    (:class:`_ImpactRule`), which stops the propagation after ``max_events`` impacts.  :func:`run`
    adds its failure checks (a non-terminal event on x' = 0, the checks of :class:`_Flights`, the flight
    bound between propagations): 1.25x the CPU per Hertz impact (module docstring).  Here nothing is
    checked: a skipped impact shows as fewer than ``max_events`` impacts by
    ``t_end`` (x stays below the floor after it) or as impact times that differ from a reference,
    which the caller compares.  ``cpu`` is the process time of the propagation alone, ``steps`` heyoka's
    Taylor steps in it (the step that ends at an impact counts as one; the propagation ends with the step of
    the last impact when ``max_events`` are found; :func:`step_cost` prices a step).  ``t_end`` should
    be finite and of the order of the run: heyoka's event detection fails (EDOM in its root finder,
    every event missed) on a step ~1e8 long, which a flight whose x is an exact polynomial (the linear
    spring at rest) takes; :func:`run` propagates by CHUNK_FLIGHTS flight bounds for that reason.
    """
    ta, rule, _, _ = _started(params, initial, setting, checked=False)
    rule.reset(max_events)
    start = time.process_time()
    steps = ta.propagate_until(t_end)[3]
    cpu = time.process_time() - start
    return np.array(rule.t), np.array(rule.u), np.array(rule.v), np.array(rule.eta), cpu, int(steps)


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


def flight_bound(x, u, v, xi, gamma, law) -> float:
    """A time after which x < 0 whatever the spring does (module docstring, missed_impact (a))."""
    xm = law.amplitude(0.5 * v * v + law.potential(xi))
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
    """heyoka from flight to flight (the impact rule and the checks in the floor event's callback,
    :class:`_Flights`), in propagations of CHUNK_FLIGHTS flight bounds; see the module docstring for the
    settings and failure rules."""
    ta, flights, cfg, dev = _started(params, initial, setting, checked=True)
    gamma, law, xi_eq = params.gamma, params.spring, params.xi_eq
    flights.reset(max_events, float(cfg["cpu_budget"]))
    samples = None if sample_times is None else np.asarray(sample_times, dtype=float)
    y_out = None if samples is None else np.full(samples.shape, np.nan)
    steps, outcome = 0, None
    start = flights.start = time.process_time()
    while len(flights.t) < max_events and ta.time < t_max:
        t0 = ta.time
        x, u, v, eta = ta.state
        t_stop = min(t_max, t0 + CHUNK_FLIGHTS * flight_bound(x, u, v, xi_eq + eta, gamma, law))
        dense = samples is not None and bool(np.any((samples >= t0) & (samples <= t_stop)))
        outcome, _, _, nsteps, c_out, _ = ta.propagate_until(t_stop, c_output=dense)
        steps += nsteps
        if dense and c_out is not None:
            m = (samples >= t0) & (samples <= ta.time)
            if m.any():
                s = c_out(samples[m])
                y_out[m] = 1.0 + 2.0 * xi_eq + s[:, 0] + 2.0 * s[:, 3]
        if outcome != hy.taylor_outcome.time_limit or flights.failure or flights.inside():
            break  # (b) before (a): a dip found during the propagation is named as such
        # missed_impact (a): the flight under way has outlived the bound from its start
        k = len(flights.t)
        x, u, v, eta = (dev.x, dev.xdot, dev.xidot, dev.eta) if k == 0 else (
            0.0, flights.u[-1], flights.v[-1], flights.eta[-1])
        bound = flights.t_prev + flight_bound(x, u, v, xi_eq + eta, gamma, law)
        if ta.time > bound:
            flights.note("missed_impact", k, f"no event before the flight bound t = {bound!r} "
                         f"(x = {ta.state[0]!r}): an impact was skipped")
            break
    cpu = time.process_time() - start
    if outcome is not None and not flights.failure and not flights.inside():
        if int(outcome) != EVENT_STOP and outcome != hy.taylor_outcome.time_limit:
            flights.note("stall", len(flights.t),
                         f"heyoka stopped with {outcome!r} at t = {ta.time!r} (state {list(ta.state)!r})")
    return MethodResult(
        method="heyoka", setting=dict(setting or {}), t=np.array(flights.t), xdot=np.array(flights.u),
        cpu_time=cpu, failure=flights.failure, failure_index=flights.index, t_end=flights.t_prev, y=y_out,
        extra={"xidot": np.array(flights.v), "eta": np.array(flights.eta), "steps": steps,
               "reason": flights.reason, "law": law.attrs(), "cooldown": _active_cooldown(ta),
               "start": {"x": dev.x, "xdot": dev.xdot, "xidot": dev.xidot, "eta": dev.eta, "xi_eq": xi_eq}},
    )


METHOD = MethodSpec(
    name="heyoka",
    run=run,
    settings_doc=(
        "the spring law: params.spring's symbolic form; tol (2^-52); cooldown: terminal-event cooldown (None: heyoka's automatic one); high_accuracy (False); "
        "cpu_budget: process seconds (inf)"
    ),
    needs=SYMBOLIC_LAW,
)

"""Method "contact-switch": exact micro-bounces until Xdot_n < delta, then the lower mass rests on the floor.

Rule (setting ``{"delta": ...}``).  The exact solver (:func:`bounce.simulate`)
runs until an impact whose rebound speed Xdot_n is below ``delta``.  There the
lower mass is put to rest on the floor: x = 0, x' = 0, with the upper mass
unchanged (y and y' kept, i.e. xi' -> xi' + Xdot_n/2, eta = xi + gamma kept).
This removes exactly Xdot_n^2/4 of E - E_m (eq. ``tot-mech-energy``: (xi'^2 + psi'^2)/2
drops from (a^2 + (u + a)^2)/2 to (a + u/2)^2 with u = Xdot_n, a = xi'_n), reported
per switch in ``extra["energy_removed"]``.  The solver is restarted from that
state (:class:`bounce.model.Deviations` with x = xdot = 0), and *its own*
classification decides what follows (:func:`bounce.exact.events.run_events`):

* floor force F = y/2 + mu y' - gamma - 1/2 < 0 (eq. ``force-on-the-floor``; or F = 0
  with F' <= 0): a sticky phase, y'' + mu y' + y/2 = 1/2 - gamma (eq.
  ``y-eq-sticky``), in closed form, until F returns to zero with F' > 0 (eq.
  ``cond_di_distacco``), then exact bouncing resumes; or, if the amplitude of F
  can no longer reach zero, the sticky phase is proved infinite and the run ends
  (stop reason ``sticky_forever``: the ball is at rest for ever);
* F > 0 (the spring is pulling the lower mass up): it lifts off at once and the
  flight is exact (recorded as a ``grazing`` record at the switch time).

The rule applies at every impact, so after a detachment the next slow impact
switches again.  Justification: section 8.2 of the paper (eq. ``sticky-ic``,
fig. ``sticky-convergence``): the eps-solutions, a lower mass started on the
floor with speed eps, converge to the sticky solution as eps -> 0, faster than
linearly in the RMS norm of eq. ``L2-norm``; here eps is the rebound speed at
the switch, at most delta.  Measured (:func:`bounce.studies.contact_switch.switch_study`): late in the
asymptotic regime max |y - y_exact| ~ 0.36 delta^2/gamma (the micro-bounce
height x ~ Xdot^2/gamma that the switch drops), and the energy error is the
exact solution's own E - E_m ~ Xdot^2/4 <= delta^2/4, which the sticky phase
dissipates at the sticky oscillator's rate instead of e^{-2 mu t/3}.

Why it pays.  Late in the asymptotic regime tau_n ~ 3/(mu n) (Theorem main_thm),
so t_n ~ (3/mu) ln n and the exact solver needs ~exp(mu t/3) impacts to reach
time t; the switch happens near n ~ 3 gamma/(mu delta) (Xdot_n ~ 3 gamma/(mu n))
and costs nothing afterwards.

Output: ``t``/``xdot`` the impacts (the switching impact included, with its
true rebound speed); ``y`` the closed-form samples of the stitched records;
``extra``: the stitched :class:`bounce.trajectory.Trajectory` (``trajectory``), the
switch times and indices, ``energy_removed``, the stop reason and ``n_impacts``.
"""

from __future__ import annotations

import math
import time

import numpy as np

from ..kinds import GRAZING, IMPACT, STICKY_START
from ..exact.events import energy_excess
from ..model import Deviations, InputError
from ..sampling import sample_trajectory
from ..simulate import simulate
from ..trajectory import Trajectory
from .base import MethodResult, MethodSpec, compile_exact_solver

#: first chunk of exact events searched for a slow impact; later chunks are n_done/8 (waste <= ~12 %)
CHUNK_MIN, CHUNK_MAX = 256, 1 << 16


def _energy(u, a, eta, gamma):
    return energy_excess(0.0, u, a, eta, gamma)


def switch_state(u: float, a: float, eta: float) -> Deviations:
    """The lower mass put to rest after an impact (u, a, eta): x = x' = 0, y and y' kept.

    y' = x' + 2 xi' = u + 2 a must stay, so xi' -> a + u/2; eta = (y - y_eq - x)/2 is unchanged.
    """
    return Deviations(x=0.0, xdot=0.0, xidot=a + 0.5 * u, eta=eta)


def run_switch(params, initial, delta: float, max_events: int = 1000, t_max: float = math.inf):
    """Stitched records of the contact-switch dynamics (see the module docstring).

    Returns ``(traj, info)``: a :class:`Trajectory` whose records are those of the
    exact sub-runs, offset in time, with the switches in between, and a dict
    (switch_index, switch_t, energy_removed, n_switches, sub_runs).
    """
    delta = float(delta)
    if not delta >= 0.0:
        raise InputError(f"delta must be >= 0, got {delta!r}")
    gamma = params.gamma
    bufs = {k: [] for k in ("t", "tau", "u", "a", "eta", "e", "kind")}
    sw_index, sw_t, e_removed = [], [], []
    state = initial.deviations(params)
    t_off = 0.0
    n_done = 0
    sub_runs = 0
    stop = "max_events"
    t_last = 0.0  # time of the last record
    pending = False
    resume_sticky = False

    def append(t, tau, u, a, eta, e, kind):
        bufs["t"].append(t)
        bufs["tau"].append(tau)
        bufs["u"].append(u)
        bufs["a"].append(a)
        bufs["eta"].append(eta)
        bufs["e"].append(e)
        bufs["kind"].append(kind)

    while n_done < max_events:
        chunk = int(min(max_events - n_done, max(CHUNK_MIN, min(CHUNK_MAX, n_done // 8))))
        tr = simulate(params, state, max_events=chunk, t_max=t_max - t_off)
        sub_runs += 1
        if pending:
            pending = False
            # the solver records a sticky_start at its t = 0 if the rest state is sticky; otherwise the
            # lower mass lifts off at once: insert a record of the rest state (kind grazing: x = x' = 0,
            # nothing exchanged, the flight restarts from it), so that the records determine the motion
            if not (len(tr) and tr.kind[0] == STICKY_START and tr.t[0] == 0.0):
                append(np.array([t_off]), np.array([0.0]), np.array([0.0]), np.array([state.xidot]),
                       np.array([state.eta]), np.array([_energy(0.0, state.xidot, state.eta, gamma)]),
                       np.array([GRAZING], dtype=np.int8))
                n_done += 1
                if n_done >= max_events:
                    break
        # a continuation from a sticky_start record re-records it at its t = 0: skip the duplicate
        j0 = 1 if (resume_sticky and len(tr) and tr.kind[0] == STICKY_START and tr.t[0] == 0.0) else 0
        resume_sticky = False
        slow = np.flatnonzero((tr.kind == IMPACT) & (tr.xdot < delta))
        m = int(slow[0]) + 1 if slow.size else len(tr)
        m = min(m, max_events - n_done + j0)
        for key, arr in (("t", tr.t[j0:m] + t_off), ("tau", tr.tau[j0:m]), ("u", tr.xdot[j0:m]),
                         ("a", tr.xidot[j0:m]), ("eta", tr.eta[j0:m]), ("e", tr.energy_excess[j0:m]),
                         ("kind", tr.kind[j0:m])):
            bufs[key].append(np.array(arr))
        m -= j0
        n_done += m
        if m:
            t_last = float(tr.t[j0 + m - 1]) + t_off
        if slow.size and slow[0] < j0 + m and n_done < max_events:
            i = int(slow[0])
            u, a, eta = float(tr.xdot[i]), float(tr.xidot[i]), float(tr.eta[i])
            state = switch_state(u, a, eta)
            e_removed.append(_energy(u, a, eta, gamma) - _energy(0.0, state.xidot, eta, gamma))
            sw_index.append(n_done - 1)
            sw_t.append(t_last)
            t_off = t_last
            pending = True  # the next sub-run starts from the rest state: record it (below)
            continue
        if tr.stop_reason != "max_events":
            stop = tr.stop_reason
            break
        if not len(tr):
            break
        state = Deviations(x=0.0, xdot=float(tr.xdot[-1]), xidot=float(tr.xidot[-1]), eta=float(tr.eta[-1]))
        resume_sticky = bool(tr.kind[-1] == STICKY_START)
        t_off = t_last
    cat = {k: (np.concatenate(v) if v else np.empty(0)) for k, v in bufs.items()}
    kind = cat["kind"].astype(np.int8)
    t = cat["t"]
    t_end = float(t_max) if stop == "t_max" else (float(t[-1]) if t.size else 0.0)
    traj = Trajectory(params=params, initial=initial, t=t, tau=cat["tau"], xdot=cat["u"], xidot=cat["a"],
                      eta=cat["eta"], energy_excess=cat["e"], kind=kind, stop_reason=stop, t_end=t_end,
                      settings={"max_events": int(max_events), "t_max": float(t_max), "energy_stop": 0.0})
    info = {"switch_index": np.array(sw_index, dtype=np.int64), "switch_t": np.array(sw_t),
            "energy_removed": np.array(e_removed), "n_switches": len(sw_index), "sub_runs": sub_runs}
    return traj, info


def run(params, initial, setting=None, *, max_events=1000, t_max=math.inf, sample_times=None) -> MethodResult:
    """METHOD "contact-switch"; setting {"delta": rebound speed below which the lower mass is put to rest}."""
    setting = dict(setting or {})
    if "delta" not in setting:
        raise InputError("contact-switch needs setting {'delta': ...}")
    compile_exact_solver()
    start = time.process_time()
    traj, info = run_switch(params, initial, setting["delta"], max_events=int(max_events), t_max=t_max)
    cpu = time.process_time() - start
    impacts = traj.kind == IMPACT
    y = None
    extra = {"trajectory": traj, "stop_reason": traj.stop_reason, "n_impacts": int(np.count_nonzero(impacts)),
             "t_valid": traj.t_valid, **info}
    if sample_times is not None:
        s = sample_trajectory(traj, np.asarray(sample_times, dtype=float))
        y = params.y_eq + s["y_minus_yeq"]
        extra["samples"] = s
    return MethodResult(method="contact-switch", setting={"delta": float(setting["delta"])}, t=traj.t[impacts],
                        xdot=traj.xdot[impacts], cpu_time=cpu, t_end=traj.t_end, y=y, extra=extra)


def energy_excess_samples(s: dict, gamma: float) -> np.ndarray:
    """E - E_m from sampled (x, xdot, y - y_eq, ydot) (eqs. tot-mech-energy, Emin), without cancellation:
    eta = (y - y_eq - x)/2, xi' = (ydot - xdot)/2, E - E_m = (xi'^2 + psi'^2 + eta^2)/2 + gamma x."""
    x, xd, yd, ydot = s["x"], s["xdot"], s["y_minus_yeq"], s["ydot"]
    eta = 0.5 * (yd - x)
    a = 0.5 * (ydot - xd)
    return 0.5 * (a * a + (xd + a) ** 2 + eta * eta) + gamma * x


METHOD = MethodSpec(
    name="contact-switch", run=run,
    settings_doc="{'delta': float >= 0}: exact until an impact with Xdot_n < delta, then x = x' = 0 (y, y' kept) "
                 "and the solver's own sticky/detach machinery; delta = 0 is the exact solver",
)


# --------------------------------------------------------------------------- the delta study



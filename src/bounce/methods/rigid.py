"""Reduced models: a rigid ball with a restitution law, and the asymptotic map of section 6.

Rigid-ball models (paper, introduction and section 9)
-----------------------------------------------------
The ball is a rigid dimer: the spring keeps its rest length (xi = 0), so the
lower end is at x = psi, the upper mass at y = psi + 1 and the centre of mass
at psi + 1/2 (eq. ``xi-psi``).  The centre of mass falls with the dimensionless
gravity gamma (eq. ``eq-motion-psi-xi``: psi'' = -gamma) and the ball hits the
floor at psi = 0, where its speed is reversed and multiplied by r (eq.
``standard-model``).  With u_0 the speed just before the first impact and u_n
(n >= 1) the speed just after impact n, eq. ``geometric-map`` reads
u_n = r(u_{n-1}) u_{n-1}, and the flight after impact n lasts tau_n = 2 u_n / gamma.

The initial speed comes from the initial state of the dimer: psi(0) = x + xi,
psi'(0) = xdot + xi' (the internal mode is discarded), so a drop from psi(0)
hits the floor at t_1 = sqrt(2 psi(0)/gamma) with u_0 = sqrt(2 gamma psi(0)),
the dimer's first impact to O(gamma) (the dimer's spring sags by gamma).

Laws (``setting["law"]`` is fixed by the METHOD):

* ``rigid-constant-r``: r constant (default e^{-mu T_xi}, eq.
  ``rest-coefficient-function-of-mu``, T_xi = pi/sqrt(1 - mu^2)).  Inelastic
  collapse at t_inf = t_1 + 2 u_1/(gamma (1 - r)) (introduction, u_1 = r u_0 the
  speed after the first impact): failure ``collapse``, ``failure_index`` the first
  impact whose flight is below the resolution of float64 time (tau_n <= eps t_n);
  the (compensated) sum of the flights goes on until tau_n <= eps t_n/4096, where
  the tail is below rounding, and ``t_end`` is that sum (= t_inf to rounding).
* ``rigid-fifth``: r(u) = 1 - (u/U)^{1/5} (eq. ``onefifth-rest-coeff``).  The
  map u_n = u_{n-1} - U^{-1/5} u_{n-1}^{6/5} gives u_n ~ 5^5 U n^{-5} (appendix,
  remark ``x-xbeta-map`` with beta = 6/5), so the flight times are summable:
  collapse again, more slowly (t_inf - t_n ~ 2 5^5 U/(4 gamma n^4)).  Default U:
  r(u_0) = e^{-mu T_xi}, i.e. U = u_0/(1 - e^{-mu T_xi})^5.
* ``rigid-our-r``: eq. ``our-r``, r = e^{-mu T_xi} above u_c = 3 gamma/mu (1 - e^{-mu T_xi}),
  r = 1 - mu u/(3 gamma) below (continuous at u_c).  Below u_c the map is eq.
  ``restituzione``, u_n ~ 3 gamma/(mu n): the flight times are not summable, no
  collapse.  ``flight``: "rigid" (default) tau_n = 2 u_n/gamma, the rigid ball's
  parabola; "dimer" tau_n = u_n/gamma below u_c, the dimer's asymptotic
  flight (Xdot_n/tau_n -> gamma, proof of Theorem main_thm, because x'' -> -2 gamma
  at the floor).  The rigid flight takes twice as long per impact: t_n ~ (6/mu) ln n
  instead of the dimer's (3/mu) ln n.
* ``time-of-contact`` (Luding & McNamara): r (default e^{-mu T_xi}) if the time
  since the last impact exceeds t_c (default T_xi, the duration of the dimer's
  double impact), else r = 1.  Once a flight is shorter than t_c every later
  impact is elastic and the ball bounces for ever with u* < gamma t_c/2: the model's
  "permanent contact" (extra ``t_contact``, ``u_contact``).

Output (:class:`bounce.methods.base.MethodResult`): ``t`` the impact times,
``xdot`` the speed just after each impact (the lower end moves with the rigid
ball).  ``y`` at ``sample_times`` is the height of the *upper mass of the rigid
dimer*, y = psi + 1 (spring at rest length; the dimer's own y rests at
y_eq = 1 - 2 gamma, a static offset of 2 gamma), NaN after the model stops
(collapse, or beyond the last computed flight); ``extra["psi"]`` is psi(t) at the same
times (the centre of mass is at psi + 1/2).  ``extra`` also holds ``energy``:
E = u_n^2/2 just after each impact (the dimer's energy with xi = xi' = 0,
eq. ``tot-mech-energy``; the rigid ball rests at E = 0), ``t_inf`` (predicted
collapse time, constant r), ``r_n`` the coefficient applied at each impact.

Asymptotic map (section 6, proof of Theorem main_thm)
----------------------------------------------------
``asymptotic-map``: the exact solver (:func:`bounce.simulate`) up to impact
``n0``, then eq. ``restituzione`` for the lower mass alone,

    Xdot_{n+1} = (1 - mu Xdot_n/(3 gamma)) Xdot_n,

with the flight time from the same expansion.  The proof writes
x(t_n + s) = Xdot_n s + Xddot_n s^2/2 + x'''(zeta) s^3/6 with Xddot_n -> -2 gamma and
x''' -> 2 mu gamma (eq. ``xddot-tau``), whence Xdot_n/tau_n -> gamma.  Variants:

* ``"paper"``: tau_n = Xdot_n/gamma and eq. ``restituzione`` as printed;
* ``"cubic"`` (default): the flight of the limiting cubic
  x(s) = Xdot_n s - gamma s^2 + mu gamma s^3/3, i.e. tau_n is its root
  tau_n = (3/(2 mu)) (1 - sqrt(1 - 4 mu Xdot_n/(3 gamma))) = Xdot_n/gamma (1 + mu Xdot_n/(3 gamma) + ...),
  and Xdot_{n+1} = -x'(tau_n) = Xdot_n - mu gamma tau_n^2/3, which is eq.
  ``restituzione`` to O(Xdot_n^3).  Both variants agree with the exact map to
  o(Xdot_n^2) per step (the spring's relaxation and the O(Xdot^3) terms); the
  cubic one has the consistent flight time to next order.

The map carries the lower mass only: ``y`` samples are the exact ones up to
t_{n0} and y_eq = 1 - 2 gamma after it (the map assumes the spring at rest at its
equilibrium; the neglected y - y_eq is the spring's residual oscillation).
"""

from __future__ import annotations

import math
import time

import numpy as np
from numba import njit

from ..kinds import IMPACT
from ..exact.events import compensated_add
from ..exact.flight import EPS
from ..model import InputError
from ..sampling import sample_trajectory
from ..simulate import simulate
from ..analysis.theory import T_xi, rest_coefficient_function_of_mu, u_c
from .base import MethodResult, MethodSpec, compile_exact_solver


#: flights shorter than this times t end a collapsing run (the tail after them is below rounding)
RESOLVED = EPS / 4096.0

# law codes of the kernel
CONSTANT, FIFTH, OUR_R, TIME_OF_CONTACT = 0, 1, 2, 3
# kernel stop codes
K_EVENTS, K_TIME, K_COLLAPSE, K_REST = 0, 1, 2, 3
STOP_NAMES = ("max_events", "t_max", "collapse", "at_rest")


def first_impact(params, initial) -> tuple[float, float, float, float]:
    """(psi0, psidot0, t_1, u_0): the centre-of-mass start and the rigid ball's first impact (time, speed)."""
    d = initial.deviations(params)
    psi0 = d.x + (d.eta - params.gamma)  # x + xi
    psid0 = d.xdot + d.xidot  # xdot + xi'
    if psi0 < 0.0:
        raise InputError(f"the rigid ball needs psi(0) = x + xi >= 0, got {psi0!r}")
    u0 = math.sqrt(psid0 * psid0 + 2.0 * params.gamma * psi0)
    t1 = (psid0 + u0) / params.gamma
    return psi0, psid0, t1, u0


@njit(cache=True)
def _rigid_kernel(law, p1, p2, p3, p4, gamma, t1, u0, max_events, t_max, out_t, out_u, out_r):
    """Impacts of the rigid ball: out_t[n], out_u[n] (speed after), out_r[n] (coefficient used).

    law CONSTANT: r = p1; FIFTH: r = 1 - (u/p1)^{1/5}; OUR_R: r = p1 (u > p2), 1 - p3 u (u <= p2),
    flight factor p4 below u_c (2 rigid, 1 dimer); TIME_OF_CONTACT: r = p1 if the time since the last
    impact > p2, else 1.  Returns (n, stop, t_end, t_valid, n_res), n_res the first impact whose flight
    is below the resolution of t (eps t), -1 if none.
    """
    t_hi = t1
    t_lo = 0.0
    if t1 > t_max:
        return 0, K_TIME, t_max, t_max, -1
    v = u0  # speed just before the impact
    since = t1  # time since the previous impact (release for the first one)
    n = 0
    n_res = -1
    while n < max_events:
        if law == CONSTANT:
            r = p1
        elif law == FIFTH:
            r = 1.0 - (v / p1) ** 0.2
            if r < 0.0:
                r = 0.0
        elif law == OUR_R:
            r = p1 if v > p2 else 1.0 - p3 * v
        else:
            r = p1 if since > p2 else 1.0
        u = r * v
        t = t_hi + t_lo
        out_t[n] = t
        out_u[n] = u
        out_r[n] = r
        n += 1
        if u == 0.0:
            return n, K_REST, t, math.inf, n_res
        factor = p4 if (law == OUR_R and v <= p2) else 2.0
        tau = factor * u / gamma
        if tau <= EPS * t and n_res < 0:
            n_res = n - 1  # first flight below the resolution of float64 time
        if tau <= RESOLVED * t:
            # flights are 1/4096 of an ulp of t: the compensated sum has converged to t_inf
            return n, K_COLLAPSE, t, t, n_res
        if t + tau > t_max:
            return n, K_TIME, t_max, t_max, n_res
        # compensated sum: t stays correctly rounded over 1e6 flights
        t_hi, t_lo = compensated_add(t_hi, t_lo, tau)
        v = u
        since = tau
    return n, K_EVENTS, t_hi + t_lo, t_hi + t_lo, n_res


def _law_parameters(law: int, params, setting: dict, u0: float) -> tuple[tuple, dict]:
    """Kernel parameters (p1..p4) and the resolved setting (the METHODS' documented defaults filled in:
    r = r1 = e^{-mu T_xi} (eq. rest-coefficient-function-of-mu), t_c = T_xi, flight "rigid")."""
    gamma, mu = params.gamma, params.mu
    r_xi = rest_coefficient_function_of_mu(mu)
    setting = {"r": r_xi, "r1": r_xi, "t_c": T_xi(mu), "flight": "rigid", **setting}
    if law == CONSTANT:
        r = float(setting["r"])
        if not 0.0 <= r <= 1.0:
            raise InputError(f"r must be in [0, 1], got {r!r}")
        return (r, 0.0, 0.0, 2.0), {"r": r}
    if law == FIFTH:
        if "U" in setting:
            U = float(setting["U"])
        else:
            r1 = float(setting["r1"])  # r at the first impact
            U = u0 / (1.0 - r1) ** 5
        if not U > 0.0:
            raise InputError(f"U must be > 0, got {U!r}")
        return (U, 0.0, 0.0, 2.0), {"U": U}
    if law == OUR_R:
        flight = setting["flight"]
        if flight not in ("rigid", "dimer"):
            raise InputError(f"flight must be 'rigid' or 'dimer', got {flight!r}")
        uc = u_c(gamma, mu)
        return (r_xi, uc, mu / (3.0 * gamma), 2.0 if flight == "rigid" else 1.0), {"flight": flight, "u_c": uc}
    r = float(setting["r"])
    tc = float(setting["t_c"])
    if not (0.0 <= r <= 1.0 and tc > 0.0):
        raise InputError(f"time-of-contact needs 0 <= r <= 1 and t_c > 0, got r={r!r}, t_c={tc!r}")
    return (r, tc, 0.0, 2.0), {"r": r, "t_c": tc}


def rigid_psi(times, psi0, psid0, gamma, t_imp, u_imp, t_valid, flight_factor=None) -> np.ndarray:
    """psi(t) of the rigid ball: the release parabola, then u_n s - gamma s^2/2 after impact n; NaN after t_valid.

    ``flight_factor`` (per impact, default 2) marks flights of the "dimer" variant of eq. our-r,
    which are shortened to u_n/gamma; their psi is the same parabola cut at tau_n (the ball returns to
    psi = 0 early by construction of that variant: a bookkeeping model, not a rigid flight).
    """
    times = np.asarray(times, dtype=float)
    psi = np.full(times.shape, np.nan)
    ok = (times >= 0.0) & (times <= t_valid)
    i = np.searchsorted(t_imp, times, side="right") - 1
    pre = ok & (i < 0)
    psi[pre] = psi0 + psid0 * times[pre] - 0.5 * gamma * times[pre] ** 2
    post = ok & (i >= 0)
    s = times[post] - t_imp[i[post]]
    u = u_imp[i[post]]
    psi[post] = np.maximum(u * s - 0.5 * gamma * s * s, 0.0)
    return psi


_WARM = {}


def warm_up() -> None:
    """Compile (or load from numba's cache) the kernels of this module and of the exact solver, once,
    so that ``cpu_time`` never includes JIT compilation (interface rule 4)."""
    if _WARM:
        return
    buf = np.empty(2)
    _rigid_kernel(CONSTANT, 0.5, 0.0, 0.0, 2.0, 0.01, 1.0, 0.1, 2, math.inf, buf, buf.copy(), buf.copy())
    _asymptotic_kernel(1e-3, 1.0, 0.01, 0.01, True, 2, math.inf, buf, buf.copy(), buf.copy())
    compile_exact_solver()
    _WARM["done"] = True


def _run_rigid(law, name, params, initial, setting=None, *, max_events=1000, t_max=math.inf, sample_times=None):
    setting = dict(setting or {})
    warm_up()
    start = time.process_time()
    psi0, psid0, t1, u0 = first_impact(params, initial)
    (p1, p2, p3, p4), resolved = _law_parameters(law, params, setting, u0)
    out_t, out_u, out_r = (np.empty(int(max_events)) for _ in range(3))
    n, stop, t_end, t_valid, n_res = _rigid_kernel(law, p1, p2, p3, p4, params.gamma, t1, u0, int(max_events),
                                            float(t_max), out_t, out_u, out_r)
    t, u, r = out_t[:n].copy(), out_u[:n].copy(), out_r[:n].copy()
    if stop == K_EVENTS and n:
        # the flight after the last recorded impact is known: valid up to the next one
        factor = p4 if (law == OUR_R and n >= 2 and u[-2] <= p2) else 2.0
        t_valid = float(t[-1] + factor * u[-1] / params.gamma)
    cpu = time.process_time() - start
    extra = {"stop_reason": STOP_NAMES[stop], "energy": 0.5 * u * u, "r_n": r, "t_1": t1, "u_0": u0,
             "psi0": psi0, "psidot0": psid0, "t_valid": t_valid, "setting_resolved": resolved,
             "y_convention": "y = psi + 1: upper mass of the rigid dimer (xi = 0); centre of mass at psi + 1/2"}
    if law == CONSTANT:
        rr = resolved["r"]
        extra["t_inf"] = t1 + 2.0 * rr * u0 / (params.gamma * (1.0 - rr)) if rr < 1.0 else math.inf
    if law == TIME_OF_CONTACT:
        elastic = np.flatnonzero(r == 1.0)
        extra["t_contact"] = float(t[elastic[0]]) if elastic.size else math.nan
        extra["u_contact"] = float(u[elastic[0]]) if elastic.size else math.nan
        extra["index_contact"] = int(elastic[0]) if elastic.size else -1
    y = None
    if sample_times is not None:
        psi = rigid_psi(sample_times, psi0, psid0, params.gamma, t, u, t_valid)
        extra["psi"] = psi
        y = psi + 1.0
    failure = "collapse" if stop == K_COLLAPSE else ""
    return MethodResult(method=name, setting={**setting, **resolved}, t=t, xdot=u, cpu_time=cpu, failure=failure,
                        failure_index=n_res if failure else -1, t_end=float(t_end), y=y, extra=extra)


def run_constant(params, initial, setting=None, **kw) -> MethodResult:
    return _run_rigid(CONSTANT, "rigid-constant-r", params, initial, setting, **kw)


def run_fifth(params, initial, setting=None, **kw) -> MethodResult:
    return _run_rigid(FIFTH, "rigid-fifth", params, initial, setting, **kw)


def run_our_r(params, initial, setting=None, **kw) -> MethodResult:
    return _run_rigid(OUR_R, "rigid-our-r", params, initial, setting, **kw)


def run_time_of_contact(params, initial, setting=None, **kw) -> MethodResult:
    return _run_rigid(TIME_OF_CONTACT, "time-of-contact", params, initial, setting, **kw)


# --------------------------------------------------------------------------- asymptotic map


@njit(cache=True)
def _asymptotic_kernel(x0, t0, gamma, mu, cubic, n_steps, t_max, out_t, out_x, out_tau):
    """Iterate eq. restituzione from Xdot = x0 at t0 (an impact): out_t, out_x the later impacts,
    out_tau[k] the flight ending at impact k.  Returns the number of impacts produced."""
    alpha = mu / (3.0 * gamma)
    t_hi = t0
    t_lo = 0.0
    x = x0
    for k in range(n_steps):
        if cubic:
            q = 4.0 * alpha * x  # tau = (3/(2 mu)) (1 - sqrt(1 - q)) = (2 x/gamma)/(1 + sqrt(1 - q))
            tau = (2.0 * x / gamma) / (1.0 + math.sqrt(1.0 - q))
            x = x - mu * gamma * tau * tau / 3.0
        else:
            tau = x / gamma
            x = (1.0 - alpha * x) * x
        if t_hi + t_lo + tau > t_max:
            return k
        t_hi, t_lo = compensated_add(t_hi, t_lo, tau)
        out_t[k] = t_hi + t_lo
        out_x[k] = x
        out_tau[k] = tau
    return n_steps


def run_asymptotic(params, initial, setting=None, *, max_events=1000, t_max=math.inf, sample_times=None):
    """Exact solver to impact n0 (setting, default 1000), then eq. restituzione (module docstring)."""
    setting = {"n0": 1000, "variant": "cubic", **(setting or {})}  # the documented defaults (METHODS)
    n0 = int(setting["n0"])
    variant = setting["variant"]
    if variant not in ("paper", "cubic"):
        raise InputError(f"variant must be 'paper' or 'cubic', got {variant!r}")
    if n0 < 1:
        raise InputError(f"n0 must be >= 1, got {n0}")
    warm_up()
    start = time.process_time()
    n0 = min(n0, int(max_events))
    traj = simulate(params, initial, max_events=n0, t_max=t_max)
    n_ex = len(traj)
    t_ex, x_ex = traj.t[:n_ex].copy(), traj.xdot[:n_ex].copy()
    failure, failure_index = "", -1
    extra = {"n0": n_ex, "stop_reason_exact": traj.stop_reason, "variant": variant}
    m = int(max_events) - n_ex
    if traj.stop_reason == "max_events" and m > 0:
        if traj.kind[-1] != IMPACT:
            raise InputError(f"event n0 = {n0} is a {traj.kind_names[-1]}, not an impact: "
                             "the map needs an impact state")
        x0 = float(x_ex[-1])
        alpha = params.mu / (3.0 * params.gamma)
        if not alpha * x0 < 0.25:
            raise InputError(
                f"n0 = {n0} is too early for the asymptotic map: mu Xdot_n0/(3 gamma) = {alpha * x0:.3g} >= 1/4 "
                "(eq. restituzione needs it small)")
        out_t, out_x, out_tau = np.empty(m), np.empty(m), np.empty(m)
        k = _asymptotic_kernel(x0, float(traj.t[-1]), params.gamma, params.mu, variant == "cubic", m,
                               float(t_max), out_t, out_x, out_tau)
        t = np.concatenate([t_ex, out_t[:k]])
        xdot = np.concatenate([x_ex, out_x[:k]])
        extra["tau_map"] = out_tau[:k].copy()
        t_valid = float(t_max) if k < m else float(t[-1])
    else:
        t, xdot = t_ex, x_ex
        t_valid = traj.t_valid
    cpu = time.process_time() - start
    extra["t_switch"] = float(t_ex[-1]) if n_ex else 0.0
    y = None
    if sample_times is not None:
        ts = np.asarray(sample_times, dtype=float)
        s = sample_trajectory(traj, ts)
        y = params.y_eq + s["y_minus_yeq"]
        if "tau_map" in extra:  # the map ran: after t_{n0} the spring is taken at rest at y_eq
            after = (ts > extra["t_switch"]) & (ts <= t_valid)
            y[after] = params.y_eq
        y[ts > t_valid] = np.nan
    return MethodResult(method="asymptotic-map", setting={"n0": n0, "variant": variant}, t=t, xdot=xdot,
                        cpu_time=cpu, failure=failure, failure_index=failure_index,
                        t_end=float(t[-1]) if len(t) else 0.0, y=y, extra=extra)


_RIGID_DOC = ("psi(0) and psi'(0) from the initial state; tau_n = 2 u_n/gamma; y = psi + 1 (rigid dimer), "
              "extra['psi'] = psi(t)")
METHODS = (
    MethodSpec("rigid-constant-r", run_constant,
               "{'r': float in [0,1], default e^{-mu T_xi}}; collapse at t_1 + 2 u_1/(gamma (1 - r)); " + _RIGID_DOC),
    MethodSpec("rigid-fifth", run_fifth,
               "{'U': float} or {'r1': r at the first impact, default e^{-mu T_xi}}: r(u) = 1 - (u/U)^{1/5}; "
               + _RIGID_DOC),
    MethodSpec("rigid-our-r", run_our_r,
               "{'flight': 'rigid' (2u/gamma) | 'dimer' (u/gamma below u_c)}: eq. our-r; " + _RIGID_DOC),
    MethodSpec("time-of-contact", run_time_of_contact,
               "{'r': default e^{-mu T_xi}, 't_c': default T_xi}: r if the last flight > t_c, else 1; " + _RIGID_DOC),
    MethodSpec("asymptotic-map", run_asymptotic,
               "{'n0': exact impacts before the map (default 1000), 'variant': 'cubic' (default) | 'paper'}: "
               "eq. restituzione after impact n0"),
)

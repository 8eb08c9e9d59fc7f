"""Method "penalty": a soft floor (spring-dashpot on x < 0) and fixed-step velocity Verlet -- the DEM way.

Discrete-element codes (LAMMPS ``pair gran/hooke``, LIGGGHTS, MercuryDPM) never
locate impacts: they let the contact overlap and push back with a stiff linear
spring-dashpot.  Here the floor acts on the lower mass only, with the force

    F_c = k_n (-x) - c_n x'   while x < 0   (0 otherwise; no clamping, as in the Hooke model),

added to the right-hand side of the x equation x'' = -gamma + S of the spring law
(S = f(xi) + 2 mu xi' g(xi), the law's physics, :mod:`bounce.springs.base`; eq. ``dimensionless-eq-motion``
for the linear law; units: k_n in units of 2k, the linear ball's own spring being 1/2 in x'' = -x/2 + ...).
The paper's floor is elastic, so c_n = 0 by default; then the contact is a half
oscillation of angular frequency omega_n = sqrt(k_n) (+ O(1) corrections) lasting
~ pi/omega_n, with overlap ~ |x'|/omega_n.

Integrator: velocity Verlet (kick-drift-kick) with the velocity-dependent forces
(the ball's damping mu g(xi) and the dashpot c_n, both linear in the velocities at the step's
new positions) taken implicitly in the closing half kick -- a 2x2 linear solve, so the scheme
stays symmetric and of order 2 on smooth motion (LAMMPS evaluates them at the
half-step velocity instead, which is first order in mu dt).  The floor force is
only C^0 at x = 0 (its derivative jumps), so the contact start and end are
resolved to the step; the overall error against the rigid floor is the soft
model's own: a delay ~ pi/omega_n per contact, i.e. O(k_n^-1/2), plus the
integration error O((omega_n dt)^2) per contact.

Setting: ``stiffness`` k_n (default 1e6), ``damping`` c_n (0), ``dt`` the step
or ``omega_dt`` = omega_n dt (dt = omega_dt / sqrt(k_n); default omega_dt = 0.1;
Verlet is unstable for omega_dt > 2), ``max_penetration`` (0.1, i.e. 0.1 L: a
DEM overlap of 10% of the length scale is the usual validity limit),
``max_contact`` (10 time units: longer than the sticky phases of the exact
dynamics, t_c ~ 5.23 in the paper's section 8.2), ``energy_tol`` (1e-3),
``cpu_budget`` (process seconds, inf).

Reported contacts are the entries into x < 0: ``t`` the entry time (cubic
Hermite root in the entering step), ``xdot`` the exit speed (Hermite slope at
the exit crossing).  Failures:

``fell_through``     x < -max_penetration, or a non-finite state (Verlet
    blown up, omega_dt > 2).
``energy_gain``      E - E_m at a contact exit (x >= 0, so no spring energy
    stored) exceeds its running minimum over earlier exits (and the start) by
    more than energy_tol relative: the exact flow strictly dissipates.
``endless_contact``  a contact lasting longer than max_contact.  With
    gamma = mu = 0.01 the asymptotic flights ~ 3/(mu n) and impact speeds
    ~ 3 gamma/(mu n) shrink until the bounce no longer leaves the soft floor
    (speed ~ the static overlap 2 gamma/k_n times omega_n): the ball then rests
    on it -- the soft model's physics, not a bug; the index where it happens is
    the result.
``budget``           process time over cpu_budget (checked every 2^18 steps).
"""

from __future__ import annotations

import functools
import math

import numpy as np
from numba import njit

from ._stepping import (
    DONE, F_ENDLESS, F_GAIN, FAIL, FAIL_IDX, IN_CONTACT, N_COMMON_SLOTS, N_CONTACT, N_STEP,
    damping, drive, energy_excess, fell_through, force, initial_energy_excess, law_arguments, potential, sample_step,
    sorted_samples, unsort, with_physics,
)
from .base import ANY_LAW, MethodResult, MethodSpec

DEFAULTS = {
    "stiffness": 1.0e6, "damping": 0.0, "dt": None, "omega_dt": 0.1, "max_penetration": 0.1,
    "max_contact": 10.0, "energy_tol": 1e-3, "cpu_budget": math.inf,
}
CHUNK = 1 << 18  # steps between budget checks (~ 1-3 ms)

# float state slots (the int slots are those of _stepping)
X, U, Y, V, AX, AY, T_IN, E_MIN, X_MIN = range(9)


@njit(cache=True, inline="always")
def hermite_root(x0, x1, d0, d1):
    """Root s in [0, 1] of the cubic Hermite p(s) with p(0) = x0, p(1) = x1, p'(0) = d0, p'(1) = d1
    (x0, x1 of opposite signs); returns (s, p'(s))."""
    s = x0 / (x0 - x1)
    for _ in range(6):
        s2 = s * s
        s3 = s2 * s
        p = (2 * s3 - 3 * s2 + 1) * x0 + (s3 - 2 * s2 + s) * d0 + (-2 * s3 + 3 * s2) * x1 + (s3 - s2) * d1
        dp = (6 * s2 - 6 * s) * x0 + (3 * s2 - 4 * s + 1) * d0 + (-6 * s2 + 6 * s) * x1 + (3 * s2 - 2 * s) * d1
        if dp == 0.0:
            break
        s_new = min(max(s - p / dp, 0.0), 1.0)
        if abs(s_new - s) < 1e-15:
            s = s_new
            break
        s = s_new
    s2 = s * s
    dp = (6 * s2 - 6 * s) * x0 + (3 * s2 - 4 * s + 1) * d0 + (-6 * s2 + 6 * s) * x1 + (3 * s2 - 2 * s) * d1
    return s, dp


def _advance(fs, ist, gamma, mu, k, cn, dt, n_steps, t_max, max_events, max_pen, max_contact, energy_tol,
             t_out, v_out, e_out, dur_out, samples, y_samples, c, xi_eq, v_eq):
    """Up to n_steps Verlet steps; updates the state arrays fs (float) and ist (int) in place.  The spring: the law's
    force, damping and potential of coefficients c (a template: :func:`~bounce.methods._stepping.with_physics`
    binds the law; its stiffness is unused, the kick is explicit in the positions)."""
    x, u, y, v, ax, ay = fs[X], fs[U], fs[Y], fs[V], fs[AX], fs[AY]
    h2 = 0.5 * dt
    n = ist[N_STEP]
    for _ in range(n_steps):
        t0 = n * dt
        if t0 >= t_max:
            ist[DONE] = 1
            break
        # kick-drift
        uh = u + h2 * ax
        vh = v + h2 * ay
        x1 = x + dt * uh
        y1 = y + dt * vh
        # closing kick, implicit in the velocities (the damping is linear in them at the new positions)
        xi1 = 0.5 * ((y1 - x1) - 1.0)
        spring = force(xi1, c)
        m = mu * damping(xi1, c)
        px = -gamma + spring
        py = -gamma - spring
        cc = 0.0
        if x1 < 0.0:
            px += -k * x1
            cc = cn
        a11 = 1.0 + h2 * (m + cc)
        a12 = -h2 * m
        a22 = 1.0 + h2 * m
        r1 = uh + h2 * px
        r2 = vh + h2 * py
        det = a11 * a22 - a12 * a12
        u1 = (a22 * r1 - a12 * r2) / det
        v1 = (a11 * r2 - a12 * r1) / det
        ax1 = px - (m + cc) * u1 + m * v1
        ay1 = py - m * v1 + m * u1
        n += 1
        t1 = n * dt
        sample_step(ist, samples, y_samples, t0, t1, dt, y, y1, v, v1)
        if fell_through(ist, x1, u1, max_pen):
            x, u, y, v, ax, ay = x1, u1, y1, v1, ax1, ay1
            break
        if x1 < fs[X_MIN]:
            fs[X_MIN] = x1
        if ist[IN_CONTACT] == 0:
            if x1 < 0.0 and x >= 0.0:  # entry
                s, _ = hermite_root(x, x1, dt * u, dt * u1)
                t_in = t0 + s * dt
                fs[T_IN] = t_in
                ist[IN_CONTACT] = 1
                t_out[ist[N_CONTACT]] = t_in
                ist[N_CONTACT] += 1
        else:
            if x1 >= 0.0:  # exit
                s, dp = hermite_root(x, x1, dt * u, dt * u1)
                i = ist[N_CONTACT] - 1
                v_out[i] = dp / dt
                dur_out[i] = t0 + s * dt - fs[T_IN]
                e = energy_excess(x1, u1, y1, v1, gamma, potential, c, xi_eq, v_eq)
                e_out[i] = e
                ist[IN_CONTACT] = 0
                if e - fs[E_MIN] > energy_tol * fs[E_MIN]:
                    ist[FAIL] = F_GAIN
                    ist[FAIL_IDX] = i
                    x, u, y, v, ax, ay = x1, u1, y1, v1, ax1, ay1
                    break
                if e < fs[E_MIN]:
                    fs[E_MIN] = e
                if ist[N_CONTACT] >= max_events:
                    ist[DONE] = 1
                    x, u, y, v, ax, ay = x1, u1, y1, v1, ax1, ay1
                    break
            elif t1 - fs[T_IN] > max_contact:
                ist[FAIL] = F_ENDLESS
                ist[FAIL_IDX] = ist[N_CONTACT] - 1
                x, u, y, v, ax, ay = x1, u1, y1, v1, ax1, ay1
                break
        x, u, y, v, ax, ay = x1, u1, y1, v1, ax1, ay1
    ist[N_STEP] = n
    fs[X], fs[U], fs[Y], fs[V], fs[AX], fs[AY] = x, u, y, v, ax, ay


def accelerations(x, u, y, v, params, k, cn):
    """x'', y'' of the soft-floor model at one state (the law's force and damping)."""
    law = params.spring
    xi = 0.5 * ((y - x) - 1.0)
    spring = law.restoring(xi) + params.mu * law.damping_factor(xi) * (v - u)
    fc = (-k * x - cn * u) if x < 0.0 else 0.0
    return -params.gamma + spring + fc, -params.gamma - spring


def _setting(setting):
    cfg = dict(DEFAULTS)
    cfg.update(setting or {})
    k = float(cfg["stiffness"])
    if not k > 0.0:
        raise ValueError(f"stiffness must be > 0, got {k!r}")
    cfg["dt"] = float(cfg["dt"]) if cfg.get("dt") is not None else float(cfg["omega_dt"]) / math.sqrt(k)
    return cfg


@functools.cache
def _warm(law):
    """Compile the kernel for ``law``'s physics outside any timed region (once per law and process)."""
    from ..model import Parameters

    fs = np.zeros(9)
    fs[X] = 1e-3
    fs[E_MIN] = 1.0
    ist = np.zeros(N_COMMON_SLOTS, dtype=np.int64)
    buf = np.zeros(2)
    with_physics(_advance, type(law))(fs, ist, 0.01, 0.01, 1e4, 0.0, 1e-3, 10, 1.0, 2, 0.1, 10.0, 1e-3, buf,
                                      buf.copy(), buf.copy(), buf.copy(), np.zeros(1), np.zeros(1),
                                      *law_arguments(Parameters(0.01, 0.01, law)))


def run(params, initial, setting=None, *, max_events=1000, t_max=math.inf, sample_times=None) -> MethodResult:
    """Soft floor + velocity Verlet; see the module docstring for the setting keys."""
    _warm(params.spring)
    cfg = _setting(setting)
    st = initial.to_state(params) if hasattr(initial, "to_state") else initial
    gamma, mu = params.gamma, params.mu
    k, cn, dt = float(cfg["stiffness"]), float(cfg["damping"]), cfg["dt"]
    law = law_arguments(params)
    advance = with_physics(_advance, type(params.spring))
    samples, order = sorted_samples(sample_times)
    y_s = np.full(samples.shape, np.nan)
    t_out, v_out, e_out, dur_out = (np.full(max_events, np.nan) for _ in range(4))
    fs = np.zeros(9)
    fs[X], fs[U], fs[Y], fs[V] = st.x, st.xdot, st.y, st.ydot
    fs[AX], fs[AY] = accelerations(st.x, st.xdot, st.y, st.ydot, params, k, cn)
    fs[E_MIN] = initial_energy_excess(st, params)
    fs[X_MIN] = st.x
    ist = np.zeros(N_COMMON_SLOTS, dtype=np.int64)
    ist[IN_CONTACT] = 1 if st.x < 0.0 else 0
    budget = float(cfg["cpu_budget"])
    failure, failure_index, cpu = drive(
        lambda: advance(fs, ist, gamma, mu, k, cn, dt, CHUNK, float(t_max), int(max_events), float(cfg["max_penetration"]),
                 float(cfg["max_contact"]), float(cfg["energy_tol"]), t_out, v_out, e_out, dur_out, samples, y_s, *law),
        ist, budget,
    )
    n = int(ist[N_CONTACT])
    t_end = float(ist[N_STEP] * dt)
    y = None if order is None else unsort(y_s, order, np.shape(sample_times))
    return MethodResult(
        method="penalty", setting=dict(setting or {}), t=t_out[:n].copy(), xdot=v_out[:n].copy(), cpu_time=cpu,
        failure=failure, failure_index=failure_index, t_end=t_end, y=y,
        extra={"steps": int(ist[N_STEP]), "dt": dt, "contact_duration": dur_out[:n].copy(),
               "energy_excess": e_out[:n].copy(), "min_x": float(fs[X_MIN]), "in_contact": bool(ist[IN_CONTACT])},
    )


METHOD = MethodSpec(
    name="penalty",
    run=run,
    settings_doc=(
        "stiffness k_n (1e6, units of 2k); damping c_n (0: elastic floor); dt, or omega_dt = sqrt(k_n) dt (0.1); "
        "max_penetration (0.1 L); max_contact (10 time units); energy_tol (1e-3 relative rise of E - E_m at "
        "contact exits); cpu_budget (process seconds, inf)"
    ),
    needs=ANY_LAW,
)

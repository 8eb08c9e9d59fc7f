"""Method "moreau-jean": Moreau--Jean event-capturing time-stepping (the scheme of the Siconos platform).

No event location: every step of length h is a theta-method step of the
measure differential inclusion, with the floor impulse p (on the lower mass
only) solving a one-contact complementarity problem at velocity level with
Newton's impact law.  With q = (x, y), v = (x', y'), unit masses and the forces
of the spring law (:mod:`bounce.springs.base`) f(q, v) = (-gamma + S, -gamma - S),
S = f(xi) + 2 mu xi' g(xi) (eq. ``dimensionless-eq-motion`` for the linear law):

    v_{k+1} - v_k = h [theta f(q_{k+1}, v_{k+1}) + (1 - theta) f(q_k, v_k)] + (p, 0),
    q_{k+1}      = q_k + h [theta v_{k+1} + (1 - theta) v_k],

with f(q_{k+1}, v_{k+1}) linearised at the step's start, as Siconos' MoreauJeanOSI does for nonlinear
Lagrangian systems (one Newton step): with the stiffness K = -df/dq = f'(xi)/2 [[1, -1], [-1, 1]] and the
damping C = -df/dv = mu g(xi) [[1, -1], [-1, 1]] at q_k (the term of g' in df/dq is left out of K: an
approximate Jacobian, which the step's first order overall tolerates),

    W (v_{k+1} - v_k) = h f(q_k, v_k) - h^2 theta K v_k + (p, 0),   W = I + h theta C + h^2 theta^2 K,

W^-1 = [[1 + s, s], [s, 1 + s]] / (1 + 2 s), s = h theta mu g + h^2 theta^2 f'/2.  For the linear law f is
linear, so this is the theta-method itself (K, C constant).  The contact is in the index set when the
predicted gap x_k + g_p h x'_k <= 0 (g_p = ``gap_prediction``, 1/2 as Siconos' default gamma), and then

    0 <= U_{k+1} + e U_k  _|_  p >= 0,     U = x' (normal velocity), e = ``restitution``,

which for one contact is the closed-form projection
p = max(0, -(U_free + e U_k) / (W^-1)_{11}).  theta = 1/2 is second order on
smooth motion; the impacts are located only to the step, so the method is first
order overall.  It crosses accumulations (a resting contact is a run of steps
with p > 0), which an event-driven scheme cannot do.

Reported contacts: a contact is a maximal run of consecutive steps with p > 0;
``t`` its start, estimated as t_k + x_k / |x'_k| clipped to [t_k - h, t_k + h]
(the crossing of the pre-impact straight line; with the mid-step gap
prediction x_k may already be below the floor by up to ~h |x'_k| / 2), ``xdot`` the
normal velocity after the run's last impulse.  Failures:

``energy_gain``      E - E_m after a contact run exceeds its running minimum by
    more than ``energy_tol`` relative (default 1e-3).
``endless_contact``  a contact run (constraint active with impulse) lasting longer
    than ``max_contact`` (default 10 time units, > the paper's sticky t_c ~ 5.23).
``fell_through``     x < -max_penetration (0.1) or a non-finite state.
``budget``           process time over ``cpu_budget`` (checked every 2^18 steps).

Setting: dt (default 1e-3), theta (0.5; 0.5..1), restitution (1.0: the paper's
elastic floor), gap_prediction (0.5), max_contact, max_penetration, energy_tol,
cpu_budget.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from ._stepping import (
    DONE, F_ENDLESS, F_GAIN, FAIL, FAIL_IDX, IN_CONTACT, N_COMMON_SLOTS, N_CONTACT, N_STEP,
    damping, drive, energy_excess, fell_through, force, initial_energy_excess, law_arguments, potential, sample_step,
    sorted_samples, stiffness, unsort, with_physics,
)
from .base import ANY_LAW, MethodResult, MethodSpec

DEFAULTS = {
    "dt": 1e-3, "theta": 0.5, "restitution": 1.0, "gap_prediction": 0.5, "max_contact": 10.0,
    "max_penetration": 0.1, "energy_tol": 1e-3, "cpu_budget": math.inf,
}
CHUNK = 1 << 18

# float state slots; int slots: those of _stepping plus
X, U, Y, V, T_IN, E_MIN, X_MIN = range(7)
N_IMPULSE = N_COMMON_SLOTS  # steps with a nonzero impulse


def _advance(fs, ist, gamma, mu, h, theta, e_rest, g_pred, n_steps, t_max, max_events, max_pen,
             max_contact, energy_tol, t_out, v_out, e_out, dur_out, samples, y_samples, c, xi_eq, v_eq):
    """Up to n_steps Moreau--Jean steps; updates the state arrays fs (float) and ist (int) in place.  The spring: the
    law's physics of coefficients c (a template: :func:`~bounce.methods._stepping.with_physics` binds the law)."""
    x, u, y, v = fs[X], fs[U], fs[Y], fs[V]
    n = ist[N_STEP]
    for _ in range(n_steps):
        t0 = n * h
        if t0 >= t_max:
            ist[DONE] = 1
            break
        # forces at step start, f = (-gamma + S, -gamma - S), and the stiffness and damping of the linearisation
        xi = 0.5 * ((y - x) - 1.0)
        m = mu * damping(xi, c)
        spring = force(xi, c) + m * (v - u)
        kk = 0.5 * stiffness(xi, c)
        # W dv = h f_k - h^2 theta K v_k, W^-1 = [[1 + s, s], [s, 1 + s]] / (1 + 2 s)
        s = h * theta * m + h * h * theta * theta * kk
        w11 = (1.0 + s) / (1.0 + 2.0 * s)
        w21 = s / (1.0 + 2.0 * s)
        kv = h * h * theta * kk * (u - v)
        rx = h * (-gamma + spring) - kv
        ry = h * (-gamma - spring) + kv
        ufree = u + w11 * rx + w21 * ry
        vfree = v + w21 * rx + w11 * ry
        p = 0.0
        if x + g_pred * h * u <= 0.0:  # index set: predicted gap closed
            viol = ufree + e_rest * u
            if viol < 0.0:
                p = -viol / w11
        u1 = ufree + w11 * p
        v1 = vfree + w21 * p
        x1 = x + h * ((1.0 - theta) * u + theta * u1)
        y1 = y + h * ((1.0 - theta) * v + theta * v1)
        n += 1
        t1 = n * h
        sample_step(ist, samples, y_samples, t0, t1, h, y, y1, v, v1)
        if fell_through(ist, x1, u1, max_pen):
            x, u, y, v = x1, u1, y1, v1
            break
        if x1 < fs[X_MIN]:
            fs[X_MIN] = x1
        if p > 0.0:
            ist[N_IMPULSE] += 1
            if ist[IN_CONTACT] == 0:
                ist[IN_CONTACT] = 1
                t_in = t0
                if u < 0.0:  # crossing of the pre-impact straight line (x may already be < 0 by up to ~h|u|/2)
                    t_in = t0 + min(max(x / -u, -h), h)
                fs[T_IN] = t_in
                t_out[ist[N_CONTACT]] = t_in
                ist[N_CONTACT] += 1
            elif t1 - fs[T_IN] > max_contact:
                ist[FAIL] = F_ENDLESS
                ist[FAIL_IDX] = ist[N_CONTACT] - 1
                x, u, y, v = x1, u1, y1, v1
                break
        elif ist[IN_CONTACT] == 1:  # the run of impulses ended at the previous step
            i = ist[N_CONTACT] - 1
            v_out[i] = u
            dur_out[i] = t0 - fs[T_IN]
            e = energy_excess(x, u, y, v, gamma, potential, c, xi_eq, v_eq)
            e_out[i] = e
            ist[IN_CONTACT] = 0
            if e - fs[E_MIN] > energy_tol * fs[E_MIN]:
                ist[FAIL] = F_GAIN
                ist[FAIL_IDX] = i
                x, u, y, v = x1, u1, y1, v1
                break
            if e < fs[E_MIN]:
                fs[E_MIN] = e
            if ist[N_CONTACT] >= max_events:
                ist[DONE] = 1
                x, u, y, v = x1, u1, y1, v1
                break
        x, u, y, v = x1, u1, y1, v1
    ist[N_STEP] = n
    fs[X], fs[U], fs[Y], fs[V] = x, u, y, v


def _setting(setting):
    cfg = dict(DEFAULTS)
    cfg.update(setting or {})
    if not float(cfg["dt"]) > 0.0:
        raise ValueError(f"dt must be > 0, got {cfg['dt']!r}")
    if not 0.0 <= float(cfg["theta"]) <= 1.0:
        raise ValueError(f"theta must be in [0, 1], got {cfg['theta']!r}")
    return cfg


@functools.cache
def _warm(law):
    """Compile the kernel for ``law``'s physics outside any timed region (once per law and process)."""
    from ..model import Parameters

    fs = np.zeros(7)
    fs[X] = 1e-3
    fs[E_MIN] = 1.0
    ist = np.zeros(N_COMMON_SLOTS + 1, dtype=np.int64)
    buf = np.zeros(2)
    with_physics(_advance, type(law))(fs, ist, 0.01, 0.01, 1e-3, 0.5, 1.0, 0.5, 10, 1.0, 2, 0.1, 10.0, 1e-3,
                                      buf, buf.copy(), buf.copy(), buf.copy(), np.zeros(1), np.zeros(1),
                                      *law_arguments(Parameters(0.01, 0.01, law)))


def run(params, initial, setting=None, *, max_events=1000, t_max=math.inf, sample_times=None) -> MethodResult:
    """Moreau--Jean time-stepping; see the module docstring for the setting keys."""
    _warm(params.spring)
    cfg = _setting(setting)
    st = initial.to_state(params) if hasattr(initial, "to_state") else initial
    gamma, mu = params.gamma, params.mu
    h, theta = float(cfg["dt"]), float(cfg["theta"])
    law = law_arguments(params)
    advance = with_physics(_advance, type(params.spring))
    samples, order = sorted_samples(sample_times)
    y_s = np.full(samples.shape, np.nan)
    t_out, v_out, e_out, dur_out = (np.full(max_events, np.nan) for _ in range(4))
    fs = np.zeros(7)
    fs[X], fs[U], fs[Y], fs[V] = st.x, st.xdot, st.y, st.ydot
    fs[E_MIN] = initial_energy_excess(st, params)
    fs[X_MIN] = st.x
    ist = np.zeros(N_COMMON_SLOTS + 1, dtype=np.int64)
    budget = float(cfg["cpu_budget"])
    failure, failure_index, cpu = drive(
        lambda: advance(fs, ist, gamma, mu, h, theta, float(cfg["restitution"]), float(cfg["gap_prediction"]),
                 CHUNK, float(t_max), int(max_events), float(cfg["max_penetration"]), float(cfg["max_contact"]),
                 float(cfg["energy_tol"]), t_out, v_out, e_out, dur_out, samples, y_s, *law),
        ist, budget,
    )
    n = int(ist[N_CONTACT])
    y = None if order is None else unsort(y_s, order, np.shape(sample_times))
    return MethodResult(
        method="moreau-jean", setting=dict(setting or {}), t=t_out[:n].copy(), xdot=v_out[:n].copy(), cpu_time=cpu,
        failure=failure, failure_index=failure_index, t_end=float(ist[N_STEP] * h), y=y,
        extra={"steps": int(ist[N_STEP]), "impulse_steps": int(ist[N_IMPULSE]),
               "contact_duration": dur_out[:n].copy(), "energy_excess": e_out[:n].copy(),
               "min_x": float(fs[X_MIN]), "in_contact": bool(ist[IN_CONTACT])},
    )


METHOD = MethodSpec(
    name="moreau-jean",
    run=run,
    settings_doc=(
        "dt (1e-3); theta (0.5, in [0.5, 1]); restitution e (1.0: elastic floor); gap_prediction (0.5: active if "
        "x + 0.5 h x' <= 0); max_contact (10 time units); max_penetration (0.1); energy_tol (1e-3 relative rise of "
        "E - E_m after a contact); cpu_budget (process seconds, inf)"
    ),
    needs=ANY_LAW,
)

"""Dense output: x(t), y(t) and velocities at any requested times.

Figures never need stored dense trajectories: the per-event records (time,
kind and the state just after each event) determine the motion in between,
a flight by eq. (F) of :mod:`bounce.exact.flight` and a sticky phase by the sticky
oscillator of :mod:`bounce.exact.events` (closed forms, linear spring), or for the
power-law spring by the Taylor-series steps of the solver itself
(:func:`bounce.series.flight.first_contact` and :func:`bounce.series.sticky.sticky_phase`
up to the sample time, which return the state there).  Samples after ``t_valid``
(the last time the simulation vouches for) are NaN.

Power law: the samples are taken in time order; within one phase each sample continues
from the previous one (a new series step starts at every sample, so a sample is exact to
rounding like the events, and a grid of n samples costs n short marches, not n^2).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .errors import InputError
from .kinds import STICKY_START
from .exact.flight import FOUND, flight_spring, gap, oscillator_at
from .exact.oscillator import fundamental, make_oscillator
from .series.flight import first_contact
from .series.taylor import DEGREE_LONG, law_array
from .series.sticky import sticky_phase

SQRT2 = math.sqrt(2.0)


@njit(cache=True)
def _sample(times, t_ev, kind, u_ev, a_ev, eta_ev, x0, u0, a0, eta0, gamma, t_valid,
            params, coefs, sparams, scoefs, out_x, out_xdot, out_ydev, out_ydot):
    for j in range(times.shape[0]):
        ts = times[j]
        if not (ts >= 0.0 and ts <= t_valid):
            out_x[j] = np.nan
            out_xdot[j] = np.nan
            out_ydev[j] = np.nan
            out_ydot[j] = np.nan
            continue
        i = np.searchsorted(t_ev, ts, side="right") - 1
        if i < 0:
            t0, x, u, a, eta, sticky = 0.0, x0, u0, a0, eta0, False
        else:
            t0, x, u, a, eta, sticky = t_ev[i], 0.0, u_ev[i], a_ev[i], eta_ev[i], kind[i] == STICKY_START
        dt = ts - t0
        if sticky:
            s = dt / SQRT2
            omc, tms, omsd, c, S, Sd = fundamental(s, sparams, scoefs)
            es0 = SQRT2 * a
            eta_t, es_t = oscillator_at(eta, es0, omc, S, Sd)
            out_x[j] = 0.0
            out_xdot[j] = 0.0
            out_ydev[j] = 2.0 * eta_t
            out_ydot[j] = SQRT2 * es_t
        else:
            xt, vt, _, omc, tms, omsd, c, S, Sd = gap(dt, x, u, a, eta, gamma, params, coefs)
            eta_t, xid_t = flight_spring(eta, a, gamma, omc, c, S, Sd)  # xi(t) + gamma, xi'(t)
            out_x[j] = max(xt, 0.0)  # clip rounding below the floor
            out_xdot[j] = vt
            out_ydev[j] = xt + 2.0 * eta_t
            out_ydot[j] = vt + 2.0 * xid_t


@njit(cache=True)
def _sample_power(times, order, t_ev, kind, u_ev, a_ev, eta_ev, x0, u0, a0, eta0, t_valid, law,
                  out_x, out_xdot, out_ydev, out_ydot):
    X = np.empty(DEGREE_LONG + 2)
    P = np.empty(DEGREE_LONG + 2)
    Q = np.empty(DEGREE_LONG + 2)
    phase = -2  # the phase the chain is in (-1: before the first event)
    t0, x, u, a, eta, sticky = 0.0, 0.0, 0.0, 0.0, 0.0, False
    for j in order:
        ts = times[j]
        if not (ts >= 0.0 and ts <= t_valid):
            out_x[j] = np.nan
            out_xdot[j] = np.nan
            out_ydev[j] = np.nan
            out_ydot[j] = np.nan
            continue
        i = np.searchsorted(t_ev, ts, side="right") - 1
        if i != phase:
            phase = i
            if i < 0:
                t0, x, u, a, eta, sticky = 0.0, x0, u0, a0, eta0, False
            else:
                t0, x, u, a, eta, sticky = t_ev[i], 0.0, u_ev[i], a_ev[i], eta_ev[i], kind[i] == STICKY_START
        dt = ts - t0
        if dt > 0.0:
            if sticky:
                _, _, a, eta = sticky_phase(a, eta, dt, law, X, P, Q, True)
            else:
                status, _, v1, v2, eta_t, xid_t, _, _ = first_contact(x, u, a, eta, dt, law, X, P, Q, True)
                if status == FOUND:  # a contact within rounding before the recorded one: at the floor
                    x, u = 0.0, v1
                else:  # HORIZON: (x'(ts), x(ts)), not clipped (a rounding-level -1e-17 shows as such)
                    x, u = v2, v1
                a, eta = xid_t, eta_t
            t0 = ts
        out_x[j] = x
        out_xdot[j] = u
        out_ydev[j] = x + 2.0 * eta
        out_ydot[j] = u + 2.0 * a


def sample(gamma, mu, initial, t_events, kind, xdot, xidot, eta, times, t_valid, spring=None):
    """x, xdot, y - y_eq, ydot at ``times`` from per-event records.

    ``initial`` is the (x, xdot, xidot, eta) state at t = 0 (a
    :class:`bounce.model.Deviations` or a 4-tuple); the event arrays are those
    of :class:`bounce.trajectory.Trajectory` (or of its netCDF dataset).  ``spring``: the law
    (:mod:`bounce.springs`); its exact solver's dense output is used: the series steps for a law the
    series solver serves (eta = xi - xi_eq of that law), the closed forms for the linear law (also when
    None).  Returns a dict of float64 arrays with keys x, xdot, y_minus_yeq, ydot.
    """
    x0, u0, a0, eta0 = (initial.x, initial.xdot, initial.xidot, initial.eta) if hasattr(initial, "eta") else initial
    times = np.ascontiguousarray(times, dtype=np.float64)
    out = {k: np.empty(times.shape) for k in ("x", "xdot", "y_minus_yeq", "ydot")}
    events = (np.ascontiguousarray(t_events, dtype=np.float64), np.ascontiguousarray(kind, dtype=np.int8),
              np.ascontiguousarray(xdot, dtype=np.float64), np.ascontiguousarray(xidot, dtype=np.float64),
              np.ascontiguousarray(eta, dtype=np.float64), float(x0), float(u0), float(a0), float(eta0))
    outputs = (out["x"].ravel(), out["xdot"].ravel(), out["y_minus_yeq"].ravel(), out["ydot"].ravel())
    solver = "exact" if spring is None else spring.solver
    if solver not in ("exact", "series"):
        raise InputError(f"spring law {spring.name!r} has no exact solver, so no dense output (bounce.springs)")
    if solver == "series":
        law = law_array(*spring.series_coefficients(), float(mu), float(gamma))
        flat = times.ravel()
        _sample_power(flat, np.argsort(flat, kind="stable"), *events, float(t_valid), law, *outputs)
        return out
    params, coefs = make_oscillator(mu)
    sparams, scoefs = make_oscillator(mu / SQRT2)
    _sample(times.ravel(), *events, float(gamma), float(t_valid), params, coefs, sparams, scoefs, *outputs)
    return out


def sample_trajectory(traj, times):
    """:func:`sample` for a :class:`bounce.trajectory.Trajectory` (closed forms for the linear spring,
    the series steps for the power law)."""
    spring = traj.params.spring
    return sample(
        traj.params.gamma, traj.params.mu, traj.initial.deviations(traj.params), traj.t, traj.kind,
        traj.xdot, traj.xidot, traj.eta, times, traj.t_valid, spring=spring,
    )

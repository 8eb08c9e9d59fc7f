"""The event loop of the power-law spring (paper, Discussion; numba kernel) and its Python front.

Same events, records and rules as :mod:`bounce.exact.events` (kind codes imported from
there): state between events (x, u = x', a = xi', eta = xi - xi_eq) with
xi_eq = -(gamma/rho)^(1/(a+1)) (eq. ``nonlin-equilibrium-xi``), and at x = 0

* **impact** (eq. ``collision-rule``, applied as the Discussion prescribes):
  psi' and xi' are exchanged: u -> -x'(tau), a -> psi'(tau^-) = u + a - gamma tau;
* **grazing** (eq. ``swishes``): a tangential contact with x'' > 0, nothing exchanged;
* **sticky_start** (eq. ``sticky-condition``): x = x' = x'' = 0, or a start at rest on
  the floor that stays (:func:`bounce.series.flight.at_rest_is_sticky`); the sticky phase
  of the nonlinear spring (its equation and floor force are derived in
  :mod:`bounce.series.sticky`) is integrated by Taylor series until
* **detach** (eq. ``cond_di_distacco``): the first F = 0 with F' > 0; the flight that
  follows lifts off from x = x' = 0 (quadratically, or cubically when F = 0, F' > 0).
  A tangential touch of F = 0 ends the phase as in the linear model, and the flight then
  records a new sticky_start at once (tau = 0) if the mass stays.

Stop reasons: those of :mod:`bounce.exact.events` (``sticky_forever``: the sticky phase proved
infinite, :func:`bounce.series.sticky.never_detaches`) plus ``slow_crossing`` (a crossing of
the rest length xi = 0 too slow to be computed to rounding, in flight or sticky, see
:mod:`bounce.series.flight`); the records up to the stop are exact.

Contacts follow :func:`bounce.exact.events.contact` (the impact rule and the rounding-level
classification of tangential contacts, shared with the linear loop), with x'' and x'''
from the series at the contact.  Time is summed with Neumaier's
compensated sum (:func:`bounce.exact.events.compensated_add`).

Energy (eq. ``nonlin-energy``): at x = 0 (psi = xi) the excess over the minimum
E_m = -gamma |xi_eq| (a+1)/(a+2) is

    E - E_m = (a^2 + (u + a)^2)/2 + V(xi_eq + eta) - V(xi_eq) + gamma eta,

and the last three terms, a Bregman divergence of V = rho |xi|^(a+2)/(a+2) of size
O(eta^2), are summed as gamma |xi_eq| / (a+2) * sum_{k>=2} C(a+2, k) (-e)^k,
e = eta / |xi_eq|, without cancellation (:func:`energy_excess`).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..kinds import (DETACH, STICKY_START, STOP_ENERGY, STOP_EVENTS, STOP_FAILED, STOP_SLOW_CROSSING, STOP_STICKY_FOREVER, STOP_TIME)
from ..exact.events import contact, compensated_add, record_event
from ..exact.flight import FOUND, HORIZON, NEVER
from .flight import (AT_REST, HANDOVER, SLOW_CROSSING, at_rest_is_sticky, first_contact, floor_force,
                           short_flight)
from .sticky import sticky_phase
from .taylor import DEGREE_LONG, L_GAMMA, L_XI_EQ, bregman, law_array
from ..trajectory import run_into_trajectory, stop_rules



@njit(cache=True)
def energy_excess(u, a, eta, law):
    """E - E_m at x = 0 (eq. ``nonlin-energy``), the potential part without cancellation."""
    return 0.5 * (a * a + (u + a) * (u + a)) + bregman(eta, law)


@njit(cache=True)
def run_power_events(
    x0, u, a, eta, law, max_events, t_max, e_stop,
    out_t, out_tau, out_u, out_a, out_eta, out_e, out_kind,
):
    """Advance (x0, u, a, eta) from t = 0 and record every event, as :func:`bounce.exact.events.run_events`.

    Returns ``(n_events, stop_reason, t_end)``; stop reasons index STOP_NAMES.
    """
    gamma = law[L_GAMMA]
    X = np.empty(DEGREE_LONG + 2)
    P = np.empty(DEGREE_LONG + 2)
    Q = np.empty(DEGREE_LONG + 2)
    t_hi = 0.0
    t_lo = 0.0
    n = 0
    stop = STOP_EVENTS
    sticky = False
    kind = -1  # the last recorded event's kind (none yet)
    if x0 == 0.0 and u == 0.0 and at_rest_is_sticky(a, eta, law):
        sticky = True
        record_event(0, 0.0, 0.0, STICKY_START, u, a, eta, energy_excess(u, a, eta, law),
                     out_t, out_tau, out_u, out_a, out_eta, out_e, out_kind)
        n = 1
    while n < max_events:
        t_limit = t_max - (t_hi + t_lo)
        if sticky:
            status, tau, a, eta = sticky_phase(a, eta, t_limit, law, X, P, Q, False)
            if status != FOUND:
                stop = (STOP_STICKY_FOREVER if status == NEVER else STOP_TIME if status == HORIZON
                        else STOP_SLOW_CROSSING if status == SLOW_CROSSING else STOP_FAILED)
                break
            kind = DETACH
            x0 = 0.0
            u = 0.0
            sticky = False
        else:
            status = HANDOVER
            if x0 == 0.0 and u > 0.0:
                status, tau, v, scale, eta_t, xid_t, acc, jerk = short_flight(u, a, eta, law, X, P, Q)
                if status == FOUND and tau > t_limit:
                    stop = STOP_TIME
                    break
            if status == HANDOVER:
                # right after a detach F = 0 to the polish's rounding (its sign there is noise, which
                # at_rest_is_sticky could read as F < 0 and restart a zero-length sticky phase, found
                # by test_sticky_records_follow_the_rules): the mass leaves iff F' > 0 (eq. cond_di_distacco)
                lifting = False
                if kind == DETACH:
                    _, Fp, _, noise_Fp = floor_force(a, eta, law)
                    lifting = Fp > noise_Fp
                status, tau, v, scale, eta_t, xid_t, acc, jerk = first_contact(x0, u, a, eta, t_limit, law, X, P, Q,
                                                                               lifting)
                if status == SLOW_CROSSING:
                    stop = STOP_SLOW_CROSSING
                    break
                if status != FOUND and status != AT_REST:
                    stop = STOP_TIME if status == HORIZON else STOP_FAILED
                    break
            if status == AT_REST:
                # after a tangential detach the mass stays (series.sticky docstring): a sticky start
                kind, tau = STICKY_START, 0.0
            else:
                x0 = 0.0
                kind, u, a, eta = contact(v, acc, jerk, scale, u, a, gamma, tau, eta_t, xid_t)  # the shared rule
            sticky = kind == STICKY_START
        t_hi, t_lo = compensated_add(t_hi, t_lo, tau)
        record_event(n, t_hi + t_lo, tau, kind, u, a, eta, energy_excess(u, a, eta, law),
                     out_t, out_tau, out_u, out_a, out_eta, out_e, out_kind)
        n += 1
        if out_e[n - 1] < e_stop:
            stop = STOP_ENERGY
            break
    return n, stop, t_hi + t_lo


def simulate_power(params, spring, initial, max_events: int = 1000, t_max: float = math.inf,
                   energy_stop: float = 0.0):
    """Simulate the power-law spring ``spring`` (a :class:`bounce.springs.power.PowerSpring`, or the
    linear law as rho = 1, a = b = 0: the law's ``series_coefficients``) inside its supported domain
    (:func:`bounce.model.check_supported`, refused up front otherwise).

    ``initial``: a :class:`bounce.model.State`, or :class:`bounce.model.Deviations` whose
    eta is xi - xi_eq of this law.  Returns a :class:`bounce.trajectory.Trajectory`
    with eta = xi - xi_eq and energy_excess = E - E_m of eq. ``nonlin-energy``.
    Exact to rounding: series flights with rigorous tails and a root finder that
    cannot skip an impact (:mod:`bounce.series.flight`).
    """
    from ..model import Deviations, InputError, Parameters, State, check_supported
    from ..springs import LINEAR

    max_events, t_max, energy_stop = stop_rules(max_events, t_max, energy_stop)
    if params.spring not in (spring, LINEAR):
        raise InputError(f"spring must be the law of params ({params.spring!r}) or given with linear params, got {spring!r}")
    law = law_array(*spring.series_coefficients(), params.mu, params.gamma)
    xi_eq = float(law[L_XI_EQ])
    if isinstance(initial, State):
        x, u, a = initial.x, initial.xdot, 0.5 * (initial.ydot - initial.xdot)
        eta = 0.5 * ((initial.y - initial.x) - 1.0) - xi_eq  # xi - xi_eq, one rounding
    elif isinstance(initial, Deviations):
        x, u, a, eta = initial.x, initial.xdot, initial.xidot, initial.eta
    else:
        raise InputError(f"initial must be a State or Deviations, got {type(initial).__name__}")
    # the domain of the law (bounce.springs.power), the same check and message as the CLI's
    check_supported(Parameters(params.gamma, params.mu, spring), Deviations(x, u, a, eta), t_max)
    return run_into_trajectory(
        lambda *buffers: run_power_events(x, u, a, eta, law, max_events, t_max, energy_stop, *buffers),
        params, initial, (max_events, t_max, energy_stop), "power-law root finder",
        spring.attrs())


__all__ = ["energy_excess", "run_power_events", "simulate_power"]

"""The dimer gas against the independent mpmath reference (tests/gas/gas_reference.py, 50 digits).

Two- and three-grain columns and rings, damping mu = 0, 0.05, 0.1, 0.5, 0.9 and the over-damped 2,
the first 50 events of each.  One event at a time, as the
single ball's tests/test_reference.py does: the reference restarts from the engine's float64 state
after event n-1 (converted exactly) and finds the next event with its own closed forms and root
search; the engine's event n must be the same contact, its time and the state of every grain after
it equal to the reference's to

    1e-13 relative (time: of the event's duration; positions: of max |x| + 1; velocities x', xi': of
    their largest magnitude; eta: of that or max |eta|)

plus the float64 floor of the comparison itself: the reported times are rounded (an ulp of t each),
and a pair's gap is a difference of positions, known to ~eps max |x| (the engine's rounding rule,
:mod:`bounce.gas.dimer`), which moves a contact approached at speed w by ~8 eps max |x| / w and the
state after it by that time its rates (velocities for x and eta, accelerations <= gamma +
(1 + 2 mu) max amplitude for x' and xi', the springs' amplitudes sqrt(xi^2 + xi'^2) never growing
between events).  The test prints the largest relative errors without the floor (``pytest -s``; the
time's beyond the rounding of the reported times).  One-step comparisons keep the check at rounding level where whole trajectories
are chaotic (the paper's drop loses a digit every few impacts).
"""

from __future__ import annotations

import numpy as np
import pytest
from mpmath import mpf

import gas_reference as R
from bounce.gas import GasParameters, GasState, simulate_gas

EPS = 2.0**-52
FIELDS = ("x", "xdot", "xidot", "eta")
EVENTS = 50

CASES = {
    "column-2": (GasParameters(2, "column", 0.01, 0.1), GasState([1.0, 2.6], [0.0, 0.1], [0.0, 0.05], [0.0, 0.0])),
    "column-3": (GasParameters(3, "column", 0.01, 0.5),
                 GasState([1.0, 2.6, 4.2], [0.3, 0.1, -0.2], [0.0, 0.05, -0.1], [0.0, 0.01, 0.1])),
    "column-3-overdamped": (GasParameters(3, "column", 0.02, 2.0),
                            GasState([1.0, 2.6, 4.2], [0.3, 0.1, -0.2], [0.0, 0.05, -0.1], [0.0, 0.01, 0.1])),
    "column-2-undamped": (GasParameters(2, "column", 0.01, 0.0),
                          GasState([0.8, 2.3], [0.05, -0.05], [0.02, -0.03], [0.03, 0.0])),
    "ring-2": (GasParameters(2, "ring", 0.0, 0.1, 5.0), GasState([0.5, 2.5], [0.2, -0.2], [0.0, 0.05], [0.1, 0.0])),
    "ring-3": (GasParameters(3, "ring", 0.0, 0.05, 7.0),
               GasState([0.5, 2.5, 4.6], [0.2, -0.1, 0.05], [0.0, 0.05, -0.02], [0.1, 0.0, 0.02])),
    "ring-3-undamped": (GasParameters(3, "ring", 0.0, 0.0, 6.5),
                        GasState([0.5, 2.5, 4.6], [0.2, -0.1, 0.05], [0.0, 0.05, -0.02], [0.1, 0.0, 0.02])),
    "ring-3-moving": (GasParameters(3, "ring", 0.0, 0.9, 8.0),
                      GasState([0.5, 2.5, 4.6], [0.3, 0.25, 0.1], [0.0, 0.05, -0.02], [0.1, 0.0, 0.02])),
}

def one_step_errors(p, state):
    """Per event: (error / tolerance) of the time and of each field, and the plain relative errors."""
    res = simulate_gas(p, state, max_events=EVENTS, snapshot_every=1)
    assert res.stop_reason == "max_events", res.message
    prev = np.array(state.deviations(p.gamma))
    t_prev = 0.0
    ratios, plain = [], []
    for n in range(len(res)):
        ref = R.Gas.from_deviations(p.geometry, p.gamma, p.mu, p.ell, *prev, t=t_prev)
        slot, tau, speed = ref.step()
        assert slot == (res.pair[n] if res.pair[n] >= 0 else p.n - 1), f"event {n}: contact {res.pair[n]} vs {slot}"
        exact = ref.deviations()
        dev = np.array([[float(v) for v in d] for d in exact]).T  # (field, grain)
        snap = np.array([res.snapshots[k][n] for k in FIELDS])
        vel = np.max(np.abs(dev[1:3]))
        # the springs' amplitudes never grow between events: those after event n-1 bound them up to the contact
        amp = max(np.max(np.hypot(dev[3] - p.gamma, dev[2])), np.max(np.hypot(prev[3] - p.gamma, prev[2])))
        wrap = p.ell or 0.0
        positions = np.max(np.abs(dev[0])) + 1.0
        dt_floor = 8 * EPS * (2 * positions + 2 * np.max(np.abs(dev[3])) + wrap) / float(speed)
        acc = p.gamma + (1 + 2 * p.mu) * amp
        scales = np.array([positions, vel, vel, max(vel, np.max(np.abs(dev[3])))])
        floors = np.array([vel, acc, acc, vel]) * dt_floor
        errs = np.array([max(float(abs(mpf(snap[f][k]) - exact[k][f])) for k in range(p.n)) for f in range(4)])
        err_t = float(abs(mpf(res.t[n]) - ref.t))
        tol_t = 1e-13 * float(tau) + np.spacing(res.t[n]) + np.spacing(t_prev) + dt_floor
        ratios.append(np.concatenate([[err_t / tol_t], errs / (1e-13 * scales + floors)]))
        rounding = np.spacing(res.t[n]) + np.spacing(t_prev)
        plain.append(np.concatenate([[max(err_t - rounding, 0.0) / float(tau)], errs / scales]))
        prev, t_prev = snap, res.t[n]
    return np.array(ratios), np.array(plain)


@pytest.mark.parametrize("name", sorted(CASES))
def test_events_match_the_mpmath_reference(name):
    p, state = CASES[name]
    ratios, plain = one_step_errors(p, state)
    print(f"\n{name}: largest relative errors (t, x, xdot, xidot, eta): "
          + ", ".join(f"{v:.1e}" for v in plain.max(axis=0)))
    worst = np.unravel_index(np.argmax(ratios), ratios.shape)
    assert ratios.max() <= 1.0, f"event {worst[0]}, field {('t',) + FIELDS}[{worst[1]}]: {ratios[worst]:.3g} x tol"

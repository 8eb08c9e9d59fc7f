"""Constructed shallow dips of a pair's gap are not skipped (bounce.gas.dimer's search, eq. (G)).

Two grains on a ring far longer than they are (the seam plays no part).  The gap between them is
built backwards with the mpmath reference from the bottom of a dip: at time T the gap is -delta with
zero velocity and curvature gap'' = s + 2 mu s' = A > 0 (s = xi_0 + xi_1), so before T it entered the
dip, crossing zero at about T - sqrt(2 delta / A).  The state a time T earlier, rounded to doubles, is
the start.  A draw is kept when the reference, from those doubles, finds its first contact inside the
dip and the dip is 64 times deeper than the gap's rounding level (8 eps of the positions).  The
engine's first event must be that contact: not the seam, not a later one (a skipped dip), at the
reference's time to 1e-12 relative plus the floor of tests/gas/test_gas_reference.py; and the lower bound
the engine may queue the pair's prediction at (pending, its search deferred) must precede that contact.
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from mpmath import mp, mpf

import gas_reference as R
from bounce.gas import GasParameters, GasRun, GasState, simulate_gas
from bounce.gas.dimer import _contact_lower_bound, _lazy_key, _pair_gap, _pair_limits

EPS = 2.0**-52
ELL = 40.0


@st.composite
def dips(draw):
    mu = draw(st.one_of(st.just(0.0), st.floats(0.0, 0.9)))
    A = draw(st.floats(-3.0, 0.0).map(lambda e: 10.0**e)) * 0.1
    delta = draw(st.floats(-12.0, -3.0).map(lambda e: 10.0**e))
    T = draw(st.floats(0.05, 3.0))
    sd = draw(st.floats(-0.15, 0.15))  # s' at the bottom
    split = draw(st.floats(0.2, 0.8))  # how s, s' divide between the grains
    psid0 = draw(st.floats(-0.2, 0.2))
    with mp.workdps(R.DPS):
        s = mpf(A) - 2 * mpf(mu) * mpf(sd)  # gap'' = s + 2 mu s' = A
        xi = [s * mpf(split), s * (1 - mpf(split))]
        xid = [mpf(sd) * mpf(split), mpf(sd) * (1 - mpf(split))]
        psid = [mpf(psid0), mpf(psid0) + mpf(sd)]  # gap' = Dpsi' - s' = 0
        psi0 = mpf(1)
        # x_1 - y_0 = (psi_1 - xi_1) - (psi_0 + xi_0 + 1) = -delta
        psi1 = psi0 + xi[0] + 1 + xi[1] - mpf(delta)
        bottom = R.Gas("ring", 0, mu, ELL, [R.Grain(psi0, psid[0], xi[0], xid[0]), R.Grain(psi1, psid[1], xi[1], xid[1])])
        start = [bottom.at(k, mpf(-T)) for k in range(2)]
        psi, psidot, xis, xidots = (np.array([float(g[f]) for g in start]) for f in range(4))
        assume(np.all(xis**2 + xidots**2 < 0.2))
        state = GasState(psi, psidot, xis, xidots)
        x = psi - xis
        assume(x[1] - (psi[0] + xis[0] + 1.0) > 0.0)  # the doubles start with the pair apart
        ref = R.Gas.from_deviations("ring", 0.0, mu, ELL, *state.deviations(0.0))
        found = ref.next_contact()
        assume(found is not None and found[0] == 0)
        tau = found[1]
        rounding = 8 * EPS * (abs(x[0]) + abs(x[1]) + 2.0)
        assume(float(delta) >= 64 * rounding)
        entry = T - math.sqrt(2 * delta / A)
        assume(tau < T and abs(float(tau) - entry) < 0.5 * (T - entry) + 1e-12)
        speed = -ref.function(0, 1, mpf(0), tau)[1]
    return GasParameters(2, "ring", 0.0, mu, ELL), state, float(tau), float(speed), T


@settings(deadline=None, max_examples=30, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(dips())
def test_shallow_dips_between_grains_are_not_skipped(case):
    p, state, tau, speed, T = case
    res = simulate_gas(p, state, max_events=1)
    assert len(res) == 1 and res.pair[0] == 0, f"first event {res.kind_names} at {res.pair}, expected the dip of pair 0"
    assert res.t[0] < T, f"skipped the dip: contact at {res.t[0]!r}, dip bottom at {T!r}"
    x = state.psi - state.xi
    floor = 8 * EPS * (2 * np.max(np.abs(x)) + 4.0) / speed
    assert abs(res.t[0] - tau) <= 1e-12 * tau + floor, (res.t[0], tau)


@settings(deadline=None, max_examples=30, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(dips())
def test_the_pending_bound_precedes_the_dip(case):
    """The lower bound a pair may be queued pending at (the window's start, or the march's first certified
    step: bounce.gas.dimer._contact_lower_bound) lies before the reference's contact in the dip, and its
    lazy key before the engine's."""
    p, state, tau, _, _ = case
    run = GasRun(p, state, math.inf, 0)
    x0, w, sd, s0, _ = _pair_gap(run.g, 0, 1, False, ELL, 0.0)
    t_start, t_limit, _ = _pair_limits(x0, w, sd, s0, math.inf)
    bound = _contact_lower_bound(x0, w, sd, s0, t_start, t_limit, p.mu)
    assert 0.0 < bound <= tau, (bound, tau)
    found = simulate_gas(p, state, max_events=1).t[0]
    assert _lazy_key(0.0, bound) < found, (bound, found)


@settings(deadline=None, max_examples=30, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(dips())
def test_the_pending_bound_after_a_contact_precedes_the_next(case):
    """Right after the dip's contact (gap 0, separating) the bound of the pair's next prediction (the march's
    first step from the contact) precedes the pair's next contact, when the next event is that contact."""
    p, state, _, _, _ = case
    run = GasRun(p, state, math.inf, 0)
    run.step(1)
    t1 = float(run.clock[0])
    x0, w, sd, s0, noise = _pair_gap(run.g, 0, 1, False, ELL, 0.0)
    assert abs(x0) <= noise and w > 0.0
    t_start, t_limit, _ = _pair_limits(0.0, w, sd, s0, math.inf)
    bound = _contact_lower_bound(0.0, w, sd, s0, t_start, t_limit, p.mu)
    assert bound > 0.0
    rec, k, _ = run.step(1)
    assume(k == 1 and rec.pair[0] == 0)  # else the seam's event changed the grains first
    assert rec.t[0] - t1 >= bound * (1.0 - 1e-12), (rec.t[0] - t1, bound)

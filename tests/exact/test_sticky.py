"""Sticky phases (paper section 3 and eq. sticky-ic) against the mpmath reference.

The reference solves the sticky phase independently: w = y - y_eq obeys
w'' + mu w' + w/2 = 0 (eq. y-eq-sticky) in closed form, and the detach time is
the first return of F = y/2 + mu y' - gamma - 1/2 to zero with F' > 0 (eqs.
force-on-the-floor, cond_di_distacco), found by the reference's non-skipping
root search; "never" is proved there by the decaying envelope of F + 2 gamma.
"""

from __future__ import annotations

import numpy as np
import pytest
from mpmath import mp, mpf

from bounce.analysis import reference as R
from bounce import Deviations, Parameters, State, simulate
from bounce.sampling import sample_trajectory

STICKY_START, DETACH = 2, 3
REL_DETACH = 1e-12  # task tolerance on the detach time
REL_FLIGHT = 1e-14  # as for every flight in test_reference.py


def ref_detach(gamma, mu, initial):
    """Reference detach of the start state, fed the doubles bounce itself uses
    (the deviation variables of ``initial``, converted exactly)."""
    w0, yd0 = R.rest_state(gamma, initial.deviations(Parameters(gamma, mu)))
    return R.sticky_detach(gamma, mu, w0, yd0)


@pytest.mark.parametrize("mu", [0.0, 0.01, 0.1, 0.5, 1.0, 2.0])
@pytest.mark.parametrize("gamma", [1e-5, 0.01, 0.05, 0.1, 0.3])
def test_sticky_ic_detach_time(gamma, mu):
    """eq. sticky-ic with eps = 0: sticky_start at t = 0, then either a detach at
    the reference's first return of F to 0 (1e-12 relative, also y - y_eq and
    ydot there) or, if the reference proves F < 0 for ever, 'sticky_forever'.
    (gamma = mu = 0.01 is the paper's case, t_c = 5.23...)."""
    p = Parameters(gamma, mu)
    s0 = State.sticky_ic(p, eps=0.0)
    tr = simulate(p, s0, max_events=3)
    assert tr.kind[0] == STICKY_START and tr.t[0] == 0.0, tr.kind_names
    td, wd = ref_detach(gamma, mu, s0)
    if td is None:
        assert tr.stop_reason == "sticky_forever" and len(tr) == 1, (tr.kind_names, tr.t)
        return
    assert len(tr) >= 2 and tr.kind[1] == DETACH, (tr.kind_names, tr.stop_reason)
    with mp.workdps(R.DPS):
        err = abs((mpf(tr.t[1]) - td) / td)
        assert err <= REL_DETACH, f"detach at {tr.t[1]!r}, reference {mp.nstr(td, 20)}: rel err {float(err):.2e}"
        # state at detach: x = xdot = 0, y - y_eq = 2 eta, ydot = 2 xi'
        w, wdot = wd
        size = abs(w) + abs(wdot)
        assert abs(2 * mpf(tr.eta[1]) - w) <= REL_DETACH * size
        assert abs(2 * mpf(tr.xidot[1]) - wdot) <= REL_DETACH * size
        assert tr.xdot[1] == 0.0


def test_paper_sticky_ic_duration():
    """The paper reports t_c = 5.23... for the sticky event of eq. sticky-ic
    (gamma = mu = 0.01, the parameters of its other figures)."""
    p = Parameters(0.01, 0.01)
    tr = simulate(p, State.sticky_ic(p, eps=0.0), max_events=2)
    assert tr.kind_names == ("sticky_start", "detach")
    assert f"{tr.t[1]:.2f}" == "5.23"


EPSILONS = [1e-2, 1e-3, 1e-4, 1e-5, 1e-6]


def test_small_eps_has_impacts_and_converges_to_sticky_solution():
    """eps > 0 in eq. sticky-ic: only impacts on (0, t_c) -- no sticky phase,
    no grazing -- and y_eps -> y_s (the eps = 0 solution) as eps -> 0, in the
    norm of eq. L2-norm.  The paper (fig. sticky-convergence) finds the norm
    falling faster than linearly with eps, with more and more impacts; so the
    norm, norm/eps and 1/(number of impacts) must all decrease as eps does.

    y_s is the reference's sticky solution (exact); y_eps comes from bounce's
    dense sampler on a 2000-point grid (a quadrature of the norm whose error
    is far below its values here, 1e-1 .. 1e-9)."""
    gamma = mu = 0.01
    p = Parameters(gamma, mu)
    s0 = State.sticky_ic(p, eps=0.0)
    w0, yd0 = R.rest_state(gamma, s0.deviations(p))
    td, _ = R.sticky_detach(gamma, mu, w0, yd0)
    tc = float(td)
    grid = (np.arange(2000) + 0.5) * (tc / 2000)  # midpoint rule on (0, t_c)
    ys = np.array([float(v) for v in R.sticky_y_minus_yeq(gamma, mu, w0, yd0, grid)])
    norms, counts = [], []
    for eps in EPSILONS:
        tr = simulate(p, State.sticky_ic(p, eps=eps), max_events=1_000_000, t_max=tc)
        assert tr.stop_reason == "t_max"
        assert len(tr) >= 1 and (tr.kind == 0).all(), f"eps={eps}: {set(tr.kind_names)}"
        y = sample_trajectory(tr, grid)["y_minus_yeq"]
        norms.append(float(np.sqrt(np.mean((y - ys) ** 2))))
        counts.append(len(tr))
    norms, counts, eps = np.array(norms), np.array(counts), np.array(EPSILONS)
    msg = f"eps {EPSILONS}: norms {norms}, impacts {counts}"
    assert (np.diff(norms) < 0).all(), msg
    assert (np.diff(norms / eps) < 0).all(), msg
    assert (np.diff(counts) > 0).all(), msg


@pytest.mark.parametrize("rel", [0.1, 1e-3])
@pytest.mark.parametrize("gamma, mu", [(0.01, 0.01), (1e-5, 0.01), (0.1, 0.5), (0.01, 2.0), (0.2, 1.0)])
def test_infinitely_long_sticky_event(gamma, mu, rel):
    """The paper's remark: (x, xdot, y, ydot) = (0, 0, 1 + 2 gamma - 2 mu ydot, ydot)
    with ydot = 4 mu gamma - eps, small eps > 0, starts a sticky event that
    never ends: stop_reason 'sticky_forever', and the reference proves F < 0
    for ever.  eps = rel * 4 mu gamma (rel >= 1e-3 keeps F'(0) = -eps/2 far
    above the rounding of y ~ 1)."""
    eps = rel * 4 * mu * gamma
    ydot = 4 * mu * gamma - eps
    s = State(0.0, 0.0, 1.0 + 2 * gamma - 2 * mu * ydot, ydot)
    td, _ = ref_detach(gamma, mu, s)
    assert td is None, "reference: this state detaches"
    tr = simulate(Parameters(gamma, mu), s, max_events=5)
    assert tr.kind_names == ("sticky_start",) and tr.t[0] == 0.0
    assert tr.stop_reason == "sticky_forever"


@pytest.mark.parametrize("gamma, mu", [(0.01, 0.01), (0.1, 1.0), (1e-5, 2.0)])
def test_rest_on_floor_pressed_down_is_sticky(gamma, mu):
    """At rest on the floor with F < 0 (spring compressed below its static
    length, or the static equilibrium itself, F = -2 gamma): a sticky phase from
    t = 0; at the equilibrium it lasts for ever (eqs. equilibrium,
    force-on-the-floor)."""
    p = Parameters(gamma, mu)
    # static equilibrium: y = y_eq, F = -2 gamma < 0
    tr = simulate(p, Deviations(x=0.0, xdot=0.0, xidot=0.0, eta=0.0), max_events=3)
    assert tr.kind_names == ("sticky_start",) and tr.stop_reason == "sticky_forever"
    # pressed down further and moving: y = y_eq - 0.05, ydot = 0.01
    s = State(0.0, 0.0, p.y_eq - 0.05, 0.01)
    tr = simulate(p, s, max_events=3)
    assert tr.kind[0] == STICKY_START and tr.t[0] == 0.0
    td, _ = ref_detach(gamma, mu, s)
    if td is None:
        assert tr.stop_reason == "sticky_forever"
    else:
        assert tr.kind[1] == DETACH
        assert abs(tr.t[1] - float(td)) <= REL_DETACH * float(td)


@pytest.mark.parametrize("gamma, mu", [(0.01, 0.01), (0.1, 1.0), (1e-5, 2.0)])
def test_rest_on_floor_pulled_up_lifts_off(gamma, mu):
    """At rest on the floor with F > 0 (spring stretched: y = 1 + 2 gamma + 0.1,
    F = 0.05): the lower mass lifts off at once -- the first event is not
    sticky_start but the impact ending that flight, at the reference's time
    (1e-14 relative, as for any flight)."""
    p = Parameters(gamma, mu)
    s = State(0.0, 0.0, 1.0 + 2 * gamma + 0.1, 0.0)
    tr = simulate(p, s, max_events=3)
    assert tr.kind[0] != STICKY_START, tr.kind_names
    assert tr.kind[0] == 0, tr.kind_names
    d = s.deviations(p)  # the doubles bounce starts from
    tau, _ = R.flight_step(gamma, mu, d.x, d.xdot, d.xidot, d.eta)
    with mp.workdps(R.DPS):
        err = abs((mpf(tr.t[0]) - tau) / tau)
    assert err <= REL_FLIGHT, f"first impact at {tr.t[0]!r}, reference {mp.nstr(tau, 20)}: rel err {float(err):.2e}"


def test_stiff_overdamped_sticky_phase_is_proved_infinite():
    """Regression: mu = 27.6 (sticky oscillator strongly over-damped).  For mu >= sqrt(2) every sticky
    event is infinite (F - its envelope never returns to 0); the proof once ran out of steps because the
    curvature bounds of t = 0, dominated by the fast mode, were never refreshed."""
    p = Parameters(6.089470548226049e-08, 27.606486975110645)
    tr = simulate(p, Deviations(x=0.0, xdot=0.0, xidot=-0.04008136490537849, eta=2.2130114781993875),
                  max_events=5, t_max=1e4)
    assert tr.kind_names == ("sticky_start",) and tr.stop_reason == "sticky_forever"


def _sticky_cases():
    """Starts that stick: eq. sticky-ic (detach or not), pressed on the floor, the infinite sticky event, a
    trajectory sticking again after impacts (gamma = mu = 0.05), the stiff over-damped modes (mu >= 2)."""
    cases = []
    for gamma, mu in [(0.01, 0.01), (0.05, 0.05), (0.1, 0.5), (0.2, 1.0), (0.3, 1.5), (0.01, 2.0), (0.3, 3.0)]:
        p = Parameters(gamma, mu)
        cases += [(p, State.sticky_ic(p, eps=0.0), 3000), (p, State(0.0, 0.0, p.y_eq - 0.05, 0.01), 50)]
    p = Parameters(6.089470548226049e-08, 27.606486975110645)
    cases.append((p, Deviations(x=0.0, xdot=0.0, xidot=-0.04008136490537849, eta=2.2130114781993875), 5))
    return cases


@pytest.mark.parametrize("case", range(len(_sticky_cases())))
def test_sticky_tables_built_on_demand_give_the_same_bits(case):
    """run_events given empty tables for mu/sqrt(2) (as the contact Monte Carlo's compiled loop passes them)
    builds them at its first sticky phase: every record and the stop reason are the bits of the run given
    make_oscillator's tables (the t_max horizon included)."""
    import math

    from bounce.exact.events import SQRT2, run_events
    from bounce.exact.oscillator import make_oscillator

    p, start, events = _sticky_cases()[case]
    d = start.deviations(p)
    params, coefs = make_oscillator(p.mu)
    sparams, scoefs = make_oscillator(p.mu / SQRT2)
    for t_max in (math.inf, 3.0):
        runs = []
        for sp, sc in ((sparams, scoefs), (np.empty(0), np.empty((0, 0)))):
            out = [np.full(events, np.nan) for _ in range(6)] + [np.full(events, -1, dtype=np.int8)]
            n, stop, t_end = run_events(d.x, d.xdot, d.xidot, d.eta, p.gamma, params, coefs, sp, sc, events, t_max,
                                        0.0, *out)
            runs.append((n, stop, t_end, out))
        (n, stop, t_end, out), (n2, stop2, t_end2, out2) = runs
        assert (n, stop) == (n2, stop2) and np.array_equal(t_end, t_end2, equal_nan=True)
        assert out[6][0] == STICKY_START or STICKY_START in out[6][:n]
        for a, b in zip(out, out2):
            assert np.array_equal(a, b, equal_nan=True)

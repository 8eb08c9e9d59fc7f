"""bounce.gas.dimer through bounce.gas.simulate_gas: one grain is the single ball, runs chain, stops.

* The first test: one grain on the floor gives the records of :func:`bounce.simulate` bit for bit
  (the same search, hot path and impact rule; the clock is double-double where simulate's is
  compensated, so times may differ by an ulp);
* the records do not depend on how the run is cut into chunks, nor on the snapshot interval;
* every stop reason: max_events, t_max, no_more_events, overlap (the internal energy bound, naming the
  grain), and a relaxed over-damped collision (the grains end touching at relative rest: recorded as
  a grazing, the run goes on).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from bounce import Deviations, Parameters, simulate
from bounce.gas import GasParameters, GasState, simulate_gas
from bounce.gas.simulate import energy_excess

FIELDS = ("x", "xdot", "xidot", "eta")


@pytest.mark.parametrize("gamma, mu, psi, psidot, xi, xidot", [
    (0.01, 0.01, 6.0, 0.0, 0.0, 0.0),  # the paper's drop (fig. rigid-fall): a chaotic transient
    (1e-5, 2.0, 0.25, 0.0, 0.0, 0.0),  # the over-damped example
    (0.05, 0.0, 1.0, 0.1, 0.1, -0.1),  # no damping, an excited spring
    (0.2, 0.7, 0.5, -0.1, 0.05, 0.1),
])
def test_one_grain_reproduces_simulate(gamma, mu, psi, psidot, xi, xidot):
    """n = 1 in the column: the same events, kinds and post-impact states as bounce.simulate, bit for bit;
    times within one ulp."""
    events = 3000
    p = GasParameters(1, "column", gamma, mu)
    state = GasState([psi], [psidot], [xi], [xidot])
    res = simulate_gas(p, state, max_events=events, snapshot_every=1)
    x, u, a, eta = state.deviations(gamma)
    traj = simulate(Parameters(gamma, mu), Deviations(x[0], u[0], a[0], eta[0]), max_events=events)
    assert res.stop_reason == traj.stop_reason == "max_events"
    assert set(res.kind_names) == {"floor"} and set(traj.kind_names) == {"impact"}
    assert np.all(res.pair == -1)
    for gas_name, ball in (("xdot", traj.xdot), ("xidot", traj.xidot), ("eta", traj.eta)):
        assert np.array_equal(res.snapshots[gas_name][:, 0], ball), gas_name
    assert np.all(res.snapshots["x"][:, 0] == 0.0)
    assert np.all(np.abs(res.t - traj.t) <= np.spacing(traj.t))
    assert np.array_equal(res.speed, traj.xdot)  # the impact speed: x' -> -x' (eq. collision-rule-x1)


def _column(n=3, mu=0.1):
    p = GasParameters(n, "column", 0.01, mu)
    s = GasState(1.0 + 1.6 * np.arange(n), 0.05 * np.sin(np.arange(n)), 0.02 * np.cos(np.arange(n)),
                 np.zeros(n))
    return p, s


def _ring(n=6, mu=0.05, ell=10.0):
    p = GasParameters(n, "ring", 0.0, mu, ell)
    k = np.arange(n)
    v = 0.1 * np.sin(1.7 * k)
    s = GasState(0.3 + k * ell / n, v - v.mean(), 0.03 * np.sin(k), 0.02 * np.cos(2 * k))
    return p, s


@pytest.mark.parametrize("case", [_column, _ring])
def test_records_independent_of_chunks_and_snapshots(case):
    p, s = case()
    one = simulate_gas(p, s, max_events=3000, snapshot_every=1)
    cut = simulate_gas(p, s, max_events=3000, snapshot_every=7, chunk=113)
    for name in ("t", "kind", "pair", "speed"):
        assert np.array_equal(getattr(one, name), getattr(cut, name)), name
    assert np.array_equal(cut.snap_event, np.arange(6, 3000, 7))
    for name in FIELDS:
        assert np.array_equal(one.snapshots[name][cut.snap_event], cut.snapshots[name]), name
        assert np.array_equal(one.final[name], cut.final[name]), name
    assert np.array_equal(one.snapshots["x"][-1], one.final["x"])


def test_t_max_stop_and_final_state():
    p, s = _ring()
    full = simulate_gas(p, s, max_events=500)
    t_max = 0.5 * (full.t[200] + full.t[201])
    res = simulate_gas(p, s, max_events=500, t_max=t_max)
    assert res.stop_reason == "t_max" and res.t_end == t_max and len(res) == 201
    assert np.array_equal(res.t, full.t[:201])


def test_no_more_events():
    """Two relaxed grains on a ring at rest relative to each other never meet."""
    p = GasParameters(2, "ring", 0.0, 0.1, 5.0)
    s = GasState([0.5, 2.5], [0.1, 0.1], [0.0, 0.0], [0.0, 0.0])
    res = simulate_gas(p, s, max_events=10)
    assert res.stop_reason == "no_more_events" and len(res) == 0 and res.t_end == math.inf


def test_overlap_stop_names_the_grain():
    """A collision fast enough to give a grain internal energy (xi^2 + xi'^2)/2 >= 1/8 stops the run after it."""
    p = GasParameters(3, "ring", 0.0, 0.1, 20.0)
    s = GasState([0.5, 5.0, 12.0], [2.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0])
    res = simulate_gas(p, s, max_events=100)
    assert res.stop_reason == "overlap" and len(res) == 1 and res.pair[0] == 0
    assert res.message.startswith("grain 0: its internal energy")
    xi = res.final["eta"]
    assert xi[0] ** 2 + res.final["xidot"][0] ** 2 >= 0.25


@pytest.mark.parametrize("mu", [1.0, 1.5, 3.0])
def test_relaxed_overdamped_collision_is_a_grazing_then_nothing(mu):
    """mu >= 1: two grains whose springs are at rest collide head on; the gap then decays like |w| S(t)
    (S the oscillator's fundamental solution, > 0 for mu >= 1) towards zero without reaching it, the
    grains stopping touching each other; below float64's resolution after ~35/lam_slow time units the
    engine records a grazing (speed within rounding) and predicts no more contact."""
    p = GasParameters(2, "ring", 0.0, mu, 100.0)
    s = GasState([0.5, 3.0], [0.05, -0.05], [0.0, 0.0], [0.0, 0.0])
    res = simulate_gas(p, s, max_events=30, snapshot_every=1)
    assert res.stop_reason == "no_more_events", res.message
    assert res.kind_names == ("pair", "grazing") and res.t[0] == 15.0
    assert res.speed[1] < 1e-14 and res.t[1] > 15.0 + 30.0
    e = energy_excess(p, res.snapshots).sum(axis=1)
    assert e[1] <= e[0] and e[1] < 1e-28  # the relative motion is gone; momentum zero
    f = res.final
    assert f["x"][1] - (f["x"][0] + 1 + 2 * f["eta"][0]) >= 0.0


@pytest.mark.parametrize("geometry", ["ring", "column"])
def test_grains_starting_in_touch_at_relative_rest_are_relaxed(geometry):
    """Two grains with springs at rest start in touch (y_0 = x_1) at relative rest: their gap is 0 for all time (in
    the column until the floor), with gap' = gap'' = 0 and s = s' = 0, the contact bounce.gas.dimer calls relaxed
    (recorded as a grazing, no contact predicted) and not a sticky onset (that needs gap'' < 0).  The engine stopped
    at t = 0 with ``sticky`` (_predict queued the root finder's status -1 as T_STICKY before dimer_run's relaxed test
    could see it; found by issue 24's column-drop)."""
    p = (GasParameters(2, "ring", 0.0, 0.2, ell=10.0) if geometry == "ring"
         else GasParameters(2, "column", 0.01, 0.2))
    res = simulate_gas(p, GasState([1.0, 2.0], [0.0, 0.0], [0.0, 0.0], [0.0, 0.0]), max_events=10)
    if geometry == "ring":  # nothing ever moves
        assert len(res.t) == 0 and res.stop_reason == "no_more_events", res.message
        return
    # both grains fall together until grain 0 meets the floor at sqrt(2 x_0 / gamma); there its upper mass keeps
    # the speed -v while its spring, now compressing, decelerates it, and grain 1's lower mass falls on at -v:
    # pressed together at zero speed (gap'' = -2 mu v < 0), the pair analogue of eq. sticky-condition, which the
    # engine does not follow (a genuine stop, non-generic: the grains started in touch)
    t_floor = math.sqrt(2.0 / 0.01)
    assert res.kind_names[0] == "floor" and res.t[0] == pytest.approx(t_floor, rel=1e-14)
    assert res.stop_reason == "sticky" and res.t_end == pytest.approx(t_floor, rel=1e-14), res.message
    assert "pair 0" in res.message

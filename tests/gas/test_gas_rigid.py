"""bounce.gas.rigid: the rigid gas with a constant restitution, its collapse, the TC model.

* The three-grain collapse threshold r_c = 7 - 4 sqrt(3) (McNamara and Young): after a collision of
  the pair (0, 1) the alternating sequence maps the separation speed s and the other pair's approach
  speed a by (s, a) -> (r a, (1 + r) a / 2 - s), whose eigenvalues are real iff r <= r_c; from a ratio
  a / s above the repelling fixed point the sequence never ends and its times sum to a finite
  collapse time.  From a / s = 10 the engine reports a collapse below r_c and a finite sequence above,
  and bisection on r puts the switch at r_c to within 2%: float64 resolves the switch only to where
  a sequence that ends after ~pi / arg(lambda) collisions outlasts the ~27 it takes to shrink the
  relative speeds by 1e16 (bounce.gas.rigid's docstring).
* A ball on the floor with restitution r collapses at 2 v0 / (gamma (1 - r)), the clock stalling.
* Two grains: exact collision time and velocities (1 + r)/2 exchange; momentum on the ring.
* TC model: a collision within t_c of the grain's previous one is elastic; with the TC model the
  collapsing three-grain state does not collapse.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from bounce.gas import RigidParameters, RigidState, simulate_rigid

R_C = 7.0 - 4.0 * math.sqrt(3.0)


def three(r, t_c=0.0, s=0.1, a=1.0):
    """Three points on a long ring right after a collision of (0, 1): separating at s, pair (1, 2)
    approaching at a (the ratio a / s = 10 lies above the repelling fixed point for every r < r_c)."""
    p = RigidParameters(3, "ring", 0.0, r, ell=1e6, size=0.0, t_c=t_c)
    return simulate_rigid(p, RigidState([0.0, 0.0, 1.0], [-s, 0.0, -a]), max_events=100_000, t_max=1e3)


@pytest.mark.parametrize("factor", [0.1, 0.5, 0.9, 0.97])
def test_three_grains_collapse_below_r_c(factor):
    res = three(factor * R_C)
    assert res.stop_reason == "collapse", res.message
    assert res.collapse["grains"] == (0, 2) and res.collapse["collisions"] == len(res)
    assert "inelastic collapse" in res.message
    # the collisions alternate between the two pairs until the end
    assert np.all(res.pair[1:] != res.pair[:-1])


@pytest.mark.parametrize("factor", [1.02, 1.1, 2.0, 5.0, 13.0])
def test_three_grains_do_not_collapse_above_r_c(factor):
    res = three(min(factor * R_C, 1.0))
    assert res.stop_reason == "t_max", res.message
    assert len(res) < 30


def test_threshold_by_bisection_is_r_c():
    lo, hi = 0.5 * R_C, 2.0 * R_C
    for _ in range(20):
        mid = 0.5 * (lo + hi)
        if three(mid).stop_reason == "collapse":
            lo = mid
        else:
            hi = mid
    assert R_C <= hi and abs(lo - R_C) <= 0.02 * R_C, (lo, hi, R_C)


@pytest.mark.parametrize("drift", [0.0, 1.0, 1e3])
@pytest.mark.parametrize("factor", [0.5, 0.97])
def test_three_grains_collapse_whatever_their_common_velocity(factor, drift):
    """A collapse of the whole gas (every grain in the cluster) is a collapse in every Galilean frame, whether the
    float64 clock or the speed criterion ends it: the cooled-below-rounding test (GasRun._cooled) does not take it."""
    p = RigidParameters(3, "ring", 0.0, factor * R_C, ell=1e6, size=0.0)
    res = simulate_rigid(p, RigidState([0.0, 0.0, 1.0], [-0.1 + drift, drift, -1.0 + drift]), max_events=100_000,
                         t_max=1e3)
    assert res.stop_reason == "collapse", res.message


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_a_cooling_ring_is_not_reported_as_collapsed(seed):
    """Ten points on a ring at r = 0.95 (McNamara and Young: fewer than the ~88 grains a collapse needs) cool without
    end (Haff's law): their relative speeds fall to the rounding of the common velocity left by the rounding of the
    zero momentum, ~1e-16 of it, after ~700 collisions per grain, where the speed criterion fired and the run was
    reported as an inelastic collapse.  It is reported as cooled below rounding, with the collision intervals growing."""
    rng = np.random.default_rng(seed)
    x = np.sort(rng.uniform(0.0, 10.0, 10))
    v = rng.standard_normal(10)
    v -= v.mean()
    res = simulate_rigid(RigidParameters(10, "ring", 0.0, 0.95, ell=10.0, size=0.0), RigidState(x, v),
                         max_events=200_000)
    assert res.stop_reason == "cooled_below_rounding", res.message
    assert res.collapse is None and "not a collapse" in res.message
    assert np.diff(res.t)[-64:].sum() >= np.diff(res.t)[-128:-64].sum()


@pytest.mark.parametrize("r", [0.3, 0.5, 0.9])
def test_ball_on_the_floor_collapses_at_the_geometric_sum(r):
    gamma, v0 = 0.01, 1.0
    p = RigidParameters(1, "column", gamma, r)
    res = simulate_rigid(p, RigidState([0.0], [v0]), max_events=100_000)
    assert res.stop_reason == "collapse" and res.collapse["criterion"] == "clock"
    t_c = 2 * v0 / (gamma * (1 - r))
    assert abs(res.t_end - t_c) <= 8 * np.spacing(t_c)
    assert res.collapse["grains"] == (0, 0)


def test_two_grains_collide_exactly():
    r = 0.6
    p = RigidParameters(2, "ring", 0.0, r, ell=100.0, size=1.0)
    res = simulate_rigid(p, RigidState([0.0, 3.0], [0.5, -0.25]), max_events=1, snapshot_every=1)
    assert res.t[0] == 2.0 / 0.75 and res.pair[0] == 0 and res.speed[0] == 0.75
    v = res.snapshots["xdot"][0]
    assert np.allclose(v, [0.5 - 0.8 * 0.75, -0.25 + 0.8 * 0.75], rtol=0, atol=1e-16)
    assert v.sum() == 0.25


def test_ring_momentum_and_energy_loss():
    rng = np.random.default_rng(3)
    n, ell, r = 50, 100.0, 0.8
    x = np.sort(rng.uniform(0, ell - n, n)) + np.arange(n)
    v = rng.normal(0, 1, n)
    p = RigidParameters(n, "ring", 0.0, r, ell=ell, size=1.0)
    res = simulate_rigid(p, RigidState(x, v), max_events=5000, snapshot_every=100)
    assert res.stop_reason in ("max_events", "collapse")
    P = res.snapshots["xdot"].sum(axis=1)
    assert np.allclose(P, v.sum(), rtol=0, atol=1e-12)
    E = 0.5 * (res.snapshots["xdot"] ** 2).sum(axis=1)
    assert np.all(np.diff(E) <= 0.0)
    xs = res.snapshots["x"]
    assert np.all(xs[:, 1:] - xs[:, :-1] - 1.0 >= -1e-12) and np.all(xs[:, 0] + ell - xs[:, -1] - 1.0 >= -1e-12)


def test_tc_model_makes_quick_recollisions_elastic():
    res = three(0.5 * R_C, t_c=1e-3)
    assert res.stop_reason == "t_max", res.message
    assert "pair_elastic" in res.kind_names
    assert all(k in ("pair", "pair_elastic") for k in res.kind_names)
    # each elastic collision follows a collision of one of its grains within t_c
    last = np.full(3, -np.inf)
    for t, kind, pair in zip(res.t, res.kind_names, res.pair):
        i, j = pair, (pair + 1) % 3
        assert (kind == "pair_elastic") == (t - max(last[i], last[j]) < 1e-3)
        last[i] = last[j] = t

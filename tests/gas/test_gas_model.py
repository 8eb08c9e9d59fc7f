"""bounce.gas.model and the fronts' settings: bad input is one InputError line naming the parameter and
its allowed range; good input passes."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bounce.errors import InputError
from bounce.gas import GasParameters, GasState, RigidParameters, RigidState, simulate_gas, simulate_rigid

Z = np.zeros(2)


@pytest.mark.parametrize("kwargs, words", [
    (dict(n=0, geometry="column", gamma=0.01, mu=0.1), ["n must be an integer in [1,"]),
    (dict(n=2.5, geometry="column", gamma=0.01, mu=0.1), ["n must be an integer"]),
    (dict(n=True, geometry="column", gamma=0.01, mu=0.1), ["n must be an integer"]),
    (dict(n=2, geometry="box", gamma=0.01, mu=0.1), ["geometry must be one of column, ring"]),
    (dict(n=2, geometry="column", gamma=-0.01, mu=0.1), ["gamma must be in [1e-12, 0.5) for the column"]),
    (dict(n=2, geometry="column", gamma=0.0, mu=0.1), ["gamma must be in"]),
    (dict(n=2, geometry="column", gamma=math.nan, mu=0.1), ["gamma must be a finite number"]),
    (dict(n=2, geometry="column", gamma=0.01, mu=-1.0), ["mu must be in [0, 1e+08]"]),
    (dict(n=2, geometry="column", gamma=0.01, mu=0.1, ell=5.0), ["ell is the ring's circumference"]),
    (dict(n=2, geometry="ring", gamma=0.01, mu=0.1, ell=5.0), ["gamma must be 0 on the ring"]),
    (dict(n=1, geometry="ring", gamma=0.0, mu=0.1, ell=5.0), ["n must be >= 2 on the ring"]),
    (dict(n=2, geometry="ring", gamma=0.0, mu=0.1), ["ell (the ring's circumference) is required"]),
    (dict(n=2, geometry="ring", gamma=0.0, mu=0.1, ell=-1.0), ["ell must be > 0"]),
])
def test_bad_parameters(kwargs, words):
    with pytest.raises(InputError) as exc:
        GasParameters(**kwargs)
    message = str(exc.value)
    assert "\n" not in message and "allowed" in message
    for w in words:
        assert w in message, message


@pytest.mark.parametrize("kwargs, words", [
    (dict(r=1.5), ["r must be in [0, 1]"]),
    (dict(size=-1.0), ["size must be >= 0"]),
    (dict(t_c=-1.0), ["t_c must be >= 0", "turns the TC model off"]),
])
def test_bad_rigid_parameters(kwargs, words):
    base = dict(n=2, geometry="column", gamma=0.01, r=0.5)
    with pytest.raises(InputError) as exc:
        RigidParameters(**{**base, **kwargs})
    for w in words:
        assert w in str(exc.value)


COLUMN = GasParameters(2, "column", 0.01, 0.1)
RING = GasParameters(2, "ring", 0.0, 0.1, 3.0)


@pytest.mark.parametrize("params, state, words", [
    (COLUMN, GasState([1.0, 2.5], Z, Z, Z), None),
    (COLUMN, GasState([1.0, 1.5], Z, Z, Z), ["grains 0 and 1 overlap", "allowed range: [0, inf)"]),
    (COLUMN, GasState([-0.5, 2.5], Z, Z, Z), ["grain 0 starts below the floor"]),
    (COLUMN, GasState([0.0, 2.5], [-0.1, 0.0], Z, Z), ["grain 0 must be >= 0 when it starts on the floor"]),
    (COLUMN, GasState([1.0, 2.5], Z, [0.5, 0.0], Z), ["grain 0 has xi^2 + xi'^2 = 0.25", "[0, 0.25)"]),
    (COLUMN, GasState([1.0, 2.5, 4.0], np.zeros(3), np.zeros(3), np.zeros(3)), ["length n = 2"]),
    (COLUMN, lambda: GasState([1.0, math.inf], Z, Z, Z), ["psi[1] must be a finite number"]),
    (RING, GasState([0.5, 1.7], [0.1, -0.1], Z, Z), None),
    (RING, GasState([0.5, 2.6], Z, Z, Z), ["ell must be >=", "across the seam"]),
])
def test_states(params, state, words):
    if words is None:
        assert simulate_gas(params, state, max_events=3).stop_reason == "max_events"
        return
    with pytest.raises(InputError) as exc:
        simulate_gas(params, state() if callable(state) else state, max_events=3)
    message = str(exc.value)
    assert "\n" not in message
    for w in words:
        assert w in message, message


def test_state_arrays_of_different_lengths():
    with pytest.raises(InputError, match="must all have one entry per grain"):
        GasState([1.0, 2.0], [0.0], [0.0, 0.0], [0.0, 0.0])


def test_rigid_states():
    p = RigidParameters(2, "ring", 0.0, 0.5, ell=3.0, size=1.0)
    with pytest.raises(InputError, match="grains 0 and 1 overlap"):
        simulate_rigid(p, RigidState([0.0, 0.5], [0.0, 0.0]))
    with pytest.raises(InputError, match="across the seam"):
        simulate_rigid(p, RigidState([0.0, 2.5], [0.0, 0.0]))


@pytest.mark.parametrize("kwargs, words", [
    (dict(max_events=0), "max_events must be an integer in [1,"),
    (dict(t_max=0.0), "t_max must be > 0"),
    (dict(t_max=math.nan), "t_max must be > 0"),
    (dict(snapshot_every=-1), "snapshot_every must be an integer in [0,"),
    (dict(chunk=0), "chunk must be an integer in [1,"),
])
def test_run_settings(kwargs, words):
    with pytest.raises(InputError) as exc:
        simulate_gas(COLUMN, GasState([1.0, 2.5], Z, Z, Z), **kwargs)
    assert words in str(exc.value)

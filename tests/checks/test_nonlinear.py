"""Claim group nonlinear: the erratum rows of the Discussion can fail.  Each evaluates the printed form through a
function that takes the form under test; the corrected form (or an input where the printed form is true) flips the
verdict to reproduced."""

from __future__ import annotations

import functools
from pathlib import Path

from bounce.checks import nonlinear as nl
from bounce.checks.base import NOT_REPRODUCED, REPRODUCED
from bounce.claims_cli import group_spec
from bounce.scenes import scene_dataset

ROOT = Path(__file__).resolve().parents[2]
#: power-law drops as in tests/checks/test_claims.py: Hertz (b = 1/2) and a = 1, b = 0 (where the linear prefactor holds)
LAWS = {"hertz": (0.5, 0.5, -0.0464), "a1b0": (1.0, 0.0, -0.1)}


@functools.cache
def _scene(name: str):
    a, b, xi = LAWS[name]
    return scene_dataset({"gamma": 0.01, "mu": 0.3, "spring": {"law": "power", "rho": 1.0, "a": a, "b": b},
                          "initial": {"psi": xi + 0.02, "psidot": 0.0, "xi": xi, "xidot": 0.0},
                          "stop": {"events": 30000}, "keep": {"first": 10000, "log_samples": 1000}}, name)


def _spec(**changes):
    return group_spec("nonlinear", {"equilibrium_tolerance": 1e-2, **changes}, ROOT)


def _measured(*names):
    return nl.measure(_spec(), [_scene(n) for n in names])


def test_equilibrium_state_psi_is_xi_eq():
    """The printed state (psi = 0) is off the floor and lands; psi = xi = xi_eq is the simulator's rest."""
    m = _measured("hertz")
    printed = nl.printed_equilibrium_state(m, _spec())
    assert printed.verdict == NOT_REPRODUCED and "lands at" in printed.measured
    corrected = nl.equilibrium_state_row(m, _spec(), lambda xi_eq: (xi_eq, 0.0, xi_eq, 0.0), "psi = xi = xi_eq")
    assert corrected.verdict == REPRODUCED
    moved = nl.equilibrium_state_row(m, _spec(), lambda xi_eq: (xi_eq, 1e-9, xi_eq, 0.0), "psi' = 1e-9")
    assert moved.verdict == NOT_REPRODUCED  # every component counts


def test_same_asymptotic_law_only_for_b_zero():
    """tau_n ~ 3/(mu n) fails on the Hertz scene; 3/(mu |xi_eq|^b n) holds there; on the b = 0 scene alone (an input
    where the printed form is true) the printed form holds."""
    m = _measured("hertz", "a1b0")
    assert nl.printed_same_asymptotic_law(m, _spec()).verdict == NOT_REPRODUCED
    corrected = nl.same_law_row(m, _spec(), lambda sc: 3.0 / (sc.mu * abs(sc.xi_eq) ** sc.b), "3/(mu |xi_eq|^b)")
    assert corrected.verdict == REPRODUCED
    assert nl.printed_same_asymptotic_law(_measured("a1b0"), _spec()).verdict == REPRODUCED


def test_linear_limit_needs_rho_one():
    """a = b = 0 is the linear model for rho = 1 only, and for any rho after rescaling time by sqrt(rho)."""
    sp = _spec()
    assert nl.printed_linear_limit(None, sp).verdict == NOT_REPRODUCED
    rescaled = nl.linear_limit_row(sp, lambda g, mu, rho: (g / rho, mu / rho**0.5, rho**0.5), "time x sqrt(rho)")
    assert rescaled.verdict == REPRODUCED
    assert nl.printed_linear_limit(None, _spec(linear_limit_rho=[1.0])).verdict == REPRODUCED

"""Claim group static-equilibrium: the prefactor row's error budget does not read the deviation it judges."""

from __future__ import annotations

import functools
from pathlib import Path

from bounce.checks import static_equilibrium as se
from bounce.checks.base import NOT_REPRODUCED, REPRODUCED
from bounce.claims_cli import group_spec
from bounce.scenes import scene_dataset

ROOT = Path(__file__).resolve().parents[2]


@functools.cache
def _scene():
    """An under-damped drop (gamma = mu = 0.01, 3e4 impacts, thinned as the asymptotic scenes are)."""
    return scene_dataset({"gamma": 0.01, "mu": 0.01, "initial": {"psi": 6.0, "psidot": 0.0, "xi": 0.0, "xidot": 0.0},
                          "stop": {"events": 30000}, "keep": {"first": 3000, "log_samples": 1000}}, "ud")


def _prefactor_row(ds):
    sp = group_spec("static-equilibrium", {"asymptotic_min_events": 20000}, ROOT)
    return se.energy_prefactor_limit(se.measure(sp, [ds]), sp)["ud"]


def test_prefactor_tolerance_ignores_the_spring_share():
    """The spring's amplitude D ten times the records' (its share D^2/(2 Xdot^2) of E - E_m 100 times) widened the old
    tolerance, 1e-3 + max D^2/(2 Xdot^2) over the last decade, 100-fold; the extrapolation's error does not read D, so
    the row is unchanged.  E - E_m 1 % high (a prefactor 1 % off) is refuted."""
    true = _prefactor_row(_scene())
    assert true.verdict == REPRODUCED
    loud = _scene().copy(deep=True)
    loud["eta"], loud["ydot"] = 10.0 * loud["eta"], 10.0 * loud["ydot"]
    assert _prefactor_row(loud) == true
    high = _scene().copy(deep=True)
    high["energy_excess"] = 1.01 * high["energy_excess"]
    assert _prefactor_row(high).verdict == NOT_REPRODUCED

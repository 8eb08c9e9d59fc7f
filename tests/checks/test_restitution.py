"""Claim group restitution: the erratum row our-r-centre-of-mass (eq. our-r's small-u branch read in the rigid
ball's own speed) flips for the corrected coefficient, 1 - 2 mu u/(3 gamma)."""

from __future__ import annotations

import functools
from pathlib import Path

from bounce.checks import restitution
from bounce.checks.base import NOT_REPRODUCED, REPRODUCED
from bounce.claims_cli import group_spec
from bounce.scenes import scene_dataset

ROOT = Path(__file__).resolve().parents[2]
#: the scene rest of tests/checks/test_claims.py: fig. rest-coeff's drop, complete records
REST = {"gamma": 1e-5, "mu": 0.01, "initial": {"psi": 0.25, "psidot": 0.0, "xi": 0.0, "xidot": 0.0},
        "stop": {"events": 200000}}


@functools.cache
def _measured():
    sp = group_spec("restitution", {}, ROOT)
    return restitution.measure(sp, [scene_dataset(REST, "rest")]), sp


def test_small_u_branch_in_the_centre_of_mass_speed():
    m, sp = _measured()
    (printed,) = restitution.our_r_centre_of_mass(m, sp).values()
    (corrected,) = restitution.centre_of_mass_row(m, sp, 2.0, "corrected").values()
    assert printed.verdict == NOT_REPRODUCED and corrected.verdict == REPRODUCED

"""Claim group restitution (fig. rest-coeff): the contact time's second-order prediction."""

from __future__ import annotations

import functools
from pathlib import Path

from bounce.checks import restitution
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


def test_contact_time_follows_the_second_order_prediction():
    """The first contact lands with the spring at rest (a_1 = 0): its duration is 1 - delta + (2 + mu T_xi) delta^2
    to O(delta^3), far closer than 1 - delta alone."""
    m, _ = _measured()
    d = m.d
    pred = restitution.contact_prediction(d, m.xi0, m.v0)
    assert abs(m.xi0[0]) < 1e-12 and abs(m.v0[0]) < 1e-12
    assert abs(d["contact_ratio"][0] - pred[0]) < d["delta"][0] ** 3 * 10 < abs(d["contact_ratio"][0] - 1 + d["delta"][0])

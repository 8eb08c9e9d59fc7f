"""Claim group restitution: the erratum row our-r-centre-of-mass (eq. our-r's small-u branch read in the rigid
ball's own speed) flips for the corrected coefficient, 1 - 2 mu u/(3 gamma); our-r-band is refuted by a wrong
large-u branch (its band against the predicted edges); the contact time's second-order prediction."""

from __future__ import annotations

import functools
from pathlib import Path

import numpy as np

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


def _band(ds):
    sp = group_spec("restitution", {}, ROOT)
    (v,) = restitution.our_r_band(restitution.measure(sp, [ds]), sp).values()
    return v


def test_our_r_band_flips_when_the_large_u_branch_is_off():
    """Landing speeds of the double-impact bounces 0.3 % lower per bounce (r ~ 0.966 instead of 0.969, 1 - r 10 % off):
    the band reaches past its predicted upper edge gamma (ln(1/thr) + 1)/(2 mu) to the largest simulated speed, so
    the row is refuted, not left not checkable for want of bounces above the band."""
    ds = scene_dataset(REST, "rest")
    assert _band(ds).verdict == REPRODUCED
    xd = ds["xdot"].values.copy()
    m = np.arange(1, 60)
    xd[2 * m - 2] *= 0.997**m
    ds["xdot"] = (ds["xdot"].dims, xd, ds["xdot"].attrs)
    assert _band(ds).verdict == NOT_REPRODUCED


def test_contact_time_follows_the_second_order_prediction():
    """The first contact lands with the spring at rest (a_1 = 0): its duration is 1 - delta + (2 + mu T_xi) delta^2
    to O(delta^3), far closer than 1 - delta alone."""
    m, _ = _measured()
    d = m.d
    pred = restitution.contact_prediction(d, m.xi0, m.v0)
    assert abs(m.xi0[0]) < 1e-12 and abs(m.v0[0]) < 1e-12
    assert abs(d["contact_ratio"][0] - pred[0]) < d["delta"][0] ** 3 * 10 < abs(d["contact_ratio"][0] - 1 + d["delta"][0])

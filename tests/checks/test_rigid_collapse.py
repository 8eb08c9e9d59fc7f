"""Claim group rigid-collapse: the erratum row our-r-rigid-ball flips when the rigid ball's law is eq. our-r with
its small-u branch written in the ball's own speed (theory.our_r(com=True)): then tau_n ~ 3/(mu n), the dimer's."""

from __future__ import annotations

from pathlib import Path

from bounce.checks import rigid_collapse as rc
from bounce.checks.base import NOT_REPRODUCED, REPRODUCED
from bounce.claims_cli import group_spec
from bounce.scenes import scene_dataset

ROOT = Path(__file__).resolve().parents[2]
#: the drop of tests/checks/test_claims.py's scene ud (fig. rigid-fall's constants)
UD = {"gamma": 0.01, "mu": 0.01, "initial": {"psi": 6.0, "psidot": 0.0, "xi": 0.0, "xidot": 0.0},
      "stop": {"events": 30000}, "keep": {"first": 3000, "log_samples": 1000}}


def test_rigid_ball_with_the_corrected_branch_follows_the_dimer():
    sp = group_spec("rigid-collapse", {"onefifth_bounces": 30000, "our_r_bounces": 30000,
                                       "tail_window": [1000, 5000]}, ROOT)
    m = rc.measure(sp, [scene_dataset(UD, "ud")])
    assert rc.our_r_rigid_ball(m, sp).verdict == NOT_REPRODUCED
    d = m.d
    ball = rc.our_r_ball(d["t1"], d["v1"], d["gamma"], d["mu"], int(sp["our_r_bounces"]), com=True)
    assert rc.rigid_ball_row(m, sp, ball, "branch in the ball's speed").verdict == REPRODUCED

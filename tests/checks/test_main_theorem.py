"""Claim group main-theorem: the erratum row asymptotics-independent-of-mu can fail (its verdict flips for the
corrected form, tau_n ~ 3/(mu n), and for inputs doctored to have one lim n tau_n for every mu)."""

from __future__ import annotations

import functools
from pathlib import Path

from bounce.checks import main_theorem as mt
from bounce.checks.base import NOT_REPRODUCED, REPRODUCED
from bounce.claims_cli import group_spec
from bounce.scenes import scene_dataset

ROOT = Path(__file__).resolve().parents[2]


@functools.cache
def _scenes() -> tuple:
    """Two complete drops, mu = 0.3 and 2 (gamma = 1e-3, 2e4 impacts: a decade past the fits' n_min)."""
    return tuple(scene_dataset({"gamma": 1e-3, "mu": mu, "initial": {"psi": 0.25, "psidot": 0.0, "xi": 0.0, "xidot": 0.0},
                                "stop": {"events": 20000}}, name) for mu, name in ((0.3, "mu03"), (2.0, "mu2")))


def _spec():
    return group_spec("main-theorem", {"fit": {"n_min": 1000}}, ROOT)


def test_asymptotics_depend_on_mu():
    sp = _spec()
    m = mt.measure(sp, list(_scenes()))
    assert mt.asymptotics_independent_of_mu(m, sp).verdict == NOT_REPRODUCED
    assert mt.mu_dependence_row(m, sp, lambda mu: mu, "n tau_n mu -> 3").verdict == REPRODUCED


def test_printed_form_holds_where_lim_n_tau_n_is_one_number():
    """The mu = 2 drop's flights stretched by 20/3 (lim n tau_n = 10, the mu = 0.3 value): the printed form holds."""
    slow, fast = _scenes()
    doctored = fast.copy(deep=True)
    doctored["tau"] = doctored["tau"] * (20.0 / 3.0)
    sp = _spec()
    assert mt.asymptotics_independent_of_mu(mt.measure(sp, [slow, doctored]), sp).verdict == REPRODUCED
    assert mt.asymptotics_independent_of_mu(mt.measure(sp, [fast]), sp).verdict == "not checkable"  # one mu only

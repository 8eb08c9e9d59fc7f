"""Claim group errata: the erratum rows added from the re-read (notes/errata-reread.md) can fail: each row evaluates
the printed form through a function that takes the form under test, and the corrected form (or an input on which
the printed form is true) flips its verdict to reproduced."""

from __future__ import annotations

import math
from pathlib import Path

from bounce.checks import errata
from bounce.checks.base import NOT_REPRODUCED, REPRODUCED
from bounce.claims_cli import group_spec

ROOT = Path(__file__).resolve().parents[2]


def _spec(**changes):
    return group_spec("errata", {"asym_events": 20000, "asym_checkpoints": [1000, 10000], **changes}, ROOT)


def test_jump_k1_holds_from_k2_on():
    """eq. k-derivative_jump for every k fails at k = 1 ([x'] = 2 Xdot_n, [y'] = 0); from k = 2 on it holds."""
    m = errata.Measurements(_spec())  # the jump run only: no experiment is read
    assert errata.jump_k1(m, _spec()).verdict == NOT_REPRODUCED
    assert errata.jump_relation_row(m, (2, 3), "for k >= 2").verdict == REPRODUCED
    assert errata.jump_relation_row(m, (1,), "k = 1").verdict == NOT_REPRODUCED


def test_td_is_the_amplitude_efolding_time():
    """T_d = 1/mu as the energy's e-folding time fails; 1/(2 mu) (the energy's) passes, and so does nothing between."""
    mu = float(_spec()["rest_params"][1])
    assert errata.td_energy_efolding(None, _spec()).verdict == NOT_REPRODUCED
    assert errata.energy_efolding_row(mu, 1 / (2 * mu), "corrected").verdict == REPRODUCED
    assert errata.energy_efolding_row(mu, 1 / (2 * mu) * (1 + 1e-6), "1e-6 off").verdict == NOT_REPRODUCED


def test_upper_mass_oscillates_only_below_sqrt2():
    """'damped harmonic oscillations' for every mu fails at mu = 2; the corrected 'for mu < sqrt 2' passes; on
    under-damped contacts alone (an input where the printed form is true) the printed form passes."""
    sp = _spec()
    assert errata.main_thm_upper_mass(None, sp).verdict == NOT_REPRODUCED
    corrected = errata.upper_mass_row(None, sp, lambda mu: mu < math.sqrt(2), "mu < sqrt 2")
    assert corrected.verdict == REPRODUCED
    assert errata.main_thm_upper_mass(None, _spec(upper_mass_mu=[0.3, 1.0])).verdict == REPRODUCED


def test_z_constraint_checks_states_on_and_above_the_boundary():
    """eq. z-constraint's row takes half its states above the boundary (the draws in [-3 gamma, 3 gamma] all fall below
    it): x''(0) = (z - z_bnd)/2 is then tested off the boundary too, where a run 1 % heavier is caught."""
    v = errata.z_constraint(errata.Measurements(_spec()), _spec())
    assert v.verdict == REPRODUCED and "on the boundary: 4 states" in v.measured


def test_xi_lemma_typos_is_judged_on_the_run():
    """The typos' row reads the run (xi'(0) and the side of +-gamma xi tends to): the printed lines fail on the
    asymptotic run, and hold on its records written with xi of the opposite sign, started at xi'(0) = 0."""
    ds = errata.CHECK.experiment(errata.ASYMPTOTIC_RUN).dataset(_spec())
    assert errata.xi_lemma_typos(errata.Measurements(_spec(), [ds]), _spec()).verdict == NOT_REPRODUCED
    doctored = errata._xi_printed_convention(ds.copy(deep=True))
    assert errata.xi_lemma_typos(errata.Measurements(_spec(), [doctored]), _spec()).verdict == REPRODUCED

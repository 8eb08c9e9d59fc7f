"""Claim group sticky-lemmas: finitely-many-sticky-events shows a final count once a run's energy falls below E_min."""

from __future__ import annotations

from bounce.checks import registry
from bounce.checks import sticky_lemmas as sl
from bounce.checks.base import NOT_REPRODUCED, REPRODUCED
from checks.test_claims import spec, sweep


def test_count_is_final_after_the_fall_below_emin():
    """gamma = mu = 0.01: eq. sticky-ic falls below E_min at t ~ 280-345 (a horizon of 400 shows it; the config's 200
    does not); from then on Lemma Min-sticky-energy forbids any sticky onset.  A record with an onset after that event
    flips the row."""
    sp = spec("sticky-lemmas", sticky_ic_eps=[0.0, 1e-2], horizon=400.0, horizon_events=200000)
    fam = sl.sticky_ic_family({k: sp[k] for k in sl.FAMILY_KEYS})
    fam.attrs["experiment"] = "sticky-ic-family"
    assert (fam["first_below"].values > 0).all() and fam["sticky_count"].values.tolist() == [1, 0]
    mc = sweep("contact-monte-carlo")
    group = registry()["sticky-lemmas"]
    (v,) = group.verdicts(group.measure(sp, [mc, fam]), sp, only="finitely-many-sticky-events")
    assert v.verdict == REPRODUCED and "final for 2/2 runs" in v.measured, v.measured
    late = fam.copy(deep=True)
    late["last_sticky"].values[0] = late["first_below"].values[0] + 1  # an onset after the fall below E_min
    (v,) = group.verdicts(group.measure(sp, [mc, late]), sp, only="finitely-many-sticky-events")
    assert v.verdict == NOT_REPRODUCED


"""Claim group contact-non-generic: the classifier-switch row on the config's 25-point scan catches a window 22 x off."""

from __future__ import annotations

from pathlib import Path

from bounce.checks import contact_non_generic as ng
from bounce.checks import registry
from bounce.checks.base import NOT_REPRODUCED, REPRODUCED
from bounce.claims_cli import group_spec

ROOT = Path(__file__).resolve().parents[2]


def test_classifier_switch_flips_on_a_window_22_times_too_large(monkeypatch):
    """xn = 100 x 4 eps scale: v_tol (288 |x'''| xn^2)^(1/3) on the sticky line 100^(2/3) = 21.5 x larger; the
    25-point scan over 6 decades (spacing 1.8) sees contacts above the true window called slow."""
    sp = group_spec("contact-non-generic", {"scan_n": 25}, ROOT)
    group = registry()["contact-non-generic"]
    (true,) = group.verdicts(group.measure(sp, []), sp, only="classifier-switch")
    for name, value in ng._window_wide(100.0).items():
        monkeypatch.setattr(ng, name, value)
    (wide,) = group.verdicts(group.measure(sp, []), sp, only="classifier-switch")
    assert (true.verdict, wide.verdict) == (REPRODUCED, NOT_REPRODUCED), wide.measured

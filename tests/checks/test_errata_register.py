"""The errata register (bounce.checks._errata_register) and the erratum rows name each other: every erratum-kind claim
backs a register entry, every row an entry names exists and is an erratum; where the paper's LaTeX is at hand each
entry's printed text sits on its stated line and its label is a label of the source."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from bounce.checks import _errata_register as errata_register, registry
from bounce.checks.base import ERRATUM
from bounce.checks._errata_register import REGISTER, SEVERITIES, Erratum, entries_by_row, row_id

ROOT = Path(__file__).resolve().parents[2]
#: the LaTeX source does not ship; as tests/pipeline/test_report.py, look beside the clone or at BOUNCE_PAPER_TEX
TEX = Path(os.environ.get("BOUNCE_PAPER_TEX", ROOT.parent / "shared" / "paper" / "stopping-time-bouncing-ball.tex"))


def _claims() -> dict[str, str]:
    """group/claim-id -> kind, over every registered group."""
    return {f"{g.name}/{c.id}": c.kind for g in registry().values() for c in g.claims}


def unregistered_errata(register, claims) -> list[str]:
    """Erratum-kind claims no entry names."""
    named = {r for e in register for r in e.rows}
    return sorted(cid for cid, kind in claims.items() if kind == ERRATUM and cid not in named)


def dangling_rows(register, claims) -> list[str]:
    """Rows named by an entry that are not erratum-kind claims of any group."""
    return sorted(f"{e.id}: {r}" for e in register for r in e.rows if claims.get(r) != ERRATUM)


def test_every_erratum_row_backs_a_register_entry():
    assert unregistered_errata(REGISTER, _claims()) == []


def test_every_row_named_by_the_register_is_an_erratum_claim():
    assert dangling_rows(REGISTER, _claims()) == []


def test_the_two_checks_can_fail():
    """A register without the factor-2 entry leaves nonlinear/printed-dissipation-rate unregistered; an entry naming a
    missing row (or a paper-kind row) is dangling."""
    claims = _claims()
    short = tuple(e for e in REGISTER if e.id != "nonlin-dissipation-factor-2")
    assert unregistered_errata(short, claims) == ["nonlinear/printed-dissipation-rate"]
    ghost = Erratum("ghost", "x", "", 1, "p", "c", errata_register.TYPO, "e", ("errata/no-such-row", "errata/r-0969"))
    assert dangling_rows(REGISTER + (ghost,), claims) == ["ghost: errata/no-such-row", "ghost: errata/r-0969"]


def test_entries_are_well_formed():
    ids = [e.id for e in REGISTER]
    assert len(ids) == len(set(ids))
    for e in REGISTER:
        assert e.severity in SEVERITIES and e.line > 0 and len(e.rows) == len(set(e.rows))
        for text in (e.id, e.section, e.printed, e.correct, e.evidence):
            assert text.strip() and "\n" not in text, e
        assert e.printed != e.correct, e
    with pytest.raises(ValueError, match="severity"):
        Erratum("x", "s", "", 1, "p", "c", "harmless", "e")
    assert row_id("nonlinear/printed-dissipation-rate[hertz]") == "nonlinear/printed-dissipation-rate"
    assert [e.id for e in entries_by_row()["errata/xi-lemma-typos"]] == ["xi-lemma-limit-t-to-0",
                                                                         "xi-lemma-abs-xi-minus-gamma"]


def test_printed_text_sits_on_its_line():
    if not TEX.exists():
        pytest.skip(f"the paper's LaTeX source is not at {TEX} (it does not ship; set BOUNCE_PAPER_TEX)")
    source = TEX.read_text(encoding="latin-1")
    lines = source.splitlines()
    wrong = [f"{e.id}: l. {e.line} does not contain {e.printed!r}" for e in REGISTER
             if not (e.line <= len(lines) and e.printed in lines[e.line - 1])]
    assert not wrong, wrong
    missing = [f"{e.id}: {e.label}" for e in REGISTER if e.label and f"\\label{{{e.label}}}" not in source]
    assert not missing, missing

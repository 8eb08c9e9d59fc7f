"""The validation report: subjects in the config's declared order, every pipeline figure linked with the paper's
figure and caption it reproduces (the captions are data of the figure registry); errata counted once each, by the
register (bounce.checks._errata_register), and an erratum row outside it stops the report."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
import yaml

from bounce.checks.base import ERRATUM, NOT_CHECKABLE, NOT_REPRODUCED, PAPER, REPRODUCED, Verdict, verdict_dataset
from bounce.figures import FIGURES
from bounce.pipeline.catalogue import pipeline_figures
from bounce.pipeline.report import ReportError, ordered_subjects, write
from bounce.studies import registry as study_registry

STUDIES = study_registry()

ROOT = Path(__file__).resolve().parents[2]
CONFIG = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())


def test_captions_cover_every_stage_figure_and_name_paper_figures():
    assert all(study.caption.strip() for study in STUDIES.values())
    # the paper's LaTeX source does not ship; where a copy sits beside the clone (or BOUNCE_PAPER_TEX names one),
    # every reproduced figure's label is checked against it
    tex = Path(os.environ.get("BOUNCE_PAPER_TEX", ROOT.parent / "shared" / "paper" / "stopping-time-bouncing-ball.tex"))
    for name, fig in FIGURES.items():
        assert fig.caption.text.strip()
        if fig.caption.paper:  # a reproduced figure carries the paper's label, which is its own name
            assert fig.caption.paper == f"fig:{name}"
            if tex.exists():
                assert f"\\label{{fig:{name}}}" in tex.read_text(encoding="latin-1")
    paths = [f["path"] for f in pipeline_figures(CONFIG)]
    assert len(paths) == len(set(paths)) == len(FIGURES) + len(STUDIES) + len(CONFIG["sweeps"])


def test_subject_order_follows_the_config():
    subjects = {"thm:b": "B", "lem:a": "A", "fig:c": "C"}
    spec = {"subjects": dict(sorted(subjects.items())), "subject_order": list(subjects)}
    assert list(ordered_subjects(spec)) == ["thm:b", "lem:a", "fig:c"]
    with pytest.raises(ReportError, match="subject_order"):
        ordered_subjects({"subjects": subjects, "subject_order": ["thm:b"]})


def test_report_links_every_figure_in_order(tmp_path):
    res = tmp_path / "results"
    (res / "checks").mkdir(parents=True)
    v = Verdict("c", "ref", "comp", "e", "m", "t", REPRODUCED, claim_id="g/c", kind=PAPER, subject="lem:a")
    verdict_dataset([v], title="G").to_netcdf(res / "checks" / "g.nc")
    figures = pipeline_figures(CONFIG)
    for f in figures:
        (tmp_path / f["path"]).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / f["path"]).write_bytes(b"png")
    figures = [dict(f, path=str(tmp_path / f["path"])) for f in figures]
    md = res / "report" / "validation.md"
    subjects = ordered_subjects({"subjects": {"lem:a": "A", "thm:b": "B"}, "subject_order": ["thm:b", "lem:a"]})
    write([res / "checks" / "g.nc"], [res / "checks" / "fig-g.png"], md, subjects, {}, figures=figures)
    text = md.read_text()
    assert text.index("| B |") < text.index("| A |")
    for f in figures:
        link = f"../{Path(f['path']).parent.name}/{Path(f['path']).name}"
        assert f"]({link})" in text
        assert (md.parent / link).exists()
    assert "fig. rigid-fall of the paper" in text and "beyond the paper" in text


def _rows(*specs):
    """Verdict rows (claim_id, kind, verdict) for the report's counting functions."""
    return [Verdict("c", "ref", "comp", "e", "m", "t", verdict, claim_id=cid, kind=kind, subject="lem:a")
            for cid, kind, verdict in specs]


def test_errata_are_counted_once_by_the_register():
    """Four rows back one erratum (the factor 2 on four scenes) and one row two typos: the errata line counts
    distinct errata (with the rows beside), the other kinds count rows; severities add up to the register."""
    from bounce.checks._errata_register import REGISTER, SEVERITIES
    from bounce.pipeline.report import CheckReport, check_errata, kind_counts, kind_table_lines, severity_counts

    factor2 = [(f"nonlinear/printed-dissipation-rate[{s}]", ERRATUM, NOT_REPRODUCED) for s in "abcd"]
    rows = _rows(*factor2, ("errata/xi-lemma-typos", ERRATUM, NOT_REPRODUCED),
                 ("our-r/our-r-centre-of-mass[rest]", ERRATUM, NOT_CHECKABLE),
                 ("g/p1", PAPER, REPRODUCED), ("g/p2", PAPER, REPRODUCED))
    reports = [CheckReport("g", "G", "fig-g.png", rows, {})]
    check_errata(reports)
    counts = {k: (a, b, c) for k, a, b, c, _ in kind_counts(reports)}
    assert counts[ERRATUM] == (0, 3, 1)  # factor 2, the two xi-lemma typos: 3 errata not reproduced; our-r: 1
    assert counts[PAPER] == (2, 0, 0)
    sev = {s: rest for s, *rest in severity_counts(reports)}
    assert sev["all"] == [len(REGISTER), 4, 6] and sum(sev[s][0] for s in SEVERITIES) == len(REGISTER)
    assert sev["typo"][1:] == [2, 1]  # two entries, one row
    text = "\n".join(kind_table_lines(reports))
    assert "| errata (the text as printed; distinct errata, backed by 6 rows) | 0 | 3 | 1 | 6 |" in text
    assert f"{len(REGISTER)} distinct errata" in text


def test_an_unregistered_erratum_row_stops_the_report(tmp_path):
    from bounce.pipeline.report import CheckReport, check_errata

    reports = [CheckReport("g", "G", "fig-g.png", _rows(("g/new-erratum[s]", ERRATUM, NOT_REPRODUCED)), {})]
    with pytest.raises(ReportError, match="g/new-erratum.*errata register"):
        check_errata(reports)
    res = tmp_path / "results"
    (res / "checks").mkdir(parents=True)
    verdict_dataset(reports[0].verdicts, title="G").to_netcdf(res / "checks" / "g.nc")
    with pytest.raises(ReportError, match="errata register"):
        write([res / "checks" / "g.nc"], [res / "checks" / "fig-g.png"], res / "report" / "v.md", {"lem:a": "A"}, {})


def test_the_article_is_organised_by_the_paper_and_counts_statements(tmp_path, monkeypatch):
    """The Sphinx article: one page per section in the config's order, each statement once (its per-scene rows inside
    one entry, linked by an anchor), a paper subject judged by the paper's statements only, counts of statements."""
    from bounce.checks.base import BEYOND
    from bounce.pipeline import article
    from bounce.pipeline.report import kind_counts

    monkeypatch.chdir(tmp_path)
    (tmp_path / "checks").mkdir()
    rows = [Verdict("law holds", "eq. x", "comp", "e", f"m{s}", "t", REPRODUCED, claim_id=f"g/law[{s}]", kind=PAPER,
                    subject="lem:a") for s in "pq"]
    rows += [Verdict("ours", "eq. x", "comp", "e", "m", "t", NOT_REPRODUCED, claim_id="g/ours", kind=BEYOND,
                     subject="lem:a"),
             Verdict("other", "thm", "comp", "e", "m", "t", NOT_CHECKABLE, claim_id="g/other", kind=PAPER,
                     subject="thm:b")]
    verdict_dataset(rows, title="G").to_netcdf(tmp_path / "checks" / "g.nc")
    from matplotlib import pyplot as plt

    plt.figure(figsize=(2, 1)).savefig(tmp_path / "checks" / "fig-g.png")
    sections = [{"title": "First", "subjects": ["thm:b"]}, {"title": "Second", "subjects": ["lem:a"]}]
    choices = [{"text": "a choice", "values": [["checks.g.x", 20]]}]
    out = tmp_path / "article"
    article.write(["checks/g.nc"], ["checks/fig-g.png"], out, {"lem:a": "A", "thm:b": "B"}, sections, choices,
                  {"title": "T", "version": "v", "commit": "c"})
    index = (out / "index.html").read_text()
    assert index.index("First") < index.index("Second") and "checks.g.x" in index
    page = (out / "section-02.html").read_text()
    assert page.count('id="row-g-law"') == 1 and "mp" in page and "mq" in page
    assert "reproduced" in page and "row-g-ours" in page  # the subject: reproduced from its paper statement alone
    assert (out / "extension.html").read_text().count('id="row-g-ours"') == 1
    assert any(p.suffix == ".png" for p in (out / "_images").iterdir())
    counts = {k: (a, b, c, n) for k, a, b, c, n in kind_counts(article.load(
        [tmp_path / "checks" / "g.nc"], [tmp_path / "checks" / "fig-g.png"], tmp_path))}
    assert counts[PAPER] == (1, 0, 1, 3) and counts[BEYOND] == (0, 1, 0, 1)


def test_claims_that_test_one_statement_count_once():
    """Claims that declare one paper statement (Claim.statement: the drops, the atlas, the proof's identities) count
    once, by the overall verdict of all their rows; the rows are all counted beside."""
    from bounce.pipeline.report import CheckReport, kind_counts

    rows = [Verdict("c", "ref", "comp", "e", "m", "t", verdict, claim_id=cid, kind=PAPER, subject="lem:a",
                    statement=statement)
            for cid, verdict, statement in (("g/limit[ud]", REPRODUCED, "S"), ("g/limit[od]", REPRODUCED, "S"),
                                            ("g/atlas-limit", NOT_CHECKABLE, "S"), ("h/limit", NOT_REPRODUCED, "T"),
                                            ("g/other", REPRODUCED, ""))]
    counts = {k: (a, b, c, n) for k, a, b, c, n in kind_counts([CheckReport("g", "G", "", rows, {})])}
    assert counts[PAPER] == (2, 1, 0, 5)  # S reproduced (one part not checkable), T not, g/other reproduced

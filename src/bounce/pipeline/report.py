"""The validation report: every claim group's verdict rows -> results/report/validation.md (the article,
:mod:`bounce.pipeline.article`, is its browsable HTML organised by the paper).

ReScience-style: counts per kind of claim (paper statement, beyond the paper, self-test: rows;
errata: distinct errors of the text, each register entry of :mod:`bounce.checks._errata_register`
counted once however many rows back it, with the rows counted beside, and the errata by severity),
a one-line verdict per declared subject (theorem, lemma, figure, equation: config
``report.subjects``; not reproduced if any claim behind it is, see :func:`overall`), a table of
every claim (id, kind, claim, paper reference, what was computed, expected, measured, tolerance,
verdict, figure), a section per claim group with its figure and numbers, the errata (each register
entry once, with the rows that check it), and a link to
every other figure the pipeline makes with the paper's figure (and caption) it reproduces, or
"beyond the paper" (the captions are data of the figure registry, :mod:`bounce.figures`).

Subjects are listed in the order the config declares them (``subject_order``: the rule's JSON
slice sorts keys, so the order travels as a list).

Grouping and kinds are data stamped on each row by its claim (:class:`bounce.checks.base.Claim`),
never read from the rows' prose.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import xarray as xr

from ..checks.base import BEYOND, ERRATUM, IDENTITY, KINDS, PAPER, NOT_CHECKABLE, NOT_REPRODUCED, REPRODUCED, Verdict, read_verdicts
from ..checks._errata_register import REGISTER, SEVERITIES, entries_by_row, row_id

ORDER = {NOT_REPRODUCED: 0, NOT_CHECKABLE: 1, REPRODUCED: 2}
BADGE = {REPRODUCED: "reproduced", NOT_REPRODUCED: "**not reproduced**", NOT_CHECKABLE: "*not checkable*"}
KIND_TITLES = {"paper": "statements of the paper", "erratum": "errata (the text as printed)",
               "beyond": "beyond the paper", "self-test": "self-tests of the solver",
               "identity": "identities and definitions (no input could falsify them; never counted as reproduced)"}


@dataclass(frozen=True)
class CheckReport:
    name: str
    title: str
    figure: str  # path of the check's PNG, relative to the report ("": the group has no figure)
    verdicts: list[Verdict]
    numbers: dict


def _numbers(ds: xr.Dataset) -> dict:
    """Scalar results of a check (0-d variables) with their long names, for its section."""
    out = {}
    for name, var in ds.data_vars.items():
        if var.ndim == 0 and not name.startswith("verdict_"):
            out[var.attrs.get("long_name", name)] = float(var.values)
    return out


def load(check_files, figure_files, report_dir) -> list[CheckReport]:
    reports = []
    for nc, png in zip(check_files, figure_files, strict=True):
        with xr.open_dataset(nc) as ds:
            ds.load()
        reports.append(CheckReport(
            name=Path(nc).stem, title=ds.attrs.get("title", Path(nc).stem),
            figure=os.path.relpath(png, report_dir) if png else "", verdicts=read_verdicts(ds), numbers=_numbers(ds),
        ))
    return reports


def overall(verdicts) -> str:
    """not reproduced if any claim is; else reproduced if any is (saying how many parts are not
    checkable); else not checkable."""
    kinds = [v.verdict for v in verdicts]
    if NOT_REPRODUCED in kinds:
        return NOT_REPRODUCED
    if REPRODUCED in kinds:
        n = kinds.count(NOT_CHECKABLE)
        return REPRODUCED + (f" ({n} part{'s' * (n > 1)} not checkable)" if n else "")
    return NOT_CHECKABLE


def _badge(verdict: str) -> str:
    head = verdict.split(" (")[0]
    return BADGE[head] + verdict[len(head):]


class ReportError(ValueError):
    """A row names a subject the config does not declare."""


def rows(reports) -> list[Verdict]:
    return [v for r in reports for v in r.verdicts]


def check_subjects(reports, subjects: dict) -> None:
    """Every row's subject must be declared in config ``report.subjects`` (one message naming the claim)."""
    for v in rows(reports):
        if v.subject not in subjects:
            raise ReportError(f"claim {v.claim_id or v.claim!r} has subject {v.subject!r}, which config "
                              f"report.subjects does not declare (declared: {', '.join(subjects)})")


def check_errata(reports, register=REGISTER) -> None:
    """Every erratum row must back a register entry (:mod:`bounce.checks._errata_register`): errata are counted there."""
    named = entries_by_row(register)
    for v in rows(reports):
        if v.kind == ERRATUM and row_id(v.claim_id) not in named:
            raise ReportError(f"erratum row {v.claim_id or v.claim!r} backs no entry of the errata register "
                              "(bounce.checks._errata_register): add the erratum there, with this row")


def erratum_entries(reports, register=REGISTER) -> list[tuple]:
    """(entry, its rows in this run, their overall verdict or "" without rows) for every register entry, in order."""
    out = []
    for e in register:
        mine = [v for v in rows(reports) if v.kind == ERRATUM and row_id(v.claim_id) in e.rows]
        out.append((e, mine, overall(mine).split(" (")[0] if mine else ""))
    return out


def statement_id(claim_id: str) -> str:
    """``group/claim`` of a row ``group/claim[scene]``: the statement the row measures on one scene."""
    return claim_id.split("[")[0]


def statements(verdicts, counted: bool = False) -> dict:
    """claim id -> its rows (one per scene), in order of first appearance; ``counted``: grouped by the paper statement
    the claims declare they test together (:attr:`bounce.checks.base.Claim.statement`), else by claim."""
    out: dict = {}
    for v in verdicts:
        out.setdefault((counted and v.statement) or statement_id(v.claim_id), []).append(v)
    return out


def kind_counts(reports, register=REGISTER) -> list[tuple[str, int, int, int, int]]:
    """(kind, reproduced, not reproduced, not checkable, rows) per kind of claim, counting statements, not rows: a
    statement measured on several scenes, or by several claims that declare it (``Claim.statement``), counts once, by
    the overall verdict of its rows (:func:`overall`); errata
    count distinct register entries checked by rows in this run, each once by the overall verdict of its rows.  The
    last number is the rows behind the count."""
    all_rows = rows(reports)
    out = []
    for k in KINDS:
        if k == ERRATUM:
            verdicts = [verdict for _, mine, verdict in erratum_entries(reports, register) if mine]
        else:
            verdicts = [overall(rs).split(" (")[0]
                        for rs in statements((v for v in all_rows if v.kind == k), counted=True).values()]
        out.append((k, *(verdicts.count(w) for w in (REPRODUCED, NOT_REPRODUCED, NOT_CHECKABLE)),
                    sum(v.kind == k for v in all_rows)))
    return out


def errata_rows(reports) -> int:
    """The erratum rows of this run (per scene), which back the distinct errata of :func:`kind_counts`."""
    return sum(v.kind == ERRATUM for v in rows(reports))


def severity_counts(reports, register=REGISTER) -> list[tuple[str, int, int, int]]:
    """(severity, distinct errata, of them checked by rows in this run, those rows) per severity, then ("all", ...):
    a row backing two entries of one severity counts once there, and once in "all"."""
    entries = erratum_entries(reports, register)
    out = []
    for sev in (*SEVERITIES, "all"):
        mine = [(e, rs) for e, rs, _ in entries if sev in ("all", e.severity)]
        backing = {v.claim_id for _, rs in mine for v in rs}
        out.append((sev, len(mine), sum(bool(rs) for _, rs in mine), len(backing)))
    return out


def _kind_title(kind: str, n_rows: int) -> str:
    """The kind's title in the counts table; the errata's says that it counts distinct errata, and their rows."""
    if kind == ERRATUM:
        return KIND_TITLES[kind][:-1] + f"; distinct errata, backed by {n_rows} rows)"
    return KIND_TITLES[kind]


def kind_table_lines(reports, register=REGISTER) -> list[str]:
    """The markdown table of counts per kind (errata: distinct) and the errata by severity, for the report and the
    README (:mod:`bounce.pipeline.readme`)."""
    n_rows = errata_rows(reports)
    lines = ["Statements, not rows: a statement measured on several scenes, or by several claims, counts once, by the "
             "overall verdict of its rows (not reproduced if any row is); errata count distinct errors of the text.", "",
             "| kind of claim | reproduced | not reproduced | not checkable | rows |", "|---|---|---|---|---|"]
    for k, a, b, c, n in kind_counts(reports, register):
        if k == IDENTITY:  # consistency only: they hold or fail, and are never counted as reproduced
            a, b, c = f"({a} hold)", (f"**{b} fail**" if b else "0"), f"({c})"
        lines.append(f"| {_kind_title(k, n_rows)} | {a} | {b} | {c} | {n} |")
    sev = severity_counts(reports, register)
    total = sev[-1]
    lines += ["", f"Errata register (`src/bounce/checks/_errata_register.py`): {total[1]} distinct errata of the text as "
              f"printed, each counted once; {total[2]} of them checked by {total[3]} claim rows of this run, the other "
              f"{total[1] - total[2]} recorded from the text.", "",
              "| severity | distinct errata | checked by claim rows | rows |", "|---|---|---|---|"]
    lines += [f"| {s} | {n} | {checked} | {nr} |" for s, n, checked, nr in sev]
    return lines


def judging_kind(subject: str) -> str:
    """The kind of claim that sets a subject's verdict: ``beyond`` for a subject beyond the paper (id ``beyond:...``),
    else ``paper`` (the paper's statements; our readings, self-tests, identities and errata never set it)."""
    return BEYOND if subject.startswith("beyond:") else PAPER


def summaries(reports, subjects: dict) -> list[tuple[str, str, int]]:
    """(subject title, overall verdict, rows) for each declared subject, from the rows that declare it.

    A subject of the paper is judged by the paper's statements only (kind ``paper``): errata are left out (a typo in
    a proof says nothing about whether the statement holds; they are listed in their own section), and so are our
    own readings beyond the paper, the solver's self-tests and identities, which never set a paper subject's
    verdict.  A subject beyond the paper (id ``beyond:...``) is judged by its ``beyond`` rows.
    """
    out = []
    for sid, title in subjects.items():
        mine = [v for v in rows(reports) if v.subject == sid and v.kind == judging_kind(sid)]
        out.append((title, overall(mine), len(mine)))
    return out


def ordered_subjects(spec: dict) -> dict:
    """config ``report.subjects`` in the config's declared order (``spec["subject_order"]``, the keys as a list;
    absent: as given).  The order must name every subject once."""
    subjects = spec["subjects"]
    order = spec.get("subject_order") or list(subjects)
    if sorted(order) != sorted(subjects):
        raise ReportError(f"report subject_order {order} does not list the subjects {sorted(subjects)} once each")
    return {sid: subjects[sid] for sid in order}


def figure_entries(figures, report_dir) -> list[dict]:
    """The pipeline's figures (``bounce.pipeline.catalogue.pipeline_figures``) with their paths relative to the report."""
    return [dict(f, link=os.path.relpath(f["path"], report_dir)) for f in figures]


def _reproduces(f: dict) -> str:
    return f"fig. {f['paper'].removeprefix('fig:')} of the paper" if f["paper"] else "beyond the paper"


def _md_cell(text: str) -> str:
    return str(text).replace("|", "\\|").replace("\n", " ")


def markdown(reports, subjects, meta: dict, figures=()) -> str:
    lines = [f"# Validation report: {meta.get('title', '')}", ""]
    lines += [f"Generated by the pipeline (`snakemake --cores 2`) from {len(reports)} claim groups; "
              f"bounce {meta.get('version', '?')}, git commit `{meta.get('commit', '?')}`.", ""]
    all_rows = [v for r in reports for v in r.verdicts]
    counts = {k: sum(v.verdict == k for v in all_rows) for k in ORDER}
    lines += [f"**{counts[REPRODUCED]} reproduced, {counts[NOT_REPRODUCED]} not reproduced, "
              f"{counts[NOT_CHECKABLE]} not checkable** (of {len(all_rows)} claims).", ""]
    lines += kind_table_lines(reports)
    lines += ["", "## Overall verdict per figure and per theorem", "",
              "Each subject of the paper is judged by the paper's statements that declare it (our readings beyond the paper, "
              "self-tests, identities and errata are left out; errata are listed below); a subject beyond the paper by "
              "its rows beyond the paper.", "",
              "| subject | verdict | claims |", "|---|---|---|"]
    lines += [f"| {s} | {_badge(v)} | {n} |" for s, v, n in summaries(reports, subjects)]
    lines += ["", "## All claims", "",
              "| id | kind | claim | paper | computed | expected | measured | tolerance | verdict | figure |",
              "|---|---|---|---|---|---|---|---|---|---|"]
    for r in reports:
        for v in r.verdicts:
            lines.append("| " + " | ".join(_md_cell(c) for c in (
                f"`{v.claim_id}`", v.kind, v.claim, v.paper_ref, v.computed, v.expected, v.measured, v.tolerance)) +
                f" | {BADGE[v.verdict]} | {f'[{r.name}]({r.figure})' if r.figure else '-'} |")
    for r in reports:
        lines += ["", f"## {r.title} (`{r.name}`)", "", f"![{r.name}]({r.figure})" if r.figure else "(no figure)", ""]
        for v in r.verdicts:
            lines.append(f"* {BADGE[v.verdict]}: {v.claim} ({v.paper_ref}) - measured {v.measured}; "
                         f"expected {v.expected}; tolerance {v.tolerance}.")
        if r.numbers:
            lines += ["", "| quantity | value |", "|---|---|"]
            lines += [f"| {_md_cell(k)} | {val:.6g} |" for k, val in r.numbers.items()]
    lines += ["", "## Errata", "", "Every distinct erratum of the paper once (the register, "
              "`src/bounce/checks/_errata_register.py`; locations are lines of the LaTeX source), by severity, with the claim "
              "rows that check the printed form against the numerics or the algebra (not reproduced: the printed form "
              "is contradicted; each row gives the evidence):", ""]
    for e, mine, verdict in sorted(erratum_entries(reports), key=lambda t: SEVERITIES.index(t[0].severity)):
        checked = (f" Checked by {', '.join(f'`{v.claim_id}` ({v.verdict})' for v in mine)}: {_badge(verdict)}."
                   if mine else " Recorded from the text (no claim row).")
        lines.append(f"* **{e.id}** ({e.severity}; {e.section}{', ' + e.label if e.label else ''}, l. {e.line}): "
                     f"printed `{e.printed}`, correct `{e.correct}`. {e.evidence}.{checked}")
    lines += ["", "## Figures", "", "Every figure of the pipeline besides the claim groups' own (above), with the "
              "figure of the paper it reproduces and that figure's caption as printed, or what it shows when it is "
              "beyond the paper.", "", "| figure | reproduces | caption |", "|---|---|---|"]
    lines += [f"| [{_md_cell(f['name'])}]({f['link']}) | {_reproduces(f)} | {_md_cell(f['caption'])} |"
              for f in figures]
    return "\n".join(lines) + "\n"


def write(check_files, figure_files, out_md, subjects: dict, meta: dict, figures=()) -> None:
    """Write the markdown report (atomically); ``subjects``: config ``report.subjects`` (in the order to list them,
    :func:`ordered_subjects`); ``figures``: :func:`bounce.pipeline.catalogue.pipeline_figures`.  The browsable HTML is
    the article (:mod:`bounce.pipeline.article`)."""
    path = Path(out_md)
    reports = load(check_files, figure_files, path.parent)
    check_subjects(reports, subjects)
    check_errata(reports)
    text = markdown(reports, subjects, meta, figure_entries(figures, path.parent))
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.tmp")
    tmp.write_text(text)
    os.replace(tmp, path)

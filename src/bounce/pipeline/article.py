"""The replication article: the validation rows organised by the paper, built with Sphinx (MyST markdown) as HTML.

results/report/article/index.html, from the same inputs as the validation report (:mod:`bounce.pipeline.report`):

* front matter: what was run (bounce version and commit, Python and the numerical packages, cores, the CPU time
  of the pipeline's jobs from their benchmark files), counts per kind of claim (statements, not per-scene rows;
  errata as distinct errors of the register), the choices the paper leaves open (config ``report.choices``, each
  with the config values that make it), and links to every part;
* part I, the replication: one page per section of the paper (config ``report.sections``, in the paper's order),
  and on it, per subject (theorem, lemma, figure, equation), the paper's statements, one entry each with its
  per-scene measurements inside, what would have falsified it (:class:`bounce.checks.base.Falsifier`), the
  reproduced figures next to the paper's captions, and what differs and why (the known failures and the errata
  of the subject);
* part II, the errata: each distinct erratum once, by severity, linked to the rows that check it;
* part III, beyond the paper: our own readings and consequences (kind ``beyond``), the solver's self-tests and the
  identities, then the methods study's and the sweeps' figures with their captions.

Each row appears once, under the subject it declares; summary lines link to it (anchors ``row-<group>-<claim>``).
The sources are generated into ``<out>/_sources_md`` and Sphinx builds ``<out>`` from them in this process.
"""

from __future__ import annotations

import os
import platform
import re
import shutil
from collections import defaultdict
from dataclasses import replace
from pathlib import Path

from ..checks.base import BEYOND, ERRATUM, IDENTITY, NOT_CHECKABLE, NOT_REPRODUCED, REPRODUCED, SELF_TEST
from ..checks._errata_register import SEVERITIES
from .report import (KIND_TITLES, ReportError, check_errata, check_subjects, erratum_entries, kind_table_lines, load,
                     judging_kind, overall, rows, statement_id, statements)

BADGE = {REPRODUCED: "✅ reproduced", NOT_REPRODUCED: "❌ **not reproduced**", NOT_CHECKABLE: "➖ *not checkable*"}


#: the packages whose versions the front matter states
PACKAGES = ("numpy", "scipy", "numba", "mpmath", "sympy", "xarray", "netCDF4", "matplotlib", "snakemake", "sphinx")


def package_versions() -> dict:
    from importlib.metadata import version

    return {name: version(name) for name in PACKAGES}


def anchor(claim_id: str) -> str:
    return "row-" + re.sub(r"[^a-z0-9]+", "-", statement_id(claim_id).lower()).strip("-")


def subject_anchor(subject: str) -> str:
    return "subject-" + re.sub(r"[^a-z0-9]+", "-", subject.lower()).strip("-")


def _cell(text) -> str:
    return str(text).replace("|", "\\|").replace("\n", " ")


def _md(text) -> str:
    """Prose from a row, safe in MyST: no accidental roles, targets or markup of underscores and stars."""
    return str(text).replace("\\", "\\\\").replace("*", "\\*").replace("_", "\\_").replace("`", "'").replace("<", "&lt;")


def _claims_info() -> dict:
    """statement id -> (known failure, falsifier in words, why an identity) from the claim registry."""
    from ..checks import registry

    return {f"{g.name}/{c.id}": (c.known_failure, c.falsifier.what if c.falsifier else "", c.why_identity)
            for g in registry().values() for c in g.claims}


def _statement_block(sid: str, rs: list, info: dict) -> list[str]:
    first = rs[0]
    known, falsifier, why = info.get(sid, ("", "", ""))
    verdict = overall(rs)
    lines = [f"({anchor(sid)})=", f"#### {_md(first.claim)}", "",
             f"`{sid}` ({first.kind}; {_md(first.paper_ref)}): {BADGE[verdict.split(' (')[0]]}{verdict[len(verdict.split(' (')[0]):]}",
             "", f"- **computed**: {_md(first.computed)}", f"- **expected**: {_md(first.expected)}",
             f"- **tolerance**: {_md(first.tolerance)}"]
    if falsifier:
        lines.append(f"- **falsified by**: {_md(falsifier)} (the verdict flips: tests/checks/test_claims.py)")
    if why:
        lines.append(f"- **an identity**: {_md(why)}")
    if known:
        lines.append(f"- **what differs, and why**: {_md(known)}")
    if len(rs) == 1 and "[" not in first.claim_id:
        lines.append(f"- **measured**: {_md(first.measured)}")
    else:
        lines += ["", "| scene | measured | verdict |", "|---|---|---|"]
        lines += [f"| {_cell(v.claim_id[v.claim_id.index('[') + 1:-1] if '[' in v.claim_id else '-')} | "
                  f"{_cell(_md(v.measured))} | {BADGE[v.verdict]} |" for v in rs]
    return lines + [""]


def _figure(path: str, caption: str, here: Path) -> list[str]:
    rel = os.path.relpath(path, here)
    return [f"```{{figure}} {rel}", ":width: 100%", "", _md(caption), "```", ""]


def section_page(title: str, sids: list, subjects: dict, reports, figures: list, info: dict, here: Path) -> str:
    """One section of the paper: per subject, its paper statements (rows), the figures, what differs."""
    lines = [f"# {_md(title)}", ""]
    by_subject = defaultdict(list)
    for r in reports:
        for v in r.verdicts:
            by_subject[v.subject].append((r, v))
    for sid in sids:
        mine = by_subject.get(sid, [])
        kind = judging_kind(sid)
        stated = [v for _, v in mine if v.kind == kind]
        lines += [f"({subject_anchor(sid)})=", f"## {_md(subjects[sid])}", "",
                  f"Verdict of the subject, from its {'claims beyond the paper' if kind == BEYOND else 'statements of the paper'}: "
                  f"{BADGE[overall(stated).split(' (')[0]] if stated else 'no statement checked'}"
                  f"{overall(stated)[len(overall(stated).split(' (')[0]):] if stated else ''}.", ""]
        for stid, rs in statements(stated).items():
            lines += _statement_block(stid, rs, info)
        others = [v for _, v in mine if v.kind not in (kind, ERRATUM)]
        if others:
            lines += ["Also measured for this subject (beyond the paper, self-tests, identities): "
                      + ", ".join(f"[`{s}`](extension.md#{anchor(s)})" for s in statements(others)) + ".", ""]
        errata = statements(v for _, v in mine if v.kind == ERRATUM)
        if errata:
            lines += ["Errata of this subject (the text as printed): "
                      + ", ".join(f"[`{s}`](errata.md#{anchor(s)})" for s in errata) + ".", ""]
        paper_figs = [f for f in figures if f["paper"] and f["paper"].startswith(sid)]
        groups = list({r.name: r for r, _ in mine if r.figure}.values())
        if paper_figs or groups:
            lines += ["### Figures", ""]
        for f in paper_figs:
            lines += _figure(f["path"], f"{f['name']}, reproducing fig. {f['paper'].removeprefix('fig:')} of the paper, "
                             f"whose caption reads: {f['caption']}", here)
        for r in groups:
            lines += _figure(r.figure, f"The figure of claim group {r.name}: {r.title}", here)
    return "\n".join(lines) + "\n"


def errata_page(reports, info: dict) -> str:
    lines = ["# Errata of the paper", "",
             "Each distinct error of the text once (the register, `src/bounce/checks/_errata_register.py`; lines of the "
             "LaTeX source, sections numbered as LaTeX numbers them), by severity, with the rows that check the printed "
             "form against the numerics or the algebra.", ""]
    entries = sorted(erratum_entries(reports), key=lambda t: SEVERITIES.index(t[0].severity))
    for sev in SEVERITIES:
        mine = [t for t in entries if t[0].severity == sev]
        lines += [f"## {sev.capitalize()} ({len(mine)})", ""]
        for e, rs, verdict in mine:
            lines += [f"- **{_md(e.id)}** ({_md(e.section)}{', ' + _md(e.label) if e.label else ''}, l. {e.line}): "
                      f"printed `{e.printed}`, correct `{e.correct}`. {_md(e.evidence)}."
                      + (f" Checked by {', '.join(f'`{v.claim_id}` ({v.verdict})' for v in rs)}: {BADGE[verdict]}."
                         if rs else " Recorded from the text (no claim row).")]
        lines.append("")
    lines += ["## The rows that check errata", ""]
    for stid, rs in statements(v for v in rows(reports) if v.kind == ERRATUM).items():
        lines += _statement_block(stid, rs, info)
    return "\n".join(lines) + "\n"


def extension_page(reports, figures: list, here: Path, info: dict) -> str:
    lines = ["# Beyond the paper", "",
             "Our own readings and consequences of the paper's statements (they never set a paper subject's verdict), "
             "the solver's self-tests, the identities (statements no input could falsify, never counted as "
             "reproduced), then the figures of the methods study and of the parameter sweeps.", ""]
    for kind in (BEYOND, SELF_TEST, IDENTITY):
        mine = statements(v for v in rows(reports) if v.kind == kind and judging_kind(v.subject) != kind)
        lines += [f"## {KIND_TITLES[kind].capitalize()} ({len(mine)})", ""]
        for stid, rs in mine.items():
            lines += _statement_block(stid, rs, info)
    lines += ["## Figures of the methods study and the sweeps", ""]
    for f in figures:
        if not f["paper"]:
            lines += _figure(f["path"], f"{f['name']}: {f['caption']}", here)
    return "\n".join(lines) + "\n"


def index_page(reports, meta: dict, choices: list, page_names: list, beyond_pages: list, subject_pages: list,
               page_of: dict) -> str:
    """The front matter; ``subject_pages``: (subject, title, page) in order; ``page_of``: statement id -> page."""
    lines = [f"# {_md(meta.get('title', ''))}: a replication", "",
             "Every figure and number here was regenerated by `snakemake --cores 2` from the configuration; every row "
             "is a claim of the paper judged against a stated tolerance, and every row can fail (its falsifier is "
             "run by the tests).", "", "## What was run", "",
             f"- bounce {meta.get('version', '?')}, git commit `{meta.get('commit', '?')}`",
             f"- Python {platform.python_version()} on {platform.machine()}, {os.cpu_count()} cores; "
             + ", ".join(f"{k} {v}" for k, v in meta.get("packages", {}).items()),
             "- the pipeline's wall and CPU time, per rule: `python benchmarks/bench_pipeline.py` (the README quotes a run)",
             "",
             "## Counts", ""]
    lines += kind_table_lines(reports)
    lines += ["", "## Verdict per subject", "",
              "A subject of the paper is judged by the paper's statements that declare it (not reproduced if any is); "
              "our readings beyond it, self-tests, identities and errata never set it.", "",
              "| subject | verdict | statements |", "|---|---|---|"]
    for sid, title, page in subject_pages:
        stated = [v for v in rows(reports) if v.subject == sid and v.kind == judging_kind(sid)]
        verdict = overall(stated) if stated else "no statement checked"
        lines.append(f"| [{_cell(_md(title))}]({page}.md#{subject_anchor(sid)}) | {_cell(verdict)} | "
                     f"{len(statements(stated))} |")
    failing = {sid: rs for sid, rs in statements(v for v in rows(reports) if v.kind != ERRATUM).items()
               if overall(rs).startswith(NOT_REPRODUCED)}
    lines += ["", "## What does not hold", "",
              "Every statement (errata aside, which are listed in part II) with a row not reproduced, linked to its entry:",
              ""]
    lines += [f"- [`{sid}`]({page_of[sid]}.md#{anchor(sid)}): {_md(rs[0].claim)}" for sid, rs in failing.items()]
    lines += ["", "## Choices the paper leaves open", "",
              "What the paper does not state and this replication had to choose (each set in `config/config.yaml`):", ""]
    lines += [f"- {_md(c['text'])} (" + ", ".join(f"`{k}` = {v}" for k, v in c["values"]) + ")"
              for c in choices]
    lines += ["", "## Contents", "", "Part I, the replication, follows the paper's sections; part II lists the errata; "
              "part III what goes beyond the paper.", "",
              "```{toctree}", ":maxdepth: 2", ":caption: Part I: the paper, section by section", ""]
    lines += page_names
    lines += ["```", "", "```{toctree}", ":maxdepth: 2", ":caption: Part II: the errata", "", "errata", "```", "",
              "```{toctree}", ":maxdepth: 2", ":caption: Part III: beyond the paper", "", *beyond_pages, "extension",
              "```", ""]
    return "\n".join(lines) + "\n"


CONF = '''project = {title!r}
html_title = {title!r}
extensions = ["myst_parser"]
myst_heading_anchors = 4
html_theme = "alabaster"
html_theme_options = {{"page_width": "80em", "sidebar_width": "18em"}}
html_sidebars = {{"**": ["globaltoc.html", "searchbox.html"]}}
suppress_warnings = ["image.not_readable", "myst.header"]
html_show_sourcelink = False
'''


def write(check_files, figure_files, out_dir, subjects: dict, sections: list, choices: list, meta: dict,
          figures=()) -> None:
    """Generate the MyST sources in ``out_dir/_sources_md`` and build the HTML article into ``out_dir``
    (replaced whole, through a temporary folder beside it)."""
    from sphinx.cmd.build import build_main

    out_dir = Path(out_dir)
    tmp = out_dir.with_name(f".{out_dir.name}.tmp")
    shutil.rmtree(tmp, ignore_errors=True)
    src = tmp / "_sources_md"
    src.mkdir(parents=True)
    reports = load(check_files, figure_files, src)
    check_subjects(reports, subjects)
    check_errata(reports)
    # the figures are referenced from the sources' folder; paths as given are relative to the working directory
    figs = [dict(f, path=os.path.abspath(f["path"])) for f in figures]
    reports = [replace(r, figure=os.path.abspath(os.path.join(src, r.figure)) if r.figure else "") for r in reports]
    info = _claims_info()
    names, beyond, subject_pages, page_of = [], [], [], {}
    for i, sec in enumerate(sections, 1):
        name = f"section-{i:02d}"
        (beyond if all(judging_kind(s) == BEYOND for s in sec["subjects"]) else names).append(name)
        subject_pages += [(sid, subjects[sid], name) for sid in sec["subjects"]]
        (src / f"{name}.md").write_text(section_page(sec["title"], sec["subjects"], subjects, reports, figs, info, src))
    for v in rows(reports):
        where = "errata" if v.kind == ERRATUM else next(p for s, _, p in subject_pages if s == v.subject) \
            if v.kind == judging_kind(v.subject) else "extension"
        page_of.setdefault(statement_id(v.claim_id), where)
    (src / "errata.md").write_text(errata_page(reports, info))
    (src / "extension.md").write_text(extension_page(reports, figs, src, info))
    (src / "index.md").write_text(index_page(reports, meta, choices, names, beyond, subject_pages, page_of))
    (src / "conf.py").write_text(CONF.format(title=meta.get("title", "bounce")))
    status = build_main(["-b", "html", "-q", "-E", "-d", str(tmp / "_doctrees"), str(src), str(tmp)])
    if status:
        raise ReportError(f"sphinx-build failed with status {status} (sources in {src})")
    shutil.rmtree(tmp / "_doctrees", ignore_errors=True)
    shutil.rmtree(out_dir, ignore_errors=True)
    os.replace(tmp, out_dir)

"""Integration: the CI-sized pipeline (config/ci.yaml) runs end to end, is idempotent and deterministic, lints
clean, and rejects a bad config before any job starts with a message naming the key.

The pipeline runs once per session (``ci_results``, tests/conftest.py) for every test here that reads it; those
tests and the other subprocess-heavy ones are ``slow`` (``python -m pytest --all``, CI).
"""

from __future__ import annotations

import csv
import io
import os
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import yaml

from bounce.pipeline import tasks, taskserver
from ci_pipeline import CI_CONFIG, ROOT, SNAKEMAKE, env, snakemake


def _launch_dir(ci_results: Path) -> Path:
    """Where snakemake ran (``--directory``, which takes precedence over the config's ``workdir``)."""
    return ci_results.parent


@pytest.mark.slow
def test_every_figure_and_dataset_is_produced(ci_results):
    config = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    figures = sorted(p.name for p in (ci_results / "figures").iterdir())
    for name in config["figures"]:
        for ext in ("png", "pdf"):
            assert f"fig-{name}.{ext}" in figures
    for name in ("rigid-fall", "rest-coeff", "very_rigid_poincare_magni", "very_rigid_poincare_overdamped_magni",
                 "sticky-traj", "sticky-convergence", "energy-decay", "asymptotic-laws"):
        assert (ci_results / "figures" / f"fig-{name}.png").stat().st_size > 10_000
    for scene in config["scenes"]:
        with xr.open_dataset(ci_results / "data" / f"{scene}.nc") as ds:
            assert ds.attrs["scene"] == scene
            assert ds.attrs["gamma"] == config["scenes"][scene]["gamma"]
            assert ds.attrs["git_commit"]
            assert np.all(np.diff(ds["t"].values) > 0)
            for var in ds.variables.values():
                assert "long_name" in var.attrs and "units" in var.attrs


@pytest.mark.slow
def test_sticky_study_matches_the_paper(ci_results):
    """t_c of the chosen (gamma, mu) truncates to the paper's 5.23; the RMS norm falls faster than eps."""
    with xr.open_dataset(ci_results / "data" / "sticky-convergence.nc") as ds:
        assert np.floor(ds.attrs["t_c"] * 100) / 100 == 5.23
        rms, eps = ds["rms"].values, ds["eps"].values
        slope = np.polyfit(np.log(eps), np.log(rms), 1)[0]
        assert slope > 1.0, f"RMS difference should fall faster than linearly in eps (paper, section 8.2): {slope}"


@pytest.mark.slow
def test_validation_report(ci_results):
    """Every configured check has rows in the report; the article has a page per section of the paper; the snakemake
    HTML report builds."""
    config = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    md = (ci_results / "report" / "validation.md").read_text()
    for name in config["checks"]:
        assert f"(`{name}`)" in md, f"check {name} missing from the report"
    assert re.search(r"\*\*\d+ reproduced, \d+ not reproduced, \d+ not checkable\*\*", md)
    article = ci_results / "report" / "article"
    index = (article / "index.html").read_text()
    for i, section in enumerate(config["report"]["sections"].values(), 1):
        assert section["title"].split(":")[0] in index and (article / f"section-{i:02d}.html").exists()
    assert (article / "errata.html").exists() and (article / "extension.html").exists()
    html = ci_results.parent / "report.html"
    snakemake(_launch_dir(ci_results), "--configfile", str(CI_CONFIG), "--report", str(html))
    assert html.stat().st_size > 100_000


@pytest.mark.slow
def test_ci_validation_verdicts(ci_results):
    """CI validation: every claim that is not an erratum (the paper's text as printed) and declares no known
    failure must stay reproduced (or not checkable at CI size); a law that stops holding fails CI here."""
    from bounce.checks import registry
    from bounce.checks.base import ERRATUM, NOT_REPRODUCED, read_verdicts

    known = {f"{g.name}/{c.id}" for g in registry().values() for c in g.claims if c.known_failure}
    bad = []
    for nc in sorted((ci_results / "checks").glob("*.nc")):
        with xr.open_dataset(nc) as ds:
            for v in read_verdicts(ds):
                if v.verdict == NOT_REPRODUCED and v.kind != ERRATUM and v.claim_id.split("[")[0] not in known:
                    bad.append(f"{v.claim_id}: {v.claim} ({v.paper_ref}): measured {v.measured}, expected {v.expected}")
    assert not bad, "\n".join(bad)


def _compared_outputs(results: Path) -> list[Path]:
    """The netCDF, PNG and PDF files of a run that must not change between runs: all but the timing files
    (results/timing/ and the studies that measure CPU time, bounce.studies: ``timed``), relative to ``results``."""
    from bounce.studies import registry

    timed = {f"methods/{stem}" for name, st in registry().items() if st.timed for stem in (name, f"fig-{name}")}
    files = sorted(p.relative_to(results) for p in results.rglob("*")
                   if p.suffix in (".nc", ".png", ".pdf") and p.parts[len(results.parts)] != "timing")
    return [f for f in files if str(f.with_suffix("")) not in timed]


@pytest.mark.slow
def test_a_rerun_of_every_rule_gives_identical_bytes(ci_results, tmp_path):
    """Issue 8: rerunning a job gives byte-identical netCDF, PNG and PDF files (timing files excepted).

    One job of every rule of the DAG (its first compared output by name: a scene, a sticky run, the sticky
    studies, a figure, a check experiment, a check, a study, a shard, a gather and a sweep figure) is deleted
    from a copy of the first run in another folder and made again there from the copied inputs, on 2 cores;
    every compared file must equal the first run's, byte for byte.  This replaced a second clean run of the whole
    DAG (~3 min on 2 cores, 74 jobs): it still catches an output that depends on the time, the folder, the
    process (hash seeds, worker order) or the other jobs running beside it, in the code of every rule; what it
    no longer covers is such a dependence confined to one wildcard value of a rule (a rule whose output depends
    on the clock for one scene only).  The first run's jobs were forked by the run's task server
    (bounce.pipeline.taskserver), the rerun's start afresh (BOUNCE_TASK_SERVER=off): a served job writes the
    bytes of a fresh one."""
    launch = _launch_dir(ci_results)
    summary = snakemake(launch, "--configfile", str(CI_CONFIG), "--summary").stdout
    rows = list(csv.DictReader(io.StringIO(summary[summary.index("output_file"):]), delimiter="\t"))
    compared = {str(Path("results") / f) for f in _compared_outputs(ci_results)}
    assert len(compared) > 50
    chosen: dict = {}
    for r in sorted(rows, key=lambda r: r["output_file"]):
        if r["output_file"] in compared:
            chosen.setdefault(r["rule"], r["output_file"])
    rules = {r["rule"] for r in rows}
    # every rule with an output compared is exercised (the report writes markdown and HTML only)
    assert set(chosen) == {r["rule"] for r in rows if r["output_file"] in compared}
    assert len(chosen) >= 10 and rules - set(chosen) <= {"report"}, (sorted(rules), sorted(chosen))

    again = tmp_path / "again"
    shutil.copytree(launch / "results", again / "results")  # copy2: the inputs keep their times, so stay done
    for f in chosen.values():
        (again / f).unlink()
    proc = snakemake(again, "--configfile", str(CI_CONFIG), "--cores", "2", *chosen.values(),
                     extra_env={taskserver.ADDRESS_VARIABLE: "off"})
    log = proc.stdout + proc.stderr
    assert f"{len(chosen)} of {len(chosen)} steps (100%) done" in log, log[-3000:]  # those jobs, nothing else

    differ = [str(f) for f in _compared_outputs(ci_results)
              if (ci_results / f).read_bytes() != (again / "results" / f).read_bytes()]
    assert not differ, f"not byte-identical when rerun: {differ}"


@pytest.mark.slow
def test_every_job_of_a_local_run_is_forked_by_the_task_server(ci_results):
    """Issue 22: a local run pays its imports once (bounce.pipeline.taskserver); each job's log says how it started."""
    logs = sorted((ci_results / "logs").rglob("*.log"))
    cpu_lines = {log: [line for line in log.read_text().splitlines() if line.startswith("cpu: ")] for log in logs}
    assert len(cpu_lines) > 50 and all(cpu_lines.values())
    afresh = [str(log.relative_to(ci_results)) for log, lines in cpu_lines.items() if taskserver.SERVED not in lines[-1]]
    assert not afresh, afresh


@pytest.mark.slow
def test_every_job_reports_the_cpu_it_spent_saving_figures(ci_results):
    """Issue 22: a job's last log line also gives the part of its CPU spent saving figures (after the timed studies the
    pipeline's largest cost): within the process's CPU and positive for every figure job, zero for a simulation."""
    by_folder = {}  # logs/<folder>/...: [(cpu, saving)]
    for log in sorted((ci_results / "logs").rglob("*.log")):
        match = tasks.CPU_LINE.match(log.read_text().splitlines()[-1])
        assert match and match[4] is not None, log
        by_folder.setdefault(log.relative_to(ci_results / "logs").parts[0], []).append((float(match[1]), float(match[4])))
    assert all(0.0 < saving <= cpu for cpu, saving in by_folder["figures"]), by_folder["figures"]
    assert all(saving == 0.0 for _, saving in by_folder["simulate"]), by_folder["simulate"]


#: a time in seconds written as text: "3.49 ms", "2 seconds", "1.5 s CPU", "CPU in process seconds"
_SECONDS = re.compile(r"\d\s*(?:ms|seconds?)\b|\d\s*s\s+(?:CPU|wall)\b|CPU in")


@pytest.mark.slow
def test_results_carry_no_timings(ci_results):
    """Issue 25 item 10: outside results/timing/ no dataset carries a CPU or wall time, neither as a variable in
    seconds nor written into a string or an attribute (the least model's reason read "at 3.49 ms CPU", the
    work-precision files' units note "CPU in process seconds")."""
    found = []
    for path in sorted(ci_results.rglob("*.nc")):
        if path.relative_to(ci_results).parts[0] == "timing":
            continue
        with xr.open_dataset(path) as ds:
            texts = [str(v) for v in ds.attrs.values()]
            for name, var in ds.variables.items():
                if var.attrs.get("units") == "s":
                    found.append(f"{path.name}: {name} in seconds")
                texts += [str(v) for v in var.attrs.values()]
                if var.dtype.kind in "OUS":
                    texts += [str(x) for x in np.ravel(var.values)]
        found += [f"{path.name}: {text[:100]!r}" for text in texts if _SECONDS.search(text)]
    assert not found, "\n".join(found)


@pytest.mark.slow
def test_rerun_does_nothing(ci_results):
    proc = snakemake(_launch_dir(ci_results), "--configfile", str(CI_CONFIG), "-n")
    assert "Nothing to be done" in proc.stdout + proc.stderr


@pytest.mark.slow
def test_lint_is_clean_but_for_conda():
    """The only lint left is 'use conda/containers': conda is not reachable here; environment.txt pins pip deps."""
    proc = subprocess.run([*SNAKEMAKE, "--lint"], capture_output=True, text=True, env=env(), cwd=ROOT)
    lints = set(re.findall(r"^\s+\* (.+?):\s*$", proc.stdout + proc.stderr, flags=re.M))
    assert lints <= {"Specify a conda environment or container for each rule."}, lints


@pytest.mark.parametrize(
    "edit, message",
    [
        (lambda c: c["scenes"]["rigid-fall"].update(gamma=-0.01), "gamma"),
        (lambda c: c["scenes"]["rigid-fall"].update(gamm=0.01), "gamm"),
        (lambda c: c["scenes"]["rigid-fall"]["stop"].update(events=0), "events"),
        (lambda c: c["sticky"].update(mu=-1.0), "mu"),
        (lambda c: c["checks"]["errata"].update(seeed=7), "seeed"),
        (lambda c: c["checks"]["main-theorem"]["fit"].update(nmin=3), "nmin"),
        (lambda c: c["report"]["subjects"].update({"thm main": "a subject without its label prefix"}), "thm main"),
    ],
)
def test_bad_config_is_refused_naming_the_key(edit, message):
    """The Snakefile's contract (bounce.pipeline.config.validated, called before any job) on the whole config."""
    from bounce.pipeline.config import ConfigError, validated

    config = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    edit(config)
    with pytest.raises(ConfigError, match=re.escape(message)):
        validated(config)


def test_bad_config_stops_snakemake_before_any_job(tmp_path):
    """The same refusal through snakemake: non-zero exit, the key named, nothing written."""
    config = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    config["checks"]["main-theorem"]["fit"].update(nmin=3)
    bad = tmp_path / "bad.yaml"
    bad.write_text(yaml.safe_dump(config))
    proc = snakemake(tmp_path, "--configfile", str(bad), "-n", check=False)
    assert proc.returncode != 0
    out = proc.stdout + proc.stderr
    assert "nmin" in out, out[-2000:]
    assert not (tmp_path / "results").exists()


@pytest.mark.slow
def test_notebooks_run_against_ci_results(ci_results, tmp_path):
    """Every jupytext notebook executes top to bottom against the CI-sized results."""
    jupytext = pytest.importorskip("jupytext")
    nbclient = pytest.importorskip("nbclient")
    notebooks = sorted((ROOT / "notebooks").glob("*.py"))
    assert notebooks, "no notebooks found"
    for path in notebooks:
        nb = jupytext.read(path)
        client = nbclient.NotebookClient(
            nb, timeout=600, kernel_name="python3", resources={"metadata": {"path": str(tmp_path)}}
        )
        os.environ["BOUNCE_RESULTS"] = str(ci_results)
        try:
            client.execute()
        finally:
            os.environ.pop("BOUNCE_RESULTS", None)
        shutil.rmtree(tmp_path / ".ipynb_checkpoints", ignore_errors=True)

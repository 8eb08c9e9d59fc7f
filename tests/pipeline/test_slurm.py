"""The CI-sized sweeps through a real SLURM (workflow/profiles/slurm, snakemake-executor-plugin-slurm), run as
the README says, give the same files, byte for byte, as a local `snakemake --cores 2` run of the same DAG.

Needs a running SLURM whose node can run this checkout's Python: the one-node cluster of
`workflow/slurm/start-local-slurm.sh` (as root), which `.ci/run` starts on every run.  Skipped, with the
reason, when no SLURM node is up, except under BOUNCE_REQUIRE_SLURM=1 (set by `.ci/run`), where it fails.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from collections import Counter
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[2]
PROFILE = ROOT / "workflow" / "profiles" / "slurm"


def _slurm_ready() -> str:
    """'' if a SLURM node is idle (or busy) and accepts jobs, else why not."""
    if shutil.which("sinfo") is None or shutil.which("sbatch") is None:
        return "SLURM is not installed (run `workflow/slurm/start-local-slurm.sh` as root)"
    try:
        out = subprocess.run(["sinfo", "-h", "-o", "%T"], capture_output=True, text=True, timeout=20)
    except (OSError, subprocess.TimeoutExpired) as exc:
        return f"sinfo failed: {exc}"
    states = out.stdout.split()
    if out.returncode != 0 or not any(s in ("idle", "mixed", "allocated") for s in states):
        return f"no SLURM node up (sinfo: {out.stdout.strip() or out.stderr.strip()[:100]}); run " \
               "`workflow/slurm/start-local-slurm.sh` as root"
    return ""


def _ci_sweeps() -> dict:
    """The sweeps of config/ci.yaml merged over config/config.yaml (as `--configfile` does), with defaults."""
    from snakemake.utils import update_config

    from bounce.pipeline.config import load_schema, validated

    config = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    update_config(config, yaml.safe_load((ROOT / "config" / "ci.yaml").read_text()))
    return validated(config, load_schema(ROOT / "config" / "schema.yaml"))["sweeps"]


@pytest.fixture(scope="module")
def slurm_run(tmp_path_factory):
    """`snakemake --profile workflow/profiles/slurm sweeps --configfile config/ci.yaml`, started (as a user
    starts it) from a folder of its own, so that the config's relative `workdir: ci-run` is resolved there.
    Cheaper than the profile's settings on the 2-CPU node, same bytes: shards on one core each (two run at
    once, overlapping each job's Snakemake start-up; a shard's numbers do not depend on its workers, and the
    local run it is compared with used two), status polling from 2 s instead of 10 (jobs here take seconds).
    Measured at a load of 6-7 on 2 cores: 342 s instead of 493 s."""
    why_not = _slurm_ready()
    if why_not:
        if os.environ.get("BOUNCE_REQUIRE_SLURM") == "1":
            pytest.fail(f"BOUNCE_REQUIRE_SLURM=1 but {why_not}")
        pytest.skip(why_not)
    launch = tmp_path_factory.mktemp("slurm")
    env = dict(os.environ)
    env["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{env.get('PATH', '')}"  # `python` in the jobs
    proc = subprocess.run([sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile"), "--profile", str(PROFILE),
                           "sweeps", "--configfile", str(ROOT / "config" / "ci.yaml"),
                           "--set-threads", "sweep_shard=1", "--slurm-init-seconds-before-status-checks", "2"],
                          cwd=launch, capture_output=True, text=True, env=env, timeout=1800)
    log = proc.stdout + proc.stderr
    assert proc.returncode == 0, f"snakemake on SLURM failed:\n{log[-6000:]}"
    return launch, log


@pytest.fixture(scope="module")
def local_results(request, tmp_path_factory):
    """results/ of a local `snakemake --cores 2` run of the same DAG: the CI-sized pipeline's (fixture ci_results)
    when another test of this session runs it anyway (the whole suite, CI), else the sweeps alone."""
    here = Path(__file__).resolve()
    if any("ci_results" in getattr(item, "fixturenames", ()) and Path(item.path).resolve() != here
           for item in request.session.items):
        return request.getfixturevalue("ci_results")
    work = tmp_path_factory.mktemp("local")
    env = dict(os.environ)
    env["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{env.get('PATH', '')}"
    proc = subprocess.run([sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile"), "--directory", str(work),
                           "sweeps", "--configfile", str(ROOT / "config" / "ci.yaml"), "--cores", "2"],
                          capture_output=True, text=True, env=env, timeout=1800)
    assert proc.returncode == 0, f"the local run failed:\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}"
    return work / "results"


@pytest.mark.slow
def test_sweeps_on_slurm_equal_the_local_run(slurm_run, local_results):
    launch, log = slurm_run
    sweeps = _ci_sweeps()
    # every job ran as a SLURM job, not locally (the plugin deletes the logs of successful jobs; count its
    # submission lines): each sweep's shards and its gather (which draws its figure), as many as the config says
    submitted = Counter(re.findall(r"has been submitted with SLURM jobid \d+ \(log: \S+/slurm_logs/rule_(sweep_\w+)/",
                                   log))
    assert submitted == {"sweep_shard": sum(spec["shards"] for spec in sweeps.values()),
                         "sweep_gather": len(sweeps)}, log[-3000:]
    # the config's relative workdir applied once (it used to be applied again inside each job)
    results = launch / "ci-run" / "results"
    assert not (launch / "ci-run" / "ci-run").exists()
    # the profile says no account: no attempt to guess one
    assert "SLURM account" not in log, log[-3000:]
    differ = []
    for name in sweeps:
        for f in (f"{name}.nc", f"fig-{name}.png", f"fig-{name}.pdf"):
            if (results / "sweeps" / f).read_bytes() != (local_results / "sweeps" / f).read_bytes():
                differ.append(f)
    assert not differ, f"differ between SLURM and the local run: {differ}"

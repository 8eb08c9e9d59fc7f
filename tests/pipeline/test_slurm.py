"""The sweeps through a real SLURM (workflow/profiles/slurm, snakemake-executor-plugin-slurm) give the same
gathered files, byte for byte, as a local `snakemake --cores 2` run.

Needs a running SLURM whose node can run this checkout's Python (the one-node cluster of
`sudo workflow/slurm/start-local-slurm.sh`, or `BOUNCE_CI_SLURM=1 .ci/run`); skipped otherwise.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SNAKEMAKE = [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile")]
SWEEPS = ("asymptotic-atlas", "contact-monte-carlo")


def _slurm_ready() -> str:
    """'' if a SLURM node is idle (or busy) and accepts jobs, else why not."""
    if shutil.which("sinfo") is None or shutil.which("sbatch") is None:
        return "SLURM is not installed (run `sudo workflow/slurm/start-local-slurm.sh`)"
    try:
        out = subprocess.run(["sinfo", "-h", "-o", "%T"], capture_output=True, text=True, timeout=20)
    except (OSError, subprocess.TimeoutExpired) as exc:
        return f"sinfo failed: {exc}"
    states = out.stdout.split()
    if out.returncode != 0 or not any(s in ("idle", "mixed", "allocated") for s in states):
        return f"no SLURM node up (sinfo: {out.stdout.strip() or out.stderr.strip()[:100]}); run " \
               "`sudo workflow/slurm/start-local-slurm.sh`"
    return ""


pytestmark = pytest.mark.skipif(bool(_slurm_ready()), reason=_slurm_ready() or "SLURM ready")


def _env():
    env = dict(os.environ)
    env["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{env.get('PATH', '')}"  # `python` in the jobs
    return env


def _snakemake(workdir: Path, *args) -> subprocess.CompletedProcess:
    proc = subprocess.run([*SNAKEMAKE, "--directory", str(workdir), *args, "sweeps",
                           "--configfile", str(ROOT / "config" / "ci.yaml")],
                          capture_output=True, text=True, env=_env(), timeout=1800, cwd=ROOT)
    assert proc.returncode == 0, f"snakemake {' '.join(args)} failed:\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}"
    return proc


def test_sweeps_on_slurm_equal_the_local_run(tmp_path):
    on_slurm, local = tmp_path / "slurm", tmp_path / "local"
    proc = _snakemake(on_slurm, "--profile", str(ROOT / "workflow" / "profiles" / "slurm"))
    _snakemake(local, "--cores", "2")
    # every job ran as a SLURM job, not locally (the plugin deletes the logs of successful jobs; count its
    # submission lines): 4 shards, 2 gathers, 2 figures
    log = proc.stderr + proc.stdout
    submitted = re.findall(r"has been submitted with SLURM jobid \d+ \(log: \S+/slurm_logs/(rule_sweep_\w+)/", log)
    assert sorted(submitted) == ["rule_sweep_figure"] * 2 + ["rule_sweep_gather"] * 2 + ["rule_sweep_shard"] * 4, \
        log[-2000:]
    for name in SWEEPS:
        a = (on_slurm / "results" / "sweeps" / f"{name}.nc").read_bytes()
        b = (local / "results" / "sweeps" / f"{name}.nc").read_bytes()
        assert a == b, f"{name}.nc differs between SLURM and the local run"
        assert (on_slurm / "results" / "sweeps" / f"fig-{name}.png").stat().st_size > 10_000

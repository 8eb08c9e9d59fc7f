"""Fixtures shared by the pipeline's integration tests."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def ci_results(tmp_path_factory):
    """The CI-sized pipeline (config/ci.yaml), run once with `snakemake --cores 2`: its results/ folder, read by
    the pipeline's and the notebooks' tests and compared with the SLURM run of its sweeps (test_slurm)."""
    work = tmp_path_factory.mktemp("pipeline")
    env = dict(os.environ)
    env["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{env.get('PATH', '')}"  # `python` in rules
    proc = subprocess.run([sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile"), "--directory", str(work),
                           "--configfile", str(ROOT / "config" / "ci.yaml"), "--cores", "2"],
                          capture_output=True, text=True, env=env, timeout=900)
    assert proc.returncode == 0, f"the CI-sized pipeline failed:\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}"
    return work / "results"

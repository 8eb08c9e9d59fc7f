"""Snakemake as the tests call it, and the CI-sized pipeline run (config/ci.yaml) the slow tests share.

Not a test: ``tests/conftest.py`` runs :func:`run_ci_pipeline` once per session (fixture ``ci_results``) for
every test that reads its outputs (tests/pipeline/test_pipeline.py, tests/sweeps/test_sweeps.py).
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SNAKEMAKE = [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile")]
CI_CONFIG = ROOT / "config" / "ci.yaml"


def env() -> dict:
    """This environment with this interpreter's folder first on PATH (the rules call ``python``); the numba
    cache (BOUNCE_NUMBA_CACHE_DIR) is inherited, so the jobs load the kernels the tests compiled."""
    out = dict(os.environ)
    out["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{out.get('PATH', '')}"
    return out


def snakemake(workdir: Path, *args: str, check: bool = True, timeout: float = 900,
              extra_env: dict | None = None) -> subprocess.CompletedProcess:
    """``snakemake --directory workdir *args`` (in :func:`env` updated with ``extra_env``); on failure (``check``) an
    AssertionError with the tail of its output."""
    proc = subprocess.run([*SNAKEMAKE, "--directory", str(workdir), *args], capture_output=True, text=True,
                          env={**env(), **(extra_env or {})}, timeout=timeout)
    if check and proc.returncode != 0:
        raise AssertionError(f"snakemake {' '.join(args)} failed:\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}")
    return proc


def warm_numba_cache() -> None:
    """The event loops of both spring laws compiled here (or loaded: ~0.5 s) before the pipeline starts, so that its
    jobs, which inherit BOUNCE_NUMBA_CACHE_DIR, load them from the cache instead of compiling them two at a time
    (the power law's alone is ~17 s of CPU cold)."""
    from bounce import Parameters, State, simulate
    from bounce.springs import spring_from_spec

    simulate(Parameters(0.01, 0.01), State.from_psi_xi(6.0, 0.0, 0.0, 0.0), max_events=10)
    hertz = Parameters(0.01, 0.3, spring=spring_from_spec({"law": "power", "rho": 1.0, "a": 0.5, "b": 0.5}))
    simulate(hertz, State.from_psi_xi(-0.0264, 0.0, -0.0464, 0.0), max_events=10)


def run_ci_pipeline(workdir: Path, *targets: str) -> Path:
    """The CI-sized pipeline (or its ``targets``) in ``workdir`` on 2 cores; returns ``workdir/results``."""
    warm_numba_cache()
    snakemake(workdir, "--configfile", str(CI_CONFIG), "--cores", "2", *targets)
    return workdir / "results"

"""Settings shared by the whole test suite: the fast default and ``--all``, hypothesis's profile, shared fixtures.

``python -m pytest`` runs the unit, reference and property tests; tests marked ``slow`` (integration: the
CI-sized pipeline and what reads it, SLURM, the long fuzz, anything that takes more than ~5 s) are deselected.
``python -m pytest --all`` runs every test; ``.ci/run`` runs it.  ``-m EXPR`` selects by marker as usual
(``-m slow``: the slow tests only) and then replaces the default deselection.
"""

import fcntl
import os
import subprocess
from pathlib import Path

import pytest
from hypothesis import settings

# CI must be reproducible: every property test draws a fixed sequence of examples (hypothesis derandomize).
# BOUNCE_HYPOTHESIS_RANDOM=1 draws fresh ones, as benchmarks/fuzz_cli.py does, to look for new counterexamples;
# one found becomes a test (tests/exact/test_edges.py: the huge damping force, found so and since fixed).
settings.register_profile("bounce", derandomize=os.environ.get("BOUNCE_HYPOTHESIS_RANDOM") != "1")
settings.load_profile("bounce")


def pytest_addoption(parser):
    parser.addoption("--all", action="store_true", dest="run_all",
                     help="bounce: run every test, the slow ones (integration) included, as CI does")


def pytest_collection_modifyitems(config, items):
    """Deselect the slow tests unless --all or a -m expression says otherwise."""
    if config.option.run_all or config.option.markexpr:
        return
    slow = [item for item in items if item.get_closest_marker("slow")]
    if slow:
        config.hook.pytest_deselected(items=slow)
        items[:] = [item for item in items if not item.get_closest_marker("slow")]


@pytest.fixture(scope="session")
def ci_results(tmp_path_factory) -> Path:
    """``results/`` of the CI-sized pipeline (config/ci.yaml, 2 cores), run once per session for every slow test
    that reads its outputs; under pytest-xdist once for all the workers (the first one runs it, the others wait
    on a lock and read the same folder).  Tests must not modify it."""
    from ci_pipeline import run_ci_pipeline

    base = tmp_path_factory.getbasetemp()
    if os.environ.get("PYTEST_XDIST_WORKER"):
        base = base.parent  # the session's folder, shared by its workers
    work, done = base / "ci-pipeline", base / "ci-pipeline.done"
    with open(base / "ci-pipeline.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not done.exists():
            work.mkdir(exist_ok=True)
            run_ci_pipeline(work)
            done.touch()
    return work / "results"


@pytest.fixture
def small_disk(tmp_path):
    """A directory on its own 2 MiB tmpfs, to fill the disk for real (needs root, or CAP_SYS_ADMIN: CI runs
    as root; skipped with the reason where mounting is not permitted)."""
    disk = tmp_path / "disk"
    disk.mkdir()
    mounted = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=2m", "tmpfs", str(disk)], capture_output=True,
                             text=True)
    if mounted.returncode != 0:
        pytest.skip(f"cannot mount a small tmpfs here: {mounted.stderr.strip()}")
    try:
        yield disk
    finally:
        subprocess.run(["umount", "--lazy", str(disk)], check=True)

"""Settings shared by the whole test suite: the fast default and ``--all``, hypothesis's profile.

``python -m pytest`` runs the unit, reference and property tests; tests marked ``slow`` (integration: the
CI-sized pipeline, SLURM, the CI-sized sweeps, anything that takes more than ~5 s) are deselected.
``python -m pytest --all`` runs every test, with the long fuzz (``tests/test_fuzz.py``: 400 examples per
test instead of 100); ``.ci/run`` runs it.  ``-m EXPR`` selects by marker as usual (``-m slow``: the slow
tests only) and then replaces the default deselection.
"""

import fcntl
import os
from pathlib import Path

import pytest
from hypothesis import settings

# CI must be reproducible: every property test draws a fixed sequence of examples (hypothesis derandomize).
# BOUNCE_HYPOTHESIS_RANDOM=1 draws fresh ones, as benchmarks/fuzz_cli.py does, to look for new counterexamples;
# one found becomes a test (tests/exact/test_edges.py: the huge damping force, found so and since fixed).
settings.register_profile("bounce", derandomize=os.environ.get("BOUNCE_HYPOTHESIS_RANDOM") != "1")
settings.load_profile("bounce")

#: examples per fuzz test (tests/test_fuzz.py) in the default run and with --all; BOUNCE_FUZZ_EXAMPLES overrides both
FUZZ_EXAMPLES = {"default": 100, "all": 400}


def pytest_addoption(parser):
    parser.addoption("--all", action="store_true", dest="run_all",
                     help="bounce: run every test, the slow ones (integration) included, with the long fuzz (CI)")


def pytest_configure(config):
    # read by tests/test_fuzz.py when it is imported (collection comes after this hook)
    os.environ.setdefault("BOUNCE_FUZZ_EXAMPLES", str(FUZZ_EXAMPLES["all" if config.option.run_all else "default"]))


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

"""Settings shared by the whole test suite."""

import os
import subprocess

import pytest
from hypothesis import settings

# CI must be reproducible: every property test draws a fixed sequence of examples (hypothesis derandomize).
# BOUNCE_HYPOTHESIS_RANDOM=1 draws fresh ones, as benchmarks/fuzz_cli.py does, to look for new counterexamples;
# one found becomes a test (tests/exact/test_edges.py: the huge damping force, found so and since fixed).
settings.register_profile("bounce", derandomize=os.environ.get("BOUNCE_HYPOTHESIS_RANDOM") != "1")
settings.load_profile("bounce")


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

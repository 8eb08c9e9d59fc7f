"""Settings shared by the whole test suite."""

import os

from hypothesis import settings

# CI must be reproducible: every property test draws a fixed sequence of examples (hypothesis derandomize).
# BOUNCE_HYPOTHESIS_RANDOM=1 draws fresh ones, as benchmarks/fuzz_cli.py does, to look for new counterexamples;
# one found becomes a test (tests/exact/test_edges.py: the huge damping force, found so and since fixed).
settings.register_profile("bounce", derandomize=os.environ.get("BOUNCE_HYPOTHESIS_RANDOM") != "1")
settings.load_profile("bounce")

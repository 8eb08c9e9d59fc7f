"""Property-based fuzz of the command line and of ``simulate`` over the whole input domain (issues 12, 25).

The cases and their contract are in ``fuzzing.py`` (accepted: finite, physically valid records and the file
alone; refused: one line naming the parameter and its range, status 2, nothing written).  Every case runs
in a worker process within :data:`TIME_BOUND` seconds (``fuzzing.Runner``): a case still running then is a
defect, like a broken contract.  Both spring laws: the linear one with every number corrupted, the power
law over :data:`fuzzing.POWER_SUPPORTED` (``benchmarks/fuzz_cli.py`` runs the same contract wider and larger).

Size: BOUNCE_FUZZ_EXAMPLES examples per test (default 300: ~1.5 min for all four on one core, most of it
the power law's; the three longer than 5 s are marked slow).
"""

from __future__ import annotations

import math
import os

import pytest
from fuzzing import DEFECT, POWER_SUPPORTED, Runner, api_cases, command_lines
from hypothesis import HealthCheck, example, given, settings

MAX_EXAMPLES = int(os.environ.get("BOUNCE_FUZZ_EXAMPLES", "300"))
#: seconds one case may take (a case of these ranges takes ~0.1 s on a loaded 2-core machine; one still running
#: after TIME_BOUND is a defect)
TIME_BOUND = 60.0
#: under pytest a fixed example sequence (tests/conftest.py)
SETTINGS = settings(deadline=None, max_examples=MAX_EXAMPLES, database=None,
                    suppress_health_check=[HealthCheck.too_slow])


@pytest.fixture(scope="module")
def runner():
    fuzz = Runner(TIME_BOUND)
    yield fuzz
    fuzz.close()


def _holds(runner, kind, case):
    outcome = runner.run(kind, case)
    assert outcome.verdict != DEFECT, (outcome.what, case)


@pytest.mark.slow
@SETTINGS
@given(argv=command_lines())
def test_cli_fuzz(runner, argv):
    """Exit 0 only with finite, physically valid output; otherwise one line naming the parameter
    and its range, status 2, nothing left in the directory."""
    _holds(runner, "cli", argv)


@pytest.mark.slow
@SETTINGS
@given(argv=command_lines(POWER_SUPPORTED))
def test_cli_fuzz_power_law(runner, argv):
    """The same with the power-law spring, within the time bound."""
    _holds(runner, "cli", argv)


@SETTINGS
@given(case=api_cases())
# phases spanning 2^537 (a first phase of 3e-162): t 1 ulp from fsum(tau), as documented (tie of rounding)
@example(case=(0.4999999999999999, 0.0, None, "deviations", (5e-324, 0.0, -3.0, 0.0), 4, math.inf))
# at rest at the natural length, a = b = 0, critical damping: was a ZeroDivisionError in the series solver
@example(case=(1e-06, 1.0, {"law": "power", "rho": 1.0, "a": 0.0, "b": 0.0}, "psi", (0.0, 0.0, 0.0, 0.0), 15,
               math.inf))
def test_simulate_fuzz(runner, case):
    """``simulate`` over the same domain: an InputError naming the parameter and its range, or a
    trajectory whose records are finite and physically valid."""
    _holds(runner, "api", case)


@pytest.mark.slow
@SETTINGS
@given(case=api_cases(POWER_SUPPORTED))
def test_simulate_fuzz_power_law(runner, case):
    """The same with the power-law spring, within the time bound."""
    _holds(runner, "api", case)

"""The power law's supported domain (bounce.springs.power), enforced up front by the API and the CLI alike.

Protects (issue 25, items 5 and 6): the fuzzed inputs that ran with the equilibrium below the floor, stalled
before their first event or ended in a traceback are refused in one line naming the parameter, or progress;
a run inside the domain progresses (its phases end within a bounded time, at the domain's edges too); the
API's power-law path refuses what the CLI refuses, with the same message; the parameters' own limits
(a, b <= 50: b = 50 still matches the mpmath reference).
"""

from __future__ import annotations

import math
import subprocess
import sys

import pytest

import power_reference as PR
from bounce import Deviations, Parameters, State, simulate
from bounce.errors import InputError
from bounce.model import check_supported
from bounce.springs.power import OVERDAMPING_MAX, WORK_MAX, PowerSpring

#: the issue's fuzzed inputs: (gamma, mu, (rho, a, b), (psi0, psidot0, xi0, xidot0)) and the word the refusal names
REFUSED = [
    # equilibrium below the floor: (gamma/rho)^(1/(a+1)) >= 1/2 (34 such runs exited 0)
    ((0.7, 0.1, (1.0, 0.5, 0.5), (1.0, 0.0, 0.5, 0.0)), "spring rho must be > gamma 2^(a+1) = 1.9799"),
    ((0.01, 0.01, (1e-6, 0.5, 0.5), (6.0, 0.0, 0.0, 0.0)), "spring rho must be > gamma 2^(a+1)"),
    # stalled before the first event: a sticky spring over-damped ...
    ((0.01, 9.3e4, (1.0, 0.417, 2.0), (1.0, 0.0, 0.0, 0.0)), "mu must be <= 8.99e+03"),
    # ... or a flight whose damping 2 mu |xi|^b is enormous where the spring is compressed
    ((0.1225, 8.39e7, (6.85e5, 0.0, 3.08), (1.0, 0.0, 0.3, 0.0)), "initial state"),
    ((0.01, 1e4, (1.0, 0.5, 0.5), (1.0, 0.0, -0.3, 0.0)), "mu must be <= 59"),
]


def _api_message(case) -> str:
    gamma, mu, law, state = case
    with pytest.raises(InputError) as err:
        simulate(Parameters(gamma, mu, PowerSpring(*law)), State.from_psi_xi(*state), max_events=10)
    return str(err.value)


def _cli(tmp_path, case, **law):
    """The CLI on ``case``; ``law`` replaces options of the law (``a="1e20"``)."""
    gamma, mu, (rho, a, b), (psi, psidot, xi, xidot) = case
    options = {"rho": repr(rho), "a": repr(a), "b": repr(b), **law}
    out = tmp_path / "run.nc"
    argv = [sys.executable, "-m", "bounce", "simulate", "--gamma", repr(gamma), "--mu", repr(mu), "--spring", "power",
            *[tok for k, v in options.items() for tok in (f"--{k}", v)], "--psi0", repr(psi), "--psidot0", repr(psidot),
            "--xi0", repr(xi), "--xidot0", repr(xidot), "--events", "10", "--out", str(out)]
    return subprocess.run(argv, capture_output=True, text=True, timeout=120), out


@pytest.mark.parametrize("case, words", REFUSED, ids=[f"refused{i}" for i in range(len(REFUSED))])
def test_fuzzed_failures_are_refused_alike_by_api_and_cli(tmp_path, case, words):
    """One line naming the parameter and its supported range, the same from simulate() and from the CLI (exit 2,
    no file); before, these ran below the floor, stalled, hung (mu = 1e12) or raised RuntimeError (mu = 1e9)."""
    message = _api_message(case)
    assert message.startswith(words) or words in message.split(":")[0], message
    assert "\n" not in message and "supported range" in message
    proc, out = _cli(tmp_path, case)
    assert proc.returncode == 2 and proc.stderr == f"error: {message}\n" and not out.exists()


@pytest.mark.parametrize("mu", [1e9, 1e12])
def test_issue_api_example_refused_at_any_damping(mu):
    """simulate(Parameters(0.7, mu, PowerSpring(1, .5, .5)), State(0, .5, 1.5, 0)) hung at mu = 1e12 and raised
    RuntimeError at mu = 1e9: the equilibrium is below the floor, refused up front."""
    with pytest.raises(InputError, match="spring rho must be > gamma 2"):
        simulate(Parameters(0.7, mu, PowerSpring(1.0, 0.5, 0.5)), State(0.0, 0.5, 1.5, 0.0))


@pytest.mark.parametrize("option, value, line", [
    ("a", "1e20", "error: spring a must be a finite number (allowed range: [0, 50]; exponent of the restoring force"),
    ("b", "1e30", "error: spring b must be a finite number (allowed range: [0, 50]; exponent of the damping"),
    ("a", "inf", "error: argument --a: must be a finite number (allowed range: [0, 50]), got 'inf'"),
])
def test_huge_exponents_are_one_line_not_a_traceback(tmp_path, option, value, line):
    """--a 1e20 and --b 1e30 ended in tracebacks (an array too big, an OverflowError)."""
    proc, out = _cli(tmp_path, (0.01, 0.01, (1.0, 0.5, 0.5), (6.0, 0.0, 0.0, 0.0)), **{option: value})
    lines = proc.stderr.splitlines()
    assert proc.returncode == 2 and len(lines) == 1 and lines[0].startswith(line) and not out.exists(), proc.stderr


def _progresses(gamma, mu, law, start, events, seconds, t_max=math.inf):
    """Run in a child process with a wall-clock bound: (stop reason, events) or a timeout failure."""
    code = ("import math, sys; from bounce import Parameters, Deviations, simulate; "
            "from bounce.springs import PowerSpring; "
            f"tr = simulate(Parameters({gamma!r}, {mu!r}, PowerSpring(*{law!r})), Deviations(*{start!r}), "
            f"max_events={events}, t_max=float('{t_max!r}')); print(tr.stop_reason, len(tr))")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=seconds)
    assert proc.returncode == 0, proc.stderr
    return proc.stdout.split()


def test_at_the_overdamping_edge_sticky_phases_end():
    """mu just inside domain 4 (Z = OVERDAMPING_MAX): a start at rest on the floor, compressed and stretched, ends its
    sticky phase (detach or proof) within the step cap, where mu 10x larger ran into it (RuntimeError)."""
    gamma, law = 0.01, (1.0, 0.5, 0.5)
    spring = PowerSpring(*law)
    w = -spring.xi_eq(gamma)
    mu = 0.999 * math.sqrt(OVERDAMPING_MAX * 0.75 * gamma / w) / math.sqrt(w)
    for eta in (-0.5 * w, 0.5 * w):
        check_supported(Parameters(gamma, mu, spring), Deviations(0.0, 0.0, 0.0, eta))
        stop, n = _progresses(gamma, mu, law, (0.0, 0.0, 0.0, eta), 3, seconds=60)
        assert stop in ("sticky_forever", "max_events") and int(n) >= 1
    with pytest.raises(InputError, match="mu must be <="):
        check_supported(Parameters(gamma, 1.01 * mu / 0.999, spring), Deviations(0.0, 0.0, 0.0, 0.0))


@pytest.mark.slow  # ~7 s of CPU (a subprocess near the time bound): --all and CI
def test_at_the_work_edge_flights_end():
    """A drop whose flights come close to WORK_MAX (a stiff a = 0 spring with non-dyadic b = 3.08, the slowest
    crossings of xi = 0 measured) finishes its first events within the time bound the domain promises (~10 s a
    phase, here with a margin for a loaded machine); the same law from higher up is refused, or runs with a t_max."""
    gamma, mu, law = 0.01, 0.0, (1e4, 0.0, 3.08)
    spring = PowerSpring(*law)
    params = Parameters(gamma, mu, spring)
    low = State.from_psi_xi(2500.0, 0.0, 0.0, 0.0).deviations(params)
    _, reach, longest = spring.longest_flight(gamma, low)
    work = longest * sum(spring.rates(mu, reach))
    assert 0.3 * WORK_MAX < work <= WORK_MAX
    stop, n = _progresses(gamma, mu, law, (low.x, low.xdot, low.xidot, low.eta), 3, seconds=90)
    assert (stop, n) == ("max_events", "3")
    high = State.from_psi_xi(2.5e5, 0.0, 0.0, 0.0).deviations(params)
    with pytest.raises(InputError, match=r"initial state \(or t_max\).*supported range: time x R <= 250000"):
        check_supported(params, high)
    check_supported(params, high, t_max=20.0)  # the first 20 time units only


def test_exponents_at_their_limit_match_the_reference():
    """b = B_MAX = 50 inside the domain (near equilibrium, where |xi|^50 is small) is exact to 1e-14 against the
    mpmath reference, like the reference-tested a = 50 (tests/series/test_series_reference.py)."""
    gamma, mu, law = 0.1, 0.5, PowerSpring(1.0, 0.5, 50.0)
    start = (0.0, 0.05, 0.02, 0.005)
    tr = simulate(Parameters(gamma, mu, law), Deviations(*start), max_events=1)
    errors = PR.first_impact_errors(gamma, mu, 1.0, 0.5, 50.0, start, law.xi_eq(gamma),
                                    (float(tr.tau[0]), float(tr.xdot[0]), float(tr.xidot[0]), float(tr.eta[0])))
    assert tr.kind_names == ("impact",) and max(errors) <= 1e-14, errors
    for name, value in (("a", 50.5), ("b", 51.0)):
        with pytest.raises(InputError, match=rf"spring {name} must be a finite number \(allowed range: \[0, 50\]"):
            PowerSpring(1.0, **{"a": 0.5, "b": 0.5, name: value})

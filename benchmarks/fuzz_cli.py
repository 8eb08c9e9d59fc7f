"""Large fuzz of the command line and of ``simulate`` over both spring laws (issues 12, 25).

Draws distinct CLI argument vectors and API calls from the strategies of ``tests/fuzzing.py`` (half of each
with the linear spring, half with the power law over its wide range, every number possibly corrupted:
NaN, inf, subnormal, huge), runs each in a worker process within a time bound (``fuzzing.Runner``) and
counts how they fell: clean refusals, valid runs, defects (the contract is in ``tests/fuzzing.py``).

Every defect is listed with the command or call that reproduces it; the exit status is 1 if there is any.
A case with no result within the time bound is run once more with ``--slow-timeout`` (the power law's
supported domain promises each phase within ~10 s of one core, :mod:`bounce.springs.power` item 5, and a
case may ask for 40 phases): it is counted "valid run, slow" when it then passes the contract, a defect
otherwise.

    python benchmarks/fuzz_cli.py                         # 2000 CLI vectors, 300 API calls, 10 s each, seed 25
    python benchmarks/fuzz_cli.py --cli 20000 --api 3000 --seed 7
"""

from __future__ import annotations

import argparse
import dataclasses
import shlex
import sys
import time
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))

import fuzzing  # noqa: E402
from hypothesis import HealthCheck, Phase, given, seed, settings  # noqa: E402

SLOW = "valid run, slow (past the time bound)"


def distinct(strategy, n: int, first_seed: int) -> list:
    """``n`` distinct examples of ``strategy``: hypothesis's generation only (no shrinking), seeded."""
    cases: list = []
    seen: set = set()
    for attempt in range(100):
        @settings(max_examples=n, database=None, phases=[Phase.generate], deadline=None,
                  suppress_health_check=list(HealthCheck))
        @seed(first_seed + attempt)
        @given(strategy)
        def collect(case):
            key = repr(case)
            if key not in seen and len(cases) < n:
                seen.add(key)
                cases.append(case)

        collect()
        if len(cases) == n:
            return cases
    raise RuntimeError(f"only {len(cases)} distinct examples of {strategy!r}")


def command(kind: str, case) -> str:
    """The command or call that reproduces a case."""
    if kind == "cli":
        return "python -m bounce simulate " + shlex.join(case) + " --out run.nc"
    gamma, mu, spec, form, values, n, t_max = case
    make = {"state": "State", "psi": "State.from_psi_xi", "deviations": "Deviations"}[form]
    return (f"simulate(Parameters({gamma!r}, {mu!r}, spring_from_spec({spec!r})), {make}{tuple(values)!r}, "
            f"max_events={n}, t_max={t_max!r})")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cli", type=int, default=2000, help="CLI argument vectors (default 2000)")
    parser.add_argument("--api", type=int, default=300, help="API calls (default 300)")
    parser.add_argument("--timeout", type=float, default=10.0, help="seconds per case (default 10)")
    parser.add_argument("--slow-timeout", type=float, default=900.0,
                        help="seconds for the second run of a case past --timeout (default 900)")
    parser.add_argument("--seed", type=int, default=25, help="seed of the examples (default 25)")
    args = parser.parse_args()

    plan = []
    for kind, count, draw in (("cli", args.cli, fuzzing.command_lines), ("api", args.api, fuzzing.api_cases)):
        for law, power in (("linear", None), ("power", fuzzing.POWER_WIDE)):
            n = count // 2 if law == "linear" else count - count // 2
            plan += [(kind, law, case) for case in distinct(draw(power), n, args.seed)]
    start = time.perf_counter()
    runner = fuzzing.Runner(args.timeout)
    print(f"{len(plan)} cases, worker ready in {time.perf_counter() - start:.1f} s, {args.timeout:g} s per case",
          flush=True)
    tally: Counter = Counter()
    found: dict = {fuzzing.DEFECT: [], SLOW: []}
    slow_runner = fuzzing.Runner(args.slow_timeout)
    try:
        for kind, law, case in plan:
            outcome = runner.run(kind, case)
            verdict = outcome.verdict
            if outcome.what.startswith("no result within"):
                outcome = slow_runner.run(kind, case)
                verdict = SLOW if outcome.verdict == fuzzing.VALID else outcome.verdict
                if verdict == SLOW:
                    outcome = dataclasses.replace(outcome, what=f"{outcome.seconds:.0f} s, {outcome.what}")
            tally[kind, law, verdict] += 1
            if verdict in found:
                found[verdict].append(f"{outcome.what}\n      {command(kind, case)}")
    finally:
        runner.close()
        slow_runner.close()
    seconds = time.perf_counter() - start

    columns = [(kind, law) for kind in ("cli", "api") for law in ("linear", "power")]
    verdicts = (fuzzing.REFUSED, fuzzing.VALID, SLOW, fuzzing.DEFECT)
    print(f"\n{'':40s}" + "".join(f"{kind.upper() + ' ' + law:>12s}" for kind, law in columns) + f"{'all':>8s}")
    for verdict in verdicts:
        row = [tally[kind, law, verdict] for kind, law in columns]
        print(f"{verdict:40s}" + "".join(f"{c:12d}" for c in row) + f"{sum(row):8d}")
    print(f"{'cases':40s}" + "".join(f"{sum(tally[c + (v,)] for v in verdicts):12d}" for c in columns)
          + f"{len(plan):8d}")
    print(f"\n{args.cli} CLI vectors, {args.api} API calls, seed {args.seed}, {args.timeout:g} s per case: "
          f"{seconds:.0f} s")
    for verdict, lines in found.items():
        if lines:
            print(f"\n{verdict} ({len(lines)}):")
            print("\n".join(f"  - {line}" for line in lines))
    return 1 if found[fuzzing.DEFECT] else 0


if __name__ == "__main__":
    sys.exit(main())

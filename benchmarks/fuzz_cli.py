"""Large fuzz of the command line and of ``simulate`` over the whole input domain (issue 12).

Runs the properties of ``tests/test_fuzz.py`` (see its docstring for the contract) with many more
examples than the test suite, and prints how the examples fell: accepted runs, refusals by the
parameter they name, and the time taken.  Exits 1 if hypothesis finds a counterexample (printed).

    python benchmarks/fuzz_cli.py              # 3000 examples per property
    python benchmarks/fuzz_cli.py --examples 20000
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--examples", type=int, default=3000, help="examples per property (default 3000)")
    args = parser.parse_args()
    os.environ["BOUNCE_FUZZ_EXAMPLES"] = str(args.examples)
    os.environ["BOUNCE_HYPOTHESIS_RANDOM"] = "1"  # fresh examples each run (the test suite's are a fixed sequence)
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))
    import test_fuzz  # noqa: E402  (reads BOUNCE_FUZZ_EXAMPLES at import)

    failed = False
    for name in ("test_cli_fuzz", "test_simulate_fuzz"):
        start = time.perf_counter()
        try:
            getattr(test_fuzz, name)()
            verdict = "passed"
        except Exception as exc:  # a counterexample: report it, keep going
            failed = True
            verdict = f"FAILED: {type(exc).__name__}: {exc}"
        print(f"{name}: {args.examples} examples, {time.perf_counter() - start:.1f} s, {verdict}")
    print("outcomes (accepted, or refused by the first word of the message):")
    for key, count in sorted(test_fuzz.OUTCOMES.items(), key=lambda kv: -kv[1]):
        print(f"  {count:7d}  {key}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())

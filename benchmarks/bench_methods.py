"""The table behind the work-precision chart: every method and setting against the exact solver.

Runs :func:`bounce.studies.compare.work_precision` with the ``methods`` section of a config
(``config/config.yaml`` by default, ``--ci`` for the CI-sized sweep; validated and defaulted by
``bounce.pipeline.config`` as in the pipeline; ``--law hertz``: the Hertz study, heyoka against bounce's
power-law solver) and prints, per method and
setting: CPU time of the transient, the relative error of the impact times within the
predictability horizon, the RMS error of y(t), CPU time per impact of the long run, the failure
category, and the CPU ratio to the exact solver measured in the same run.  The machine may be
shared: the ratios are what to quote.

    python benchmarks/bench_methods.py            # full sweep (~1.5 min on one core)
    python benchmarks/bench_methods.py --ci       # seconds
    python benchmarks/bench_methods.py --law hertz
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np
import yaml

from bounce.pipeline.config import validated
from bounce.studies.compare import headline, work_precision
from bounce.studies import study_slice

ROOT = Path(__file__).resolve().parents[1]


def _merge(base: dict, over: dict) -> dict:
    out = dict(base)
    for k, v in over.items():
        out[k] = _merge(out[k], v) if isinstance(v, dict) and isinstance(out.get(k), dict) else v
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ci", action="store_true", help="merge config/ci.yaml (small sweep)")
    parser.add_argument("--law", choices=("linear", "hertz"), default="linear",
                        help="the study's spring law (hertz: methods.work_precision_hertz)")
    args = parser.parse_args()
    config = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    if args.ci:
        config = _merge(config, yaml.safe_load((ROOT / "config" / "ci.yaml").read_text()))
    block = "work_precision" if args.law == "linear" else "work_precision_hertz"
    ds = work_precision(study_slice(validated(config)["methods"], "work_precision", block))
    exact = headline(ds)
    cpu0, per0 = exact["exact_cpu_transient"], exact["exact_cpu_per_impact"]
    print(f"work-precision on scene {ds.attrs['scene']} (gamma = {ds.attrs['gamma']}, mu = {ds.attrs['mu']}); "
          f"errors against the exact solver; ratios = CPU / exact CPU, same run")
    head = f"{'method':<14}{'setting':<52}{'CPU transient':>14}{'ratio':>9}{'err t_1..n_h':>14}{'RMS err y':>11}" \
           f"{'CPU/impact':>12}{'ratio':>9}  failure"
    print(head)
    print("-" * len(head))
    for i in range(ds.sizes["run"]):
        r = ds.isel(run=i)
        cpu, per = float(r["cpu_transient"]), float(r["cpu_per_impact"])
        print(f"{str(r['method'].values):<14}{str(r['setting'].values)[:51]:<52}{cpu:>14.3g}{cpu / cpu0:>9.3g}"
              f"{float(r['err_impact_times']):>14.2g}{float(r['err_y_rms']):>11.2g}{per:>12.3g}"
              f"{per / per0 if np.isfinite(per) else np.nan:>9.3g}  {r['failure'].values or '-'}"
              f"{'' if int(r['failure_index']) < 0 else ' at impact ' + str(int(r['failure_index']))}")
    print()
    for target in (1e-6, 1e-9, 1e-12):
        best = {k: v for k, v in headline(ds, target).items() if isinstance(v, dict)}
        print(f"cheapest per family with impact-time error <= {target:g}: " + json.dumps(
            {k: {"setting": v["setting"], "cpu_ratio_transient": float(f"{v['cpu_ratio_transient']:.3g}"),
                 "cpu_ratio_per_impact": float(f"{v['cpu_ratio_per_impact']:.3g}")} for k, v in best.items()}))


if __name__ == "__main__":
    main()

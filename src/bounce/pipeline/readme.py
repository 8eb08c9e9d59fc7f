"""The README's numbers, written from the pipeline's own outputs so that they cannot go stale.

``snakemake --cores 2 readme`` (on demand, like the thumbnails) rewrites the block of README.md
between the markers ``<!-- numbers:begin -->`` and ``<!-- numbers:end -->`` from

* ``results/checks/*.nc``: the validation counts per kind of claim, errata counted once each (the register's
  distinct entries, by severity, with the rows backing them: :func:`bounce.pipeline.report.kind_table_lines`);
* ``results/methods/horizon.nc``: the float64 predictability horizon per regime;
* ``results/methods/work-precision.nc`` and its timings ``results/timing/methods/work-precision-cpu.nc``:
  the best accuracy each method reached and its CPU time per flight against the exact solver's,
  measured in the same run;
* ``results/timing/pipeline.json`` (``benchmarks/bench_pipeline.py``): wall time, cores and load;
  ``results/timing/**/*.tsv``: the wall time of every job (Snakemake benchmark files; the CPU of a job is the last
  line of its log, ``results/logs/**.log``);
* ``results/timing/bench-simulator.json`` (``benchmarks/bench_simulator.py --json ...``) when present.

Every line names the file it comes from; what a run did not produce is said, never guessed.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import xarray as xr

BEGIN, END = "<!-- numbers:begin -->", "<!-- numbers:end -->"


def _sig(x: float, digits: int = 2) -> str:
    """A number with ``digits`` significant digits, as people write it (1.2e-07, 3400, 0.97)."""
    if not np.isfinite(x):
        return "n/a"
    if x == 0:
        return "0"
    if 1e-3 <= abs(x) < 100:
        return f"{x:.{digits}g}"
    if 100 <= abs(x) < 1e7:  # whole numbers, rounded to ``digits`` significant digits: 3,900
        return f"{round(x, digits - 1 - int(np.floor(np.log10(abs(x))))):,.0f}"
    return f"{x:.{digits - 1}e}"


def validation_lines(results: Path) -> list[str]:
    from .report import check_errata, kind_table_lines, load

    files = sorted((results / "checks").glob("*.nc"))
    if not files:
        return ["- Validation: no `results/checks/*.nc` in this run."]
    reports = load(files, [f.with_name(f"fig-{f.stem}.png") for f in files], results / "report")
    check_errata(reports)
    return ["Validation (`results/report/article/index.html` and `results/report/validation.md`, from "
            "`results/checks/*.nc`):", "", *kind_table_lines(reports)]


def horizon_lines(results: Path) -> list[str]:
    path = results / "methods" / "horizon.nc"
    if not path.exists():
        return []
    with xr.open_dataset(path) as ds:
        h = ds["horizon"].sel(precision="float64")
        parts = [f"{str(r)}: {int(h.sel(regime=r))}" for r in ds["regime"].values]
        tol = ds.attrs.get("tol")
    return [f"- Predictability horizon of float64 (impacts whose times agree with mpmath to {tol:g} relative; "
            f"`results/methods/horizon.nc`): {', '.join(parts)}."]


def work_precision_lines(results: Path) -> list[str]:
    path = results / "methods" / "work-precision.nc"
    timing = results / "timing" / "methods" / "work-precision-cpu.nc"
    if not (path.exists() and timing.exists()):
        return []
    with xr.open_dataset(path) as ds, xr.open_dataset(timing) as tds:
        method = ds["method"].values
        cpu = tds["cpu_per_flight"].values
        err_t = ds["err_impact_times"].values
        err_1 = ds["err_one_step_max"].values
        exact_cpu = float(np.nanmedian(cpu[method == "exact"]))
        lines = [f"- Work-precision on the drop (`results/methods/work-precision.nc`, `results/timing/methods/`, n_h = {int(ds.attrs['n_h'])}; "
                 "best over the settings tried; CPU of a one-flight call relative to the exact solver's in the same run, "
                 "each call's set-up included: not a throughput, for which see \"Speed and accuracy\"):"]
        for m in dict.fromkeys(method):
            if m == "exact":
                continue
            sel = method == m
            i = int(np.nanargmin(np.where(sel, err_1, np.inf)))
            lines.append(f"  - {m}: impact times of the first n_h impacts to {_sig(np.nanmin(err_t[sel]))} at best; "
                         f"one-step error {_sig(err_1[i])} at best, at {_sig(cpu[i] / exact_cpu)}x the exact "
                         "solver's CPU per one-flight call")
    return lines


def pipeline_lines(results: Path) -> list[str]:
    """The recorded whole run (benchmarks/bench_pipeline.py): wall, load, and the exact CPU of every process it started
    (the jobs' benchmark files undercount: Snakemake samples a job's CPU, every 30 s after its first 15 s)."""
    record = results / "timing" / "pipeline.json"
    if not record.exists():
        return ["- Pipeline timing: not measured in this run (`python benchmarks/bench_pipeline.py`)."]
    r = json.loads(record.read_text())
    cpu = (f", {r['cpu_seconds']:.0f} s of CPU over its {r['jobs']} jobs and Snakemake itself"
           if "cpu_seconds" in r else "")
    return [f"- Whole pipeline from an empty results/ (`python benchmarks/bench_pipeline.py`, "
            f"`results/timing/pipeline.json`): {r['wall_seconds']:.0f} s wall on {r['cores']} cores{cpu}, 1-min load "
            f"average {r['load_average_1min_before']:.1f} before and {r['load_average_1min_after']:.1f} after "
            f"({r['cpus_on_machine']} CPUs); outputs {r['outputs_megabytes']:.0f} MB, largest file "
            f"{r['largest_output_megabytes']:.0f} MB."]


def speed_lines(results: Path) -> list[str]:
    path = results / "timing" / "bench-simulator.json"
    if not path.exists():
        return ["- Solver speed: not measured in this run "
                "(`python benchmarks/bench_simulator.py --json results/timing/bench-simulator.json`)."]
    payload = json.loads(path.read_text())
    load = payload.get("loadavg_start") or [float("nan")]
    lines = [f"- Solver speed (`benchmarks/bench_simulator.py`, medians of {payload['args']['repeats']}, "
             f"{payload['pinning']}, load average {load[0]:.1f} at start; `results/timing/bench-simulator.json`):"]
    for r in payload["rows"]:
        lines.append(f"  - scene {r['scene']}, {r['method']}: {_sig(r['rate_median'])} impacts/s over "
                     f"{r['impacts']:,} impacts, {_sig(r['ratio_to_scipy'])}x scipy's rate")
    return lines


def block(results: Path, commit: str) -> str:
    """The generated README block (markdown), from the outputs under ``results``."""
    results = Path(results)
    lines = [BEGIN, f"*Generated by `snakemake --cores 2 readme` from the outputs of commit `{commit[:12]}`; "
             "do not edit by hand.*", ""]
    lines += validation_lines(results) + [""]
    lines += pipeline_lines(results) + horizon_lines(results) + work_precision_lines(results) + speed_lines(results)
    lines.append(END)
    return "\n".join(lines)


def update(readme: Path, text: str) -> None:
    """Replace the marked block of ``readme`` with ``text`` (which carries the markers)."""
    readme = Path(readme)
    old = readme.read_text()
    start, stop = old.find(BEGIN), old.find(END)
    if start < 0 or stop < start:
        raise ValueError(f"{readme}: no block between {BEGIN} and {END}")
    readme.write_text(old[:start] + text + old[stop + len(END):])

"""Wall time of the whole pipeline from an empty results/ (the README's pipeline-time number).

    python benchmarks/bench_pipeline.py [--cores 2] [--configfile config/ci.yaml]

Removes the pipeline's outputs (results/ under the config's workdir), runs ``snakemake --cores N``
once, and writes ``<workdir>/results/timing/pipeline.json``: wall seconds, the CPU seconds of every process
the run started (snakemake, its jobs and their workers: ``getrusage`` of the waited-for children, exact), cores,
the load average before and after (the machine is shared: a number without its load means little), the jobs run
and the size of the outputs.  The README's generated section reads that file.

The jobs' own benchmark files (``results/timing/**.tsv``, ``cpu_time``) undercount long jobs: snakemake samples a
job's CPU every 0.5 s for its first 30 samples (~15 s of wall time), then every 30 s, and keeps the last sample, so a
job of 15-45 s of wall time is recorded with the CPU of its first ~15 s (measured: stability-map's runs alone took
25 s of CPU, its tsv says 15.0).  Their sum is a lower bound; ``cpu_seconds`` here is the total.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import shutil
import subprocess
import sys
import time
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]
OUTPUTS = ("data", "figures", "checks", "methods", "report", "logs", "sweeps", "timing")


def _workdir(configfile: str | None) -> Path:
    workdir = "."
    for path in [ROOT / "config" / "config.yaml"] + ([Path(configfile)] if configfile else []):
        workdir = (yaml.safe_load(path.read_text()) or {}).get("workdir", workdir)
    return ROOT / workdir


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cores", type=int, default=2)
    parser.add_argument("--configfile", default=None, help="extra config (e.g. config/ci.yaml)")
    args = parser.parse_args(argv)
    results = _workdir(args.configfile) / "results"
    for name in OUTPUTS:
        shutil.rmtree(results / name, ignore_errors=True)
    command = [sys.executable, "-m", "snakemake", "--cores", str(args.cores), "--quiet"]
    if args.configfile:
        command += ["--configfile", args.configfile]
    load_before = os.getloadavg()
    cpu_before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.monotonic()
    proc = subprocess.run(command, cwd=ROOT, capture_output=True, text=True)
    wall = time.monotonic() - start
    cpu_after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (cpu_after.ru_utime - cpu_before.ru_utime) + (cpu_after.ru_stime - cpu_before.ru_stime)
    load_after = os.getloadavg()
    if proc.returncode != 0:
        sys.stderr.write(proc.stderr[-3000:])
        return proc.returncode
    size = sum(p.stat().st_size for p in results.rglob("*") if p.is_file())
    record = {
        "wall_seconds": round(wall, 1),
        "cpu_seconds": round(cpu, 1),
        "jobs": sum(1 for _ in (results / "timing").rglob("*.tsv")),
        "cores": args.cores,
        "cpus_on_machine": os.cpu_count(),
        "load_average_1min_before": round(load_before[0], 2),
        "load_average_1min_after": round(load_after[0], 2),
        "configfile": args.configfile or "config/config.yaml",
        "outputs_megabytes": round(size / 1e6, 1),
        "largest_output_megabytes": round(max(p.stat().st_size for p in results.rglob("*") if p.is_file()) / 1e6, 1),
        "python": platform.python_version(),
        "machine": platform.machine(),
    }
    (results / "timing").mkdir(parents=True, exist_ok=True)
    (results / "timing" / "pipeline.json").write_text(json.dumps(record, indent=1) + "\n")
    print(json.dumps(record))
    return 0


if __name__ == "__main__":
    sys.exit(main())

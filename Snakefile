"""bounce: regenerate every figure of Cherubini, Metafune & Paparella, "On the Stopping Time of a
Bouncing Ball", from config/config.yaml, through netCDF datasets.

    snakemake --cores 2                                   # full pipeline -> results/
    snakemake --cores 2 --configfile config/ci.yaml       # the CI-sized run of the same DAG
    snakemake --report results/report/report.html         # browsable HTML report, every figure + caption

Stages (one file each under workflow/rules/): simulate -> sticky -> figures -> checks -> report;
methods (speed against accuracy).
"""

import json
import os
import re
import sys
from pathlib import Path

from snakemake.utils import min_version

from bounce.pipeline.config import ConfigError, load_schema, validated

min_version("8.0")


configfile: Path(workflow.basedir) / "config" / "config.yaml"


report: "workflow/report/workflow.rst"


# The config contract (bounce.pipeline.config): unknown keys, NaN/inf, out-of-range values, unphysical scenes and
# dangling references stop the run here, before any job starts, with one line naming the key.
try:
    _checked = validated(config, load_schema(Path(workflow.basedir) / "config" / "schema.yaml"))
except ConfigError as _err:
    sys.exit(f"config error: {_err}")
config.clear()
config.update(_checked)

# Where results/, logs and .snakemake/ go: "." for the full pipeline, its own folder for the CI-sized
# config, so that a CI-sized run never overwrites the full results (`snakemake --directory DIR` takes
# precedence over it, as the tests do).  The folder is resolved once, by the snakemake the user started,
# and handed to the jobs it spawns in the environment, absolute: a job re-reads this Snakefile from
# another folder.  Under the SLURM executor the batch job starts where the user did (without their
# --directory) and its job step starts a second snakemake (through srun) from the folder the first one
# has already moved into, where a relative `workdir` would be applied twice (ci-run/ci-run/results).
if workflow.is_main_process or "BOUNCE_WORKDIR" not in os.environ:
    # with --directory, snakemake has already moved there
    _run_dir = Path.cwd() if workflow.overwrite_workdir is not None else Path(config["workdir"]).resolve()
    os.environ["BOUNCE_WORKDIR"] = str(_run_dir)


envvars:
    "BOUNCE_WORKDIR",  # passed to the jobs (also by executors that do not share the environment)


workdir: os.environ["BOUNCE_WORKDIR"]


include: "workflow/rules/common.smk"
include: "workflow/rules/simulate.smk"
include: "workflow/rules/sticky.smk"
include: "workflow/rules/figures.smk"
include: "workflow/rules/checks.smk"
include: "workflow/rules/methods.smk"
include: "workflow/rules/docs.smk"
include: "workflow/rules/sweeps.smk"
include: "workflow/rules/hooks.smk"


rule all:
    """Every figure of the paper (PNG and PDF) and the derived datasets behind them."""
    input:
        figure_files(),
        "results/data/sticky-convergence.nc",
        "results/data/sticky-inference.nc",
        "results/report/validation.md",
        "results/report/article",
        [f"results/methods/{name}.nc" for name in STUDIES],
        SWEEP_FILES,
        [gas_scene_file(name) for name in GAS_SCENES],
    default_target: True

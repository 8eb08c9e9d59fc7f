"""bounce: regenerate every figure of Cherubini, Metafune & Paparella, "On the Stopping Time of a
Bouncing Ball", from config/config.yaml, through netCDF datasets.

    snakemake --cores 2                                   # full pipeline -> results/
    snakemake --cores 2 --configfile config/ci.yaml       # the CI-sized run of the same DAG
    snakemake --report results/report/report.html         # browsable HTML report, every figure + caption

Stages (one file each under workflow/rules/): simulate -> sticky -> figures -> checks -> report;
methods (speed against accuracy).
"""

import json
import re
from pathlib import Path

from snakemake.utils import min_version, validate

min_version("8.0")


configfile: Path(workflow.basedir) / "config" / "config.yaml"


report: "workflow/report/workflow.rst"


validate(config, Path(workflow.basedir) / "config" / "schema.yaml")


include: "workflow/rules/common.smk"
include: "workflow/rules/simulate.smk"
include: "workflow/rules/sticky.smk"
include: "workflow/rules/figures.smk"
include: "workflow/rules/checks.smk"
include: "workflow/rules/methods.smk"
include: "workflow/rules/docs.smk"
include: "workflow/rules/sweeps.smk"


rule all:
    """Every figure of the paper (PNG and PDF) and the derived datasets behind them."""
    input:
        figure_files(),
        "results/data/sticky-convergence.nc",
        "results/data/sticky-inference.nc",
        "results/report/validation.md",
        "results/report/validation.html",
        [f"results/methods/{name}.nc" for name in STUDIES],
        SWEEP_FILES,
    default_target: True

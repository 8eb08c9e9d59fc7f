"""Stage 4: every checkable claim of the paper, one claim group per rule -> results/checks/<name>.nc
(numbers and verdicts) + fig-<name>.{png,pdf}; then the validation report.  A group reads only the
datasets it declares (config `checks.<name>.inputs`: scenes, the sticky runs, sweeps' gathered files)
and its own experiments (bounce.checks.base.Experiment: its long simulations, one rule each)."""

from bounce.checks import input_files as check_input_files
from bounce.checks import registry as check_registry

CHECK_GROUPS = check_registry()
#: the configured groups without a figure (bounce.checks.base.Check.plot is None: exact algebra)
FIGURELESS = [name for name in CHECKS if CHECK_GROUPS[name].plot is None]


rule check_experiment:
    """A long simulation of a claim group (bounce.checks.base.Experiment), from the config keys it declares."""
    output:
        "results/data/checks/{name}/{experiment}.nc",
    params:
        spec=lambda w: as_json(CHECK_GROUPS[w.name].experiment(w.experiment).spec(config["checks"][w.name])),
    resources:
        mem_mb=2000,
        runtime=60,
    log:
        "results/logs/checks/{name}/{experiment}.log",
    benchmark:
        "results/timing/checks/{name}/{experiment}.tsv"
    wildcard_constraints:
        name="|".join(re.escape(n) for n in CHECKS),
        experiment="[a-z0-9][a-z0-9-]*",
    shell:
        "python -I \"$BOUNCE_TASK_CLIENT\" check-experiment --name {wildcards.name} --experiment {wildcards.experiment} "
        "--spec {params.spec:q} --out {output} > {log} 2>&1"


rule check:
    """Run one claim group of config `checks` on the datasets it declares (config `checks.<name>.inputs`, in order)
    and on its experiments."""
    input:
        lambda w: check_input_files(w.name, config),
    output:
        nc="results/checks/{name}.nc",
        png=report("results/checks/fig-{name}.png", caption="../report/check.rst", category="Validation checks",
                   labels=lambda w: {"figure": f"results/checks/fig-{w.name}.png", "claim group": w.name}),
        pdf="results/checks/fig-{name}.pdf",
    params:
        spec=lambda w: as_json(config["checks"][w.name]),
    resources:
        mem_mb=4000,
        runtime=60,
    log:
        "results/logs/checks/{name}.log",
    benchmark:
        "results/timing/checks/{name}.tsv"
    wildcard_constraints:
        name="|".join(re.escape(n) for n in CHECKS if n not in FIGURELESS),
    shell:
        "python -I \"$BOUNCE_TASK_CLIENT\" check --name {wildcards.name} --spec {params.spec:q} --inputs {input} "
        "--out {output.nc} {output.png} {output.pdf} > {log} 2>&1"


rule check_without_figure:
    """A claim group without a figure (exact algebra): its numbers and verdicts only."""
    input:
        lambda w: check_input_files(w.name, config),
    output:
        nc="results/checks/{name}.nc",
    params:
        spec=lambda w: as_json(config["checks"][w.name]),
    resources:
        mem_mb=4000,
        runtime=60,
    log:
        "results/logs/checks/{name}.log",
    benchmark:
        "results/timing/checks/{name}.tsv"
    wildcard_constraints:
        name="|".join(re.escape(n) for n in FIGURELESS) or "(?!)",
    shell:
        "python -I \"$BOUNCE_TASK_CLIENT\" check --name {wildcards.name} --spec {params.spec:q} --inputs {input} "
        "--out {output.nc} > {log} 2>&1"


rule report:
    """The validation report (markdown: a table of every claim with its verdict, per-subject verdicts, a section per
    check, the errata) and the replication article (HTML built with Sphinx: the rows organised by the paper's
    sections, the errata, what goes beyond the paper)."""
    input:
        nc=[f"results/checks/{name}.nc" for name in CHECKS],
        png=[f"results/checks/fig-{name}.png" for name in CHECKS if name not in FIGURELESS],
        # every other figure, linked with the paper's figure it reproduces (bounce.pipeline.catalogue.pipeline_figures)
        figures=[f["path"] for f in PIPELINE_FIGURES],
    output:
        md=report("results/report/validation.md", caption="../report/validation.rst", category="Validation report"),
        # the article: a folder, which Snakemake's one-file HTML report cannot hold (it is linked from validation.rst)
        article=directory("results/report/article"),
    params:
        # the subjects' declared order as a list (as_json sorts keys), the sections as a list in the paper's order, the figures
        # with their captions, and the choices the paper leaves open with the config values that make them
        spec=as_json(dict(config["report"], subject_order=list(config["report"]["subjects"]),
                          sections=list(config["report"]["sections"].values()),
                          choices=report_choices(config), figures=PIPELINE_FIGURES, figureless=FIGURELESS)),
    resources:
        mem_mb=1000,
        runtime=10,
    log:
        "results/logs/report.log",
    benchmark:
        "results/timing/report.tsv"
    shell:
        "python -I \"$BOUNCE_TASK_CLIENT\" report --spec {params.spec:q} --inputs {input.nc} --out {output.md} {output.article} "
        "> {log} 2>&1"

"""Stage 3: every figure, from netCDF only -> results/figures/fig-<paper label>.{png,pdf}."""


rule figure:
    """Draw one figure (named after the paper's figure label) from its datasets."""
    input:
        lambda w: FIGURES[w.name][0],
    output:
        png=report("results/figures/fig-{name}.png", caption="../report/figure.rst", category="Figures of the paper"),
        pdf="results/figures/fig-{name}.pdf",
    params:
        spec=lambda w: as_json(FIGURES[w.name][1]),
    resources:
        mem_mb=2000,
        runtime=10,
    log:
        "results/logs/figures/{name}.log",
    benchmark:
        "results/timing/figures/{name}.tsv"
    wildcard_constraints:
        name="|".join(re.escape(n) for n in FIGURES),
    shell:
        "python -m bounce.pipeline.tasks figure --name {wildcards.name} --spec {params.spec:q} "
        "--inputs {input} --out {output.png} {output.pdf} > {log} 2>&1"

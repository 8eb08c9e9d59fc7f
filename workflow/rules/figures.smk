"""Stage 3: every figure, from netCDF only -> results/figures/fig-<paper label or name>.{png,pdf}."""


# figure name -> the label of the paper's figure it reproduces ("": beyond the paper) and its caption
# (bounce.pipeline.catalogue)
FIGURE_CAPTIONS = {f["name"]: f for f in PIPELINE_FIGURES if f["path"] == figure_file("figures", f["name"])}


rule figure:
    """Draw one figure (named after the paper's figure label, or what it shows if beyond the paper) from its datasets."""
    input:
        lambda w: FIGURES[w.name][0],
    output:
        png=report("results/figures/fig-{name}.png", caption="../report/figure.rst",
                   category=lambda w: "Figures of the paper" if FIGURE_CAPTIONS[w.name]["paper"] else "Beyond the paper",
                   labels=lambda w: {"figure": f"results/figures/fig-{w.name}.png",
                                     "reproduces": FIGURE_CAPTIONS[w.name]["paper"] or "beyond the paper"}),
        pdf="results/figures/fig-{name}.pdf",
    params:
        spec=lambda w: as_json(FIGURES[w.name][1]),
        # for the report's caption only (workflow/report/figure.rst)
        paper=lambda w: FIGURE_CAPTIONS[w.name]["paper"],
        caption=lambda w: FIGURE_CAPTIONS[w.name]["caption"],
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
        "python -I \"$BOUNCE_TASK_CLIENT\" figure --name {wildcards.name} --spec {params.spec:q} "
        "--inputs {input} --out {output.png} {output.pdf} > {log} 2>&1"

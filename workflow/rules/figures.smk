"""Stage 3: every figure, from netCDF only -> results/figures/fig-<paper label>.{png,pdf}."""


# datasets a figure reads besides its own (FIGURES): the double-impact run of check restitution and the
# float64 predictability horizon for fig. rest-coeff; the fit range and slopes of check sticky-convergence
EXTRA_FIGURE_INPUTS = {
    "rest-coeff": ["results/checks/restitution.nc", "results/methods/horizon.nc"],
    "sticky-convergence": ["results/checks/sticky-convergence.nc"],
}


rule figure:
    """Draw one figure (named after the paper's figure label) from its datasets."""
    input:
        lambda w: FIGURES[w.name][0] + EXTRA_FIGURE_INPUTS.get(w.name, []),
    output:
        png=report("results/figures/fig-{name}.png", caption="../report/figure.rst", category="Figures of the paper"),
        pdf="results/figures/fig-{name}.pdf",
    params:
        spec=lambda w: as_json(FIGURES[w.name][1]),
    log:
        "results/logs/figures/{name}.log",
    wildcard_constraints:
        name="|".join(re.escape(n) for n in FIGURES),
    shell:
        "python -m bounce.tasks figure --name {wildcards.name} --spec {params.spec:q} "
        "--inputs {input} --out {output.png} {output.pdf} > {log} 2>&1"

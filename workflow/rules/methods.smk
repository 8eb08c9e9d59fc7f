"""Stage 5: speed against accuracy -> results/methods/<study>.nc + fig-<study>.{png,pdf}."""


rule study:
    """One study of bounce.methods (predictability horizon, contact switch, reduced models, least model), reading
    the scene datasets it declares (bounce.studies: Study.scenes)."""
    input:
        lambda w: STUDY_INPUTS[w.name],
    output:
        nc="results/methods/{name}.nc",
        timing="results/timing/methods/{name}-cpu.nc",
        png=report("results/methods/fig-{name}.png", caption="../report/study.rst", category="Speed against accuracy"),
        pdf="results/methods/fig-{name}.pdf",
    params:
        spec=lambda w: as_json(STUDIES[w.name]),
    resources:
        mem_mb=4000,
        runtime=60,
    log:
        "results/logs/methods/{name}.log",
    benchmark:
        "results/timing/methods/{name}.tsv"
    wildcard_constraints:
        name="|".join(re.escape(n) for n in STUDIES),
    shell:
        "python -I \"$BOUNCE_TASK_CLIENT\" study --name {wildcards.name} --spec {params.spec:q} "
        "--out {output.nc} {output.timing} {output.png} {output.pdf} > {log} 2>&1"

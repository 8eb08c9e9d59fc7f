"""Stage 1: one simulation per scene of config `scenes` -> results/data/<scene>.nc."""


rule simulate:
    """Run the exact event-driven simulator on one scene (its config slice only) into netCDF."""
    output:
        "results/data/{scene}.nc",
    params:
        spec=lambda w: as_json(config["scenes"][w.scene]),
    resources:
        mem_mb=2000,
        runtime=20,
    log:
        "results/logs/simulate/{scene}.log",
    benchmark:
        "results/timing/simulate/{scene}.tsv"
    wildcard_constraints:
        scene="|".join(re.escape(s) for s in SCENES),
    shell:
        "python -m bounce.pipeline.tasks scene --name {wildcards.scene} --spec {params.spec:q} --out {output} > {log} 2>&1"

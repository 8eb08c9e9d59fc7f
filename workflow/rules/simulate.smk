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
        "python -I \"$BOUNCE_TASK_CLIENT\" scene --name {wildcards.scene} --spec {params.spec:q} --out {output} > {log} 2>&1"


rule simulate_gas:
    """Run the gas engines (bounce.gas, beyond the paper) on one gas scene (its config slice only) into netCDF."""
    output:
        "results/data/gas/{gas_scene}.nc",
    params:
        spec=lambda w: as_json(config["gas_scenes"][w.gas_scene]),
    resources:
        mem_mb=2000,
        runtime=20,
    log:
        "results/logs/simulate/gas/{gas_scene}.log",
    benchmark:
        "results/timing/simulate/gas/{gas_scene}.tsv"
    wildcard_constraints:
        gas_scene="|".join(re.escape(s) for s in GAS_SCENES) or "^$",
    shell:
        "python -I \"$BOUNCE_TASK_CLIENT\" gas-scene --name {wildcards.gas_scene} --spec {params.spec:q} --out {output} > {log} 2>&1"

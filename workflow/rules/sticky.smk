"""Stage 2: the sticky solutions of section 8.2 (eq. sticky-ic), their eps-convergence and the
inference of the unstated gamma, mu from the paper's t_c = 5.23..."""


rule sticky_run:
    """Simulate eq. sticky-ic for one eps into netCDF."""
    output:
        "results/data/sticky/eps{eps}.nc",
    params:
        spec=sticky_run_spec,
    resources:
        mem_mb=1000,
        runtime=10,
    log:
        "results/logs/sticky/eps{eps}.log",
    benchmark:
        "results/timing/sticky/eps{eps}.tsv"
    shell:
        "python -m bounce.pipeline.tasks scene --name sticky-eps{wildcards.eps} --spec {params.spec:q} --out {output} > {log} 2>&1"


rule sticky_convergence:
    """Impacts in (0, t_c) and RMS distance to the eps = 0 solution (eq. L2-norm), per eps."""
    input:
        STICKY_CONV,
    output:
        "results/data/sticky-convergence.nc",
    params:
        spec=as_json({"samples": STICKY["samples"]}),
    resources:
        mem_mb=2000,
        runtime=10,
    log:
        "results/logs/sticky/convergence.log",
    benchmark:
        "results/timing/sticky/convergence.tsv"
    shell:
        "python -m bounce.pipeline.tasks sticky-convergence --spec {params.spec:q} --inputs {input} --out {output} > {log} 2>&1"


rule sticky_inference:
    """t_c on a (gamma, mu) grid: which parameters give the paper's t_c = 5.23..., how uniquely."""
    output:
        "results/data/sticky-inference.nc",
    params:
        spec=as_json({k: STICKY[k] for k in ("gamma", "mu", "ydot0", "t_c_paper", "inference")}),
    resources:
        mem_mb=2000,
        runtime=30,
    log:
        "results/logs/sticky/inference.log",
    benchmark:
        "results/timing/sticky/inference.tsv"
    shell:
        "python -m bounce.pipeline.tasks sticky-inference --spec {params.spec:q} --out {output} > {log} 2>&1"

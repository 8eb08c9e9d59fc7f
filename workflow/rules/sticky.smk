"""Stage 2: the sticky solutions of section 8.2 (eq. sticky-ic), their eps-convergence and the
inference of the unstated gamma, mu from the paper's t_c = 5.23..."""


rule sticky_runs:
    """Simulate eq. sticky-ic for every eps of config `sticky` into one netCDF each: one job, since a run is much
    shorter than a job's start-up (~1 s of CPU each, when they were one job per eps)."""
    output:
        [sticky_file(eps) for eps in STICKY_EPS],
    params:
        spec=as_json({"gamma": STICKY["gamma"], "mu": STICKY["mu"], "ydot0": STICKY["ydot0"], "eps": STICKY_EPS,
                      "stop": {"events": STICKY["events"], "t_max": STICKY["t_max"]}}),
    resources:
        mem_mb=1000,
        runtime=10,
    log:
        "results/logs/sticky/runs.log",
    benchmark:
        "results/timing/sticky/runs.tsv"
    shell:
        "python -I \"$BOUNCE_TASK_CLIENT\" sticky-runs --spec {params.spec:q} --out {output} > {log} 2>&1"


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
        "python -I \"$BOUNCE_TASK_CLIENT\" sticky-convergence --spec {params.spec:q} --inputs {input} --out {output} > {log} 2>&1"


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
        "python -I \"$BOUNCE_TASK_CLIENT\" sticky-inference --spec {params.spec:q} --out {output} > {log} 2>&1"

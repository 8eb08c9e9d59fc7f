"""Stage 6: parameter studies at scale (config `sweeps`): each sweep is split into `shards` jobs,
each using all its cores (`threads`), gathered into results/sweeps/<name>.nc, and drawn from that
file alone into results/sweeps/fig-<name>.{png,pdf}.  On a cluster (workflow/profiles/slurm) every
shard is one SLURM job with the cores, memory and run time declared below."""

import importlib

SWEEPS = config.get("sweeps", {})
# a sweep's config slice without `threads` (the cores of a job do not change its numbers)
SWEEP_SPEC = {name: {k: v for k, v in spec.items() if k != "threads"} for name, spec in SWEEPS.items()}
SWEEP_SHARDS = {name: [f"results/sweeps/{name}/shard-{k}-of-{int(spec['shards'])}.nc" for k in range(int(spec["shards"]))]
                for name, spec in SWEEPS.items()}
SWEEP_FILES = [f"results/sweeps/{name}.nc" for name in SWEEPS] + [
    f"results/sweeps/fig-{name}.{ext}" for name in SWEEPS for ext in ("png", "pdf")]


rule sweep_shard:
    """One shard of a sweep: its items on all the job's cores (worker processes)."""
    output:
        "results/sweeps/{name}/shard-{shard}-of-{shards}.nc",
    params:
        spec=lambda w: as_json(SWEEP_SPEC[w.name]),
    threads: lambda w: int(SWEEPS[w.name].get("threads", 2))
    resources:
        # workers x the sweep's per-worker peak (bounce.sweeps: memory_mb), plus the job's own process
        mem_mb=lambda w, threads: threads * importlib.import_module("bounce.sweeps").registry()[w.name].memory_mb(
            SWEEP_SPEC[w.name]) + 500,
        runtime=lambda w: int(SWEEPS[w.name].get("shard_minutes", 30)),
    log:
        "results/logs/sweeps/{name}/shard-{shard}-of-{shards}.log",
    benchmark:
        "results/timing/sweeps/{name}/shard-{shard}-of-{shards}.tsv"
    wildcard_constraints:
        name="|".join(re.escape(n) for n in SWEEPS) or "^$",
        shard=r"\d+",
        shards=r"\d+",
    shell:  # parallel over items, not in BLAS: one thread per worker (snakemake's one-thread environment: the task server's)
        "OMP_NUM_THREADS=1 GOTO_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 MKL_NUM_THREADS=1 VECLIB_MAXIMUM_THREADS=1 "
        "NUMEXPR_NUM_THREADS=1 python -I \"$BOUNCE_TASK_CLIENT\" sweep-shard --name {wildcards.name} --spec {params.spec:q} --shard {wildcards.shard} "
        "--workers {threads} --out {output} > {log} 2>&1"


rule sweep_gather:
    """Every shard of a sweep -> results/sweeps/<name>.nc (the same bytes whatever ran the shards), then its figure,
    drawn from that file alone (one job: a figure job of its own was mostly start-up)."""
    input:
        lambda w: SWEEP_SHARDS[w.name],
    output:
        nc="results/sweeps/{name}.nc",
        png=report("results/sweeps/fig-{name}.png", caption="../report/sweep.rst", category="Sweeps"),
        pdf="results/sweeps/fig-{name}.pdf",
    params:
        spec=lambda w: as_json(SWEEP_SPEC[w.name]),
    resources:
        mem_mb=2000,
        runtime=10,
    log:
        "results/logs/sweeps/{name}/gather.log",
    benchmark:
        "results/timing/sweeps/{name}/gather.tsv"
    wildcard_constraints:
        name="|".join(re.escape(n) for n in SWEEPS) or "^$",
    shell:
        "python -I \"$BOUNCE_TASK_CLIENT\" sweep-gather --name {wildcards.name} --spec {params.spec:q} --inputs {input} "
        "--out {output.nc} {output.png} {output.pdf} > {log} 2>&1"


rule sweeps:
    """Every sweep and its figure: `snakemake --cores 2 sweeps` (or a cluster profile)."""
    input:
        SWEEP_FILES,

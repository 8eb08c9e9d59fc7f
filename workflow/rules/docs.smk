"""On demand, not in `all`: what the README shows, from a full run's outputs.

    snakemake --cores 2 thumbnails     # docs/thumbnails/ (committed)
    snakemake --cores 2 readme         # the README's generated block of numbers
"""


rule thumbnails:
    """Shrink every figure PNG to a 480-px-wide thumbnail for the README."""
    input:
        [f"results/figures/fig-{name}.png" for name in FIGURES],
    output:
        [f"docs/thumbnails/fig-{name}.png" for name in FIGURES],
    resources:
        mem_mb=1000,
        runtime=10,
    log:
        "results/logs/docs/thumbnails.log",
    shell:
        "python -I \"$BOUNCE_TASK_CLIENT\" thumbnails --inputs {input} --out {output} > {log} 2>&1"


rule readme:
    """Rewrite the README's generated block (<!-- numbers:begin/end -->) from this run's outputs: validation
    counts per kind, pipeline and job timings, the predictability horizon, work-precision, solver speed."""
    input:
        [f"results/checks/{name}.nc" for name in CHECKS],
        "results/methods/horizon.nc",
        "results/methods/work-precision.nc",
    output:
        touch("results/timing/readme.done"),
    log:
        "results/logs/docs/readme.log",
    shell:
        "python -I \"$BOUNCE_TASK_CLIENT\" readme --inputs results --out README.md > {log} 2>&1"

"""Stage 4 (on demand, not in `all`): README thumbnails, committed under docs/thumbnails/.

    snakemake --cores 2 thumbnails
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
        "python -m bounce.tasks thumbnails --inputs {input} --out {output} > {log} 2>&1"

"""Where the pipeline's files live, written once: ``results/<stage>/<name>.nc`` and the figures beside them.

Stages: ``data`` (scenes, the sticky runs, the claim groups' experiments), ``checks`` (one file per claim
group), ``methods`` (the studies), ``sweeps`` (gathered sweeps), ``figures`` (the paper's figures).  The
rules (``workflow/rules/*.smk``), the figure and study registries, the claim groups' inputs and the report
name files through these functions, relative to the working directory.
"""

from __future__ import annotations

RESULTS = "results"


def dataset(stage: str, name: str) -> str:
    """``results/<stage>/<name>.nc``."""
    return f"{RESULTS}/{stage}/{name}.nc"


def scene_file(name: str) -> str:
    """The dataset of scene ``name`` (rule simulate)."""
    return dataset("data", name)


def sticky_dataset(eps: float) -> str:
    """Name (under ``data``) of one eps run of eq. sticky-ic (tag: 0, 0.001, 1e-06, ...)."""
    return f"sticky/eps{float(eps):g}"


def experiment_file(group: str, experiment: str) -> str:
    """A claim group's own long simulation (rule check_experiment)."""
    return dataset("data", f"checks/{group}/{experiment}")


def figure_file(stage: str, name: str, ext: str = "png") -> str:
    """``results/<stage>/fig-<name>.<ext>``: a paper figure (stage ``figures``), a study's, a sweep's or a
    claim group's figure beside its dataset."""
    return f"{RESULTS}/{stage}/fig-{name}.{ext}"


def gas_scene_file(name: str) -> str:
    """The dataset of gas scene ``name`` (rule simulate_gas; config ``gas_scenes``)."""
    return dataset("data", f"gas/{name}")

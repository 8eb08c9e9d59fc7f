"""The speed-against-accuracy studies of :mod:`bounce.methods`: the registry, one line per study.

A study is ``build(spec) -> xr.Dataset`` plus ``plot(ds, spec, outputs)`` in one module of this package
(contract: :mod:`bounce.studies.base`, registry line ``STUDY = Study(...)``), the slice of the validated config it takes and the scene datasets it reads (declared
inputs of its rule, their paths in the slice).  The Snakefile (``workflow/rules/common.smk``,
``methods.smk``) and the rule entry point (:mod:`bounce.pipeline.tasks`) both read this table.

What a study simulates itself and what it reads: a study runs the methods it compares, the exact
solver included where that run is one of the compared columns (its CPU time in work-precision,
stability-map and contact-switch; the dimer's own r_n and energy curve next to the rigid models in
reduced-vs-dimer); a trajectory it only reads as a reference is a scene, produced by the scene rule
and declared in ``Study.scenes`` (least-model).
"""

from __future__ import annotations

from .._registry import discover, find
from .base import Study


def registry() -> dict[str, Study]:
    """name -> Study for every module of this package that defines ``STUDY`` (or ``STUDIES``)."""
    return discover(__name__, __path__, "STUDY", Study, family="STUDIES")


def get(name: str) -> Study:
    """The study ``name`` (its module when named for it, else every module)."""
    return find(__name__, __path__, "STUDY", Study, name, family="STUDIES")


def study_slices(config: dict) -> dict:
    """name -> the config slice of each study (what its rule receives)."""
    return {name: study.config(config) for name, study in registry().items()}


def study_inputs(config: dict) -> dict:
    """name -> the scene datasets each study reads (its rule's inputs)."""
    from ..paths import scene_file

    return {name: [scene_file(s) for s in study.scenes(config)] for name, study in registry().items()}

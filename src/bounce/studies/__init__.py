"""The speed-against-accuracy studies of :mod:`bounce.methods`: the registry, one line per study.

A study is ``build(spec) -> xr.Dataset`` plus ``plot(ds, spec, outputs)`` in one module of
``bounce.methods``, the slice of the validated config it takes and the scene datasets it reads (declared
inputs of its rule, their paths in the slice).  The Snakefile (``workflow/rules/common.smk``,
``methods.smk``) and the rule entry point (:mod:`bounce.pipeline.tasks`) both read this table.

What a study simulates itself and what it reads: a study runs the methods it compares, the exact
solver included where that run is one of the compared columns (its CPU time in work-precision,
stability-map and contact-switch; the dimer's own r_n and energy curve next to the rigid models in
reduced-vs-dimer); a trajectory it only reads as a reference is a scene, produced by the scene rule
and declared in ``Study.scenes`` (least-model).
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from typing import Callable


@dataclass(frozen=True)
class Study:
    """``module.build(spec)`` makes the dataset, ``module.plot(ds, spec, outputs)`` its figure."""

    module: str
    build: str
    plot: str
    config: Callable[[dict], dict]
    #: what its figure fig-<study> shows (the report's caption; every study is beyond the paper)
    caption: str
    #: the scenes whose datasets (results/data/<scene>.nc, the scene rule's) the study reads
    scenes: Callable[[dict], list] = lambda config: []
    #: the study measures CPU time (budgets, the cheapest model): its dataset and figure are timing files,
    #: not byte-reproducible by design (its CPU seconds also go to results/timing/methods/<study>-cpu.nc)
    timed: bool = False

    def functions(self) -> tuple[Callable, Callable]:
        module = importlib.import_module(self.module)
        return getattr(module, self.build), getattr(module, self.plot)


def scene_file(name: str) -> str:
    """The dataset of scene ``name`` (workflow/rules/simulate.smk)."""
    return f"results/data/{name}.nc"


def _least_model_scenes(config: dict) -> list:
    return list(config["reduced"]["least_model"]["scenes"])


def _least_model_slice(config: dict) -> dict:
    """The least-model settings plus the specs and datasets of the scenes it names (validated to exist)."""
    lm = config["reduced"]["least_model"]
    return dict(lm, scene_specs={name: config["scenes"][name] for name in lm["scenes"]},
                scene_files={name: scene_file(name) for name in lm["scenes"]})


def study_slice(methods: dict, kind: str, block: str | None = None) -> dict:
    """The slice of ``config['methods']`` one study of :mod:`bounce.studies.compare` reads: its block
    (``block``, default ``kind``) under the key ``kind`` and the one scene it names."""
    spec = methods[block or kind]
    return {"scenes": {spec["scene"]: methods["scenes"][spec["scene"]]}, kind: spec}


#: study name -> Study (one line per study)
STUDIES = {
    "horizon": Study("bounce.studies.horizon", "horizon_dataset", "plot_horizon", lambda c: c["reduced"]["horizon"],
                     caption=("Predictability horizon of the float64 solver against mpmath: the impact index"
                              " up to which impact times agree, per damping regime.")),
    "contact-switch": Study("bounce.methods.contact_switch", "switch_study", "plot_switch_study",
                            lambda c: c["reduced"]["switch"],
                            caption=("The contact-switch approximation (a contact rule with threshold delta)"
                                     " against the exact dimer, as delta -> 0.")),
    "reduced-vs-dimer": Study("bounce.studies.reduced", "reduced_vs_dimer", "plot_reduced_vs_dimer",
                              lambda c: c["reduced"]["vs_dimer"],
                              caption=("Rigid-ball models (constant r, eq. onefifth-rest-coeff, eq. our-r, "
                                       "time of contact) against the dimer on the paper's drops.")),
    "least-model": Study("bounce.studies.reduced", "least_model", "plot_least_model", _least_model_slice,
                         scenes=_least_model_scenes, timed=True,
                         caption=("The cheapest model meeting an explicit tolerance on each scene's quantity"
                                  " of interest.")),
    "work-precision": Study("bounce.studies.compare", "work_precision", "plot_work_precision",
                            lambda c: study_slice(c["methods"], "work_precision"), timed=True,
                            caption=("Work-precision of general-purpose methods (solve_ivp, penalty DEM, "
                                     "Moreau-Jean, heyoka) on the fig. rigid-fall drop.")),
    "stability-map": Study("bounce.studies.compare", "stability_map", "plot_stability_map",
                           lambda c: study_slice(c["methods"], "stability_map"), timed=True,
                           caption=("Where each general-purpose method stops on the fig. rigid-fall drop, "
                                    "and why.")),
    "work-precision-hertz": Study("bounce.studies.compare", "work_precision", "plot_work_precision",
                                  lambda c: study_slice(c["methods"], "work_precision", "work_precision_hertz"), timed=True,
                                  caption=("Work-precision of heyoka against bounce's power-law solver on "
                                           "the Hertz drop (a = b = 1/2).")),
    "stability-map-hertz": Study("bounce.studies.compare", "stability_map", "plot_stability_map",
                                 lambda c: study_slice(c["methods"], "stability_map", "stability_map_hertz"), timed=True,
                                 caption="Where heyoka stops on the Hertz drop (a = b = 1/2), and why."),
}


def study_slices(config: dict) -> dict:
    """name -> the config slice of each study (what its rule receives)."""
    return {name: study.config(config) for name, study in STUDIES.items()}


def study_inputs(config: dict) -> dict:
    """name -> the scene datasets each study reads (its rule's inputs)."""
    return {name: [scene_file(s) for s in study.scenes(config)] for name, study in STUDIES.items()}

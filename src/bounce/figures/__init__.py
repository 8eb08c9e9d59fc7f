"""The figures: one module per group, one line per figure in :data:`FIGURES` (the registry the
Snakefile reads).  A figure function ``draw(datasets, spec, outputs)`` reads netCDF datasets only;
its registry line says which datasets it reads and which config slice it takes, as functions of the
validated config (names of datasets under ``results/data/``).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial
from typing import Callable

from . import asymptotics, contacts, sticky, trajectories


def _one(fn):
    """Adapt a single-dataset figure function to the list-of-datasets calling convention."""
    return lambda datasets, spec, outputs: fn(datasets[0], spec, outputs)


@dataclass(frozen=True)
class Figure:
    """``draw(datasets, spec, outputs)``; ``inputs(config)`` dataset names; ``spec(config)`` its slice."""

    draw: Callable
    inputs: Callable[[dict], list]
    spec: Callable[[dict], dict]


def _scene_figure(draw, key: str) -> Figure:
    """A figure of one scene, configured by ``config["figures"][key]`` (which names the scene)."""
    return Figure(_one(draw), lambda c: [c["figures"][key]["scene"]], lambda c: c["figures"][key])


def _sticky_runs(config: dict) -> list:
    return [sticky_dataset(eps) for eps in config["sticky"]["eps_traj"]]


def sticky_dataset(eps: float) -> str:
    """Dataset name of one eps run of eq. sticky-ic (tag: 0, 0.001, 1e-06, ...)."""
    return f"sticky/eps{float(eps):g}"


_ASYMPTOTIC = lambda c: ["asymptotic-underdamped", "asymptotic-overdamped"]  # noqa: E731
_NONE = lambda c: {}  # noqa: E731

#: figure name (the paper's figure label) -> Figure: the registry, one line per figure
FIGURES = {
    "rigid-fall": _scene_figure(trajectories.rigid_fall, "rigid-fall"),
    "rest-coeff": _scene_figure(contacts.rest_coeff, "rest-coeff"),
    "very_rigid_poincare": _scene_figure(partial(contacts.contact_portrait, magnified=False), "very_rigid_poincare"),
    "very_rigid_poincare_magni": _scene_figure(partial(contacts.contact_portrait, magnified=True), "very_rigid_poincare"),
    "very_rigid_poincare_overdamped": _scene_figure(partial(contacts.contact_portrait, magnified=False),
                                                    "very_rigid_poincare_overdamped"),
    "very_rigid_poincare_overdamped_magni": _scene_figure(partial(contacts.contact_portrait, magnified=True),
                                                          "very_rigid_poincare_overdamped"),
    "sticky-traj": Figure(trajectories.sticky_traj, _sticky_runs, lambda c: {"t_end": c["sticky"]["t_max"]}),
    "sticky-convergence": Figure(_one(sticky.sticky_convergence), lambda c: ["sticky-convergence"], _NONE),
    "sticky-inference": Figure(_one(sticky.sticky_inference), lambda c: ["sticky-inference"], _NONE),
    "energy-decay": Figure(asymptotics.energy_decay, _ASYMPTOTIC, _NONE),
    "asymptotic-laws": Figure(asymptotics.asymptotic_laws, _ASYMPTOTIC, _NONE),
}


def figure_table(config: dict) -> dict:
    """name -> (input dataset paths, spec) for the Snakefile; the spec carries the figure's ``label``."""
    return {name: ([f"results/data/{d}.nc" for d in fig.inputs(config)], dict(fig.spec(config), label=name))
            for name, fig in FIGURES.items()}

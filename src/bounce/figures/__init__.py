"""The figures: one module per group, one line per figure in :data:`FIGURES` (the registry the
Snakefile reads).  A figure function ``draw(datasets, spec, outputs)`` reads netCDF datasets only;
its registry line says which files it reads and which config slice it takes, as functions of the
validated config (files named relative to ``results/`` without ``.nc``: ``data/<scene>``,
``checks/<claim group>``, ``methods/<study>``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from . import asymptotics, contacts, sticky, trajectories


def _one(fn):
    """Adapt a single-dataset figure function to the list-of-datasets calling convention."""
    return lambda datasets, spec, outputs: fn(datasets[0], spec, outputs)


@dataclass(frozen=True)
class Figure:
    """``draw(datasets, spec, outputs)``; ``inputs(config)`` the files it reads; ``spec(config)`` its slice."""

    draw: Callable
    inputs: Callable[[dict], list]
    spec: Callable[[dict], dict]


def sticky_dataset(eps: float) -> str:
    """Dataset name of one eps run of eq. sticky-ic (tag: 0, 0.001, 1e-06, ...)."""
    return f"sticky/eps{float(eps):g}"


def _scene_figure(draw, key: str, *extra: str) -> Figure:
    """A figure of the scene named by ``config["figures"][key]`` (plus ``extra`` files), configured there."""
    return Figure(draw, lambda c: [f"data/{c['figures'][key]['scene']}", *extra], lambda c: c["figures"][key])


def _files(*names: str) -> Callable[[dict], list]:
    return lambda c: list(names)


_ASYMPTOTIC = _files("data/asymptotic-underdamped", "data/asymptotic-overdamped")
_NONE = lambda c: {}  # noqa: E731

#: figure name (the paper's figure label) -> Figure: the registry, one line per figure
FIGURES = {
    "rigid-fall": _scene_figure(_one(trajectories.rigid_fall), "rigid-fall"),
    # r_n while the impacts pair up (check restitution) and the float64 horizon (study horizon)
    "rest-coeff": _scene_figure(contacts.rest_coeff, "rest-coeff", "checks/restitution", "methods/horizon"),
    "very_rigid_poincare": _scene_figure(_one(contacts.contact_portrait), "very_rigid_poincare"),
    "very_rigid_poincare_magni": _scene_figure(_one(contacts.contact_portrait_magni), "very_rigid_poincare"),
    "very_rigid_poincare_overdamped": _scene_figure(_one(contacts.contact_portrait), "very_rigid_poincare_overdamped"),
    "very_rigid_poincare_overdamped_magni": _scene_figure(_one(contacts.contact_approach_magni),
                                                          "very_rigid_poincare_overdamped"),
    "sticky-traj": Figure(trajectories.sticky_traj,
                          lambda c: [f"data/{sticky_dataset(e)}" for e in c["sticky"]["eps_traj"]],
                          lambda c: {"t_end": c["sticky"]["t_max"]}),
    # the report's fit range and slopes come from check sticky-convergence
    "sticky-convergence": Figure(sticky.sticky_convergence, _files("data/sticky-convergence", "checks/sticky-convergence"),
                                 _NONE),
    "sticky-inference": Figure(_one(sticky.sticky_inference), _files("data/sticky-inference"), _NONE),
    "energy-decay": Figure(asymptotics.energy_decay, _ASYMPTOTIC, _NONE),
    "asymptotic-laws": Figure(asymptotics.asymptotic_laws, _ASYMPTOTIC, _NONE),
}


def figure_table(config: dict) -> dict:
    """name -> (input paths, spec) for the Snakefile; the spec carries the figure's ``label``."""
    return {name: ([f"results/{f}.nc" for f in fig.inputs(config)], dict(fig.spec(config), label=name))
            for name, fig in FIGURES.items()}

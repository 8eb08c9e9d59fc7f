"""The figures: one module per group, one line per figure in :data:`FIGURES` (the registry the
Snakefile reads).  A figure function ``draw(datasets, spec, outputs)`` reads netCDF datasets only;
its registry line says which files it reads and which config slice it takes, as functions of the
validated config (files named relative to ``results/`` without ``.nc``: ``data/<scene>``,
``checks/<claim group>``, ``methods/<study>``), and which figure of the paper it reproduces, with
that figure's caption (:class:`Caption`; the report prints it next to the link).  The figures of
the other stages are beyond the paper; their captions are the study's ``caption``
(:mod:`bounce.studies`) and the sweep's ``title`` (:mod:`bounce.sweeps`), and
:func:`bounce.pipeline.catalogue.pipeline_figures` lists them all.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from ..paths import sticky_dataset
from . import asymptotics, contacts, gases, sticky, trajectories


def _one(fn):
    """Adapt a single-dataset figure function to the list-of-datasets calling convention."""
    return lambda datasets, spec, outputs: fn(datasets[0], spec, outputs)


@dataclass(frozen=True)
class Caption:
    """``paper``: the label of the paper's figure reproduced ("" when the figure is beyond the paper);
    ``text``: the paper's caption (as printed, labels as in the LaTeX source) or what the figure shows."""

    paper: str
    text: str


def _beyond(text: str) -> Caption:
    return Caption("", text)


@dataclass(frozen=True)
class Figure:
    """``draw(datasets, spec, outputs)``; ``inputs(config)`` the files it reads; ``spec(config)`` its slice;
    ``caption`` the paper's figure it reproduces."""

    draw: Callable
    inputs: Callable[[dict], list]
    spec: Callable[[dict], dict]
    caption: Caption


def _scene_figure(draw, key: str, *extra: str, caption: Caption) -> Figure:
    """A figure of the scene named by ``config["figures"][key]`` (plus ``extra`` files), configured there."""
    return Figure(draw, lambda c: [f"data/{c['figures'][key]['scene']}", *extra], lambda c: c["figures"][key], caption)


def _files(*names: str) -> Callable[[dict], list]:
    return lambda c: list(names)


_ASYMPTOTIC = _files("data/asymptotic-underdamped", "data/asymptotic-overdamped")
_NONE = lambda c: {}  # noqa: E731

_POINCARE = ("The dots represent the state of the system immediately after a contact with the floor (that is, "
             "x = 0) for the simulation of figure (fig:rest-coeff). The equilibrium position of the upper point mass "
             "is y_eq = 1 - 2 gamma. The thin lines have the sole purpose of making evident the temporal sequence of "
             "states.")

#: figure name (the paper's figure label) -> Figure: the registry, one line per figure
FIGURES = {
    "gas-spacetime": Figure(_one(gases.spacetime), lambda c: [f"data/gas/{c['figures']['gas-spacetime']['gas_scene']}"],
                            lambda c: c["figures"]["gas-spacetime"], _beyond(
        "World lines of the grains of a gas scene (beyond the paper: the dimer gas of the introduction's motivation; "
        "McNamara and Young's space-time diagram of clustering).")),
    "rigid-fall": _scene_figure(_one(trajectories.rigid_fall), "rigid-fall", caption=Caption(
        "fig:rigid-fall", "Numerical simulation with initial conditions xi(0) = xi'(0) = psi'(0) = 0, psi(0) = 6, and "
        "gamma = mu = 0.01. The upper curve is y(t), the lower curve is x(t). The solid dots show the instants when "
        "there is an impact. The inset magnifies the region within the dashed rectangle.")),
    # r_n while the impacts pair up (check restitution) and the float64 horizon (study horizon)
    "rest-coeff": _scene_figure(contacts.rest_coeff, "rest-coeff", "checks/restitution", "methods/horizon",
                                caption=Caption(
        "fig:rest-coeff", "Restitution coefficient computed using the definition (eq:Falcon-rest-coeff) from a "
        "simulation with gamma = 1e-5, mu = 1e-2, and initial conditions xi(0) = xi'(0) = psi'(0) = 0, psi(0) = 0.25.")),
    "very_rigid_poincare": _scene_figure(contacts.contact_portrait, "very_rigid_poincare", "methods/horizon",
                                         caption=Caption("fig:very_rigid_poincare", _POINCARE)),
    "very_rigid_poincare_magni": _scene_figure(contacts.contact_portrait_magni, "very_rigid_poincare", "methods/horizon",
                                               caption=Caption("fig:very_rigid_poincare_magni",
                                                               "Magnification of the figure (fig:very_rigid_poincare), "
                                                               "close to (0,0,0).")),
    "very_rigid_poincare_overdamped": _scene_figure(contacts.contact_portrait, "very_rigid_poincare_overdamped", "methods/horizon",
                                                    caption=Caption("fig:very_rigid_poincare_overdamped",
                                                                    "Same as figure (fig:very_rigid_poincare), but with "
                                                                    "mu = 2.")),
    "very_rigid_poincare_overdamped_magni": _scene_figure(contacts.contact_approach_magni,
                                                          "very_rigid_poincare_overdamped", "methods/horizon", caption=Caption(
        "fig:very_rigid_poincare_overdamped_magni",
        "Magnification of figure (fig:very_rigid_poincare_overdamped), close to (0,0,0).")),
    "sticky-traj": Figure(trajectories.sticky_traj,
                          lambda c: [f"data/{sticky_dataset(e)}" for e in c["sticky"]["eps_traj"]],
                          lambda c: {"t_end": c["sticky"]["t_max"]}, Caption(
        "fig:sticky-traj", "Simulations using the initial conditions (eq:sticky-ic) for three different values of "
        "epsilon. Solid dots mark the times of impact. In the panel epsilon = 0, in the interval between the first two "
        "solid dots, the lower point mass is in contact with the floor.")),
    # the report's fit range and slopes come from check sticky-convergence
    "sticky-convergence": Figure(sticky.sticky_convergence, _files("data/sticky-convergence", "checks/sticky-convergence"),
                                 _NONE, Caption(
        "fig:sticky-convergence", "Number of impacts performed by the lower point mass in the interval (0, t_c) and "
        "root mean squared difference (eq:L2-norm) as function of epsilon.")),
    "sticky-inference": Figure(_one(sticky.sticky_inference), _files("data/sticky-inference"), _NONE, _beyond(
        "The paper does not give gamma, mu for figs. sticky-traj and sticky-convergence: t_c(gamma, mu) of the "
        "eps = 0 sticky phase and the band of t_c = 5.23..., through the values the scenes use.")),
    "energy-decay": Figure(asymptotics.energy_decay, _ASYMPTOTIC, _NONE, _beyond(
        "E - E_m against time (exponential at the rate of check static-equilibrium) and against the impact index, "
        "under- and over-damped (Theorem static-equilibrium).")),
    "asymptotic-laws": Figure(asymptotics.asymptotic_laws, _ASYMPTOTIC, _NONE, _beyond(
        "n tau_n mu/3 and n Xdot_n mu/(3 gamma) to 1e6 impacts: the laws of Theorem main_thm approached.")),
}

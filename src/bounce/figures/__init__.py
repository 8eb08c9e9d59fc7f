"""Figure functions: ``FIGURES[name](datasets, spec, outputs)``; they read netCDF datasets only."""

from __future__ import annotations

from . import asymptotics, contacts, sticky, trajectories


def _one(fn):
    """Adapt a single-dataset figure function to the list-of-datasets calling convention."""
    return lambda datasets, spec, outputs: fn(datasets[0], spec, outputs)


FIGURES = {
    "rigid-fall": _one(trajectories.rigid_fall),
    "rest-coeff": contacts.rest_coeff,
    "very_rigid_poincare": _one(contacts.contact_portrait),
    "very_rigid_poincare_magni": _one(contacts.contact_portrait_magni),
    "very_rigid_poincare_overdamped": _one(contacts.contact_portrait),
    "very_rigid_poincare_overdamped_magni": _one(contacts.contact_approach_magni),
    "sticky-traj": trajectories.sticky_traj,
    "sticky-convergence": sticky.sticky_convergence,
    "sticky-inference": _one(sticky.sticky_inference),
    "energy-decay": asymptotics.energy_decay,
    "asymptotic-laws": asymptotics.asymptotic_laws,
}

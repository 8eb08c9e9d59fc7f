"""Claim group sticky-convergence on real per-eps runs (small): every row but unstated-parameters (an identity) is
decided there, none is refuted, and every falsifier flips its row; rms-quadrature in particular, which the synthetic
inputs of tests/checks/test_claims.py (no per-eps runs) leave not checkable."""

from __future__ import annotations

import functools

import numpy as np
import xarray as xr

from bounce.analysis import theory
from bounce.analysis.sticky import convergence
from bounce.checks import registry
from bounce.checks.base import NOT_REPRODUCED, REPRODUCED, falsify, unflipped
from bounce.scenes import scene_dataset
from checks.test_claims import spec

G, MU, YDOT0 = 0.01, 0.01, -0.1


@functools.cache
def _inputs() -> tuple:
    """sticky-convergence.nc, sticky-inference.nc and the runs, as the pipeline makes them, for eps in 1e-2 .. 1e-4."""
    runs = [scene_dataset({"gamma": G, "mu": MU, "initial": {"sticky": {"eps": e, "ydot": YDOT0}},
                           "stop": {"events": 20000, "t_max": 12.0}}, f"eps{e:g}") for e in (0.0, 1e-2, 1e-3, 1e-4)]
    conv = convergence(runs[0], runs[1:], 20001)  # the pipeline's grid (config sticky.samples)
    g = np.linspace(0.005, 0.015, 3)
    m = np.array([0.0, 0.02])
    inf = xr.Dataset({"t_c": (("gamma", "mu"), np.array([[theory.t_c(gi, mi) for mi in m] for gi in g]))},
                     coords={"gamma": g, "mu": m}, attrs={"ydot0": YDOT0, "t_c_paper": 5.23})
    return (conv, inf, *runs)


def test_rms_quadrature_is_decided_and_flips():
    group = registry()["sticky-convergence"]
    sp = spec("sticky-convergence")
    true_rows = group.verdicts(group.measure(sp, list(_inputs())), sp, only="rms-quadrature")
    assert [v.verdict for v in true_rows] == [REPRODUCED], true_rows
    doctored = falsify(group, "rms-quadrature", sp, list(_inputs()))
    assert [v.verdict for v in doctored] == [NOT_REPRODUCED] and not unflipped(true_rows, doctored)


def test_every_falsifier_flips_on_real_runs():
    """test_claims.py's test_claim and test_falsifier_flips on these inputs: no row refuted, every row but the identity
    decided, and each falsifier flips its rows."""
    group = registry()["sticky-convergence"]
    sp = spec("sticky-convergence")
    m = group.measure(sp, list(_inputs()))
    for c in group.claims:
        true_rows = group.verdicts(m, sp, only=c.id)
        assert all(v.verdict == REPRODUCED for v in true_rows) or c.falsifier is None, true_rows
        if c.falsifier is not None:
            assert not unflipped(true_rows, falsify(group, c.id, sp, list(_inputs()))), c.id

"""Section 8.2: convergence of eps-solutions to the sticky solution, and the inference of gamma, mu.

Both produce small netCDF datasets for the figures and the report.  The
convergence study reads the per-eps event datasets only (closed-form samples).
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from .fitting import fit_loglog  # noqa: F401 (one fit; bounce.figures.sticky imports it from here)
from ..io import sample_dataset
from ..kinds import DETACH, IMPACT, STICKY_START
from ..model import Parameters, State
from ..simulate import simulate



def sticky_duration(gamma: float, mu: float, ydot0: float = -0.1) -> float:
    """t_c: duration of the sticky phase of eq. sticky-ic with eps = 0 (nan if it never ends)."""
    p = Parameters(gamma, mu)
    tr = simulate(p, State.sticky_ic(p, eps=0.0, ydot0=ydot0), max_events=2)
    if len(tr) == 2 and tr.kind[1] == DETACH:
        return float(tr.t[1])
    return float("nan")


def t_c_map(spec: dict) -> xr.Dataset:
    """t_c on a (gamma, mu) grid, and where it rounds to the paper's 5.23."""
    g = np.linspace(*spec["inference"]["gamma"], spec["inference"]["n"])
    m = np.linspace(*spec["inference"]["mu"], spec["inference"]["n"])
    tc = np.array([[sticky_duration(gi, mi, spec["ydot0"]) for mi in m] for gi in g])
    t_paper = float(spec["t_c_paper"])
    chosen = sticky_duration(spec["gamma"], spec["mu"], spec["ydot0"])
    return xr.Dataset(
        {"t_c": (("gamma", "mu"), tc, {"long_name": "duration of the eps = 0 sticky phase (eq. sticky-ic)", "units": "1"}),
         "matches_paper": (("gamma", "mu"), (np.floor(tc * 100) / 100 == t_paper).astype(np.int8),
                           {"long_name": "t_c truncates to the paper's 5.23", "units": "1", "flag_values": [0, 1],
                            "flag_meanings": "no yes"})},
        coords={"gamma": ("gamma", g, {"long_name": "gamma", "units": "1"}),
                "mu": ("mu", m, {"long_name": "mu", "units": "1"})},
        attrs={"title": "Which (gamma, mu) give the paper's t_c = 5.23...", "ydot0": spec["ydot0"],
               "t_c_paper": t_paper, "gamma_chosen": spec["gamma"], "mu_chosen": spec["mu"],
               "t_c_chosen": chosen, "Conventions": "CF-1.10"},
    )


def convergence(reference: xr.Dataset, runs: list[xr.Dataset], samples: int) -> xr.Dataset:
    """Impacts in (0, t_c) and the RMS difference ||y_eps - y_s|| of eq. L2-norm, per eps.

    t_c is the detach time of the eps = 0 ``reference``.  The norm is integrated by
    the trapezoid rule on ``samples`` points of [0, t_c] (y is C^1, so the error is
    O(h^2); the report checks it against a grid twice as fine).
    """
    kinds = reference["kind"].values
    if kinds.size < 2 or kinds[0] != STICKY_START or kinds[1] != DETACH:
        raise ValueError("the eps = 0 reference must start sticky at t = 0 and detach")
    t_c = float(reference["t"].values[1])
    grid = np.linspace(0.0, t_c, int(samples))
    y_s = sample_dataset(reference, grid)["y_minus_yeq"]
    eps, n_imp, rms = [], [], []
    for ds in runs:
        eps.append(float(ds.attrs["xdot0"]))
        t = ds["t"].values
        n_imp.append(int(np.count_nonzero((ds["kind"].values == IMPACT) & (t > 0) & (t < t_c))))
        if float(ds.attrs["t_valid"]) < t_c:
            raise ValueError(f"eps = {eps[-1]}: simulation stops at t = {ds.attrs['t_valid']} < t_c; raise sticky.events")
        d = sample_dataset(ds, grid)["y_minus_yeq"] - y_s
        rms.append(float(np.sqrt(np.trapezoid(d * d, grid) / t_c)))
    order = np.argsort(eps)
    return xr.Dataset(
        {"n_impacts": ("eps", np.array(n_imp)[order], {"long_name": "impacts of the lower mass in (0, t_c)", "units": "1"}),
         "rms": ("eps", np.array(rms)[order], {"long_name": "RMS difference ||y_eps - y_s|| on (0, t_c) (eq. L2-norm)", "units": "1"})},
        coords={"eps": ("eps", np.array(eps)[order], {"long_name": "initial lower-mass speed eps (eq. sticky-ic)", "units": "1"})},
        attrs={"title": "Convergence of eps-solutions to the sticky solution (fig. sticky-convergence)",
               "t_c": t_c, "gamma": reference.attrs["gamma"], "mu": reference.attrs["mu"], "samples": int(samples),
               "Conventions": "CF-1.10"},
    )

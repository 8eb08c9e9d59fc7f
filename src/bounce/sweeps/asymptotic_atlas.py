"""Sweep ``asymptotic-atlas``: the limits of Theorem main_thm over a (mu, gamma) grid, and the transient.

For every cell (mu, gamma) of a log-spaced grid, the drop from psi(0) = ``psi0`` (xi = 0, at
rest) is simulated for ``events`` events and, for each q_n of the check ``main-theorem``
(n tau_n mu/3 of Theorem main_thm, n Xdot_n mu/(3 gamma) via Lemma Giorgio's, and the other
limits of its proof), the limit L of q_n is fitted with its error and decay exponent (:func:`bounce.analysis.fitting.fit_limit`: corrections
of the map eq. restituzione plus the sticky spring's relaxation; the fit's error is the
largest change of L under window and model variants).  The transient is the first n after
which |q_n - 1| < ``transient`` for good (:func:`bounce.analysis.fitting.transient_length`).
The theorem predicts L = 1 in every cell; a NaN limit means no fit window of a decade
after the transient within ``events`` (slow over-damped relaxation, n^{-3 lam/mu}).

The check ``main-theorem`` judges its atlas claims on this gathered file (a declared input, config
``checks.main-theorem.inputs``); the quantities are defined once, in :mod:`bounce.analysis.observables`.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from ..analysis.observables import QUANTITIES, QUANTITY_CLAIMS, series_quantities, trajectory_series
from ..analysis.fitting import fit_limit, transient_length
from ..model import Parameters, State
from ..simulate import simulate
from .base import ITEM, Sweep, axis, log_edges

NAME = "asymptotic-atlas"
QUANTITY_LABELS = {q: QUANTITY_CLAIMS[q][0] for q in QUANTITIES}
FIT_KEYS = ("limit", "limit_err", "exponent", "exponent_err")



def size(spec: dict) -> int:
    return int(spec["mu"]["n"]) * int(spec["gamma"]["n"])


def prepare(spec: dict, items: np.ndarray) -> dict:
    """(mu, gamma) of each cell: item k is (mu_i, gamma_j) with k = i * n_gamma + j."""
    mus, gammas = axis(spec["mu"]), axis(spec["gamma"])
    i, j = np.divmod(np.asarray(items, dtype=np.int64), gammas.size)
    return {"mu": mus[i], "gamma": gammas[j]}


def compute(spec: dict, inputs: dict) -> dict:
    fit = spec["fit"]  # the limit fit of check main-theorem; defaults in config/schema.yaml
    m = len(inputs["mu"])
    out = {k: np.full((m, len(QUANTITIES)), np.nan) for k in (*FIT_KEYS, "transient")}
    out["n_events"] = np.zeros(m, dtype=np.int64)
    start = State.from_psi_xi(float(spec["psi0"]), 0.0, 0.0, 0.0)
    for c in range(m):
        mu, gamma = float(inputs["mu"][c]), float(inputs["gamma"][c])
        traj = simulate(Parameters(gamma, mu), start, max_events=int(spec["events"]))
        s = trajectory_series(traj)
        qs = series_quantities(s)
        out["n_events"][c] = len(traj)
        for k, name in enumerate(QUANTITIES):
            f = fit_limit(s["n"], s["t"], qs[name], mu, fit)
            for key in FIT_KEYS:
                out[key][c, k] = f[key]
            out["transient"][c, k] = transient_length(s["n"], qs[name], float(spec["transient"]))
        del traj, s, qs
    return out


_Q = (ITEM, "quantity")
VARIABLES = {
    "limit": (_Q, "fitted limit L of q_n (Theorem main_thm: L = 1)", "1", None),
    "limit_err": (_Q, "error of L: largest change under window/model variants, or the LSQ error", "1", None),
    "exponent": (_Q, "fitted decay exponent p of q_n - L ~ n^-p", "1", None),
    "exponent_err": (_Q, "error of the decay exponent", "1", None),
    "transient": (_Q, "transient length: first impact n after which |q_n - 1| < transient for good", "1",
                  "inf: not settled within the simulated events"),
    "n_events": ((ITEM,), "events simulated", "1", None),
}


def finish(ds: xr.Dataset, spec: dict) -> xr.Dataset:
    """The items reshaped to the (mu, gamma) grid, with coordinates and the settings in the attributes."""
    mus, gammas = axis(spec["mu"]), axis(spec["gamma"])
    shape = (mus.size, gammas.size)
    out = xr.Dataset(attrs=dict(ds.attrs))
    for name, var in ds.data_vars.items():
        values = var.values.reshape(shape + var.shape[1:])
        out[name] = xr.Variable(("mu", "gamma") + var.dims[1:], values, var.attrs)
    out = out.assign_coords(
        mu=xr.Variable(("mu",), mus, {"long_name": "damping mu = nu / sqrt(2 k m)", "units": "1"}),
        gamma=xr.Variable(("gamma",), gammas, {"long_name": "gravity gamma = g m / (2 L k)", "units": "1"}),
        quantity=xr.Variable(("quantity",), np.array(QUANTITIES, dtype=object),
                             {"long_name": "q_n: " + "; ".join(f"{k} = {v}" for k, v in QUANTITY_LABELS.items())}),
    )
    out.attrs.update(psi0=float(spec["psi0"]), events=int(spec["events"]), transient_threshold=float(spec["transient"]))
    return out



def plot(ds: xr.Dataset, spec: dict, outputs) -> None:
    """|L - 1| of both constants and the transient length of n tau_n mu / 3 over (mu, gamma)."""
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm
    from matplotlib.ticker import NullFormatter

    from ..figures.common import WIDTH, save, tex_num

    mu, gamma = ds["mu"].values, ds["gamma"].values
    fig, axes = plt.subplots(1, 3, figsize=(WIDTH, 2.5), sharey=True, constrained_layout=True)
    panels = [
        (np.abs(ds["limit"].sel(quantity="tau").values - 1.0), r"$|L-1|$, $L=\lim\, n\tau_n\mu/3$", "viridis"),
        (np.abs(ds["limit"].sel(quantity="xdot").values - 1.0), r"$|L-1|$, $L=\lim\, n\dot X_n\mu/(3\gamma)$", "viridis"),
        (ds["transient"].sel(quantity="tau").values, r"transient of $n\tau_n\mu/3$ [impacts]", "magma"),
    ]
    for ax, (z, title, cmap), letter in zip(axes, panels, "abc"):
        z = np.where(np.isfinite(z) & (z > 0), z, np.nan)
        finite = z[np.isfinite(z)]
        norm = LogNorm(vmin=max(finite.min(), 1e-16), vmax=max(finite.max(), 2e-16)) if finite.size else None
        ax.set_facecolor("0.85")  # grey: not determined (no fit window / never settled)
        mesh = ax.pcolormesh(log_edges(gamma), log_edges(mu), z, shading="flat", cmap=cmap, norm=norm)
        fig.colorbar(mesh, ax=ax, shrink=0.9)
        ax.set(xscale="log", yscale="log", xlabel=r"$\gamma$", title=f"({letter}) {title}")
        ax.grid(False)
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.yaxis.set_minor_formatter(NullFormatter())
    axes[0].set_ylabel(r"$\mu$")
    fig.suptitle(f"Theorem main_thm over {mu.size} x {gamma.size} (mu, gamma), psi(0) = {ds.attrs['psi0']:g}, "
                 f"${tex_num(ds.attrs['events'])}$ events (grey: not determined)", fontsize=8)
    save(fig, outputs)


def estimated_memory_mb(spec: dict) -> int:
    """Peak memory of one worker: the trajectory (7 x 8 bytes per event) and ~12 per-impact arrays."""
    return math.ceil(20 * 8 * int(spec["events"]) / 1e6) + 300


SWEEP = Sweep(NAME, "Theorem main_thm over a (mu, gamma) grid: fitted limits and transient lengths",
              size, prepare, compute, VARIABLES, finish, plot, estimated_memory_mb)

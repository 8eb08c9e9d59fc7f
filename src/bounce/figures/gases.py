"""Figures of the gas scenes (config ``gas_scenes``, beyond the paper), drawn from their netCDF alone."""

from __future__ import annotations

import numpy as np
import xarray as xr

from .common import WIDTH, plt, save


def _world_lines(t: np.ndarray, x: np.ndarray, wrap: float) -> np.ndarray:
    """x per snapshot, folded onto [0, wrap) on a ring and broken (NaN) where a grain crosses the seam."""
    if not wrap:
        return x
    folded = np.mod(x, wrap)
    jump = np.abs(np.diff(folded, axis=0)) > 0.5 * wrap
    folded[1:][jump] = np.nan
    return folded


def spacetime(ds: xr.Dataset, spec: dict, outputs) -> None:
    """World lines of the grains (McNamara and Young's space-time diagram of clustering): each grain's lower mass
    (and, for dimers, its upper mass y = x + 1 + 2 xi) at the scene's snapshots, against time; on a ring folded onto
    [0, ell)."""
    if ds.sizes.get("snapshot", 0) < 2:
        raise ValueError(f"gas scene {ds.attrs.get('scene', '?')}: the space-time diagram needs snapshots "
                         "(snapshot_every > 0)")
    every = int(spec.get("every", 1))
    t = ds["snapshot_t"].values
    wrap = float(ds.attrs["ell"]) if ds.attrs["geometry"] == "ring" else 0.0
    x = ds["x"].values[:, ::every]
    fig, ax = plt.subplots(figsize=(WIDTH, 3.6), constrained_layout=True)
    ax.plot(t, _world_lines(t, x, wrap), color="C0", lw=0.5)
    if "eta" in ds:  # dimers: the upper masses, xi = eta - gamma
        y = x + 1.0 + 2.0 * (ds["eta"].values[:, ::every] - float(ds.attrs["gamma"]))
        ax.plot(t, _world_lines(t, y, wrap), color="C1", lw=0.3, alpha=0.7)
    model = "dimers" if "eta" in ds else "rigid grains"
    where = f"ring of circumference {wrap:g}" if wrap else f"column on the floor (gamma = {float(ds.attrs['gamma']):g})"
    ax.set(xlabel="time t (units of sqrt(m/2k), the paper's)", xlim=(t[0], t[-1]),
           ylabel="position along the ring (rest lengths L)" if wrap else "height (rest lengths L)",
           title=f"{int(ds.sizes['grain'])} {model} on a {where}: world lines "
                 f"(blue: lower masses{', orange: upper' if 'eta' in ds else ''})")
    ax.title.set_fontsize(8)
    save(fig, outputs)

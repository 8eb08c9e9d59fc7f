"""Sweep ``our-r-band``: the band of impact speeds where eq. ``our-r`` fails, over the damping mu.

Eq. ``our-r`` (:func:`bounce.analysis.theory.our_r`) stitches r = e^{-mu T_xi} (large impact speeds u, the
macroscopic bounce of sec. 8) to r = 1 - mu u/(3 gamma) (small u, eq. ``restituzione``) at
u_c = 3 gamma/mu (1 - e^{-mu T_xi}) (:func:`bounce.analysis.theory.u_c`).  The check ``our-r`` (claim
``our-r-band``) finds, on one drop (gamma = 1e-5, mu = 0.01), that the law is right on both sides
and wrong in a band [u1, u2] around u_c, whose edges the two branches' error models predict.  This sweep
maps that band over a log grid of mu (under-damped, mu < 1; one item per mu; the check's claim
``band-across-mu`` judges it): for each mu the drop from psi(0) = ``psi0`` (xi = 0, at
rest) is simulated for ``events`` events and r is measured per macroscopic bounce exactly as the
check does (:func:`bounce.analysis.restitution.double_impact` and
:func:`~bounce.analysis.restitution.band_test`, imported, not re-coded): r = ratio of successive
landing speeds u = Xdot of the lower mass, over the initial run of double impacts and then over
every impact.  It is judged on the dissipated fraction, err = (1 - r)/(1 - r_our) - 1 (where
1 - r ~ 1e-4, a relative error of r itself says nothing).  Per mu also the band's predicted edges (u1 from the
small-u model's spring term |ydot_n|/(4 mu gamma), u2 = gamma (ln(1/thr) -+ 1)/(2 mu)) and the bounces beyond
the measured band on each side, and fig. rest-coeff's phases as check ``restitution`` measures them
(:func:`~bounce.analysis.restitution.plateau_statistic`, :func:`~bounce.analysis.restitution.falcon_phases`: the
plateau's mean r against exp(-mu T_xi), the decline, the fluctuation; its claim ``same-behaviour-across-mu``).

Per mu the bounces are binned on a log grid of u/u_c (``u_over_uc``): in each (mu, u/u_c) cell the
number of bounces, the median and largest |err| and the fraction with |err| > ``our_r_threshold``;
per mu the band [u1, u2] (smallest and largest u of a failing bounce, as in the check).  A cell
no bounce reached is NaN (the drop does not sample it: above sqrt(2 gamma psi0), or below the
speed reached after ``events`` impacts, ~3 gamma/(mu n)).
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from ..analysis.restitution import FALCON_BOUNCES, band_test, double_impact, falcon_phases, plateau_statistic
from ..analysis.theory import u_c
from ..io import to_dataset
from ..model import Parameters, State
from ..simulate import simulate
from .base import ITEM, Sweep, axis, log_edges

NAME = "our-r-band"
#: the band's predicted edges per mu (bounce.analysis.restitution.band_edges)
PREDICTED = ("u1_predicted_low", "u1_predicted", "u1_predicted_high", "u2_predicted_low", "u2_predicted_high")
#: fig. rest-coeff's phases per mu: the plateau's statistic and the later phases (bounce.analysis.restitution:
#: plateau_statistic, falcon_phases), by their keys there
PLATEAU = {"mean": "plateau_mean", "std": "plateau_std", "standard_error": "plateau_standard_error",
           "correction": "plateau_gravity_correction"}
PHASES = {"drop": "decline_drop", "turns": "fluctuation_turns", "spread": "fluctuation_spread"}


def size(spec: dict) -> int:
    return int(spec["mu"]["n"])


def prepare(spec: dict, items: np.ndarray) -> dict:
    return {"mu": axis(spec["mu"])[np.asarray(items, dtype=np.int64)]}


def bounce_errors(spec: dict, mu: float) -> dict:
    """(u, err) of every macroscopic bounce of the drop at this mu (the check's measurement), u_c, the band with its
    predicted edges and the bounces beyond it; fig. rest-coeff's plateau and later phases (check restitution's)."""
    gamma = float(spec["gamma"])
    start = State.from_psi_xi(float(spec["psi0"]), 0.0, 0.0, 0.0)
    ds = to_dataset(simulate(Parameters(gamma, mu), start, max_events=int(spec["events"])))
    dbl = double_impact(ds, spec)
    measured = band_test(ds, dbl, spec)
    plateau = plateau_statistic(dbl)
    phases = falcon_phases(dbl, plateau["mean"])
    return {"u": measured["u"], "err": measured["err"], "u_c": u_c(gamma, mu),
            "u1": measured["u1"], "u2": measured["u2"], "double": int(np.sum(measured["kind"] == 1)),
            **dict(zip(PREDICTED, measured["small"] + measured["large"])),
            "bounces_below_band": measured["below"], "bounces_above_band": measured["above"],
            "r_theory": dbl["r0"], "plateau_bounces": plateau["bounces"],
            **{v: plateau[k] for k, v in PLATEAU.items()}, **{v: phases[k] for k, v in PHASES.items()}}


def compute(spec: dict, inputs: dict) -> dict:
    edges = log_edges(axis(spec["u_over_uc"]))
    n_bins = edges.size - 1
    m = len(inputs["mu"])
    out = {k: np.full((m, n_bins), np.nan) for k in ("median_err", "max_err", "fraction_failing")}
    out["bounces"] = np.zeros((m, n_bins), dtype=np.int64)
    for k in ("u_c", "u1", "u2", "u_min", "u_max", "r_theory") + PREDICTED + tuple(PLATEAU.values()) + tuple(PHASES.values()):
        out[k] = np.full(m, np.nan)
    for k in ("double_bounces", "bounces_below_band", "bounces_above_band", "plateau_bounces"):
        out[k] = np.zeros(m, dtype=np.int64)
    thr = float(spec["our_r_threshold"])
    for i, mu in enumerate(inputs["mu"]):
        b = bounce_errors(spec, float(mu))
        ok = np.isfinite(b["err"])
        u, err = b["u"][ok], np.abs(b["err"][ok])
        out["u_c"][i], out["u1"][i], out["u2"][i], out["double_bounces"][i] = b["u_c"], b["u1"], b["u2"], b["double"]
        for k in PREDICTED + ("bounces_below_band", "bounces_above_band", "r_theory", "plateau_bounces") + \
                tuple(PLATEAU.values()) + tuple(PHASES.values()):
            out[k][i] = b[k]
        if u.size:
            out["u_min"][i], out["u_max"][i] = u.min(), u.max()
        cell = np.searchsorted(edges, u / b["u_c"], side="right") - 1
        for j in range(n_bins):
            e = err[cell == j]
            out["bounces"][i, j] = e.size
            if e.size:
                out["median_err"][i, j] = np.median(e)
                out["max_err"][i, j] = e.max()
                out["fraction_failing"][i, j] = np.count_nonzero(e > thr) / e.size
    return {"mu": np.asarray(inputs["mu"], dtype=float), **out}


_C = (ITEM, "u_bin")
VARIABLES = {
    "mu": ((ITEM,), "damping mu = nu / sqrt(2 k m)", "1", None),
    "median_err": (_C, "median over the cell's bounces of |(1 - r)/(1 - r_our) - 1|", "1",
                   "r: ratio of successive landing speeds (check our-r); r_our: eq. our-r; NaN: no bounce"),
    "max_err": (_C, "largest |(1 - r)/(1 - r_our) - 1| over the cell's bounces", "1", None),
    "fraction_failing": (_C, "fraction of the cell's bounces with |(1 - r)/(1 - r_our) - 1| > our_r_threshold",
                         "1", None),
    "bounces": (_C, "macroscopic bounces whose landing speed falls in the cell", "1", None),
    "u_c": ((ITEM,), "stitching speed u_c = 3 gamma/mu (1 - exp(-mu T_xi)) of eq. our-r", "sqrt(2k/m) L", None),
    "u1": ((ITEM,), "band of eq. our-r: smallest landing speed of a failing bounce", "sqrt(2k/m) L",
           "NaN: no failing bounce"),
    "u2": ((ITEM,), "band of eq. our-r: largest landing speed of a failing bounce", "sqrt(2k/m) L",
           "NaN: no failing bounce"),
    "u_min": ((ITEM,), "smallest landing speed measured", "sqrt(2k/m) L", None),
    "u_max": ((ITEM,), "largest landing speed measured", "sqrt(2k/m) L", None),
    "double_bounces": ((ITEM,), "bounces of the initial double-impact run", "1", None),
    "u1_predicted_low": ((ITEM,), "predicted u1, low end: first bounce from below with |ydot_n|/(4 mu gamma) > "
                         "thr - thr^2", "sqrt(2k/m) L", "inf: no such bounce"),
    "u1_predicted": ((ITEM,), "predicted u1: first bounce from below with |ydot_n|/(4 mu gamma) > thr "
                     "(the small-u branch's error model)", "sqrt(2k/m) L", "inf: no such bounce"),
    "u1_predicted_high": ((ITEM,), "predicted u1, high end: first bounce from below with |ydot_n|/(4 mu gamma) > "
                          "thr + thr^2", "sqrt(2k/m) L", "inf: no such bounce"),
    "u2_predicted_low": ((ITEM,), "predicted u2, low end: gamma (ln(1/thr) - 1)/(2 mu) (the large-u branch's "
                         "error model)", "sqrt(2k/m) L", None),
    "u2_predicted_high": ((ITEM,), "predicted u2, high end: gamma (ln(1/thr) + 1)/(2 mu)", "sqrt(2k/m) L", None),
    "bounces_below_band": ((ITEM,), "macroscopic bounces slower than u1", "1", "0: no failing bounce"),
    "bounces_above_band": ((ITEM,), "macroscopic bounces faster than u2", "1", "0: no failing bounce"),
    "r_theory": ((ITEM,), "restitution exp(-mu T_xi) of eq. rest-coefficient-function-of-mu", "1", None),
    "plateau_bounces": ((ITEM,), "bounces of the plateau of r_m = f_(m+1)/f_m (flights f_m >= plateau_flight T_d, "
                        "within the double-impact run)", "1", "check restitution decides a mu from 3 on"),
    "plateau_mean": ((ITEM,), "mean r_m over the plateau", "1", "NaN: fewer than 3 plateau bounces"),
    "plateau_std": ((ITEM,), "standard deviation (ddof 1) of r_m over the plateau", "1", None),
    "plateau_standard_error": ((ITEM,), "standard error of the plateau's mean r_m", "1", None),
    "plateau_gravity_correction": ((ITEM,), "first-order gravity correction r mu T_xi max(delta_m) of the plateau's r",
                                   "1", "delta_m: the contact's shortening by gravity (check restitution)"),
    "decline_drop": ((ITEM,), "plateau's mean r_m minus the mean r_m over the rest of the double-impact run", "1",
                     "NaN: the run ends at the plateau's end"),
    "fluctuation_turns": ((ITEM,), "fraction of the steps at which r_m turns, over the bounces after the double-impact "
                          f"run up to m = {FALCON_BOUNCES}", "1", "2/3 for an unordered sequence, 0 for a trend"),
    "fluctuation_spread": ((ITEM,), "standard deviation of r_m over the bounces after the double-impact run up to "
                           f"m = {FALCON_BOUNCES}", "1", None),
}


def finish(ds: xr.Dataset, spec: dict) -> xr.Dataset:
    """mu as the item coordinate, the u/u_c bins with their edges, the settings in the attributes."""
    centres = axis(spec["u_over_uc"])
    ds = ds.swap_dims({ITEM: "mu"}).drop_vars(ITEM)
    ds["mu"].attrs.update(long_name="damping mu = nu / sqrt(2 k m)", units="1")
    ds = ds.assign_coords(u_bin=xr.Variable(("u_bin",), centres, {
        "long_name": "landing speed over u_c, bin centre (log grid)", "units": "1"}))
    ds["u_bin_edges"] = xr.Variable(("u_bin_edge",), log_edges(centres),
                                    {"long_name": "edges of the u/u_c bins (geometric midpoints)", "units": "1"})
    ds.attrs.update(gamma=float(spec["gamma"]), psi0=float(spec["psi0"]), events=int(spec["events"]),
                    our_r_threshold=float(spec["our_r_threshold"]), double_band=float(spec["double_band"]),
                    plateau_flight=float(spec["plateau_flight"]))
    return ds


def plot(ds: xr.Dataset, spec: dict, outputs) -> None:
    """Median error of 1 - r over (u/u_c, mu) with the band's edges; the error against u/u_c per mu."""
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm

    from ..figures.common import WIDTH, save, tex_num

    mu, thr = ds["mu"].values, float(ds.attrs["our_r_threshold"])
    uc = ds["u_c"].values
    med = ds["median_err"].values
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(WIDTH, 3.6), constrained_layout=True)
    finite = med[np.isfinite(med) & (med > 0)]
    norm = LogNorm(vmin=max(finite.min(), 1e-6), vmax=max(finite.max(), 1.0)) if finite.size else None
    a1.set_facecolor("0.85")  # grey: no bounce at that speed
    z = np.where(med > 0, med, np.nan)
    mesh = a1.pcolormesh(ds["u_bin_edges"].values, log_edges(mu), z, shading="flat", cmap="viridis", norm=norm)
    fig.colorbar(mesh, ax=a1, shrink=0.9, label="median error of 1 - r")
    edges = ds["u_bin_edges"].values
    # the edges the error models predict (bounce.analysis.restitution.band_edges), clipped to the grid: a bar per mu
    # over each predicted range, a tick at u1's value at the threshold
    clip = lambda v: np.clip(v / uc, edges[0], edges[-1])  # noqa: E731
    for lo, hi in (("u1_predicted_low", "u1_predicted_high"), ("u2_predicted_low", "u2_predicted_high")):
        a1.hlines(mu, clip(ds[lo].values), clip(ds[hi].values), color="C3", lw=2.5, zorder=1.5)
    found = np.isfinite(ds["u1_predicted"].values)  # inf: no bounce with the spring term above the threshold
    a1.plot(clip(ds["u1_predicted"].values[found]), mu[found], "|", color="C3", ms=9, mew=2, label="predicted edges")
    # band edges; hollow where the edge is the run's own end (or start) or beyond the grid (drawn at its end)
    for edge, marker, bound in (("u1", "<", "u_min"), ("u2", ">", "u_max")):
        x = ds[edge].values / uc
        open_ = (ds[edge].values == ds[bound].values) | (x < edges[0]) | (x > edges[-1])
        x = np.clip(x, edges[0], edges[-1])
        a1.plot(x[~open_], mu[~open_], "w" + marker, mec="k", mew=0.5, ms=5,
                label="band edges u1, u2" if edge == "u1" else None)
        a1.plot(x[open_], mu[open_], marker, ms=5, mfc="none", mec="C1",
                label="edge at the run's end or off the grid" if edge == "u1" and open_.any() else None)
    a1.axvline(1.0, color="w", lw=0.6, ls="--")
    a1.set(xscale="log", yscale="log", xlabel=r"landing speed $u / u_c$", ylabel=r"$\mu$", xlim=(edges[0], edges[-1]))
    a1.set_title(f"(a) eq. our-r fails where the median error of 1 - r > {thr:g}", fontsize=7)
    fig.legend(*a1.get_legend_handles_labels(), loc="outside lower center", fontsize=6, ncol=3, frameon=False)
    centres = ds["u_bin"].values
    by_mu = plt.cm.ScalarMappable(LogNorm(mu.min(), mu.max()) if mu.min() < mu.max() else None, cmap="plasma")
    for i, m in enumerate(mu):
        a2.loglog(centres, med[i], "-", lw=0.9, color=by_mu.to_rgba(m))
    fig.colorbar(by_mu, ax=a2, shrink=0.9, label=r"$\mu$")
    a2.axhline(thr, color="k", ls="--", lw=0.8)
    a2.axvline(1.0, color="0.5", ls=":", lw=0.8)
    a2.set(xlabel=r"landing speed $u / u_c$", ylabel=r"median $|(1-r)/(1-r_{\rm our})-1|$")
    a2.set_title(f"(b) the same error, one line per $\\mu$;\ndashed: the threshold {thr:g}; dotted: $u = u_c$",
                 fontsize=6.5)
    a = ds.attrs
    fig.suptitle(r"Eq. our-r against the dimer: $\gamma=%s$, drop from $\psi(0)=%s$, $%s$ events per $\mu$; "
                 "r = ratio of successive landing speeds" % (tex_num(a["gamma"]), tex_num(a["psi0"]), tex_num(a["events"])),
                 fontsize=8)
    save(fig, outputs)


def estimated_memory_mb(spec: dict) -> int:
    """One worker: the trajectory and its dataset (~20 float64 per event) and the check's per-bounce arrays."""
    return math.ceil(40 * 8 * int(spec["events"]) / 1e6) + 300


SWEEP = Sweep(NAME, "Eq. our-r over (mu, impact speed): where the stitched restitution law fails (on 1 - r)",
              size, prepare, compute, VARIABLES, finish, plot, estimated_memory_mb)

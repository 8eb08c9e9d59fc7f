"""Check ``gas-column``: a column of dimers on the floor comes to rest without collapse; the rigid column collapses.

Beyond the paper (issue 24, experiment 5): the single ball's result (no inelastic collapse, Theorem ``main_thm``; the
energy decays to its minimum, Theorem ``static-equilibrium``) carried to n balls stacked on the floor, against the
rigid model the paper's introduction says collapses.  Input: the sweep ``column-drop``
(:mod:`bounce.sweeps.column_drop`: columns dropped from rest with random gaps, as dimers with exp(-mu T_xi) = r and as
rigid rods with restitution r).

1. ``dimer-column-rests``: every dimer column gets to rest (its energy above the column's minimum down to the
   sweep's fraction ``rest`` of its start) without an engine stop (overlap, sticky contact), in a finite number of
   impacts at a finite time (no collapse: time advances through every impact).
2. ``rigid-column-collapses``: every rigid twin ends in the engine's collapse stop (infinitely many collisions in a
   finite time, detected where float64 stops resolving them, :mod:`bounce.gas.rigid`), neither cooled nor cut by the
   event cap; the row gives the collapse time against n and where it happened.  No published collapse time of a
   dropped column was at hand to compare with (Bernu and Mazighi, J. Phys. A 23, 5745 (1990), and Luding et al.,
   Phys. Rev. E 49, 1634 (1994), study rigid columns on a wall; their papers could not be consulted here), so the row
   states what the data show.
3. ``rigid-column-single-ball``: for n = 1 the collapse time is the bouncing ball's,
   t = (v_0/gamma)(1 + r)/(1 - r) with v_0 = sqrt(2 gamma h) (the fall, then flights 2 r^k v_0/gamma summed), within
   ``collapse_rtol`` (1e-12: ~100 flights each to rounding, the sum's rounding ~100 ulps).

Measured (``python -m bounce check gas-column/dimer-column-rests`` and ``.../rigid-column-collapses`` on the
pipeline's sweep: gamma = 0.001, lowest mass at 1, gaps < 1, rest = 0.03, 3 states per (r, n), n = 1..16): every
dimer column rests, every rigid twin collapses.  Medians at r = 0.9 (0.95), n = 1, 2, 4, 8, 16: the dimers' impacts
to rest 24, 60, 160, 5.1e3, 4.8e4 (44, 91, 304, 1.4e3, 6.6e3), growing faster than any power of n beyond n = 4,
and by orders of magnitude between states at r <= 0.8 (config.yaml); their time to rest 605, 338, 265, 500, 601
(1050, 560, 444, 540, 708), a fraction of each column's own start energy, so not monotone in n; the rigid collapse
time 850, 575, 341, 267, 165 (1744, 1230, 739, 514, 349), always the bottom grain alone on the floor (the grains
above knock it down, sooner the more there are), the single ball's (v_0/gamma)(1 + r)/(1 - r) to the last bit at
n = 1.  The dimers' smallest interval between events is 1.5e-8: time advances through every impact.

Falsifiers (tests/checks/test_claims.py::test_falsifier_flips): the tallest column's dimers cut by the event cap before
rest, its rigid twin cut by the cap instead of collapsing, the drop height recorded 1e-9 relative high.
"""

from __future__ import annotations

import math
import warnings
from types import SimpleNamespace

import numpy as np
import xarray as xr

from ..gas.common import STOP_COLLAPSE, STOP_EVENTS
from .base import BEYOND, NOT_CHECKABLE, Check, Falsifier, Verdict, claim, judge, on_named, split_inputs, variable

NAME = "gas-column"
SUBJECT = "beyond:gases"
MARKERS = "osD^v<>"


def single_ball_collapse(gamma: float, height: float, r: float) -> float:
    """The rigid ball dropped from rest at ``height``: fall v_0/gamma, then flights 2 r^k v_0/gamma, k >= 1, summed:
    (v_0/gamma)(1 + r)/(1 - r), v_0 = sqrt(2 gamma height)."""
    v0 = math.sqrt(2.0 * gamma * height)
    return v0 / gamma * (1.0 + r) / (1.0 - r)


def _medians(values: np.ndarray) -> np.ndarray:
    """Median over the samples (last axis), NaN where none is finite."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # an all-NaN slice: NaN, as wanted
        return np.nanmedian(values, axis=-1)


def measure(spec: dict, inputs: list) -> SimpleNamespace:
    _, named = split_inputs(inputs)
    ds = named["column-drop"]
    r, n = ds["r"].values, ds["n"].values
    rested = (ds["dimer_rested"].values == 1) & (ds["dimer_stop"].values == STOP_EVENTS)
    t_rest = np.where(rested, ds["dimer_t_rest"].values, np.nan)
    impacts = np.where(rested, ds["dimer_impacts"].values, np.nan).astype(float)
    collapsed = ds["rigid_stop"].values == STOP_COLLAPSE
    t_collapse = np.where(collapsed, ds["rigid_t_end"].values, np.nan)
    law = np.array([single_ball_collapse(float(ds.attrs["gamma"]), float(ds.attrs["height"]), float(x)) for x in r])
    dims = ("r", "n", "sample")
    data = xr.Dataset(coords={"r": ("r", r, {"long_name": "restitution coefficient r", "units": "1"}),
                              "n": ("n", n, {"long_name": "grains in the column", "units": "1"}),
                              "sample": ("sample", ds["sample"].values, {"long_name": "initial state", "units": "1"})})
    data["t_rest"] = variable(("r", "n"), _medians(t_rest), "dimer column: median time to rest (dimensionless)")
    data["impacts"] = variable(("r", "n"), _medians(impacts), "dimer column: median impacts to rest")
    data["t_collapse"] = variable(("r", "n"), _medians(t_collapse), "rigid column: median collapse time (dimensionless)")
    data["rested"] = variable(dims, rested.astype(np.int8), "dimer column: 1 at rest without an engine stop")
    data["rest_over_collapse"] = variable(dims, t_rest / t_collapse,
                                          "dimer column's time to rest over its rigid twin's collapse time")
    data["collapse_ratio"] = variable(dims, t_collapse / law[:, None, None],
                                      "rigid column: collapse time over one rigid ball's (v0/gamma)(1+r)/(1-r)")
    data.attrs.update(check=NAME, **{k: ds.attrs[k] for k in ("gamma", "height", "gap", "rest", "samples", "max_events")})
    ctx = (f"sweep column-drop: columns of n in {list(map(int, n))} grains dropped from rest (gamma = "
           f"{ds.attrs['gamma']:g}, lowest mass at {ds.attrs['height']:g}, gaps < {ds.attrs['gap']:g}), "
           f"{int(ds.attrs['samples'])} states per (r, n), r in {list(map(float, r))}")
    return SimpleNamespace(ds=ds, r=r, n=n, rested=rested, t_rest=t_rest, impacts=impacts, collapsed=collapsed,
                           t_collapse=t_collapse, law=law, data=data, ctx=ctx)


def _per_n(m, values: np.ndarray, fmt: str) -> str:
    """'r=..: n=1 a, n=2 b, ...' of the medians over the samples."""
    med = _medians(values)
    return "; ".join(f"r={r:g}: " + ", ".join(f"n={k} {format(v, fmt)}" for k, v in zip(m.n, row))
                     for r, row in zip(m.r, med))


# --------------------------------------------------------------------------- falsifiers

def _tallest_not_at_rest(ds: xr.Dataset) -> xr.Dataset:
    """The tallest column's dimers cut by the event cap before rest: not rested, energy fraction twice ``rest``."""
    ds["dimer_rested"].values[:, -1, :] = 0
    ds["dimer_energy"].values[:, -1, :] = 2.0 * float(ds.attrs["rest"])
    return ds


def _tallest_rigid_capped(ds: xr.Dataset) -> xr.Dataset:
    """The tallest column's rigid twin cut by the event cap, not collapsed."""
    ds["rigid_stop"].values[:, -1, :] = STOP_EVENTS
    return ds


def _height_recorded_high(ds: xr.Dataset) -> xr.Dataset:
    """The drop height recorded 1e-9 relative above the runs' (a parameter off in its ninth digit)."""
    ds.attrs["height"] = float(ds.attrs["height"]) * (1.0 + 1e-9)
    return ds


CLAIMS: list = []


@claim(CLAIMS, "dimer-column-rests", BEYOND, SUBJECT,
       falsifier=Falsifier("the tallest dimer column cut by the event cap before rest (energy fraction 2 x rest)",
                           on_named("column-drop", _tallest_not_at_rest)))
def dimer_column_rests(m, spec) -> Verdict:
    ds = m.ds
    stops = ds["dimer_stop"].values
    ok = m.rested & np.isfinite(m.t_rest) & (m.t_rest > 0.0) & (m.impacts > 0)
    bad = int((~ok).sum())
    measured = (f"{int(ok.sum())} of {ok.size} columns at rest; median time to rest {_per_n(m, m.t_rest, '.3g')}; "
                f"median impacts to rest {_per_n(m, m.impacts, '.3g')}; smallest interval between events "
                f"{np.nanmin(ds['dimer_min_interval'].values):.2g}")
    if bad:
        codes = sorted({int(c) for c in stops[~ok]})
        measured += (f"; {bad} not at rest (stop codes {codes}, energy fraction reached up to "
                     f"{np.nanmax(ds['dimer_energy'].values[~ok]):.3g})")
    return Verdict(
        "a column of dimers (the paper's balls) dropped onto the floor comes to rest without collapse, for every n",
        "Theorems main_thm and static-equilibrium (one ball), carried to a column; introduction", m.ctx,
        f"every run: E - E_min down to {ds.attrs['rest']:g} of its start in finitely many impacts at a finite "
        f"time, no engine stop (overlap, sticky contact) and within {int(ds.attrs['max_events'])} events",
        measured, "exact (the engine's stop, the recorded energies and times)", judge(bool(ok.all())))


@claim(CLAIMS, "rigid-column-collapses", BEYOND, SUBJECT,
       falsifier=Falsifier("the tallest rigid column cut by the event cap instead of collapsing",
                           on_named("column-drop", _tallest_rigid_capped)))
def rigid_column_collapses(m, spec) -> Verdict:
    ds = m.ds
    ok = m.collapsed & np.isfinite(m.t_collapse)
    low, high = ds["rigid_low"].values[ok], ds["rigid_high"].values[ok]
    where = (f"collapsing grains {int(low.min())}..{int(high.max())}" if ok.any() else "none collapsed")
    measured = (f"{int(ok.sum())} of {ok.size} rigid columns collapsed ({where}); median collapse time "
                f"{_per_n(m, m.t_collapse, '.3g')}")
    if not ok.all():
        measured += f"; stop codes of the others {sorted({int(c) for c in ds['rigid_stop'].values[~ok]})}"
    return Verdict(
        "the rigid column (rods, constant restitution r = exp(-mu T_xi) of the same dimers) collapses: infinitely "
        "many collisions in a finite time, for every n",
        "introduction (rigid models collapse); no published collapse time of a dropped column at hand to compare",
        m.ctx, "every rigid twin ends in the engine's collapse stop (not cooled, not cut by the event cap)",
        measured, "exact (the engine's stop)", judge(bool(ok.all())))


@claim(CLAIMS, "rigid-column-single-ball", BEYOND, SUBJECT,
       falsifier=Falsifier("the drop height recorded 1e-9 relative above the runs' (collapse time off by 5e-10)",
                           on_named("column-drop", _height_recorded_high)))

def rigid_column_single_ball(m, spec) -> Verdict:
    text = "one rigid grain on the floor collapses at t = (v0/gamma)(1 + r)/(1 - r), v0 = sqrt(2 gamma h)"
    ref = "the bouncing ball with constant restitution (introduction: rigid models collapse)"
    rtol = float(spec["collapse_rtol"])
    if 1 not in m.n:
        return Verdict(text, ref, m.ctx, "n = 1 on the sweep's grid", "no n = 1", "none", NOT_CHECKABLE)
    j = int(np.flatnonzero(m.n == 1)[0])
    err = np.abs(m.data["collapse_ratio"].values[:, j, :] - 1.0)
    worst = float(np.max(np.where(np.isfinite(err), err, np.inf)))
    return Verdict(text, ref, m.ctx + "; the n = 1 rigid runs",
                   "; ".join(f"r={r:g}: t = {t:.15g}" for r, t in zip(m.r, m.law)),
                   "; ".join(f"r={r:g}: t = {t:.15g}" for r, t in zip(m.r, np.nanmax(m.t_collapse[:, j, :], axis=1)))
                   + f"; largest relative error {worst:.2g}",
                   f"relative {rtol:g} (~100 flights summed, each to rounding)", judge(worst <= rtol))


def plot(ds: xr.Dataset, spec: dict, outputs) -> None:
    """Per run, against n: (a) the dimer column's time to rest over its rigid twin's collapse time; (b) the rigid
    column's collapse time over one rigid ball's (v0/gamma)(1+r)/(1-r), exactly 1 at n = 1."""
    from ..figures.common import WIDTH, plt, save

    n = ds["n"].values
    fig, axes = plt.subplots(1, 2, figsize=(WIDTH, 2.8), constrained_layout=True)
    for i, r in enumerate(ds["r"].values):
        for ax, name in zip(axes, ("rest_over_collapse", "collapse_ratio")):
            ax.plot(np.repeat(n, ds.sizes["sample"]), ds[name].values[i].ravel(), MARKERS[i % len(MARKERS)], ms=4,
                    mfc="none", color=f"C{i}", label=f"r = {r:g}")
    not_rested = int((ds["rested"].values == 0).sum())
    axes[0].set(ylabel="dimers' time to rest / rigid collapse time")
    axes[0].set_title(f"(a) dimers at rest ({not_rested} of {ds['rested'].size} runs not: not drawn)", fontsize=8)
    axes[1].set(ylabel="collapse time / one rigid ball's")
    axes[1].set_title("(b) rigid rods: every run drawn collapsed;\n1 = (v0/gamma)(1+r)/(1-r), the ball alone",
                      fontsize=8)
    for ax in axes:
        ax.axhline(1.0, color="k", lw=0.6, ls=":")
        ax.set(xscale="log", yscale="log", xlabel="grains in the column n")
        ax.set_xticks(n, [str(int(k)) for k in n])
        ax.xaxis.set_minor_locator(plt.matplotlib.ticker.NullLocator())
        for axis in (ax.yaxis,):
            axis.set_major_formatter(plt.matplotlib.ticker.FormatStrFormatter("%g"))
            axis.set_minor_formatter(plt.matplotlib.ticker.FormatStrFormatter("%g"))
        ax.tick_params(which="minor", labelsize=6)
        ax.legend(fontsize=6)
    fig.suptitle(f"check gas-column: {int(ds.attrs['samples'])} states per (r, n), gamma = {ds.attrs['gamma']:g}; "
                 f"times dimensionless (units sqrt(m/2k))", fontsize=8)
    save(fig, outputs)


TITLE = "Beyond the paper: a column on the floor, dimers at rest and rigid rods collapsing (sweep column-drop)"
CHECK = Check(NAME, measure, tuple(CLAIMS), plot, TITLE)

"""Sweep ``contact-monte-carlo``: how rare are near-zero-speed contacts? (Theorem contact-non-generic)

The Monte Carlo of the check ``contact-non-generic`` at scale: ``n_samples`` random initial
states (gamma log-uniform, mu cycling through the under-, critically and over-damped regimes,
E - E_m = gamma^2 10^U, a random direction in the state space;
:func:`bounce.checks.contact_non_generic.sample_initial`, drawn once for the whole sweep from ``seed``),
each run for ``events`` events.  For every impact the arrival speed |Xdot_n| is compared
with the launch speed of its flight, ratio = |Xdot_n| / max(|Xdot_{n-1}|, |Xdot_n|), and with
the classifier's rounding window, margin = |Xdot_n| / v_tol
(:func:`bounce.checks.contact_non_generic._contact_scales`, the events.py classifier).  The
histograms of both are pooled per regime: the fraction of contacts with ratio < r, as r -> 0,
is the measure of near-zero-speed contacts; the theorem says zero-speed contacts (sticky
onsets, grazings) are non-generic, i.e. their count in a random sample is 0.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from ..analysis.anomalies import _contact_scales, sample_initial
from ..kinds import KIND_NAMES
from ..model import Deviations, Parameters
from ..exact.oscillator import make_oscillator
from ..simulate import simulate
from .base import ITEM, Sweep

NAME = "contact-monte-carlo"
REGIMES = ("under-damped", "critical", "over-damped")
#: histogram edges: log10 of ratio in [-16, 0] and of margin in [-2, 18] by quarter decades, plus 0
RATIO_EDGES = np.concatenate([[0.0], 10.0 ** np.arange(-16.0, 0.001, 0.25)])
MARGIN_EDGES = np.concatenate([[0.0], 10.0 ** np.arange(-2.0, 18.001, 0.25)])
THRESHOLDS = (1e-2, 1e-3, 1e-4, 1e-6)


def size(spec: dict) -> int:
    return int(spec["n_samples"])


def prepare(spec: dict, items: np.ndarray) -> dict:
    """The random states of ``items``, drawn for all ``n_samples`` at once (independent of the sharding)."""
    gamma, mu, regime, dE, x, u, a, eta = sample_initial(np.random.default_rng(int(spec["seed"])), size(spec), spec)
    return {k: v[items] for k, v in
            dict(gamma=gamma, mu=mu, damping_regime=regime, energy=dE, x=x, xdot=u, xidot=a, eta=eta).items()}


def compute(spec: dict, inputs: dict) -> dict:
    m = len(inputs["gamma"])
    events = int(spec["events"])
    counts = np.zeros((m, len(KIND_NAMES)), dtype=np.int64)
    min_ratio = np.full(m, np.nan)
    min_margin = np.full(m, np.nan)
    ratio_hist = np.zeros((len(REGIMES), RATIO_EDGES.size - 1), dtype=np.int64)
    margin_hist = np.zeros((len(REGIMES), MARGIN_EDGES.size - 1), dtype=np.int64)
    ref = np.empty(events)
    mar = np.empty(events)
    for i in range(m):
        g, mu = float(inputs["gamma"][i]), float(inputs["mu"][i])
        x, u, a, eta = (float(inputs[k][i]) for k in ("x", "xdot", "xidot", "eta"))
        tr = simulate(Parameters(g, mu), Deviations(x, u, a, eta), max_events=events)
        n = len(tr)
        counts[i] = np.bincount(tr.kind, minlength=len(KIND_NAMES))
        params, coefs = make_oscillator(mu)
        _contact_scales(x, u, a, eta, tr.tau, tr.xdot, tr.xidot, tr.eta, tr.kind, g, mu, params, coefs,
                        ref[:n], mar[:n])
        ok = np.isfinite(ref[:n])
        if ok.any():
            r, v = ref[:n][ok], mar[:n][ok]
            min_ratio[i], min_margin[i] = r.min(), v.min()
            reg = int(inputs["damping_regime"][i])
            ratio_hist[reg] += np.histogram(r, RATIO_EDGES)[0]
            margin_hist[reg] += np.histogram(np.minimum(v, MARGIN_EDGES[-1]), MARGIN_EDGES)[0]
    return {**{k: np.asarray(inputs[k]) for k in ("gamma", "mu", "damping_regime", "energy")},
            "counts": counts, "min_ratio": min_ratio, "min_margin": min_margin,
            "ratio_hist": ratio_hist, "margin_hist": margin_hist}


VARIABLES = {
    "gamma": ((ITEM,), "gravity gamma of the sample", "1", None),
    "mu": ((ITEM,), "damping mu of the sample", "1", None),
    "damping_regime": ((ITEM,), "damping regime (0 under-damped, 1 critical, 2 over-damped)", "1", None),
    "energy": ((ITEM,), "initial E - E_m", "1", None),
    "counts": ((ITEM, "kind"), "events of each kind", "1", None),
    "min_ratio": ((ITEM,), "smallest |Xdot_n| / launch speed over the sample's impacts", "1", None),
    "min_margin": ((ITEM,), "smallest |Xdot_n| / v_tol (classifier window) over the sample's impacts", "1", None),
    "ratio_hist": (("regime", "ratio_bin"), "impacts per bin of |Xdot_n| / launch speed", "1",
                   "bin edges: ratio_edges"),
    "margin_hist": (("regime", "margin_bin"), "impacts per bin of |Xdot_n| / v_tol", "1",
                    "bin edges: margin_edges; the last bin holds everything above its lower edge"),
}


def _cumulative_fraction(hist: np.ndarray, edges: np.ndarray, r: float) -> np.ndarray:
    """Fraction of the counts below r (r on an edge), per row."""
    k = int(np.searchsorted(edges, r * (1.0 + 1e-12))) - 1
    total = hist.sum(axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        return hist[..., :k].sum(axis=-1) / total


def finish(ds: xr.Dataset, spec: dict) -> xr.Dataset:
    """Bin edges, regime and kind names, and the fractions of near-zero-speed contacts per regime."""
    ds = ds.assign_coords(
        regime_name=xr.Variable(("regime",), np.array(REGIMES, dtype=object), {"long_name": "damping regime"}),
        kind=xr.Variable(("kind",), np.array(KIND_NAMES, dtype=object), {"long_name": "kind of event"}),
    )
    ds["ratio_edges"] = xr.Variable(("ratio_edge",), RATIO_EDGES, {"long_name": "bin edges of ratio_hist", "units": "1"})
    ds["margin_edges"] = xr.Variable(("margin_edge",), MARGIN_EDGES,
                                     {"long_name": "bin edges of margin_hist", "units": "1"})
    hist = ds["ratio_hist"].values
    frac = np.stack([_cumulative_fraction(hist, RATIO_EDGES, r) for r in THRESHOLDS], axis=-1)
    ds["fraction_below"] = xr.Variable(("regime", "threshold"), frac, {
        "long_name": "fraction of impacts with |Xdot_n| / launch speed below the threshold", "units": "1"})
    ds = ds.assign_coords(threshold=xr.Variable(("threshold",), np.array(THRESHOLDS), {"long_name": "ratio", "units": "1"}))
    counts = ds["counts"].values.sum(axis=0)
    ds.attrs.update(
        n_samples=int(spec["n_samples"]), events=int(spec["events"]), seed=int(spec["seed"]),
        n_impacts=int(hist.sum()), **{f"n_{k}": int(c) for k, c in zip(KIND_NAMES, counts)},
        n_inside_classifier_window=int(ds["margin_hist"].values[:, : np.searchsorted(MARGIN_EDGES, 1.0)].sum()),
    )
    return ds


def plot(ds: xr.Dataset, spec: dict, outputs) -> None:
    """Cumulative fraction of impacts below a speed ratio, and below a multiple of the classifier's window."""
    import matplotlib.pyplot as plt

    from ..figures.common import WIDTH, save

    fig, axes = plt.subplots(1, 2, figsize=(WIDTH, 2.7), constrained_layout=True)
    for ax, var, edges, xlabel in (
        (axes[0], "ratio_hist", ds["ratio_edges"].values, r"$r = |\dot X_n| / \max(|\dot X_{n-1}|, |\dot X_n|)$"),
        (axes[1], "margin_hist", ds["margin_edges"].values, r"$|\dot X_n| / v_{\rm tol}$ (classifier window)"),
    ):
        hist = ds[var].values
        for reg, name in enumerate(ds["regime_name"].values):
            total = hist[reg].sum()
            if total == 0:
                continue
            cum = np.cumsum(hist[reg]) / total
            keep = cum > 0
            ax.step(edges[1:][keep], cum[keep], where="post", label=f"{name} ({total:.3g} impacts)")
        ax.set(xscale="log", yscale="log", xlabel=xlabel, ylabel="fraction of impacts below")
    r = np.geomspace(1e-4, 1e-1, 10)
    axes[0].plot(r, 0.5 * r**2, "k:", label=r"$\propto r^2$ (grazing dip)")
    axes[1].axvline(1.0, color="k", ls="--", lw=0.8, label="window: tangential below")
    axes[0].legend(loc="upper left")
    axes[1].legend(loc="lower right")
    a = ds.attrs
    fig.suptitle(f"Theorem contact-non-generic: {a['n_samples']:,} random states x {a['events']} events; "
                 f"grazing {a['n_grazing']}, sticky_start {a['n_sticky_start']}", fontsize=8)
    save(fig, outputs)


def estimated_memory_mb(spec: dict) -> int:
    """One worker: the sweep's random states (8 arrays of n_samples) and one short trajectory."""
    return math.ceil(8 * 8 * int(spec["n_samples"]) * 2 / 1e6 + 64 * int(spec["events"]) / 1e6) + 300


SWEEP = Sweep(NAME, "Theorem contact-non-generic: Monte Carlo of contact speeds over random initial states",
              size, prepare, compute, VARIABLES, finish, plot, estimated_memory_mb)

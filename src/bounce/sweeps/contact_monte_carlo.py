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

Cost: the samples run in one compiled loop (:func:`_run_samples`), each with the oscillator tables
of its own mu built there (:func:`bounce.exact.oscillator.oscillator_tables`, ~16 us, ~1/6 of a
sample's time) and those of mu/sqrt(2) only if it sticks: ~12,000 trajectories of 100 events per
second per core (benchmarks/bench_monte_carlo.py; 1,250 when the tables were built in numpy).
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from numba import njit

from ..analysis.anomalies import _contact_scales, sample_initial
from ..exact.events import run_events
from ..exact.oscillator import oscillator_tables
from ..kinds import KIND_NAMES, STOP_FAILED
from ..model import Deviations, Parameters, check_supported
from ..trajectory import stop_rules
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
    """Every sample as :func:`bounce.simulate.simulate` runs it (the same checks, then the linear spring's event
    loop :func:`bounce.exact.events.run_events` with the oscillator tables of mu and mu/sqrt(2)), in one compiled
    loop (:func:`_run_samples`): the same bits as a ``simulate`` per sample, ~10x faster
    (benchmarks/bench_monte_carlo.py)."""
    m = len(inputs["gamma"])
    events, t_max, energy_stop = stop_rules(int(spec["events"]), math.inf, 0.0)
    gamma, mu = (np.asarray(inputs[k], dtype=np.float64) for k in ("gamma", "mu"))
    x, u, a, eta = (np.asarray(inputs[k], dtype=np.float64) for k in ("x", "xdot", "xidot", "eta"))
    for i in range(m):  # simulate's refusals, in its words (every sample of the sweep passes them)
        check_supported(Parameters(float(gamma[i]), float(mu[i])),
                        Deviations(float(x[i]), float(u[i]), float(a[i]), float(eta[i])))
    counts = np.zeros((m, len(KIND_NAMES)), dtype=np.int64)
    min_ratio = np.full(m, np.nan)
    min_margin = np.full(m, np.nan)
    ratio_hist = np.zeros((len(REGIMES), RATIO_EDGES.size - 1), dtype=np.int64)
    margin_hist = np.zeros((len(REGIMES), MARGIN_EDGES.size - 1), dtype=np.int64)
    failed, n, t_end = _run_samples(gamma, mu, x, u, a, eta, np.asarray(inputs["damping_regime"], dtype=np.int64),
                                    events, t_max, energy_stop, RATIO_EDGES, MARGIN_EDGES,
                                    counts, min_ratio, min_margin, ratio_hist, margin_hist)
    if failed >= 0:  # as bounce.trajectory.run_into_trajectory reports it
        raise RuntimeError(f"root finder did not converge after event {n} (t = {t_end!r}); "
                           "please report the parameters and initial state")
    return {**{k: np.asarray(inputs[k]) for k in ("gamma", "mu", "damping_regime", "energy")},
            "counts": counts, "min_ratio": min_ratio, "min_margin": min_margin,
            "ratio_hist": ratio_hist, "margin_hist": margin_hist}


@njit(cache=True)
def _bin(v, edges):
    """The bin of v as ``np.histogram(v, edges)`` counts it (the last bin closed), -1 outside [edges[0], edges[-1]]
    or NaN."""
    last = edges.size - 1
    if not (edges[0] <= v <= edges[last]):
        return -1
    if v == edges[last]:
        return last - 1
    return np.searchsorted(edges, v, side="right") - 1


@njit(cache=True)
def _run_samples(gamma, mu, x, u, a, eta, regime, events, t_max, energy_stop, ratio_edges, margin_edges,
                 counts, min_ratio, min_margin, ratio_hist, margin_hist):
    """The sweep's per-sample work, compiled: per sample the oscillator tables of mu
    (:func:`bounce.exact.oscillator.oscillator_tables`, ~16 us, a fifth of the sample's time at 100 events), the
    event loop (which builds the tables of mu/sqrt(2) itself at a first sticky phase, rare: the theorem's point),
    the event counts, the contact scales
    (:func:`bounce.analysis.anomalies._contact_scales`), the smallest ratio and margin (``np.min``: a NaN margin
    gives NaN) and the histograms (``np.histogram``'s bins; margins clipped to the last edge).  Fills the outputs;
    returns (-1, 0, 0.0), or (sample, events, t) of the first sample whose root search failed."""
    out_t, out_tau, out_u, out_a, out_eta, out_e = (np.empty(events), np.empty(events), np.empty(events),
                                                    np.empty(events), np.empty(events), np.empty(events))
    out_kind = np.empty(events, dtype=np.int8)
    ref = np.empty(events)
    mar = np.empty(events)
    top = margin_edges[margin_edges.size - 1]
    no_params, no_coefs = np.empty(0), np.empty((0, 0))  # mu/sqrt(2): built by run_events if a sample sticks
    for i in range(gamma.size):
        g, m = gamma[i], mu[i]
        params, coefs = oscillator_tables(m)
        n, reason, t_end = run_events(x[i], u[i], a[i], eta[i], g, params, coefs, no_params, no_coefs, events, t_max,
                                      energy_stop, out_t, out_tau, out_u, out_a, out_eta, out_e, out_kind)
        if reason == STOP_FAILED:
            return i, n, t_end
        for k in range(n):
            counts[i, out_kind[k]] += 1
        _contact_scales(x[i], u[i], a[i], eta[i], out_tau[:n], out_u[:n], out_a[:n], out_eta[:n], out_kind[:n],
                        g, m, params, coefs, ref[:n], mar[:n])
        reg = regime[i]
        r_min = np.inf
        v_min = np.inf
        found = False
        for k in range(n):
            r = ref[k]
            if not math.isfinite(r):
                continue
            v = mar[k]
            if not found:
                r_min, v_min, found = r, v, True
            else:
                r_min = min(r_min, r)
                if not (v_min != v_min) and (v != v or v < v_min):  # NaN propagates, as in np.min
                    v_min = v
            b = _bin(r, ratio_edges)
            if b >= 0:
                ratio_hist[reg, b] += 1
            if v == v:  # np.minimum(NaN, top) is NaN, which np.histogram does not count
                b = _bin(v if v < top else top, margin_edges)
                if b >= 0:
                    margin_hist[reg, b] += 1
        if found:
            min_ratio[i], min_margin[i] = r_min, v_min
    return -1, 0, 0.0


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
            ax.step(edges[1:][keep], cum[keep], where="post", label=f"{name} ({int(total):,} impacts)")
        ax.set(xscale="log", yscale="log", xlabel=xlabel, ylabel="fraction of impacts below")
    r = np.geomspace(1e-4, 1e-1, 10)
    axes[0].plot(r, 0.5 * r**2, "k:", label=r"$\propto r^2$ (grazing dip)")
    axes[1].axvline(1.0, color="k", ls="--", lw=0.8, label="window: tangential below")
    axes[0].set_title("(a) speed ratio at an impact: the grazing dip", fontsize=8)
    axes[1].set_title("(b) impact speed over the classifier's window", fontsize=8)
    handles, labels = axes[0].get_legend_handles_labels()
    window = axes[1].get_legend_handles_labels()
    fig.legend(handles + window[0][-1:], labels + window[1][-1:], loc="outside lower center", ncols=3, fontsize=7,
               frameon=False)
    a = ds.attrs
    fig.suptitle(f"Theorem contact-non-generic: {a['n_samples']:,} random states x {a['events']} events; "
                 f"grazing {a['n_grazing']}, sticky_start {a['n_sticky_start']}", fontsize=8)
    save(fig, outputs)


def estimated_memory_mb(spec: dict) -> int:
    """One worker: the sweep's random states (8 arrays of n_samples) and one short trajectory."""
    return math.ceil(8 * 8 * int(spec["n_samples"]) * 2 / 1e6 + 64 * int(spec["events"]) / 1e6) + 300


SWEEP = Sweep(NAME, "Theorem contact-non-generic: Monte Carlo of contact speeds over random initial states",
              size, prepare, compute, VARIABLES, finish, plot, estimated_memory_mb)

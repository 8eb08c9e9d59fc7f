"""Check ``rigid-model-suffices``: up to when the rigid gas reproduces the dimer gas (beyond the paper).

The least-model question of :mod:`bounce.studies.reduced`, asked of a gas: from the same random state on a ring, the
rigid points with restitution r against the dimers with exp(-mu T_xi) = r (sweep ``rigid-suffices``,
:mod:`bounce.sweeps.rigid_suffices`: what is compared, why the twin is fair, the parting times t_seq of the
collision sequences and t_temp of the temperatures, in mean free times 1/omega0).

1. ``sequence-parting-1-over-n`` (one row per r): the rigid collisions per grain before the collision sequences part
   fall as 1/n, i.e. the whole gas makes a number of collisions independent of n before they part.  Why: a dimer
   collision lasts T_xi, so a rigid collision followed within T_xi by another collision of one of its grains is a
   three-body contact for the dimers, a different history (the sweep's ``t_unresolved``); at uniform positions such
   a pair comes with a probability ~omega0 T_xi per collision (~0.035 at the sweep's speed 0.01), so after a number of
   collisions of the whole gas that does not depend on n.  Fitted: log c = a + s log n over the states that parted
   (least squares; the standard error of s from the residuals: the states' scatter); reproduced if
   |s + 1| <= ``sigmas`` x its standard error, decided only where that tolerance is below 1, so that a count per grain
   independent of n (s = 0, the alternative) would be refuted (else not checkable: the sweep has too few states or
   too narrow a range of n to tell the two apart).  States with no parting before the rigid run's end are left out
   (counted in the row: a censored few at the smallest n).
2. ``temperature-holds-to-collapse``: where the rigid gas collapses (in most states of an (r, n) cell), its
   temperature stays within the sweep's ``temperature_rtol`` of the dimers' up to its collapse: the median over the
   cell's states of t_temp / t_collapse is >= 1 (t_temp is the first grid time from which on the two differ for
   good, so >= 1 means the ratio was within the tolerance at the grid's last time before the collapse; resolution:
   one step of the grid).  The rigid model gets the temperature right, the sequence wrong, until it collapses.
3. ``temperature-outlasts-sequence``: in the states whose temperatures part within the horizon, the collision
   sequences part first (t_seq < t_temp) significantly more often than not (one-sided sign test at ``sign_alpha``;
   not checkable with too few states to reach it): the collision-by-collision history is the first observable the
   rigid model loses.  Not "in every state": at n = 10 one state of the CI size parts the other way.

Measured on the default sweep (r in {0.5, 0.8, 0.95}, n in {10, 30, 100, 300}, 8 states each; ``python -m bounce
check rigid-model-suffices/...``): slopes -1.20 +- 0.16, -0.70 +- 0.18, -1.02 +- 0.14; the whole gas makes 36 +- 4
collisions before the sequences part, ~1.2 / (omega0 T_xi); in the cells that collapse t_temp / t_collapse has
medians 1.07 .. 1.14 for n >= 30 (the grid's step is a factor 1.23) and 0.993 at r = 0.5, n = 10, within the one
step by which t_temp is resolved (claim 2's tolerance); the
temperatures never part within 300 mean free times at r = 0.95 (no collapse) but in a few states; claim 3 holds in
all 58 states whose temperatures part, t_temp / t_seq median 59.
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import xarray as xr

from .base import (BEYOND, NOT_CHECKABLE, Check, Falsifier, Verdict, claim, judge, on_named, split_inputs, variable,
                   with_variable)

NAME = "rigid-model-suffices"
SUBJECT = "beyond:gases"
SWEEP = "rigid-suffices"
REF = "introduction (rigid models of granular gases); the least model of the single ball (beyond the paper)"


def fit_power(n: np.ndarray, c: np.ndarray) -> tuple[float, float, int]:
    """(s, its standard error, points) of log c = a + s log n over the finite positive c; NaN with fewer than two n."""
    ok = np.isfinite(c) & (c > 0)
    x, y = np.log(n[ok].astype(float)), np.log(c[ok])
    if np.unique(x).size < 2 or x.size < 3:
        return math.nan, math.nan, int(ok.sum())
    A = np.column_stack([np.ones(x.size), x])
    coef, *_ = np.linalg.lstsq(A, y, rcond=None)
    resid = y - A @ coef
    cov = float(resid @ resid) / (x.size - 2) * np.linalg.inv(A.T @ A)
    return float(coef[1]), math.sqrt(cov[1, 1]), int(ok.sum())


def measure(spec: dict, inputs: list) -> SimpleNamespace:
    _, named = split_inputs(inputs)
    ds = named[SWEEP]
    r, ns = ds["r"].values, ds["n"].values
    parted = np.isfinite(ds["t_seq"].values)
    c = np.where(parted, ds["collisions_seq"].values, np.nan)
    n_full = np.broadcast_to(ns[None, :, None], c.shape)
    fits = [fit_power(n_full[i].ravel(), c[i].ravel()) for i in range(r.size)]
    whole = (n_full * c)[parted]
    contact = (ds["omega0"].values * ds["T_xi"].values[:, None, None])[parted]
    data = xr.Dataset(coords={"r": ("r", r, {"long_name": "restitution coefficient r", "units": "1"}),
                              "n": ("n", ns, {"long_name": "number of grains", "units": "1"})})
    data["collisions_seq_mean_log"] = variable(("r", "n"), np.nanmean(np.log(c), axis=-1),
                                               "mean over the parted states of ln(rigid collisions per grain before "
                                               "the sequences part)")
    data["collisions_seq_se_log"] = variable(("r", "n"), np.nanstd(np.log(c), axis=-1, ddof=1)
                                             / np.sqrt(np.maximum(parted.sum(axis=-1), 1)),
                                             "its standard error over the states")
    data["slope"] = variable(("r",), [f[0] for f in fits], "fitted exponent s of collisions per grain ~ n^s")
    data["slope_err"] = variable(("r",), [f[1] for f in fits], "standard error of s")
    data.attrs.update(check=NAME, sigmas=float(spec["sigmas"]), samples=int(ds.attrs["samples"]))
    ctx = (f"sweep {SWEEP}: {int(ds.attrs['samples'])} random ring states per (r, n), r in {list(map(float, r))}, n in "
           f"{list(map(int, ns))}, rms speed {float(ds.attrs['speed']):g}, each as rigid points (restitution r) and "
           f"as dimers (exp(-mu T_xi) = r) to {float(ds.attrs['horizon']):g} mean free times or the rigid collapse")
    return SimpleNamespace(ds=ds, r=r, ns=ns, parted=parted, fits=fits, whole=whole, contact=contact, data=data,
                           ctx=ctx)


CLAIMS: list = []


def _per_grain_fixed(ds):
    """Partings after a number of collisions per grain independent of n: collisions_seq x n / n_min."""
    n = ds["n"].values
    return with_variable(ds, "collisions_seq", ds["collisions_seq"].values * (n / n.min())[None, :, None])


def _temperature_early(ds):
    """Temperatures that part at a third of the simulated time (t_temp and t_temp / t_collapse x 1/3)."""
    return with_variable(with_variable(ds, "t_temp", ds["t_temp"].values / 3.0), "t_temp_collapse",
                         ds["t_temp_collapse"].values / 3.0)


def _temperature_first(ds):
    """Temperatures that part before the collision sequences in every state that parts: t_temp = t_seq / 2."""
    t_temp = np.where(np.isfinite(ds["t_temp"].values), ds["t_seq"].values / 2.0, ds["t_temp"].values)
    return with_variable(ds, "t_temp", t_temp)


@claim(CLAIMS, "sequence-parting-1-over-n", BEYOND, SUBJECT,
       falsifier=Falsifier("partings after a number of collisions per grain independent of n (collisions_seq x n/n_min: "
                           "s = 0, the alternative)", on_named(SWEEP, _per_grain_fixed)))
def sequence_parting_1_over_n(m, spec):
    k = float(spec["sigmas"])
    text = ("the rigid gas reproduces the dimer gas's collision sequence for a number of collisions per grain that "
            "falls as 1/n (a fixed number of collisions of the whole gas)")
    computed = (m.ctx + "; per r, least squares of ln(collisions per grain before the sequences part) against ln n "
                "over the states that parted")
    rows = {}
    for i, r in enumerate(m.r):
        s, se, points = m.fits[i]
        left = int((~m.parted[i]).sum())
        if not math.isfinite(s):
            rows[f"r={r:g}"] = Verdict(text, REF, computed, "s = -1", f"{points} parted states: no fit", "none",
                                       NOT_CHECKABLE)
            continue
        measured = (f"s = {s:.3f} +- {se:.2g} ({points} states; {left} without a parting before the rigid run's end "
                    f"left out); whole-gas collisions before the parting, all r: mean {m.whole.mean():.3g} +- "
                    f"{m.whole.std(ddof=1) / math.sqrt(m.whole.size):.2g}, x omega0 T_xi: "
                    f"{np.mean(m.whole * m.contact):.3g}")
        decided = k * se < 1.0
        rows[f"r={r:g}"] = Verdict(text, REF, computed, "s = -1", measured,
                                   f"|s + 1| <= {k:g} x its standard error (the states' scatter) = {k * se:.2g}; decided "
                                   "only below 1, where a count per grain independent of n (s = 0) would be refuted",
                                   judge(abs(s + 1.0) <= k * se) if decided else NOT_CHECKABLE)
    return rows


@claim(CLAIMS, "temperature-holds-to-collapse", BEYOND, SUBJECT,
       falsifier=Falsifier("temperatures parting at a third of the simulated time (t_temp / 3)",
                           on_named(SWEEP, _temperature_early)))
def temperature_holds_to_collapse(m, spec) -> Verdict:
    ds = m.ds
    rtol = float(ds.attrs["temperature_rtol"])
    text = ("where the rigid gas collapses, its temperature stays within a tolerance of the dimer gas's up to the "
            "collapse")
    computed = (m.ctx + f"; per (r, n) cell in which most rigid runs collapse, the median over its collapsing states of "
                f"t_temp / t_collapse (t_temp: the first time of the log grid from which on |T_dimer/T_rigid - 1| > "
                f"{rtol:g})")
    collapses = np.mean(np.isfinite(ds["collapse_time"].values), axis=-1) >= 0.5
    if not collapses.any():
        return Verdict(text, REF, computed, "median >= 1", "no cell collapses in most states", "none", NOT_CHECKABLE)
    ratio = ds["t_temp_collapse"].values  # NaN in the states that did not collapse
    med = np.full(collapses.shape, np.nan)
    med[collapses] = [np.nanmedian(ratio[i, j]) for i, j in zip(*np.nonzero(collapses))]
    step = float(ds["time"].values[1] / ds["time"].values[0])
    cells = "; ".join(f"r={m.r[i]:g}, n={m.ns[j]}: {med[i, j]:.3g}" for i, j in zip(*np.nonzero(collapses)))
    # t_temp is a grid time and t_collapse is not: a parting at the collapse reads as low as 1/step
    return Verdict(text, REF, computed, "median t_temp / t_collapse >= 1 in every such cell",
                   f"{cells} (grid step: a factor {step:.3g})",
                   f">= 1/{step:.3g}: one step of the log grid, where t_temp is resolved (t_collapse lies between two "
                   f"grid times); tolerance on T: {rtol:g} (sweep temperature_rtol)",
                   judge(bool(np.all(med[collapses] >= 1.0 / step))))


@claim(CLAIMS, "temperature-outlasts-sequence", BEYOND, SUBJECT,
       falsifier=Falsifier("temperatures parting at half the sequences' parting time in every state (t_temp = t_seq/2)",
                           on_named(SWEEP, _temperature_first)))
def temperature_outlasts_sequence(m, spec) -> Verdict:
    ds = m.ds
    text = "the collision sequence is the first observable the rigid model loses: it parts before the temperature"
    t_seq, t_temp = ds["t_seq"].values, ds["t_temp"].values
    temp = np.isfinite(t_temp)
    computed = m.ctx + "; the states whose temperatures part within the horizon"
    if not temp.any():
        return Verdict(text, REF, computed, "t_seq < t_temp", "no temperatures parted", "none", NOT_CHECKABLE)
    first = t_seq[temp] < t_temp[temp]
    ratio = t_temp[temp] / t_seq[temp]
    k, m_states, alpha = int(first.sum()), int(temp.sum()), float(spec["sign_alpha"])
    # one-sided sign test against "either may part first" (probability 1/2 each): P(K >= k)
    p_value = sum(math.comb(m_states, j) for j in range(k, m_states + 1)) / 2.0**m_states
    measured = (f"{k} of {m_states} states (sign test p = {p_value:.2g}); t_temp / t_seq: median {np.median(ratio):.3g}, "
                f"range [{ratio.min():.3g}, {ratio.max():.3g}]")
    tolerance = (f"sign test at p <= {alpha:g} (a counterexample at n = 10 exists: the claim is about the typical "
                 "state, not every state)")
    if 0.5**m_states > alpha:  # even k = m could not reach the level
        return Verdict(text, REF, computed, "t_seq < t_temp in most states", measured + f"; too few states for p <= "
                       f"{alpha:g} (at least {math.ceil(math.log2(1.0 / alpha))})", tolerance, NOT_CHECKABLE)
    return Verdict(text, REF, computed, "t_seq < t_temp in most states", measured, tolerance,
                   judge(p_value <= alpha))


def plot(ds: xr.Dataset, spec: dict, outputs) -> None:
    """Rigid collisions per grain before the sequences part against n (geometric means, their errors), the fitted
    power laws and a 1/n guide."""
    from ..figures.common import WIDTH, plt, save

    fig, ax = plt.subplots(figsize=(0.6 * WIDTH, 2.8), constrained_layout=True)
    n = ds["n"].values
    for i, r in enumerate(ds["r"].values):
        mean, se = ds["collisions_seq_mean_log"].values[i], ds["collisions_seq_se_log"].values[i]
        line = ax.errorbar(n, np.exp(mean), yerr=[np.exp(mean) - np.exp(mean - se), np.exp(mean + se) - np.exp(mean)],
                           fmt="o", ms=3, capsize=2,
                           label=rf"r = {r:g}: $s = {ds['slope'].values[i]:.2f} \pm {ds['slope_err'].values[i]:.2f}$")
        ok = np.isfinite(mean)
        if ok.any() and np.isfinite(ds["slope"].values[i]):
            b = np.mean(mean[ok] - ds["slope"].values[i] * np.log(n[ok]))
            ax.plot(n, np.exp(b) * n ** ds["slope"].values[i], "-", lw=0.7, color=line[0].get_color())
    ax.plot(n, np.exp(np.nanmean(ds["collisions_seq_mean_log"].values[:, 0])) * n[0] / n, "k:", lw=0.8,
            label=r"$\propto 1/n$")
    ax.set(xscale="log", yscale="log", xlabel="number of grains n",
           ylabel="rigid collisions per grain\nbefore the sequences part")
    ax.legend(fontsize=6)
    fig.suptitle("rigid vs dimer gas: collisions before their collision sequences part (geometric means)", fontsize=8)
    save(fig, outputs)


TITLE = "Beyond the paper: where the rigid gas suffices for the dimer gas (sweep rigid-suffices)"
CHECK = Check(NAME, measure, tuple(CLAIMS), plot, TITLE)

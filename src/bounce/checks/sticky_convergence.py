"""Section 8.2: eps-solutions of eq. sticky-ic converge to the sticky solution (figs. sticky-traj,
sticky-convergence), t_c = 5.23... and the unstated (gamma, mu).

Inputs (in order): results/data/sticky-convergence.nc (eps, n_impacts, rms; attrs t_c, gamma, mu,
samples) and results/data/sticky-inference.nc (t_c on a gamma x mu grid).  The per-eps event files
(results/data/sticky/eps*.nc, spec ``sticky_dir``) are used to re-integrate the RMS norm of eq.
L2-norm on finer grids.

Own closed form for t_c (independent of the simulator): on the sticky phase F(t) = 2 gamma (C(t) - 1)
- (alpha/2) S(t), alpha = 4 gamma mu - Ydot0, with C, S the fundamental solutions of w'' + mu w' +
w/2 = 0 (see :mod:`bounce.checks.sticky_lemmas`); t_c is its first zero after 0.
"""

from __future__ import annotations

import glob
import math
import os

import numpy as np
import xarray as xr
from scipy.optimize import brentq

from ..io import read_dataset, sample_dataset
from ..sticky_study import fit_loglog
from .base import NOT_CHECKABLE, Check, Verdict, judge, verdict_dataset
from .sticky_lemmas import sticky_fundamental

NAME = "sticky-convergence"


def _v(dims, values, long_name, units="1", **extra):
    return (dims, np.asarray(values), {"long_name": long_name, "units": units, **extra})


def t_c_closed_form(gamma: float, mu: float, ydot0: float = -0.1) -> float:
    """First detach time of the eps = 0 sticky phase of eq. sticky-ic (nan if it never detaches)."""
    alpha = 4.0 * gamma * mu - ydot0

    def F(t):
        C, S = sticky_fundamental(mu, t)
        return float(2.0 * gamma * (C - 1.0) - 0.5 * alpha * S)

    if mu >= math.sqrt(2.0):
        return math.nan
    w = math.sqrt(0.5 - mu * mu / 4.0)
    for k in range(1, 6):  # lobes where S < 0
        t = np.linspace((2 * k - 1) * math.pi / w, 2 * k * math.pi / w, 2001)
        f = np.array([F(x) for x in t])
        idx = np.flatnonzero((f[:-1] < 0) & (f[1:] >= 0))
        if idx.size:
            i = int(idx[0])
            return brentq(F, t[i], t[i + 1], xtol=1e-15, rtol=4 * np.finfo(float).eps)
    return math.nan


def gamma_band(mu: float, lo: float, hi: float, g_range, ydot0: float = -0.1):
    """gamma interval with lo <= t_c(gamma, mu) < hi (t_c increases with gamma), by bisection on the closed form."""
    def g_at(level):
        a, b = g_range
        fa, fb = t_c_closed_form(a, mu, ydot0) - level, t_c_closed_form(b, mu, ydot0) - level
        if fa > 0 or fb < 0:
            return math.nan
        return brentq(lambda g: t_c_closed_form(g, mu, ydot0) - level, a, b, xtol=1e-14)
    return g_at(lo), g_at(hi)


def rms_on_grid(run: xr.Dataset, ref: xr.Dataset, t_c: float, n: int) -> float:
    grid = np.linspace(0.0, t_c, int(n))
    d = sample_dataset(run, grid)["y_minus_yeq"] - sample_dataset(ref, grid)["y_minus_yeq"]
    return float(np.sqrt(np.trapezoid(d * d, grid) / t_c))


def run(spec: dict, inputs) -> xr.Dataset:
    conv, inf = inputs[0], inputs[1]
    eps = conv["eps"].values
    rms = conv["rms"].values
    nimp = conv["n_impacts"].values
    t_c = float(conv.attrs["t_c"])
    gamma, mu = float(conv.attrs["gamma"]), float(conv.attrs["mu"])
    samples = int(conv.attrs.get("samples", spec.get("samples", 20001)))
    ydot0 = float(inf.attrs.get("ydot0", spec.get("ydot0", -0.1)))
    t_paper = float(inf.attrs.get("t_c_paper", spec.get("t_c_paper", 5.23)))
    verdicts = []

    # ---- RMS falls faster than linearly
    eps_max = float(spec.get("fit_eps_max", 1e-3))
    sel = eps <= eps_max
    p_all, _, p_all_err = fit_loglog(eps, rms)
    p, c, p_err = fit_loglog(eps[sel], rms[sel])
    local = np.diff(np.log(rms)) / np.diff(np.log(eps))
    verdicts.append(Verdict(
        claim="The RMS difference ||y_eps - y_s|| falls to zero faster than linearly in eps",
        paper_ref="sec. 8.2, eq. L2-norm, fig. sticky-convergence",
        computed=f"least-squares slope of log rms vs log eps for eps <= {eps_max:g} ({int(sel.sum())} points) and over "
                 f"all {eps.size}; gamma = {gamma}, mu = {mu}, t_c = {t_c:.6f}",
        expected="exponent p > 1",
        measured=f"p = {p:.4f} +- {p_err:.4f} (eps <= {eps_max:g}); all eps: {p_all:.4f} +- {p_all_err:.4f}; local "
                 f"slopes (small to large eps) {np.round(local, 3).tolist()}, tending to ~5/3 as eps -> 0",
        tolerance="p - 3 sigma > 1 (sigma = standard error of the slope) and every local slope > 1",
        verdict=judge(p - 3 * p_err > 1 and bool(np.all(local > 1)))))
    verdicts.append(Verdict(
        claim="As eps decreases the eps-solutions tend to the sticky solution",
        paper_ref="sec. 8.2, figs. sticky-traj, sticky-convergence",
        computed="rms at each eps, ordered by eps",
        expected="strictly decreasing to 0 as eps -> 0",
        measured=f"rms from {rms[-1]:.3g} (eps = {eps[-1]:g}) to {rms[0]:.3g} (eps = {eps[0]:g}); strictly monotone: "
                 f"{bool(np.all(np.diff(rms) > 0))}",
        tolerance="strict monotonicity (grid error of the norm, measured below, is 1e-10 relative)",
        verdict=judge(bool(np.all(np.diff(rms) > 0)) and rms[0] < 1e-3 * rms[-1])))

    # ---- impacts in (0, t_c)
    q, _, q_err = fit_loglog(eps[sel], nimp[sel])
    verdicts.append(Verdict(
        claim="The number of impacts in (0, t_c) grows without bound as eps -> 0",
        paper_ref="sec. 8.2, fig. sticky-convergence",
        computed=f"impacts of the lower mass in (0, t_c) per eps; power-law fit for eps <= {eps_max:g}",
        expected="strictly increasing as eps decreases (the paper shows the figure only, no law)",
        measured=f"{nimp[::-1].tolist()} for eps = {eps[::-1].tolist()}; fit n ~ eps^({q:.4f} +- {q_err:.4f}); "
                 f"rms * n^2 = {np.round(rms * nimp.astype(float) ** 2, 6)[sel].tolist()}",
        tolerance="strict monotonicity (counts are exact)",
        verdict=judge(bool(np.all(np.diff(nimp) < 0)))))

    # ---- grid error of the RMS integral
    sticky_dir = spec.get("sticky_dir", "results/data/sticky")
    files = {}
    for f in sorted(glob.glob(os.path.join(sticky_dir, "eps*.nc"))):
        ds = read_dataset(f)
        files[float(ds.attrs["xdot0"])] = ds
    recheck = [float(e) for e in spec.get("recheck_eps", eps.tolist())]
    grid_same = np.full(len(recheck), np.nan)
    grid_fine = np.full(len(recheck), np.nan)
    grid_finer = np.full(len(recheck), np.nan)
    consistent = 0.0 in files and math.isclose(float(files[0.0].attrs["gamma"]), gamma) and math.isclose(
        float(files[0.0].attrs["mu"]), mu)
    if consistent and all(e in files for e in recheck):
        ref = files[0.0]
        for i, e in enumerate(recheck):
            grid_same[i] = rms_on_grid(files[e], ref, t_c, samples)
            grid_fine[i] = rms_on_grid(files[e], ref, t_c, 2 * samples - 1)
            grid_finer[i] = rms_on_grid(files[e], ref, t_c, 4 * samples - 3)
        stored = np.array([rms[np.argmin(np.abs(eps - e))] for e in recheck])
        same_ok = np.abs(grid_same - stored) <= 1e-12 * stored
        rel = np.abs(grid_fine - grid_same) / grid_fine
        order = np.log2(np.abs(grid_same - grid_finer) / np.abs(grid_fine - grid_finer) - 1)  # Richardson
        # effect on the fitted exponent: refit with the finer values
        rms_fine = rms.copy()
        for e, v in zip(recheck, grid_fine):
            rms_fine[np.argmin(np.abs(eps - e))] = v
        p_fine = fit_loglog(eps[sel], rms_fine[sel])[0]
        verdicts.append(Verdict(
            claim="The RMS integral (trapezoid rule) is converged on the pipeline's grid",
            paper_ref="eq. L2-norm (quadrature of the report, not of the paper)",
            computed=f"rms of eps in {recheck} re-integrated from results/data/sticky on {samples}, {2 * samples - 1} and "
                     f"{4 * samples - 3} points of [0, t_c]",
            expected="same grid reproduces the stored value; twice-finer grid changes it by far less than the "
                     "fit's scatter",
            measured=f"same grid: {int(same_ok.sum())}/{len(recheck)} equal; max relative change on the finer grid "
                     f"{np.max(rel):.2g}; observed order {np.nanmedian(order):.2f}; exponent {p:.6f} -> {p_fine:.6f}",
            tolerance=f"same grid 1e-12 relative; finer grid < 1e-6 relative (the slope's standard error {p_err:.2g} "
                      "corresponds to ~1e-2 relative scatter of the rms values)",
            verdict=judge(bool(np.all(same_ok)) and float(np.max(rel)) < 1e-6)))
    else:
        verdicts.append(Verdict(
            claim="The RMS integral (trapezoid rule) is converged on the pipeline's grid",
            paper_ref="eq. L2-norm",
            computed=f"re-integration from {sticky_dir}",
            expected="-",
            measured=f"per-eps files for {recheck} (with gamma = {gamma}, mu = {mu}) not found in {sticky_dir}",
            tolerance="-",
            verdict=NOT_CHECKABLE))

    # ---- t_c
    t_cf = t_c_closed_form(gamma, mu, ydot0)
    trunc = math.floor(t_c * 100) / 100
    verdicts.append(Verdict(
        claim="The eps = 0 solution of eq. sticky-ic sticks for t_c = 5.23...",
        paper_ref="sec. 8.2 (t_c = 5.23...)",
        computed=f"detach time of the simulator (attribute t_c) with the inferred gamma = {gamma}, mu = {mu}, "
                 f"Ydot0 = {ydot0}; own closed form (first zero of 2 gamma (C - 1) - (alpha/2) S)",
        expected=f"{t_paper} (truncated to two decimals); simulator = closed form",
        measured=f"t_c = {t_c:.12f} (closed form {t_cf:.12f}, rel. difference {abs(t_c - t_cf) / t_cf:.1g})",
        tolerance="truncation to the paper's two decimals; 1e-12 relative between simulator and closed form "
                  "(detach times are exact to rounding)",
        verdict=judge(abs(trunc - t_paper) < 1e-9 and abs(t_c - t_cf) <= 1e-12 * t_cf)))

    # ---- inference: how unique
    g_grid, m_grid = inf["gamma"].values, inf["mu"].values
    tc_grid = inf["t_c"].values
    band = (np.floor(tc_grid * 100) / 100 == t_paper)
    ii, jj = np.nonzero(band)
    g_lo_grid, g_hi_grid = (float(g_grid[ii].min()), float(g_grid[ii].max())) if ii.size else (math.nan, math.nan)
    m_lo_grid, m_hi_grid = (float(m_grid[jj].min()), float(m_grid[jj].max())) if jj.size else (math.nan, math.nan)
    mus_band = [float(m) for m in spec.get("band_mu", [0.0, mu, float(m_grid.max())])]
    edges = [gamma_band(m, t_paper, t_paper + 0.01, (float(g_grid.min()), float(g_grid.max())), ydot0) for m in mus_band]
    tc_at = [t_c_closed_form(gamma, m, ydot0) for m in (float(m_grid.min()), float(m_grid.max()))]
    verdicts.append(Verdict(
        claim="gamma and mu of figs. sticky-traj and sticky-convergence",
        paper_ref="sec. 8.2, figs. sticky-traj, sticky-convergence",
        computed="the paper states neither; inferred gamma = mu = 0.01 (those of fig. rigid-fall); t_c(gamma, mu) on "
                 f"the pipeline's {g_grid.size} x {m_grid.size} grid and the band 5.23 <= t_c < 5.24 from the closed form",
        expected="a unique (gamma, mu) reproducing t_c = 5.23...",
        measured=f"band on the grid: {int(band.sum())}/{band.size} cells, gamma in [{g_lo_grid:.5g}, {g_hi_grid:.5g}], "
                 f"mu in [{m_lo_grid:.4g}, {m_hi_grid:.4g}] (grid: mu in [{m_grid.min():g}, {m_grid.max():g}]); "
                 f"closed-form band: "
                 + "; ".join(f"mu = {m:g}: gamma in [{a:.6g}, {b:.6g})" for m, (a, b) in zip(mus_band, edges))
                 + f"; at gamma = {gamma}: t_c = {tc_at[0]:.5f} (mu = {m_grid.min():g}) .. {tc_at[1]:.5f} "
                   f"(mu = {m_grid.max():g}). For each mu the band is ~1 % wide in gamma, but it drifts with mu: "
                   f"gamma in [{np.nanmin([e[0] for e in edges]):.4g}, {np.nanmax([e[1] for e in edges]):.4g}) over "
                   f"mu in [{min(mus_band):g}, {max(mus_band):g}]; mu is not determined by t_c",
        tolerance="-",
        verdict=NOT_CHECKABLE))

    data = xr.Dataset(
        {
            "rms": _v("eps", rms, "RMS difference ||y_eps - y_s|| on (0, t_c) (eq. L2-norm)"),
            "n_impacts": _v("eps", nimp, "impacts of the lower mass in (0, t_c)"),
            "local_slope_rms": _v("eps_mid", local, "local slope d log rms / d log eps"),
            "recheck_eps": _v("recheck", np.array(recheck), "eps re-integrated on finer grids"),
            "rms_same_grid": _v("recheck", grid_same, "rms re-integrated on the pipeline's grid"),
            "rms_fine_grid": _v("recheck", grid_fine, "rms on the twice-finer grid"),
            "rms_finer_grid": _v("recheck", grid_finer, "rms on the four-times-finer grid"),
            "t_c_grid": (("gamma", "mu"), tc_grid, {"long_name": "duration of the eps = 0 sticky phase", "units": "1"}),
            "band_mu": _v("band", np.array(mus_band), "mu at which the gamma band is computed"),
            "band_gamma_lo": _v("band", np.array([e[0] for e in edges]), "smallest gamma with t_c >= 5.23"),
            "band_gamma_hi": _v("band", np.array([e[1] for e in edges]), "gamma where t_c reaches 5.24"),
        },
        coords={"eps": ("eps", eps, {"long_name": "initial lower-mass speed eps (eq. sticky-ic)", "units": "1"}),
                "eps_mid": ("eps_mid", np.sqrt(eps[1:] * eps[:-1]), {"long_name": "geometric midpoint of eps", "units": "1"}),
                "gamma": ("gamma", g_grid, {"long_name": "gamma", "units": "1"}),
                "mu": ("mu", m_grid, {"long_name": "mu", "units": "1"})},
        attrs={"check": NAME, "t_c": t_c, "t_c_closed_form": t_cf, "gamma_inferred": gamma, "mu_inferred": mu,
               "rms_exponent": p, "rms_exponent_err": p_err, "rms_intercept": c, "impacts_exponent": q,
               "impacts_exponent_err": q_err, "fit_eps_max": eps_max, "t_c_paper": t_paper},
    )
    return verdict_dataset(verdicts, data, title="Sticky solutions: eps -> 0 convergence and t_c (section 8.2)")


def plot(ds: xr.Dataset, spec: dict, outputs) -> None:
    from ..figures.common import WIDTH, plt, save

    fig, axs = plt.subplots(1, 3, figsize=(WIDTH, 3.0))
    eps = ds["eps"].values
    sel = eps <= ds.attrs["fit_eps_max"]
    ax = axs[0]
    ax.loglog(eps, ds["rms"].values, "o", ms=3, label="pipeline")
    if np.isfinite(ds["rms_fine_grid"].values).any():
        ax.loglog(ds["recheck_eps"].values, ds["rms_fine_grid"].values, "+", color="C3", ms=6, label="2x finer grid")
    p, c = ds.attrs["rms_exponent"], ds.attrs["rms_intercept"]
    ax.loglog(eps[sel], np.exp(c) * eps[sel] ** p, "k-", lw=0.7,
              label=r"$\propto\epsilon^{%.3f\pm%.3f}$" % (p, ds.attrs["rms_exponent_err"]))
    ax.loglog(eps, eps * ds["rms"].values[-1] / eps[-1], "k:", lw=0.7, label=r"$\propto\epsilon$")
    ax.set_xlabel(r"$\epsilon$")
    ax.set_ylabel(r"$\Vert y_\epsilon - y_s\Vert$")
    ax.legend(fontsize=6, loc="lower right")
    ax.set_title("(a) eq. L2-norm", fontsize=8)
    ax = axs[1]
    ax.loglog(eps, ds["n_impacts"].values, "o", ms=3)
    ax.set_xlabel(r"$\epsilon$")
    ax.set_ylabel(r"impacts in $(0, t_c)$")
    ax.set_title(r"(b) slope $%.3f$ for $\epsilon\leq%g$" % (ds.attrs["impacts_exponent"], ds.attrs["fit_eps_max"]),
                 fontsize=8)
    ax = axs[2]
    g, m, tc = ds["gamma"].values, ds["mu"].values, ds["t_c_grid"].values
    cs = ax.contourf(m, g, tc, levels=20, cmap="viridis")
    fig.colorbar(cs, ax=ax, label=r"$t_c$")
    ax.contour(m, g, tc, levels=[ds.attrs["t_c_paper"], ds.attrs["t_c_paper"] + 0.01], colors="w", linewidths=0.8)
    ax.plot([ds.attrs["mu_inferred"]], [ds.attrs["gamma_inferred"]], "r*", ms=7)
    ax.set_xlabel(r"$\mu$")
    ax.set_ylabel(r"$\gamma$")
    ax.set_title(r"(c) $t_c(\gamma,\mu)$; white: $5.23\leq t_c<5.24$", fontsize=8)
    fig.suptitle(f"Check {NAME}: section 8.2, inferred $\\gamma={ds.attrs['gamma_inferred']:g}$, "
                 f"$\\mu={ds.attrs['mu_inferred']:g}$, $t_c={ds.attrs['t_c']:.4f}$ (dimensionless units)", fontsize=8.5)
    fig.tight_layout()
    save(fig, outputs)


CHECK = Check(NAME, run, plot, title="Sticky solutions: eps -> 0 convergence and t_c (section 8.2)")

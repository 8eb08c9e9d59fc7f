"""Figs. sticky-convergence and sticky-inference (section 8.2)."""

from __future__ import annotations

import numpy as np

from ..sticky_study import fit_loglog
from .common import WIDTH, plt, save


def sticky_convergence(ds, spec, outputs) -> None:
    """Impacts in (0, t_c) and RMS difference (eq. L2-norm) against eps, log-log, with fitted slopes."""
    eps = ds["eps"].values
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(WIDTH, 2.8))
    for ax, var, lab in ((a1, "n_impacts", r"impacts in $(0,t_c)$"), (a2, "rms", r"$\Vert y_\epsilon - y_s\Vert$")):
        y = ds[var].values
        ok = (eps > 0) & (y > 0)
        ax.loglog(eps[ok], y[ok], "o", ms=3, color="C0")
        slope, icpt, err = fit_loglog(eps[ok], y[ok])
        ax.loglog(eps[ok], np.exp(icpt) * eps[ok] ** slope, color="C3", lw=0.8,
                  label=r"fit: slope $%.3f \pm %.3f$" % (slope, err))
        ax.set_xlabel(r"$\epsilon$")
        ax.set_ylabel(lab)
        ax.legend(loc="best")
    fig.suptitle(r"Fig. sticky-convergence: $\gamma=%g$, $\mu=%g$, $t_c=%.4f$"
                 % (ds.attrs["gamma"], ds.attrs["mu"], ds.attrs["t_c"]))
    fig.tight_layout()
    save(fig, outputs)


def sticky_inference(ds, spec, outputs) -> None:
    """t_c(gamma, mu) with the band where it truncates to the paper's 5.23, and the chosen point."""
    fig, ax = plt.subplots(figsize=(WIDTH * 0.7, 3.2))
    g, m, tc = ds["gamma"].values, ds["mu"].values, ds["t_c"].values
    cs = ax.contourf(m, g, tc, levels=20, cmap="viridis")
    fig.colorbar(cs, ax=ax, label=r"$t_c$")
    ax.contour(m, g, tc, levels=[5.23, 5.24], colors="w", linewidths=1.0)
    ax.plot([ds.attrs["mu_chosen"]], [ds.attrs["gamma_chosen"]], "r*", ms=9,
            label=r"chosen: $t_c=%.4f$" % ds.attrs["t_c_chosen"])
    ax.set_xlabel(r"$\mu$")
    ax.set_ylabel(r"$\gamma$")
    ax.set_title(r"Sticky duration $t_c$ (eq. sticky-ic, $\epsilon=0$); white: $5.23\leq t_c<5.24$", fontsize=8)
    ax.legend(loc="lower right", fontsize=7)
    save(fig, outputs)

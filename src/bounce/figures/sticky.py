"""Figs. sticky-convergence and sticky-inference (section 8.2)."""

from __future__ import annotations

import numpy as np

from ..analysis.sticky import fit_loglog
from .common import WIDTH, plt, save, tex_num


def sticky_convergence(datasets, spec, outputs) -> None:
    """Fig. sticky-convergence: impacts in (0, t_c) and the RMS difference (eq. L2-norm) against eps.

    The slopes are those of the validation report: least squares on log-log for
    eps <= fit_eps_max of check sticky-convergence (its dataset is the second input), where
    the asymptotic regime holds; the points above it are drawn hollow.  The dotted line in the
    RMS panel has slope 1 (through the smallest eps): "faster than linearly" means steeper than it.
    """
    ds, check = datasets
    eps_max = float(check.attrs["fit_eps_max"])
    eps = ds["eps"].values
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(WIDTH, 2.9))
    panels = ((a1, "n_impacts", r"impacts in $(0,t_c)$", "impacts_exponent", "(a) impacts of the lower mass"),
              (a2, "rms", r"$\Vert y_\epsilon - y_s\Vert$ (eq. L2-norm)  [$L$]", "rms_exponent",
               "(b) RMS distance to the sticky solution"))
    for ax, var, lab, reported, title in panels:
        y = ds[var].values
        ok = (eps > 0) & (y > 0)
        fit = ok & (eps <= eps_max)
        ax.loglog(eps[fit], y[fit], "o", ms=4, color="C0", label=r"$\epsilon\leq%s$ (fitted)" % tex_num(eps_max))
        if np.any(ok & ~fit):
            ax.loglog(eps[ok & ~fit], y[ok & ~fit], "o", ms=4, color="C0", mfc="none",
                      label=r"$\epsilon>%s$ (not fitted)" % tex_num(eps_max))
        slope, icpt, err = fit_loglog(eps[fit], y[fit])
        if not np.isclose(slope, float(check.attrs[reported]), rtol=1e-9, atol=0.0):
            raise ValueError(f"{var}: slope {slope} differs from the report's {check.attrs[reported]}")
        ax.loglog(eps[ok], np.exp(icpt) * eps[ok] ** slope, color="C3", lw=0.8,
                  label=r"fit: slope $%.3f \pm %s$" % (slope, tex_num(err, 1)))
        if var == "rms":  # the paper: the RMS difference falls to zero faster than linearly
            k = int(np.argmin(np.where(ok, eps, np.inf)))
            ax.loglog(eps[ok], y[k] * eps[ok] / eps[k], color="0.3", lw=0.8, ls=":", label="slope 1 (linear)")
        ax.set_xlabel(r"$\epsilon$ ($=\dot X_0$, eq. sticky-ic)")
        ax.set_ylabel(lab)
        ax.set_title(title, fontsize=8)
        ax.legend(loc="best", fontsize=6.5)
    fig.suptitle(r"Fig. sticky-convergence: $\gamma=%s$, $\mu=%s$, $t_c=%.4f$; slopes fitted for "
                 r"$\epsilon\leq%s$, as in the validation report"
                 % (tex_num(ds.attrs["gamma"]), tex_num(ds.attrs["mu"]), ds.attrs["t_c"], tex_num(eps_max)),
                 fontsize=8)
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

"""Beyond the paper: energy decay and the asymptotic laws of Theorem main_thm, both damping regimes."""

from __future__ import annotations

import numpy as np

from .common import WIDTH, plt, save, tex_num


def _regime(ds):
    return r"$\gamma=%s$, $\mu=%s$" % (tex_num(ds.attrs["gamma"]), tex_num(ds.attrs["mu"]))


def energy_decay(datasets, spec, outputs) -> None:
    """E - E_m (eqs. tot-mech-energy, Emin) against time (linear: the decay is exponential in t), one
    panel per regime, and against the impact index n (log-log), both damping regimes.

    The guides are the rate of check static-equilibrium (beyond the paper): E - E_m ~ e^{-kappa t},
    kappa = min(2 mu/3, 2 lam), lam the slow rate of the sticky oscillator (eq. y-eq-sticky);
    with t_n ~ (3/mu) ln n (Theorem main_thm) this is E - E_m ~ n^{-3 kappa/mu}, the slope
    expected in the last panel, which prints the slope fitted on the last two decades of n.
    """
    from ..analysis.theory import equilibrium_rates

    fig, axes = plt.subplots(1, len(datasets) + 1, figsize=(WIDTH, 2.9))
    a_n = axes[-1]
    for i, (ax, ds) in enumerate(zip(axes, datasets)):
        e = ds["energy_excess"].values
        n = ds["event"].values + 1
        t = ds["t"].values - ds["t"].values[0]
        mu = float(ds.attrs["mu"])
        kappa = equilibrium_rates(mu)["energy"]
        ax.semilogy(t, e, color=f"C{i}", lw=1.0)
        late = n >= n[-1] / 100
        t0, e0 = t[late][0], e[late][0]
        ax.semilogy(t[late], e0 * np.exp(-kappa * (t[late] - t0)), "--", color="C3", lw=1.3,
                    label=r"$\propto e^{-\kappa t}$, $\kappa=%s$" % tex_num(kappa, 4))
        ax.set_xlabel(r"$t - t_1$  [$\sqrt{m/2k}$]")
        ax.set_title("(%s) %s" % ("abc"[i], _regime(ds)), fontsize=8)
        ax.set_ylim(top=1e3 * e.max())  # headroom for the legend, off the curve
        ax.legend(fontsize=6.5, loc="upper right")
        slope = np.polyfit(np.log(n[late]), np.log(e[late]), 1)[0]
        a_n.loglog(n, e, color=f"C{i}", label=r"$\mu=%s$: slope $%.2f$, expected $-3\kappa/\mu=%.2f$"
                   % (tex_num(mu), slope, -3 * kappa / mu))
    axes[0].set_ylabel(r"$E - E_m$")
    a_n.set_xlabel(r"impact index $n$")
    a_n.set_ylabel(r"$E - E_m$", labelpad=1)
    a_n.set_title("(%s) both, against $n$; slopes fitted\nfor $n\\geq n_{max}/100$" % "abc"[len(datasets)], fontsize=7)
    fig.legend(*a_n.get_legend_handles_labels(), loc="lower right", fontsize=6.5, frameon=False, ncol=2,
               title="(c), slope of $\\ln(E-E_m)$ against $\\ln n$:", title_fontsize=6.5)
    fig.suptitle(r"Energy decay to $E_m=-\gamma^2/2$ (Theorem static-equilibrium; rates beyond the paper): "
                 r"$E-E_m\sim e^{-\kappa t}$," "\n"
                 r"$\kappa=\min(2\mu/3,\,2\lambda)$, $\lambda$ the slow decay rate of eq. y-eq-sticky; "
                 r"$t_n\sim(3/\mu)\ln n$ makes it $n^{-3\kappa/\mu}$", fontsize=8)
    fig.tight_layout(rect=(0, 0.09, 1, 1))
    save(fig, outputs)


def asymptotic_laws(datasets, spec, outputs) -> None:
    """n tau_n mu/3 and n Xdot_n mu/(3 gamma) against n (Theorem main_thm: both -> 1)."""
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(WIDTH, 2.8), sharey=False)
    for i, ds in enumerate(datasets):
        mu, gamma = float(ds.attrs["mu"]), float(ds.attrs["gamma"])
        n = ds["event"].values + 1  # impact number n (t_0 = 0 is the release)
        idx = ds["event"].values  # tau_n = t_{n+1} - t_n is stored at event n (0-based)
        tau_n = ds["tau"].values
        sel = idx >= 1
        a1.semilogx(idx[sel], idx[sel] * tau_n[sel] * mu / 3.0, color=f"C{i}", label=_regime(ds))
        a2.semilogx(n, n * ds["xdot"].values * mu / (3.0 * gamma), color=f"C{i}", label=_regime(ds))
    for ax, lab, title in ((a1, r"$n\,\tau_n\,\mu/3$", r"(a) flight time $\tau_n$"),
                           (a2, r"$n\,\dot X_n\,\mu/(3\gamma)$", r"(b) impact speed $\dot X_n$")):
        ax.axhline(1.0, color="k", lw=0.6, ls="--")
        ax.set_title(title + " (dashed: the limit 1)", fontsize=8)
        ax.set_xlabel(r"impact index $n$")
        ax.set_ylabel(lab)
        ax.set_ylim(0.0, 2.0)
    a1.legend(fontsize=7)
    fig.suptitle(r"Theorem main_thm: $\tau_n \sim 3/(\mu n)$ and $\dot X_n \sim 3\gamma/(\mu n)$")
    fig.tight_layout()
    save(fig, outputs)

"""Beyond the paper: energy decay and the asymptotic laws of Theorem main_thm, both damping regimes."""

from __future__ import annotations

import numpy as np

from .common import WIDTH, plt, save


def _regime(ds):
    return r"$\gamma=%g$, $\mu=%g$" % (ds.attrs["gamma"], ds.attrs["mu"])


def energy_decay(datasets, spec, outputs) -> None:
    """E - E_m (eqs. tot-mech-energy, Emin) against the time since the first impact and against n."""
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(WIDTH, 2.9))
    for i, ds in enumerate(datasets):
        e = ds["energy_excess"].values
        n = ds["event"].values + 1
        t = ds["t"].values
        a1.loglog(t[1:] - t[0], e[1:], color=f"C{i}", label=_regime(ds))
        a2.loglog(n, e, color=f"C{i}", label=_regime(ds))
        late = n >= n[-1] / 100
        slope = np.polyfit(np.log(n[late]), np.log(e[late]), 1)[0]
        a2.text(0.04, 0.06 + 0.1 * i, r"late slope %.2f" % slope, color=f"C{i}", transform=a2.transAxes, fontsize=7)
    a1.set_xlabel(r"$t - t_1$ (time since the first impact)")
    a1.set_ylabel(r"$E - E_m$")
    a2.set_xlabel(r"impact index $n$")
    a2.set_ylabel(r"$E - E_m$")
    a1.legend(fontsize=7)
    fig.suptitle("Energy decay towards the equilibrium energy $E_m=-\\gamma^2/2$ (Theorem static-equilibrium)")
    fig.tight_layout()
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
    for ax, lab in ((a1, r"$n\,\tau_n\,\mu/3$"), (a2, r"$n\,\dot X_n\,\mu/(3\gamma)$")):
        ax.axhline(1.0, color="k", lw=0.6, ls="--")
        ax.set_xlabel(r"impact index $n$")
        ax.set_ylabel(lab)
        ax.set_ylim(0.0, 2.0)
    a1.legend(fontsize=7)
    fig.suptitle(r"Theorem main_thm: $\tau_n \sim 3/(\mu n)$ and $\dot X_n \sim 3\gamma/(\mu n)$")
    fig.tight_layout()
    save(fig, outputs)

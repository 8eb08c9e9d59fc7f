"""Figs. rest-coeff and very_rigid_poincare(_magni, _overdamped, _overdamped_magni)."""

from __future__ import annotations

import numpy as np

from .common import WIDTH, plt, save

IMPACT = 0


def _impact_only(ds):
    kind = ds["kind"].values
    if np.any(kind != IMPACT):
        raise ValueError(f"{ds.attrs.get('scene', 'dataset')}: expected impacts only (grazing/sticky events present)")
    return ds


def rest_coeff(ds, spec, outputs) -> None:
    """Fig. rest-coeff: r_n = f_{n+1}/f_n with f_n = tau_{2n} (eqs. Falcon-rest-coeff, my-time-of-flight).

    Indexing: t_0 = 0 is the release and t_n the n-th impact, so tau_n = t_{n+1} - t_n is
    ``tau[n]`` of the file (duration ending at event n, 0-based) and tau_0 is the initial
    fall.  From rest the impacts come in pairs (double impacts, section 8.1): tau_{2n-1}
    are the short intra-contact flights, tau_{2n} the macroscopic ones, so f_n = tau_{2n}.
    f_0 is the release (half a parabola), hence r_n is plotted from n = 1.
    """
    _impact_only(ds)
    tau = ds["tau"].values
    mu = float(ds.attrs["mu"])
    n_max = int(spec.get("n_max", 150))
    f = tau[0::2]
    n = np.arange(1, min(n_max, f.size - 2) + 1)
    r = f[n + 1] / f[n]
    T_xi = np.pi / np.sqrt(1.0 - mu**2)
    fig, ax = plt.subplots(figsize=(WIDTH, 3.0))
    ax.plot(n, r, "o", ms=2.5, color="C0", label=r"$r_n = f_{n+1}/f_n$, $f_n=\tau_{2n}$")
    ax.axhline(np.exp(-mu * T_xi), color="C3", ls="--", label=r"$e^{-\mu T_\xi}$ (eq. rest-coefficient-function-of-mu)")
    ax.set_xlabel(r"$n$ (macroscopic flight)")
    ax.set_ylabel(r"$r_n$")
    lo, hi = spec.get("r_range", (0.6, 1.1))
    out = (r < lo) | (r > hi)
    ax.plot(n[out], np.clip(r[out], lo, hi), "^", ms=3, color="C0", mfc="none",
            label="outside the range (clipped)" if out.any() else None)
    ax.set_ylim(lo - 0.01, hi + 0.01)
    ax.set_title(r"Fig. rest-coeff: $\gamma=%g$, $\mu=%g$, $\psi(0)=%g$" % (ds.attrs["gamma"], mu, ds.attrs["x0"]))
    ax.legend(loc="lower left")
    save(fig, outputs)


def contact_portrait(ds, spec, outputs, magnified: bool) -> None:
    """State just after each contact, (xdot, y - y_eq, ydot), thin lines joining consecutive states.

    The main figure shows the first ``events`` contacts (the transient); the
    magnified one the contacts ``magni_events = [first, last]``, which sit close to
    (0, 0, 0), with axes scaled to them.  Colour: log of the contact index.
    """
    _impact_only(ds)
    n_all = ds.sizes["event"]
    first, last = spec["magni_events"] if magnified else (0, spec["events"])
    sel = np.arange(min(first, n_all - 1), min(last, n_all))
    xdot = ds["xdot"].values[sel]
    ydev = ds["y_minus_yeq"].values[sel]
    ydot = ds["ydot"].values[sel]
    fig = plt.figure(figsize=(WIDTH, 4.8))
    ax = fig.add_subplot(projection="3d")
    ax.plot(xdot, ydev, ydot, color="0.55", lw=0.25)
    pts = ax.scatter(xdot, ydev, ydot, s=1.5, c=np.log10(sel + 1), cmap="viridis", depthshade=False)
    fig.colorbar(pts, ax=ax, shrink=0.6, pad=0.12, label=r"$\log_{10} n$ (contact index)")
    ax.set_xlabel(r"$\dot X_n$", labelpad=8)
    ax.set_ylabel(r"$Y_n - y_{eq}$", labelpad=8)
    ax.set_zlabel(r"$\dot Y_n$", labelpad=8)
    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        axis.get_major_formatter().set_powerlimits((-2, 2))
    what = (r"magnified near $(0,0,0)$: contacts %d-%d" % (sel[0] + 1, sel[-1] + 1) if magnified
            else "contacts 1-%d" % sel.size)
    ax.set_title(r"Fig. %s: state just after each contact, $\gamma=%g$, $\mu=%g$ (%s)"
                 % (spec.get("label", "very_rigid_poincare"), ds.attrs["gamma"], ds.attrs["mu"], what), fontsize=8)
    save(fig, outputs)

"""Figs. rest-coeff and very_rigid_poincare(_magni, _overdamped, _overdamped_magni)."""

from __future__ import annotations

import numpy as np

from .common import WIDTH, plt, save, tex_num

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


def _power(*arrays) -> int:
    """Power of ten p with max|v| / 10^p in [1, 10): the axis then reads ``name / 10^p``, no offset text."""
    m = max(float(np.nanmax(np.abs(a))) if np.size(a) else 0.0 for a in arrays)
    return int(np.floor(np.log10(m))) if m > 0 else 0


def _scaled(name: str, p: int) -> str:
    """Axis label of values drawn in units of 10^p."""
    return name if p == 0 else r"%s  [$\times10^{%d}$]" % (name, p)


XDOT, YDEV, YDOT = r"$\dot X_n$", r"$Y_n - y_{eq}$", r"$\dot Y_n$"


def _states(ds, first: int, last: int):
    """Contact indices n (1-based) and the states just after contacts first+1..last (clipped to the run)."""
    _impact_only(ds)
    n_all = ds.sizes["event"]
    if first >= n_all:
        raise ValueError(f"{ds.attrs.get('scene', 'dataset')}: contacts from {first + 1} requested, "
                         f"the run has {n_all}")
    sel = np.arange(first, min(last, n_all))
    return sel + 1, ds["xdot"].values[sel], ds["y_minus_yeq"].values[sel], ds["ydot"].values[sel]


def _portrait_3d(fig, position, n, xdot, ydev, ydot, title, origin: bool = False):
    """The paper's view: dots at (Xdot_n, Y_n - y_eq, Ydot_n), thin lines in contact order, colour log10 n;
    each axis scaled by its own power of ten (stated in its label).  ``origin``: the equilibrium
    (0, 0, 0) is drawn (red +) and kept in view."""
    ax = fig.add_subplot(position, projection="3d")
    px, pw, pv = _power(xdot), _power(ydev), _power(ydot)
    X, W, V = xdot / 10.0**px, ydev / 10.0**pw, ydot / 10.0**pv
    ax.plot(X, W, V, color="0.6", lw=0.3)
    pts = ax.scatter(X, W, V, s=2 if n.size <= 500 else 0.5, c=np.log10(n), cmap="viridis", depthshade=False)
    if origin:
        ax.plot([0], [0], [0], "r+", ms=8, mew=1.2)
        ax.set_xlim(min(0.0, X.min()), max(0.0, X.max()))
        ax.set_ylim(min(0.0, W.min()), max(0.0, W.max()))
        ax.set_zlim(min(0.0, V.min()), max(0.0, V.max()))
    ax.set_xlabel(_scaled(XDOT, px), labelpad=-2, fontsize=7)
    ax.set_ylabel(_scaled(YDEV, pw), labelpad=-2, fontsize=7)
    ax.set_zlabel(_scaled(YDOT, pv), labelpad=-5, fontsize=7)
    ax.tick_params(labelsize=6, pad=0)
    ax.set_title(title, fontsize=8)
    return ax, pts


def _projection(ax, n, ydev, ydot, title):
    """(Y_n - y_eq, Ydot_n) at the magnification of the window, the origin (equilibrium) marked; the
    states joined in contact order (a line coloured by log10 n), dots only where they do not merge."""
    from matplotlib.collections import LineCollection

    pw = _power(ydev, ydot)
    W, V = ydev / 10.0**pw, ydot / 10.0**pw
    segments = np.stack([np.column_stack([W[:-1], V[:-1]]), np.column_stack([W[1:], V[1:]])], axis=1)
    lines = LineCollection(segments, cmap="viridis", lw=0.5, zorder=1)
    lines.set_array(np.log10(n[:-1]))
    lines.set_clim(np.log10(n[0]), np.log10(n[-1]))
    ax.add_collection(lines)
    if n.size <= 400:
        ax.scatter(W, V, s=1.5, c=np.log10(n), cmap="viridis", zorder=2)
    ax.plot([0], [0], "r+", ms=7, mew=1.0, zorder=3)
    ax.set_xlabel(_scaled(YDEV, pw), labelpad=1, fontsize=7)
    ax.set_ylabel(_scaled(YDOT, pw), labelpad=1, fontsize=7)
    ax.set_title(title, fontsize=7, pad=2)
    ax.tick_params(labelsize=6)
    lim = 1.08 * max(np.max(np.abs(W)), np.max(np.abs(V)))
    ax.set_xlim(-lim, lim)
    ax.set_ylim(-lim, lim)
    ax.set_aspect("equal")


def _regime(ds) -> str:
    return r"$\gamma=%s$, $\mu=%s$" % (tex_num(ds.attrs["gamma"]), tex_num(ds.attrs["mu"]))


def _series(ax, n, values, name):
    """values against the contact index n (log axis), scaled by a power of ten.  Leading contacts
    more than ten times larger than all later ones (the overdamped first impacts) would flatten
    the rest: they are drawn at the edge of the axes as arrows with their value written out."""
    later = np.max(np.abs(values[2:])) if values.size > 2 else 0.0
    big = np.zeros(values.size, dtype=bool)
    big[:2] = (np.abs(values[:2]) > 10.0 * later) & (later > 0)
    p = _power(values[~big])
    v = values / 10.0**p
    lo, hi = min(0.0, v[~big].min()), max(0.0, v[~big].max())
    pad = 0.08 * (hi - lo)
    lo, hi = lo - pad, hi + pad
    ax.axhline(0.0, color="k", lw=0.5)
    ax.plot(n[~big], v[~big], "-", color="0.6", lw=0.4)
    ax.scatter(n[~big], v[~big], s=3, c=np.log10(n[~big]), cmap="viridis", zorder=2, vmin=0, vmax=np.log10(n[-1]))
    for k in np.flatnonzero(big):
        edge = hi if v[k] > 0 else lo
        ax.annotate("", xy=(n[k], edge), xytext=(n[k], edge - 0.25 * (hi - lo) * np.sign(v[k])),
                    arrowprops=dict(arrowstyle="->", color="C3", lw=0.8))
        ax.text(n[k] * 1.15, edge - 0.2 * (hi - lo) * np.sign(v[k]),
                r"$n=%d$: $%s$ (off scale)" % (n[k], tex_num(values[k])), fontsize=6, color="C3", va="center")
    ax.set_ylim(lo, hi)
    ax.set_xscale("log")
    ax.set_ylabel(_scaled(name, p), fontsize=7)
    ax.tick_params(labelsize=6)


def contact_portrait(ds, spec, outputs) -> None:
    """Figs. very_rigid_poincare(_overdamped): state just after each of the first ``events`` contacts.

    (a) the paper's 3-D view (Xdot_n, Y_n - y_eq, Ydot_n); (b) Ydot_n and (c) Y_n - y_eq against n:
    the double impacts' zig-zag (sign of Ydot_n alternating) and the disordered transient for
    mu < 1; for mu = 2 the spring shrinking for the first impacts, then expanding towards its
    equilibrium length monotonically from below (Y_n - y_eq < 0 rising to 0), as section 8.1 says.
    """
    n, xdot, ydev, ydot = _states(ds, 0, int(spec["events"]))
    fig = plt.figure(figsize=(WIDTH, 3.6))
    grid = fig.add_gridspec(2, 2, width_ratios=(1.25, 1.0), hspace=0.28, wspace=0.45)
    ax3, pts = _portrait_3d(fig, grid[:, 0], n, xdot, ydev, ydot, "(a) state just after contact $n$")
    axes = [fig.add_subplot(grid[0, 1]), None]
    axes[1] = fig.add_subplot(grid[1, 1], sharex=axes[0])
    for ax, values, name, letter in zip(axes, (ydot, ydev), (YDOT, YDEV), "bc"):
        _series(ax, n, values, name)
        ax.set_title(f"({letter})", loc="left", fontsize=7, pad=2)
    axes[0].tick_params(labelbottom=False)
    axes[1].set_xlabel(r"contact $n$", fontsize=8)
    bar = fig.colorbar(pts, ax=axes, shrink=0.8, pad=0.03, aspect=30)
    bar.set_label(r"$\log_{10} n$ (contact index)", fontsize=7)
    bar.ax.tick_params(labelsize=6)
    fig.suptitle(r"Fig. %s: %s, contacts 1-%d (lengths in $L$, speeds in $L/\sqrt{m/2k}$; "
                 r"$y_{eq}=1-2\gamma$)" % (spec.get("label", "very_rigid_poincare"), _regime(ds), n[-1]), fontsize=8)
    save(fig, outputs)


def contact_portrait_magni(ds, spec, outputs) -> None:
    """Figs. very_rigid_poincare(_overdamped)_magni: near (0, 0, 0), at several magnifications.

    (a) the 3-D view of the first window of ``magni_windows`` (contact ranges [first, last));
    (b)-(e) the projection (Y_n - y_eq, Ydot_n) of each window, each at its own scale: for mu < 1
    the damped oscillation of the spring about its equilibrium makes the states spiral in (the
    same spiral at every magnification); for mu = 2 they approach it monotonically from below,
    with no spiral.
    """
    windows = [tuple(int(v) for v in w) for w in spec["magni_windows"]]
    states = [_states(ds, a, b) for a, b in windows]
    cols = (len(windows) + 1) // 2
    fig = plt.figure(figsize=(WIDTH, 4.4))
    grid = fig.add_gridspec(2, 1 + cols, width_ratios=(1.6,) + (1.0,) * cols, wspace=0.5, hspace=0.45)
    n, xdot, ydev, ydot = _states(ds, *spec["magni_3d"])
    _portrait_3d(fig, grid[:, 0], n, xdot, ydev, ydot, "(a) contacts %d-%d" % (n[0], n[-1]), origin=True)
    for k, (n, _, ydev, ydot) in enumerate(states):
        _projection(fig.add_subplot(grid[k // cols, 1 + k % cols]), n, ydev, ydot,
                    "(%s) contacts %d-%d" % ("bcdefgh"[k], n[0], n[-1]))
    fig.suptitle(r"Fig. %s: %s, close to $(0,0,0)$" "\n"
                 r"(b)-(%s): projection on $(Y_n-y_{eq}, \dot Y_n)$, each window at its own scale; "
                 r"$+$: equilibrium; colour: $\log_{10} n$" % (spec.get("label", "very_rigid_poincare_magni"),
                                                             _regime(ds), "bcdefgh"[len(windows) - 1]), fontsize=8)
    save(fig, outputs)


def contact_approach_magni(ds, spec, outputs) -> None:
    """Fig. very_rigid_poincare_overdamped_magni: the approach to (0, 0, 0) for mu = 2.

    (a) the 3-D view of the contacts ``magni_3d`` with the equilibrium in view; (b) the three
    coordinates against n on log-log axes over the whole run (every decade a magnification):
    y_eq - Y_n, Ydot_n and Xdot_n stay positive and decrease monotonically from ``magni_3d[0]``
    on -- the spring approaches its equilibrium length from below, with no spiral.  The legend
    counts the contacts where a coordinate has the other sign or is not smaller than the one before.
    """
    n, xdot, ydev, ydot = _states(ds, *spec["magni_3d"])
    fig = plt.figure(figsize=(WIDTH, 3.2))
    grid = fig.add_gridspec(1, 2, width_ratios=(1.2, 1.0), wspace=0.5)
    _portrait_3d(fig, grid[0, 0], n, xdot, ydev, ydot, "(a) contacts %d-%d" % (n[0], n[-1]), origin=True)
    ax = fig.add_subplot(grid[0, 1])
    first = int(spec["magni_3d"][0])
    n, xdot, ydev, ydot = _states(ds, first, ds.sizes["event"])
    bad = 0
    for k, (values, name) in enumerate(((-ydev, r"$y_{eq} - Y_n$"), (ydot, YDOT), (xdot, XDOT))):
        bad += int(np.count_nonzero(values <= 0) + np.count_nonzero(np.diff(values) >= 0))
        ax.loglog(n, np.where(values > 0, values, np.nan), color=f"C{k}", label=name)
    ax.set_xlabel(r"contact $n$")
    ax.set_ylabel(r"state just after contact $n$")
    ax.set_title("(b) contacts %d-%d, log-log" % (n[0], n[-1]), fontsize=8)
    ax.legend(fontsize=7, loc="center right")
    ax.text(0.03, 0.03, "all three positive and decreasing\nat every contact" if bad == 0 else
            "%d (coordinate, contact) pairs not\npositive and decreasing" % bad,
            transform=ax.transAxes, fontsize=7, va="bottom")
    fig.suptitle(r"Fig. %s: %s, close to $(0,0,0)$ (red $+$: equilibrium)"
                 % (spec.get("label", "very_rigid_poincare_overdamped_magni"), _regime(ds)), fontsize=8)
    save(fig, outputs)

"""Figs. rest-coeff and very_rigid_poincare(_magni, _overdamped, _overdamped_magni)."""

from __future__ import annotations

import numpy as np

from ..analysis import theory
from ..kinds import IMPACT
from .common import WIDTH, plt, save, tex_num



def _impact_only(ds):
    kind = ds["kind"].values
    if np.any(kind != IMPACT):
        raise ValueError(f"{ds.attrs.get('scene', 'dataset')}: expected impacts only (grazing/sticky events present)")
    return ds


def _horizon_impacts(horizon, ds) -> int:
    """float64 predictability horizon H (impacts t_1..t_H within the horizon study's tolerance of the
    mpmath reference) of the horizon regime with the scene's gamma, mu and psi(0)."""
    return _horizon(horizon, ds)[0]


def _horizon(horizon, ds) -> tuple[int, bool]:
    """(H, reached): the float64 horizon of :func:`_horizon_impacts`, and whether it was reached inside the impacts
    the study compared (else the float64 run tracked the reference as far as it was computed: H is a lower bound)."""
    for name in horizon["regime"].values:
        d = horizon.sel(regime=name)
        if all(np.isclose(float(d[k]), float(ds.attrs[a])) for k, a in (("gamma", "gamma"), ("mu", "mu"), ("psi0", "x0"))):
            h = int(d["horizon"].sel(precision="float64"))
            return h, h < int(d["n_compared"])
    raise ValueError(f"horizon study has no regime with gamma = {ds.attrs['gamma']}, mu = {ds.attrs['mu']}, "
                     f"psi(0) = {ds.attrs['x0']} (config reduced.horizon.regimes)")


def rest_coeff(datasets, spec, outputs) -> None:
    """Fig. rest-coeff: r_n = f_{n+1}/f_n with f_n = tau_{2n} (eqs. Falcon-rest-coeff, my-time-of-flight).

    Indexing: t_0 = 0 is the release and t_n the n-th impact, so tau_n = t_{n+1} - t_n is
    ``tau[n]`` of the file and tau_0 is the initial fall.  From rest the impacts come in pairs
    (double impacts, section 8.1): tau_{2n-1} ~ T_xi is the flight inside the n-th contact,
    tau_{2n} the macroscopic flight after it, so f_n = tau_{2n} (f_0, the release, is excluded).
    The pairing holds for the first R contacts (R = ``double_run`` of check restitution: the
    contact flight within its band of T_xi); r_n needs contacts n and n + 1, so it is drawn for
    n < R only -- beyond, f_n = tau_{2n} is no longer a macroscopic flight.  The float64
    predictability horizon H (impact times t_1..t_H, horizon study) bounds r_n too: r_n reads
    t_{2n}..t_{2n+3}.  Inputs: the scene, results/checks/restitution.nc, results/methods/horizon.nc.
    (b) shows the contact r_n spans (contact n + 1, inner flight tau_{2n+1}), where the pairing breaks.
    """
    ds, restitution, horizon = datasets
    _impact_only(ds)
    tau = ds["tau"].values
    mu = float(ds.attrs["mu"])
    T_xi = theory.T_xi(mu)
    if restitution.attrs.get("rest_scene") != ds.attrs.get("scene"):
        raise ValueError(f"check restitution read scene {restitution.attrs.get('rest_scene')!r}, "
                         f"the figure draws {ds.attrs.get('scene')!r}")
    paired = int(restitution.attrs["double_run"])  # contacts 1..paired are double impacts
    h64 = _horizon_impacts(horizon, ds)
    n_h = (h64 - 3) // 2  # last n whose r_n reads impacts within the horizon only
    n_last = min(int(spec.get("n_max", 150)), paired - 1, (tau.size - 4) // 2)
    n = np.arange(1, n_last + 1)
    r = tau[2 * n + 2] / tau[2 * n]
    fig, (ax, bx) = plt.subplots(2, 1, figsize=(WIDTH, 3.9), sharex=True, height_ratios=(2.2, 1.0))
    ax.plot(n, r, "o", ms=3, color="C0", label=r"$r_n = f_{n+1}/f_n$, $f_n=\tau_{2n}$ (eq. Falcon-rest-coeff)")
    ax.axhline(np.exp(-mu * T_xi), color="C3", ls="--",
               label=r"$e^{-\mu T_\xi}=%.4f$ (eq. rest-coefficient-function-of-mu)" % np.exp(-mu * T_xi))
    # (b) the contact between f_n and f_{n+1}: contact n + 1, its inner flight tau_{2n+1}
    m = np.arange(1, min(n_last + 6, (tau.size - 2) // 2) + 1)
    contact = tau[2 * m + 1] / T_xi
    ok = m + 1 <= paired
    bx.plot(m[ok], contact[ok], "o", ms=2.5, color="C0", label="double impact")
    bx.plot(m[~ok], contact[~ok], "x", ms=4, color="C3", label="not a double impact")
    bx.axhline(1.0, color="k", lw=0.6, ls=":")
    marks = [(paired - 0.5, "C3", "-", "pairing ends (contact %d)" % (paired + 1))]
    if n_h < m[-1]:
        marks.append((n_h + 0.5, "0.3", "-.", r"float64 horizon ($t_{%d}$)" % h64))
    for x, color, style, text in marks:
        for axis in (ax, bx):
            axis.axvline(x, color=color, lw=0.9, ls=style)
        ax.text(x + 0.3, 0.5, text, transform=ax.get_xaxis_transform(), rotation=90, ha="left", va="center",
                fontsize=6, color=color)
    ax.set_xlim(0, m[-1] + 1)
    ax.set_ylabel(r"$r_n$")
    ax.legend(loc="center left", fontsize=7)
    fig.suptitle(r"Fig. rest-coeff: $\gamma=%s$, $\mu=%s$, $\psi(0)=%s$, $\xi(0)=\dot\xi(0)=\dot\psi(0)=0$"
                 % (tex_num(ds.attrs["gamma"]), tex_num(mu), tex_num(ds.attrs["x0"])), fontsize=9)
    ax.set_title(r"(a) the restitution coefficient of the $n$-th macroscopic flight", fontsize=7, loc="left", pad=2)
    bx.set_ylabel(r"$\tau_{2n+1}/T_\xi$", fontsize=8)
    bx.set_xlabel(r"$n$ (macroscopic flight)")
    bx.set_title(r"(b) the contact between $f_n$ and $f_{n+1}$: its inner flight $\tau_{2n+1}\approx T_\xi$ "
                 r"while the impacts come in pairs", fontsize=7, loc="left", pad=2)
    bx.legend(loc="upper left", fontsize=6, ncol=2)
    fig.tight_layout()
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


def _horizon_text(horizon, ds, first: int = 1) -> str:
    """The float64 predictability horizon in words, for the Poincare figures' titles (``first``: the first contact
    drawn; a figure that starts past the horizon says that all of it is)."""
    h, reached = _horizon(horizon, ds)
    if reached and first > h:
        return (r"every contact drawn is past the float64 horizon $n=%d$: the dynamics' shape, not the true "
                r"trajectory's contacts" % h)
    if not reached:
        return r"float64 tracks the exact contacts at least to $n=%d$ (as far as the horizon study compared)" % h
    return (r"past the float64 horizon $n>%d$ the states are the dynamics' shape, not the true trajectory's contacts"
            % h)


def _mark_horizon(axes, bar, horizon, ds, n_last: int) -> None:
    """A dash-dot line at the float64 horizon H and the contacts past it shaded, when H falls inside the panel; the
    same line on the colour bar (log10 n), so that the colours past the horizon can be told in the 3-D view too."""
    h, reached = _horizon(horizon, ds)
    if not reached or h >= n_last:
        return
    bar.ax.axhline(np.log10(h + 0.5), color="0.3", lw=1.2, ls="-.")
    bar.set_label(bar.ax.get_ylabel() + "; dash-dot: float64 horizon", fontsize=7)
    for ax in axes:
        ax.axvline(h + 0.5, color="0.3", lw=0.9, ls="-.")
        ax.axvspan(h + 0.5, n_last * 1.5, color="0.92", zorder=0)
    # inside the shaded part, upright beside the line: past the horizon the states have come close to 0
    axes[0].text(h * 1.12, 0.97, "float64 horizon", transform=axes[0].get_xaxis_transform(),
                 rotation=90, ha="left", va="top", fontsize=5, color="0.3")


def contact_portrait(datasets, spec, outputs) -> None:
    """Figs. very_rigid_poincare(_overdamped): state just after each of the first ``events`` contacts.

    (a) the paper's 3-D view (Xdot_n, Y_n - y_eq, Ydot_n); (b) Ydot_n and (c) Y_n - y_eq against n:
    the double impacts' zig-zag (sign of Ydot_n alternating) and the disordered transient for
    mu < 1; for mu = 2 the spring shrinking for the first impacts, then expanding towards its
    equilibrium length monotonically from below (Y_n - y_eq < 0 rising to 0), as section 8.1 says.
    The float64 predictability horizon H (study horizon: the contacts whose times float64 gets to 1e-8 of the mpmath
    reference) is marked in (b) and (c) and on the colour bar (the colours of (a) past it): past it the contacts are not those of the true system, only its shape.
    """
    ds, horizon = datasets
    n, xdot, ydev, ydot = _states(ds, 0, int(spec["events"]))
    fig = plt.figure(figsize=(WIDTH, 3.8))
    grid = fig.add_gridspec(2, 2, width_ratios=(1.25, 1.0), hspace=0.28, wspace=0.45, top=0.86)
    ax3, pts = _portrait_3d(fig, grid[:, 0], n, xdot, ydev, ydot, "(a) state just after contact $n$")
    axes = [fig.add_subplot(grid[0, 1]), None]
    axes[1] = fig.add_subplot(grid[1, 1], sharex=axes[0])
    for ax, values, name, letter in zip(axes, (ydot, ydev), (YDOT, YDEV), "bc"):
        _series(ax, n, values, name)
        ax.set_title(f"({letter}) {name} against $n$", loc="left", fontsize=7, pad=2)
    axes[0].set_xlim(0.7, n[-1] * 1.3)
    axes[0].tick_params(labelbottom=False)
    axes[1].set_xlabel(r"contact $n$", fontsize=8)
    bar = fig.colorbar(pts, ax=axes, shrink=0.8, pad=0.03, aspect=30)
    bar.set_label(r"$\log_{10} n$ (contact index)", fontsize=7)
    bar.ax.tick_params(labelsize=6)
    _mark_horizon(axes, bar, horizon, ds, int(n[-1]))
    fig.suptitle(r"Fig. %s: %s, contacts 1-%d (lengths in $L$, speeds in $L/\sqrt{m/2k}$; "
                 r"$y_{eq}=1-2\gamma$)" "\n%s" % (spec.get("label", "very_rigid_poincare"), _regime(ds), n[-1],
                                              _horizon_text(horizon, ds)), fontsize=8)
    save(fig, outputs)


def contact_portrait_magni(datasets, spec, outputs) -> None:
    """Figs. very_rigid_poincare(_overdamped)_magni: near (0, 0, 0), at several magnifications.

    (a) the 3-D view of the first window of ``magni_windows`` (contact ranges [first, last));
    (b)-(e) the projection (Y_n - y_eq, Ydot_n) of each window, each at its own scale: for mu < 1
    the damped oscillation of the spring about its equilibrium makes the states spiral in (the
    same spiral at every magnification); for mu = 2 they approach it monotonically from below,
    with no spiral.  The title says where the float64 predictability horizon lies (study horizon).
    """
    ds, horizon = datasets
    windows = [tuple(int(v) for v in w) for w in spec["magni_windows"]]
    states = [_states(ds, a, b) for a, b in windows]
    cols = (len(windows) + 1) // 2
    fig = plt.figure(figsize=(WIDTH, 4.4))
    grid = fig.add_gridspec(2, 1 + cols, width_ratios=(1.6,) + (1.0,) * cols, wspace=0.5, hspace=0.45)
    n, xdot, ydev, ydot = _states(ds, *spec["magni_3d"])
    first = int(min([n[0]] + [s[0][0] for s in states]))
    _portrait_3d(fig, grid[:, 0], n, xdot, ydev, ydot, "(a) contacts %d-%d" % (n[0], n[-1]), origin=True)
    for k, (n, _, ydev, ydot) in enumerate(states):
        _projection(fig.add_subplot(grid[k // cols, 1 + k % cols]), n, ydev, ydot,
                    "(%s) contacts %d-%d" % ("bcdefgh"[k], n[0], n[-1]))
    fig.suptitle(r"Fig. %s: %s, close to $(0,0,0)$" "\n"
                 r"(b)-(%s): projection on $(Y_n-y_{eq}, \dot Y_n)$, each window at its own scale; "
                 r"$+$: equilibrium; colour: $\log_{10} n$" "\n%s" % (spec.get("label", "very_rigid_poincare_magni"),
                                                                  _regime(ds), "bcdefgh"[len(windows) - 1],
                                                                  _horizon_text(horizon, ds, first)), fontsize=8)
    save(fig, outputs)


def contact_approach_magni(datasets, spec, outputs) -> None:
    """Fig. very_rigid_poincare_overdamped_magni: the approach to (0, 0, 0) for mu = 2.

    (a) the 3-D view of the contacts ``magni_3d`` with the equilibrium in view; (b) the three
    coordinates against n on log-log axes over the whole run (every decade a magnification):
    y_eq - Y_n, Ydot_n and Xdot_n stay positive and decrease monotonically from ``magni_3d[0]``
    on -- the spring approaches its equilibrium length from below, with no spiral.  The legend
    counts the contacts where a coordinate has the other sign or is not smaller than the one before.  The title
    says where the float64 predictability horizon lies (study horizon), and (b) marks it (dash-dot; when the study
    never lost track, the last contact it compared).
    """
    ds, horizon = datasets
    n, xdot, ydev, ydot = _states(ds, *spec["magni_3d"])
    fig = plt.figure(figsize=(WIDTH, 3.4))
    grid = fig.add_gridspec(1, 2, width_ratios=(1.2, 1.0), wspace=0.5, top=0.84)
    _portrait_3d(fig, grid[0, 0], n, xdot, ydev, ydot, "(a) contacts %d-%d" % (n[0], n[-1]), origin=True)
    ax = fig.add_subplot(grid[0, 1])
    first = int(spec["magni_3d"][0])
    n, xdot, ydev, ydot = _states(ds, first, ds.sizes["event"])
    bad = 0
    for k, (values, name) in enumerate(((-ydev, r"$y_{eq} - Y_n$"), (ydot, YDOT), (xdot, XDOT))):
        bad += int(np.count_nonzero(values <= 0) + np.count_nonzero(np.diff(values) >= 0))
        ax.loglog(n, np.where(values > 0, values, np.nan), color=f"C{k}", label=name)
    h, reached = _horizon(horizon, ds)
    if n[0] < h < n[-1]:  # dash-dot: the horizon, or (not reached) the last contact the horizon study compared
        ax.axvline(h, color="0.3", lw=0.9, ls="-.")
        ax.text(h * 1.12, 0.63, "float64 horizon" if reached else "mpmath-checked", transform=ax.get_xaxis_transform(),
                rotation=90, ha="left", va="center", fontsize=6, color="0.3")
    ax.set_xlabel(r"contact $n$")
    ax.set_ylabel(r"state just after contact $n$")
    ax.set_title("(b) contacts %d-%d, log-log" % (n[0], n[-1]), fontsize=8)
    ax.legend(fontsize=7, loc="center right")
    ax.text(0.03, 0.03, "all three positive and decreasing\nat every contact" if bad == 0 else
            "%d (coordinate, contact) pairs not\npositive and decreasing" % bad,
            transform=ax.transAxes, fontsize=7, va="bottom")
    fig.suptitle(r"Fig. %s: %s, close to $(0,0,0)$ (red $+$: equilibrium)" "\n%s"
                 % (spec.get("label", "very_rigid_poincare_overdamped_magni"), _regime(ds), _horizon_text(horizon, ds)),
                 fontsize=8)
    save(fig, outputs)

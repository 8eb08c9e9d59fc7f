"""Figs. rigid-fall and sticky-traj: x(t), y(t) sampled in closed form from the event records."""

from __future__ import annotations

import numpy as np

from ..io import sample_dataset
from ..kinds import DETACH, IMPACT, STICKY_START
from .common import WIDTH, label_time, plt, save, tex_num



def _curves(ds, times):
    s = sample_dataset(ds, times)
    y_eq = 1.0 - 2.0 * float(ds.attrs["gamma"])
    return s["x"], y_eq + s["y_minus_yeq"]


def _impacts(ds, t0, t1):
    t = ds["t"].values
    sel = (ds["kind"].values == IMPACT) & (t >= t0) & (t <= t1)
    return t[sel]


def _landing_box(ds, t0, t1):
    """The dashed box of fig. rigid-fall, from the run: the last landing of the ball in [t0, t1] where the lower
    mass hits the floor more than once (impacts less than one period of the spring, 2 pi, apart) and which a
    longer flight follows; in time 1.5 and 2.5 times the landing's span before and after it (the paper's box
    around t = 340-344 for gamma = mu = 0.01), in height from the floor to the lower mass's highest hop between
    the landing's impacts, with 15 % margins.
    None if no landing has two impacts."""
    imp = _impacts(ds, t0, t1)
    every = _impacts(ds, -np.inf, np.inf)
    period = 2.0 * np.pi
    starts = np.r_[0, np.nonzero(np.diff(imp) >= period)[0] + 1]
    ends = np.r_[starts[1:] - 1, len(imp) - 1]
    for a, b in zip(imp[starts[::-1]], imp[ends[::-1]]):
        after = every[every > b]
        if b > a and after.size and after[0] - b >= period:
            span = b - a
            ta, tb = max(t0, a - 1.5 * span), min(t1, b + 2.5 * span)
            x, _ = _curves(ds, np.linspace(a, b, 4000))  # the lower mass's hops between the landing's impacts
            hi = float(np.nanmax(x))
            return {"t": [ta, tb], "y": [-0.15 * hi, 1.15 * hi]}
    return None


def rigid_fall(ds, spec, outputs) -> None:
    """Fig. rigid-fall: y(t) (upper curve), x(t) (lower curve), impacts as dots, inset of the dashed box
    (``spec["inset"]`` if given, else derived from the run: :func:`_landing_box`)."""
    t0, t1 = spec["t_window"]
    times = np.linspace(t0, t1, int(spec.get("samples", 20000)))
    x, y = _curves(ds, times)
    fig, ax = plt.subplots(figsize=(WIDTH, 3.8))
    ax.plot(times, y, color="C0", label=r"$y(t)$, upper mass")
    ax.plot(times, x, color="C1", label=r"$x(t)$, lower mass")
    ti = _impacts(ds, t0, t1)
    ax.plot(ti, np.zeros_like(ti), "k.", ms=4, label="impacts")
    label_time(ax)
    ax.set_ylabel(r"height  [$L$]")
    ax.set_xlim(t0, t1)
    ax.set_title(r"Fig. rigid-fall: $\gamma=%s$, $\mu=%s$, $\psi(0)=%s$, $\xi(0)=\dot\xi(0)=\dot\psi(0)=0$"
                 % (tex_num(ds.attrs["gamma"]), tex_num(ds.attrs["mu"]), tex_num(ds.attrs["x0"])))
    ax.legend(loc="upper center", ncol=3, bbox_to_anchor=(0.5, -0.16), frameon=False)
    inset = spec.get("inset") or _landing_box(ds, t0, t1)
    if inset:
        (a, b), (c, d) = inset["t"], inset["y"]
        ins = ax.inset_axes([0.72, 0.5, 0.27, 0.47])
        tt = np.linspace(a, b, 4000)
        xi_, yi_ = _curves(ds, tt)
        ins.plot(tt, yi_, color="C0")
        ins.plot(tt, xi_, color="C1")
        tk = _impacts(ds, a, b)
        ins.plot(tk, np.zeros_like(tk), "k.", ms=3)
        ins.set_xlim(a, b)
        ins.set_ylim(c, d)
        ins.tick_params(labelsize=6)
        ins.set_xlabel(r"$t$", fontsize=6, labelpad=1)
        ins.yaxis.tick_right()  # tick labels and label right of the inset, off the main curves
        ins.yaxis.set_label_position("right")
        ins.set_ylabel(r"height [$L$]", fontsize=6, labelpad=2)
        ins.grid(alpha=0.3)
        rect, connectors = ax.indicate_inset_zoom(ins, edgecolor="k")
        rect.set_linestyle("--")
    save(fig, outputs)




def sticky_traj(datasets, spec, outputs) -> None:
    """Fig. sticky-traj: one panel per eps (eq. sticky-ic), solid dots at the contacts, t_c marked.

    For eps = 0 the run is one sticky contact: its two dots are the start (t = 0) and the
    detachment at t_c (the lower mass rests on the floor in between, shaded); t_c, read from
    that run, is marked in every panel.  For eps > 0 every dot is an impact; the title counts
    the dots drawn and those in (0, t_c).
    """
    t1 = float(spec.get("t_end", 12.0))
    times = np.linspace(0.0, t1, 6000)
    fig, axes = plt.subplots(len(datasets), 1, figsize=(WIDTH, 1.75 * len(datasets) + 0.6), sharex=True)
    axes = np.atleast_1d(axes)
    sticky = [ds for ds in datasets if np.any(ds["kind"].values == DETACH)]
    t_c = float(sticky[0]["t"].values[sticky[0]["kind"].values == DETACH][0]) if sticky else None
    for letter, ax, ds in zip("abcdefgh", axes, datasets):
        x, y = _curves(ds, times)
        ax.plot(times, y, color="C0", label=r"$y(t)$, upper mass")
        ax.plot(times, x, color="C1", label=r"$x(t)$, lower mass")
        t, kind = ds["t"].values, ds["kind"].values
        dots = t[np.isin(kind, (IMPACT, STICKY_START, DETACH)) & (t <= t1)]
        ax.plot(dots, np.zeros_like(dots), "k.", ms=4, label="contacts (solid dots)", zorder=3)
        for start in np.flatnonzero(kind == STICKY_START):
            end = t[start + 1] if start + 1 < t.size else t1
            ax.axvspan(t[start], min(end, t1), color="0.88", lw=0, label="lower mass on the floor (sticky)")
        eps = float(ds.attrs["xdot0"])
        if eps == 0.0:
            what = "one sticky contact: the dots are its start and its detachment at $t_c$"
        else:
            inside = int(np.count_nonzero((kind == IMPACT) & (t > 0) & (t < t_c))) if t_c else 0
            what = "%d impacts drawn, %d of them in $(0, t_c)$" % (dots.size, inside)
        if t_c is not None:
            ax.axvline(t_c, color="C3", lw=0.8, ls="--", label=r"$t_c$ (end of the $\epsilon=0$ sticky contact)")
        ax.set_ylabel(r"height  [$L$]")
        ax.set_title(r"(%s) $\epsilon = %s$: %s" % (letter, tex_num(eps), what), fontsize=8)
    if t_c is not None:
        axes[0].annotate(r"$t_c=%.4f$" % t_c, xy=(t_c, 0.5), xycoords=("data", "axes fraction"),
                         xytext=(4, 0), textcoords="offset points", color="C3", fontsize=7)
    label_time(axes[-1])
    handles = {}
    for ax in axes:
        for h, lab in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(lab, h)
    fig.legend(handles.values(), handles.keys(), loc="lower center", ncol=3, fontsize=7, frameon=False)
    fig.suptitle(r"Fig. sticky-traj: $\gamma=%s$, $\mu=%s$, $\dot Y_0=%s$ (eq. sticky-ic)"
                 % tuple(tex_num(datasets[0].attrs[k]) for k in ("gamma", "mu", "ydot0")), fontsize=9)
    fig.tight_layout(rect=(0, 0.06, 1, 1))
    save(fig, outputs)

"""Figs. rigid-fall and sticky-traj: x(t), y(t) sampled in closed form from the event records."""

from __future__ import annotations

import numpy as np

from ..io import sample_dataset
from .common import WIDTH, label_time, plt, save

IMPACT = 0


def _curves(ds, times):
    s = sample_dataset(ds, times)
    y_eq = 1.0 - 2.0 * float(ds.attrs["gamma"])
    return s["x"], y_eq + s["y_minus_yeq"]


def _impacts(ds, t0, t1):
    t = ds["t"].values
    sel = (ds["kind"].values == IMPACT) & (t >= t0) & (t <= t1)
    return t[sel]


def rigid_fall(ds, spec, outputs) -> None:
    """Fig. rigid-fall: y(t) (upper curve), x(t) (lower curve), impacts as dots, inset of the dashed box."""
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
    ax.set_title(r"Fig. rigid-fall: $\gamma=\mu=%g$, $\psi(0)=%g$, $\xi(0)=\dot\xi(0)=\dot\psi(0)=0$"
                 % (ds.attrs["gamma"], ds.attrs["x0"]))
    ax.legend(loc="upper center", ncol=3, bbox_to_anchor=(0.5, -0.16), frameon=False)
    inset = spec.get("inset")
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
        ins.grid(alpha=0.3)
        rect, connectors = ax.indicate_inset_zoom(ins, edgecolor="k")
        rect.set_linestyle("--")
    save(fig, outputs)


def sticky_traj(datasets, spec, outputs) -> None:
    """Fig. sticky-traj: one panel per eps (eq. sticky-ic), impacts as dots, the sticky interval shaded."""
    t1 = float(spec.get("t_end", 12.0))
    times = np.linspace(0.0, t1, 6000)
    fig, axes = plt.subplots(len(datasets), 1, figsize=(WIDTH, 2.0 * len(datasets)), sharex=True)
    for ax, ds in zip(np.atleast_1d(axes), datasets):
        x, y = _curves(ds, times)
        ax.plot(times, y, color="C0", label=r"$y(t)$")
        ax.plot(times, x, color="C1", label=r"$x(t)$")
        ti = _impacts(ds, 0.0, t1)
        ax.plot(ti, np.zeros_like(ti), "k.", ms=3, label="impacts")
        kind = ds["kind"].values
        t = ds["t"].values
        for start in np.flatnonzero(kind == 2):
            end = t[start + 1] if start + 1 < t.size else t1
            ax.axvspan(t[start], min(end, t1), color="0.85", lw=0, label="sticky phase")
            ax.plot([t[start], min(end, t1)], [0, 0], "k.", ms=4)
        ax.set_ylabel(r"height  [$L$]")
        ax.set_title(r"$\epsilon = %g$  (%d impacts in view)" % (ds.attrs["xdot0"], ti.size))
        ax.legend(loc="center right", ncol=1, fontsize=7)
    label_time(np.atleast_1d(axes)[-1])
    fig.suptitle(r"Fig. sticky-traj: $\gamma=%g$, $\mu=%g$, $\dot Y_0=%g$ (eq. sticky-ic)"
                 % (datasets[0].attrs["gamma"], datasets[0].attrs["mu"], datasets[0].attrs["ydot0"]))
    fig.tight_layout()
    save(fig, outputs)

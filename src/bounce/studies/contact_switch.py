"""Study ``contact-switch``: the contact-switch approximation (:mod:`bounce.methods.contact_switch`, a
contact rule with threshold delta) against the exact dimer, as delta -> 0."""

from __future__ import annotations

import math
import time

import numpy as np

from ..kinds import IMPACT
from ..methods.base import compile_exact_solver
from ..methods.contact_switch import energy_excess_samples, run
from ..model import Deviations
from ..sampling import sample_trajectory
from ..simulate import simulate
from .base import Study


def _exact_cost_fit(t, n_min: int) -> tuple[float, float]:
    """Least-squares fit ln n = a + b t_n over the impacts n >= n_min: returns (b, e^a).

    Theorem main_thm: tau_n ~ 3/(mu n), so t_n ~ (3/mu) ln n + const and n(t) ~ C e^{mu t/3}: b -> mu/3."""
    n = np.arange(1, len(t) + 1)
    sel = n >= n_min
    if np.count_nonzero(sel) < 3:
        return math.nan, math.nan
    b, a = np.polyfit(t[sel], np.log(n[sel]), 1)
    return float(b), float(math.exp(a))


def switch_study(spec: dict):
    """Error and cost of the contact switch against the exact solver, per case and delta.

    ``spec`` (config ``reduced.switch``)::

        {"cases": {"drop-underdamped": {"gamma": 0.01, "mu": 0.01, "psi0": 6.0, "t_max": 3500.0}, ...},
         "deltas": [1e-2, ..., 1e-8], "samples": 20001, "max_events": 3000000, "fit_n_min": 1000}

    Per (case, delta): max |y - y_exact| and RMS on [0, t_max] (closed-form samples), max |E - E_exact|
    (E from the sampled state), impacts used vs the exact solver's impacts to t_max, CPU times, first switch
    time, number of switches, how the run ended.  Per case: the fit n(t) ~ C e^{b t} of the exact solver's
    late impacts (b against mu/3), and the predicted switch index 3 gamma/(mu delta).
    """
    import xarray as xr

    from ..model import Parameters

    compile_exact_solver()
    cases = list(spec["cases"])
    deltas = np.array(sorted((float(d) for d in spec["deltas"]), reverse=True))
    samples = int(spec["samples"])
    max_events = int(spec["max_events"])
    shape = (len(cases), deltas.size)
    out = {k: np.full(shape, np.nan) for k in ("err_y_max", "err_y_rms", "err_e_max", "err_e_rel", "cpu",
                                               "t_switch", "xdot_switch", "n_impacts")}
    n_switches = np.zeros(shape, dtype=np.int64)
    sticky_forever = np.zeros(shape, dtype=np.int8)
    per_case = {k: np.full(len(cases), np.nan) for k in ("n_exact", "cpu_exact", "rate_fit", "rate_theory",
                                                         "prefactor_fit", "t_max", "gamma", "mu", "psi0")}
    curves_t, curves_n = [], []
    for i, name in enumerate(cases):
        c = spec["cases"][name]
        g, m, psi0, T = float(c["gamma"]), float(c["mu"]), float(c["psi0"]), float(c["t_max"])
        p = Parameters(g, m)
        ini = Deviations(x=psi0, xdot=0.0, xidot=0.0, eta=g)
        t0 = time.process_time()
        ex = simulate(p, ini, max_events=max_events, t_max=T)
        per_case["cpu_exact"][i] = time.process_time() - t0
        grid = np.linspace(0.0, T, samples)
        sx = sample_trajectory(ex, grid)
        e_ex = energy_excess_samples(sx, g)
        imp = ex.kind == IMPACT
        per_case["n_exact"][i] = np.count_nonzero(imp)
        b, C = _exact_cost_fit(ex.t[imp], int(spec["fit_n_min"]))
        per_case["rate_fit"][i], per_case["prefactor_fit"][i] = b, C
        per_case["rate_theory"][i] = m / 3.0
        per_case["t_max"][i], per_case["gamma"][i], per_case["mu"][i], per_case["psi0"][i] = T, g, m, psi0
        # the exact cost curve n(t), thinned for the figure
        ti = ex.t[imp]
        keep = np.unique(np.geomspace(1, max(ti.size, 1), 400).astype(np.int64)) - 1
        curves_t.append(ti[keep])
        curves_n.append(keep + 1)
        for j, d in enumerate(deltas):
            r = run(p, ini, {"delta": d}, max_events=max_events, t_max=T, sample_times=grid)
            dy = r.y - (p.y_eq + sx["y_minus_yeq"])
            out["err_y_max"][i, j] = np.nanmax(np.abs(dy))
            out["err_y_rms"][i, j] = math.sqrt(np.nanmean(dy * dy))
            de = energy_excess_samples(r.extra["samples"], g) - e_ex
            out["err_e_max"][i, j] = np.nanmax(np.abs(de))
            sw = r.extra["switch_t"]
            if sw.size:
                k = np.searchsorted(grid, sw[0])
                out["err_e_rel"][i, j] = out["err_e_max"][i, j] / e_ex[min(k, grid.size - 1)]
                out["t_switch"][i, j] = sw[0]
                out["xdot_switch"][i, j] = r.xdot[np.searchsorted(r.t, sw[0])]
            else:
                out["err_e_rel"][i, j] = 0.0
            out["cpu"][i, j] = r.cpu_time
            out["n_impacts"][i, j] = r.extra["n_impacts"]
            n_switches[i, j] = r.extra["n_switches"]
            sticky_forever[i, j] = r.extra["stop_reason"] == "sticky_forever"
    L = max(len(x) for x in curves_t)
    ct = np.full((len(cases), L), np.nan)
    cn = np.full((len(cases), L), np.nan)
    for i, (a, b_) in enumerate(zip(curves_t, curves_n)):
        ct[i, : a.size] = a
        cn[i, : b_.size] = b_
    cd = ("case", "delta")
    u = {"units": "1"}
    ds = xr.Dataset(
        {
            "err_y_max": (cd, out["err_y_max"], {"long_name": "max |y - y_exact| on [0, t_max]", "units": "L"}),
            "err_y_rms": (cd, out["err_y_rms"], {"long_name": "RMS of y - y_exact on [0, t_max]", "units": "L"}),
            "err_energy_max": (cd, out["err_e_max"], {"long_name": "max |E - E_exact| on [0, t_max]", **u}),
            "err_energy_rel": (cd, out["err_e_rel"],
                               {"long_name": "max |E - E_exact| / (E_exact - E_m at the first switch)", **u}),
            "cpu": (cd, out["cpu"], {"long_name": "CPU time of the contact-switch run", "units": "s"}),
            "n_impacts": (cd, out["n_impacts"], {"long_name": "impacts computed by the contact switch", **u}),
            "t_switch": (cd, out["t_switch"], {"long_name": "time of the first switch", "units": "sqrt(m/2k)"}),
            "xdot_switch": (cd, out["xdot_switch"], {"long_name": "rebound speed at the first switch", **u}),
            "n_switches": (cd, n_switches, {"long_name": "number of switches", **u}),
            "sticky_forever": (cd, sticky_forever, {"long_name": "ended in a sticky phase proved infinite", **u}),
            "n_exact": (("case",), per_case["n_exact"], {"long_name": "impacts of the exact solver to t_max", **u}),
            "cpu_exact": (("case",), per_case["cpu_exact"], {"long_name": "CPU time of the exact run", "units": "s"}),
            "rate_fit": (("case",), per_case["rate_fit"],
                         {"long_name": "fitted b in n(t) ~ C e^{b t} (late impacts)", "units": "1/sqrt(m/2k)"}),
            "rate_theory": (("case",), per_case["rate_theory"], {"long_name": "mu/3", "units": "1/sqrt(m/2k)"}),
            "prefactor_fit": (("case",), per_case["prefactor_fit"], {"long_name": "fitted C in n(t) ~ C e^{b t}", **u}),
            "t_max": (("case",), per_case["t_max"], {"long_name": "end of the window", "units": "sqrt(m/2k)"}),
            "gamma": (("case",), per_case["gamma"], {"long_name": "gamma", **u}),
            "mu": (("case",), per_case["mu"], {"long_name": "mu", **u}),
            "psi0": (("case",), per_case["psi0"], {"long_name": "psi(0)", "units": "L"}),
            "exact_curve_t": (("case", "curve"), ct, {"long_name": "t_n of the exact solver (thinned)",
                                                      "units": "sqrt(m/2k)"}),
            "exact_curve_n": (("case", "curve"), cn, {"long_name": "impact index n (thinned)", **u}),
        },
        coords={"case": cases, "delta": ("delta", deltas, {"long_name": "switch threshold delta on Xdot_n", **u})},
        attrs={"title": "Contact switch (exact until Xdot_n < delta, then the lower mass at rest) against the "
                        "exact solver", "samples": samples, "fit_n_min": int(spec["fit_n_min"]),
               "Conventions": "CF-1.10"},
    )
    return ds


def plot_switch_study(ds, spec, outputs) -> None:
    """Error in y and E against delta, impacts against delta, and the exact solver's n(t) ~ e^{mu t/3}."""
    from matplotlib.lines import Line2D

    from ..figures.common import WIDTH, legend_below, plt, save, tex_num

    fig, axes = plt.subplots(1, 3, figsize=(WIDTH, 2.7))
    a1, a2, a3 = axes
    n_min = int(ds.attrs["fit_n_min"])
    handles = []
    for i, case in enumerate(ds["case"].values):
        d = ds.sel(case=case)
        lab = r"$\gamma=%s$, $\mu=%s$" % (tex_num(float(d["gamma"])), tex_num(float(d["mu"])))
        handles.append(Line2D([], [], color=f"C{i}", label=lab))
        dl = ds["delta"].values
        sw = d["n_switches"].values > 0
        a1.loglog(dl[sw], d["err_y_max"].values[sw], "o-", ms=2.5, color=f"C{i}")
        a1.loglog(dl[sw], d["err_energy_max"].values[sw], "s--", ms=2.5, color=f"C{i}", mfc="none")
        a2.loglog(dl, d["n_impacts"].values, "o-", ms=2.5, color=f"C{i}")
        a2.axhline(float(d["n_exact"]), color=f"C{i}", lw=0.6, ls=":")
        tc, nc = d["exact_curve_t"].values, d["exact_curve_n"].values
        ok = np.isfinite(tc) & (nc >= n_min)
        if np.count_nonzero(ok) > 2:
            t0 = np.interp(n_min, nc[np.isfinite(tc)], tc[np.isfinite(tc)])
            a3.semilogy(float(d["mu"]) * (tc[ok] - t0) / 3.0, nc[ok] / n_min, color=f"C{i}", lw=1.2)
            a3.text(0.03, 0.92 - 0.08 * i, r"$b=%.4g$, $\mu/3=%.4g$" % (float(d["rate_fit"]), float(d["rate_theory"])),
                    color=f"C{i}", transform=a3.transAxes, fontsize=6)
    d = ds["delta"].values
    handles.append(Line2D([], [], color="0.4", lw=0.8, ls=":", label=r"$\delta^2/4$"))
    handles.append(Line2D([], [], color="k", marker="o", ms=3, lw=0, label=r"max $|y-y_{\rm exact}|$"))
    handles.append(Line2D([], [], color="k", marker="s", ms=3, lw=0, mfc="none", label=r"max $|E-E_{\rm exact}|$"))
    a1.loglog(d, d**2 / 4, color="0.4", lw=0.8, ls=":")
    a1.set_xlabel(r"switch threshold $\delta$ on $\dot X_n$")
    a1.set_ylabel(r"error on $[0,t_{\max}]$ ($y$ in $L$)")
    a2.set_xlabel(r"switch threshold $\delta$ on $\dot X_n$")
    a2.set_ylabel(r"impacts computed to $t_{\max}$")
    a2.set_title("(b) cost (dotted: exact solver)", fontsize=8)
    x = np.linspace(0.0, a3.get_xlim()[1], 50)
    a3.semilogy(x, np.exp(x), color="k", lw=0.6, ls="--", label=r"$e^{\mu (t-t_{n_0})/3}$")
    a3.legend(fontsize=6, loc="lower right")
    a3.set_xlabel(r"$\mu\,(t_n - t_{n_0})/3$,  $n_0=%d$" % n_min)
    a3.set_ylabel(r"$n/n_0$ (exact solver)")
    a3.set_title(r"(c) exact cost: $n(t)\sim C\,e^{bt}$", fontsize=8)
    a1.set_title(r"(a) error against the exact solver", fontsize=8)
    fig.suptitle(r"Contact switch: exact until $\dot X_n<\delta$, then $x=\dot x=0$ and eq. y-eq-sticky "
                 r"(lengths in $L$, time in $\sqrt{m/2k}$)", fontsize=8)
    fig.tight_layout()
    legend_below(fig, handles, [h.get_label() for h in handles], ncol=3)
    save(fig, outputs)


STUDY = Study("contact-switch", switch_study, plot_switch_study, lambda c: c["reduced"]["switch"],
              caption=("The contact-switch approximation (a contact rule with threshold delta) against the exact dimer,"
                       " as delta -> 0."))

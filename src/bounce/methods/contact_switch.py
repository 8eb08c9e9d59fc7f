"""Method "contact-switch": exact micro-bounces until Xdot_n < delta, then the lower mass rests on the floor.

Rule (setting ``{"delta": ...}``).  The exact solver (:func:`bounce.simulate`)
runs until an impact whose rebound speed Xdot_n is below ``delta``.  There the
lower mass is put to rest on the floor: x = 0, x' = 0, with the upper mass
unchanged (y and y' kept, i.e. xi' -> xi' + Xdot_n/2, eta = xi + gamma kept).
This removes exactly Xdot_n^2/4 of E - E_m (eq. ``tot-mech-energy``: (xi'^2 + psi'^2)/2
drops from (a^2 + (u + a)^2)/2 to (a + u/2)^2 with u = Xdot_n, a = xi'_n), reported
per switch in ``extra["energy_removed"]``.  The solver is restarted from that
state (:class:`bounce.model.Deviations` with x = xdot = 0), and *its own*
classification decides what follows (:func:`bounce.exact.events.run_events`):

* floor force F = y/2 + mu y' - gamma - 1/2 < 0 (eq. ``force-on-the-floor``; or F = 0
  with F' <= 0): a sticky phase, y'' + mu y' + y/2 = 1/2 - gamma (eq.
  ``y-eq-sticky``), in closed form, until F returns to zero with F' > 0 (eq.
  ``cond_di_distacco``), then exact bouncing resumes; or, if the amplitude of F
  can no longer reach zero, the sticky phase is proved infinite and the run ends
  (stop reason ``sticky_forever``: the ball is at rest for ever);
* F > 0 (the spring is pulling the lower mass up): it lifts off at once and the
  flight is exact (recorded as a ``grazing`` record at the switch time).

The rule applies at every impact, so after a detachment the next slow impact
switches again.  Justification: section 8.2 of the paper (eq. ``sticky-ic``,
fig. ``sticky-convergence``): the eps-solutions, a lower mass started on the
floor with speed eps, converge to the sticky solution as eps -> 0, faster than
linearly in the RMS norm of eq. ``L2-norm``; here eps is the rebound speed at
the switch, at most delta.  Measured (:func:`switch_study`): late in the
asymptotic regime max |y - y_exact| ~ 0.36 delta^2/gamma (the micro-bounce
height x ~ Xdot^2/gamma that the switch drops), and the energy error is the
exact solution's own E - E_m ~ Xdot^2/4 <= delta^2/4, which the sticky phase
dissipates at the sticky oscillator's rate instead of e^{-2 mu t/3}.

Why it pays.  Late in the asymptotic regime tau_n ~ 3/(mu n) (Theorem main_thm),
so t_n ~ (3/mu) ln n and the exact solver needs ~exp(mu t/3) impacts to reach
time t; the switch happens near n ~ 3 gamma/(mu delta) (Xdot_n ~ 3 gamma/(mu n))
and costs nothing afterwards.

Output: ``t``/``xdot`` the impacts (the switching impact included, with its
true rebound speed); ``y`` the closed-form samples of the stitched records;
``extra``: the stitched :class:`bounce.trajectory.Trajectory` (``trajectory``), the
switch times and indices, ``energy_removed``, the stop reason and ``n_impacts``.
"""

from __future__ import annotations

import math
import time

import numpy as np

from ..kinds import GRAZING, IMPACT, STICKY_START
from ..exact.events import energy_excess
from ..model import Deviations, InputError
from ..sampling import sample_trajectory
from ..simulate import simulate
from ..trajectory import Trajectory
from .base import MethodResult, MethodSpec

#: first chunk of exact events searched for a slow impact; later chunks are n_done/8 (waste <= ~12 %)
CHUNK_MIN, CHUNK_MAX = 256, 1 << 16


def _energy(u, a, eta, gamma):
    return energy_excess(0.0, u, a, eta, gamma)


def switch_state(u: float, a: float, eta: float) -> Deviations:
    """The lower mass put to rest after an impact (u, a, eta): x = x' = 0, y and y' kept.

    y' = x' + 2 xi' = u + 2 a must stay, so xi' -> a + u/2; eta = (y - y_eq - x)/2 is unchanged.
    """
    return Deviations(x=0.0, xdot=0.0, xidot=a + 0.5 * u, eta=eta)


def run_switch(params, initial, delta: float, max_events: int = 1000, t_max: float = math.inf):
    """Stitched records of the contact-switch dynamics (see the module docstring).

    Returns ``(traj, info)``: a :class:`Trajectory` whose records are those of the
    exact sub-runs, offset in time, with the switches in between, and a dict
    (switch_index, switch_t, energy_removed, n_switches, sub_runs).
    """
    delta = float(delta)
    if not delta >= 0.0:
        raise InputError(f"delta must be >= 0, got {delta!r}")
    gamma = params.gamma
    bufs = {k: [] for k in ("t", "tau", "u", "a", "eta", "e", "kind")}
    sw_index, sw_t, e_removed = [], [], []
    state = initial.deviations(params)
    t_off = 0.0
    n_done = 0
    sub_runs = 0
    stop = "max_events"
    t_last = 0.0  # time of the last record
    pending = False
    resume_sticky = False

    def append(t, tau, u, a, eta, e, kind):
        bufs["t"].append(t)
        bufs["tau"].append(tau)
        bufs["u"].append(u)
        bufs["a"].append(a)
        bufs["eta"].append(eta)
        bufs["e"].append(e)
        bufs["kind"].append(kind)

    while n_done < max_events:
        chunk = int(min(max_events - n_done, max(CHUNK_MIN, min(CHUNK_MAX, n_done // 8))))
        tr = simulate(params, state, max_events=chunk, t_max=t_max - t_off)
        sub_runs += 1
        if pending:
            pending = False
            # the solver records a sticky_start at its t = 0 if the rest state is sticky; otherwise the
            # lower mass lifts off at once: insert a record of the rest state (kind grazing: x = x' = 0,
            # nothing exchanged, the flight restarts from it), so that the records determine the motion
            if not (len(tr) and tr.kind[0] == STICKY_START and tr.t[0] == 0.0):
                append(np.array([t_off]), np.array([0.0]), np.array([0.0]), np.array([state.xidot]),
                       np.array([state.eta]), np.array([_energy(0.0, state.xidot, state.eta, gamma)]),
                       np.array([GRAZING], dtype=np.int8))
                n_done += 1
                if n_done >= max_events:
                    break
        # a continuation from a sticky_start record re-records it at its t = 0: skip the duplicate
        j0 = 1 if (resume_sticky and len(tr) and tr.kind[0] == STICKY_START and tr.t[0] == 0.0) else 0
        resume_sticky = False
        slow = np.flatnonzero((tr.kind == IMPACT) & (tr.xdot < delta))
        m = int(slow[0]) + 1 if slow.size else len(tr)
        m = min(m, max_events - n_done + j0)
        for key, arr in (("t", tr.t[j0:m] + t_off), ("tau", tr.tau[j0:m]), ("u", tr.xdot[j0:m]),
                         ("a", tr.xidot[j0:m]), ("eta", tr.eta[j0:m]), ("e", tr.energy_excess[j0:m]),
                         ("kind", tr.kind[j0:m])):
            bufs[key].append(np.array(arr))
        m -= j0
        n_done += m
        if m:
            t_last = float(tr.t[j0 + m - 1]) + t_off
        if slow.size and slow[0] < j0 + m and n_done < max_events:
            i = int(slow[0])
            u, a, eta = float(tr.xdot[i]), float(tr.xidot[i]), float(tr.eta[i])
            state = switch_state(u, a, eta)
            e_removed.append(_energy(u, a, eta, gamma) - _energy(0.0, state.xidot, eta, gamma))
            sw_index.append(n_done - 1)
            sw_t.append(t_last)
            t_off = t_last
            pending = True  # the next sub-run starts from the rest state: record it (below)
            continue
        if tr.stop_reason != "max_events":
            stop = tr.stop_reason
            break
        if not len(tr):
            break
        state = Deviations(x=0.0, xdot=float(tr.xdot[-1]), xidot=float(tr.xidot[-1]), eta=float(tr.eta[-1]))
        resume_sticky = bool(tr.kind[-1] == STICKY_START)
        t_off = t_last
    cat = {k: (np.concatenate(v) if v else np.empty(0)) for k, v in bufs.items()}
    kind = cat["kind"].astype(np.int8)
    t = cat["t"]
    t_end = float(t_max) if stop == "t_max" else (float(t[-1]) if t.size else 0.0)
    traj = Trajectory(params=params, initial=initial, t=t, tau=cat["tau"], xdot=cat["u"], xidot=cat["a"],
                      eta=cat["eta"], energy_excess=cat["e"], kind=kind, stop_reason=stop, t_end=t_end,
                      settings={"max_events": int(max_events), "t_max": float(t_max), "energy_stop": 0.0})
    info = {"switch_index": np.array(sw_index, dtype=np.int64), "switch_t": np.array(sw_t),
            "energy_removed": np.array(e_removed), "n_switches": len(sw_index), "sub_runs": sub_runs}
    return traj, info


def _warm_up() -> None:
    from .rigid import warm_up

    warm_up()


def run(params, initial, setting=None, *, max_events=1000, t_max=math.inf, sample_times=None) -> MethodResult:
    """METHOD "contact-switch"; setting {"delta": rebound speed below which the lower mass is put to rest}."""
    setting = dict(setting or {})
    if "delta" not in setting:
        raise InputError("contact-switch needs setting {'delta': ...}")
    _warm_up()
    start = time.process_time()
    traj, info = run_switch(params, initial, setting["delta"], max_events=int(max_events), t_max=t_max)
    cpu = time.process_time() - start
    impacts = traj.kind == IMPACT
    y = None
    extra = {"trajectory": traj, "stop_reason": traj.stop_reason, "n_impacts": int(np.count_nonzero(impacts)),
             "t_valid": traj.t_valid, **info}
    if sample_times is not None:
        s = sample_trajectory(traj, np.asarray(sample_times, dtype=float))
        y = params.y_eq + s["y_minus_yeq"]
        extra["samples"] = s
    return MethodResult(method="contact-switch", setting={"delta": float(setting["delta"])}, t=traj.t[impacts],
                        xdot=traj.xdot[impacts], cpu_time=cpu, t_end=traj.t_end, y=y, extra=extra)


def energy_excess_samples(s: dict, gamma: float) -> np.ndarray:
    """E - E_m from sampled (x, xdot, y - y_eq, ydot) (eqs. tot-mech-energy, Emin), without cancellation:
    eta = (y - y_eq - x)/2, xi' = (ydot - xdot)/2, E - E_m = (xi'^2 + psi'^2 + eta^2)/2 + gamma x."""
    x, xd, yd, ydot = s["x"], s["xdot"], s["y_minus_yeq"], s["ydot"]
    eta = 0.5 * (yd - x)
    a = 0.5 * (ydot - xd)
    return 0.5 * (a * a + (xd + a) ** 2 + eta * eta) + gamma * x


METHOD = MethodSpec(
    name="contact-switch", run=run,
    settings_doc="{'delta': float >= 0}: exact until an impact with Xdot_n < delta, then x = x' = 0 (y, y' kept) "
                 "and the solver's own sticky/detach machinery; delta = 0 is the exact solver",
)


# --------------------------------------------------------------------------- the delta study


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
    from .rigid import warm_up

    warm_up()
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

    from ..figures.common import WIDTH, plt, save, tex_num

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
            a3.text(0.03, 0.92 - 0.08 * i, r"$b=%.5f$, $\mu/3=%.5f$" % (float(d["rate_fit"]), float(d["rate_theory"])),
                    color=f"C{i}", transform=a3.transAxes, fontsize=6)
    d = ds["delta"].values
    handles.append(Line2D([], [], color="0.4", lw=0.8, ls=":", label=r"$\delta^2/4$"))
    handles.append(Line2D([], [], color="k", marker="o", ms=3, lw=0, label=r"max $|y-y_{\rm exact}|$"))
    handles.append(Line2D([], [], color="k", marker="s", ms=3, lw=0, mfc="none", label=r"max $|E-E_{\rm exact}|$"))
    a1.loglog(d, d**2 / 4, color="0.4", lw=0.8, ls=":")
    a1.set_xlabel(r"switch threshold $\delta$ on $\dot X_n$")
    a1.set_ylabel(r"error on $[0,t_{\max}]$ ($y$ in $L$)")
    a1.legend(handles=handles, fontsize=5.5, loc="lower right")
    a2.set_xlabel(r"switch threshold $\delta$ on $\dot X_n$")
    a2.set_ylabel(r"impacts computed to $t_{\max}$")
    a2.set_title("cost (dotted: exact solver)", fontsize=8)
    x = np.linspace(0.0, a3.get_xlim()[1], 50)
    a3.semilogy(x, np.exp(x), color="k", lw=0.6, ls="--", label=r"$e^{\mu (t-t_{n_0})/3}$")
    a3.legend(fontsize=6, loc="lower right")
    a3.set_xlabel(r"$\mu\,(t_n - t_{n_0})/3$,  $n_0=%d$" % n_min)
    a3.set_ylabel(r"$n/n_0$ (exact solver)")
    a3.set_title(r"exact cost: $n(t)\sim C\,e^{bt}$", fontsize=8)
    a1.set_title(r"error against the exact solver", fontsize=8)
    fig.suptitle(r"Contact switch: exact until $\dot X_n<\delta$, then $x=\dot x=0$ and eq. y-eq-sticky "
                 r"(lengths in $L$, time in $\sqrt{m/2k}$)", fontsize=8)
    fig.tight_layout()
    save(fig, outputs)

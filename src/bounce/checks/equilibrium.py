"""Check ``static-equilibrium``: Theorem static-equilibrium and its proof (paper, sec. 6).

Claims checked on the event records (x = 0 at every event):

1. E is non-increasing (eq. energy-dissipation): E - E_m never increases from one
   record to the next beyond the rounding of its computation, and never falls below 0
   (E_m = -gamma^2/2, eq. Emin, is the minimum).
2. E -> E_m = -gamma^2/2.  E is recomputed from eq. tot-mech-energy with the event state
   (psi = xi = eta - gamma, psi' = xdot + xi', xi'), independently of the stored
   excess, and its limit E_inf is extrapolated from the last decade of impacts.  The proof
   of the theorem prints lim E = -gamma/2: checked as an erratum candidate.
3. The state tends to the equilibrium (eq. equilibrium): xdot -> 0 and the sticky
   oscillator amplitude D = sqrt((y - y_eq)^2 + 2 ydot^2) -> 0, with measured rates.

Decay rates (beyond the paper; from Theorem main_thm with t_n ~ (3/mu) ln n): after an impact
psi' ~ Xdot_n/2 and xi' ~ -Xdot_n/2, so E - E_m ~ Xdot_n^2/4 + (spring offset)^2/2.
Xdot_n ~ 3 gamma/(mu n) = e^{-mu t/3}; the spring offset relaxes like the sticky oscillator
w'' + mu w' + w/2 = 0 (eq. y-eq-sticky) at the slow rate lam (mu/2 if mu^2 < 2, else
(mu - sqrt(mu^2 - 2))/2).  Hence, in time:

    Xdot_n ~ e^{-(mu/3) t},   D ~ e^{-lam t},   E - E_m ~ e^{-kappa t},  kappa = min(2 mu/3, 2 lam),

and for mu^2 < 2 the prefactor n^2 (E - E_m) -> 9 gamma^2/(4 mu^2).  Rates are fitted on the
last decade of impacts (log-linear in t); their error is the change from the previous decade.
"""

from __future__ import annotations

import math
import time

import numpy as np
import xarray as xr

from .asymptotics import sticky_modes
from .base import NOT_CHECKABLE, Check, Verdict, judge, verdict_dataset

NAME = "static-equilibrium"
EPS = 2.0**-52

DEFAULTS = {
    "monotone_ulps": 16,  # rounding budget of E - E_m between two records, in units of eps
    "asymptotic_min_events": 100000,  # rates are fitted only on scenes this long
    "rate_sigmas": 3.0,
    "rate_floor": 0.01,  # relative; see the tolerance text
    "limit_bracket": 1e-3,  # (E_N - E_m)/|E_m| must be below this: the limit pinned to 0.1 %
    "prefactor_tolerance": 1e-3,  # plus the spring share, see the row
    "plot_points": 400,
}


def _cfg(spec):
    cfg = dict(DEFAULTS)
    cfg.update({k: v for k, v in (spec or {}).items()})
    return cfg


def energy_formula(ds) -> np.ndarray:
    """E at the events from eq. tot-mech-energy (x = 0: psi = xi = eta - gamma)."""
    gamma = float(ds.attrs["gamma"])
    xidot, eta, xdot = ds["xidot"].values, ds["eta"].values, ds["xdot"].values
    xi = eta - gamma
    psidot = xdot + xidot
    return 0.5 * xidot**2 + 0.5 * xi**2 + 0.5 * psidot**2 + gamma * xi


def rates_theory(mu: float) -> dict:
    _, lam, _ = sticky_modes(mu)
    return {"energy": min(2.0 * mu / 3.0, 2.0 * lam), "xdot": mu / 3.0, "spring": lam}


def _decade_rate(t, v, n, hi_n):
    sel = (n > hi_n / 10.0) & (n <= hi_n) & (v > 0) & np.isfinite(v)
    if sel.sum() < 10:
        return math.nan
    return -float(np.polyfit(t[sel] - t[sel][0], np.log(v[sel]), 1)[0])


def fit_rate(t, v, n):
    """Decay rate of v in t on the last decade of n, and its change from the previous decade."""
    top = float(n[-1])
    r1 = _decade_rate(t, v, n, top)
    r0 = _decade_rate(t, v, n, top / 10.0)
    return r1, (abs(r1 - r0) if math.isfinite(r0) else math.nan)


def run(spec: dict, inputs: list) -> xr.Dataset:
    t_start = time.perf_counter()
    cfg = _cfg(spec)
    verdicts: list[Verdict] = []
    names, gammas, mus, nsim = [], [], [], []
    rows = {k: [] for k in ("max_rel_increase", "min_excess", "E_inf", "E_inf_formula_gap", "excess_last",
                            "rate_energy", "rate_energy_err", "rate_xdot", "rate_xdot_err", "rate_spring",
                            "rate_spring_err", "prefactor", "xdot_last", "spring_last", "xdot_first", "spring_first")}
    kp = int(cfg["plot_points"])
    plot_n = np.full((len(inputs), kp), np.nan)
    plot_t = np.full((len(inputs), kp), np.nan)
    plot_e = np.full((len(inputs), kp), np.nan)
    plot_x = np.full((len(inputs), kp), np.nan)
    plot_d = np.full((len(inputs), kp), np.nan)
    plot_inc = np.full((len(inputs), kp), np.nan)
    for i, ds in enumerate(inputs):
        name = str(ds.attrs.get("scene", f"input{i}"))
        gamma, mu = float(ds.attrs["gamma"]), float(ds.attrs["mu"])
        names.append(name), gammas.append(gamma), mus.append(mu)
        n = (ds["event"].values + 1).astype(float) if "event" in ds.coords else np.arange(1.0, ds.sizes["event"] + 1)
        nsim.append(int(ds.attrs.get("n_events_simulated", len(n))))
        t = ds["t"].values
        e = ds["energy_excess"].values
        xdot = ds["xdot"].values
        ydot = ds["ydot"].values if "ydot" in ds else xdot + 2 * ds["xidot"].values
        w = 2.0 * ds["eta"].values  # y - y_eq at x = 0
        spring = np.sqrt(w**2 + 2.0 * ydot**2)
        ctx = f"scene {name} (gamma = {gamma:g}, mu = {mu:g}, {nsim[-1]} events)"
        # 1. monotone energy
        rel = np.diff(e) / e[:-1]
        max_inc = float(np.max(rel)) if rel.size else math.nan
        budget = float(cfg["monotone_ulps"]) * EPS
        rows["max_rel_increase"].append(max_inc)
        rows["min_excess"].append(float(np.min(e)))
        verdicts.append(Verdict(
            f"E never increases and never falls below E_m = -gamma^2/2 [{name}]",
            "eq. energy-dissipation, eq. Emin", f"{ctx}: (e_(k+1) - e_k)/e_k over consecutive records, e = E - E_m",
            "max increase <= 0 (to rounding), min e >= 0",
            f"max (e_(k+1) - e_k)/e_k = {max_inc:.3g}; min e = {np.min(e):.3g}",
            f"{cfg['monotone_ulps']} eps = {budget:.2g}: e is a sum of three squares from the core state, each "
            "with a few roundings (<= 4 eps relative), two records compared",
            judge(max_inc <= budget and float(np.min(e)) >= 0.0)))
        # 2. E -> E_m
        E = energy_formula(ds)
        Em = -0.5 * gamma**2
        gap = float(np.max(np.abs((E - Em) - e)) / gamma**2)
        rows["E_inf_formula_gap"].append(gap)
        rows["excess_last"].append(float(e[-1]))
        th = rates_theory(mu)
        asym = nsim[-1] >= int(cfg["asymptotic_min_events"])
        kappa, kerr = fit_rate(t, e, n)
        sel = n > n[-1] / 10.0
        rel_tol = float(cfg["limit_bracket"])
        E_N = float(E[-1])
        bracket = (E_N - Em) / abs(Em)
        verdicts.append(Verdict(
            f"E -> E_m = -gamma^2/2 [{name}]", "Theorem static-equilibrium, eq. Emin",
            f"{ctx}: E_N from eq. tot-mech-energy at the last event; E non-increasing and >= E_m (row above) "
            "bracket lim E in [E_m, E_N]",
            f"lim E = {Em:.6g}", f"E_N = {E_N:.10g}: (E_N - E_m)/|E_m| = {bracket:.3g}; formula vs stored excess: "
            f"{gap:.1g} gamma^2", f"(E_N - E_m)/|E_m| <= {rel_tol:g} (the data pin the limit to {rel_tol:g} of E_m) and "
            "formula = E_m + stored excess to 1e-9 gamma^2 (rounding of O(1) terms early on)",
            judge(0.0 <= bracket <= rel_tol and gap <= 1e-9)))
        verdicts.append(Verdict(
            f"lim E = -gamma/2 (as printed in the proof of Theorem static-equilibrium) [{name}]",
            "proof of Theorem static-equilibrium", "same bracket [E_m, E_N] of lim E",
            f"lim E = -gamma/2 = {-gamma / 2:.6g} as printed (erratum candidate: -gamma^2/2 = {Em:.3g}, eq. Emin)",
            f"lim E in [{Em:.6g}, {E_N:.6g}], i.e. {E_N / (-gamma / 2):.3g} x (-gamma/2)",
            "-gamma/2 must lie in the bracket (any tolerance below 1 - gamma separates the two)",
            judge(Em <= -gamma / 2 <= E_N)))
        rows["E_inf"].append(E_N)
        # 3. rates
        rx, rxe = fit_rate(t, xdot, n)
        rs, rse = fit_rate(t, spring, n)
        for key, val in (("rate_energy", (kappa, kerr)), ("rate_xdot", (rx, rxe)), ("rate_spring", (rs, rse))):
            rows[key].append(val[0]), rows[key + "_err"].append(val[1])
        pref = float(np.median((n[sel] ** 2 * e[sel]) * 4 * mu**2 / (9 * gamma**2))) if asym else math.nan
        rows["prefactor"].append(pref)
        rows["xdot_first"].append(float(xdot[0])), rows["spring_first"].append(float(spring[0]))
        rows["xdot_last"].append(float(xdot[-1])), rows["spring_last"].append(float(spring[-1]))
        if asym:
            for label, (r, re_), expect, what in (
                ("E - E_m", (kappa, kerr), th["energy"], "min(2 mu/3, 2 lam)"),
                ("Xdot_n", (rx, rxe), th["xdot"], "mu/3"),
                ("D = sqrt((y - y_eq)^2 + 2 ydot^2)", (rs, rse), th["spring"], "lam")):
                tol = max(float(cfg["rate_sigmas"]) * re_, float(cfg["rate_floor"]) * expect) if math.isfinite(re_) else math.nan
                verdicts.append(Verdict(
                    f"{label} -> 0 exponentially in t at rate {what} [{name}]",
                    "Theorem static-equilibrium (rate: beyond the paper, from Theorem main_thm and eq. y-eq-sticky)",
                    f"{ctx}: slope of log({label}) vs t on the last decade of impacts; error = change from the "
                    "previous decade",
                    f"rate = {expect:.6g}", f"rate = {r:.6g} +- {re_:.2g} (first {label}: "
                    f"{(e[0] if label.startswith('E') else xdot[0] if label.startswith('X') else spring[0]):.3g}, "
                    f"last: {(e[-1] if label.startswith('E') else xdot[-1] if label.startswith('X') else spring[-1]):.3g})",
                    f"|rate - expected| <= max({cfg['rate_sigmas']:g} x decade change, {cfg['rate_floor']:g} x expected): "
                    f"the fit ignores corrections O(ln n/n) and the faster modes, which the decade change bounds",
                    judge(abs(r - expect) <= tol) if math.isfinite(tol) else NOT_CHECKABLE))
            if mu * mu < 2.0:
                share = float(np.max(spring[sel] ** 2 / (2.0 * xdot[sel] ** 2)))
                ptol = float(cfg["prefactor_tolerance"]) + share
                verdicts.append(Verdict(
                    f"n^2 (E - E_m) -> 9 gamma^2/(4 mu^2) [{name}]",
                    "beyond the paper: E - E_m = Xdot^2/4 + D^2/8 at an event, Xdot_n ~ 3 gamma/(mu n) (Theorem main_thm)",
                    f"{ctx}: median of n^2 (E - E_m) 4 mu^2/(9 gamma^2) over the last decade",
                    "1", f"{pref:.6f} (spring share D^2/(2 Xdot^2) up to {share:.2g})",
                    f"|. - 1| <= {ptol:.3g} = {cfg['prefactor_tolerance']:g} (O(ln n/n) corrections of Xdot_n over the "
                    "decade) + the spring's share of E - E_m, max D^2/(2 Xdot^2) over the decade (it decays faster)",
                    judge(abs(pref - 1.0) <= ptol)))
        # plot samples
        idx = np.unique(np.clip(np.searchsorted(n, np.geomspace(1, n[-1], kp)), 0, len(n) - 1))
        m = idx.size
        plot_n[i, :m], plot_t[i, :m], plot_e[i, :m] = n[idx], t[idx], e[idx]
        plot_x[i, :m], plot_d[i, :m] = xdot[idx], spring[idx]
        # largest relative change of e over the records up to each sample (monotonicity panel)
        inc = np.concatenate([[np.nan], rel])
        plot_inc[i, :m] = np.maximum.reduceat(np.nan_to_num(inc, nan=-np.inf), idx)[: m] if m else []
    data = xr.Dataset(coords={"scene": ("scene", np.array(names, dtype=object), {"long_name": "input scene", "units": "1"})})
    data["scene_gamma"] = ("scene", np.array(gammas), {"long_name": "gamma", "units": "1"})
    data["scene_mu"] = ("scene", np.array(mus), {"long_name": "mu", "units": "1"})
    long = {
        "max_rel_increase": "largest relative increase of E - E_m between consecutive records",
        "min_excess": "smallest E - E_m", "E_inf": "E at the last record from eq. tot-mech-energy (upper end of the bracket of lim E)",
        "E_inf_formula_gap": "max |(E_formula - E_m) - stored excess| / gamma^2",
        "excess_last": "E - E_m at the last record",
        "rate_energy": "decay rate of E - E_m in t (last decade)", "rate_energy_err": "its change from the previous decade",
        "rate_xdot": "decay rate of Xdot_n in t", "rate_xdot_err": "its change from the previous decade",
        "rate_spring": "decay rate of sqrt((y-y_eq)^2 + 2 ydot^2) in t", "rate_spring_err": "its change from the previous decade",
        "prefactor": "median n^2 (E - E_m) 4 mu^2/(9 gamma^2) over the last decade",
        "xdot_first": "xdot after the first event", "xdot_last": "xdot after the last event",
        "spring_first": "sqrt((y-y_eq)^2 + 2 ydot^2) at the first event", "spring_last": "same at the last event",
    }
    for k, v in rows.items():
        data[k] = ("scene", np.array(v, dtype=float), {"long_name": long[k], "units": "1"})
    th = [rates_theory(m) for m in mus]
    for k in ("energy", "xdot", "spring"):
        data[f"rate_{k}_theory"] = ("scene", np.array([x[k] for x in th]), {"long_name": f"predicted decay rate ({k})", "units": "1"})
    for k, arr, ln in (("n", plot_n, "event index n (1 = first impact) of the plotted samples"),
                       ("t", plot_t, "time of the plotted samples"), ("excess", plot_e, "E - E_m at the samples"),
                       ("xdot", plot_x, "xdot after the event"),
                       ("spring", plot_d, "sqrt((y - y_eq)^2 + 2 ydot^2) at the event"),
                       ("increase", plot_inc, "largest (e_(k+1) - e_k)/e_k over the records from this sample to the next")):
        data[f"sample_{k}"] = (("scene", "sample"), arr, {"long_name": ln, "units": "1"})
    data.attrs.update(check=NAME, monotone_budget=float(cfg["monotone_ulps"]) * EPS,
                      runtime_s=round(time.perf_counter() - t_start, 2))
    return verdict_dataset(verdicts, data, title=TITLE)


def plot(ds: xr.Dataset, spec: dict, outputs) -> None:
    from ..figures.common import WIDTH, plt, save

    fig, axes = plt.subplots(2, 2, figsize=(WIDTH, 5.4))
    (a1, a2), (a3, a4) = axes
    for i, name in enumerate(ds["scene"].values):
        g, mu = float(ds["scene_gamma"][i]), float(ds["scene_mu"][i])
        lab = r"%s ($\gamma=%g$, $\mu=%g$)" % (name, g, mu)
        n, t, e = ds["sample_n"].values[i], ds["sample_t"].values[i], ds["sample_excess"].values[i]
        col = f"C{i}"
        kth = float(ds["rate_energy_theory"][i])
        a1.semilogy(kth * t, e / e[0], color=col, label=lab)
        late = n > np.nanmax(n) / 10
        tt = kth * t[late]
        a1.semilogy(tt, e[late][-1] / e[0] * np.exp(-(tt - tt[-1])), "k:", lw=1.0)
        a2.loglog(n, e / g**2, color=col, label=lab)
        a3.loglog(n, ds["sample_xdot"].values[i], color=col, ls="-", label=r"$\dot X_n$, " + name)
        a3.loglog(n, ds["sample_spring"].values[i], color=col, ls="--",
                  label=r"$\sqrt{(y-y_{eq})^2+2\dot y^2}$, " + name)
        inc = ds["sample_increase"].values[i]
        a4.loglog(n, -inc, color=col, marker=".", ms=2, ls="none", label=name)
        up = inc > 0
        if up.any():
            a4.loglog(n[up], inc[up], "rx", ms=4)
    a1.set_xlabel(r"$\kappa t$, $\kappa=\min(2\mu/3,2\lambda)$, $t$ in $\sqrt{m/2k}$")
    a1.set_ylabel(r"$(E-E_m)/(E-E_m)_{n=1}$")
    a1.set_title(r"(a) $E-E_m$ vs scaled time; dotted: $e^{-\kappa t}$", fontsize=8)
    a1.legend(fontsize=5.5)
    a2.set_xlabel(r"impact index $n$")
    a2.set_ylabel(r"$(E-E_m)/\gamma^2$")
    a2.set_title(r"(b) $(E-E_m)/\gamma^2$; $\to 9/(4\mu^2 n^2)$ for $\mu^2<2$", fontsize=8)
    mu_ud = [float(m) for m in ds["scene_mu"].values if m * m < 2]
    if mu_ud:
        nn = np.geomspace(1e2, float(np.nanmax(ds["sample_n"].values)), 50)
        a2.loglog(nn, 9 / (4 * mu_ud[0] ** 2 * nn**2), "k:", lw=0.8, label=r"$9/(4\mu^2n^2)$, $\mu=%g$" % mu_ud[0])
    a2.legend(fontsize=5.5)
    a3.set_xlabel(r"impact index $n$")
    a3.set_ylabel("distance from equilibrium at the events")
    a3.set_title(r"(c) state $\to$ equilibrium ($x=0$ at events)", fontsize=8)
    a3.legend(fontsize=5)
    a4.axhline(float(ds.attrs["monotone_budget"]), color="r", lw=0.8, ls="--", label="rounding budget (16 eps)")
    a4.set_xlabel(r"impact index $n$")
    a4.set_ylabel(r"smallest loss $-(e_{k+1}-e_k)/e_k$")
    a4.set_title(r"(d) $e=E-E_m$ decreases at every record (increases: red $\times$)", fontsize=8)
    a4.legend(fontsize=5.5)
    fig.suptitle("static-equilibrium: Theorem static-equilibrium, $E\\to E_m=-\\gamma^2/2$ "
                 "(units: lengths $L$, times $\\sqrt{m/2k}$)", fontsize=9)
    fig.tight_layout()
    save(fig, outputs)


TITLE = "Theorem static-equilibrium: monotone energy decay to E_m = -gamma^2/2 and the state to equilibrium"
CHECK = Check(NAME, run, plot, TITLE)

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

The prefactor P_n = n^2 (E - E_m) 4 mu^2/(9 gamma^2) = (n Xdot_n mu/(3 gamma))^2 (1 + D^2/(2 Xdot_n^2)) approaches 1
by (ln n/n, 1/n) terms: those of n Xdot_n mu/(3 gamma) (Lemma Giorgio's) and the spring's share D^2/(2 Xdot_n^2) ~
e^{-(2 lam - 2 mu/3) t_n} = n^-1 (mu^2 < 2: lam = mu/2).  Its limit is the Richardson extrapolation that cancels both
(bounce.analysis.fitting.richardson_ln) on the last two decades, its error the larger of the extrapolation's change and
its distance to the least-squares tail fit (fitting.tail_limit), as the limits of check nonlinear.
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import xarray as xr

from ..analysis.fitting import fit_rate, richardson_ln, tail_limit
from ..exact.flight import EPS
from ..analysis.theory import E_min, energy_prefactor, equilibrium_rates, tot_mech_energy
from .base import (BEYOND, ERRATUM, NOT_CHECKABLE, PAPER, Check, Falsifier, Verdict, claim, judge, on_scenes,
                   rise_once)

NAME = "static-equilibrium"

def energy_formula(ds) -> np.ndarray:
    """E at the events from eq. tot-mech-energy (x = 0: psi = xi = eta - gamma)."""
    gamma = float(ds.attrs["gamma"])
    xidot, eta, xdot = ds["xidot"].values, ds["eta"].values, ds["xdot"].values
    return tot_mech_energy(eta - gamma, xidot, xdot + xidot, gamma)


def _prefactor(n, e, gamma, mu) -> tuple[float, float]:
    """(L, err) of P_n = n^2 (E - E_m) 4 mu^2/(9 gamma^2) on the last two decades: Richardson extrapolation (ln n/n and
    1/n cancelled), err the larger of its change and its distance to the least-squares tail fit."""
    sel = n >= n[-1] / 100.0
    P = n[sel] ** 2 * e[sel] / energy_prefactor(gamma, mu)
    L, err = richardson_ln(n[sel], P)
    return L, max(err, abs(L - tail_limit(n[sel], P)[0]))


def _scene(i: int, ds: xr.Dataset, spec: dict) -> SimpleNamespace:
    """Everything the claims need from one scene dataset (event records, x = 0 at every event)."""
    name = str(ds.attrs.get("scene", f"input{i}"))
    gamma, mu = float(ds.attrs["gamma"]), float(ds.attrs["mu"])
    n = (ds["event"].values + 1).astype(float) if "event" in ds.coords else np.arange(1.0, ds.sizes["event"] + 1)
    nsim = int(ds.attrs.get("n_events_simulated", len(n)))
    t = ds["t"].values
    e = ds["energy_excess"].values
    xdot = ds["xdot"].values
    ydot = ds["ydot"].values if "ydot" in ds else xdot + 2 * ds["xidot"].values
    w = 2.0 * ds["eta"].values  # y - y_eq at x = 0
    spring = np.sqrt(w**2 + 2.0 * ydot**2)
    rel = np.diff(e) / e[:-1]
    E = energy_formula(ds)
    Em = E_min(gamma)
    asym = nsim >= int(spec["asymptotic_min_events"])
    return SimpleNamespace(
        name=name, gamma=gamma, mu=mu, n=n, nsim=nsim, t=t, e=e, xdot=xdot, spring=spring, rel=rel,
        ctx=f"scene {name} (gamma = {gamma:g}, mu = {mu:g}, {nsim} events)",
        max_inc=float(np.max(rel)) if rel.size else math.nan, Em=Em, E_N=float(E[-1]),
        gap=float(np.max(np.abs((E - Em) - e)) / gamma**2), asym=asym, theory=equilibrium_rates(mu),
        rates={"energy": fit_rate(t, e, n), "xdot": fit_rate(t, xdot, n), "spring": fit_rate(t, spring, n)},
        prefactor=_prefactor(n, e, gamma, mu) if asym and mu * mu < 2.0 else (math.nan, math.nan))


def measure(spec: dict, inputs: list) -> SimpleNamespace:
    scenes = [_scene(i, ds, spec) for i, ds in enumerate(inputs)]
    kp = int(spec["plot_points"])
    plot = {k: np.full((len(scenes), kp), np.nan) for k in ("n", "t", "excess", "xdot", "spring", "increase")}
    for i, sc in enumerate(scenes):
        n = sc.n
        idx = np.unique(np.clip(np.searchsorted(n, np.geomspace(1, n[-1], kp)), 0, len(n) - 1))
        m = idx.size
        plot["n"][i, :m], plot["t"][i, :m], plot["excess"][i, :m] = n[idx], sc.t[idx], sc.e[idx]
        plot["xdot"][i, :m], plot["spring"][i, :m] = sc.xdot[idx], sc.spring[idx]
        # largest relative change of e over the records up to each sample (monotonicity panel)
        inc = np.concatenate([[np.nan], sc.rel])
        plot["increase"][i, :m] = np.maximum.reduceat(np.nan_to_num(inc, nan=-np.inf), idx)[: m] if m else []
    rows = {
        "max_rel_increase": [sc.max_inc for sc in scenes], "min_excess": [float(np.min(sc.e)) for sc in scenes],
        "E_inf": [sc.E_N for sc in scenes], "E_inf_formula_gap": [sc.gap for sc in scenes],
        "excess_last": [float(sc.e[-1]) for sc in scenes], "prefactor": [sc.prefactor[0] for sc in scenes],
        "prefactor_err": [sc.prefactor[1] for sc in scenes],
        "xdot_last": [float(sc.xdot[-1]) for sc in scenes], "spring_last": [float(sc.spring[-1]) for sc in scenes],
        "xdot_first": [float(sc.xdot[0]) for sc in scenes], "spring_first": [float(sc.spring[0]) for sc in scenes],
    }
    for k in ("energy", "xdot", "spring"):
        rows[f"rate_{k}"] = [sc.rates[k][0] for sc in scenes]
        rows[f"rate_{k}_err"] = [sc.rates[k][1] for sc in scenes]
    data = xr.Dataset(coords={"scene": ("scene", np.array([sc.name for sc in scenes], dtype=object),
                                        {"long_name": "input scene", "units": "1"})})
    data["scene_gamma"] = ("scene", np.array([sc.gamma for sc in scenes]), {"long_name": "gamma", "units": "1"})
    data["scene_mu"] = ("scene", np.array([sc.mu for sc in scenes]), {"long_name": "mu", "units": "1"})
    long = {
        "max_rel_increase": "largest relative increase of E - E_m between consecutive records",
        "min_excess": "smallest E - E_m", "E_inf": "E at the last record from eq. tot-mech-energy (upper end of the bracket of lim E)",
        "E_inf_formula_gap": "max |(E_formula - E_m) - stored excess| / gamma^2",
        "excess_last": "E - E_m at the last record",
        "rate_energy": "decay rate of E - E_m in t (last decade)", "rate_energy_err": "its change from the previous decade",
        "rate_xdot": "decay rate of Xdot_n in t", "rate_xdot_err": "its change from the previous decade",
        "rate_spring": "decay rate of sqrt((y-y_eq)^2 + 2 ydot^2) in t", "rate_spring_err": "its change from the previous decade",
        "prefactor": "limit of n^2 (E - E_m) 4 mu^2/(9 gamma^2) (Richardson, last two decades)",
        "prefactor_err": "its error: max(Richardson change, |L - tail fit|)",
        "xdot_first": "xdot after the first event", "xdot_last": "xdot after the last event",
        "spring_first": "sqrt((y-y_eq)^2 + 2 ydot^2) at the first event", "spring_last": "same at the last event",
    }
    for k in long:
        data[k] = ("scene", np.array(rows[k], dtype=float), {"long_name": long[k], "units": "1"})
    for k in ("energy", "xdot", "spring"):
        data[f"rate_{k}_theory"] = ("scene", np.array([sc.theory[k] for sc in scenes]),
                                    {"long_name": f"predicted decay rate ({k})", "units": "1"})
    for k, ln in (("n", "event index n (1 = first impact) of the plotted samples"),
                  ("t", "time of the plotted samples"), ("excess", "E - E_m at the samples"),
                  ("xdot", "xdot after the event"), ("spring", "sqrt((y - y_eq)^2 + 2 ydot^2) at the event"),
                  ("increase", "largest (e_(k+1) - e_k)/e_k over the records from this sample to the next")):
        data[f"sample_{k}"] = (("scene", "sample"), plot[k], {"long_name": ln, "units": "1"})
    data.attrs.update(check=NAME, monotone_budget=float(spec["monotone_ulps"]) * EPS)
    return SimpleNamespace(scenes=scenes, data=data)


RATES = {  # quantity -> (label, what the rate is)
    "energy": ("E - E_m", "min(2 mu/3, 2 lam)"),
    "xdot": ("Xdot_n", "mu/3"),
    "spring": ("D = sqrt((y - y_eq)^2 + 2 ydot^2)", "lam"),
}


# --------------------------------------------------------------------------- falsifiers (contract, point 4)

def _settled_off(ds):
    """The spring's offset eta = xi + gamma 0.2 gamma off at every record: a ball settling off the equilibrium,
    E -> E_m + (0.2 gamma)^2/2 = 0.96 E_m."""
    ds["eta"] = ds["eta"] + 0.2 * float(ds.attrs["gamma"])
    return ds


def _gamma_one(ds):
    """The records labelled gamma = 1, the one weight where the printed -gamma/2 is -gamma^2/2."""
    ds.attrs["gamma"] = 1.0
    return ds


def _excess_high(ds):
    """E - E_m 2 % above the records' at every event."""
    ds["energy_excess"] = 1.02 * ds["energy_excess"]
    return ds


#: the records behind each decay rate (RATES): E - E_m, Xdot_n, the spring's D from eta and ydot
_RATE_VARIABLES = {"energy": ("energy_excess",), "xdot": ("xdot",), "spring": ("eta", "ydot")}


def _decaying_slower(key: str, fraction: float):
    """A doctor: the records of quantity ``key`` decaying at ``fraction`` x the predicted rate (times
    e^{(1 - fraction) rate t})."""
    def doctor(ds):
        rate = equilibrium_rates(float(ds.attrs["mu"]))[key]
        slow = np.exp((1.0 - fraction) * rate * (ds["t"] - float(ds["t"][0])))
        for name in _RATE_VARIABLES[key]:
            ds[name] = ds[name] * slow
        return ds
    return doctor


def _slower(key: str, fraction: float, why: str = "") -> Falsifier:
    return Falsifier(f"{RATES[key][0]} decaying at {fraction:g} x the predicted rate {RATES[key][1]}{why} (records "
                     f"times e^(({1 - fraction:g}) rate t))", on_scenes(_decaying_slower(key, fraction)))


CLAIMS: list = []


@claim(CLAIMS, "energy-non-increasing", PAPER, "thm:static-equilibrium",
       falsifier=Falsifier("one record's E - E_m 1e-12 (relative) above its predecessor's (a corrupted record)",
                           on_scenes(rise_once)))
def energy_non_increasing(m, spec) -> dict:
    budget = float(spec["monotone_ulps"]) * EPS
    return {sc.name: Verdict(
        f"E never increases and never falls below E_m = -gamma^2/2 [{sc.name}]",
        "eq. energy-dissipation, eq. Emin", f"{sc.ctx}: (e_(k+1) - e_k)/e_k over consecutive records, e = E - E_m",
        "max increase <= 0 (to rounding), min e >= 0",
        f"max (e_(k+1) - e_k)/e_k = {sc.max_inc:.3g}; min e = {np.min(sc.e):.3g}",
        f"{spec['monotone_ulps']} eps = {budget:.2g}: e is a sum of three squares from the core state, each "
        "with a few roundings (<= 4 eps relative), two records compared",
        judge(sc.max_inc <= budget and float(np.min(sc.e)) >= 0.0)) for sc in m.scenes}


@claim(CLAIMS, "energy-limit", PAPER, "thm:static-equilibrium",
       falsifier=Falsifier("the spring's offset eta 0.2 gamma off at every record (a ball settling off the "
                           "equilibrium: E_N - E_m = 0.04 |E_m|)", on_scenes(_settled_off)))
def energy_limit(m, spec) -> dict:
    rel_tol = float(spec["limit_bracket"])
    out = {}
    for sc in m.scenes:
        bracket = (sc.E_N - sc.Em) / abs(sc.Em)
        out[sc.name] = Verdict(
            f"E -> E_m = -gamma^2/2 [{sc.name}]", "Theorem static-equilibrium, eq. Emin",
            f"{sc.ctx}: E_N from eq. tot-mech-energy at the last event; E non-increasing and >= E_m (row above) "
            "bracket lim E in [E_m, E_N]",
            f"lim E = {sc.Em:.6g}", f"E_N = {sc.E_N:.10g}: (E_N - E_m)/|E_m| = {bracket:.3g}; formula vs stored "
            f"excess: {sc.gap:.1g} gamma^2", f"(E_N - E_m)/|E_m| <= {rel_tol:g} (the data pin the limit to "
            f"{rel_tol:g} of E_m) and formula = E_m + stored excess to 1e-9 gamma^2 (rounding of O(1) terms early on)",
            judge(0.0 <= bracket <= rel_tol and sc.gap <= 1e-9))
    return out


@claim(CLAIMS, "printed-energy-limit", ERRATUM, "thm:static-equilibrium",
       known_failure="the proof prints lim E = -gamma/2; eq. Emin gives -gamma^2/2",
       falsifier=Falsifier("the records labelled gamma = 1, the one weight where -gamma/2 = -gamma^2/2 (an input where "
                           "the printed form holds)", on_scenes(_gamma_one)))
def printed_energy_limit(m, spec) -> dict:
    return {sc.name: Verdict(
        f"lim E = -gamma/2 (as printed in the proof of Theorem static-equilibrium) [{sc.name}]",
        "proof of Theorem static-equilibrium", "same bracket [E_m, E_N] of lim E",
        f"lim E = -gamma/2 = {-sc.gamma / 2:.6g} as printed (erratum candidate: -gamma^2/2 = {sc.Em:.3g}, eq. Emin)",
        f"lim E in [{sc.Em:.6g}, {sc.E_N:.6g}], i.e. {sc.E_N / (-sc.gamma / 2):.3g} x (-gamma/2)",
        "-gamma/2 must lie in the bracket (any tolerance below 1 - gamma separates the two)",
        judge(sc.Em <= -sc.gamma / 2 <= sc.E_N)) for sc in m.scenes}


def _rate_verdicts(m, spec, key: str) -> dict:
    """Decay rate of one quantity in t on the last decade, against theory.equilibrium_rates (asymptotic scenes)."""
    label, what = RATES[key]
    out = {}
    for sc in m.scenes:
        if not sc.asym:
            continue
        r, re_ = sc.rates[key]
        expect = sc.theory[key]
        v = {"energy": sc.e, "xdot": sc.xdot, "spring": sc.spring}[key]
        tol = max(float(spec["rate_sigmas"]) * re_, float(spec["rate_floor"]) * expect) if math.isfinite(re_) else math.nan
        out[sc.name] = Verdict(
            f"{label} -> 0 exponentially in t at rate {what} [{sc.name}]",
            "Theorem static-equilibrium (rate: beyond the paper, from Theorem main_thm and eq. y-eq-sticky)",
            f"{sc.ctx}: slope of log({label}) vs t on the last decade of impacts; error = change from the "
            "previous decade",
            f"rate = {expect:.6g}", f"rate = {r:.6g} +- {re_:.2g} (first {label}: {v[0]:.3g}, last: {v[-1]:.3g})",
            f"|rate - expected| <= max({spec['rate_sigmas']:g} x decade change, {spec['rate_floor']:g} x expected): "
            f"the fit ignores corrections O(ln n/n) and the faster modes, which the decade change bounds",
            judge(abs(r - expect) <= tol) if math.isfinite(tol) else NOT_CHECKABLE)
    return out


@claim(CLAIMS, "energy-rate", BEYOND, "thm:static-equilibrium", falsifier=_slower(
    "energy", 0.5, ", the rate of an amplitude (Xdot_n, D) taken for that of its square"))
def energy_rate(m, spec) -> dict:
    return _rate_verdicts(m, spec, "energy")


@claim(CLAIMS, "xdot-rate", BEYOND, "thm:static-equilibrium", falsifier=_slower("xdot", 0.9))
def xdot_rate(m, spec) -> dict:
    return _rate_verdicts(m, spec, "xdot")


@claim(CLAIMS, "spring-rate", BEYOND, "thm:static-equilibrium", falsifier=_slower("spring", 0.9))
def spring_rate(m, spec) -> dict:
    return _rate_verdicts(m, spec, "spring")


@claim(CLAIMS, "energy-prefactor", BEYOND, "thm:static-equilibrium",
       falsifier=Falsifier("E - E_m 2 % above the records' at every event (n^2 (E - E_m) -> 1.02 x 9 gamma^2/(4 mu^2))",
                           on_scenes(_excess_high)))
def energy_prefactor_limit(m, spec) -> dict:
    k = float(spec["rate_sigmas"])
    out = {}
    for sc in m.scenes:
        if not (sc.asym and sc.mu * sc.mu < 2.0):
            continue
        L, err = sc.prefactor
        out[sc.name] = Verdict(
            f"n^2 (E - E_m) -> 9 gamma^2/(4 mu^2) [{sc.name}]",
            "beyond the paper: E - E_m = Xdot^2/4 + D^2/8 at an event, Xdot_n ~ 3 gamma/(mu n) (Theorem main_thm)",
            f"{sc.ctx}: limit of P_n = n^2 (E - E_m) 4 mu^2/(9 gamma^2) by Richardson extrapolation (the ln n/n and 1/n "
            "terms cancelled: those of n Xdot_n mu/(3 gamma) and the spring's share D^2/(2 Xdot^2) ~ 1/n) on the last "
            "two decades, checked against the least-squares tail fit",
            "L = 1", f"L = {L:.8f} +- {err:.2g}",
            f"|L - 1| <= {k:g} x error (the larger of the extrapolation's change when its points move x2 and its "
            "distance to the tail fit)",
            judge(abs(L - 1.0) <= k * err) if math.isfinite(L) and math.isfinite(err) else NOT_CHECKABLE)
    return out


def plot(ds: xr.Dataset, spec: dict, outputs) -> None:
    from ..figures.common import WIDTH, legend_below, plt, save, tex_num

    fig, axes = plt.subplots(2, 2, figsize=(WIDTH, 5.4))
    (a1, a2), (a3, a4) = axes
    for i, name in enumerate(ds["scene"].values):
        g, mu = float(ds["scene_gamma"][i]), float(ds["scene_mu"][i])
        lab = r"%s ($\gamma=%s$, $\mu=%s$)" % (name, tex_num(g), tex_num(mu))
        n, t, e = ds["sample_n"].values[i], ds["sample_t"].values[i], ds["sample_excess"].values[i]
        col = f"C{i}"
        kth = float(ds["rate_energy_theory"][i])
        a1.semilogy(kth * t, e / e[0], color=col, label=lab)
        late = n > np.nanmax(n) / 10
        tt = kth * t[late]
        a1.semilogy(tt, e[late][-1] / e[0] * np.exp(-(tt - tt[-1])), "k:", lw=1.0)
        a2.loglog(n, e / g**2, color=col, label=lab)
        a3.loglog(n, ds["sample_xdot"].values[i], color=col, ls="-")
        a3.loglog(n, ds["sample_spring"].values[i], color=col, ls="--")
        inc = ds["sample_increase"].values[i]
        a4.loglog(n, -inc, color=col, marker=".", ms=2, ls="none", label=name)
        up = inc > 0
        if up.any():
            a4.loglog(n[up], inc[up], "rx", ms=4)
    a1.set_xlabel(r"$\kappa t$, $\kappa=\min(2\mu/3,2\lambda)$, $t$ in $\sqrt{m/2k}$")
    a1.set_ylabel(r"$(E-E_m)/(E-E_m)_{n=1}$")
    a1.set_title(r"(a) $E-E_m$ vs scaled time; dotted: $e^{-\kappa t}$", fontsize=8)
    a2.set_xlabel(r"impact index $n$")
    a2.set_ylabel(r"$(E-E_m)/\gamma^2$")
    a2.set_title(r"(b) $(E-E_m)/\gamma^2$; $\to 9/(4\mu^2 n^2)$ for $\mu^2<2$", fontsize=8)
    mu_ud = [float(m) for m in ds["scene_mu"].values if m * m < 2]
    if mu_ud:
        nn = np.geomspace(1e2, float(np.nanmax(ds["sample_n"].values)), 50)
        a2.loglog(nn, 9 / (4 * mu_ud[0] ** 2 * nn**2), "k:", lw=0.8)
        a2.set_title(r"(b) $(E-E_m)/\gamma^2$" "\n" r"dotted: its limit $9/(4\mu^2 n^2)$ for $\mu^2<2$, $\mu=%g$"
                     % mu_ud[0], fontsize=8)
    a3.set_xlabel(r"impact index $n$")
    a3.set_ylabel("distance from equilibrium at the events")
    a3.set_title(r"(c) state $\to$ equilibrium ($x=0$ at events)" "\n"
                 r"solid: $\dot X_n$, dashed: $\sqrt{(y-y_{eq})^2+2\dot y^2}$", fontsize=8)
    a4.axhline(float(ds.attrs["monotone_budget"]), color="r", lw=0.8, ls="--")
    a4.set_xlabel(r"impact index $n$")
    a4.set_ylabel(r"smallest loss $-(e_{k+1}-e_k)/e_k$")
    a4.set_title(r"(d) $e=E-E_m$ decreases at every record" "\n"
                 r"(increases: red $\times$; dashed: rounding budget, 16 eps)", fontsize=8)
    fig.suptitle("static-equilibrium: Theorem static-equilibrium, $E\\to E_m=-\\gamma^2/2$ "
                 "(units: lengths $L$, times $\\sqrt{m/2k}$)", fontsize=9)
    fig.tight_layout()
    legend_below(fig, *a1.get_legend_handles_labels())
    save(fig, outputs)


TITLE = "Theorem static-equilibrium: monotone energy decay to E_m = -gamma^2/2 and the state to equilibrium"
CHECK = Check(NAME, measure, tuple(CLAIMS), plot, TITLE)

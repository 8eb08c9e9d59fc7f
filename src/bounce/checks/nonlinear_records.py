"""Check ``nonlinear-records``: the Discussion's power-law spring (eq. eq-motion-nonlin-psi-xi) measured on its
simulated records, where the Discussion only argues (and group ``algebra`` derives with sympy).

xi'' = -rho xi |xi|^a - 2 mu xi' |xi|^b, psi'' = -gamma; at every record x = 0, so psi = xi = xi_eq + eta
(xi_eq = -(gamma/rho)^(1/(a+1)), eq. nonlin-equilibrium-xi).  Paper indexing as in check ``main-theorem``: the
record of event k is impact n = k + 1 (its post-impact state gives Xddot_n, Xdddot_n), and its ``tau`` is the
flight ending at event k, tau_k = t_(k+1) - t_k of the paper.

1. ``xddot-limit``: Xddot_n -> -2 gamma ("we are guaranteed that Xddot_n ... [is] in a neighborhood of
   -2 gamma"; Theorem main_thm's limit carried over).  Xddot_n = -gamma - xi''(t_n+) from the record's (xi, xi')
   (:func:`bounce.analysis.theory.nonlin_contact_derivatives`).
2. ``xdddot-limit``: Xdddot_n -> 2 mu gamma (gamma/rho)^(b/(a+1)) (eq. limitex3dot carried over), Xdddot_n =
   -xi'''(t_n+) likewise.  Both tend to their limits because the state tends to the static equilibrium with
   xi' ~ -Xdot_n/2 ~ 1/n; the correction is (c ln n + d)/n plus the spring's relaxation.
3. ``flight-constant`` (beyond): n tau_n -> C = 1/(alpha gamma) = 3 (rho/gamma)^(b/(a+1))/mu = 3/(mu |xi_eq|^b)
   (:func:`bounce.analysis.theory.nonlin_flight_constant`: eq. tau3 with Xddot_n -> -2 gamma gives tau_n ~
   Xdot_n/gamma, the map eq. mappa with the Discussion's alpha gives n Xdot_n -> 1/alpha).  The Discussion's
   "the same asymptotic law as the linear case" holds for the 1/n form, with this prefactor (3/mu only for
   b = 0; the printed reading is the erratum ``nonlinear/printed-same-asymptotic-law``).
4. ``linear-law-recovered``: "We recover the linear model for a = b = 0", with rho = 1 (the linear model's own
   stiffness; other rho rescale time: erratum ``nonlinear/printed-linear-limit``).  a = b = 0 is inside the power
   law's supported domain (a, b in [0, 50], rho > gamma 2^(a+1): :mod:`bounce.springs.power`), so the power law
   runs on its own solver (Taylor series with rigorous tails, :mod:`bounce.series`) against the closed-form linear
   solver (:mod:`bounce.exact`) from the same state: event times, kinds and post-impact states compared event by
   event over ``linear_events`` events, in probes of at most PROBE_EVENTS events, each solver restarted from its
   own last state (stored exactly, as deviations).

Limits (1-3): Richardson extrapolation :func:`bounce.analysis.fitting.richardson_ln` (the ln n/n and 1/n terms of
Lemma Giorgio's expansion cancelled) on the impacts n >= fit_n_min; its error is the larger of its change when its
points move by a factor 2 and its distance to the least-squares tail fit :func:`bounce.analysis.fitting.tail_limit`;
the tolerance is limit_sigmas times that error.
"""

from __future__ import annotations

import math
from functools import cached_property
from types import SimpleNamespace

import numpy as np
import xarray as xr

from ..analysis.fitting import limit_with_error, log_select
from ..analysis.theory import (
    nonlin_contact_derivatives,
    nonlin_contact_limits,
    nonlin_equilibrium_xi,
    nonlin_flight_constant,
)
from ..exact.flight import EPS
from ..kinds import IMPACT
from ..model import Deviations, Parameters, State
from ..simulate import simulate
from ..springs import spring_from_spec
from . import base
from .base import (
    BEYOND,
    NOT_CHECKABLE,
    PAPER,
    PROBE_EVENTS,
    Check,
    Falsifier,
    Verdict,
    claim,
    judge,
    on_scenes,
    variable,
)

NAME = "nonlinear-records"
SUBJECT = "sec:Discussion"

#: the power law that is the linear model (Discussion: a = b = 0, with the linear model's rho = 1)
LINEAR_AS_POWER = {"law": "power", "rho": 1.0, "a": 0.0, "b": 0.0}

#: the limits 1-3: key -> (q_n -> 1 in words, the paper's reference)
LIMITS = {
    "xddot": ("Xddot_n/(-2 gamma)", "Discussion (Theorem main_thm's lim Xddot_n = -2 gamma carried over)"),
    "xdddot": ("Xdddot_n/(2 mu gamma (gamma/rho)^(b/(a+1)))", "Discussion (eq. limitex3dot carried over)"),
    "ntau": ("n tau_n/C, C = 3 (rho/gamma)^(b/(a+1))/mu", "beyond the paper (Discussion, eqs. tau3 and mappa)"),
}


def _scene(i: int, ds: xr.Dataset, spec: dict) -> SimpleNamespace:
    """The scaled quantities q_n (each -> 1) of one power-law scene, their limits and errors."""
    at = ds.attrs
    name = str(at.get("scene", f"input{i}"))
    gamma, mu = float(at["gamma"]), float(at["mu"])
    rho, a, b = float(at["spring_rho"]), float(at["spring_a"]), float(at["spring_b"])
    event = ds["event"].values.astype(np.int64)
    impact = ds["kind"].values == IMPACT
    xi = nonlin_equilibrium_xi(gamma, rho, a) + ds["eta"].values
    xdd, x3 = nonlin_contact_derivatives(xi, ds["xidot"].values, gamma, mu, rho, a, b)
    xdd_lim, x3_lim = nonlin_contact_limits(gamma, mu, rho, a, b)
    C = nonlin_flight_constant(gamma, mu, rho, a, b)
    n = event + 1.0  # impact n is event n - 1
    series = {"xddot": (n, xdd / xdd_lim), "xdddot": (n, x3 / x3_lim),
              "ntau": (event.astype(float), event * ds["tau"].values / C)}  # tau at event n is tau_n
    nsim = int(at.get("n_events_simulated", len(n)))
    sc = SimpleNamespace(name=name, gamma=gamma, mu=mu, rho=rho, a=a, b=b, C=C, limits=(xdd_lim, x3_lim),
                         series=series, nsim=nsim, fit={},
                         ctx=(f"scene {name} (rho = {rho:g}, a = {a:g}, b = {b:g}, gamma = {gamma:g}, mu = {mu:g}; "
                              f"{nsim} events, stop: {at.get('stop_reason', '')})"))
    for key, (nn, q) in series.items():  # (L, err, first n, last n) on the impacts n >= fit_n_min
        sel = impact & (nn >= float(spec["fit_n_min"]))
        window = (float(nn[sel][0]), float(nn[sel][-1])) if sel.any() else (math.nan, math.nan)
        ok = sel.sum() >= 20 and window[1] >= 8.0 * window[0]  # richardson_ln reaches down to n_top/8
        sc.fit[key] = (limit_with_error(nn[sel], q[sel]) if ok else (math.nan, math.nan)) + window
    return sc


def linear_probe(spec: dict) -> SimpleNamespace:
    """The power law LINEAR_AS_POWER and the linear model from the same state, ``linear_events`` events in probes
    of <= PROBE_EVENTS events, each solver restarted from its own last post-event state (exact deviations).
    Differences per event: |t_pow - t_lin|/t_lin and max |state_pow - state_lin| over (xdot, xi', eta) relative to
    the event's state scale max(|xdot|, |xi'|, |eta|) of the linear run."""
    gamma, mu = map(float, spec["linear_params"])
    psi, psidot, xi, xidot = map(float, spec["linear_start"])
    total = int(spec["linear_events"])
    runs = {}
    for label, p in (("power", Parameters(gamma, mu, spring_from_spec(LINEAR_AS_POWER))),
                     ("linear", Parameters(gamma, mu))):
        start, t0, parts = State.from_psi_xi(psi, psidot, xi, xidot), 0.0, []
        while sum(len(r[0]) for r in parts) < total:
            tr = simulate(p, start, max_events=min(PROBE_EVENTS, total - sum(len(r[0]) for r in parts)))
            parts.append((t0 + tr.t, tr.xdot, tr.xidot, tr.eta, tr.kind))
            if len(tr) == 0 or tr.stop_reason != "max_events":
                break
            t0 += float(tr.t[-1])
            start = Deviations(0.0, float(tr.xdot[-1]), float(tr.xidot[-1]), float(tr.eta[-1]))
        runs[label] = [np.concatenate(z) for z in zip(*parts)]
    pw, ln = runs["power"], runs["linear"]
    m = min(len(pw[0]), len(ln[0]))
    scale = np.maximum.reduce([np.abs(ln[k][:m]) for k in (1, 2, 3)])
    dt = np.abs(pw[0][:m] - ln[0][:m]) / ln[0][:m]
    ds = np.max([np.abs(pw[k][:m] - ln[k][:m]) for k in (1, 2, 3)], axis=0) / scale
    return SimpleNamespace(gamma=gamma, mu=mu, start=(psi, psidot, xi, xidot), events=(len(pw[0]), len(ln[0])),
                           kinds_equal=bool(np.array_equal(pw[4][:m], ln[4][:m])), dt=dt, dstate=ds,
                           k=np.arange(1, m + 1, dtype=float), n_impacts=int(np.sum(ln[4][:m] == IMPACT)))


class Measurements(base.Measurements):
    """Per-scene limits (:func:`_scene`) and the a = b = 0 probe (:func:`linear_probe`), each on first use."""

    @cached_property
    def power_scenes(self) -> list:
        return [_scene(i, ds, self.spec) for i, ds in enumerate(self.scenes)]

    @cached_property
    def probe(self) -> SimpleNamespace:
        return linear_probe(self.spec)

    @cached_property
    def data(self) -> xr.Dataset:
        scs, pr, kp = self.power_scenes, self.probe, int(self.spec["plot_points"])
        data = xr.Dataset(coords={
            "scene": ("scene", np.array([s.name for s in scs], dtype=object), {"long_name": "input scene", "units": "1"}),
            "probe_event": ("probe_event", pr.k, {"long_name": "event of the a = b = 0 probe (1 = first)", "units": "1"})})
        for key in ("a", "b", "rho", "gamma", "mu", "C"):
            data[f"scene_{key}"] = variable("scene", [getattr(s, key) for s in scs],
                                            "C = 3 (rho/gamma)^(b/(a+1))/mu" if key == "C" else key,
                                            "sqrt(m/2k)" if key == "C" else "1")
        for key, (text, _) in LIMITS.items():
            data[f"{key}_limit"] = variable("scene", [s.fit[key][0] for s in scs], f"Richardson limit of {text}")
            data[f"{key}_limit_err"] = variable("scene", [s.fit[key][1] for s in scs],
                                                "its error: max(Richardson change, |L - tail fit|)")
            nn, qq = np.full((len(scs), kp), np.nan), np.full((len(scs), kp), np.nan)
            for i, s in enumerate(scs):
                n, q = s.series[key]
                idx = log_select(n, max(n[0], 1.0), n[-1], kp)
                nn[i, :idx.size], qq[i, :idx.size] = n[idx], q[idx]
            data[f"{key}_n"] = variable(("scene", "sample"), nn, "impact index n")
            data[f"{key}_q"] = variable(("scene", "sample"), qq, text)
        data["probe_dt"] = variable("probe_event", pr.dt, "|t_power - t_linear|/t_linear")
        data["probe_dstate"] = variable("probe_event", pr.dstate,
                                        "max |state_power - state_linear| over (xdot, xi', eta), over the state's scale")
        data.attrs.update(check=NAME, probe_gamma=pr.gamma, probe_mu=pr.mu,
                          probe_ulps_per_event=float(self.spec["linear_ulps"]))
        return data


def _limit_rows(m, spec, key, claim_text, limit_of, symbol: str, note_of=lambda sc: "") -> dict:
    """One row per scene: the limit L of q_n = value/``limit_of(sc)`` against 1; ``symbol`` names the value,
    ``note_of(sc)`` adds to the expectation."""
    k = float(spec["limit_sigmas"])
    text, ref = LIMITS[key]
    out = {}
    for sc in m.power_scenes:
        L, err, lo, hi = sc.fit[key]
        ok = math.isfinite(L) and math.isfinite(err)
        lim = limit_of(sc)
        out[sc.name] = Verdict(
            f"{claim_text} [{sc.name}]", ref,
            f"{sc.ctx}: q_n = {text} on the impacts n in [{lo:.4g}, {hi:.4g}] (n >= {spec['fit_n_min']}); limit by "
            "Richardson extrapolation (ln n/n and 1/n cancelled, bounce.analysis.fitting.richardson_ln) checked "
            "against the least-squares tail fit (bounce.analysis.fitting.tail_limit)",
            f"L = 1 (lim {symbol} = {lim:.8g}{note_of(sc)})",
            f"L - 1 = {L - 1:+.3g} +- {err:.2g}, i.e. lim {symbol} = {L * lim:.8g} +- {err * abs(lim):.2g}" if ok else "no fit window (fewer than 20 impacts or less than a "
                                                              "factor 8 in n after fit_n_min)",
            f"|L - 1| <= {k:g} x error (the larger of the extrapolation's change when its points move x2 and its "
            "distance to the tail fit; nothing else)",
            judge(abs(L - 1.0) <= k * err) if ok else NOT_CHECKABLE)
    return out


def _rest_at_linear_equilibrium(ds: xr.Dataset) -> xr.Dataset:
    """The records of a spring resting at the linear law's xi = -gamma instead of xi_eq (eta shifted by the gap)."""
    at = ds.attrs
    gap = -float(at["gamma"]) - nonlin_equilibrium_xi(float(at["gamma"]), float(at["spring_rho"]), float(at["spring_a"]))
    ds["eta"] = ds["eta"] + gap
    return ds


def _rigid_flights(ds: xr.Dataset) -> xr.Dataset:
    """The records with every flight twice as long: the rigid ball's 2 Xdot_n/gamma (the whole ball launched at the
    impact speed) instead of the centre of mass's launch at Xdot_n/2."""
    ds["tau"] = 2.0 * ds["tau"]
    return ds


LINEAR_EQUILIBRIUM = Falsifier(
    "records of a spring that rests at the linear law's equilibrium xi = -gamma instead of the power law's xi_eq "
    "(eta shifted by -gamma - xi_eq)", on_scenes(_rest_at_linear_equilibrium))

CLAIMS: list = []


@claim(CLAIMS, "xddot-limit", PAPER, SUBJECT, falsifier=LINEAR_EQUILIBRIUM)
def xddot_limit(m, spec) -> dict:
    return _limit_rows(m, spec, "xddot", "Xddot_n -> -2 gamma for the power-law spring", lambda sc: sc.limits[0],
                       "Xddot_n")


@claim(CLAIMS, "xdddot-limit", PAPER, SUBJECT, falsifier=LINEAR_EQUILIBRIUM)
def xdddot_limit(m, spec) -> dict:
    return _limit_rows(m, spec, "xdddot", "Xdddot_n -> 2 mu gamma (gamma/rho)^(b/(a+1)) for the power-law spring",
                       lambda sc: sc.limits[1], "Xdddot_n")


@claim(CLAIMS, "flight-constant", BEYOND, SUBJECT,
       falsifier=Falsifier("records of the rigid ball's flights, tau_n = 2 Xdot_n/gamma (every flight doubled)",
                           on_scenes(_rigid_flights)))
def flight_constant(m, spec) -> dict:
    return _limit_rows(m, spec, "ntau", "tau_n ~ C/n with C = 1/(alpha gamma) = 3 (rho/gamma)^(b/(a+1))/mu (the "
                       "linear law's 3/mu only for b = 0)", lambda sc: sc.C, "n tau_n",
                       lambda sc: f"; the linear law's 3/mu = {3.0 / sc.mu:.6g}")


def _stiffer_power_law() -> dict:
    return {"LINEAR_AS_POWER": {**LINEAR_AS_POWER, "rho": 1.0 + 1e-6}}


@claim(CLAIMS, "linear-law-recovered", PAPER, SUBJECT,
       falsifier=Falsifier("the power law with rho = 1 + 1e-6 (a = b = 0): one part in a million stiffer than the "
                           "linear model", patch=_stiffer_power_law))
def linear_law_recovered(m, spec) -> Verdict:
    pr, ulps = m.probe, float(spec["linear_ulps"])
    n = min(pr.events)
    t_ulps, s_ulps = (float(np.max(d / (pr.k * EPS))) if n else math.nan for d in (pr.dt, pr.dstate))
    ok = n == int(spec["linear_events"]) and pr.events[0] == pr.events[1] and pr.kinds_equal
    psi, psidot, xi, xidot = pr.start
    return Verdict(
        "The power law with a = b = 0 and rho = 1 is the linear model: its solver reproduces the closed-form linear "
        "solver's events", "Discussion ('We recover the linear model for a = b = 0')",
        f"gamma = {pr.gamma:g}, mu = {pr.mu:g}, from psi = {psi:g}, psi' = {psidot:g}, xi = {xi:g}, xi' = {xidot:g}: "
        f"{spec['linear_events']} events of the power law (series solver, bounce.series) and of the linear model "
        f"(closed forms, bounce.exact), in probes of <= {PROBE_EVENTS} events each restarted from its own solver's "
        "last state; per event k, |dt_k|/t_k and max |d(xdot, xi', eta)|/max(|xdot|, |xi'|, |eta|), over k eps",
        "the same events: kinds equal, times and post-impact states equal to rounding",
        f"{pr.events[0]} and {pr.events[1]} events ({pr.n_impacts} impacts), kinds "
        f"{'equal' if pr.kinds_equal else 'differ'}; max over k of the time difference {t_ulps:.3g} x k eps, of the "
        f"state difference {s_ulps:.3g} x k eps (largest relative differences {np.max(pr.dt):.2g}, "
        f"{np.max(pr.dstate):.2g})",
        f"<= {ulps:g} x k eps at event k: each solver is exact to a few ulps of its state per event (closed forms; the "
        "series' rigorous tails below 2^-55 of the rounding scale), and the errors of k events add",
        judge(ok and t_ulps <= ulps and s_ulps <= ulps) if n else NOT_CHECKABLE)


def plot(ds: xr.Dataset, spec: dict, outputs) -> None:
    from ..figures.common import WIDTH, legend_below, plt, save

    fig, axes = plt.subplots(2, 2, figsize=(WIDTH, 5.2))
    (a_xdd, a_x3), (a_tau, a_probe) = axes
    for i, name in enumerate(ds["scene"].values):
        lab = rf"{name} ($\rho={float(ds['scene_rho'][i]):g}$, $a={float(ds['scene_a'][i]):g}$, $b={float(ds['scene_b'][i]):g}$)"
        for ax, key in ((a_xdd, "xddot"), (a_x3, "xdddot")):
            ax.loglog(ds[f"{key}_n"].values[i], np.abs(ds[f"{key}_q"].values[i] - 1.0), color=f"C{i}", label=lab)
        a_tau.semilogx(ds["ntau_n"].values[i], ds["ntau_q"].values[i], color=f"C{i}", label=lab)
        ratio = 3.0 / float(ds["scene_mu"][i]) / float(ds["scene_C"][i])
        if abs(ratio - 1.0) > 1e-12:
            a_tau.axhline(ratio, color=f"C{i}", ls=":", lw=0.8)
    for ax, title in ((a_xdd, r"(a) $|\ddot X_n/(-2\gamma)-1|$"),
                      (a_x3, r"(b) $|\dddot X_n/(2\mu\gamma(\gamma/\rho)^{b/(a+1)})-1|$")):
        nmax = float(np.nanmax(ds["xddot_n"].values))
        nn = np.geomspace(10.0, nmax, 20)
        ax.loglog(nn, 10.0 / nn, "k:", lw=0.8, label=r"$\propto 1/n$")
        ax.set_xlabel(r"impact index $n$")
        ax.set_ylabel("relative deviation from the limit (1)")
        ax.set_title(title, fontsize=8)
    a_tau.axhline(1.0, color="k", lw=0.6)
    a_tau.set_ylim(0.0, 1.3)
    a_tau.set_xlabel(r"impact index $n$")
    a_tau.set_ylabel(r"$n\tau_n/C$,  $C=3(\rho/\gamma)^{b/(a+1)}/\mu$ (1)")
    a_tau.set_title(r"(c) flight constant; dotted: the linear law's $3/\mu$ over $C$", fontsize=8)
    k = ds["probe_event"].values
    eps = np.finfo(float).eps
    a_probe.semilogy(k, np.maximum(ds["probe_dt"].values, eps / 100), "o", ms=2, label=r"$|\Delta t_k|/t_k$ (0 drawn at $\epsilon/100$)")
    a_probe.semilogy(k, np.maximum(ds["probe_dstate"].values, eps / 100), "s", ms=2,
                     label=r"$\max|\Delta(\dot x,\xi',\eta)|$ / state scale")
    a_probe.semilogy(k, float(ds.attrs["probe_ulps_per_event"]) * k * eps, "k--", lw=0.8,
                     label=rf"tolerance ${float(ds.attrs['probe_ulps_per_event']):g}\,k\,\epsilon$")
    a_probe.set_xlabel(r"event $k$")
    a_probe.set_ylabel("relative difference (1)")
    a_probe.set_title(rf"(d) power law $a=b=0$, $\rho=1$ vs linear solver ($\gamma={float(ds.attrs['probe_gamma']):g}$, "
                      rf"$\mu={float(ds.attrs['probe_mu']):g}$)", fontsize=7)
    a_probe.legend(fontsize=5.5)
    fig.suptitle(r"power-law spring (Discussion) on its records (lengths in $L$, times in $\sqrt{m/2k}$)", fontsize=9)
    fig.tight_layout()
    legend_below(fig, *a_xdd.get_legend_handles_labels())  # in (a) it covered the curves
    save(fig, outputs)


TITLE = ("Discussion, on the power-law records: Xddot_n and Xdddot_n limits, the flight constant tau_n ~ C/n, "
         "a = b = 0 with rho = 1 against the linear solver")
CHECK = Check(NAME, Measurements, tuple(CLAIMS), plot, TITLE)

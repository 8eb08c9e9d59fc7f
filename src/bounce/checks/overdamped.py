"""Check ``overdamped``: figs. very_rigid_poincare_overdamped(_magni) and sec. 8.1's over-damped ball (mu = 2).

Indexing: impact n (paper, t_0 = 0 the release) is bounce's event n - 1, tau_n = traj.tau[n], Xdot_n = traj.xdot[n - 1];
just before impact n the centre of mass moves at psi'(t_n^-) = xi'(t_n^+) = xidot[n-1] (eq. collision-rule).

Scene overdamped (mu = 2): y - y_eq at the events (= 2 eta, x = 0) is negative and increasing from some n0 on; n0,
the impact of the minimum, sign changes; the transients of n tau_n mu/3 (Theorem main_thm's relation) and of
n Xdot_n mu/(3 gamma) (its proof's); the effective restitution of the first impact,
r_eff = gamma tau_1/(2|psi'(t_1^-)|) (the rigid ball's first flight is 2 r u/gamma).
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import xarray as xr

from ..analysis.restitution import event_arrays
from .base import PAPER, Check, Falsifier, Verdict, claim, judge, on_scenes, with_variable

NAME = "overdamped"


def overdamped(ds, cfg) -> dict:
    gamma, mu = float(ds.attrs["gamma"]), float(ds.attrs["mu"])
    tau, xd, xi, w, kind = event_arrays(ds)
    neg = w < 0
    inc = np.diff(w) > 0
    ok = neg[:-1] & inc  # record i is negative and the next is larger
    ok = np.append(ok, neg[-1])
    bad = np.nonzero(~ok)[0]
    i0 = 0 if bad.size == 0 else int(bad[-1]) + 1
    n = np.arange(1, len(tau))
    q = n * tau[1:] * mu / 3.0  # tau_n / (3/(mu n)), Theorem main_thm
    q_x = n * np.abs(xd[:-1]) * mu / (3.0 * gamma)  # Xdot_n / (3 gamma/(mu n)), proof of Theorem main_thm
    n10 = settled(n, q, cfg["transient"])
    r_eff = gamma * tau[1] / (2.0 * abs(xi[0]))  # psi'(t_1^-) = xidot[0]
    return {"gamma": gamma, "mu": mu, "w": w, "n0": i0 + 1, "n_min": int(np.argmin(w)) + 1,
            "sign_changes": int(np.sum(np.diff(np.sign(w)) != 0)),
            "slope_changes": int(np.sum(np.diff(np.sign(np.diff(w))) != 0)),
            "n10": n10, "r_eff": r_eff, "n_events": len(w),
            "n_strict_tau": settled(n, q, cfg["transient_strict"]), "n_strict_xdot": settled(n, q_x, cfg["transient_strict"]),
            "n_loose_xdot": settled(n, q_x, cfg["transient"])}


def settled(n, q, tol: float) -> float:
    """First n after which |q_n - 1| < tol for every later recorded impact (1 if always, inf if never)."""
    bad = np.nonzero(~(np.abs(q - 1.0) < tol))[0]
    if not bad.size:
        return 1.0
    return float(n[bad[-1] + 1]) if bad[-1] + 1 < n.size else math.inf


def measure(spec: dict, inputs: list) -> SimpleNamespace:
    """The over-damped input's approach to equilibrium (the first input with mu^2 > 2)."""
    data = xr.Dataset()
    dso = next((d for d in inputs if float(d.attrs["mu"]) ** 2 > 2.0), None)
    m = SimpleNamespace(over=dso is not None)
    if m.over:
        m.od_name = name = str(dso.attrs.get("scene", "over-damped input"))
        m.od = o = overdamped(dso, spec)
        m.od_ctx = f"scene {name} (gamma = {o['gamma']:g}, mu = {o['mu']:g}, {o['n_events']} impacts)"
        w = o["w"]
        k = np.unique(np.geomspace(1, len(w), 400).astype(int)) - 1
        data = data.assign(od_n=("od_sample", (k + 1).astype(float), {"long_name": "impact index n", "units": "1"}),
                           od_y_minus_yeq=("od_sample", w[k], {"long_name": "y - y_eq at impact n", "units": "1"}))
        data.attrs.update(od_n0=o["n0"], od_n_min=o["n_min"], od_r_eff=o["r_eff"], od_transient=o["n10"],
                          od_gamma=o["gamma"], od_mu=o["mu"], od_scene=name)
    data.attrs.update(check=NAME)
    m.data = data
    return m


CLAIMS: list = []


def _from_above(ds):
    """Records whose spring approaches its equilibrium from above (y - y_eq with its sign flipped)."""
    return with_variable(ds, "y_minus_yeq", -ds["y_minus_yeq"].values)


def _on_asymptotic_laws(ds):
    """Records on Theorem main_thm's laws from the first impact on: tau_n = 3/(mu n), Xdot_n = 3 gamma/(mu n)."""
    mu, gamma = float(ds.attrs["mu"]), float(ds.attrs["gamma"])
    tau, xd = ds["tau"].values.copy(), ds["xdot"].values.copy()
    n = np.arange(1, len(tau))
    tau[1:] = 3.0 / (mu * n)
    xd[:-1] = 3.0 * gamma / (mu * n)
    return with_variable(with_variable(ds, "tau", tau), "xdot", xd)


def _first_flight_long(ds):
    """Records whose first flight after the landing lasts 3 times the simulated one (r_eff x 3)."""
    tau = ds["tau"].values.copy()
    tau[1] *= 3.0
    return with_variable(ds, "tau", tau)


@claim(CLAIMS, "overdamped-monotone-approach", PAPER, "fig:very_rigid_poincare_overdamped",
       falsifier=Falsifier("the over-damped spring approaching its equilibrium from above (y - y_eq sign-flipped)",
                           on_scenes(_from_above)))
def overdamped_monotone_approach(m, spec) -> dict:
    if not m.over:
        return {}
    o, few = m.od, int(spec["few_impacts"])
    return {m.od_name: Verdict(
        "The over-damped spring shrinks for the first few impacts, then expands, approaching its equilibrium "
        "length monotonically from below", "figs. very_rigid_poincare_overdamped(_magni), sec. 8.1",
        f"{m.od_ctx}: y - y_eq (= spring length - its equilibrium, x = 0) at the impacts: n0 = first impact from "
        "which it is < 0 and increasing at every later impact; impact of the minimum; sign changes",
        f"n0 and the minimum within the first few ({few}) impacts, then no sign change of y - y_eq or of its "
        "increments",
        f"n0 = {o['n0']}, minimum at impact {o['n_min']}, sign changes of y - y_eq: {o['sign_changes']}, of its "
        f"increments: {o['slope_changes']} (all before n0)",
        f"'first few' read as <= {few} impacts", judge(o["n0"] <= few and o["n_min"] <= few))}


def _overdamped_transient(ds):
    """Records with a transient: the first 30 flights 15 % longer than simulated."""
    tau = ds["tau"].values.copy()
    tau[1:31] *= 1.15
    return with_variable(ds, "tau", tau)


@claim(CLAIMS, "overdamped-no-transient", PAPER, "fig:very_rigid_poincare_overdamped",
       falsifier=Falsifier("a transient in the over-damped records: the first 30 flights 15 % longer than simulated",
                           on_scenes(_overdamped_transient)))
def overdamped_no_transient(m, spec) -> dict:
    if not m.over:
        return {}
    o, few, tol = m.od, int(spec["few_impacts"]), spec["transient"]
    return {m.od_name: Verdict(
        "The over-damped system enters the asymptotic regime immediately, without a disordered transient",
        "sec. 8.1; Theorem main_thm", f"{m.od_ctx}: first n after which |n tau_n mu/3 - 1| < {tol:g} for good "
        "(the asymptotic relation Theorem main_thm states is tau_n ~ 3/(mu n); Xdot_n ~ 3 gamma/(mu n) is a step of "
        "its proof, reported here and judged in row overdamped-asymptotic-1pc)",
        f"<= {few} impacts", f"{o['n10']:.0f} (for Xdot_n, n Xdot_n mu/(3 gamma) within the same band: "
        f"{o['n_loose_xdot']:.0f}: its over-damped correction decays slowly, as n^(-3 lam/mu) = n^-0.44 at mu = 2)",
        f"'immediately' read as <= {few} impacts (the under-damped rest-coeff transient lasts ~2e3), at {tol:.0%}: the "
        "paper's contrast with the under-damped disorder (sec. 8.1), not 1 % accuracy of the asymptotic laws (row "
        "overdamped-asymptotic-1pc)", judge(o["n10"] <= few))}


@claim(CLAIMS, "overdamped-asymptotic-1pc", PAPER, "fig:very_rigid_poincare_overdamped",
       known_failure="read strictly (the asymptotic laws to 1 %), 'immediately' does not hold: it takes thousands "
                     "of impacts, more than the under-damped transient",
       falsifier=Falsifier("over-damped records on Theorem main_thm's laws from the first impact on (tau_n = 3/(mu n), "
                           "Xdot_n = 3 gamma/(mu n))", on_scenes(_on_asymptotic_laws)))
def overdamped_asymptotic_1pc(m, spec) -> dict:
    if not m.over:
        return {}
    o, few, tol = m.od, int(spec["few_impacts"]), spec["transient_strict"]

    def when(v):
        return f"{v:.0f}" if math.isfinite(v) else f"not within the {o['n_events']} impacts simulated"

    return {m.od_name: Verdict(
        "The over-damped system enters the asymptotic regime immediately, read strictly: tau_n and Xdot_n within "
        f"{tol:.0%} of 3/(mu n) and 3 gamma/(mu n)",
        "sec. 8.1; Theorem main_thm", f"{m.od_ctx}: first n after which |n tau_n mu/3 - 1| < {tol:g} and "
        f"|n Xdot_n mu/(3 gamma) - 1| < {tol:g} for good (and the same for Xdot at {spec['transient']:g})",
        f"<= {few} impacts for both", f"tau: {when(o['n_strict_tau'])}; Xdot: {when(o['n_strict_xdot'])} "
        f"(at {spec['transient']:.0%}: tau {when(o['n10'])}, Xdot {when(o['n_loose_xdot'])})",
        f"{tol:g}: the strict reading (the law to two significant digits; {spec['transient']:g} is the loose "
        f"reading of overdamped-no-transient); 'immediately' read as <= {few} impacts, as there",
        judge(o["n_strict_tau"] <= few and o["n_strict_xdot"] <= few))}


@claim(CLAIMS, "overdamped-inelastic", PAPER, "fig:very_rigid_poincare_overdamped",
       falsifier=Falsifier("the over-damped ball's first flight 3 times the simulated one (r_eff x 3: a rebound "
                           "regaining 0.14 % of the drop height)", on_scenes(_first_flight_long)))
def overdamped_inelastic(m, spec) -> dict:
    if not m.over:
        return {}
    o, frac = m.od, float(spec["inelastic_energy_fraction"])
    return {m.od_name: Verdict(
        "Macroscopically, the over-damped ball performs a single, totally inelastic impact",
        "sec. 8.1", f"{m.od_ctx}: r_eff = gamma tau_1/(2|psi'(t_1^-)|), the constant restitution a rigid ball needs "
        "for the first flight", "r_eff ~ 0",
        f"r_eff = {o['r_eff']:.3g} (rebound height ratio r_eff^2 = {o['r_eff'] ** 2:.2g})",
        f"r_eff^2 <= {frac:g}: less than {frac:.1%} of the drop height is regained", judge(o["r_eff"] ** 2 <= frac))}


def plot(ds: xr.Dataset, spec: dict, outputs) -> None:
    """(a) y - y_eq at the impacts against n, with n0; (b) its monotone approach from below, log-log, against the
    over-damped decay n^(-3 lambda/mu)."""
    from ..figures.common import WIDTH, plt, save, tex_num

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(WIDTH, 3.0), constrained_layout=True)
    if "od_n" in ds:
        n, w = ds["od_n"].values, ds["od_y_minus_yeq"].values
        g, mu = float(ds.attrs["od_gamma"]), float(ds.attrs["od_mu"])
        a1.semilogx(n, w / g, "k.-", ms=2, lw=0.6, label=r"$(y-y_{eq})/\gamma$ at impact $n$")
        a1.axhline(0, color="C2", lw=0.8, label="equilibrium length")
        a1.axvline(ds.attrs["od_n0"], color="C3", ls=":", label=r"$n_0=%d$: negative and rising from here" % ds.attrs["od_n0"])
        a1.set(xlabel="impact index $n$", ylabel=r"$(y-y_{eq})/\gamma$ at impact $n$")
        a1.set_title(r"(a) %s ($\gamma=%s$, $\mu=%s$): spring length vs equilibrium" % (ds.attrs["od_scene"], tex_num(g),
                                                                                          tex_num(mu)),
                     fontsize=7)
        a1.legend(fontsize=6, loc="lower right")
        neg = w < 0
        a2.loglog(n[neg], -w[neg] / g, "k.-", ms=2, lw=0.6, label=r"$-(y-y_{eq})/\gamma$")
        late = n > 100
        if late.any():
            p = 3 * (mu - math.sqrt(mu**2 - 2)) / 2 / mu  # 3 lambda/mu, lambda the slow over-damped rate
            a2.loglog(n[late], -w[late][0] / g * (n[late] / n[late][0]) ** -p, "C1--",
                      label=r"$\propto n^{-3\lambda/\mu}$, $\lambda=(\mu-\sqrt{\mu^2-2})/2$")
        a2.set(xlabel="impact index $n$", ylabel=r"$-(y-y_{eq})/\gamma$ at impact $n$")
        a2.set_title(r"(b) monotone approach from below; $r_{eff}=%.3f$" % ds.attrs["od_r_eff"], fontsize=7)
        a2.legend(fontsize=6, loc="upper right")
    fig.suptitle("over-damped ball, sec. 8.1 (lengths in $L$; y: upper mass height, $y_{eq}=1-2\\gamma$)", fontsize=8)
    save(fig, outputs)


TITLE = "The over-damped ball (mu = 2): monotone approach from below, no transient, a single inelastic impact"
CHECK = Check(NAME, measure, tuple(CLAIMS), plot, TITLE)

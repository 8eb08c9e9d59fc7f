"""Check ``restitution``: the restitution coefficient of sec. 8 and eq. our-r of sec. 9.

Indexing: impact n (paper, t_0 = 0 the release) is bounce's event n - 1, tau_n = traj.tau[n],
Xdot_n = traj.xdot[n - 1]; the centre-of-mass velocity psi' = (xdot + ydot)/2 = xdot + xi' just
after impact n is psi'(t_n^+) = xdot[n-1] + xidot[n-1], and just before it, by the collision
rule (eq. collision-rule), psi'(t_n^-) = xi'(t_n^+) = xidot[n-1].

(a) Double-impact regime of scene rest-coeff (gamma = 1e-5, mu = 0.01): a macroscopic bounce
    is a double impact (impacts 2m-1, 2m) followed by the macroscopic flight f_m = tau_{2m}
    (eq. my-time-of-flight); r_m = f_{m+1}/f_m (eq. Falcon-rest-coeff) against
    r = exp(-mu T_xi) (eq. rest-coefficient-function-of-mu) on the initial plateau, defined
    physically: bounces whose flight f_m lasts at least ``plateau_flight`` x T_d (T_d = 1/mu,
    eq. char-times), so that the spring's residual vibration is damped by e^{-mu f} <= e^{-2}
    before the next contact (the paper: flights "of the order of T_d or larger").  Also the
    centre-of-mass velocity ratio of eq. proper-rest-coeff, in the printed orientation
    (before/after the double impact) and inverted.
(b) The contact time: tau_{2m-1} against T_xi = pi/sqrt(1 - mu^2).  After the landing at speed V_m the
    lower mass is at x = (V/omega) e^{-mu t} sin(omega t) - gamma t^2/2 + (the spring's vibration left
    at the landing): the centre of mass falls by gamma t^2/2, so the lower mass lands again earlier by
    delta_m = gamma T_xi e^{mu T_xi}/(2 V_m) to first order, 1 - delta_m + (2 + mu T_xi) delta_m^2 to
    second; a spring half-extension xi_0 = (y - x - 1)/2 and half-rate xi'_0 = (ydot - xdot^-)/2 left at the
    landing move the end of the contact by (xi_0/V)(e^{mu T_xi} + 1)/T_xi + (xi'_0/V) e^{mu T_xi} (first
    order in their relative size a_m = |(xi_0, xi'_0)|/V_m; omega = sqrt(1 - mu^2) ~ 1).
(c) Scene overdamped (mu = 2): y - y_eq at the events (= 2 eta, x = 0) is negative and
    increasing from some n0 on; n0, the impact of the minimum, sign changes; the transients of
    n tau_n mu/3 (Theorem main_thm's relation) and of n Xdot_n mu/(3 gamma) (its proof's); the effective restitution of the first impact, r_eff = gamma tau_1/(2|psi'(t_1^-)|)
    (the rigid ball's first flight is 2 r u/gamma).
(d) Eq. our-r.  The impact speed is the lower mass's, u = Xdot (eq. collision-rule-map): it
    is the variable of eq. restituzione, and in the double-impact regime it equals the
    centre-of-mass speed (the spring is at rest at landing).  The dimer's restitution per
    macroscopic bounce is the ratio of successive landing speeds: Xdot_{2m+1}/Xdot_{2m-1} for
    the initial run of double impacts (contact flight within ``double_band`` of T_xi), and
    Xdot_{n+1}/Xdot_n for every impact after it (each flight is then a bounce, as in eq.
    restituzione).  The band [u1, u2] spans the bounces where the dissipated fraction is off,
    |(1 - r)/(1 - r_our) - 1| > ``our_r_threshold`` = thr (1 - r, not r: r ~ 1 - 1e-4 at small u).
    Its edges are predicted by the two branches' error models, each from the spring's vibration:
    the large-u branch (eq. rest-coefficient-function-of-mu) assumes the spring at rest at landing; the
    vibration a contact leaves, of the order of what it dissipates, decays over the flight f = 2u/gamma
    as e^{-mu f}, so its relative error on 1 - r is ~ e^{-mu f}: thr at u_L = gamma ln(1/thr)/(2 mu), within
    a factor e of the unknown O(1) prefactor (u_L (1 +- 1/ln(1/thr))).  (Measured on rest-coeff: the vibration
    at the plateau's landings, a_m of (b) times e^{mu f_(m-1)}, is 0.027-0.041 of the landing speed, 1 - r = 0.031;
    the band's upper edge gives a prefactor 1.3.)  The small-u branch assumes the
    map's jerk x'''(zeta_n) = 2 mu gamma (eq. limitex3dot); by eq. dimensionless-eq-motion
    x''' = (ydot - xdot)/2 + mu (yddot - xddot), and in mid-flight xdot ~ 0, so the upper mass's velocity
    ydot_n adds ydot_n/2: 1 - r = (mu u/(3 gamma))(1 + ydot_n/(4 mu gamma)) + O(eps^2), eps_n =
    ydot_n/(4 mu gamma); the branch fails from the first bounce (from below) with |eps_n| > thr, known to
    +- thr^2 (the neglected order).
    In terms of the rigid ball's own speed (the centre of mass, flight 2u/gamma) the small-u
    branch is checked too: there u_COM = gamma tau_n/2 = Xdot_n/2, so the law reads 1 - 2 mu u/(3 gamma).
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import xarray as xr

from ..analysis.restitution import double_impact, event_arrays, our_r_test
from ..analysis.theory import our_r
from .base import (BEYOND, ERRATUM, NOT_CHECKABLE, PAPER, Check, Falsifier, Verdict, claim, judge, on_scenes,
                   with_variable)

NAME = "restitution"


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



def landing_vibration(ds, d) -> tuple[np.ndarray, np.ndarray]:
    """(xi_0/V_m, xi'_0/V_m) at the landings 2m - 1, m = 1..P+1, of the plateau's contacts: the spring's half-extension
    (y - x - 1)/2 = (y - y_eq)/2 - gamma and half-rate (ydot - xdot^-)/2 = (ydot + V_m)/2 left by the previous
    contact, over the landing speed V_m (eq. collision-rule-y1: ydot is continuous at the impact)."""
    rec = 2 * np.arange(1, d["plateau"] + 2) - 2  # the record of impact 2m - 1
    V = ds["xdot"].values[rec]
    return (event_arrays(ds)[3][rec] / 2.0 - d["gamma"]) / V, (ds["ydot"].values[rec] + V) / 2.0 / V


def contact_prediction(d, xi0, v0) -> np.ndarray:
    """tau_(2m-1)/T_xi of the contacts (module docstring, (b)): 1 - delta + (2 + mu T_xi) delta^2 + the first-order
    shift by the vibration left at the landing (xi0, v0: relative to the landing speed)."""
    e, T, delta = math.exp(d["mu"] * d["Txi"]), d["Txi"], d["delta"]
    return 1.0 - delta + (2.0 + d["mu"] * T) * delta**2 + xi0 * (e + 1.0) / T + v0 * e


def band_edges(u, spring_err, gamma: float, mu: float, thr: float) -> tuple[tuple, tuple]:
    """The band's predicted edges (module docstring, (d)): ((u1 low, u1 at thr, u1 high), (u2 low, u2 high)): the first
    bounce whose spring term |eps_n| exceeds thr -+ thr^2, and gamma (ln(1/thr) -+ 1)/(2 mu)."""
    eps = np.abs(spring_err)

    def first_above(level):
        s = eps > level
        return float(u[s].min()) if s.any() else math.inf

    ell = math.log(1.0 / thr)
    return (tuple(first_above(thr + k * thr**2) for k in (-1, 0, 1)),
            tuple(gamma * (ell + k) / (2.0 * mu) for k in (-1, 1)))


def measure(spec: dict, inputs: list) -> SimpleNamespace:
    """The under-damped input's double impacts and eq. our-r test; the over-damped input's approach."""
    data = xr.Dataset()
    dsr = next((d for d in inputs if float(d.attrs["mu"]) < 1.0), None)
    dso = next((d for d in inputs if float(d.attrs["mu"]) ** 2 > 2.0), None)
    m = SimpleNamespace(under=dsr is not None, over=dso is not None)
    if m.under:
        m.name = name = str(dsr.attrs.get("scene", "under-damped input"))
        m.d = d = double_impact(dsr, spec)
        m.ctx = f"scene {name} (gamma = {d['gamma']:g}, mu = {d['mu']:g})"
        m.P = P = d["plateau"]
        if P >= 3:
            r = d["r"]
            m.rm, m.rs = float(np.mean(r)), float(np.std(r, ddof=1))
            m.se = m.rs / math.sqrt(r.size)  # the standard error of the mean
            m.corr = d["r0"] * d["mu"] * d["Txi"] * float(np.max(d["delta"]))
            m.tol = spec["r_sigmas"] * m.se + m.corr
        m.xi0, m.v0 = landing_vibration(dsr, d)
        m.o = o = our_r_test(dsr, d, spec)
        # the small-u branch's error model: eps_n = ydot_n/(4 mu gamma) at the single-impact bounces (module docstring)
        R = d["run_len"]
        m.spring_err = np.concatenate([np.full(R - 1, np.nan), dsr["ydot"].values[2 * R:-1] / (4.0 * d["mu"] * d["gamma"])])
        m.band_small, m.band_large = band_edges(o["u"], m.spring_err, d["gamma"], d["mu"], spec["our_r_threshold"])
        data = data.assign(
            plateau_m=("plateau", d["m"].astype(float), {"long_name": "bounce index m of the plateau", "units": "1"}),
            plateau_r=("plateau", d["r"], {"long_name": "r_m = f_(m+1)/f_m on the plateau", "units": "1"}),
            plateau_after=("plateau", d["after"], {"long_name": "psi'(t_(2m+2)^+)/psi'(t_(2m)^+)", "units": "1"}),
            plateau_before_after=("plateau", d["before_after"],
                                  {"long_name": "|psi'(t_(2m+1)^-)|/psi'(t_(2m+2)^+) (printed orientation)", "units": "1"}),
            contact_ratio=("contact", d["contact_ratio"], {"long_name": "tau_(2m-1)/T_xi (contact time)", "units": "1"}),
            contact_delta=("contact", d["delta"], {"long_name": "first-order gravity shortening delta_m", "units": "1"}),
            contact_predicted=("contact", contact_prediction(d, m.xi0, m.v0), {
                "long_name": "predicted tau_(2m-1)/T_xi: gravity to second order, the landing's vibration to first",
                "units": "1"}),
            falcon_r=("bounce_f", d["r_all"][:200], {"long_name": "r_m = f_(m+1)/f_m, first 200 bounces", "units": "1"}),
            bounce_u=("bounce", o["plot"]["u"], {
                "long_name": "landing speed u (lower mass) of the macroscopic bounce", "units": "1",
                "comment": "all double-impact and all failing bounces, ~3000 log-spaced others"}),
            bounce_r=("bounce", o["plot"]["r"], {"long_name": "dimer restitution per macroscopic bounce", "units": "1"}),
            bounce_double=("bounce", o["plot"]["kind"], {"long_name": "1: double-impact bounce, 0: single-impact bounce",
                                                          "units": "1"}),
            com_u=("com_sample", o["plot"]["ucom"], {
                "long_name": "rigid-ball (centre-of-mass) speed gamma tau_n/2 of flight n after the double impacts",
                "units": "1"}),
            com_r=("com_sample", o["plot"]["rcom"], {"long_name": "tau_(n+1)/tau_n", "units": "1"}),
        )
        data.attrs.update(r_theory=d["r0"], T_xi=d["Txi"], u_c=o["uc"], band_u1=o["u1"], band_u2=o["u2"],
                          band_u1_predicted=m.band_small[1], band_u2_predicted=float(np.mean(m.band_large)),
                          r_band_u1=o["d1"], r_band_u2=o["d2"], slope_com=o["slope_com"],
                          slope_x=o["slope_x"], plateau_length=P, double_run=d["run_len"],
                          rest_gamma=d["gamma"], rest_mu=d["mu"], rest_scene=name,
                          our_r_threshold=spec["our_r_threshold"])
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


def _plateau_low(ds):
    """Records whose r_m = f_(m+1)/f_m is 1 % low over the double-impact regime (f_m = tau_(2m) scaled by 0.99^m)."""
    if "tau" in ds:
        tau = ds["tau"].values.copy()
        m = np.arange(1, min(200, (len(tau) - 1) // 2))
        tau[2 * m] *= 0.99**m
        with_variable(ds, "tau", tau)
    return ds


@claim(CLAIMS, "r-plateau", PAPER, "fig:rest-coeff",
       falsifier=Falsifier("r_m 1 % below exp(-mu T_xi) over the plateau", on_scenes(_plateau_low)))
def r_plateau(m, spec) -> dict:
    if not m.under:
        return {}
    d = m.d
    if m.P < 3:
        return {m.name: Verdict("Initially r_n is constant = exp(-mu T_xi)", "eq. rest-coefficient-function-of-mu",
                                m.ctx, f"{d['r0']:.6f}", f"plateau of {m.P} bounces only", "-", NOT_CHECKABLE)}
    return {m.name: Verdict(
        "Initially r_n = f_{n+1}/f_n is constant and agrees with r = exp(-mu T_xi)",
        "eq. rest-coefficient-function-of-mu, eq. Falcon-rest-coeff, fig. rest-coeff",
        f"{m.ctx}: mean and spread of r_m = f_(m+1)/f_m, f_m = tau_(2m), over the plateau m = 1..{m.P} "
        f"(f_m >= {spec['plateau_flight']:g} T_d)",
        f"r = exp(-mu pi/sqrt(1-mu^2)) = {d['r0']:.6f}",
        f"mean r = {m.rm:.6f}, std {m.rs:.2g} (standard error {m.se:.2g}), mean - r = {m.rm - d['r0']:+.2g}, "
        f"max |r_m - r| = {np.max(np.abs(d['r'] - d['r0'])):.2g}",
        f"|mean - r| <= {m.tol:.2g} = {spec['r_sigmas']:g} x the mean's standard error + the first-order gravity correction "
        f"r mu T_xi max(delta_m) = {m.corr:.2g} (eq. rest-coefficient-function-of-mu is the gamma -> 0 limit)",
        judge(abs(m.rm - d["r0"]) <= m.tol))}


def _printed_orientation(ds):
    """Records in which each double impact's landing speed is r times the take-off speed after it (the printed
    orientation of eq. proper-rest-coeff: |psi'(t_(2m+1)^-)| = exp(-mu T_xi) psi'(t_(2m+2)^+), a contact that gains
    speed by 1/r): xi' at impact 2m + 1 set so (psi' before it is xi' after it, eq. collision-rule)."""
    if "xidot" in ds and float(ds.attrs["mu"]) < 1.0:
        xd, xi = ds["xdot"].values, ds["xidot"].values.copy()
        r0 = math.exp(-float(ds.attrs["mu"]) * math.pi / math.sqrt(1.0 - float(ds.attrs["mu"]) ** 2))
        m = np.arange(1, min(200, (len(xi) - 2) // 2))
        xi[2 * m] = -r0 * (xd[2 * m + 1] + xi[2 * m + 1])
        with_variable(ds, "xidot", xi)
    return ds


def _takeoff_low(ds):
    """Records whose take-off velocity after double impact m, psi'(t_(2m)^+) = xdot + xi' of impact 2m, is 0.99^m of
    the simulated one: successive take-offs 1 % slower than exp(-mu T_xi)."""
    if "xdot" in ds and float(ds.attrs["mu"]) < 1.0:
        xd, xi = ds["xdot"].values.copy(), ds["xidot"].values.copy()
        m = np.arange(1, min(200, len(xd) // 2))
        xd[2 * m - 1] *= 0.99**m
        xi[2 * m - 1] *= 0.99**m
        with_variable(with_variable(ds, "xdot", xd), "xidot", xi)
    return ds


@claim(CLAIMS, "printed-ratio", ERRATUM, "fig:rest-coeff",
       known_failure="eq. proper-rest-coeff prints before/after, Psidot_n/Psidot_{n+2} = 1/r",
       falsifier=Falsifier("landing speeds r times the take-off after each double impact (the printed orientation: "
                           "before/after = exp(-mu T_xi))", on_scenes(_printed_orientation)))
def printed_ratio(m, spec) -> dict:
    if not (m.under and m.P >= 3):
        return {}
    bm = float(np.mean(m.d["before_after"]))
    return {m.name: Verdict(
        "r = Psidot_n/Psidot_{n+2}, Psidot_n, Psidot_{n+2} the centre-of-mass velocity before and after a "
        "double impact, equals exp(-mu T_xi) (as printed)",
        "eq. proper-rest-coeff", f"{m.ctx}: |psi'(t_(2m+1)^-)| / psi'(t_(2m+2)^+) over the plateau",
        f"{m.d['r0']:.6f}", f"mean {bm:.6f} (= 1/{1 / bm:.6f})",
        f"same tolerance, {m.tol:.2g}", judge(abs(bm - m.d["r0"]) <= m.tol))}


@claim(CLAIMS, "ratio-after-before", BEYOND, "fig:rest-coeff",
       falsifier=Falsifier("take-off velocities after the double impacts 1 % lower per bounce (x 0.99^m)",
                           on_scenes(_takeoff_low)))
def ratio_after_before(m, spec) -> dict:
    if not (m.under and m.P >= 3):
        return {}
    am, bm = float(np.mean(m.d["after"])), float(np.mean(m.d["before_after"]))
    return {m.name: Verdict(
        "Erratum candidate: the ratio is after/before, r = Psidot_{n+2}/Psidot_n = exp(-mu T_xi)",
        "eq. proper-rest-coeff", f"{m.ctx}: psi'(t_(2m+2)^+)/psi'(t_(2m)^+) (successive take-off velocities) "
        "and psi'(t_(2m+2)^+)/|psi'(t_(2m+1)^-)| over the plateau",
        f"{m.d['r0']:.6f}", f"take-off ratio {am:.6f}; after/before {1 / bm:.6f}",
        f"same tolerance, {m.tol:.2g}", judge(abs(am - m.d["r0"]) <= m.tol and abs(1 / bm - m.d["r0"]) <= m.tol))}


def _contacts_long(ds):
    """Records whose contacts last 0.1 % longer (tau_(2m-1) x 1.001 over the double-impact regime)."""
    if "tau" in ds:
        tau = ds["tau"].values.copy()
        m = np.arange(1, min(200, (len(tau) - 1) // 2))
        tau[2 * m - 1] *= 1.001
        with_variable(ds, "tau", tau)
    return ds


@claim(CLAIMS, "contact-time", PAPER, "fig:rest-coeff",
       falsifier=Falsifier("contacts 0.1 % longer than the simulated ones (tau_(2m-1) x 1.001)",
                           on_scenes(_contacts_long)))
def contact_time(m, spec) -> dict:
    if not (m.under and m.P >= 3):
        return {}
    d = m.d
    cr, delta = d["contact_ratio"], d["delta"]
    pred = contact_prediction(d, m.xi0, m.v0)
    a = np.hypot(m.xi0, m.v0)
    off = np.abs(cr - pred)
    tol = (delta + a) ** 2
    worst = int(np.argmax(off / tol))
    return {m.name: Verdict(
        "A double impact (the contact) lasts about T_xi = pi/sqrt(1-mu^2), half the proper period",
        "eq. char-times and the discussion after it",
        f"{m.ctx}: tau_(2m-1)/T_xi for the contacts m = 1..{m.P + 1} of the plateau, against the contact of a "
        "damped spring landing at V_m under gravity, with the vibration the previous contact left at the landing "
        "(its half-extension and half-rate xi_0, xi'_0 read from the records at the landing)",
        "1 - delta_m + (2 + mu T_xi) delta_m^2 + (xi_0/V_m)(e^(mu T_xi) + 1)/T_xi + (xi'_0/V_m) e^(mu T_xi), "
        "delta_m = gamma T_xi e^(mu T_xi)/(2 V_m) (gravity), i.e. 1 as gamma -> 0",
        f"tau_c/T_xi in [{cr.min():.4f}, {cr.max():.4f}]; delta_m in [{delta.min():.2g}, {delta.max():.2g}], vibration "
        f"a_m = |(xi_0, xi'_0)|/V_m in [{a.min():.2g}, {a.max():.2g}]; |measured - predicted| up to {off.max():.2g} "
        f"(worst, contact {worst + 1}: {off[worst]:.2g} of {tol[worst]:.2g}); from 1 - delta_m alone up to "
        f"{np.max(np.abs(cr - 1.0 + delta)):.2g}",
        "|measured - predicted| <= (delta_m + a_m)^2 for every contact: the orders the prediction neglects "
        "(delta a, a^2, delta^3)", judge(bool(np.all(off <= tol))))}


def _speeds_low(ds):
    """Records whose impact speeds are 5 % low for their restitution: 1 - r = 1.05 mu u/(3 gamma) at small u."""
    if "xdot" in ds:
        with_variable(ds, "xdot", ds["xdot"].values / 1.05)
    return ds


@claim(CLAIMS, "our-r-band", PAPER, "eq:our-r",
       falsifier=Falsifier("impact speeds 5 % low for their restitution (Xdot / 1.05: the small-u branch reads "
                           "1 - 1.05 mu u/(3 gamma))", on_scenes(_speeds_low)))
def our_r_band(m, spec) -> dict:
    if not m.under:
        return {}
    o, thr, least, d = m.o, spec["our_r_threshold"], int(spec["our_r_min_outside"]), m.d
    u = o["u"]
    n_below, n_above = int(np.sum(u < o["u1"])), int(np.sum(u > o["u2"]))
    (s_lo, s_at, s_hi), (l_lo, l_hi) = m.band_small, m.band_large
    ok = bool(np.isfinite(o["u1"]) and s_lo <= o["u1"] <= s_hi and l_lo <= o["u2"] <= l_hi
              and o["u1"] < o["uc"] < o["u2"])
    # the band where the models predict it, but the run ends (or starts) inside it: a side is not sampled
    verdict = NOT_CHECKABLE if ok and min(n_below, n_above) < least else judge(ok)
    return {m.name: Verdict(
        f"Eq. our-r is accurate for large and small impact speeds (1 - r within {thr:.0%}) and fails in an "
        "intermediate band (under-damped spring)", "eq. our-r, sec. Discussion",
        f"{m.ctx}: restitution per macroscopic bounce, r = ratio of successive landing speeds u = Xdot "
        f"({d['run_len']} double-impact bounces, then every impact); band [u1, u2] = range of u where the dissipated "
        f"fraction is off, |(1 - r)/(1 - r_our) - 1| > {thr:g}; its edges against the branches' error models "
        "(module docstring (d)): u2 where the vibration left by a contact, e^(-mu f) after a flight f = 2u/gamma, "
        f"reaches {thr:g}; u1 at the first bounce whose upper-mass velocity puts the map's jerk off by {thr:g}, "
        "|ydot_n|/(4 mu gamma) > thr",
        f"u1 in [{s_lo:.3g}, {s_hi:.3g}] (|ydot_n|/(4 mu gamma) > thr -+ thr^2; > thr first at {s_at:.3g}); u2 in "
        f"[{l_lo:.3g}, {l_hi:.3g}] = gamma (ln(1/thr) -+ 1)/(2 mu); u1 < u_c < u2 (the stitching point lies in the band)",
        f"band [u1, u2] = [{o['u1']:.3g}, {o['u2']:.3g}] = [{o['u1'] / o['uc']:.3g}, {o['u2'] / o['uc']:.3g}] u_c "
        f"(u_c = {o['uc']:.3g}; {o['n_bad']} of {o['n_bounces']} bounces; simulated u in [{np.min(u):.3g}, "
        f"{np.max(u):.3g}]); max error of 1 - r above u2: {o['max_err_above']:.2g}, below u1: "
        f"{o['max_err_below']:.2g} ({n_above} bounces above u2, {n_below} below u1); judged on r itself "
        f"the band would be [{o['d1']:.3g}, {o['d2']:.3g}]",
        f"{thr:g} relative on 1 - r (the brief's 5 %, applied to the dissipated fraction: where 1 - r ~ 1e-4 a 5 % "
        "band on r would accept any law); the edges: the neglected order thr^2 of the small-u error model, a factor "
        "e of the large-u one's O(1) prefactor; edges where predicted but fewer than "
        f"{least} bounces on a side: not checkable (the run does not reach past the band)",
        verdict)}


@claim(CLAIMS, "our-r-small-u", PAPER, "eq:our-r",
       falsifier=Falsifier("impact speeds 5 % low for their restitution (Xdot / 1.05: 1 - r = 1.05 mu u/(3 gamma))",
                           on_scenes(_speeds_low)))
def our_r_small_u(m, spec) -> dict:
    if not m.under:
        return {}
    o, emax = m.o, float(spec["fit_err_max"])
    tol_x = max(3.0 * o["drift_x"], float(spec["slope_floor"]))
    return {m.name: Verdict(
        "Small-u branch of eq. our-r: 1 - r = mu u/(3 gamma) with u the lower mass's impact speed",
        "eq. our-r, eq. restituzione",
        f"{m.ctx}: limit L of (1 - r_n)/(mu u_n/(3 gamma)), r_n = Xdot_(n+1)/Xdot_n, u_n = Xdot_n, fitted like the "
        "limits of check main-theorem (corrections ln n/n, 1/n, sticky-spring terms)",
        "L = 1", f"L = {o['slope_x']:.6f} +- {o['drift_x']:.2g} (last u ~ {o['u_tail']:.2g})",
        f"|L - 1| <= {tol_x:.2g} = max(3 x fit error, {spec['slope_floor']:g}); not checkable without a fit "
        f"window of a decade after the transient or with a fit error > {emax:g}",
        judge(abs(o["slope_x"] - 1.0) <= tol_x)
        if np.isfinite(o["drift_x"]) and o["drift_x"] <= emax else NOT_CHECKABLE)}


def centre_of_mass_row(m, spec, coefficient: float, stated: str) -> dict:
    """Eq. our-r's small-u branch, 1 - r = c mu u/(3 gamma), with u the rigid ball's own speed: the centre of mass,
    which takes off at u = gamma tau_n/2 and flies 2u/gamma (eq. standard-model, the convention of the large-u
    branch).  ``coefficient`` is c of the form under test: 1 as printed, 2 for the branch rewritten in that speed
    (after an impact near equilibrium psi' = Xdot_n/2, and eq. restituzione is a map of Xdot_n)."""
    if not m.under:
        return {}
    o, emax = m.o, float(spec["fit_err_max"])
    tol_c = max(3.0 * o["drift_com"], 2.0 * float(spec["slope_floor"]))
    return {m.name: Verdict(
        f"Small-u branch of eq. our-r as a rigid-ball law: 1 - r = {coefficient:g} mu u/(3 gamma) with u the ball's "
        f"(centre-of-mass) speed, flight 2u/gamma, as for eq. standard-model and the large-u branch ({stated})",
        "eq. our-r", f"{m.ctx}: limit of (1 - r_n)/(mu u_n/(3 gamma)) with r_n = tau_(n+1)/tau_n, u_n = gamma tau_n/2",
        f"L = {coefficient:g}", f"L = {o['slope_com']:.6f} +- {o['drift_com']:.2g} (row our-r-small-u: the printed "
        "branch holds with u the lower mass's speed Xdot_n = 2 u, the variable of eq. restituzione; the stitching "
        "point u_c carries the same factor 2)",
        f"|L - {coefficient:g}| <= {tol_c:.2g} = max(3 x fit error, 2 x {spec['slope_floor']:g}) (the fit of row "
        "our-r-small-u, in this speed)",
        judge(abs(o["slope_com"] - coefficient) <= tol_c)
        if np.isfinite(o["drift_com"]) and o["drift_com"] <= 2 * emax else NOT_CHECKABLE)}


def _flights_doubled(ds):
    """Records whose flights after the double-impact regime (events >= 400) last 2 Xdot_n/gamma, twice the dimer's: the
    flights of a rigid ball at the lower mass's speed (eq. standard-model), so that gamma tau_n/2 is Xdot_n."""
    if "tau" in ds:
        tau = ds["tau"].values.copy()
        tau[400:] *= 2.0
        with_variable(ds, "tau", tau)
    return ds


@claim(CLAIMS, "our-r-centre-of-mass", ERRATUM, "eq:our-r",
       falsifier=Falsifier("single-impact flights twice the simulated ones (tau_n x 2: a rigid ball flying 2u/gamma at the lower "
                           "mass's speed, for which the printed coefficient holds)", on_scenes(_flights_doubled)),
       known_failure="eq. our-r's small-u branch 1 - mu u/(3 gamma) is the lower mass's map (u = Xdot_n, eq. "
                     "restituzione); in the rigid ball's own speed, the centre of mass's (flight 2u/gamma, as eq. "
                     "standard-model and the large-u branch), it is 1 - 2 mu u/(3 gamma)")
def our_r_centre_of_mass(m, spec) -> dict:
    return centre_of_mass_row(m, spec, 1.0, "as printed")


def _overdamped(fn):
    """``fn`` applied to the over-damped scenes only (mu^2 > 2, as measure picks them)."""
    return on_scenes(lambda ds: fn(ds) if float(ds.attrs["mu"]) ** 2 > 2.0 else ds)


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
                           _overdamped(_from_above)))
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
                           _overdamped(_overdamped_transient)))
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
                           "Xdot_n = 3 gamma/(mu n))", _overdamped(_on_asymptotic_laws)))
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


def _constant_r(ds):
    """Records of flights f_m = tau_(2m) = f_1 exp(-mu T_xi)^(m-1), m < 400: a rigid ball with a constant r."""
    if "tau" in ds and float(ds.attrs["mu"]) < 1.0:
        tau = ds["tau"].values.copy()
        mu = float(ds.attrs["mu"])
        m = np.arange(1, min(400, (len(tau) - 1) // 2 + 1))
        tau[2 * m] = tau[2] * math.exp(-mu * math.pi / math.sqrt(1.0 - mu**2)) ** (m - 1)
        with_variable(ds, "tau", tau)
    return ds


@claim(CLAIMS, "falcon-comparison", PAPER, "fig:rest-coeff",
       falsifier=Falsifier("flights of a rigid ball with constant r = exp(-mu T_xi) (f_m = f_1 r^(m-1) for the first 400 bounces)",
                           on_scenes(_constant_r)))
def falcon_comparison(m, spec) -> dict:
    if not (m.under and m.P >= 3):
        return {}
    r, P, R, k = m.d["r_all"], m.P, m.d["run_len"], float(spec["r_sigmas"])
    decline = r[P:R - 1]  # r_m, m = P+1 .. R-1: the rest of the double-impact run
    after = r[R:200]  # m = R+1 .. 200 (the figure's bounces)
    drop = m.rm - float(np.mean(decline)) if decline.size else math.nan
    turns = float(np.mean(np.diff(np.sign(np.diff(after))) != 0)) if after.size > 3 else math.nan
    spread, loss = float(np.std(after)) if after.size > 3 else math.nan, 1.0 - m.d["r0"]
    return {m.name: Verdict(
        "The simulated r_n is constant, then declines, then fluctuates without a clear pattern: the behaviour the "
        "paper finds qualitatively the same as that of the tungsten-carbide bead of Falcon et al. 1998 (their fig. 7)",
        "sec. 8.1, eq. Falcon-rest-coeff, fig. rest-coeff",
        f"{m.ctx}: r_m = f_(m+1)/f_m; the plateau m = 1..{P}, the rest of the double-impact run m = {P + 1}.."
        f"{R - 1} (mean below the plateau's), and the bounces m = {R}..{R + after.size - 1} after it (fraction of "
        "the steps at which r_m turns, the sign of r_(m+1) - r_m changing); the experiment's side of the comparison "
        "(Falcon et al., Eur. Phys. J. B 3, 45, 1998) is not available to this pipeline",
        "a plateau, then a mean below it by more than the plateau's spread, then turns at >= half the steps with a "
        "spread of at least 1 - r",
        f"plateau of {P} bounces, mean {m.rm:.5f} (std {m.rs:.2g}); decline: mean {m.rm - drop:.5f}, {drop:.2g} "
        f"below; after the run: r_m in [{np.min(after):.3g}, {np.max(after):.3g}], std {spread:.2g} (1 - r = {loss:.2g}), "
        f"turns at {turns:.2f} of the steps",
        f"decline > {k:g} x the plateau's per-bounce std (r_sigmas); 'without a clear pattern': turns at >= 1/2 of "
        "the steps (2/3 for an unordered sequence, none for a trend) with a std >= 1 - r (a fluctuation of the order of "
        "the dissipation per bounce, not rounding)", judge(bool(drop > k * m.rs and turns >= 0.5 and spread >= loss)))}


@claim(CLAIMS, "overdamped-inelastic", PAPER, "fig:very_rigid_poincare_overdamped",
       falsifier=Falsifier("the over-damped ball's first flight 3 times the simulated one (r_eff x 3: a rebound "
                           "regaining 0.14 % of the drop height)", _overdamped(_first_flight_long)))
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


def _spread(ax, u, v, color, label):
    """The median of v against u in log-spaced bins (five a decade, at least 5 bounces each) with its 25-75 % (dark)
    and 5-95 % (light) ranges: a cloud of 1e5 bounces as a line with its spread."""
    from ..figures.common import log_binned

    c, q = log_binned(u, v, lambda w: np.percentile(w, (5, 25, 50, 75, 95)), least=5)
    if not c.size:
        return
    p5, p25, p50, p75, p95 = q.T
    ax.fill_between(c, p5, p95, color=color, alpha=0.15, lw=0)
    ax.fill_between(c, p25, p75, color=color, alpha=0.35, lw=0)
    ax.plot(c, p50, "-", color=color, lw=1.2, label=label + " (median, 25-75 %, 5-95 %)")


def plot(ds: xr.Dataset, spec: dict, outputs) -> None:
    from ..figures.common import WIDTH, plt, save

    fig, axes = plt.subplots(3, 2, figsize=(WIDTH, 8.4))
    (a1, a2), (a3, a4), (a5, a6) = axes
    if "plateau_r" in ds:
        r0 = float(ds.attrs["r_theory"])
        fr = ds["falcon_r"].values
        lo, hi = 0.85, 1.06  # r_m beyond these (the pairs breaking up) drawn at the edge, clipped
        fr = fr[:80]
        mf = np.arange(1, fr.size + 1)
        a1.plot(mf, np.clip(fr, lo, hi), "k.-", ms=3, lw=0.5, label=r"$r_m=f_{m+1}/f_m$, $f_m=\tau_{2m}$")
        for edge, mark in ((lo, "v"), (hi, "^")):
            out = (fr < lo) if edge == lo else (fr > hi)
            a1.plot(mf[out], np.full(out.sum(), edge), mark, ms=4, color="C3", clip_on=False,
                    label=r"$r_m$ off the axis (clipped)" if edge == lo and out.any() else None)
        m = ds["plateau_m"].values
        a1.plot(m, ds["plateau_after"].values, "o", mfc="none", ms=4, color="C0",
                label=r"$\dot\Psi(t_{2m+2}^+)/\dot\Psi(t_{2m}^+)$")
        a1.plot(m, ds["plateau_before_after"].values, "s", mfc="none", ms=4, color="C3",
                label=r"printed: $|\dot\Psi(t_{2m+1}^-)|/\dot\Psi(t_{2m+2}^+)$")
        a1.axhline(r0, color="C2", lw=1, label=r"$e^{-\mu T_\xi}$")
        a1.axvspan(0.5, m.max() + 0.5, color="C2", alpha=0.1, label=r"plateau ($f_m\geq 2T_d$)")
        a1.set_ylim(lo, hi)
        a1.set_xlim(0, min(fr.size, 80))
        a1.set_xlabel("macroscopic bounce $m$")
        a1.set_ylabel("restitution coefficient")
        a1.set_title(r"(a) %s: $\gamma=%g$, $\mu=%g$" % (ds.attrs["rest_scene"], ds.attrs["rest_gamma"],
                                                          ds.attrs["rest_mu"]), fontsize=8)
        a1.legend(fontsize=5.5, loc="lower left", ncol=2, framealpha=0.9)
        c = ds["contact_ratio"].values
        mc = np.arange(1, c.size + 1)
        a2.plot(mc, c, "k.", ms=4, label=r"$\tau_{2m-1}/T_\xi$ (contact)")
        a2.plot(mc, 1 - ds["contact_delta"].values, "C1-", label=r"$1-\gamma T_\xi e^{\mu T_\xi}/(2V_m)$")
        a2.plot(mc, ds["contact_predicted"].values, "C0x", ms=4, label="predicted (with the vibration at landing)")
        a2.axhline(1, color="C2", lw=1, label=r"$T_\xi=\pi/\sqrt{1-\mu^2}$")
        a2.set_xlabel("double impact $m$")
        a2.set_ylabel(r"contact time / $T_\xi$")
        a2.set_title("(b) duration of the double impact", fontsize=8)
        a2.set_ylim(top=1.0025)
        a2.legend(fontsize=5, loc="upper right", ncol=2, framealpha=0.9)
        u, r, dbl = ds["bounce_u"].values, ds["bounce_r"].values, ds["bounce_double"].values.astype(bool)
        g, mu = float(ds.attrs["rest_gamma"]), float(ds.attrs["rest_mu"])
        uu = np.geomspace(u.min(), u.max(), 400)
        for ax in (a5, a6):
            ax.axvspan(ds.attrs["band_u1"], ds.attrs["band_u2"], color="r", alpha=0.1,
                       label=r"$|(1-r)/(1-r_{our})-1|>%g$" % ds.attrs["our_r_threshold"])
            for key in ("band_u1_predicted", "band_u2_predicted"):
                if np.isfinite(ds.attrs[key]):
                    ax.axvline(ds.attrs[key], color="r", ls=":", lw=0.8,
                               label="edges predicted by the error models" if key.startswith("band_u1") else None)
        _spread(a5, u[~dbl], r[~dbl], "0.3", f"{np.count_nonzero(~dbl)} single-impact bounces")
        a5.semilogx(u[dbl], r[dbl], "o", ms=3, color="C0", label="double-impact bounces")
        a5.semilogx(uu, our_r(uu, g, mu), "C3-", lw=1, label="eq. our-r")
        a5.set_xscale("log")
        a5.set_ylim(0.6, 1.2)
        a5.set_xlabel(r"impact speed $u=\dot X$ of the lower mass  [$L/\sqrt{m/2k}$]")
        a5.set_ylabel(r"restitution per bounce $r$")
        a5.set_title("(e) eq. our-r vs the dimer", fontsize=8)

        one = 1 - r
        pos = one > 0
        _spread(a6, u[pos & ~dbl], one[pos & ~dbl], "0.3", r"$u=\dot X$, $r=\dot X_{n+1}/\dot X_n$")
        a6.plot(u[pos & dbl], one[pos & dbl], "o", ms=3, color="C0")
        uc_, rc_ = ds["com_u"].values, ds["com_r"].values
        pc = rc_ < 1
        _spread(a6, uc_[pc], 1 - rc_[pc], "C1", r"$u=\gamma\tau_n/2$ (c.o.m.), $r=\tau_{n+1}/\tau_n$")
        a6.set_xscale("log")
        a6.set_yscale("log")
        a6.loglog(uu, 1 - our_r(uu, g, mu), "C3-", lw=1, label=r"eq. our-r")
        a6.loglog(uu, 1 - our_r(uu, g, mu, com=True), "C1--", lw=1, label=r"$1-2\mu u/(3\gamma)$")
        a6.set_xlabel(r"impact speed $u$  [$L/\sqrt{m/2k}$]")
        a6.set_ylabel(r"$1-r$")
        a6.set_title(r"(f) dissipation per bounce, two speed conventions", fontsize=8)
        handles = {}
        for ax in (a5, a6):  # one legend for (e) and (f), below them: their data fill the panels
            for h, lab in zip(*ax.get_legend_handles_labels()):
                handles.setdefault(lab, h)
        fig.legend(handles.values(), handles.keys(), loc="lower center", ncol=2, fontsize=5.5, frameon=False)
    if "od_n" in ds:
        n, w = ds["od_n"].values, ds["od_y_minus_yeq"].values
        g = float(ds.attrs["od_gamma"])
        a3.semilogx(n, w / g, "k.-", ms=2, lw=0.6)
        a3.axhline(0, color="C2", lw=0.8)
        a3.axvline(ds.attrs["od_n0"], color="C3", ls=":", label=r"$n_0=%d$" % ds.attrs["od_n0"])
        a3.set_xlabel("impact index $n$")
        a3.set_ylabel(r"$(y-y_{eq})/\gamma$ at impact $n$")
        a3.set_title(r"(c) %s ($\mu=%g$): spring length vs equilibrium" % (ds.attrs["od_scene"], ds.attrs["od_mu"]),
                     fontsize=7)
        a3.legend(fontsize=6)
        neg = w < 0
        a4.loglog(n[neg], -w[neg] / g, "k.-", ms=2, lw=0.6, label=r"$-(y-y_{eq})/\gamma$")
        nn = n[n > 100]
        if nn.size:
            p = 3 * (float(ds.attrs["od_mu"]) - math.sqrt(float(ds.attrs["od_mu"]) ** 2 - 2)) / 2 / float(ds.attrs["od_mu"])
            ref = -w[n > 100][0] / g * (nn / nn[0]) ** -p
            a4.loglog(nn, ref, "C1--", label=r"$\propto n^{-3\lambda/\mu}$")
        a4.set_xlabel("impact index $n$")
        a4.set_ylabel(r"$-(y-y_{eq})/\gamma$")
        a4.set_title(r"(d) monotone approach from below; $r_{eff}=%.3f$" % ds.attrs["od_r_eff"], fontsize=8)
        a4.legend(fontsize=6)
    fig.suptitle("restitution: sec. 8 and eq. our-r (units: lengths $L$, times $\\sqrt{m/2k}$)", fontsize=9)
    fig.tight_layout(rect=(0, 0.07, 1, 1))
    save(fig, outputs)


TITLE = "Restitution coefficient: r = exp(-mu T_xi), contact time, over-damped approach, eq. our-r"
CHECK = Check(NAME, measure, tuple(CLAIMS), plot, TITLE)

"""The dimer's restitution measured on an unthinned scene dataset, shared by the claim groups
``restitution``, ``overdamped`` and ``our-r`` (:mod:`bounce.checks`) and the sweep ``our-r-band``
(:mod:`bounce.sweeps.our_r_band`): the double-impact regime of fig. rest-coeff (r_m = f_{m+1}/f_m,
f_m = tau_{2m}, eq. ``Falcon-rest-coeff``) with its plateau's statistic and its later phases (:func:`plateau_statistic`,
:func:`falcon_phases`), the per-bounce restitution against eq. ``our-r`` and the band where
it fails, with its edges predicted by the two branches' error models (:func:`band_test`).

The error models (thr = ``our_r_threshold``; the band is where |(1 - r)/(1 - r_our) - 1| > thr):

* large u (eq. ``rest-coefficient-function-of-mu``) assumes the spring at rest at landing; the vibration a contact
  leaves, of the order of what it dissipates, decays over the flight f = 2u/gamma as e^{-mu f}, so its relative
  error on 1 - r is ~ e^{-mu f}: thr at u_L = gamma ln(1/thr)/(2 mu), within a factor e of the unknown O(1)
  prefactor, u2 in gamma (ln(1/thr) -+ 1)/(2 mu).  (Measured on scene rest-coeff: the vibration at the plateau's
  landings is 0.027-0.041 of the landing speed, 1 - r = 0.031; the band's upper edge gives a prefactor 1.3.)
* small u assumes the map's jerk x'''(zeta_n) = 2 mu gamma (eq. ``limitex3dot``); by eq.
  ``dimensionless-eq-motion`` x''' = (ydot - xdot)/2 + mu (yddot - xddot), and in mid-flight xdot ~ 0, so the upper
  mass's velocity ydot_n adds ydot_n/2: 1 - r = (mu u/(3 gamma))(1 + eps_n) + O(eps^2), eps_n = ydot_n/(4 mu gamma)
  (:func:`spring_error`); the branch fails from the first bounce (from below) with |eps_n| > thr, known to +- thr^2
  (the neglected order).
"""

from __future__ import annotations

import math

import numpy as np

from .fitting import fit_limit
from .theory import T_xi, contact_shortening, our_r, rest_coefficient_function_of_mu, u_c

def event_arrays(ds):
    """(tau, Xdot, xi', y - y_eq, kind) per event of a complete (unthinned) scene dataset."""
    n = ds.sizes["event"]
    if "event" in ds.coords and not np.array_equal(ds["event"].values, np.arange(n)):
        raise ValueError("restitution needs complete (unthinned) event records")
    return (ds["tau"].values, ds["xdot"].values, ds["xidot"].values, ds["y_minus_yeq"].values
            if "y_minus_yeq" in ds else 2.0 * ds["eta"].values, ds["kind"].values)

def double_impact(ds, cfg) -> dict:
    gamma, mu = float(ds.attrs["gamma"]), float(ds.attrs["mu"])
    tau, xd, xi, _, kind = event_arrays(ds)
    Txi, Td, r0 = T_xi(mu), 1.0 / mu, rest_coefficient_function_of_mu(mu)
    M = (len(tau) - 1) // 2
    m = np.arange(1, M)
    f = tau[2 * m]  # f_m = tau_{2m}
    contact = tau[2 * m - 1]  # tau_{2m-1}
    V = xd[2 * m - 2]  # landing speed Xdot_{2m-1}
    # initial run with the double-impact signature
    sig = np.abs(contact / Txi - 1.0) <= cfg["double_band"]
    run_len = int(np.argmin(sig)) if not sig.all() else sig.size
    # plateau: f_m >= plateau_flight T_d (contiguous from m = 1)
    longf = f >= cfg["plateau_flight"] * Td
    P = int(np.argmin(longf)) if not longf.all() else longf.size
    P = min(P, run_len - 1)
    mp = m[:P]
    r = f[1 : P + 1] / f[:P]  # r_m = f_{m+1}/f_m, m = 1..P
    psi_plus = lambda nn: xd[nn - 1] + xi[nn - 1]  # noqa: E731
    psi_minus = lambda nn: xi[nn - 1]  # noqa: E731
    after = psi_plus(2 * mp + 2) / psi_plus(2 * mp)  # consecutive take-off velocities
    before_after = -psi_minus(2 * mp + 1) / psi_plus(2 * mp + 2)  # printed orientation
    cr = contact[: P + 1] / Txi
    delta = contact_shortening(gamma, mu, V[: P + 1])
    return {"gamma": gamma, "mu": mu, "r0": r0, "Txi": Txi, "m": mp, "f": f, "r": r, "after": after,
            "before_after": before_after, "contact_ratio": cr, "delta": delta, "V": V[: P + 1],
            "run_len": run_len, "plateau": P, "r_all": f[1:] / f[:-1]}

#: the bounces of fig. rest-coeff's phases: r_m, m <= this, is read (the figure's drop leaves the double-impact run at
#: m ~ 57 and fluctuates over the rest)
FALCON_BOUNCES = 200


def plateau_statistic(dbl) -> dict:
    """The plateau of r_m = f_(m+1)/f_m (eq. Falcon-rest-coeff) of :func:`double_impact`: its length, mean, spread
    (ddof 1), the mean's standard error and the first-order gravity correction r mu T_xi max(delta_m) (eq.
    rest-coefficient-function-of-mu is the gamma -> 0 limit); NaN statistics below 3 bounces."""
    r, n = dbl["r"], int(dbl["plateau"])
    if n < 3:
        return {"bounces": n, "mean": math.nan, "std": math.nan, "standard_error": math.nan, "correction": math.nan}
    std = float(np.std(r, ddof=1))
    return {"bounces": n, "mean": float(np.mean(r)), "std": std, "standard_error": std / math.sqrt(n),
            "correction": dbl["r0"] * dbl["mu"] * dbl["Txi"] * float(np.max(dbl["delta"]))}


def falcon_phases(dbl, plateau_mean: float) -> dict:
    """Fig. rest-coeff's phases after the plateau (sec. 8.1: 'then r declines, and finally it begins to fluctuate
    without a clear pattern'): ``drop``, the plateau's mean minus the mean of r_m over the rest of the double-impact
    run (m = P+1..R-1; NaN if empty); over the bounces after it (m = R+1..:data:`FALCON_BOUNCES`) the fraction of the
    steps at which r_m turns (the sign of r_(m+1) - r_m changing) and the spread of r_m (NaN for fewer than 4)."""
    r, P, R = dbl["r_all"], int(dbl["plateau"]), int(dbl["run_len"])
    decline, after = r[P:R - 1], r[R:FALCON_BOUNCES]
    enough = after.size > 3
    return {"drop": plateau_mean - float(np.mean(decline)) if decline.size else math.nan,
            "turns": float(np.mean(np.diff(np.sign(np.diff(after))) != 0)) if enough else math.nan,
            "spread": float(np.std(after)) if enough else math.nan, "after": after}


def our_r_test(ds, dbl, cfg) -> dict:
    gamma, mu = dbl["gamma"], dbl["mu"]
    tau, xd, xi, _, kind = event_arrays(ds)
    R = dbl["run_len"]  # double impacts m = 1..R: impacts 1..2R
    # double-impact bounces: landing speeds Xdot_{2m-1}, m = 1..R
    ud = xd[2 * np.arange(1, R + 1) - 2]
    rd = ud[1:] / ud[:-1]
    ud = ud[:-1]
    # single-impact bounces after the run: every impact n >= 2R + 1
    us = xd[2 * R :]
    rs = us[1:] / us[:-1]
    us = us[:-1]
    u = np.concatenate([ud, us])
    r = np.concatenate([rd, rs])
    kind_b = np.concatenate([np.ones(ud.size, dtype=np.int8), np.zeros(us.size, dtype=np.int8)])
    ro = our_r(u, gamma, mu)
    # judged on the dissipated fraction 1 - r (the quantity eq. our-r models; r itself is ~1 - 1e-4 at small u,
    # where a relative error of r says nothing); the error of r itself is kept for comparison
    err = (1.0 - r) / (1.0 - ro) - 1.0
    thr = cfg["our_r_threshold"]
    bad = np.abs(err) > thr
    u1, u2 = (float(u[bad].min()), float(u[bad].max())) if bad.any() else (math.nan, math.nan)
    err_r = r / ro - 1.0
    bad_r = np.abs(err_r) > thr
    d1, d2 = (float(u[bad_r].min()), float(u[bad_r].max())) if bad_r.any() else (math.nan, math.nan)
    # small-u branch in the centre-of-mass convention: u_COM = gamma tau_n / 2 of every flight
    # small-u branch: q_x = (1 - Xdot_(n+1)/Xdot_n)/(mu Xdot_n/(3 gamma)) (the map quantity of check
    # main-theorem) and, in the centre-of-mass convention u = gamma tau_n/2, r = tau_(n+1)/tau_n,
    # q_com = (1 - r)/(mu u/(3 gamma)); limits fitted like the limits of Theorem main_thm
    t = ds["t"].values
    n = np.arange(1, len(tau) - 1)
    with np.errstate(divide="ignore", invalid="ignore"):
        q_x = (1.0 - xd[n] / xd[n - 1]) / (mu * xd[n - 1] / (3.0 * gamma))
        q_com = (1.0 - tau[n + 1] / tau[n]) / (mu * (gamma * tau[n] / 2.0) / (3.0 * gamma))
    fit = cfg["fit"]
    fx = fit_limit(n.astype(float), t[n - 1], q_x, mu, fit)
    fc = fit_limit(n.astype(float), t[n - 1], q_com / 2.0, mu, fit)
    slope_x, drift_x = fx["limit"], fx["limit_err"]
    slope_com, drift_com = 2.0 * fc["limit"], 2.0 * fc["limit_err"]
    ulast = float(xd[-2])
    # thinned copies for the figure: every double-impact bounce, every failing one, ~3000 log-spaced others
    keep = np.unique(np.concatenate([np.nonzero(kind_b == 1)[0], np.nonzero(bad)[0],
                                     np.geomspace(1, u.size, 3000).astype(np.int64) - 1]))
    ncom = np.unique(np.geomspace(2 * R + 1, len(tau) - 2, 3000).astype(np.int64))
    plot = {"u": u[keep], "r": r[keep], "kind": kind_b[keep],
            "ucom": gamma * tau[ncom] / 2.0, "rcom": tau[ncom + 1] / tau[ncom]}
    return {"plot": plot, "u": u, "r": r, "kind": kind_b, "err": err, "u1": u1, "u2": u2, "d1": d1, "d2": d2,
            "n_bad": int(bad.sum()), "n_bounces": int(u.size), "slope_com": slope_com, "slope_x": slope_x,
            "drift_com": drift_com, "drift_x": drift_x,
            "uc": u_c(gamma, mu), "u_tail": ulast,
            "max_err_above": float(np.max(np.abs(err[u > u2]))) if bad.any() and (u > u2).any() else math.nan,
            "max_err_below": float(np.max(np.abs(err[u < u1]))) if bad.any() and (u < u1).any() else math.nan}


def spring_error(ds, dbl) -> np.ndarray:
    """eps_n = ydot_n/(4 mu gamma), the small-u branch's error model (module docstring), per bounce of
    :func:`our_r_test` (its ``u``): NaN at the double-impact bounces, ydot just after impact n at the single ones."""
    R = dbl["run_len"]
    return np.concatenate([np.full(R - 1, np.nan), ds["ydot"].values[2 * R:-1] / (4.0 * dbl["mu"] * dbl["gamma"])])


def band_edges(u, spring_err, gamma: float, mu: float, thr: float) -> tuple[tuple, tuple]:
    """The band's predicted edges (module docstring): ((u1 low, u1 at thr, u1 high), (u2 low, u2 high)): the first
    bounce whose spring term |eps_n| exceeds thr -+ thr^2, and gamma (ln(1/thr) -+ 1)/(2 mu)."""
    eps = np.abs(spring_err)

    def first_above(level):
        s = eps > level
        return float(u[s].min()) if s.any() else math.inf

    ell = math.log(1.0 / thr)
    return (tuple(first_above(thr + k * thr**2) for k in (-1, 0, 1)),
            tuple(gamma * (ell + k) / (2.0 * mu) for k in (-1, 1)))


def band_test(ds, dbl, cfg) -> dict:
    """:func:`our_r_test` of the drop with its band's predicted edges (:func:`band_edges`: ``small`` = (u1 low, at
    thr, high), ``large`` = (u2 low, high)), the small-u error model per bounce (``spring_err``) and the bounces
    beyond the measured band on each side (``below`` u1, ``above`` u2)."""
    test = our_r_test(ds, dbl, cfg)
    u, spring = test["u"], spring_error(ds, dbl)
    small, large = band_edges(u, spring, dbl["gamma"], dbl["mu"], cfg["our_r_threshold"])
    return dict(test, spring_err=spring, small=small, large=large,
                below=int(np.sum(u < test["u1"])), above=int(np.sum(u > test["u2"])))

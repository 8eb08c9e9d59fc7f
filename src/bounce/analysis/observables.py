"""The measurements two wings share: the per-impact quantities of Theorem main_thm and their scaled
forms q_n (each -> 1 by the theorem), read from a trajectory or a (possibly thinned) scene dataset.

The claim group ``main-theorem`` (:mod:`bounce.checks.main_theorem`) judges their limits on the paper's
drops; the sweep ``asymptotic-atlas`` (:mod:`bounce.sweeps.asymptotic_atlas`) maps them over
(gamma, mu).  Defined here once, so that neither imports the other.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from ..kinds import IMPACT
from ..exact.events import first_events_linear
from ..model import Parameters
from .theory import contact_derivatives

QUANTITIES = ("tau", "xdot", "ratio", "xddot", "xdddot", "map")

QUANTITY_LABELS = {
    "tau": r"$n\tau_n\mu/3$",
    "xdot": r"$n\dot X_n\mu/(3\gamma)$",
    "ratio": r"$\dot X_n/(\gamma\tau_n)$",
    "xddot": r"$\ddot X_n/(-2\gamma)$",
    "xdddot": r"$\dddot X_n/(2\mu\gamma)$",
    "map": r"$\frac{\dot X_n-\dot X_{n+1}}{\dot X_n^2}\frac{3\gamma}{\mu}$",
}

QUANTITY_CLAIMS = {
    "tau": ("tau_n ~ 3/(mu n)", "Theorem main_thm"),
    "xdot": ("Xdot_n ~ 3 gamma/(mu n)", "proof of Theorem main_thm (Lemma Giorgio's)"),
    "ratio": ("Xdot_n / tau_n -> gamma", "proof of Theorem main_thm, last display"),
    "xddot": ("Xddot_n -> -2 gamma", "proof of Theorem main_thm"),
    "xdddot": ("Xdddot_n -> 2 mu gamma", "proof of Theorem main_thm, eq. limitex3dot"),
    "map": ("(Xdot_n - Xdot_{n+1})/Xdot_n^2 -> mu/(3 gamma)", "eq. restituzione (eq. mappa, alpha_n)"),
}

#: the statement of the paper each quantity's limit is (bounce.checks.base.Claim.statement): the claims that test it
#: on the drops, over the atlas and through the proof's identities share it, and the report counts it once
QUANTITY_STATEMENTS = {q: f"main_thm:{q}-limit" for q in QUANTITY_CLAIMS}


def scaled_quantities(n, tau_n, xdot_n, xdot_next, xidot_n, eta_n, gamma, mu) -> dict:
    """The six q_n (all -> 1 by the theorem) from per-impact arrays in paper indexing."""
    xdd, xddd = contact_derivatives(xidot_n, eta_n, gamma, mu)
    with np.errstate(divide="ignore", invalid="ignore"):
        return {
            "tau": n * tau_n * mu / 3.0,
            "xdot": n * xdot_n * mu / (3.0 * gamma),
            "ratio": xdot_n / (gamma * tau_n),
            "xddot": xdd / (-2.0 * gamma),
            "xdddot": xddd / (2.0 * mu * gamma),
            "map": (xdot_n - xdot_next) / xdot_n**2 * (3.0 * gamma / mu),
        }

def trajectory_series(traj) -> dict:
    """Per-impact arrays (paper indexing n = 1 .. len - 1) of a complete trajectory."""
    p = traj.params
    k = np.arange(len(traj) - 1)  # event k = impact n = k + 1; needs events k and k + 1
    impacts = (traj.kind[:-1] == IMPACT) & (traj.kind[1:] == IMPACT)
    if impacts.all():  # every event an impact (every cell of asymptotic-atlas): views, not copies of 1e6 events
        now, nxt = slice(0, k.size), slice(1, k.size + 1)
    else:
        k = k[impacts]
        now, nxt = k, k + 1
    return {
        "n": (k + 1).astype(np.float64), "t": traj.t[now], "tau": traj.tau[nxt], "xdot": traj.xdot[now],
        "xdot_next": traj.xdot[nxt], "xidot": traj.xidot[now], "eta": traj.eta[now],
        "gamma": p.gamma, "mu": p.mu,
    }

def dataset_series(ds: xr.Dataset) -> dict:
    """Per-impact arrays at the kept events of a (possibly thinned) scene dataset.

    tau_n and Xdot_{n+1} need event k + 1; when it was not kept (a gap of a thinned file), one
    event is simulated from the stored state after event k (exact: the core's own variables; all such events in one
    compiled call, :func:`bounce.exact.events.first_events_linear`).
    """
    gamma, mu = float(ds.attrs["gamma"]), float(ds.attrs["mu"])
    params = Parameters(gamma, mu)
    ev = ds["event"].values.astype(np.int64) if "event" in ds.coords else np.arange(ds.sizes["event"])
    kind = ds["kind"].values
    xdot, xidot, eta, tau, t = (ds[v].values for v in ("xdot", "xidot", "eta", "tau", "t"))
    m = len(ev)
    tau_next = np.full(m, np.nan)
    xdot_next = np.full(m, np.nan)
    impact = kind == IMPACT
    follows = np.zeros(m, dtype=bool)
    follows[:-1] = ev[1:] == ev[:-1] + 1
    kept = impact & follows
    kept[:-1] &= kind[1:] == IMPACT
    tau_next[:-1][kept[:-1]], xdot_next[:-1][kept[:-1]] = tau[1:][kept[:-1]], xdot[1:][kept[:-1]]
    # a gap of the thinned records (the last record ends the data): the next event from the stored state
    gap = impact & ~follows & (xdot > 0.0)
    gap[-1:] = False  # (an empty dataset has no last record)
    (i,) = np.nonzero(gap)
    kinds, tau_gap, xdot_gap = first_events_linear(params, xdot[i], xidot[i], eta[i])
    i = i[kinds == IMPACT]
    tau_next[i], xdot_next[i] = tau_gap[kinds == IMPACT], xdot_gap[kinds == IMPACT]
    ok = kept.copy()
    ok[i] = True
    return {
        "n": (ev[ok] + 1).astype(np.float64), "t": t[ok], "tau": tau_next[ok], "xdot": xdot[ok],
        "xdot_next": xdot_next[ok], "xidot": xidot[ok], "eta": eta[ok], "gamma": gamma, "mu": mu,
    }

def series_quantities(s: dict) -> dict:
    return scaled_quantities(s["n"], s["tau"], s["xdot"], s["xdot_next"], s["xidot"], s["eta"], s["gamma"], s["mu"])

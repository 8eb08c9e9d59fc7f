"""Anomalous contacts (paper sections 3 and 7): the experiments behind Theorem contact-non-generic and
the sticky lemmas, shared by the claims that use them.

* :func:`sample_initial`, :func:`_contact_scales`: random initial conditions over energies and dampings,
  and every impact's arrival speed compared with its flight's launch speed and with the classifier's
  rounding window (as :func:`bounce.exact.events.contact_window`): the Monte Carlo of the sweep
  ``contact-monte-carlo`` (:mod:`bounce.sweeps.contact_monte_carlo`, its own rules);
  :func:`monte_carlo_summary` reads its gathered file for the claims.
* :func:`construct_contact`: a start state that reaches a prescribed contact (sticky onset, grazing or
  a slow impact) after a time T, evolved backward in :mod:`bounce.analysis.reference` (mpmath).
* :func:`minimum_sticky_energy`: the numerical minimum of E - E_m over the anomalous states, the
  independent side of Lemma Min-sticky-energy.

Nothing here judges: the claims do.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from . import reference
from ..kinds import IMPACT
from ..exact.events import TANGENT_ACC, TANGENT_JERK, energy_excess, rounding_level
from ..exact.flight import gap
from ..model import Deviations
from ..exact.oscillator import make_oscillator
from .fitting import tail_exponent
from .theory import contact_derivatives


# --------------------------------------------------------------------------- sampling

def sample_parameters(rng, n: int, spec: dict):
    """gamma log-uniform, mu cycling through under- / critically / over-damped."""
    g_lo, g_hi = spec["gamma"]
    gamma = 10.0 ** rng.uniform(math.log10(g_lo), math.log10(g_hi), n)
    u_lo, u_hi = spec["mu_under"]
    o_lo, o_hi = spec["mu_over"]
    regime = np.arange(n) % 3
    mu = np.where(regime == 0, 10.0 ** rng.uniform(math.log10(u_lo), math.log10(u_hi), n),
                  np.where(regime == 1, 1.0, 10.0 ** rng.uniform(math.log10(o_lo), math.log10(o_hi), n)))
    return gamma, mu, regime


def sample_initial(rng, n: int, spec: dict):
    """Random states with prescribed E - E_m = gamma^2 10^U: (a, psi', eta, sqrt(2 gamma x)) = sqrt(2 dE) * unit."""
    gamma, mu, regime = sample_parameters(rng, n, spec)
    e_lo, e_hi = spec["energy_over_gamma2"]
    dE = gamma**2 * 10.0 ** rng.uniform(math.log10(e_lo), math.log10(e_hi), n)
    w = rng.normal(size=(n, 4))
    w /= np.linalg.norm(w, axis=1)[:, None]
    r = np.sqrt(2.0 * dE)
    a, psid, eta = r * w[:, 0], r * w[:, 1], r * w[:, 2]
    x = dE * w[:, 3] ** 2 / gamma  # gamma x = dE w3^2
    return gamma, mu, regime, dE, x, psid - a, a, eta


# --------------------------------------------------------------------------- Monte Carlo

@njit(cache=True)
def _contact_scales(x0, u0, a0, eta0, tau, u, a, eta, kind, gamma, mu, params, coefs, out_ref, out_margin):
    """Per impact: launch-speed ratio |Xdot_n|/v_ref and classifier margin |Xdot_n|/v_tol
    (v_tol as :func:`bounce.exact.events.contact_window`, with x'' and x''' of :func:`bounce.analysis.theory.contact_derivatives`)."""
    px, pu, pa, pe = x0, u0, a0, eta0
    launch = abs(u0)
    for n in range(tau.shape[0]):
        if kind[n] != IMPACT:
            out_ref[n] = np.nan
            out_margin[n] = np.nan
        else:
            _, _, scale, _, _, _, _, _, _ = gap(tau[n], px, pu, pa, pe, gamma, params, coefs)
            v = abs(u[n])
            ref = max(launch, v)
            out_ref[n] = v / ref if ref > 0 else np.nan
            xid_t = u[n] + a[n]  # xi'(t-) = psi'(t+)
            xidd = -(eta[n] - gamma) - 2.0 * mu * xid_t
            acc = -gamma - xidd
            jerk = xid_t + 2.0 * mu * xidd
            xn = rounding_level(scale)
            vt = max(math.sqrt(TANGENT_ACC * abs(acc) * xn), (TANGENT_JERK * abs(jerk) * xn * xn) ** (1.0 / 3.0))
            out_margin[n] = v / vt
        px, pu, pa, pe = 0.0, u[n], a[n], eta[n]
        launch = abs(u[n])


def binned_tail(hist: np.ndarray, edges: np.ndarray, k: int, edge: str = "upper") -> np.ndarray:
    """The k smallest values of a histogrammed sample, each at an edge of its bin (ranked; pooled over the
    leading axes of ``hist``).

    ``upper``: N(< edge) is then exact at every upper bin edge (the empirical CDF at the edges), for tail
    fits; ``lower``: every value is underestimated, so k / value over-estimates a count extrapolated linearly.
    """
    counts = hist.reshape(-1, hist.shape[-1]).sum(axis=0)
    at = edges[1:] if edge == "upper" else edges[:-1]
    return np.repeat(at, counts)[:k]


def binned_tail_exponent(hist: np.ndarray, edges: np.ndarray, lo: int, hi: int) -> tuple[float, float, float]:
    """N(< r) = C r^p (:func:`bounce.analysis.fitting.tail_exponent`) through the empirical CDF of a histogrammed sample at
    its upper bin edges (exact there), from the last edge with at most ``lo`` values below it to the first with at
    least ``hi``; pooled over the leading axes of ``hist``.  (p, its std. error, C); nan if fewer than two edges."""
    counts = hist.reshape(-1, hist.shape[-1]).sum(axis=0)
    below = np.cumsum(counts)[counts > 0]
    at = edges[1:][counts > 0]
    i0 = max(int(np.searchsorted(below, lo, side="right")) - 1, 0)
    i1 = min(int(np.searchsorted(below, hi)), below.size - 1)
    below, at = below[i0:i1 + 1], at[i0:i1 + 1]
    if below.size < 2:
        return math.nan, math.nan, math.nan
    ranked = np.zeros(int(below[-1]))  # rank k -> value; zeros (no CDF point there) are skipped by the fit
    ranked[below - 1] = at
    return tail_exponent(ranked, int(below[0]), int(below[-1]))


def monte_carlo_summary(ds, k: int) -> dict:
    """The Monte Carlo of the gathered sweep ``contact-monte-carlo`` (its file, read as a declared input):
    per sample gamma, mu, regime, E - E_m, event counts per kind and the smallest speed ratio and classifier
    margin; the pooled low tails of both (:func:`binned_tail`, k values) and the number of impacts."""
    return dict(
        gamma=ds["gamma"].values, mu=ds["mu"].values, regime=ds["damping_regime"].values, dE=ds["energy"].values,
        counts=ds["counts"].values, min_ratio=ds["min_ratio"].values, min_margin=ds["min_margin"].values,
        tail_ratio=binned_tail(ds["ratio_hist"].values, ds["ratio_edges"].values, k),
        tail_margin=binned_tail(ds["margin_hist"].values, ds["margin_edges"].values, k),
        tail_margin_lower=binned_tail(ds["margin_hist"].values, ds["margin_edges"].values, k, "lower"),
        **{v: ds[v].values for v in ("ratio_hist", "ratio_edges", "margin_hist", "margin_edges")},
        n_contacts=int(ds["ratio_hist"].values.sum()), seed=int(ds.attrs["seed"]), events=int(ds.attrs["events"]),
        bin_width=float(np.log10(ds["ratio_edges"].values[2] / ds["ratio_edges"].values[1])))


# --------------------------------------------------------------------------- constructions

def construct_contact(gamma, mu, a_pre, eta, v, T, n_check: int = 24):
    """A start state that reaches the contact (x = 0, xdot = -v, xi' = a_pre, eta) at t = T.

    :func:`bounce.analysis.reference.backward_contact` (mpmath; T halved until the backward flight stays
    above the floor), rounded to float64.  Returns (Deviations, T, x'' and x''' at the exact contact,
    scale of eq. (F) at T for the classifier's window).
    """
    back, T = reference.backward_contact(gamma, mu, a_pre, eta, v, T, n_check)
    start = Deviations(*back.floats())
    T = float(T)
    acc, jerk = contact_derivatives(float(a_pre), float(eta), gamma, mu)
    params, coefs = make_oscillator(mu)
    scale = gap(T, start.x, start.xdot, start.xidot, start.eta, gamma, params, coefs)[2]
    return start, T, acc, jerk, scale


# --------------------------------------------------------------------------- Lemma Min-sticky-energy

def minimum_sticky_energy(gamma: float, mu: float, n_grid: int = 301):
    """Numerical min of E - E_m over {x = xdot = 0, x'' >= 0} (variables Ydot, z = 2 eta).

    Grid over a box containing every state with E - E_m <= 4 gamma^2, then SLSQP from the best
    feasible grid point, with the simulator's energy function (:func:`bounce.exact.events.energy_excess`).
    Returns (E - E_m, Ydot, z, x'' at the minimiser, best grid value).
    """
    from scipy.optimize import minimize  # scipy.optimize takes ~0.3 s to import: loaded where it is used

    L = 4.0 * gamma  # |Ydot| <= 2 sqrt(dE) <= 4 gamma and |z| <= sqrt(8 dE) < 6 gamma for dE <= 4 gamma^2
    yd = np.linspace(-L, L, n_grid)
    z = np.linspace(-1.5 * L, 1.5 * L, n_grid)
    Y, Z = np.meshgrid(yd, z, indexing="ij")
    e = energy_excess(0.0, 0.0, 0.5 * Y, 0.5 * Z, gamma)  # the whole grid in one compiled call
    feasible = Z / 2.0 - 2.0 * gamma + mu * Y >= 0.0  # x'' >= 0
    e = np.where(feasible, e, np.inf)
    i, j = np.unravel_index(np.argmin(e), e.shape)

    def fun(v):
        return energy_excess(0.0, 0.0, 0.5 * v[0], 0.5 * v[1], gamma) / gamma**2

    res = minimize(fun, x0=[Y[i, j], Z[i, j]], method="SLSQP",
                   constraints=[{"type": "ineq", "fun": lambda v: (v[1] / 2.0 - 2.0 * gamma + mu * v[0]) / gamma}],
                   options={"ftol": 1e-15, "maxiter": 500})
    yd_min, z_min = float(res.x[0]), float(res.x[1])
    return float(res.fun) * gamma**2, yd_min, z_min, z_min / 2.0 - 2.0 * gamma + mu * yd_min, float(e[i, j])

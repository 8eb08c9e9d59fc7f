"""The paper's closed forms, once: one function per equation, named after its LaTeX label.

Every claim, study, figure and benchmark that needs one of these formulas imports it from
here; nothing else re-codes them.  Units are the paper's dimensionless ones (lengths in L,
times in sqrt(m/2k)); gamma > 0 and mu >= 0 throughout (eq. dimensionless-eq-motion).

Domains.  The spring xi'' + 2 mu xi' + xi = 0 (eq. eq-motion-psi-xi) oscillates for mu < 1 and
does not for mu >= 1.  The quantities defined by its half period (eq. char-times and what
follows from it) are continued to mu >= 1 by their limits as mu -> 1-, which are also the
physics: a compressed spring that never swings back never lifts the lower mass, so the double
impact never ends (T_xi = inf) and nothing of the centre of mass's speed is returned (r = 0,
the totally inelastic impact of the over-damped ball, sec. 8.1).  The same holds for the sticky
oscillator w'' + mu w' + w/2 = 0 (eq. y-eq-sticky) at mu >= sqrt 2.  No function here raises
for a physical mu; each docstring states its value at the ends of the domain.
"""

from __future__ import annotations

import math

import numpy as np

from ..exact.oscillator import natural_frequency

SQRT2 = math.sqrt(2.0)


# --------------------------------------------------------------------------- sec. 2: energy and equilibrium

def E_min(gamma: float) -> float:
    """E_m = -gamma^2/2, the energy of the static equilibrium (eq. ``Emin``), the minimum of E."""
    return -0.5 * gamma * gamma


def tot_mech_energy(xi, xidot, psidot, gamma, x=0.0):
    """E of eq. ``tot-mech-energy``, (psi'^2 + xi'^2 + xi^2)/2 + gamma psi, psi = x + xi (x = 0: at the floor).

    Direct evaluation: it loses digits of E - E_m to cancellation near the equilibrium (the core keeps
    E - E_m as a sum of squares, :func:`bounce.exact.events.energy_excess`); used as the independent side.
    """
    return 0.5 * xidot**2 + 0.5 * xi**2 + 0.5 * psidot**2 + gamma * (x + xi)


# --------------------------------------------------------------------------- sec. 3: sticky events

def min_sticky_energy(gamma: float, mu: float) -> float:
    """E_min of Lemma Min-sticky-energy (eq. ``min-sticky-energy``): (3 - 2 mu^2)/(2 (1 + 2 mu^2)) gamma^2.

    The lemma's bound as printed (an energy, not an excess over E_m = -gamma^2/2); valid for all mu >= 0.
    """
    return (3.0 - 2.0 * mu * mu) / (2.0 * (1.0 + 2.0 * mu * mu)) * gamma * gamma


def sticky_energy(ydot, z, gamma: float):
    """E(t_s) = Ydot_s^2/4 + z^2/8 - gamma^2/2 on x = xdot = 0, z = Y_s + 2 gamma - 1 (eq. ``sticky-energy``)."""
    return ydot**2 / 4 + z**2 / 8 - gamma**2 / 2


def ydot_min_Esticky(gamma: float, mu: float) -> tuple[float, float]:
    """(Ydot_s, z) of the minimiser in the proof of Lemma Min-sticky-energy (eq. ``ydot-min-Esticky``)."""
    d = 1.0 + 2.0 * mu * mu
    return 4.0 * gamma * mu / d, 4.0 * gamma / d


def sticky_modes(mu: float) -> tuple[str, float, float]:
    """(kind, slow decay rate lam, angular frequency omega) of w'' + mu w' + w/2 = 0 (eq. ``y-eq-sticky``).

    kind is "oscillatory" (mu < sqrt 2: lam = mu/2, omega = sqrt(2 - mu^2)/2), "critical" (mu = sqrt 2)
    or "overdamped" (lam = (mu - sqrt(mu^2 - 2))/2, the slow root, omega = 0).  All mu >= 0.
    """
    d = mu * mu - 2.0
    if d < 0.0:
        return "oscillatory", mu / 2.0, math.sqrt(-d) / 2.0
    if d == 0.0:
        return "critical", mu / 2.0, 0.0
    return "overdamped", (mu - math.sqrt(d)) / 2.0, 0.0


def sticky_fundamental(mu: float, t):
    """C, S of w'' + mu w' + w/2 = 0 (eq. ``y-eq-sticky``; C(0) = 1, C'(0) = 0; S(0) = 0, S'(0) = 1), t >= 0.

    numpy closed forms in the three regimes (all mu >= 0); accurate to a few ulps of the O(1) values
    (used for roots of O(1) functions, not for small parts).
    """
    t = np.asarray(t, dtype=float)
    lam = mu / 2.0
    disc = 0.5 - lam * lam
    e = np.exp(-lam * t)
    if disc > 0:
        w = math.sqrt(disc)
        return e * (np.cos(w * t) + lam / w * np.sin(w * t)), e * np.sin(w * t) / w
    if disc == 0:
        return e * (1.0 + lam * t), e * t
    k = math.sqrt(-disc)
    return e * (np.cosh(k * t) + lam / k * np.sinh(k * t)), e * np.sinh(k * t) / k


def sticky_onset(gamma: float, mu: float, alpha: float) -> tuple[float, float]:
    """(xi', eta) of the sticky-line state of eq. ``sticky-cond-Y`` with alpha = 4 gamma mu - Ydot_s > 0.

    x = xdot = 0, Ydot = 4 gamma mu - alpha, Y = 1 + 2 gamma - 2 mu Ydot, i.e. xi' = Ydot/2 and
    eta = xi + gamma = 2 gamma - mu Ydot (the core's deviation variables).
    """
    ydot = 4.0 * gamma * mu - alpha
    return 0.5 * ydot, 2.0 * gamma - mu * ydot


def sticky_floor_force(gamma: float, mu: float, alpha: float, t):
    """F(t) = 2 gamma (C(t) - 1) - (alpha/2) S(t) during the sticky phase from an onset with this alpha.

    Eq. ``force-on-the-floor`` with G = eta + 2 mu eta' obeying eq. ``y-eq-sticky``, G(0) = 2 gamma,
    G'(0) = -alpha/2; the phase ends at the first F = 0 with F' > 0 (eq. ``cond_di_distacco``).
    """
    C, S = sticky_fundamental(mu, t)
    return 2.0 * gamma * (C - 1.0) - 0.5 * alpha * S


def sticky_duration_infimum(mu: float) -> float:
    """pi/omega_s, omega_s = sqrt(1/2 - mu^2/4): the infimum of sticky durations (Lemma ``td-ts-bound``).

    The detach time decreases to the first zero of S as alpha -> inf; inf for mu >= sqrt 2 (S > 0 for all t:
    no detachment from a strong onset either).
    """
    return math.pi / math.sqrt(0.5 - mu * mu / 4.0) if mu < SQRT2 else math.inf


def eps_star(gamma: float, mu: float) -> tuple[float, float]:
    """(eps*, t*): alpha below which a sticky onset never detaches, and the tangency time (sec. 3, remark on
    infinitely long sticky events, before Theorem Finite-number-sticky-ev).

    eps* = 4 gamma min_{S(t) < 0} (1 - C(t))/(-S(t)) over the first three lobes of S < 0 (later lobes are
    worse: the envelope decays); eps* = 0 at mu = 0 (t* = 2 pi sqrt 2, the first tangency) and inf for
    mu >= sqrt 2 (S > 0: every onset with alpha > 0 lasts for ever).  Bounded minimisation to 1e-13 t.
    """
    if mu == 0.0:
        return 0.0, 2.0 * math.pi * SQRT2
    if mu >= SQRT2:
        return math.inf, math.nan
    from scipy.optimize import minimize_scalar  # scipy.optimize takes ~0.3 s to import: loaded where it is used

    w = math.sqrt(0.5 - mu * mu / 4.0)

    def h(t):
        C, S = sticky_fundamental(mu, t)
        return float((1.0 - C) / (-S))

    best = (math.inf, math.nan)
    for k in (1, 2, 3):
        lo, hi = (2 * k - 1) * math.pi / w, 2 * k * math.pi / w
        res = minimize_scalar(h, bounds=(lo + 1e-9 * hi, hi - 1e-9 * hi), method="bounded",
                              options={"xatol": 1e-13 * hi})
        if res.fun < best[0]:
            best = (float(res.fun), float(res.x))
    return 4.0 * gamma * best[0], best[1]


def t_c(gamma: float, mu: float, ydot0: float = -0.1) -> float:
    """Duration t_c of the eps = 0 sticky phase of eq. ``sticky-ic`` (paper: t_c = 5.23... for its figures).

    First root with F' > 0 of :func:`sticky_floor_force` (alpha = 4 gamma mu - ydot0), searched on a
    2001-point grid of each of the first five lobes of S < 0 and polished by brentq to 4 ulps; nan if the
    phase never ends (mu >= sqrt 2, or alpha below :func:`eps_star`).
    """
    from scipy.optimize import brentq  # scipy.optimize takes ~0.3 s to import: loaded where it is used

    alpha = 4.0 * gamma * mu - ydot0
    if mu >= SQRT2:
        return math.nan

    def F(t):
        return float(sticky_floor_force(gamma, mu, alpha, t))

    w = math.sqrt(0.5 - mu * mu / 4.0)
    for k in range(1, 6):
        t = np.linspace((2 * k - 1) * math.pi / w, 2 * k * math.pi / w, 2001)
        f = sticky_floor_force(gamma, mu, alpha, t)  # the grid at once: the same values as F point by point
        idx = np.flatnonzero((f[:-1] < 0) & (f[1:] >= 0))
        if idx.size:
            i = int(idx[0])
            return brentq(F, t[i], t[i + 1], xtol=1e-15, rtol=4 * np.finfo(float).eps)
    return math.nan


def sticky_dissipation(gamma: float, mu: float, ydot_s: float) -> tuple[float, float]:
    """(duration t_d - t_s, energy dissipated (mu/2) int ydot^2) of the sticky phase from the onset with Ydot_s
    (eq. ``energy-dissipation`` with xi' = ydot/2 in contact; proof of Theorem ``Finite-number-sticky-ev``).

    w = y - y_eq obeys w'' + mu w' + w/2 = 0 (eq. ``y-eq-sticky``) from w = 4 gamma - 2 mu Ydot_s, w' = Ydot_s, so
    w = w0 C + w0' S (:func:`sticky_fundamental`) and its energy e = w'^2/2 + w^2/4 has e' = -mu w'^2: exactly
    (mu/2) int_0^t_d ydot^2 = (e(0) - e(t_d))/2, the phase ending at :func:`t_c`.  The difference loses
    log10(e(0)/(e(0) - e(t_d))) digits, ~ -log10(mu t_d): relative error ~ 1e-16/(mu t_d), below 1e-13 for
    mu >= 1e-3.  (nan, nan) if the phase never ends.
    """
    t_d = t_c(gamma, mu, ydot_s)
    if not math.isfinite(t_d):
        return math.nan, math.nan
    C, S = sticky_fundamental(mu, t_d)
    w0, w0d = 4 * gamma - 2 * mu * ydot_s, ydot_s
    w, wd = w0 * C + w0d * S, -w0 * S / 2 + w0d * (C - mu * S)
    return t_d, 0.5 * ((w0d * w0d / 2 + w0 * w0 / 4) - (float(wd) ** 2 / 2 + float(w) ** 2 / 4))


def least_sticky_dissipation(gamma: float, mu: float, excess_1: float, n_alpha: int):
    """D of the proof of Theorem ``Finite-number-sticky-ev``: the least energy a finite sticky phase dissipates
    among onsets with E - E_m <= excess_1, from a grid of alpha_s = 4 gamma mu - Ydot_s in (eps*, alpha_max]
    (geometric near :func:`eps_star`, where the phases lengthen).  A grid minimum is at least the infimum, so a
    bound built on it is never looser than the proof's.

    On the sticky line E - E_m = Ydot^2/4 + (4 gamma - 2 mu Ydot)^2/8 (eq. ``sticky-energy``): a parabola in Ydot,
    so the admissible Ydot form an interval.  Returns (D, alpha at D, alpha grid, dissipation on it); nan and
    empty grids when no onset is admissible.
    """
    a2, a1, a0 = 0.25 + 0.5 * mu * mu, -2 * gamma * mu, 2 * gamma * gamma - excess_1
    disc = a1 * a1 - 4 * a2 * a0
    if disc <= 0:
        return math.nan, math.nan, np.array([]), np.array([])
    y_lo = (-a1 - math.sqrt(disc)) / (2 * a2)
    y_hi = (-a1 + math.sqrt(disc)) / (2 * a2)
    lo = max(eps_star(gamma, mu)[0], 4 * gamma * mu - y_hi, 0.0)
    hi = 4 * gamma * mu - y_lo
    alphas = lo + (hi - lo) * np.geomspace(1e-6, 1.0, n_alpha)
    diss = np.array([sticky_dissipation(gamma, mu, 4 * gamma * mu - al)[1] for al in alphas])
    k = int(np.nanargmin(diss))
    return float(diss[k]), float(alphas[k]), alphas, diss


def sticky_count_bound(gamma: float, mu: float, excess_1: float, D: float) -> float:
    """N <= 1 + (E(s_1) - E_min)/D: the proof of Theorem ``Finite-number-sticky-ev`` (no sticky onset below
    E_min, Lemma ``Min-sticky-energy``; each finite sticky event dissipates >= D); ``excess_1`` = E(s_1) - E_m."""
    return 1.0 + (excess_1 - (min_sticky_energy(gamma, mu) - E_min(gamma))) / D


def t_c_gamma_band(mu: float, lo: float, hi: float, g_range, ydot0: float = -0.1) -> tuple[float, float]:
    """gamma interval with lo <= t_c(gamma, mu) < hi (t_c increases with gamma), by brentq on :func:`t_c`;
    nan at an end whose level is outside t_c(g_range)."""
    from scipy.optimize import brentq  # scipy.optimize takes ~0.3 s to import: loaded where it is used

    def g_at(level):
        a, b = g_range
        fa, fb = t_c(a, mu, ydot0) - level, t_c(b, mu, ydot0) - level
        if fa > 0 or fb < 0:
            return math.nan
        return brentq(lambda g: t_c(g, mu, ydot0) - level, a, b, xtol=1e-14)
    return g_at(lo), g_at(hi)


# --------------------------------------------------------------------------- sec. 2 / 7: a contact's derivatives

def contact_derivatives(xidot, eta, gamma: float, mu: float):
    """(x'', x''') at x = 0 from xi' and eta = xi + gamma on the same side of the contact (eq. eq-motion-psi-xi).

    x = psi - xi, psi'' = -gamma, xi'' = -xi - 2 mu xi': x'' = -gamma - xi'' and x''' = -xi''' = xi' + 2 mu xi''.
    Just after an impact this is (Xddot_n, Xdddot_n) of the proof of Theorem main_thm; just before a
    contact it is the pair the event classifier tests (eq. swishes, eq. sticky-condition).
    """
    xidd = -(eta - gamma) - 2.0 * mu * xidot
    return -gamma - xidd, xidot + 2.0 * mu * xidd


# --------------------------------------------------------------------------- sec. 6: Theorem main_thm

def tau_asymptotic(n, mu: float):
    """tau_n ~ 3/(mu n) (Theorem ``main_thm``); inf at mu = 0 (no dissipation: no decay)."""
    with np.errstate(divide="ignore"):
        return 3.0 / (mu * np.asarray(n, dtype=float))


def restituzione(gamma: float, mu: float) -> float:
    """a = mu/(3 gamma), the constant of the map Xdot_{n+1} = Xdot_n - a Xdot_n^2 + ... (eq. ``restituzione``)."""
    return mu / (3.0 * gamma)


def limitex3dot(gamma: float, mu: float) -> tuple[float, float]:
    """(lim Xddot_n, lim Xdddot_n) = (-2 gamma, 2 mu gamma) (proof of Theorem main_thm, eq. ``limitex3dot``)."""
    return -2.0 * gamma, 2.0 * mu * gamma


def delta(gamma: float, mu: float) -> float:
    """lim Delta_n = lim (Xdot_n - Xdot_{n+1})/tau_n^2 = mu gamma/3 (eq. ``delta``)."""
    return mu * gamma / 3.0


def contact_shortening(gamma: float, mu: float, V):
    """delta = gamma T_xi e^(mu T_xi)/(2 V): the first-order relative shortening by gravity of a double impact landing
    at speed V (beyond the paper: eq. ``char-times``'s contact lasts T_xi (1 - delta) + O(delta^2)), and the
    first-order relative shift r mu T_xi delta of its restitution from eq. ``rest-coefficient-function-of-mu``
    (the gamma -> 0 limit)."""
    Txi = T_xi(mu)
    return gamma * Txi * math.exp(mu * Txi) / (2.0 * np.asarray(V, dtype=float))


def correction_exponent(mu: float) -> float:
    """Decay exponent p of n tau_n mu/3 - 1 (beyond the paper): min(1, 3 lam/mu).

    1 from the next order of eq. restituzione (ln(n)/n); 3 lam/mu from the spring's slow mode of
    eq. y-eq-sticky, e^{-lam t_n} with t_n ~ (3/mu) ln n: smaller than 1 for mu > 3/2.  1 at mu = 0.
    """
    if mu == 0.0:
        return 1.0
    _, lam, _ = sticky_modes(mu)
    return min(1.0, 3.0 * lam / mu)


def equilibrium_rates(mu: float) -> dict:
    """Decay rates in t of E - E_m, Xdot_n and the spring's amplitude (beyond the paper; Theorem
    static-equilibrium with Theorem main_thm's t_n ~ (3/mu) ln n and eq. y-eq-sticky's slow rate lam):
    {"energy": min(2 mu/3, 2 lam), "xdot": mu/3, "spring": lam}."""
    _, lam, _ = sticky_modes(mu)
    return {"energy": min(2.0 * mu / 3.0, 2.0 * lam), "xdot": mu / 3.0, "spring": lam}


def energy_prefactor(gamma: float, mu: float) -> float:
    """lim n^2 (E - E_m) = 9 gamma^2/(4 mu^2) for mu^2 < 2 (beyond the paper: E - E_m ~ Xdot_n^2/4 at an
    impact, Xdot_n ~ 3 gamma/(mu n))."""
    return 9.0 * gamma * gamma / (4.0 * mu * mu)


# --------------------------------------------------------------------------- sec. 8: restitution

def char_times(gamma: float, mu: float) -> tuple[float, float, float]:
    """(T_psi, T_xi, T_d) = (sqrt(1/(2 gamma)), pi/sqrt(1 - mu^2), 1/mu) of eq. ``char-times``.

    T_xi = inf for mu >= 1 (see :func:`T_xi`); T_d = inf at mu = 0.
    """
    return math.sqrt(0.5 / gamma), T_xi(mu), (1.0 / mu if mu > 0.0 else math.inf)


def T_xi(mu: float) -> float:
    """Half the proper period of the spring, pi/sqrt(1 - mu^2) (eq. ``char-times``), the double impact's duration.

    inf for mu >= 1: the over-damped spring never swings back, the contact never ends (the limit mu -> 1-).
    omega within 1.25 ulp for every mu < 1 (:func:`bounce.exact.oscillator.natural_frequency`, its Python body: the
    same bits, correctly rounded products and sqrt, without loading numba's kernel, ~0.6 s of CPU in a job that runs
    none, e.g. a gas sweep's gather computing mu(r)).
    """
    return math.pi / natural_frequency.py_func(mu) if mu < 1.0 else math.inf


def rest_coefficient_function_of_mu(mu: float) -> float:
    """r = exp(-mu T_xi) (eq. ``rest-coefficient-function-of-mu``): 1 at mu = 0, 0 for mu >= 1 (totally
    inelastic, sec. 8.1; the limit mu -> 1-)."""
    return math.exp(-mu * T_xi(mu)) if mu < 1.0 else 0.0


def u_c(gamma: float, mu: float) -> float:
    """Stitching speed of eq. ``our-r``: u_c = 3 gamma/mu (1 - exp(-mu T_xi)).

    -expm1 keeps the digits of 1 - r for small mu; at mu = 0 the limit 3 pi gamma (r = 1 on both
    branches there, so u_c only matters as a number); 3 gamma/mu for mu >= 1 (r = 0).
    """
    if mu == 0.0:
        return 3.0 * math.pi * gamma
    one_minus_r = -math.expm1(-mu * T_xi(mu)) if mu < 1.0 else 1.0
    return 3.0 * gamma / mu * one_minus_r


def our_r(u, gamma: float, mu: float, com: bool = False):
    """r(u) of eq. ``our-r``: exp(-mu T_xi) for u > u_c, 1 - mu u/(3 gamma) for u <= u_c (numpy, any shape).

    ``com``: the small-u branch rewritten for the centre-of-mass speed, 1 - 2 mu u/(3 gamma) (the erratum
    of eq. our-r as a rigid-ball law), stitched at its own u_c.
    """
    r0 = rest_coefficient_function_of_mu(mu)
    k = (2.0 if com else 1.0) * mu / (3.0 * gamma)
    uc = (1.0 - r0) / k if k > 0.0 else math.inf
    u = np.asarray(u, dtype=float)
    return np.where(u > uc, r0, 1.0 - k * u)


def onefifth_rest_coeff(u, U: float):
    """r(u) = 1 - (u/U)^(1/5) (eq. ``onefifth-rest-coeff``, leading order), numpy."""
    return 1.0 - (np.asarray(u, dtype=float) / U) ** 0.2


def geometric_map_collapse_time(u0: float, r: float, gamma: float) -> float:
    """Time from an impact at speed u0 to the collapse of a rigid ball with constant r (eqs.
    ``standard-model``, ``geometric-map``; flights 2 u/gamma): 2 r u0/(gamma (1 - r)); inf for r = 1."""
    return 2.0 * r * u0 / (gamma * (1.0 - r)) if r < 1.0 else math.inf


# --------------------------------------------------------------------------- Discussion: the nonlinear spring

def nonlin_equilibrium_xi(gamma: float, rho: float, a: float) -> float:
    """xi_eq = -(gamma/rho)^(1/(a+1)) (eq. ``nonlin-equilibrium-xi``): rho |xi|^(a+1) = gamma, the spring holds the ball."""
    return -((gamma / rho) ** (1.0 / (a + 1.0)))


def nonlin_energy(xi, xidot, psi, psidot, gamma: float, rho: float, a: float):
    """E of eq. ``nonlin-energy``: psi'^2/2 + xi'^2/2 + rho |xi|^(a+2)/(a+2) + gamma psi.

    Direct evaluation (the independent side of the core's cancellation-free excess, as :func:`tot_mech_energy`)."""
    return 0.5 * psidot**2 + 0.5 * xidot**2 + rho / (a + 2.0) * np.abs(xi) ** (a + 2.0) + gamma * psi


def nonlin_energy_rate(xi, xidot, mu: float, b: float):
    """dE/dt = -2 mu xi'^2 |xi|^b in flight (derived from eqs. ``nonlin-energy`` and ``eq-motion-nonlin-psi-xi``).

    dE/dt = psi' psi'' + xi' xi'' + rho xi |xi|^a xi' + gamma psi'
          = psi' (-gamma) + gamma psi' + xi' (-rho xi |xi|^a - 2 mu xi' |xi|^b) + rho xi |xi|^a xi'
          = -2 mu xi'^2 |xi|^b.
    The Discussion prints -mu xi'^2 |xi|^b (a factor 2 lost; for a = b = 0 it must reduce to eq.
    ``energy-dissipation``, -2 mu xi'^2, which the printed form does not)."""
    return -2.0 * mu * xidot**2 * np.abs(xi) ** b


def nonlin_alpha_limit(gamma: float, mu: float, rho: float, a: float, b: float) -> float:
    """alpha = lim alpha_n = mu (3 gamma)^-1 (gamma/rho)^(b/(a+1)) of the map eq. ``mappa`` (Discussion), so that
    n Xdot_n alpha -> 1 (Lemma Giorgio's); the linear spring (rho = 1, a = b = 0) gives mu/(3 gamma)."""
    return mu / (3.0 * gamma) * (gamma / rho) ** (b / (a + 1.0))


def nonlin_contact_derivatives(xi, xidot, gamma: float, mu: float, rho: float, a: float, b: float):
    """(x'', x''') at x = 0 from xi and xi' on the same side of the contact, for the power law of eq.
    ``eq-motion-nonlin-psi-xi`` (the nonlinear :func:`contact_derivatives`; just after impact n: Xddot_n, Xdddot_n).

    x = psi - xi with psi'' = -gamma, xi'' = -rho xi |xi|^a - 2 mu xi' |xi|^b:  x'' = -gamma - xi'' and
    x''' = -xi''' = rho (a+1) |xi|^a xi' + 2 mu xi'' |xi|^b + 2 mu b xi'^2 |xi|^(b-1) sgn(xi).
    At the static equilibrium (xi' = 0, rho |xi|^(a+1) = gamma) they are :func:`nonlin_contact_limits`."""
    xi, xidot = np.asarray(xi, dtype=float), np.asarray(xidot, dtype=float)
    w = np.abs(xi)
    xidd = -rho * xi * w**a - 2.0 * mu * xidot * w**b
    damping_slope = b * w ** (b - 1.0) * np.sign(xi) if b != 0.0 else 0.0
    x3 = rho * (a + 1.0) * w**a * xidot + 2.0 * mu * xidd * w**b + 2.0 * mu * xidot**2 * damping_slope
    return -gamma - xidd, x3


def nonlin_contact_limits(gamma: float, mu: float, rho: float, a: float, b: float) -> tuple[float, float]:
    """(lim Xddot_n, lim Xdddot_n) = (-2 gamma, 2 mu gamma (gamma/rho)^(b/(a+1))) (Discussion: the analogues of
    eq. ``limitex3dot``; the linear law, rho = 1, a = b = 0, gives :func:`limitex3dot`)."""
    return -2.0 * gamma, 2.0 * mu * gamma * (gamma / rho) ** (b / (a + 1.0))


def nonlin_flight_constant(gamma: float, mu: float, rho: float, a: float, b: float) -> float:
    """C of tau_n ~ C/n for the power-law spring (beyond the paper, from the Discussion's map): C = 1/(alpha gamma)
    = 3 (rho/gamma)^(b/(a+1))/mu = 3/(mu |xi_eq|^b).

    The time of flight eq. ``tau3`` with Xddot_n -> -2 gamma gives tau_n = Xdot_n/gamma + O(Xdot_n^2), and the map
    eq. ``mappa`` with alpha = :func:`nonlin_alpha_limit` gives n Xdot_n -> 1/alpha (Lemma Giorgio's); so
    n tau_n -> 1/(alpha gamma).  b = 0 (any a and rho) keeps Theorem main_thm's 3/mu."""
    return 1.0 / (gamma * nonlin_alpha_limit(gamma, mu, rho, a, b))


def nonlin_sticky_scaling(gamma: float, mu: float, rho: float, a: float, b: float) -> tuple[float, float]:
    """(mu_eff, c) such that the power-law spring's relaxation near equilibrium is eq. ``y-eq-sticky`` in the time
    c t with damping mu_eff (beyond the paper; :func:`sticky_modes` then applies).

    The Discussion's sticky equation (derived in :mod:`bounce.series.events`), xi'' = -(gamma + f(xi) + 2 mu xi'
    |xi|^b)/2, linearised at xi_eq (f(xi_eq) = -gamma, f' = rho (a+1) |xi_eq|^a) is d'' + m d' + k d = 0 with
    m = mu |xi_eq|^b, k = rho (a+1) |xi_eq|^a/2; with c = sqrt(2k) it becomes w'' + (m/c) w' + w/2 = 0.  Along
    the asymptotic map t_n ~ ln(n)/(alpha gamma), so a mode e^{-lam c t} is a correction n^(-lam c/(alpha gamma))
    (oscillatory: n^(-3/2), as for the linear spring).  Linear law (rho = 1, a = b = 0): (mu, 1)."""
    w = (gamma / rho) ** (1.0 / (a + 1.0))  # |xi_eq|
    c = math.sqrt(rho * (a + 1.0) * w**a)
    return mu * w**b / c, c


def nonlin_cycle_loss(u, mu: float, rho: float, a: float, b: float):
    """1 - r to first order in mu for one compression-expansion cycle of the power-law spring hit at speed u
    from rest at its rest length, without gravity (the Discussion's justification of eq. ``onefifth-rest-coeff``).

    Undamped, xi' = -u sqrt(1 - (|xi|/A)^(a+2)) with amplitude A = ((a+2) u^2/(2 rho))^(1/(a+2)); the
    dissipation 2 mu xi'^2 |xi|^b (:func:`nonlin_energy_rate`) over the cycle (two quarter swings) is
    Delta E = 4 mu u A^(b+1) I with I = int_0^1 z^b sqrt(1 - z^(a+2)) dz = B((b+1)/(a+2), 3/2)/(a+2), and
    r = sqrt(1 - 2 Delta E/u^2) = 1 - Delta E/u^2 + O(mu^2):  1 - r = 4 mu I A^(b+1)/u ~ u^(2(b+1)/(a+2) - 1).
    Hertz (a = b = 1/2): (u/U)^(1/5) with U = (4 rho/5)^3/(4 mu I)^5 (:func:`onefifth_U`); linear
    (a = b = 0, rho = 1): mu pi, the first order of eq. ``rest-coefficient-function-of-mu``.  By scaling, r
    depends on mu u^((2b - a)/(a+2)) rho^(-(b+1)/(a+2)) alone, so this is the exact leading term as u -> 0
    (for 2b > a) and the relative error is O(1 - r)."""
    from scipy.special import beta

    integral = beta((b + 1.0) / (a + 2.0), 1.5) / (a + 2.0)
    amplitude = ((a + 2.0) * np.asarray(u, dtype=float) ** 2 / (2.0 * rho)) ** (1.0 / (a + 2.0))
    return 4.0 * mu * integral * amplitude ** (b + 1.0) / np.asarray(u, dtype=float)


def onefifth_U(mu: float, rho: float) -> float:
    """U of eq. ``onefifth-rest-coeff`` for the Hertz spring (a = b = 1/2, gravity-free, first order in mu):
    (u/U)^(1/5) = :func:`nonlin_cycle_loss`, i.e. U = u/loss(u)^5 (independent of u)."""
    return float(1.0 / nonlin_cycle_loss(1.0, mu, rho, 0.5, 0.5) ** 5)


# --------------------------------------------------------------------------- sec. 5: no inelastic collapse

def asympt_4ord(gamma, T):
    """(Xddot_n, Xdddot_n, X^(4)_n) = (-gamma T^2/2, gamma T, -gamma), leading terms of eq. ``asympt-4ord``
    (case Xddot_inf = Xdddot_inf = 0 of a hypothetical collapse at residual time T_n = T)."""
    return -gamma * T**2 / 2, gamma * T, -gamma


def taylor_x_4ord(xddot, xdddot, x4, tau):
    """Xdot_n from x(t_{n+1}) = 0, eq. ``taylor-x-4ord`` without its O(tau^4) remainder."""
    return -(xddot / 2 * tau + xdddot / 6 * tau**2 + x4 / 24 * tau**3)


def taylor_xdot_4ord(xdot, xddot, xdddot, x4, tau):
    """Xdot_{n+1} after the impact at t_{n+1} (collision rule), eq. ``taylor-xdot-4ord`` without O(tau^4)."""
    return -xdot - xddot * tau - xdddot / 2 * tau**2 - x4 / 6 * tau**3


def strange_combination(delta, xddot, T, xdddot_zeta, xdot):
    """(T_n/Xdot_n)(Xdot_n - Xdot_{n+1})/(T_n - T_{n+1}) as eq. ``strange-combination`` writes it."""
    return 4 * delta / abs(xddot) * T / (1 + (1 - 8 / 3 * xdddot_zeta * xdot / xddot**2) ** 0.5)


def tau3bar(xddot, xdddot_zeta, xdot):
    """The second non-zero root of eq. ``x-exact-expansion``, eq. ``tau3bar``."""
    return 1.5 * abs(xddot) / xdddot_zeta * (1 + (1 - 8 / 3 * xdddot_zeta * xdot / xddot**2) ** 0.5)

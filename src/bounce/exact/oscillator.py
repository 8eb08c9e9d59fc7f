"""Fundamental solutions of the unit damped oscillator, without cancellation.

The internal mode of the ball obeys (paper, eq. ``eq-motion-psi-xi``)

    xi'' + 2 mu xi' + xi = 0,        mu >= 0,

so every free flight is a combination of the two fundamental solutions

    c(t):  c(0) = 1, c'(0) = 0        S(t):  S(0) = 0, S'(0) = 1,

with ``c' = -S`` and ``c = S' + 2 mu S``.  Late in the asymptotic regime the
flights are short (tau ~ 3/(mu n)), and what the dynamics needs is not c, S, S'
themselves but their *small parts*

    omc = 1 - c(t),   tms = t - S(t),   omsd = 1 - S'(t),

which are O(t^2), O(t^2) and O(t).  Forming them as differences of O(1) numbers
would lose all digits for t ~ 1e-6, so for ``q = rho t <= SERIES_Q`` (rho the
largest characteristic rate, ``max(1, mu + sqrt(mu^2 - 1))``) they are summed
directly from their Taylor series, whose coefficients come from the recurrence

    (k+2)(k+1) z_{k+2} = -2 mu (k+1) z_{k+1} - z_k.

Every coefficient obeys ``|z_k| <= (3k+1) rho^k / k!`` (the roots r1, r2 of
r^2 + 2 mu r + 1 have |r| <= rho), which gives a rigorous truncation rule: stop
once the tail bound is below 2^-55 of every sum; the degree this needs is
tabulated per oscillator against q, so the hot loop is a branch-free Horner sum.

For q > SERIES_Q the closed forms are used (under-, critically and over-damped),
and the small parts are *not* formed as 1 - c etc.: with strong over-damping c
stays within ~1/mu^2 of 1 long after rho t = 2 (the slow mode decays at rate
~1/(2 mu)), and 1 - c would lose a factor mu^2 (4e-4 relative at mu = 1e6).
They are written with ``expm1`` of each root and of their difference,
e.g. (over-damped, slow and fast rates ``lam_slow = 1/(mu + kappa)``,
``lam_fast = mu + kappa``, kappa = sqrt(mu^2-1))

    1 - c  = -expm1(-lam_slow t) - lam_slow e^{-lam_slow t} sh,
    1 - S' = -expm1(-lam_slow t) + lam_fast e^{-lam_slow t} sh,
    sh     = -expm1(-2 kappa t) / (2 kappa) = e^{-kappa t} sinh(kappa t)/kappa,

sums of terms whose cancellation is bounded by a factor ~2 for rho t > SERIES_Q,
so the small parts keep a few ulps relative to themselves for every mu > 1
(checked against mpmath for mu up to 1e8 in tests/exact/test_edges.py).  For mu <= 1
(rho = 1, t > 2, c decaying at rate >= mu or oscillating) 1 - c is formed by
subtraction to a few ulps of 1, which is what eq. (F) needs.  Nothing overflows
for long flights and everything is continuous across mu = 1.

An oscillator is a pair of arrays ``(params, coefs)`` made once per damping, in
compiled code, by :func:`oscillator_tables` (~16 us of CPU: the Taylor recurrence,
then the degree table, 600 grid points x 3 Horner sums of 48 terms and 600 logs);
the numba kernels take the two arrays.  Python callers use :func:`make_oscillator`
(checked, cached, read-only); compiled loops over many dampings (the contact Monte
Carlo, one damping per sample) call :func:`oscillator_tables` themselves.  The
tables are the bits of the numpy builder they replaced (tests/exact/test_oscillator_tables.py).
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from numba import njit

#: number of Taylor coefficients kept (enough for q <= SERIES_Q to 2^-54).
N_COEFS = 48
#: largest q = rho * t at which the Taylor series is used.
SERIES_Q = 2.0

# layout of the ``params`` array
P_MU, P_RHO, P_BRANCH, P_FREQ, P_LSLOW, P_LFAST, P_TSCALE = range(7)
UNDER, CRITICAL, OVER = 0.0, 1.0, 2.0


def make_oscillator(mu: float) -> tuple[np.ndarray, np.ndarray]:
    """Read-only, cached :func:`build_oscillator` (for Python callers that reuse a damping)."""
    return _cached_oscillator(float(mu))


@lru_cache(maxsize=64)
def _cached_oscillator(mu: float) -> tuple[np.ndarray, np.ndarray]:
    params, coefs = build_oscillator(mu)
    params.flags.writeable = False
    coefs.flags.writeable = False
    return params, coefs


@njit(cache=True)
def natural_frequency(mu):
    """omega = sqrt(1 - mu^2) (mu < 1) or kappa = sqrt(mu^2 - 1) (mu > 1) of eq. ``eq-motion-psi-xi``, within
    1.25 ulp: 1 - mu^2 directly for mu < 1/2 (mu^2 <= 1/4: one rounding beside 1), (1 - mu)(1 + mu) and
    (mu - 1)(mu + 1) from there (no cancellation near mu = 1).  The phase omega t of a flight of length t
    carries the frequency's error times t, ~eps t.  (The product form at mu = 1e-16 gave 1 - eps, not 1: a
    phase error of 1.5e-14 after t = 139.)"""
    if mu < 0.5:
        return math.sqrt(1.0 - mu * mu)
    if mu < 1.0:
        return math.sqrt((1.0 - mu) * (1.0 + mu))
    return math.sqrt((mu - 1.0) * (mu + 1.0))


def build_oscillator(mu: float) -> tuple[np.ndarray, np.ndarray]:
    """Coefficients of xi'' + 2 mu xi' + xi = 0 for the kernels of this module: the checked front of
    :func:`oscillator_tables` (mu a finite number >= 0, else ValueError)."""
    mu = float(mu)
    if not (mu >= 0.0 and math.isfinite(mu)):
        raise ValueError(f"mu must be a finite number >= 0, got {mu!r}")
    return oscillator_tables(mu)


@njit(cache=True)
def oscillator_tables(mu):
    """Coefficients of xi'' + 2 mu xi' + xi = 0 for the kernels of this module (mu finite, >= 0: unchecked
    here, see :func:`build_oscillator`; compiled, so that loops over many dampings build them in place).

    Returns ``(params, coefs)``: ``params`` holds mu, rho, the branch (0 under-,
    1 critically, 2 over-damped), omega = sqrt(1-mu^2) or kappa = sqrt(mu^2-1),
    the over-damped rates and the time scale sigma = 2^round(log2 rho);
    ``coefs[j, k]`` multiplies (sigma t)^k in the Taylor series of omc (j = 0),
    tms (j = 1) and omsd (j = 2); ``coefs[3, K]`` is the largest q = rho t for
    which truncating after t^K meets the tail rule (see :func:`_degree_thresholds`).
    Scaling t by a power of two is exact and keeps the coefficients ~1/k!
    (unscaled, rho^k/k! overflows for mu > 2e7).  Every operation is the IEEE operation, in the same
    order, of the numpy builder it replaces (tests/exact/test_oscillator_tables.py: the same bits).
    """
    if mu < 1.0:
        branch, freq = UNDER, natural_frequency(mu)
        rho, lslow, lfast = 1.0, mu, mu
    elif mu == 1.0:
        branch, freq = CRITICAL, 0.0
        rho, lslow, lfast = 1.0, 1.0, 1.0
    else:
        branch, freq = OVER, natural_frequency(mu)
        lfast = mu + freq
        lslow = 1.0 / lfast  # = mu - kappa, without cancellation
        rho = lfast
    log2_rho = math.log2(rho)
    if not log2_rho < 1023.5:  # rho = inf for mu > ~1.3e154: (mu - 1)(mu + 1) overflows
        raise ValueError("mu must be below ~1.3e154: the over-damped rate mu + sqrt(mu^2 - 1) overflows")
    sigma = 2.0 ** round(log2_rho)  # round: half to even, as Python's
    params = np.array([mu, rho, branch, freq, lslow, lfast, sigma])
    # Taylor coefficients of c and S in the scaled time sigma t (z_k / sigma^k)
    c = np.empty(N_COEFS + 1)
    s = np.empty(N_COEFS + 1)
    c[0], c[1] = 1.0, 0.0 / sigma
    s[0], s[1] = 0.0, 1.0 / sigma
    m = mu / sigma
    sigma2 = sigma * sigma
    for k in range(N_COEFS - 1):
        c[k + 2] = (-2.0 * m * (k + 1) * c[k + 1] - c[k] / sigma2) / ((k + 2) * (k + 1))
        s[k + 2] = (-2.0 * m * (k + 1) * s[k + 1] - s[k] / sigma2) / ((k + 2) * (k + 1))
    coefs = np.zeros((4, N_COEFS))
    for k in range(2, N_COEFS):
        coefs[0, k] = -c[k]  # 1 - c
        coefs[1, k] = -s[k]  # t - S
    for k in range(1, N_COEFS):
        coefs[2, k] = -(k + 1) * s[k + 1] * sigma  # 1 - S'  (S' = sum (k+1) s_{k+1} t^k)
    _degree_thresholds(rho, sigma, coefs)
    return params, coefs


#: the q grid of :func:`_degree_thresholds` and, per degree K = 2 .. N_COEFS - 2 (rows), the log of the
#: tail bound 2 (3K+4) q^(K+1) / (K+1)! and where it is valid (K + 1 >= 3 q): independent of mu, made once
_Q_GRID = np.geomspace(1e-14, SERIES_Q, 600)
_K_ROWS = np.arange(2, N_COEFS - 1)[:, None]
_LOG_TAIL = (np.log(2.0 * (3 * _K_ROWS + 4)) + (_K_ROWS + 1) * np.log(_Q_GRID)[None, :]
             - np.cumsum(np.log(np.arange(1, N_COEFS + 1)))[_K_ROWS])  # log((k)!) at index k-1
_TAIL_VALID = _K_ROWS + 1 >= 3.0 * _Q_GRID[None, :]
# one degree more never hurts: the bound falls with K at every q <= 2 (by a factor (3K+7)/(3K+4) q/(K+2) <= 0.65,
# far beyond rounding) and its validity only widens, so each row's first bad q is at or after the previous row's
assert np.all(np.diff(_LOG_TAIL, axis=0) < 0.0) and np.all(_TAIL_VALID[1:] >= _TAIL_VALID[:-1])
_ROOM = 2.0**-55


@njit(cache=True)
def _degree_thresholds(rho, sigma, coefs):
    """For each degree K, the largest q = rho t up to which the series may stop at t^K (into ``coefs[3]``).

    Rule: the tail after t^K, bounded by 2 (3K+4) q^(K+1) / (K+1)! (valid for
    K + 1 >= 3 q since |z_k| <= (3k+1) rho^k / k!), must stay below 2^-55 of the
    smallest of the three sums at every q' <= q of a fine logarithmic grid (the
    sums are positive and smooth on (0, SERIES_Q], and they are evaluated here
    with all N_COEFS terms, by Horner at every grid point).  A row's first bad q
    is at or after the previous row's (asserted on the tables above), so one pass
    over the grid serves every degree: ~10 us in all (600 points x 3 Horner sums
    of 48 terms, 600 logs).  The sums are a few ulps from the numpy builder's
    (pow and a BLAS product; their logs differ by < 3e-14), which changes no
    decision: every deciding comparison is > 1e-6 from a tie in the log
    (tests/exact/test_oscillator_tables.py).
    """
    q = _Q_GRID
    nq = q.size
    t = q / rho * sigma  # the scaled time of the coefficients
    a0 = np.full(nq, coefs[0, N_COEFS - 1])
    a1 = np.full(nq, coefs[1, N_COEFS - 1])
    a2 = np.full(nq, coefs[2, N_COEFS - 1])
    for k in range(N_COEFS - 2, -1, -1):
        c0, c1, c2 = coefs[0, k], coefs[1, k], coefs[2, k]
        for i in range(nq):
            ti = t[i]
            a0[i] = a0[i] * ti + c0
            a1[i] = a1[i] * ti + c1
            a2[i] = a2[i] * ti + c2
    i = 0
    log_room = _log_room(a0[0], a1[0], a2[0])
    for r in range(_LOG_TAIL.shape[0]):  # degree K = r + 2
        while i < nq and _TAIL_VALID[r, i] and _LOG_TAIL[r, i] <= log_room:
            i += 1
            if i < nq:
                log_room = _log_room(a0[i], a1[i], a2[i])
        # i: the row's first bad grid point (nq: none)
        coefs[3, r + 2] = q[nq - 1] if i == nq else (q[i - 1] if i > 0 else 0.0)
    coefs[3, N_COEFS - 1] = SERIES_Q


@njit(cache=True)
def _log_room(s0, s1, s2):
    """log(2^-55 min |s_j|), -inf when a sum is 0."""
    smallest = min(abs(s0), min(abs(s1), abs(s2)))
    return math.log(_ROOM * smallest) if smallest > 0.0 else -math.inf


@njit(cache=True, inline="always")
def _series_parts(t, rho, sigma, coefs):
    """Taylor sums of (1-c, t-S, 1-S') at t, truncated at the degree the tail rule allows
    (Horner in the exactly scaled time sigma t)."""
    q = rho * t
    K = 2
    while q > coefs[3, K]:
        K += 1
    ts = sigma * t
    omc = 0.0
    tms = 0.0
    omsd = 0.0
    for k in range(K, 0, -1):
        omc = omc * ts + coefs[0, k]
        tms = tms * ts + coefs[1, k]
        omsd = omsd * ts + coefs[2, k]
    return omc * ts, tms * ts, omsd * ts


@njit(cache=True, inline="always")
def _closed_form(t, params):
    """(1-c, t-S, 1-S', c, S, S') from the closed forms, for rho t > SERIES_Q.

    Over-damped: each small part is a sum of terms that cancel at most by a factor
    ~2 there (expm1 of each rate, no 1 - c): a few ulps relative to itself.
    Under- and critically damped (mu <= 1): by subtraction, a few ulps of 1 (all
    that eq. (F) needs, whose error is counted against the scale of its terms);
    the subtraction is kept bit for bit because the chaotic transients of the
    pipeline's scenes are reproduced to the last bit only by the same roundings.
    """
    mu = params[P_MU]
    branch = params[P_BRANCH]
    if branch == UNDER:
        w = params[P_FREQ]
        e = math.exp(-mu * t)
        sn = math.sin(w * t) / w
        cs = math.cos(w * t)
        c, S, Sd = e * (cs + mu * sn), e * sn, e * (cs - mu * sn)
        return 1.0 - c, t - S, 1.0 - Sd, c, S, Sd
    if branch == CRITICAL:
        e = math.exp(-t)
        c, S, Sd = (1.0 + t) * e, t * e, (1.0 - t) * e
        return 1.0 - c, t - S, 1.0 - Sd, c, S, Sd
    k = params[P_FREQ]
    ls = params[P_LSLOW]
    lf = params[P_LFAST]
    e1 = math.exp(-ls * t)
    decay = -math.expm1(-ls * t)  # 1 - e^{-lam_slow t}
    em = math.expm1(-2.0 * k * t)
    sh = -em / (2.0 * k)  # e^{-kt} sinh(kt)/k
    # c = e1 (lam_fast - lam_slow w)/(2 kappa), w = e^{-2 kappa t}: no cancellation
    c = e1 * (0.5 * (2.0 + em) + mu * sh)
    S = e1 * sh
    # S' = e1 (lam_fast w - lam_slow)/(2 kappa) = e1 (1 - lam_fast sh): the first form is exact
    # in sign and digits away from mu ~ 1, the second near it (kappa -> 0)
    if 2.0 * k >= 1.0:
        Sd = e1 * (lf * math.exp(-2.0 * k * t) - ls) / (2.0 * k)
    else:
        Sd = e1 * (1.0 - lf * sh)
    # 1 - c = (1 - e1) + e1 (1 - (lam_fast - lam_slow w)/(2 kappa)) = decay - lam_slow e1 sh
    # 1 - S' = (1 - e1) + e1 lam_fast sh  (both terms >= 0)
    return decay - ls * S, t - S, decay + lf * S, c, S, Sd


@njit(cache=True, inline="always")
def fundamental(t, params, coefs):
    """Return ``(omc, tms, omsd, c, S, Sd)`` at time t >= 0.

    omc = 1 - c(t), tms = t - S(t), omsd = 1 - S'(t) are accurate to a few ulps
    *relative to themselves* for every t and mu >= 0 (Taylor branch for rho t <=
    SERIES_Q, expm1 closed forms beyond); c, S, Sd = S' to a few ulps of their
    envelope e^{-lam_slow t} (relative, away from their zeros) in the closed-form
    branch, and in the Taylor branch (where they are 1 - omc, t - tms, 1 - omsd) to a
    few ulps of 1, t and 1 respectively (absolute; e.g. S(2) at mu = 1 is 4 ulps of S off).

    Inlined (numba, with its two branches) into its few callers (gap): a call that passes the two
    arrays cost as much as the evaluation (benchmarks/bench_gas.py: 18 % of the gas engine's time);
    the same operations, so the same bits.
    """
    if params[P_RHO] * t <= SERIES_Q:
        omc, tms, omsd = _series_parts(t, params[P_RHO], params[P_TSCALE], coefs)
        return omc, tms, omsd, 1.0 - omc, t - tms, 1.0 - omsd
    return _closed_form(t, params)

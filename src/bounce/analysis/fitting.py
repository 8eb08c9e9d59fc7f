"""Fitting helpers, once: limits of sequences, log-log slopes, decay rates, tail exponents, Richardson.

Used by the claims (:mod:`bounce.checks`), the studies and the figures; nothing here simulates.
Every fitter returns its estimate together with an error estimate of stated origin (the change
under a variant of the fit, or the formal least-squares error), never the estimate alone.

The limit fit (:func:`fit_limit`) is the one of Theorem main_thm's limits: q_n on a window of
log-spaced impacts, by linear least squares on the corrections the theory predicts (the next
orders of eq. restituzione: ln(n)/n, 1/n, (ln(n)/n)^2; the spring's relaxation as the sticky
oscillator of eq. y-eq-sticky, in the measured t_n), its error the largest change under the
variants (window start x3, window end /3, one map order less, one slow power more) or the formal
LSQ error if larger.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .theory import correction_exponent, sticky_modes


# --------------------------------------------------------------------------- selection

def log_select(n: np.ndarray, lo: float, hi: float, k: int) -> np.ndarray:
    """Indices of ~k samples of the sorted array n, log-spaced in [lo, hi] (found by bisection: the fits call this
    many times on runs of 1e6 impacts)."""
    if not lo <= hi:
        return np.arange(0)
    first, end = int(np.searchsorted(n, lo, side="left")), int(np.searchsorted(n, hi, side="right"))
    if end <= first:
        return np.arange(0)
    want = np.geomspace(lo, hi, k)
    pos = np.clip(np.searchsorted(n[first:end], want), 0, end - first - 1)
    return first + np.unique(pos)


def settle_index(q: np.ndarray, ref: float, threshold: float, block: int = 1 << 15) -> int:
    """First index after which |q/ref - 1| <= threshold for good (len(q) if never).  Scanned from the end in blocks
    of ``block`` samples, in place: the same numbers as on the whole array, without its temporaries (the fits call
    this on runs of 1e6 impacts: 1.9 ms, 4.2 ms on the whole array)."""
    q = np.asarray(q)
    hi = q.size
    while hi > 0:
        lo = max(hi - block, 0)
        d = q[lo:hi] / ref
        d -= 1.0
        np.abs(d, out=d)
        ok = d <= threshold  # NaN is not settled
        last_bad = ok.size - 1 - int(np.argmin(ok[::-1]))  # argmin: the first False from the end
        if not ok[last_bad]:
            return lo + last_bad + 1
        hi = lo
    return 0


def transient_length(n: np.ndarray, q: np.ndarray, threshold: float) -> float:
    """First n after which |q_n - 1| < threshold at every later sample (inf if never)."""
    i = settle_index(q, 1.0, threshold)
    return float(n[i]) if i < len(n) else math.inf


# --------------------------------------------------------------------------- least squares

def column_max_abs(a: np.ndarray) -> np.ndarray:
    """max |a| of each column (exact), reduced in column order: numpy's max over axis 0 of a row-major array of a few
    columns is ~5x slower (52 against 10 us on 2000 x 5, 350 us with a NaN; the profile fits take ~1e5 per sweep)."""
    return np.abs(a, order="F").max(axis=0)


def scaled_lstsq(a: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Coefficients and residual of min |a c - q| with the columns scaled to max 1 (conditioning)."""
    scale = column_max_abs(a)
    scale[scale == 0.0] = 1.0
    coef, *_ = np.linalg.lstsq(a / scale, q, rcond=None)
    coef = coef / scale
    return coef, q - a @ coef


def fit_loglog(x, y) -> tuple[float, float, float]:
    """Least-squares slope and intercept of log y against log x, with the slope's standard error."""
    lx, ly = np.log(np.asarray(x, float)), np.log(np.asarray(y, float))
    A = np.vstack([lx, np.ones_like(lx)]).T
    coef, res, *_ = np.linalg.lstsq(A, ly, rcond=None)
    dof = max(lx.size - 2, 1)
    sigma2 = float(res[0]) / dof if res.size else 0.0
    cov = sigma2 * np.linalg.inv(A.T @ A)
    return float(coef[0]), float(coef[1]), float(np.sqrt(cov[0, 0]))


def loglog_slope(x, y) -> float:
    """Slope of log y against log x (np.polyfit, degree 1)."""
    return float(np.polyfit(np.log(x), np.log(y), 1)[0])


def tail_exponent(tail: np.ndarray, lo: int, hi: int) -> tuple[float, float, float]:
    """Fit N(< r) = C r^p through the ranked smallest values r_(k), k = lo..hi (1-based); p, its std. error, C."""
    k = np.arange(1, tail.size + 1)
    sel = (k >= lo) & (k <= hi) & (tail > 0)
    lx, ly = np.log(tail[sel]), np.log(k[sel])
    A = np.vstack([lx, np.ones_like(lx)]).T
    coef, res, *_ = np.linalg.lstsq(A, ly, rcond=None)
    dof = max(lx.size - 2, 1)
    cov = (float(res[0]) / dof if res.size else 0.0) * np.linalg.inv(A.T @ A)
    return float(coef[0]), float(np.sqrt(cov[0, 0])), float(np.exp(coef[1]))


# --------------------------------------------------------------------------- rates and Richardson

def decade_rate(t, v, n, hi_n) -> float:
    """Decay rate of v in t (slope of log v, log-linear least squares) over the impacts hi_n/10 < n <= hi_n."""
    sel = (n > hi_n / 10.0) & (n <= hi_n) & (v > 0) & np.isfinite(v)
    if sel.sum() < 10:
        return math.nan
    return -float(np.polyfit(t[sel] - t[sel][0], np.log(v[sel]), 1)[0])


def fit_rate(t, v, n) -> tuple[float, float]:
    """Decay rate of v in t on the last decade of n, and its change from the previous decade (the error)."""
    top = float(n[-1])
    r1 = decade_rate(t, v, n, top)
    r0 = decade_rate(t, v, n, top / 10.0)
    return r1, (abs(r1 - r0) if math.isfinite(r0) else math.nan)


def richardson_derivative(f, k: int, t):
    """k-th derivative at 0 of f with f(0) = ... = f^(k-1)(0) = 0: k! f(t)/t^k at t and t/2, Richardson-extrapolated
    (first order in t removed); returns (value, |difference of the two quotients|) as its error.

    f may return mpmath numbers (the quotient is then formed in mpmath)."""
    from mpmath import mpf

    q1 = math.factorial(k) * f(t) / mpf(t) ** k
    q2 = math.factorial(k) * f(t / 2) / (mpf(t) / 2) ** k
    return 2 * q2 - q1, abs(q2 - q1)


def tail_limit(n: np.ndarray, q: np.ndarray) -> tuple[float, float]:
    """L of q_n = L + (ln n/n, 1/n, (ln n/n)^2, ln n/n^2, 1/n^2) on all of n (least squares: the expansion
    of Lemma Giorgio's with next orders, 1/x_n = a n + c ln n + d + ...); error = change of L when the
    window starts at its geometric middle."""
    def fit(sel):
        nn = n[sel]
        ln = np.log(nn)
        a = np.column_stack([np.ones_like(nn), ln / nn, 1 / nn, (ln / nn) ** 2, ln / nn**2, 1 / nn**2])
        a = a / column_max_abs(a)
        return float(np.linalg.lstsq(a, q[sel], rcond=None)[0][0])  # column 0 is all ones: L unscaled
    L = fit(np.ones_like(n, dtype=bool))
    L2 = fit(n >= np.sqrt(n[0] * n[-1]))
    return L, abs(L2 - L)


# --------------------------------------------------------------------------- limits of Theorem main_thm

def spring_columns(t, mu, slow_powers) -> list[np.ndarray]:
    """The sticky oscillator's relaxation (eq. y-eq-sticky) as fit columns in t - t[0]: e^{-lam s}(cos, sin)
    (oscillatory), (1, s) e^{-lam s} (critical), e^{-j lam s}, j = 1..slow_powers (over-damped)."""
    kind, lam, omega = sticky_modes(mu)
    s = t - t[0]
    e = np.exp(-lam * s)
    if kind == "oscillatory":
        return [e * np.cos(omega * s), e * np.sin(omega * s)]
    if kind == "critical":
        return [e, s * e]
    return [e**j for j in range(1, slow_powers + 1)]


def limit_basis(n, t, mu, map_orders=3, slow_powers=2) -> np.ndarray:
    """Columns 1, ln n/n, 1/n, (ln n/n)^2 (the first 1 + map_orders) and the spring columns."""
    ln = np.log(n)
    cols = [np.ones_like(n), ln / n, 1.0 / n, (ln / n) ** 2][: 1 + map_orders]
    return np.column_stack(cols + spring_columns(t, mu, slow_powers))


@dataclass(frozen=True)
class LimitFit:
    """One least-squares fit of :func:`limit_basis`: the limit L, its formal error, the rms residual and
    all coefficients (L first, then the map terms, then the spring terms)."""

    limit: float
    formal_err: float
    rms: float
    coef: np.ndarray


def fit_basis(n, t, q, mu, map_orders, slow_powers) -> LimitFit:
    """Least squares of q on :func:`limit_basis`, with the formal standard error of the constant term."""
    a = limit_basis(n, t, mu, map_orders, slow_powers)
    coef, resid = scaled_lstsq(a, q)
    dof = max(len(q) - a.shape[1], 1)
    s2 = float(resid @ resid) / dof
    scale = column_max_abs(a)
    scale[scale == 0.0] = 1.0
    cov = np.linalg.pinv((a / scale).T @ (a / scale)) * s2
    se = math.sqrt(max(cov[0, 0], 0.0)) / scale[0]
    return LimitFit(float(coef[0]), se, float(np.sqrt(np.mean(resid**2))), coef)


def exponent_profile(n, t, q, mu) -> float:
    """Profile fit of p in L + n^-p (a ln n + b) + sticky-spring terms (the case p_th = 1), p in [0.5, 2]."""
    from scipy.optimize import minimize_scalar  # scipy.optimize takes ~0.3 s to import: loaded where it is used

    basis = np.column_stack([np.ones_like(n), n, n] + spring_columns(t, mu, 2))  # columns 1, 2: n^-p ln n, n^-p
    ln = np.log(n)

    def rms(p):
        basis[:, 2] = n**-p
        np.multiply(basis[:, 2], ln, out=basis[:, 1])
        return float(np.sqrt(np.mean(scaled_lstsq(basis, q)[1] ** 2)))

    grid = np.geomspace(0.5, 2.0, 61)  # the profile can be multimodal: scan, then refine the best bracket
    vals = [rms(p) for p in grid]
    i = int(np.argmin(vals))
    a, b = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]
    res = minimize_scalar(rms, bounds=(a, b), method="bounded", options={"xatol": 1e-7})
    return float(res.x) if res.fun <= vals[i] else float(grid[i])


def fit_limit(n, t, q, mu, fit: dict) -> dict:
    """Fitted limit L +- err of q_n, the fit window, and the fitted decay exponent +- err.

    ``fit``: n_min (first impact of a window), settle (and not before q_n stays within this fraction of
    its last value), min_span (a window covers at least this ratio), points (log-spaced impacts per fit),
    map_orders, slow_powers (see :func:`limit_basis`).  The decay exponent p of q_n - L: for
    p_th = 1 (mu <= 3/2) a profile fit (:func:`exponent_profile`), its error the change under window
    start x3 / end /3; for p_th = 3 lam/mu < 1 the local log-log slope of q_n - L minus the fitted map
    terms on the last decade, its error the change from the previous decade (the n^-2p admixture) plus
    the effect of L's error.  (A free-p profile fit is multimodal there: n^-p, n^-2p and the constant are
    nearly collinear for p ~ 0.06.)
    """
    out = {"limit": math.nan, "limit_err": math.nan, "rms": math.nan, "n_lo": math.nan, "n_hi": math.nan,
           "exponent": math.nan, "exponent_err": math.nan, "exponent_theory": correction_exponent(mu)}
    good = np.isfinite(q) & np.isfinite(t)
    if not good.all():
        n, t, q = n[good], t[good], q[good]
    if n.size < 20:
        return out
    i_settle = settle_index(q, q[-1], fit["settle"])
    if i_settle >= n.size:
        return out
    lo, hi = max(float(fit["n_min"]), float(n[i_settle])), float(n[-1])
    out.update(n_lo=lo, n_hi=hi)
    if hi / lo < fit["min_span"]:
        return out
    k = int(fit["points"])
    mo, sp = int(fit["map_orders"]), int(fit["slow_powers"])

    def one(lo_, hi_, mo_, sp_) -> LimitFit | None:
        s = log_select(n, lo_, hi_, k)
        return fit_basis(n[s], t[s], q[s], mu, mo_, sp_) if s.size > 3 * (mo_ + sp_ + 3) else None

    main = one(lo, hi, mo, sp)
    if main is None:
        L, se, rms, coef_map = math.nan, math.nan, math.nan, np.full(mo, np.nan)
    else:
        L, se, rms, coef_map = main.limit, main.formal_err, main.rms, np.array(main.coef[1 : 1 + mo])
    variants = [one(3 * lo, hi, mo, sp), one(lo, hi / 3, mo, sp), one(lo, hi, mo - 1, sp)]
    if sticky_modes(mu)[0] == "overdamped":
        variants.append(one(lo, hi, mo, sp + 1))
    spread = [abs(v.limit - L) for v in variants if v is not None and math.isfinite(v.limit)]
    err = max(spread + [se])
    out.update(limit=L, limit_err=err, rms=rms)

    p_th = correction_exponent(mu)
    if p_th < 1.0:
        def local(lo_, hi_):
            s = log_select(n, lo_, hi_, k)
            ln = np.log(n[s])
            map_part = np.column_stack([ln / n[s], 1.0 / n[s], (ln / n[s]) ** 2][:mo]) @ coef_map
            d = np.abs(q[s] - L - map_part)  # the spring part of the correction
            if s.size < 10 or np.any(d <= 0):
                return math.nan
            return -float(np.polyfit(np.log(n[s]), np.log(d), 1)[0])

        w = min(10.0, math.sqrt(hi / lo))  # a decade, or half the window if it is shorter than two
        p = local(hi / w, hi)
        p0 = local(hi / w**2, hi / w)
        s = log_select(n, hi / w, hi, k)
        dL = float(np.max(err / np.abs(q[s] - L))) if s.size else math.nan  # relative shift of |q - L| by err
        drift = abs(p - p0) if math.isfinite(p0) else math.nan
        out.update(exponent=p, exponent_err=(drift + dL / math.log(10.0)) if math.isfinite(drift) else math.nan)
        return out

    def expo(lo_, hi_):
        s = log_select(n, lo_, hi_, k)
        return exponent_profile(n[s], t[s], q[s], mu) if s.size > 30 else math.nan

    p = expo(lo, hi)
    pv = [expo(3 * lo, hi), expo(lo, hi / 3)]
    pv = [abs(v - p) for v in pv if math.isfinite(v)]
    out.update(exponent=p, exponent_err=max(pv) if pv else math.nan)
    return out


# --------------------------------------------------------------------------- limits of the map eq. mappa (Richardson)

def richardson_ln(n: np.ndarray, q: np.ndarray, n_top: float | None = None) -> tuple[float, float]:
    """Richardson extrapolation of q_n = L + (c ln n + d)/n + O(ln^2 n/n^2) (Lemma Giorgio's expansion of the map
    eq. mappa) from q at m, 2m, 4m with 4m = n_top (default: the last n): R = 4 q_4m - 4 q_2m + q_m cancels the
    ln n/n and 1/n terms exactly (one ratio-2 step leaves c ln 2/n, a second removes it).

    q at the three points is linear interpolation in ln n (thinned records; the interpolation error,
    ~(dq/d ln n) (delta ln n)^2/8, is far below the remainder for log-spaced samples of ~1e3 per decade).
    Error = |R(n_top) - R(n_top/2)|: the change of the extrapolation when every point moves by a factor 2,
    which bounds the O(ln^2 n/n^2) remainder (it halves roughly 4x per step); nan if n does not reach n_top/8."""
    top = float(n[-1]) if n_top is None else float(n_top)

    log_n = np.log(n)

    def at(m):
        if m / 4.0 < n[0]:
            return math.nan
        lq = np.interp(np.log([m / 4.0, m / 2.0, m]), log_n, q)
        return float(4.0 * lq[2] - 4.0 * lq[1] + lq[0])

    r1, r0 = at(top), at(top / 2.0)
    return r1, abs(r1 - r0)


def correction_decay(n: np.ndarray, q: np.ndarray, extra: np.ndarray | None = None) -> tuple[float, float, float]:
    """Decay exponent p of the correction in q_n = L + n^-p (c ln n + d) (Lemma Giorgio's: p = 1), by a profile
    least-squares fit over p in [0.25, 4] (scan, then bounded refinement); ``extra``: further known columns (rows
    aligned with n), e.g. the spring's relaxation (:func:`spring_columns`), fitted along.  Returns (p, its error, L): the error is
    the larger change of p when the window starts at its geometric middle or ends at the geometric middle of its
    upper half (a remainder of the next order moves p; a pure law does not)."""
    from scipy.optimize import minimize_scalar  # scipy.optimize takes ~0.3 s to import: loaded where it is used

    def profile(sel):
        nn, qq = n[sel], q[sel]
        more = [] if extra is None else list(np.asarray(extra)[sel].T)
        if nn.size < 10 + len(more):
            return math.nan, math.nan
        basis = np.column_stack([np.ones_like(nn), nn, nn] + more)  # columns 1, 2: n^-p ln n, n^-p
        ln = np.log(nn)

        def fit(p):
            basis[:, 2] = nn**-p
            np.multiply(basis[:, 2], ln, out=basis[:, 1])
            return scaled_lstsq(basis, qq)

        def rms(p):
            return float(np.sqrt(np.mean(fit(p)[1] ** 2)))

        grid = np.geomspace(0.25, 4.0, 81)
        vals = [rms(p) for p in grid]
        i = int(np.argmin(vals))
        res = minimize_scalar(rms, bounds=(grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]), method="bounded",
                              options={"xatol": 1e-8})
        p = float(res.x) if res.fun <= vals[i] else float(grid[i])
        return p, float(fit(p)[0][0])

    lo, hi = float(n[0]), float(n[-1])
    p, L = profile(np.ones(n.size, dtype=bool))
    mid = math.sqrt(lo * hi)
    variants = [profile(n >= mid)[0], profile(n <= math.sqrt(mid * hi))[0]]
    err = max((abs(v - p) for v in variants if math.isfinite(v)), default=math.nan)
    return p, err, L


def limit_with_error(n: np.ndarray, q: np.ndarray) -> tuple[float, float]:
    """(L, err): the Richardson limit of q_n (:func:`richardson_ln`: ln n/n and 1/n cancelled), err the larger of its
    change when its points move by a factor 2 and its distance to the independent least-squares tail fit
    (:func:`tail_limit`)."""
    L, change = richardson_ln(n, q)
    return L, max(change, abs(L - tail_limit(n, q)[0]))

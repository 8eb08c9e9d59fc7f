"""Predictability horizon of the exact solver: float64 (bounce) against higher precision.

The same drop is computed by bounce (float64), by the one high-precision reference
:mod:`bounce.analysis.reference` at ``dps`` decimal digits (the yardstick) and at ``dps_low`` digits (a
self-check: :func:`bounce.analysis.reference.impacts_at`), and in ``longdouble``: numpy's ``np.longdouble``,
which on x86_64 Linux is the x87 80-bit extended format (64-bit significand, eps = 2^-63 = 1.08e-19,
~19 significant digits; stored in 16 bytes, hence numpy's name float128 -- it is *not* IEEE quadruple
precision).  The long-double run (:func:`longdouble_trajectory`) is a precision under test, like
float64, not a reference: about 20x faster than mpmath, it carries the long runs.

Long-double flight (:func:`flight`).  Free flight (eq. ``eq-motion-psi-xi``): psi'' = -gamma,
xi'' + 2 mu xi' + xi = 0, x = psi - xi.  With the fundamental solutions c, S
(c(0) = 1, c'(0) = 0; S(0) = 0, S'(0) = 1) of the spring and its start state
(x0, u = xdot, a = xi', eta = xi + gamma),

    x(t) = x0 + u t + a (t - S) - gamma (t^2/2 + 1 - c) + eta (1 - c),

with the small parts 1 - c, t - S, 1 - S' summed from their Taylor series for
rho t <= 1 (rho the largest characteristic rate; the series is cut where the
term falls below the long-double epsilon) and from the under-, critically or
over-damped closed forms otherwise.  Impact (eq. ``collision-rule``): psi' and
xi' are exchanged.  Root search: safe steps from the lower bound
x(t + s) >= x(t) + x'(t) s - B s^2/2, where B = gamma + sup|xi''| is bounded by the
closed-form amplitude envelope of xi'' (a solution of the same equation), so no
step can cross the floor; the march converges quadratically at a transversal
root, and two Newton steps polish it to the working precision.  Tangential
contacts (x' = 0 at the root, within the working precision) end the run
(:class:`Tangency`); the three drops below have impacts only.

What is measured (:func:`horizon_dataset`).  For each regime the impact times
t_n and rebound speeds Xdot_n of float64, of longdouble, and of mpmath at
``dps_low`` digits are compared with mpmath at ``dps`` digits; the relative error
of t_n against n (and against t) grows like e^{lambda n} in a chaotic transient.
The horizon H(tol) is the first impact whose time differs by more than ``tol``
relative; lambda_n and lambda_t are least-squares slopes of ln(error) against n
and t over the band ``fit_band`` of errors.  Consistency check: the horizon
should move out by ~ln(eps_64/eps_low)/lambda_n impacts from float64 to the
lower-precision reference.

Beyond the horizon the individual impacts are not computable in float64, but
statistics of the late regime are: n Xdot_n mu/(3 gamma) (Theorem main_thm) and
E - E_m at fixed n are compared across float64 and longdouble runs of ``n_long``
impacts.
"""

from __future__ import annotations

import math
import time

import numpy as np
import xarray as xr

from .base import Study

EPS64 = 2.0**-52


class Tangency(RuntimeError):
    """A contact with x' = 0 within the working precision (grazing / sticky): not handled here."""


# --------------------------------------------------------------------------- long-double arithmetic


class _LD:
    """np.longdouble arithmetic with floating-point errors raised (underflow aside)."""

    name = "longdouble"

    def __init__(self):
        self.eps = np.longdouble(np.finfo(np.longdouble).eps)

    def __enter__(self):
        self._err = np.seterr(all="raise", under="ignore")
        return self

    def __exit__(self, *exc):
        np.seterr(**self._err)
        return False

    num = staticmethod(np.longdouble)
    exp = staticmethod(np.exp)
    sin = staticmethod(np.sin)
    cos = staticmethod(np.cos)
    sqrt = staticmethod(np.sqrt)
    expm1 = staticmethod(np.expm1)


# --------------------------------------------------------------------------- the spring


class Spring:
    """xi'' + 2 mu xi' + xi = 0 in long double: small parts, closed forms, envelopes."""

    def __init__(self, B, mu: float):
        self.B = B
        one = B.num(1)
        self.mu = B.num(mu)
        mu_ = self.mu
        if mu < 1.0:
            self.branch = 0
            self.w = B.sqrt((one - mu_) * (one + mu_))
            self.rho = one
        elif mu == 1.0:
            self.branch = 1
            self.rho = one
        else:
            self.branch = 2
            self.kappa = B.sqrt((mu_ - one) * (mu_ + one))
            self.r_fast = -(mu_ + self.kappa)
            self.r_slow = -one / (mu_ + self.kappa)  # = -mu + kappa without cancellation
            self.rho = mu_ + self.kappa
        # Taylor coefficients of c and S: (k+2)(k+1) z_{k+2} = -2 mu (k+1) z_{k+1} - z_k
        n = 160
        c = [one, B.num(0)]
        s = [B.num(0), one]
        for k in range(n):
            for z in (c, s):
                z.append((-2 * mu_ * (k + 1) * z[k + 1] - z[k]) / ((k + 2) * (k + 1)))
        self.omc = [-ck for ck in c]  # coefficients of 1 - c from k = 2
        self.tms = [-sk for sk in s]  # of t - S from k = 2
        self.omsd = [-(k + 1) * s[k + 1] for k in range(n)]  # of 1 - S' from k = 1

    def parts(self, t):
        """(omc, tms, omsd, c, S, Sd) at t >= 0: 1 - c, t - S, 1 - S' and c, S, S'."""
        B = self.B
        one = B.num(1)
        if self.rho * t <= 1:
            omc = tms = omsd = B.num(0)
            p = t  # t^k
            omsd += self.omsd[1] * p
            for k in range(2, len(self.omc) - 1):
                p = p * t
                a, b, d = self.omc[k] * p, self.tms[k] * p, self.omsd[k] * p
                omc += a
                tms += b
                omsd += d
                if k > 4 and abs(a) + abs(b) + abs(d) <= B.eps * 1e-3 * (abs(omc) + abs(tms) + abs(omsd)):
                    break
            return omc, tms, omsd, one - omc, t - tms, one - omsd
        if self.branch == 0:
            e = B.exp(-self.mu * t)
            sn, cs = B.sin(self.w * t), B.cos(self.w * t)
            c = e * (cs + self.mu * sn / self.w)
            S = e * sn / self.w
            Sd = e * (cs - self.mu * sn / self.w)
        elif self.branch == 1:
            e = B.exp(-t)
            c, S, Sd = (one + t) * e, t * e, (one - t) * e
        else:
            e1, e2 = B.exp(self.r_slow * t), B.exp(self.r_fast * t)
            d = self.r_slow - self.r_fast
            S = (e1 - e2) / d
            Sd = (self.r_slow * e1 - self.r_fast * e2) / d
            c = Sd + 2 * self.mu * S
        return one - c, t - S, one - Sd, c, S, Sd

    def envelope(self, z0, z1):
        """An upper bound of sup_{t >= 0} |z(t)| for the solution with z(0) = z0, z'(0) = z1."""
        B = self.B
        if self.branch == 0:
            q = (z1 + self.mu * z0) / self.w
            return B.sqrt(z0 * z0 + q * q)
        if self.branch == 1:
            return abs(z0) + abs(z1 + z0) * B.exp(B.num(-1))
        d = self.r_slow - self.r_fast
        A = (z1 - self.r_fast * z0) / d
        C = (self.r_slow * z0 - z1) / d
        return abs(A) + abs(C)


# --------------------------------------------------------------------------- flights


def _safe_step(x, v, Bd, B):
    """Smallest positive root of x + v s - Bd s^2/2."""
    disc = B.sqrt(v * v + 2 * Bd * x)
    if v < 0:
        return 2 * x / (disc - v)
    return (v + disc) / Bd


def flight(B, spring: Spring, gamma, x0, u, a, eta, max_steps: int = 200_000):
    """First impact of the flight from (x0, u, a, eta): (tau, xdot_after, xidot_after, eta_after)."""
    mu = spring.mu
    xi0 = eta - gamma
    z2 = -xi0 - 2 * mu * a  # xi''(0)
    z3 = -a - 2 * mu * z2  # xi'''(0)
    Bd = (gamma + spring.envelope(z2, z3)) * (1 + B.num(2) ** -20)

    def at(t):
        omc, tms, omsd, c, S, Sd = spring.parts(t)
        x = x0 + u * t + a * tms - gamma * (t * t / 2 + omc) + eta * omc
        v = u + a * omsd - gamma * (t + S) + eta * S
        scale = abs(x0) + abs(u) * t + abs(a * tms) + gamma * (t * t / 2 + abs(omc)) + abs(eta * omc)
        return x, v, scale, omc, S, Sd

    if not (x0 > 0 or (x0 == 0 and u > 0)):
        raise Tangency("flight must start above the floor or moving up")
    t = B.num(0)
    x, v = x0, u
    tol = 64 * B.eps
    for _ in range(max_steps):
        t = t + _safe_step(x, v, Bd, B)
        x, v, scale, omc, S, Sd = at(t)
        if x <= tol * scale:
            break
    else:
        raise RuntimeError("safe march did not reach the floor")
    if x < -tol * scale * 1e6:
        raise RuntimeError("safe step crossed the floor (bound violated)")
    for _ in range(3):
        if not v < 0:
            raise Tangency(f"tangential contact at t = {float(t)!r}")
        dt = -x / v
        t = t + dt
        x, v, scale, omc, S, Sd = at(t)
        if abs(dt) <= B.eps * t:
            break
    if not -v > 4096 * B.eps * (abs(u) + gamma * t + abs(a) + abs(eta)):
        raise Tangency(f"contact speed {float(v)!r} at the working precision")
    psid = u + a - gamma * t  # psi'(tau^-)
    eta_t = eta + (gamma - eta) * omc + a * S  # xi(tau) + gamma
    return t, -v, psid, eta_t  # after the impact: xdot = -x'(tau), xi' = psi'(tau^-), psi' = xi'(tau^-)


def longdouble_trajectory(gamma: float, mu: float, start, n: int) -> dict:
    """Impacts of the exact dynamics in long double from the float64 state ``start`` (a
    :class:`bounce.model.Deviations`, converted exactly).  Returns longdouble arrays t, xdot, xidot, eta,
    ``n`` reached, why it stopped, eps and the CPU seconds."""
    B = _LD()
    out = {"t": [], "xdot": [], "xidot": [], "eta": []}
    stop = "max_events"
    t0 = time.process_time()
    with B:
        g = B.num(gamma)
        spring = Spring(B, mu)
        x, u, a, eta = (B.num(float(v)) for v in (start.x, start.xdot, start.xidot, start.eta))
        t = B.num(0)
        for _ in range(int(n)):
            try:
                tau, u, a, eta = flight(B, spring, g, x, u, a, eta)
            except Tangency:
                stop = "tangency"
                break
            x = B.num(0)
            t = t + tau
            for key, v in zip(out, (t, u, a, eta)):
                out[key].append(v)
    res = {k: np.array(v, dtype=np.longdouble) for k, v in out.items()}
    res.update(n=len(out["t"]), stop=stop, eps=float(B.eps), cpu=time.process_time() - t0)
    return res


def reference_trajectory(gamma: float, mu: float, start, n: int, dps: int) -> dict:
    """Impacts of :mod:`bounce.analysis.reference` at ``dps`` digits from the float64 state ``start`` (converted
    exactly): object arrays of mpf t, xdot, xidot, eta, ``n`` reached, why it stopped, eps and CPU seconds."""
    from ..analysis.reference import Dev, impacts_at

    run = impacts_at(gamma, mu, Dev(start.x, start.xdot, start.xidot, start.eta), n, dps)
    res = {k: np.array(run[k], dtype=object) for k in ("t", "xdot", "xidot", "eta")}
    res.update(n=run["n"], stop=run["stop"], eps=float(run["eps"]), cpu=run["cpu"])
    return res


def _to_mpf(v):
    """Exact conversion of a float64, longdouble or mpf to mpf."""
    import mpmath

    if isinstance(v, mpmath.mpf):
        return v
    if isinstance(v, np.longdouble):
        num, den = v.as_integer_ratio()  # exact: den is a power of two
        return mpmath.mpf(num) / den
    return mpmath.mpf(float(v))


def rel_diff(a, ref) -> np.ndarray:
    """|a - ref|/|ref| elementwise, formed exactly at 80 digits, as float64 (ref: the mp reference)."""
    import mpmath

    with mpmath.workdps(80):
        return np.array([float(abs(_to_mpf(x) - _to_mpf(r)) / abs(_to_mpf(r))) for x, r in zip(a, ref)])


def horizon_index(err, tol: float) -> int:
    """Number of leading impacts with relative error <= tol."""
    bad = np.flatnonzero(~(np.asarray(err) <= tol))
    return int(bad[0]) if bad.size else len(err)


#: relative error of the dps_low self-check up to which the yardstick is trusted (its own error is then
#: <= 10^-(dps - dps_low) of it: 1e-14 for dps - dps_low = 10)
YARDSTICK_TRUSTED = 1e-4


def yardstick_reach(t_low, t_ref, n: int) -> int:
    """Impacts over which the ``dps``-digit yardstick is exact for this study: the self-check (``dps_low`` digits)
    stays within :data:`YARDSTICK_TRUSTED` of it, plus the first impact beyond (at most ``n``).

    Errors scale with the working precision (the consistency check of the module docstring), so the yardstick's
    own error is ~10^-(dps - dps_low) times the self-check's: <= 1e-14 relative there for dps - dps_low = 10, six
    decades below the ``tol`` of this study and at the foot of its ``fit_band``.  Beyond it the self-check stops
    measuring the yardstick's error (impact-time errors saturate well below 1 where t_n is large against the
    flights: ~1e-2 in the rest-coeff drop), so nothing is compared there.  The chaotic drop: 30 digits reach 1e-4 at
    impact 74; the rest-coeff drop at 182."""
    err = rel_diff(t_low[:n], t_ref[:n])
    return min(n, horizon_index(err, YARDSTICK_TRUSTED) + 1)


def growth_rate(x, err, band) -> tuple[float, float, int]:
    """Slope of ln(err) against x over the first stretch with err in ``band`` (after the last time the error
    was below band[0]); returns (slope, its standard error, number of points)."""
    err = np.asarray(err, dtype=float)
    x = np.asarray(x, dtype=float)
    lo, hi = band
    above = np.flatnonzero(err > hi)
    end = int(above[0]) if above.size else len(err)
    below = np.flatnonzero(err[:end] < lo)
    start = int(below[-1]) + 1 if below.size else 0
    sel = np.arange(start, end)
    sel = sel[err[sel] > 0]
    if sel.size < 3:
        return math.nan, math.nan, int(sel.size)
    A = np.vstack([x[sel], np.ones(sel.size)]).T
    coef, res, *_ = np.linalg.lstsq(A, np.log(err[sel]), rcond=None)
    dof = max(sel.size - 2, 1)
    s2 = float(res[0]) / dof if res.size else 0.0
    se = math.sqrt(s2 * np.linalg.inv(A.T @ A)[0, 0])
    return float(coef[0]), se, int(sel.size)


# --------------------------------------------------------------------------- the study

PRECISIONS = ("float64", "longdouble", "mp_low")


def _float64_run(gamma, mu, start, n):
    from ..model import Parameters
    from ..simulate import simulate
    from ..kinds import IMPACT

    tr = simulate(Parameters(gamma, mu), start, max_events=int(n))
    ok = tr.kind == IMPACT
    m = int(np.argmin(ok)) if not ok.all() else len(tr)  # impacts-only prefix
    return {"t": tr.t[:m].copy(), "xdot": tr.xdot[:m].copy(), "xidot": tr.xidot[:m].copy(),
            "eta": tr.eta[:m].copy(), "n": m}


def _energy_excess(u, a, eta):
    return 0.5 * (a * a + (u + a) * (u + a) + eta * eta)


def horizon_dataset(spec: dict) -> xr.Dataset:
    """Divergence of float64, longdouble and mp(dps_low) from mp(dps) per regime; horizons, growth rates,
    and late statistics across precisions (module docstring).  ``spec`` (config ``reduced.horizon``)::

        {"tol": 1e-8, "fit_band": [1e-13, 1e-4], "dps": 40, "dps_low": 30,
         "regimes": {"chaotic": {"gamma": 0.01, "mu": 0.01, "psi0": 6.0, "n_mp": 120, "n_long": 20000}, ...},
         "statistic_at": [1000, 10000, 20000]}
    """
    from ..model import Deviations

    tol = float(spec["tol"])
    band = tuple(spec["fit_band"])
    dps, dps_low = int(spec["dps"]), int(spec["dps_low"])
    names = list(spec["regimes"])
    n_max = max(int(r["n_mp"]) for r in spec["regimes"].values())
    checkpoints = [int(k) for k in spec["statistic_at"]]
    shape = (len(names), len(PRECISIONS), n_max)
    err_t = np.full(shape, np.nan)
    err_x = np.full(shape, np.nan)
    t_ref = np.full((len(names), n_max), np.nan)
    H = np.full((len(names), len(PRECISIONS)), -1, dtype=np.int64)
    H_decor = np.full((len(names), len(PRECISIONS)), -1, dtype=np.int64)
    lam_n = np.full((len(names), len(PRECISIONS)), np.nan)
    lam_n_se = np.full((len(names), len(PRECISIONS)), np.nan)
    lam_t = np.full((len(names), len(PRECISIONS)), np.nan)
    lam_shift_n = np.full((len(names), len(PRECISIONS)), np.nan)
    lam_shift_t = np.full((len(names), len(PRECISIONS)), np.nan)
    n_compared = np.zeros(len(names), dtype=np.int64)
    cpu_ref = np.zeros(len(names))
    stat_prec = ("float64", "longdouble")
    stat_c = np.full((len(names), len(stat_prec), len(checkpoints)), np.nan)
    stat_e = np.full_like(stat_c, np.nan)
    stat_t = np.full_like(stat_c, np.nan)
    cpu_long = np.full((len(names), len(stat_prec)), np.nan)
    for i, name in enumerate(names):
        r = spec["regimes"][name]
        g, m, psi0, n = float(r["gamma"]), float(r["mu"]), float(r["psi0"]), int(r["n_mp"])
        start = Deviations(x=psi0, xdot=0.0, xidot=0.0, eta=g)  # psi(0) = psi0, xi = xi' = psi' = 0
        ref = reference_trajectory(g, m, start, n, dps)
        cpu_ref[i] = ref["cpu"]
        runs = {
            "float64": _float64_run(g, m, start, n),
            "longdouble": longdouble_trajectory(g, m, start, n),
            "mp_low": reference_trajectory(g, m, start, n, dps_low),
        }
        k = yardstick_reach(runs["mp_low"]["t"], ref["t"], min(ref["n"], *(run["n"] for run in runs.values())))
        n_compared[i] = k
        t_ref[i, :k] = [float(v) for v in ref["t"][:k]]
        for j, p in enumerate(PRECISIONS):
            et = rel_diff(runs[p]["t"][:k], ref["t"][:k])
            ex = rel_diff(runs[p]["xdot"][:k], ref["xdot"][:k])
            err_t[i, j, :k] = et
            err_x[i, j, :k] = ex
            H[i, j] = horizon_index(et, tol)
            H_decor[i, j] = horizon_index(et, 1e-2)
            # growth of the larger of the two errors (t_n errors lag behind the state's)
            e = np.maximum(et, ex)
            lam_n[i, j], lam_n_se[i, j], _ = growth_rate(np.arange(1, k + 1), e, band)
            lam_t[i, j], _, _ = growth_rate(t_ref[i, :k], e, band)
        # second estimate: how far the horizon moves per e-fold of working precision
        eps_p = {"float64": EPS64, "longdouble": float(np.finfo(np.longdouble).eps),
                 "mp_low": float(runs["mp_low"]["eps"])}
        h64 = H[i, 0]
        for j, p in enumerate(PRECISIONS):
            if j and h64 < k and H[i, j] < k and H[i, j] > h64:
                lam_shift_n[i, j] = math.log(EPS64 / eps_p[p]) / (H[i, j] - h64)
                lam_shift_t[i, j] = math.log(EPS64 / eps_p[p]) / (t_ref[i, H[i, j]] - t_ref[i, h64])
        # statistics beyond the horizon: float64 vs longdouble runs of n_long impacts
        n_long = int(r["n_long"])
        if n_long:
            t0 = time.process_time()
            longs = {"float64": _float64_run(g, m, start, n_long)}
            cpu_long[i, 0] = time.process_time() - t0
            ld = longdouble_trajectory(g, m, start, n_long)
            cpu_long[i, 1] = ld["cpu"]
            longs["longdouble"] = ld
            for j, p in enumerate(stat_prec):
                run = longs[p]
                for c, nc in enumerate(checkpoints):
                    if nc <= run["n"]:
                        u, a, eta = (np.float64(run[q][nc - 1]) for q in ("xdot", "xidot", "eta"))
                        stat_c[i, j, c] = nc * float(u) * m / (3.0 * g)
                        stat_e[i, j, c] = float(_energy_excess(u, a, eta))
                        stat_t[i, j, c] = float(run["t"][nc - 1])
    reg = ("regime",)
    attrs_u = {"units": "1"}
    ds = xr.Dataset(
        {
            "err_t": (("regime", "precision", "impact"), err_t,
                      {"long_name": "relative error of the impact time t_n against mp reference", **attrs_u}),
            "err_xdot": (("regime", "precision", "impact"), err_x,
                         {"long_name": "relative error of the rebound speed Xdot_n against mp reference", **attrs_u}),
            "t_ref": (("regime", "impact"), t_ref, {"long_name": "impact time t_n (mp reference)",
                                                    "units": "sqrt(m/2k)"}),
            "horizon": (("regime", "precision"), H, {"long_name": f"impacts with |dt_n|/t_n <= {tol:g}", **attrs_u}),
            "horizon_decorrelation": (("regime", "precision"), H_decor,
                                      {"long_name": "impacts with |dt_n|/t_n <= 1e-2", **attrs_u}),
            "lambda_n": (("regime", "precision"), lam_n,
                         {"long_name": "growth rate of ln(error) per impact", "units": "1/impact"}),
            "lambda_n_se": (("regime", "precision"), lam_n_se, {"long_name": "standard error of lambda_n",
                                                                "units": "1/impact"}),
            "lambda_t": (("regime", "precision"), lam_t,
                         {"long_name": "growth rate of ln(error) per unit time", "units": "1/sqrt(m/2k)"}),
            "lambda_n_shift": (("regime", "precision"), lam_shift_n,
                               {"long_name": "ln(eps_64/eps_p)/(H_p - H_64): e-folds of precision per impact "
                                             "of horizon gained", "units": "1/impact"}),
            "lambda_t_shift": (("regime", "precision"), lam_shift_t,
                               {"long_name": "ln(eps_64/eps_p)/(t_{H_p} - t_{H_64}): e-folds of precision per unit "
                                             "time of horizon gained", "units": "1/sqrt(m/2k)"}),
            "n_compared": (reg, n_compared, {"long_name": "impacts compared (at most n_mp; the yardstick's reach, "
                                                          "yardstick_reach)", **attrs_u}),
            "cpu_reference": (reg, cpu_ref, {"long_name": "CPU time of the mp reference run", "units": "s"}),
            "stat_nXdot": (("regime", "stat_precision", "checkpoint"), stat_c,
                           {"long_name": "n Xdot_n mu/(3 gamma) at n (Theorem main_thm: -> 1)", **attrs_u}),
            "stat_energy": (("regime", "stat_precision", "checkpoint"), stat_e,
                            {"long_name": "E - E_m just after impact n", **attrs_u}),
            "stat_t": (("regime", "stat_precision", "checkpoint"), stat_t,
                       {"long_name": "t_n (individual impact time: not predictable beyond the horizon)",
                        "units": "sqrt(m/2k)"}),
            "cpu_long": (("regime", "stat_precision"), cpu_long,
                         {"long_name": "CPU time of the long run", "units": "s"}),
            "gamma": (reg, [float(spec["regimes"][k]["gamma"]) for k in names], {"long_name": "gamma", **attrs_u}),
            "mu": (reg, [float(spec["regimes"][k]["mu"]) for k in names], {"long_name": "mu", **attrs_u}),
            "psi0": (reg, [float(spec["regimes"][k]["psi0"]) for k in names], {"long_name": "psi(0)", "units": "L"}),
        },
        coords={"regime": names, "precision": list(PRECISIONS), "impact": np.arange(1, n_max + 1),
                "stat_precision": list(stat_prec), "checkpoint": checkpoints},
        attrs={"title": "Predictability horizon of the exact solver (float64) against mpmath", "tol": tol,
               "fit_band": list(band), "dps": dps, "dps_low": dps_low,
               "eps_float64": EPS64, "eps_longdouble": float(np.finfo(np.longdouble).eps),
               "longdouble": f"{np.finfo(np.longdouble).nmant + 1}-bit significand "
                             f"({np.finfo(np.longdouble).dtype}; x87 80-bit extended on x86_64)",
               "Conventions": "CF-1.10"},
    )
    return ds


def plot_horizon(ds: xr.Dataset, spec: dict, outputs) -> None:
    """Relative error of t_n against n (top) and against t_n (bottom) per regime and precision, with the
    horizons (dotted) and the fitted growth rates."""
    from ..figures.common import WIDTH, label_time, plt, save, tex_num

    names = list(ds["regime"].values)
    fig, axes = plt.subplots(2, len(names), figsize=(WIDTH, 4.8), sharey=True, squeeze=False)
    labels = {"float64": "float64 (bounce)", "longdouble": "long double (x87 80-bit)",
              "mp_low": f"mpmath {ds.attrs['dps_low']} digits"}
    floor = 1e-40
    for col, name in enumerate(names):
        d = ds.sel(regime=name)
        k = int(d["n_compared"])
        n = ds["impact"].values[:k]
        t = d["t_ref"].values[:k]
        for row, xs in enumerate((n, t)):
            ax = axes[row][col]
            for j, p in enumerate(ds["precision"].values):
                e = np.maximum(d["err_t"].sel(precision=p).values[:k], floor)
                ax.semilogy(xs, e, color=f"C{j}", lw=0.8, label=labels[p])
                h = int(d["horizon"].sel(precision=p))
                if h < k:
                    ax.axvline(xs[h], color=f"C{j}", lw=0.6, ls=":")
            ax.axhline(ds.attrs["tol"], color="k", lw=0.5, ls="--")
            ax.set_ylim(1e-40, 10)
            ax.set_yticks([1e-40, 1e-32, 1e-24, 1e-16, 1e-8, 1.0])
        lam_n = float(d["lambda_n"].sel(precision="float64"))
        lam_t = float(d["lambda_t"].sel(precision="float64"))
        axes[0][col].set_title(r"(%s) $\gamma=%s$, $\mu=%s$, $\psi(0)=%s$"
                               % (("abcdefgh"[col],) + tuple(tex_num(float(d[k])) for k in ("gamma", "mu", "psi0"))),
                               fontsize=8)
        axes[1][col].set_title(r"(%s) the same against the time $t_n$" % "abcdefgh"[len(names) + col], fontsize=8)
        h64 = int(d["horizon"].sel(precision="float64"))
        if np.isfinite(lam_n):
            txt_n = r"$H_{64}=%d$, fit $\lambda_n=%.2f$" % (h64, lam_n)
            txt_t = r"fit $\lambda_t=%.3f$" % lam_t
        else:
            txt_n = r"$H_{64}\geq%d$ (whole run)" % h64
            txt_t = "no exponential growth"
        axes[0][col].text(0.97, 0.04, txt_n, transform=axes[0][col].transAxes, ha="right", va="bottom", fontsize=7)
        axes[1][col].text(0.97, 0.04, txt_t, transform=axes[1][col].transAxes, ha="right", va="bottom", fontsize=7)
        if h64 < k:  # zoom the time axis on the divergence (the impacts before it can span most of the time)
            axes[1][col].set_xlim(t[max(0, h64 - 30)], t[-1] + 0.02 * (t[-1] - t[max(0, h64 - 30)]))
        axes[0][col].set_xlabel(r"impact index $n$")
        label_time(axes[1][col])
        axes[1][col].set_xlabel(r"$t_n$  [$\sqrt{m/2k}$]")
    for row in range(2):
        axes[row][0].set_ylabel(r"$|t_n - t_n^{\mathrm{ref}}|\,/\,t_n^{\mathrm{ref}}$")
    # the legend where the errors stay lowest (most room above the curves)
    quiet = int(np.nanargmin([np.nanmax(ds["err_t"].sel(regime=r).values) for r in names]))
    axes[0][quiet].legend(fontsize=6, loc="upper left")
    fig.suptitle(r"Predictability horizon of the exact solver: impact times against mpmath at %d digits "
                 r"(dotted: first $n$ with error $>%s$;" "\n"
                 r"curves end where %d digits leave the yardstick by $10^{-4}$)"
                 % (ds.attrs["dps"], tex_num(ds.attrs["tol"]), ds.attrs["dps_low"]), fontsize=8)
    fig.tight_layout()
    save(fig, outputs)


STUDY = Study("horizon", horizon_dataset, plot_horizon, lambda c: c["reduced"]["horizon"],
              caption=("Predictability horizon of the float64 solver against mpmath: the impact index up to which"
                       " impact times agree, per damping regime."))

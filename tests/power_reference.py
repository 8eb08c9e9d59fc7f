"""Independent high-precision reference for one flight of the nonlinear (power-law) spring.

Written from the paper's Discussion alone, sharing no code with ``bounce``:

    psi'' = -gamma,   xi'' = -rho xi |xi|^a - 2 mu xi' |xi|^b     (eq. ``eq-motion-nonlin-psi-xi``)

x = psi - xi (eq. ``xi-psi``); a flight ends at the first x = 0 with x' < 0, where psi' and xi' are
exchanged (eq. ``collision-rule``, see ``src/bounce/events.py``).  Linear: (rho, a, b) = (1, 0, 0).
psi is a parabola; xi is computed at ``dps`` decimal digits (float inputs are converted exactly).

**Regular steps** (xi != 0).  With s = sign(xi) and z = s xi > 0 the spring equation reads
z'' = -rho z^(a+1) - 2 mu z' z^b on the whole step; its Taylor coefficients follow from the
J. C. P. Miller recurrence for powers, P = z^p:  k z_0 P_k = sum_{j=1..k} ((p+1) j - k) z_j P_{k-j},
a Cauchy product for z' z^b and z_{k+2} = (-rho P_k - 2 mu (z' z^b)_k) / ((k+1)(k+2)), computed in
the scaled time sigma = (t - t0)/H in fixed point (Python integers carrying GUARD_BITS bits more than
the working precision; ~100x faster than mpf arithmetic).  Degree N = 1.2 dps + 12; the step makes
the last two terms |z_k| h^k <= 10^-dps X_m (X_m the amplitude bound below; Jorba-Zou), so the
series truncation is at the working precision (checked by a second precision in the tests).
x on a step is formed as a displacement from the step's start,
x(t0 + h) = x(t0) + psi'(t0) h - gamma h^2/2 - s (z(h) - z(0)), without the O(gamma)
cancellation of psi - xi.  A step must keep z > 0: its polynomial is sampled at 16 points and
must exceed B_z delta^2 / 8 (delta the spacing, B_z >= |xi''| the energy bound below) at each,
so that it cannot touch 0 between samples; otherwise the step is halved.

**The non-analytic point xi = 0** (for non-integer a, b the field is not smooth there, for
0 < b < 1 not Lipschitz): regular steps stop short of it and a crossing series takes over.
Near a crossing at t_c with |xi'(t_c)| = V > 0, on the side where z = s xi > 0 and
tau = |t - t_c|, w(tau) = z(t_c +- tau) solves w'' = -rho w^(a+1) -+ 2 mu w' w^b, w(0) = 0,
w'(0) = V, and equals the generalised power series

    w = V tau (1 + sum_{(i,j) != 0} c_ij X^i Y^j),  X = +-2 mu V^b tau^(1+b),  Y = rho V^a tau^(2+a),

whose coefficients c_ij do not depend on (V, rho, mu): with e_ij = i (1+b) + j (2+a) (the Euler
operator tau d/dtau on X^i Y^j), c_m e_m (1 + e_m) = -A_{m-(0,1)} - B_{m-(1,0)} where
A = (1+u)^(1+a), B = (1 + sum c (1+e) X^i Y^j) (1+u)^b, u = sum c X^i Y^j, and the powers follow
the two-variable Miller recurrence e_m P_m = sum_{0<m'<=m} (p e_m' - e_{m-m'}) F_m' P_{m-m'}.
It is truncated at total degree K = CROSSING_DEGREE and used where |X|, |Y| <= eps_window, where the
two top degrees are below 2^-prec/10 (computed from the coefficients).  The incoming side (mu -> -mu)
is matched to the last regular state by Newton's method on (tau, V) (analytic Jacobian); the
outgoing side starts the next regular step.  xi = xi' = 0 is a rest point (the spring energy
is 0 and cannot rise): xi stays 0.

**First root that cannot skip a shallow dip** (:func:`_first_root`).  The spring energy
E_s = xi'^2/2 + rho |xi|^(a+2)/(a+2) does not increase in flight (dE_s/dt = -2 mu xi'^2 |xi|^b),
so from any time t0 on |xi| <= X_m = ((a+2) E_s(t0)/rho)^(1/(a+2)), |xi'| <= sqrt(2 E_s(t0)) and
|x''| = |gamma + xi''| <= B(t0) = gamma + rho X_m^(a+1) + 2 mu sqrt(2 E_s) X_m^b.  The search
interval is cut recursively, left half first; an interval [t0, t1] of length h is discarded
only if x(t0), x(t1) > B h^2/8 + (evaluation error): since x >= (linear interpolation) - B h^2/8,
no dip below the floor, however shallow or narrow, can hide in it.  An interval with
x(t1) <= 0 and x'(t0) + B h < 0 holds exactly one root (x strictly decreasing), polished by
bracketed Newton; the root returned is therefore the first one, with x' < 0.  A tangency closer
than the working precision raises :class:`RootSearchError` instead of guessing.

``x_min_interior`` is the smallest interior local minimum of x (the depth of the nearest miss),
+inf if x has none: x' is sampled on the search's own grid refined to >= 512 points per flight,
and each sign change - to + of x' is refined by bisection.  A minimum between two samples where
x' does not change sign lies within B delta^2 / 8 of the sampled x (delta the spacing).
"""

from __future__ import annotations

import bisect
import functools
from dataclasses import dataclass

import mpmath
from mpmath import mp, mpf

DPS = 50  #: default working precision (decimal digits)
CROSSING_DEGREE = 40  #: total degree K of the crossing series
GUARD_BITS = 40  #: extra bits of the fixed-point series arithmetic
SAMPLES = 16  #: samples per regular step for the z > 0 check


class RootSearchError(RuntimeError):
    """A tangency or a non-convergence below the working precision."""


def M(v) -> mpf:
    """Exact conversion of a float (or int, or mpf) to mpf at the current precision."""
    return v if isinstance(v, mpf) else mpf(v)


def _tol():
    return mpf(10) ** (-mp.dps)


# --------------------------------------------------------------------------------------------
# fixed-point numbers: Python ints n standing for n 2^-F (F = working bits + GUARD_BITS)
# --------------------------------------------------------------------------------------------


def _bits():
    return mp.prec + GUARD_BITS


def _fix(v, F):
    return int(mpmath.ldexp(M(v), F))


def _unfix(n, F):
    return mpmath.ldexp(mpf(n), -F)


def _dot(xs, ys):
    """sum x_i y_i of two int sequences."""
    return sum(map(int.__mul__, xs, ys))


# --------------------------------------------------------------------------------------------
# crossing series (universal coefficients)
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class CrossingSeries:
    """u(X, Y) = sum c_ij X^i Y^j of the module docstring for one (a, b), in fixed point."""

    terms: tuple  # ((i, j, c, e, e^2, b i + a j, e (b i + a j)), ...) fixed-point ints, c != 0
    eps_window: mpf  # |X|, |Y| <= eps_window keeps the truncation below 10^-dps
    degree: int
    F: int

    def sums(self, X, Y):
        """(u, D u, D^2 u, V d/dV u, V d/dV D u) at (X, Y), D = tau d/dtau (Euler operator)."""
        F = self.F
        x, y = _fix(X, F), _fix(Y, F)
        xp, yp = [1 << F], [1 << F]
        for _ in range(self.degree):
            xp.append(xp[-1] * x >> F)
            yp.append(yp[-1] * y >> F)
        u = du = ddu = vu = vdu = 0
        for i, j, c, e, ee, g, eg in self.terms:
            t = c * xp[i] * yp[j] >> (2 * F)
            u += t
            du += e * t
            ddu += ee * t
            vu += g * t
            vdu += eg * t
        return _unfix(u, F), _unfix(du, 2 * F), _unfix(ddu, 2 * F), _unfix(vu, 2 * F), _unfix(vdu, 2 * F)


@functools.lru_cache(maxsize=None)
def crossing_series(a: mpf, b: mpf, degree: int, prec: int) -> CrossingSeries:
    """The universal coefficients c_ij up to total degree ``degree`` (module docstring)."""
    with mp.workprec(prec):
        F = _bits()
        one = 1 << F
        monomials = [(g - j, j) for g in range(degree + 1) for j in range(g + 1)]
        e_mp = {m: m[0] * (1 + b) + m[1] * (2 + a) for m in monomials}
        e = {m: _fix(v, F) for m, v in e_mp.items()}
        pa, pb = _fix(1 + a, F), _fix(b, F)
        c = {(0, 0): 0}
        Fs, eF, D, A, eA, Q, eQ, B = ({(0, 0): one} for _ in range(8))
        eF[(0, 0)] = eA[(0, 0)] = eQ[(0, 0)] = 0
        for g in range(1, degree + 1):
            level = [(g - j, j) for j in range(g + 1)]
            for m in level:
                am = A[(m[0], m[1] - 1)] if m[1] >= 1 else 0
                bm = B[(m[0] - 1, m[1])] if m[0] >= 1 else 0
                den = e_mp[m] * (1 + e_mp[m])
                c[m] = Fs[m] = _fix(-_unfix(am + bm, F) / den, F)
                eF[m] = e[m] * c[m] >> F
                D[m] = c[m] + eF[m]
            for m in level:
                # e_m P_m = sum_{0 < m' <= m} (p e_m' - e_{m-m'}) F_m' P_{m-m'}
                lo = [(i, j) for i in range(m[0] + 1) for j in range(m[1] + 1) if i + j]
                hi = [(m[0] - i, m[1] - j) for i, j in lo]
                f_lo, ef_lo = [Fs[k] for k in lo], [eF[k] for k in lo]
                sa = pa * _dot(ef_lo, [A[k] for k in hi]) - (_dot(f_lo, [eA[k] for k in hi]) << F)
                sq = pb * _dot(ef_lo, [Q[k] for k in hi]) - (_dot(f_lo, [eQ[k] for k in hi]) << F)
                A[m], Q[m] = (sa >> F) // e[m], (sq >> F) // e[m]
                eA[m], eQ[m] = e[m] * A[m] >> F, e[m] * Q[m] >> F
                B[m] = Q[m] + (_dot([D[k] for k in lo], [Q[k] for k in hi]) >> F)
        terms = []
        for (i, j), cm in c.items():
            if cm:
                g = _fix(b * i + a * j, F)
                terms.append((i, j, cm, e[(i, j)], e[(i, j)] ** 2 >> F, g, e[(i, j)] * g >> F))
        # window: the two top degrees at |X| = |Y| = eps stay below 2^-prec / 10
        top = [_unfix(sum(abs(c[(g - j, j)]) for j in range(g + 1)), F) for g in (degree - 1, degree)]
        tol = mpf(2) ** (-prec) / 10
        eps = min([mpf(1) / 4] + [(tol / t) ** (mpf(1) / g) for t, g in zip(top, (degree - 1, degree)) if t > 0])
        return CrossingSeries(terms=tuple(terms), eps_window=eps, degree=degree, F=F)


# --------------------------------------------------------------------------------------------
# segments of a flight: each gives (x, psi', xi, xi') at any t in it
# --------------------------------------------------------------------------------------------


@dataclass
class Regular:
    """A Taylor step of z = s xi > 0 from t0: z(t0 + H sigma) = sum Z_k sigma^k (fixed point)."""

    t0: mpf
    H: mpf
    s: int
    Z: list
    F: int
    z0: mpf
    x0: mpf
    psid0: mpf
    gamma: mpf

    def state(self, t):
        tau = t - self.t0
        F, Z = self.F, self.Z
        sig = _fix(tau / self.H, F)
        dz = dzs = 0
        for k in range(len(Z) - 1, 0, -1):
            dz = (dz + Z[k]) * sig >> F
            dzs = (dzs * sig >> F) + k * Z[k]
        dz, zp = _unfix(dz, F), _unfix(dzs, F) / self.H
        x = self.x0 + self.psid0 * tau - self.gamma * tau * tau / 2 - self.s * dz
        return x, self.psid0 - self.gamma * tau, self.s * (self.z0 + dz), self.s * zp


@dataclass
class Crossing:
    """Around xi(t_c) = 0, |xi'(t_c)| = V: the crossing series (s_out = sign of xi after t_c)."""

    tc: mpf
    V: mpf
    s_out: int
    xc: mpf
    psidc: mpf
    law: "Law"

    def state(self, t):
        tau = t - self.tc
        if tau >= 0:
            w, wp = self.law.crossing_w(tau, self.V, +1)[:2]
            xi, xid = self.s_out * w, self.s_out * wp
        else:  # z_in = -s_out xi = w(t_c - t), dz_in/dt = -w'
            w, wp = self.law.crossing_w(-tau, self.V, -1)[:2]
            xi, xid = -self.s_out * w, self.s_out * wp
        x = self.xc + self.psidc * tau - self.law.gamma * tau * tau / 2 - xi
        return x, self.psidc - self.law.gamma * tau, xi, xid


@dataclass
class Rest:
    """xi = xi' = 0: the spring stays at rest length."""

    t0: mpf
    x0: mpf
    psid0: mpf
    gamma: mpf

    def state(self, t):
        tau = t - self.t0
        return self.x0 + self.psid0 * tau - self.gamma * tau * tau / 2, self.psid0 - self.gamma * tau, mpf(0), mpf(0)


# --------------------------------------------------------------------------------------------
# the law and one flight
# --------------------------------------------------------------------------------------------


@dataclass
class Law:
    """gamma, mu, rho > 0, a, b >= 0 of eq. eq-motion-nonlin-psi-xi (mpf)."""

    gamma: mpf
    mu: mpf
    rho: mpf
    a: mpf
    b: mpf

    def __post_init__(self):
        for name in ("gamma", "mu", "rho"):
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be > 0")
        for name in ("a", "b"):
            if not getattr(self, name) >= 0:
                raise ValueError(f"{name} must be >= 0")
        self.series = crossing_series(self.a, self.b, CROSSING_DEGREE, mp.prec)
        self.degree = int(1.2 * mp.dps) + 12

    def spring_energy(self, xi, xid):
        return xid * xid / 2 + self.rho * abs(xi) ** (self.a + 2) / (self.a + 2)

    def energy(self, x, psid, xi, xid):
        """E of eq. nonlin-energy, psi = x + xi."""
        return psid * psid / 2 + self.spring_energy(xi, xid) + self.gamma * (x + xi)

    def xi_bounds(self, xi, xid):
        """(|xi|, |xi'|, |xi''|) bounds valid from this state on (non-increasing spring energy)."""
        es = self.spring_energy(xi, xid) * (1 + mpf(10) ** (-(mp.dps // 2)))
        xm = ((self.a + 2) * es / self.rho) ** (1 / (self.a + 2))
        vm = mp.sqrt(2 * es)
        return xm, vm, self.rho * xm ** (self.a + 1) + 2 * self.mu * vm * xm**self.b

    # -- regular Taylor steps --------------------------------------------------------------

    def taylor(self, z0, z1, H):
        """Fixed-point coefficients Z_k of z(t0 + H sigma), z'' = -rho z^(a+1) - 2 mu z' z^b, z(t0) = z0 > 0."""
        F = _bits()
        N, p, b = self.degree, self.a + 1, self.b
        rho_s, mu2_s = _fix(self.rho * H * H, F), _fix(2 * self.mu * H, F)  # the equation in sigma
        p1, b1 = _fix(p + 1, F), _fix(b + 1, F)
        Z = [_fix(z0, F), _fix(z1 * H, F)]
        jZ = [0, Z[1]]
        P = [_fix(z0**p, F)]
        Q = [_fix(z0**b, F)]
        dZQ = []  # (j+1) Z_{j+1}, j = 0..
        for k in range(N - 1):
            if k:
                # Miller: k Z_0 P_k = (p+1) sum j Z_j P_{k-j} - k sum Z_j P_{k-j}
                zs, jzs = Z[1:k + 1], jZ[1:k + 1]
                rP, rQ = P[k - 1::-1], Q[k - 1::-1]
                num_p = (p1 * _dot(jzs, rP) >> F) - k * _dot(zs, rP)
                num_q = (b1 * _dot(jzs, rQ) >> F) - k * _dot(zs, rQ)
                P.append(num_p // (k * Z[0]))
                Q.append(num_q // (k * Z[0]))
            dZQ.append(jZ[k + 1])
            r = _dot(dZQ, Q[k::-1]) >> F  # (z' z^b)_k
            Z.append(-(rho_s * P[k] + mu2_s * r >> F) // ((k + 1) * (k + 2)))
            jZ.append((k + 2) * Z[-1])
        return Z, F

    # -- crossing series -------------------------------------------------------------------

    def window(self, V):
        """Largest tau with |X|, |Y| <= eps_window."""
        eps = self.series.eps_window
        d1 = (eps / (2 * self.mu * V**self.b)) ** (1 / (1 + self.b))
        d2 = (eps / (self.rho * V**self.a)) ** (1 / (2 + self.a))
        return min(d1, d2)

    def crossing_w(self, tau, V, direction):
        """(w, w', w'', V dw/dV, V dw'/dV) of the crossing series; direction +1 after, -1 before t_c."""
        if tau == 0:
            return mpf(0), V, mpf(0), mpf(0), V
        X = direction * 2 * self.mu * V**self.b * tau ** (1 + self.b)
        Y = self.rho * V**self.a * tau ** (2 + self.a)
        u, du, ddu, vu, vdu = self.series.sums(X, Y)
        w = V * tau * (1 + u)
        wp = V * (1 + u + du)
        return w, wp, V * (du + ddu) / tau, w + V * tau * vu, wp + V * (vu + vdu)

    def match_incoming(self, z, zdot):
        """(sigma, V) with w(sigma; V) = z, w'(sigma; V) = -zdot on the incoming side, or None."""
        sigma, V = z / -zdot, -zdot
        tol = _tol()
        for _ in range(60):
            w, wp, wpp, vw, vwp = self.crossing_w(sigma, V, -1)
            r1, r2 = w - z, wp + zdot
            det = wp * vwp - vw * wpp  # Jacobian in (sigma, log V)
            if det == 0:
                return None
            ds = (r1 * vwp - vw * r2) / det
            dl = (wp * r2 - wpp * r1) / det
            sigma -= ds
            V *= 1 - dl
            if not (sigma > 0 and V > 0):
                return None
            if abs(ds) <= tol * sigma and abs(dl) <= tol:
                return sigma, V
        return None


class PowerFlight:
    """One flight from (x, x', xi', xi) at t = 0, as a chain of segments built on demand."""

    def __init__(self, law: Law, x, xdot, xidot, xi):
        self.law = law
        self.x0 = x
        self.psid0 = xdot + xidot
        self.starts = []
        self.segments = []
        self.t_end = mpf(0)
        self.end_state = (x, xdot + xidot, xi, xidot)  # (x, psi', xi, xi')
        self.H = None  # scale of the next regular step

    def _append(self, seg, t_end):
        self.starts.append(self.t_end)
        self.segments.append(seg)
        self.t_end = t_end
        self.end_state = seg.state(t_end)

    def _extend(self):
        law, g = self.law, self.law.gamma
        t = self.t_end
        x, psid, xi, xid = self.end_state
        if xi == 0 and xid == 0:
            length = 2 * (abs(psid) / g + mp.sqrt(2 * abs(x) / g)) + 1  # beyond the parabola's root
            self._append(Rest(t, x, psid, g), t + length)
            return
        if xi == 0:
            V = abs(xid)
            self._append(Crossing(t, V, 1 if xid > 0 else -1, x, psid, law), t + law.window(V))
            return
        s = 1 if xi > 0 else -1
        z0, z1 = s * xi, s * xid
        if z1 < 0 and z0 < -z1 * law.window(-z1) / 2:
            m = law.match_incoming(z0, z1)
            if m is not None and m[0] <= law.window(m[1]):
                sigma, V = m
                tc = t + sigma
                xc = x + psid * sigma - g * sigma * sigma / 2 + xi  # xi(t_c) = 0
                self._append(Crossing(tc, V, -s, xc, psid - g * sigma, law), tc + law.window(V))
                self.H = None
                return
        xm, _, bz = law.xi_bounds(xi, xid)
        H = self.H or min(mpf(1), z0 / abs(z1) if z1 else mpf(1))
        for _ in range(200):
            Z, F = law.taylor(z0, z1, H)
            N = len(Z) - 1
            tail = [(_tol() * xm / _unfix(abs(Z[k]), F)) ** (mpf(1) / k) for k in (N - 1, N) if Z[k]]
            smax = min(tail) if tail else mpf(2)
            if smax < mpf(1) / 4:  # scale far beyond the radius: rescale before trusting the digits
                H *= smax * 2
                continue
            h = H * min(smax, mpf(1))
            seg = Regular(t, H, s, Z, F, z0, x, psid, g)
            delta = h / SAMPLES
            if all(s * seg.state(t + i * delta)[2] > bz * delta * delta / 8 for i in range(1, SAMPLES + 1)):
                self._append(seg, t + h)
                self.H = 2 * h if smax >= 1 else h
                return
            H = h / 2
        raise RootSearchError("no admissible regular step (xi stalls at 0?)")

    def covered(self, t):
        while not self.segments or self.t_end < t:
            self._extend()

    def state(self, t):
        """(x, psi', xi, xi') at time t >= 0."""
        self.covered(t)
        i = bisect.bisect_right(self.starts, t) - 1
        return self.segments[max(i, 0)].state(t)

    def x(self, t):
        return self.state(t)[0]

    def xdot(self, t):
        st = self.state(t)
        return st[1] - st[3]

    def x2_bound(self, t):
        """Bound of |x''| on [t, end of flight] (module docstring)."""
        _, psid, xi, xid = self.state(t)
        return self.law.gamma + self.law.xi_bounds(xi, xid)[2]

    def energy(self, t):
        return self.law.energy(*self.state(t))

    def horizon(self):
        """A time T with x(T) < 0 (psi falls without bound, xi stays bounded)."""
        while True:
            self._extend()
            if self.end_state[0] < 0:
                return self.t_end

    def first_impact(self):
        """(tau, x_min_interior, t_min_interior) of the first x = 0 with x' < 0."""
        x0, psid0, xi0, xid0 = self.end_state if not self.segments else self.state(mpf(0))
        u = psid0 - xid0
        if x0 > 0:
            t_a = mpf(0)
        elif x0 == 0 and u > 0:
            t_a = u / self.x2_bound(mpf(0))  # x(t) >= u t - B t^2/2 > 0 on (0, 2u/B)
        else:
            raise ValueError("a flight must start above the floor or on it moving up (x > 0, or x = 0 and x' > 0)")
        T = self.horizon()
        grid = []
        tau = _first_root(self, t_a, T, grid)
        if tau is None:
            raise RootSearchError("no contact before the horizon")
        xmin, tmin = _interior_minimum(self, tau, grid)
        return tau, xmin, tmin


def _error_bar(flight, t, x2):
    """Evaluation error of x(t): 2^-prec+8 of the magnitudes it is formed from."""
    return mpf(2) ** (-(mp.prec - 8)) * (abs(flight.x0) + abs(flight.psid0) * t + x2 * t * t + 1)


def _refine(flight, lo, hi):
    """The root of x in (lo, hi], x(lo) > 0 >= x(hi), x' < 0 on [lo, hi]: bracketed Newton."""
    tol = mpf(2) ** (-(mp.prec - 8))
    t = hi
    xt = flight.x(t)
    for _ in range(400):
        if xt == 0:
            return t
        step = -xt / flight.xdot(t)
        if abs(step) <= tol * abs(t):
            return t + step
        t_new = t + step
        if not lo < t_new < hi:
            t_new = (lo + hi) / 2
        t = t_new
        xt = flight.x(t)
        if xt > 0:
            lo = t
        else:
            hi = t
        if hi - lo <= tol * abs(hi):
            return hi
    raise RootSearchError("Newton refinement did not converge")


def _first_root(flight, t_a, t_b, grid):
    """First t in (t_a, t_b] with x(t) = 0 (module docstring); the visited points go to ``grid``."""
    f_a, f_b = flight.x(t_a), flight.x(t_b)
    min_width = (abs(t_b) + 1) * mpf(2) ** (-(mp.prec - 16))
    stack = [(t_a, f_a, t_b, f_b)]
    while stack:
        t0, f0, t1, f1 = stack.pop()
        grid.append(t0)
        h = t1 - t0
        B = flight.x2_bound(t0)
        err = _error_bar(flight, t1, B)
        if f1 > err and min(f0, f1) > B * h * h / 8 + err:
            continue  # no root, however shallow, can hide here
        if f1 <= 0 and flight.xdot(t0) + B * h < 0:
            return _refine(flight, t0, t1)
        if h <= min_width:
            raise RootSearchError(f"unresolved tangency of x with the floor near t = {t0}")
        tm = t0 + h / 2
        fm = flight.x(tm)
        stack.append((tm, fm, t1, f1))
        stack.append((t0, f0, tm, fm))
    return None


def _interior_minimum(flight, tau, grid, min_points=512):
    """Smallest interior local minimum of x on (0, tau): (x_min, t_min), or (+inf, None)."""
    pts = sorted({t for t in grid if 0 < t < tau} | {tau * k / min_points for k in range(1, min_points)})
    best, t_best = mp.inf, None
    prev_t, prev_d = pts[0], flight.xdot(pts[0])
    for t in pts[1:]:
        d = flight.xdot(t)
        if prev_d < 0 <= d:
            lo, hi = prev_t, t
            while hi - lo > (abs(hi) + 1) * mpf(2) ** (-(mp.prec // 2)):  # x is flat at its minimum
                mid = (lo + hi) / 2
                if flight.xdot(mid) < 0:
                    lo = mid
                else:
                    hi = mid
            xm = flight.x(lo)
            if xm < best:
                best, t_best = xm, lo
        prev_t, prev_d = t, d
    return best, t_best


def xi_equilibrium(gamma, rho, a, dps=DPS):
    """xi_eq = -(gamma/rho)^(1/(a+1)) (eq. nonlin-equilibrium-xi)."""
    with mp.workdps(dps):
        return -((M(gamma) / M(rho)) ** (1 / (M(a) + 1)))


def make_flight(gamma, mu, rho, a, b, x, xdot, xidot, xi):
    """A :class:`PowerFlight` at the current mp precision (inputs converted exactly)."""
    law = Law(*(M(v) for v in (gamma, mu, rho, a, b)))
    return PowerFlight(law, M(x), M(xdot), M(xidot), M(xi))


def reference_first_impact(gamma, mu, rho, a, b, x, xdot, xidot, xi, dps=DPS) -> dict:
    """First impact of a flight of eq. eq-motion-nonlin-psi-xi from (x, x', xi', xi) at t = 0.

    Returns mpf values: ``tau`` (the first x = 0 with x' < 0), the state just after the impact
    (``xdot`` = -x'(tau^-), ``xidot`` = psi'(tau^-), ``xi`` = xi(tau), ``eta`` = xi - xi_eq),
    ``x_min_interior`` / ``t_min_interior`` (smallest interior local minimum of x; +inf / None
    if none) and ``energy_start`` / ``energy_end`` (eq. nonlin-energy, before the impact).
    """
    with mp.workdps(dps):
        fl = make_flight(gamma, mu, rho, a, b, x, xdot, xidot, xi)
        tau, xmin, tmin = fl.first_impact()
        _, psid, xi_t, xid = fl.state(tau)
        return dict(
            tau=tau, xdot=xid - psid, xidot=psid, xi=xi_t,
            eta=xi_t - xi_equilibrium(gamma, rho, a, dps),
            x_min_interior=xmin, t_min_interior=tmin,
            energy_start=fl.energy(mpf(0)), energy_end=fl.energy(tau),
        )


def first_impact_errors(gamma, mu, rho, a, b, start, xi_eq, impact) -> list:
    """Errors of a solver's first impact against :func:`reference_first_impact`, each relative to its rounding scale.

    ``start`` = (x, x', xi', eta) of the flight with xi = xi_eq + eta exactly (the solver's float64 origin
    ``xi_eq``), ``impact`` = (tau, x', xi', eta) just after it.  Scales as in test_power_core.flight_errors: tau
    and x' to themselves; xi' = psi'(tau-) to |x'(0)| + |xi'(0)| + gamma tau (the terms it is summed from);
    eta to |eta| + |eta - eta0|.  Returns [tau, x', xi', eta] errors as floats.
    """
    x, u, v, eta0 = start
    with mp.workdps(60):
        xi0 = mpf(xi_eq) + mpf(eta0)
    ref = reference_first_impact(gamma, mu, rho, a, b, x, u, v, xi0)
    tau = float(ref["tau"])
    with mp.workdps(60):
        eta_ref = float(ref["xi"] - mpf(xi_eq))  # xi(tau) - xi_eq, rounded once
    tau_s, xdot, xidot, eta = impact
    return [abs(tau_s - tau) / tau,
            abs(xdot - float(ref["xdot"])) / abs(float(ref["xdot"])),
            abs(xidot - float(ref["xidot"])) / (abs(u) + abs(v) + gamma * tau),
            abs(eta - eta_ref) / (abs(eta_ref) + abs(eta_ref - eta0))]


# --------------------------------------------------------------------------------------------
# the sticky phase (lower mass at rest on the floor)
# --------------------------------------------------------------------------------------------
#
# Derived here from the Discussion's equations alone: with the floor holding the lower mass,
# x = 0 and y = 2 xi + 1; the upper mass obeys y'' = -gamma - S, S = rho xi |xi|^a + 2 mu xi' |xi|^b
# (the spring's push on the lower mass), so xi'' = -(gamma + S)/2, and the floor must supply
# -F, F = S - gamma (eq. force-on-the-floor for the linear law).  The phase ends at the first
# F = 0 with F' > 0 (eq. cond_di_distacco).  On xi < 0, z = -xi > 0 obeys
#
#     z'' = gamma/2 - (rho/2) z^(a+1) - mu z' z^b,        F = 2 z'' - 2 gamma,
#
# integrated by Taylor steps in mpf arithmetic (powers z^p by Miller's recurrence, coefficients
# of t^k unscaled), degree STICKY_DEGREE, step a quarter of the coefficients' root-test radius
# (so the neglected terms are ~4^-degree of the kept ones; checked by a second precision in the
# tests), shortened until z stays within [z0/2, 2 z0] (the cases used keep xi < 0).  The detach
# is the first sign change - to + of F on STICKY_SAMPLES samples per step, refined by bisection on
# the step's polynomial: a reference for transversal detachments, not a proof against a
# tangential touch between samples.

STICKY_DEGREE = 60
STICKY_SAMPLES = 64


def _sticky_coefficients(c, r, m, p, b, z0, z1, n):
    """Coefficients z_k of z(t0 + t) = sum z_k t^k for z'' = c - r z^p - m z' z^b, z(t0) = z0 > 0."""
    Z, P, Q = [z0, z1], [z0**p], [z0**b]
    for k in range(n - 1):
        if k:
            P.append(sum((p * j - (k - j)) * Z[j] * P[k - j] for j in range(1, k + 1)) / (k * z0))
            Q.append(sum((b * j - (k - j)) * Z[j] * Q[k - j] for j in range(1, k + 1)) / (k * z0))
        damping = sum((j + 1) * Z[j + 1] * Q[k - j] for j in range(k + 1))
        Z.append(((c if k == 0 else 0) - r * P[k] - m * damping) / ((k + 1) * (k + 2)))
    return Z


def _poly(Z, t, order):
    """order-th derivative of sum Z_k t^k at t."""
    acc = mpf(0)
    for k in range(len(Z) - 1, order - 1, -1):
        f = 1
        for j in range(order):
            f *= k - j
        acc = acc * t + f * Z[k]
    return acc


def reference_sticky(gamma, mu, rho, a, b, xidot, xi, t_end, dps=DPS) -> dict:
    """The sticky phase from (xi', xi), xi < 0, at rest on the floor, up to its detach or t_end.

    Returns mpf values ``t_detach`` (None if F < 0 on (0, t_end]) and the state there or at t_end:
    ``xi``, ``xidot``; also ``F_max``, the largest sampled F (the margin of a 'never').
    """
    with mp.workdps(dps):
        g, m_, rho_, a_, b_ = (M(v) for v in (gamma, mu, rho, a, b))
        c, r, p = g / 2, rho_ / 2, a_ + 1
        z, zd = -M(xi), -M(xidot)
        t = mpf(0)
        F_max = -mp.inf
        t_end = M(t_end)
        while t < t_end:
            if not z > 0:
                raise RootSearchError("the sticky reference needs xi < 0")
            Z = _sticky_coefficients(c, r, m_, p, b_, z, zd, STICKY_DEGREE)
            radius = min(abs(Z[k]) ** (-mpf(1) / k) for k in range(STICKY_DEGREE // 2, STICKY_DEGREE + 1) if Z[k] != 0)
            h = min(radius / 4, t_end - t)
            while not all(z / 2 <= _poly(Z, h * i / 8, 0) <= 2 * z for i in range(1, 9)):
                h /= 2
            prev = 2 * _poly(Z, mpf(0), 2) - 2 * g
            for i in range(1, STICKY_SAMPLES + 1):
                s = h * i / STICKY_SAMPLES
                F = 2 * _poly(Z, s, 2) - 2 * g
                F_max = max(F_max, F)
                if prev < 0 <= F:
                    lo, hi = s - h / STICKY_SAMPLES, s
                    while hi - lo > (t + hi) * mpf(2) ** (-mp.prec + 8):
                        mid = (lo + hi) / 2
                        if 2 * _poly(Z, mid, 2) - 2 * g < 0:
                            lo = mid
                        else:
                            hi = mid
                    return dict(t_detach=t + hi, xi=-_poly(Z, hi, 0), xidot=-_poly(Z, hi, 1), F_max=F_max)
                prev = F
            z, zd = _poly(Z, h, 0), _poly(Z, h, 1)
            t += h
        return dict(t_detach=None, xi=-z, xidot=-zd, F_max=F_max)

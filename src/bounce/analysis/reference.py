"""The one independent high-precision reference for the two-mass bouncing ball (mpmath).

Used by the tests, the claims (:mod:`bounce.checks`), the studies and the benchmarks.  Written from
the paper alone (sections 2-3), sharing no code with the float64 core (it imports nothing from
``bounce``):

* free flight (eq. ``eq-motion-psi-xi``): psi'' = -gamma in closed form, and
  xi'' + 2 mu xi' + xi = 0 by its own closed forms (under-, critically and
  over-damped, :class:`Oscillator`);  x = psi - xi (eq. ``xi-psi``);
* impact (eq. ``collision-rule``): psi' and xi' are exchanged at x = 0;
* sticky phase (eqs. ``sticky-cond-Y``, ``y-eq-sticky``): with the lower mass on
  the floor, w = y - y_eq obeys w'' + mu w' + w/2 = 0, the floor force is
  F = y/2 + mu y' - gamma - 1/2 = w/2 + mu w' - 2 gamma (eq. ``force-on-the-floor``)
  and the mass detaches at the first F = 0 with F' > 0 (eq. ``cond_di_distacco``).

States use the same deviation variables as the package's public API so that
the same float64 numbers can be fed to both: x, u = xdot, a = xi' and
eta = xi + gamma (y = 1 - 2 gamma + x + 2 eta).  Every float64 input is converted
exactly; all arithmetic is done with ``DPS`` decimal digits.

Root search that cannot skip a root (:func:`first_root`): the interval to
search is cut recursively.  On [t0, t1] a function f with |f''| <= B satisfies
f >= (linear interpolation of the end values) - B h^2/8 (h = t1 - t0), so an
interval with both end values above B h^2/8 holds no root and is discarded.
An interval with f(t0) > 0 >= f(t1) and f'(t0) + B h < 0 holds exactly one root
(f is strictly decreasing there), which is then polished by bracketed Newton.
Anything else is halved, left half first, so the root returned is the first.
B is a rigorous bound from the closed forms (:meth:`Oscillator.sup_abs`).
"""

from __future__ import annotations

import functools
import math
import time
from dataclasses import dataclass

import mpmath
from mpmath import mp, mpf

#: working precision (decimal digits).  Deep in the asymptotic regime x ~ 1e-17
#: is formed from terms ~1e-13 (gamma = 1e-5), so ~4 digits cancel; 50 digits
#: leave > 40 for the comparisons at 1e-14.
DPS = 50


def _hp(fn):
    """Run ``fn`` at DPS digits (restoring the caller's precision afterwards)."""

    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        with mp.workdps(DPS):
            return fn(*args, **kwargs)

    return wrapper


def M(v) -> mpf:
    """Exact conversion of a float (or int, or mpf) to mpf."""
    return v if isinstance(v, mpf) else mpf(v)


class RootSearchError(RuntimeError):
    """The search met a tangency below the working precision."""


class Oscillator:
    """z'' + 2 beta z' + k z = 0 (beta >= 0, k > 0): closed forms and bounds."""

    def __init__(self, beta, k):
        self.beta = M(beta)
        self.k = M(k)
        disc = self.beta**2 - self.k
        if disc < 0:
            self.branch = "under"
            self.w = mp.sqrt(-disc)
        elif disc == 0:
            self.branch = "critical"
        else:
            self.branch = "over"
            kappa = mp.sqrt(disc)
            self.kappa = kappa
            self.r_fast = -self.beta - kappa
            self.r_slow = -self.k / (self.beta + kappa)  # = -beta + kappa, no cancellation

    def value(self, z0, z1, t):
        """(z(t), z'(t)) for z(0) = z0, z'(0) = z1."""
        b, k = self.beta, self.k
        if self.branch == "under":
            w = self.w
            e = mp.exp(-b * t)
            s, c = mp.sin(w * t), mp.cos(w * t)
            return (e * (z0 * c + (z1 + b * z0) / w * s),
                    e * (z1 * c - (b * z1 + k * z0) / w * s))
        if self.branch == "critical":
            e = mp.exp(-b * t)
            q = z1 + b * z0
            return e * (z0 + q * t), e * (z1 - b * q * t)
        A, B = self._modes(z0, z1)
        e1, e2 = mp.exp(self.r_slow * t), mp.exp(self.r_fast * t)
        return A * e1 + B * e2, A * self.r_slow * e1 + B * self.r_fast * e2

    def _modes(self, z0, z1):
        d = self.r_slow - self.r_fast  # = 2 kappa
        return (z1 - self.r_fast * z0) / d, (self.r_slow * z0 - z1) / d

    def sup_abs(self, z0, z1, t0):
        """A rigorous upper bound of |z(t)| over t >= t0 (t0 >= 0)."""
        b = self.beta
        if self.branch == "under":
            amp = mp.sqrt(z0**2 + ((z1 + b * z0) / self.w) ** 2)
            return amp * mp.exp(-b * t0)
        if self.branch == "critical":
            q = abs(z1 + b * z0)
            # max of t e^{-b t} over t >= t0 is at max(t0, 1/b)
            tm = max(t0, 1 / b)
            return abs(z0) * mp.exp(-b * t0) + q * tm * mp.exp(-b * tm)
        A, B = self._modes(z0, z1)
        return abs(A) * mp.exp(self.r_slow * t0) + abs(B) * mp.exp(self.r_fast * t0)


def _refine(f, df, lo, hi):
    """The root of f in (lo, hi], f(lo) > 0 >= f(hi), f' < 0 on [lo, hi]: safeguarded Newton.

    Converged when a Newton step is below tol |t| (tol = 2^-(prec - 8)) or the bracket [lo, hi], which
    always holds a sign change of the computed f, is narrower than tol |hi|.  Newton steps are taken only
    inside the bracket and only while each is at most half the one before; otherwise the bracket is
    bisected.  So the steps shrink geometrically and the bracket halves at every bisection: at most
    ~2 prec evaluations.  The safeguard matters where f is evaluated with an absolute error delta far
    above tol |t f'| (x = psi - xi formed from terms ~|xi(0)| while x ~ u t: at mu = 0, gamma = 10^-2.5,
    u = 1.1e-11 the computed f is a staircase with steps 5.5e-76 at 243 bits, and Newton alone cycled
    across one of them for ever).  Error bound: tol |t| + delta / min |f'| on the bracket.
    """
    tol = mpf(2) ** (-(mp.prec - 8))
    t = hi
    ft = f(t)
    last_move = hi - lo
    for _ in range(4 * mp.prec):
        if ft == 0:
            return t
        step = -ft / df(t)
        if abs(step) <= tol * abs(t):
            return t + step  # converged: one more step is below the working precision
        t_new = t + step
        if not lo < t_new < hi or abs(step) > last_move / 2:
            t_new = (lo + hi) / 2  # Newton left the bracket or stalls at the rounding of f: bisect
        last_move = abs(t_new - t)
        t = t_new
        ft = f(t)
        if ft > 0:
            lo = t
        else:
            hi = t
        if hi - lo <= tol * abs(hi):
            return hi
    raise RootSearchError("Newton refinement did not converge")


def first_root(f, df, d2_bound, t_a, t_b, f_a=None, f_b=None, min_width=None):
    """First t in (t_a, t_b] with f(t) = 0, or None if f > 0 on [t_a, t_b].

    Requires f(t_a) > 0.  ``d2_bound(t0)`` must bound |f''| on [t0, t_b].
    """
    f_a = f(t_a) if f_a is None else f_a
    f_b = f(t_b) if f_b is None else f_b
    if not f_a > 0:
        raise ValueError("first_root needs f(t_a) > 0")
    if min_width is None:
        min_width = (abs(t_b) + 1) * mpf(2) ** (-(mp.prec - 16))
    stack = [(t_a, f_a, t_b, f_b)]
    while stack:
        t0, f0, t1, f1 = stack.pop()
        h = t1 - t0
        B = d2_bound(t0)
        if f1 > 0 and min(f0, f1) > B * h * h / 8:
            continue  # root-free interval
        if f1 <= 0 and df(t0) + B * h < 0:
            return _refine(f, df, t0, t1)  # the unique root of this interval
        if h <= min_width:
            raise RootSearchError(f"unresolved tangency near t = {mpmath.nstr(t0, 20)}")
        tm = t0 + h / 2
        fm = f(tm)
        stack.append((tm, fm, t1, f1))
        stack.append((t0, f0, tm, fm))
    return None


@dataclass
class Flight:
    """Free flight from (x0, u, a, eta) at t = 0, exact closed form."""

    gamma: mpf
    mu: mpf
    x0: mpf
    u: mpf
    a: mpf
    eta: mpf

    def __post_init__(self):
        self.osc = Oscillator(self.mu, 1)
        self.xi0 = self.eta - self.gamma
        self.psid0 = self.u + self.a  # psi' = xdot + xi'
        # initial data of xi'' (a solution of the same equation)
        mu = self.mu
        self.xi2 = -self.xi0 - 2 * mu * self.a
        self.xi3 = -self.a - 2 * mu * self.xi2

    def xi(self, t):
        return self.osc.value(self.xi0, self.a, t)

    def x(self, t):
        xi, _ = self.xi(t)
        return self.x0 + self.psid0 * t - self.gamma * t * t / 2 - (xi - self.xi0)

    def xdot(self, t):
        _, xid = self.xi(t)
        return self.psid0 - self.gamma * t - xid

    def scale(self, t):
        """Rounding yardstick of x(t): the sum of the magnitudes of its terms
        x0 + u t + a (t - S) - gamma (t^2/2 + 1 - c) + eta (1 - c), with c, S the
        fundamental solutions; a relative change eps of each state component
        changes x(t) by at most eps * scale."""
        c, _ = self.osc.value(mpf(1), mpf(0), t)
        S, _ = self.osc.value(mpf(0), mpf(1), t)
        return (abs(self.x0) + abs(self.u) * t + abs(self.a) * abs(t - S)
                + self.gamma * (t * t / 2 + abs(1 - c)) + abs(self.eta) * abs(1 - c))

    def x2_bound(self, t0):
        """Bound of |x''| = |gamma + xi''| on [t0, inf)."""
        return self.gamma + self.osc.sup_abs(self.xi2, self.xi3, t0)

    def horizon(self):
        """A time T > 0 with x(T) < 0 (psi falls without bound, xi stays bounded)."""
        xi_sup = self.osc.sup_abs(self.xi0, self.a, 0)
        c = self.x0 + abs(self.xi0) + xi_sup + 1
        p = self.psid0
        return (p + mp.sqrt(p * p + 2 * self.gamma * c)) / self.gamma * 2

    def first_contact(self):
        """Time of the first x = 0 after t = 0."""
        if self.x0 > 0:
            t_a = mpf(0)
        elif self.x0 == 0 and self.u > 0:
            # x(t) >= u t - B t^2/2 > 0 on (0, 2u/B): start the search at u/B
            t_a = self.u / self.x2_bound(0)
        elif self.x0 == 0 and self.u == 0 and -self.gamma - self.xi2 > 0:
            # lift-off from rest, x''(0) = A > 0: x(t) >= A t^2/2 - M3 t^3/6 with
            # M3 >= |x'''| = |xi'''|, positive on (0, 3A/M3): start at 1.5 A/M3
            A = -self.gamma - self.xi2
            M3 = self.osc.sup_abs(self.xi3, -self.xi2 - 2 * self.mu * self.xi3, 0)
            t_a = mpf(3) / 2 * A / M3
        else:
            raise ValueError("flight must start above the floor, moving up, or accelerating up")
        T = self.horizon()
        fT = self.x(T)
        while not fT < 0:
            T *= 2
            fT = self.x(T)
        tau = first_root(self.x, self.xdot, self.x2_bound, t_a, T, f_b=fT)
        if tau is None:
            raise RootSearchError("no contact before the horizon")
        return tau

    def impact_state(self, tau):
        """State just after an impact at tau (psi' <-> xi' exchanged)."""
        xi, xid = self.xi(tau)
        psid = self.psid0 - self.gamma * tau
        return Dev(x=mpf(0), u=xid - psid, a=psid, eta=xi + self.gamma)


@dataclass
class Dev:
    """A state in deviation variables (x, u = xdot, a = xi', eta = xi + gamma)."""

    x: mpf
    u: mpf
    a: mpf
    eta: mpf

    def floats(self):
        return float(self.x), float(self.u), float(self.a), float(self.eta)


@_hp
def energy_excess(gamma, st: Dev):
    """E - E_m (eqs. tot-mech-energy, Emin) of a state."""
    g = M(gamma)
    return (st.a**2 + (st.u + st.a) ** 2 + st.eta**2) / 2 + g * st.x


@_hp
def flight_step(gamma, mu, x0, u, a, eta):
    """One flight and impact: returns (tau, Dev just after the impact)."""
    fl = Flight(*(M(v) for v in (gamma, mu, x0, u, a, eta)))
    tau = fl.first_contact()
    return tau, fl.impact_state(tau)


@_hp
def flight_x(gamma, mu, x0, u, a, eta, times):
    """x(t) and its float64 rounding yardstick at the given times of a flight."""
    fl = Flight(*(M(v) for v in (gamma, mu, x0, u, a, eta)))
    return [(fl.x(M(t)), fl.scale(M(t))) for t in times]


@_hp
def x2_bound0(gamma, mu, u, a, eta):
    """Rigorous bound of |x''| over a whole flight starting at (0, u, a, eta)."""
    fl = Flight(*(M(v) for v in (gamma, mu, 0.0, u, a, eta)))
    return fl.x2_bound(mpf(0))


@_hp
def free_flight(gamma, mu, x0, u, a, eta, t) -> Dev:
    """State at time t of the free flight (no floor) from (x0, u, a, eta): t of either sign (the closed
    forms of :class:`Oscillator` hold for every real t), so a contact state can be evolved backward."""
    fl = Flight(*(M(v) for v in (gamma, mu, x0, u, a, eta)))
    t = M(t)
    xi, xid = fl.xi(t)
    return Dev(x=fl.x(t), u=fl.xdot(t), a=xid, eta=xi + fl.gamma)


@_hp
def backward_contact(gamma, mu, a_pre, eta, v, T, n_check: int = 24) -> tuple[Dev, mpf]:
    """A start state that reaches the contact (x = 0, xdot = -v, xi' = a_pre, eta) after a time T.

    The contact state is evolved backward by T; T is halved (at most 30 times) until x > 0 at the
    n_check grid points of (-T, 0), so the flight from the start meets the floor first at T (up to a
    dip between grid points, which the forward simulation would report).  Returns (start as mpf, T).
    """
    T = M(T)
    through_contact = Flight(*(M(w) for w in (gamma, mu, 0, -M(v), a_pre, eta)))  # the free flight of free_flight
    for _ in range(30):
        if all(through_contact.x(-T * (k + 1) / n_check) > 0 for k in range(n_check)):
            return free_flight(gamma, mu, 0, -M(v), a_pre, eta, -T), T
        T /= 2
    raise ValueError("could not find a backward flight that stays above the floor")


def _impacts(g, m, st: Dev):
    """Endless (t, tau, state after the impact) of the exact dynamics from ``st`` (mpf), at the working precision."""
    t = mpf(0)
    while True:
        fl = Flight(g, m, st.x, st.u, st.a, st.eta)
        tau = fl.first_contact()
        st = fl.impact_state(tau)
        t += tau
        yield t, tau, st


@_hp
def trajectory(gamma, mu, start: Dev, n_impacts):
    """Impact times, flight times and post-impact states of the exact dynamics
    (impacts only) from ``start`` at t = 0: lists of length n_impacts."""
    ts, taus, states = [], [], []
    impacts = _impacts(M(gamma), M(mu), Dev(*(M(v) for v in (start.x, start.u, start.a, start.eta))))
    for _, (t, tau, st) in zip(range(n_impacts), impacts):
        ts.append(t)
        taus.append(tau)
        states.append(st)
    return ts, taus, states


def impacts_at(gamma, mu, start: Dev, n_impacts: int, dps: int, cpu_budget: float = math.inf) -> dict:
    """The impacts of :func:`trajectory` at ``dps`` decimal digits instead of DPS, for precision studies
    (:mod:`bounce.studies.horizon`), stopping early at a tangency the search cannot resolve or when the
    process has used ``cpu_budget`` CPU seconds.

    Returns lists ``t``, ``xdot``, ``xidot``, ``eta`` (mpf at ``dps`` digits: each value carries the
    rounding of this precision, which is the point), ``n`` reached, ``stop`` ("max_events", "tangency"
    or "budget"), ``eps`` = 2^(1 - prec) of the working precision and ``cpu`` seconds.
    """
    out = {"t": [], "xdot": [], "xidot": [], "eta": []}
    stop = "max_events"
    t0 = time.process_time()
    with mp.workdps(int(dps)):
        eps = mpf(2) ** (1 - mp.prec)
        impacts = _impacts(M(gamma), M(mu), Dev(*(M(v) for v in (start.x, start.u, start.a, start.eta))))
        for _ in range(int(n_impacts)):
            try:
                t, _, st = next(impacts)
            except RootSearchError:
                stop = "tangency"
                break
            for key, v in zip(out, (t, st.u, st.a, st.eta)):
                out[key].append(v)
            if time.process_time() - t0 > cpu_budget:
                stop = "budget"
                break
    return {**out, "n": len(out["t"]), "stop": stop, "eps": eps, "cpu": time.process_time() - t0}


# --------------------------------------------------------------------------
# sticky phase
# --------------------------------------------------------------------------


class Sticky:
    """Lower mass at rest on the floor: w = y - y_eq, w'' + mu w' + w/2 = 0."""

    def __init__(self, gamma, mu, w0, wd0):
        self.gamma, self.mu = M(gamma), M(mu)
        self.osc = Oscillator(self.mu / 2, mpf(1) / 2)
        self.w0, self.wd0 = w0, wd0
        mu = self.mu
        # G = w/2 + mu w' is again a solution; F = G - 2 gamma
        w2 = -mu * wd0 - w0 / 2
        w3 = -mu * w2 - wd0 / 2
        w4 = -mu * w3 - w2 / 2
        self.G0 = w0 / 2 + mu * wd0
        self.G1 = wd0 / 2 + mu * w2
        self.G2 = w2 / 2 + mu * w3
        self.G3 = w3 / 2 + mu * w4

    def w(self, t):
        return self.osc.value(self.w0, self.wd0, t)

    def force(self, t):
        G, _ = self.osc.value(self.G0, self.G1, t)
        return G - 2 * self.gamma

    def force_dot(self, t):
        _, Gd = self.osc.value(self.G0, self.G1, t)
        return Gd

    def detach_time(self):
        """First t > 0 with F = 0, F' > 0, or None if F < 0 forever (proved)."""
        g = lambda t: -self.force(t)  # noqa: E731
        dg = lambda t: -self.force_dot(t)  # noqa: E731
        d2 = lambda t0: self.osc.sup_abs(self.G2, self.G3, t0)  # noqa: E731
        g0, dg0 = g(mpf(0)), dg(mpf(0))
        if g0 > 0:
            t_a = mpf(0)  # F(0) < 0: pressed on the floor
        elif dg0 > 0:
            # onset, F(0) = 0 up to the rounding of the input, F'(0) < 0:
            # g(t) >= g0 + g'0 t - B0 t^2/2 > 0 around t = g'0/B0 if g0 ~ 0
            B0 = d2(mpf(0))
            t_a = dg0 / B0
            if not g0 + dg0**2 / (2 * B0) > 0 or not g(t_a) > 0:
                raise ValueError("F(0) > 0 beyond rounding: not a sticky state")
        else:
            raise ValueError("F(0) >= 0 and F'(0) >= 0: not a sticky state")
        if self.mu == 0:
            # undamped: F is periodic, a return of F to 0 happens within one period if ever
            T = t_a + 2 * mp.pi / self.osc.w
        else:
            # beyond T the envelope of G is below 2 gamma: F < 0 for ever after
            T = mpf(1)
            while self.osc.sup_abs(self.G0, self.G1, T) >= 2 * self.gamma:
                T *= 2
        if T <= t_a:
            return None
        return first_root(g, dg, d2, t_a, T)


@_hp
def rest_state(gamma, initial):
    """(w0, ydot0) = (y - y_eq, ydot), exactly, of a start state given either as
    (x, xdot, y, ydot) (attributes x, xdot, y, ydot) or in deviation variables
    (attributes x, xdot, xidot, eta: y - y_eq = x + 2 eta, ydot = xdot + 2 xi')."""
    if hasattr(initial, "eta"):
        return M(initial.x) + 2 * M(initial.eta), M(initial.xdot) + 2 * M(initial.xidot)
    return M(initial.y) - (1 - 2 * M(gamma)), M(initial.ydot)


@_hp
def sticky_detach(gamma, mu, w0, ydot0):
    """Detach time of a sticky phase starting at x = xdot = 0, y - y_eq = w0, ydot = ydot0.

    Returns (t_d, (w, w') at t_d), or (None, None) if the mass never detaches
    (proved: F < 0 up to the time where the envelope of G = w/2 + mu w' falls
    below 2 gamma for ever).
    """
    st = Sticky(M(gamma), M(mu), M(w0), M(ydot0))
    td = st.detach_time()
    if td is None:
        return None, None
    return td, st.w(td)


@_hp
def sticky_y_minus_yeq(gamma, mu, w0, ydot0, times):
    """y(t) - y_eq during a sticky phase started at (0, 0, y_eq + w0, ydot0)."""
    st = Sticky(M(gamma), M(mu), M(w0), M(ydot0))
    return [st.w(M(t))[0] for t in times]


@_hp
def condition_numbers(gamma, mu, x0, u, a, eta):
    """Relative condition numbers of (tau, xdot, xidot, eta) after one flight.

    kappa_q = sum_i |d q / d z_i| |z_i| / |q| over the state components z_i,
    by a central difference at relative step 1e-20 (the map is smooth there).
    kappa_q * 2^-53 is the error a solver would show if its only fault were to
    perturb each input component by half an ulp (backward stability).
    """
    z0 = [M(v) for v in (x0, u, a, eta)]

    def outputs(z):
        tau, st = flight_step(gamma, mu, *z)
        return [tau, st.u, st.a, st.eta]

    base = outputs(z0)
    kappa = [mpf(0)] * 4
    h = mpf("1e-20")
    for i in range(4):
        if z0[i] == 0:
            continue
        zp, zm = list(z0), list(z0)
        zp[i] = z0[i] * (1 + h)
        zm[i] = z0[i] * (1 - h)
        op, om = outputs(zp), outputs(zm)
        for j in range(4):
            kappa[j] += abs((op[j] - om[j]) / (2 * h * base[j]))
    return [float(k) for k in kappa]


@_hp
def fundamental_parts(mu, t):
    """(1 - c, t - S, 1 - S', c, S, S') of xi'' + 2 mu xi' + xi = 0 at t, as floats.

    c, S are the solutions with (c, c') = (1, 0) and (S, S') = (0, 1) at t = 0; the small
    parts are formed at DPS digits, enough for the cancellation ~mu^2 of 1 - c at mu <= 1e10.
    """
    osc = Oscillator(M(mu), 1)
    t = M(t)
    c = osc.value(1, 0, t)[0]
    S, Sd = osc.value(0, 1, t)
    return tuple(float(v) for v in (1 - c, t - S, 1 - Sd, c, S, Sd))

"""A Hertz sticky onset reached from a flight (eq. sticky-condition: x = x' = x'' = 0, x''' < 0).

Such a landing is not generic (two conditions on the flight), so it is constructed backwards, as
tests/exact/test_events.py does for the linear law: at the onset the lower mass is on the floor at rest
(x = x' = 0) with the spring at xi_c < 0 and xi' = v chosen so that the floor force vanishes,

    F = f(xi_c) + 2 mu v |xi_c|^b - gamma = 0,   i.e.  v = (gamma + rho |xi_c|^(a+1)) / (2 mu |xi_c|^b),

and F' = x''' < 0 (bounce.series.flight.floor_force: F' = f'(xi) v + 2 mu b |xi|^(b-1) sign(xi) v^2
- 2 mu gamma |xi|^b at F = 0).  For Hertz (rho = 1, a = b = 1/2) and xi_c < 0 this needs the
damping to lift the lower mass (v > 0), and the sticky phase that follows crosses the rest length
xi = 0 before it detaches (a scan of gamma in {0.01, 0.05, 0.1}, mu in [0.02, 2], |xi_c| in
[0.005, 1] found no onset whose sticky phase detaches with xi < 0 throughout, so the reference
must cross xi = 0).  The flight before the onset is integrated backwards for a time T with
mpmath.odefun (time reversed: z(s) = xi(T - s) solves z'' = -f(z) + 2 mu z' |z|^b; xi < 0 on it,
where the field is analytic), psi is the exact parabola, and the start (x, x', xi', xi) is
rounded to float64.

Independent references, written here from the Discussion's equations and sharing no code with
bounce: the flight (mpmath.odefun, both sides of the onset), and the sticky phase
xi'' = -(gamma + f(xi) + 2 mu xi' |xi|^b)/2 (bounce.series.sticky, eq. (ST)) through xi = 0 to its
detach (F = 0, F' > 0, eq. cond_di_distacco), integrated in s = sqrt(|xi|) as the independent
variable: while xi' > 0, d xi' / ds = 2 s xi'' / xi' and dt/ds = 2 s / xi' with |xi|^(1/2) = s, a
field analytic in s on each side of xi = 0 (mpmath.odefun again; the crossing is the end point of
one integration and the start of the next).  Each reference is checked at two precisions.
"""

from __future__ import annotations

import functools

import mpmath
import numpy as np
import pytest
from mpmath import mp, mpf

import power_reference as PR

from bounce import Deviations, Parameters
from bounce.kinds import GRAZING, IMPACT
from bounce.exact.events import contact_window
from bounce.series.events import simulate_power
from bounce.series.flight import floor_force
from bounce.series.taylor import L_XI_EQ, law_array
from bounce.springs.power import PowerSpring

HERTZ = PowerSpring(1.0, 0.5, 0.5)
EPS = np.finfo(float).eps
DPS = 20  #: working digits of the references (their error is ~1e-20 relative: test_references_two_precisions_agree)
#: (gamma, mu, xi_c, T): the onset's spring compression and the flight time before it
ONSETS = {"g0.1_mu1": (0.1, 1.0, -0.05, 0.3), "g0.01_mu0.2": (0.01, 0.2, -0.01, 0.3)}


def onset_state(gamma, mu, xi_c):
    """(xi', F') at the onset x = x' = 0, xi = xi_c < 0 with F = 0 (Hertz, rho = 1)."""
    g, m, w = mpf(gamma), mpf(mu), -mpf(xi_c)
    v = (g + w ** mpf(1.5)) / (2 * m * mp.sqrt(w))
    Fp = mpf(1.5) * mp.sqrt(w) * v - m * v * v / mp.sqrt(w) - 2 * m * g * mp.sqrt(w)
    return v, Fp


class Flight:
    """The Hertz flight through the onset (x = 0, psi' = xi' = v at t = T): (x, x', xi, xi') at t."""

    def __init__(self, gamma, mu, xi_c, T):
        self.g, self.mu, self.xi_c, self.T = mpf(gamma), mpf(mu), mpf(xi_c), mpf(T)
        self.v, self.Fp = onset_state(gamma, mu, xi_c)
        m = self.mu
        # backwards, z(s) = xi(T - s): z'' = -f(z) + 2 mu z' |z|^(1/2); forwards the flight's own equation
        self.back = mpmath.odefun(lambda s, y: [y[1], -y[0] * mp.sqrt(abs(y[0])) + 2 * m * y[1] * mp.sqrt(abs(y[0]))],
                                  0, [self.xi_c, -self.v])
        self.fwd = mpmath.odefun(lambda s, y: [y[1], -y[0] * mp.sqrt(abs(y[0])) - 2 * m * y[1] * mp.sqrt(abs(y[0]))],
                                 0, [self.xi_c, self.v])

    def state(self, t):
        tau = mpf(t) - self.T
        if tau < 0:
            xi, z1 = self.back(-tau)
            xid = -z1
        else:
            xi, xid = self.fwd(tau)
        # psi = x + xi is the parabola through the onset: psi(T) = xi_c, psi'(T) = v; x as a displacement
        x = (self.xi_c - xi) + self.v * tau - self.g * tau * tau / 2
        return x, self.v - self.g * tau - xid, xi, xid

    def start(self, xi_eq):
        """The state at t = 0 rounded to float64, eta = xi - xi_eq of the solver's float xi_eq."""
        x, xd, xi, xid = self.state(0)
        return Deviations(float(x), float(xd), float(xid), float(xi - mpf(xi_eq)))


def sticky_inward(gamma, mu, xi0, v0):
    """(s0, (xi', t) as functions of r) on the xi < 0 side: xi = -(s0 - r)^2, s0 = sqrt(-xi0), r in [0, s0]."""
    g, m, xi0, v0 = (mpf(q) for q in (gamma, mu, xi0, v0))
    s0 = mp.sqrt(-xi0)

    def inward(r, y):  # f = -s^3, |xi|^(1/2) = s = s0 - r, dxi/dr = 2 s
        s = s0 - r
        acc = -(g - s**3 + 2 * m * y[0] * s) / 2
        return [2 * s * acc / y[0], 2 * s / y[0]]

    return s0, mpmath.odefun(inward, 0, [v0, mpf(0)])


def sticky_reference(gamma, mu, xi0, v0):
    """Hertz sticky phase from (xi0 < 0, xi' = v0 > 0) through xi = 0 to its detach (module docstring):
    (t_detach, xi, xi', F_in) as mpf, F_in the largest F sampled on the xi < 0 side after the start
    (where F = 0 at an onset); xi' must stay > 0 (asserted at the crossing and the detach; a zero in
    between would stop odefun, which divides by it)."""
    g, m = mpf(gamma), mpf(mu)
    s0, sol_in = sticky_inward(gamma, mu, xi0, v0)

    def outward(s, y):  # xi = s^2
        acc = -(g + s**3 + 2 * m * y[0] * s) / 2
        return [2 * s * acc / y[0], 2 * s / y[0]]

    # no detach before xi = 0: F = -s^3 + 2 mu xi' s - gamma < 0 after the start (sampled)
    F_in = max(-(s0 - r) ** 3 + 2 * m * sol_in(r)[0] * (s0 - r) - g for r in np.linspace(0.05, 1, 20) * s0)
    v_c, t_c = sol_in(s0)
    sol_out = mpmath.odefun(outward, 0, [v_c, t_c])

    def F(s):
        return s**3 + 2 * m * sol_out(s)[0] * s - g

    s, h = mpf(0), s0 / 64  # F(0) = -gamma; the first sign change - to + on a grid of s0/64
    while F(s + h) < 0:
        s += h
    s_d = mp.findroot(F, (s, s + h), solver="anderson")
    v_d, t_d = sol_out(s_d)
    assert v_c > 0 and v_d > 0, "the reference needs xi' > 0 from the start to the detach"
    return t_d, s_d * s_d, v_d, F_in


@functools.lru_cache(maxsize=None)
def built(name):
    """(gamma, mu, T, law, xi_eq, flight reference, rounded start) of ONSETS[name]."""
    gamma, mu, xi_c, T = ONSETS[name]
    law = law_array(1.0, 0.5, 0.5, mu, gamma)
    xi_eq = float(law[L_XI_EQ])
    with mp.workdps(DPS):
        flight = Flight(gamma, mu, xi_c, T)
        d = flight.start(xi_eq)
    return gamma, mu, T, law, xi_eq, flight, d


@pytest.fixture(params=list(ONSETS))
def onset(request):
    return built(request.param)


def test_onset_construction(onset):
    """The constructed landing: F = 0 and F' < 0 at the onset (bounce's floor_force agrees to
    rounding) and x > 0 on [0, T) (sampled): the flight's first contact is the onset."""
    gamma, mu, T, law, xi_eq, flight, d = onset
    with mp.workdps(DPS):
        assert flight.Fp < 0 and d.x > 0
        assert all(flight.state(T * k / 64)[0] > 0 for k in range(64))
        F, Fp, noise_F, noise_Fp = floor_force(float(flight.v), float(flight.xi_c - mpf(xi_eq)), law)
        assert abs(F) <= noise_F and abs(Fp - float(flight.Fp)) <= noise_Fp + 1e-15 * abs(Fp)


def test_references_two_precisions_agree():
    """The references' own truncation and rounding: the flight's start and the sticky phase's
    detach at DPS and DPS + 4 digits agree to 10^(2 - DPS) relative (far below the 1e-15 used)."""
    gamma, mu, xi_c, T = ONSETS["g0.1_mu1"]
    flight = built("g0.1_mu1")[5]
    with mp.workdps(DPS):
        low = flight.state(0), sticky_reference(gamma, mu, flight.xi_c, flight.v)[:3]
    with mp.workdps(DPS + 4):
        fine = Flight(gamma, mu, xi_c, T)
        high = fine.state(0), sticky_reference(gamma, mu, fine.xi_c, fine.v)[:3]
        tol = mpf(10) ** (2 - DPS)
        for lo, hi in zip(low, high):
            assert all(abs(a - b) <= tol * abs(b) for a, b in zip(lo, hi)), (lo, hi)


def test_sticky_reference_agrees_with_the_time_stepped_one():
    """On the xi < 0 side the s = sqrt|xi| reference meets tests/power_reference.reference_sticky
    (Taylor steps in t, the reference of tests/series/test_series_sticky.py): from the onset of g0.1_mu1
    to half-way to xi = 0 in s (t = 0.155), xi and xi' agree to 10^(2 - DPS) relative (measured:
    3e-23 in xi, 0 in xi')."""
    gamma, mu, T, law, xi_eq, flight, d = built("g0.1_mu1")
    with mp.workdps(DPS):
        s0, sol_in = sticky_inward(gamma, mu, flight.xi_c, flight.v)
        v_half, t_half = sol_in(s0 / 2)
        stepped = PR.reference_sticky(gamma, mu, 1.0, 0.5, 0.5, flight.v, flight.xi_c, t_half, dps=DPS)
        assert stepped["t_detach"] is None
        tol = mpf(10) ** (2 - DPS)
        assert abs(stepped["xi"] + s0**2 / 4) <= tol * s0**2 / 4 and abs(stepped["xidot"] - v_half) <= tol * v_half


def contact_scale(d, gamma, T, xi_T, xi_eq):
    """The flight's rounding scale at the contact, as bounce.series.flight._contact forms it: the
    terms of x = x0 + u0 t - gamma t^2/2 - (xi(t) - xi0) over the flight."""
    return d.x + abs(d.xdot) * T + 0.5 * gamma * T * T + abs(float(xi_T) - (xi_eq + d.eta) - d.xidot * T)


@functools.lru_cache(maxsize=None)
def exact_detach(name):
    """(t_detach - T, S = d t_detach / d xi'(T)) of the exact hybrid motion: sticky from the onset on."""
    gamma, mu, T, law, xi_eq, flight, d = built(name)
    with mp.workdps(DPS):
        td = sticky_reference(gamma, mu, flight.xi_c, flight.v)[0]
        step = mpf(10) ** -9
        return td, (sticky_reference(gamma, mu, flight.xi_c, flight.v + step)[0] - td) / step


@pytest.mark.parametrize("name, ulps", [("g0.1_mu1", 0), ("g0.01_mu0.2", 0), ("g0.1_mu1", -32)])
def test_onset_from_a_flight_is_a_sticky_start_then_the_reference_detach(name, ulps):
    """The rounded start lands on the floor within the classifier's window of the exact onset.

    Expectation: sticky_start, not an impact or a grazing.  Rounding the start moves x near the
    onset by at most the contact's rounding level xn (bounce.exact.events.rounding_level), and x ~ F' s^3/6
    there (s = t - T, x'' = F = 0), so the rounded flight meets the floor within delta3 =
    (6 xn/|F'|)^(1/3) of T, with |x'| <= |F'| delta3^2/2 and x'' <= |F'| delta3: below the
    tangential speed and the onset window of bounce.exact.events.contact (4 times these), i.e. a
    sticky onset to rounding; test_perturbed_starts_are_impacts_or_misses shows that perturbations
    beyond xn are impacts.  ``ulps``: the start's x moved by that many ulps, still within xn; -32
    ulps (7e-18, ~7x the start's own rounding) lowers the flight, so the onset is found early
    (t0 < T) with F = |F'| (T - t0) > 0 recorded, a start the sticky phase counts as F = 0.
    Checked:
      * sticky_start within 2 delta3 of T, x' = 0, and the state there the exact flight's at the
        recorded time t0 (xi, xi' to 1e-15 of |xi'| + |eta| + gamma);
      * the sticky phase from that state, through xi = 0, to the detach: time, xi, xi' to 1e-14
        (the reference started from the exact flight at t0, not from the solver's numbers);
      * against the exact hybrid motion (sticky from T on), the detach moves by the onset's offset
        dt = t0 - T at second order only: the flight and the sticky motion share xi, xi', xi''
        at F = 0 and their xi'' differ by F/2 ~ F' (t - T)/2 (flight -gamma - F, sticky -gamma - F/2),
        so on either side (late: flight where it should be sticky, F < 0; early: sticky where it
        should fly, F > 0) the sticky phase runs with xi' too large by |F'| dt^2/4; the detach then
        moves by S |F'| dt^2/4, S = d t_detach / d xi' of the reference (finite difference), to 10%
        (the next order is O(|dt|) relative; measured for g0.1_mu1 -1.7889e-12 against -1.7886e-12
        predicted at dt = +2.8e-6, -4.1744e-12 against -4.1742e-12 at dt = -4.3e-6).
    """
    gamma, mu, T, law, xi_eq, flight, d = built(name)
    start = Deviations(d.x + ulps * np.spacing(d.x), d.xdot, d.xidot, d.eta)  # x shifted: xi unchanged
    tr = simulate_power(Parameters(gamma, mu, HERTZ), HERTZ, start, max_events=2)
    assert tr.kind_names == ("sticky_start", "detach"), (tr.kind_names, tr.stop_reason)
    with mp.workdps(DPS):
        xn, _, _, delta3 = contact_window(contact_scale(start, gamma, T, flight.xi_c, xi_eq), 0.0, float(flight.Fp))
        assert abs(ulps) * np.spacing(d.x) <= xn
        t0, t1 = tr.t[0], tr.t[1]
        dt = t0 - T
        assert abs(dt) <= 2 * delta3 and tr.xdot[0] == 0.0, (dt, delta3)
        if ulps < 0:
            F = floor_force(tr.xidot[0], tr.eta[0], law)
            assert dt < 0 and F[0] > F[2], (dt, F)  # the early onset this case is for
        _, _, xi0, xid0 = flight.state(t0)  # the exact flight at the recorded onset time
        scale = abs(xid0) + abs(xi0 - xi_eq) + gamma
        assert abs(mpf(tr.xidot[0]) - xid0) <= 1e-15 * scale and abs(xi_eq + mpf(tr.eta[0]) - xi0) <= 1e-15 * scale

        td, xi_d, xid_d, F_in = sticky_reference(gamma, mu, xi0, xid0)
        assert F_in < 0  # no detach before xi = 0
        assert abs(mpf(t1) - (mpf(t0) + td)) <= 1e-14 * t1, (t1, t0 + td)
        scale = abs(xid_d) + abs(xi_d - xi_eq) + gamma
        assert abs(xi_eq + mpf(tr.eta[1]) - xi_d) <= 1e-14 * scale and abs(mpf(tr.xidot[1]) - xid_d) <= 1e-14 * scale

        td_exact, S = exact_detach(name)
        predicted = S * abs(flight.Fp) * mpf(dt) ** 2 / 4
        moved = mpf(t1) - (T + td_exact)
        assert abs(moved - predicted) <= 0.1 * abs(predicted) + 1e-14 * t1, (moved, predicted)


def test_perturbed_starts_are_impacts_or_misses():
    """Non-genericity: perturbed starts of the onset's flight (g0.1_mu1) give impacts, a grazing
    only when tuned on a curve, a sticky onset only at the constructed point.

    Shifting the start's x by dx and x' by du (xi, xi' kept) moves psi only, so the perturbed flight
    is exactly x(t) + dx + du t (x the reference flight; dx, du include the start's own rounding,
    exact in mpmath).  Near T, x ~ F' s^3/6 (F' < 0) is decreasing through the floor, so every small
    (dx, du) meets the floor near T: an impact, at the root t* of x + dx + du t with the speed
    -(x'(t*) + du) (here 2e-9 to 5e-7, far above the tangential threshold of the contact window).
    With du = eps > 0, x + eps t has a local minimum at t_g < T (x'(t_g) = -eps, x'' > 0); tuning dx so
    that it touches the floor gives a grazing (eq. swishes), dx a little lower an impact before t_g,
    a little higher a flight that misses the floor there and lands after T.  Checked against the
    reference: the kind, the time to 2 xn/|x'| (the rounding window of a simple root; xn the
    contact's rounding level), the speed to |x''| times the time's error plus 8 eps of its terms.
    """
    gamma, mu, T, law, xi_eq, flight, d = built("g0.1_mu1")
    params = Parameters(gamma, mu, HERTZ)
    with mp.workdps(DPS):
        x_0, u_0, _, _ = flight.state(0)
        Fp = abs(flight.Fp)

        def first_contact_ref(dx, du, lo, hi):
            root = mp.findroot(lambda t: flight.state(t)[0] + dx + du * t, (mpf(lo), mpf(hi)), solver="anderson")
            x, xd, _, _ = flight.state(root)
            x2 = (flight.state(root + mpf(10) ** -8)[1] - xd) * 10**8  # x'' by a difference (to ~1e-4)
            return root, xd + du, x2

        # tangency of x + du t before T: x'(t_g) = -du, for the start's x' + 1e-8 as rounded
        xdot_graze = float(d.xdot + 1e-8)
        eps_u = mpf(xdot_graze) - u_0
        s_g = float(mp.sqrt(2 * eps_u / Fp))
        t_g = mp.findroot(lambda t: flight.state(t)[1] + eps_u, (T - 3 * s_g, T - s_g / 3), solver="anderson")
        dx_graze = -(flight.state(t_g)[0] + eps_u * t_g)  # x(t_g) + dx + du t_g = 0
        # the tangency itself is decided at the rounding level (the start's rounding of xi, xi' moves x
        # by ~1e-18 there: a miss by that much is as right as a grazing), so the grazing is aimed
        # 2 xn into the floor: a contact of speed ~sqrt(4 x'' xn), tangential for the classifier
        x2_g = float(flight.state(t_g + mpf(10) ** -8)[1] - flight.state(t_g)[1]) * 1e8
        xn_g = contact_window(contact_scale(d, gamma, float(t_g), flight.state(t_g)[2], xi_eq), x2_g, 0.0)[0]
        cases = []  # (dx, du, expected kind, bracket of the first contact)
        for dx in (-1e-10, -1e-13, 1e-13, 1e-10):
            w = 10 * (6 * abs(dx) / float(Fp)) ** (1 / 3)
            cases.append((dx, 0.0, IMPACT, (T - w, T) if dx < 0 else (T, T + w)))
        for du in (-1e-9, 1e-9):  # x + du t: the root moves by ~(6 |du| T / |F'|)^(1/3), before T if du < 0
            w = 10 * (6 * abs(du) * T / float(Fp)) ** (1 / 3)
            cases.append((0.0, du, IMPACT, (T - w, T) if du < 0 else (T, T + w)))
        cases += [(dx_graze - 1e-13, None, IMPACT, (t_g - 3 * s_g, t_g)),
                  (dx_graze - 2 * xn_g, None, GRAZING, None),
                  (dx_graze + 1e-13, None, IMPACT, (T, T + 20 * s_g))]  # misses at t_g, lands after T
        for dx, du, kind, bracket in cases:
            if du is None:  # around the tangency: dx is measured from the exact start, x' as above
                start = Deviations(float(x_0 + dx), xdot_graze, d.xidot, d.eta)
            else:
                start = Deviations(float(d.x + dx), float(d.xdot + du), d.xidot, d.eta)
            dx_e, du_e = mpf(start.x) - x_0, mpf(start.xdot) - u_0  # exact, with the start's rounding
            tr = simulate_power(params, HERTZ, start, max_events=1)
            assert tr.kind[0] == kind, (dx, du, tr.kind_names)
            if kind == GRAZING:  # at t_g within the window delta2 = sqrt(2 xn/x''), nothing exchanged
                delta2 = contact_window(contact_scale(d, gamma, float(t_g), flight.state(t_g)[2], xi_eq), x2_g, 0.0)[2]
                assert abs(tr.t[0] - float(t_g)) <= 2 * delta2 and tr.xdot[0] == 0.0, (tr.t[0], t_g, delta2)
                continue
            t_star, xd_star, x2 = first_contact_ref(dx_e, du_e, *bracket)
            xn = contact_window(contact_scale(start, gamma, float(t_star), flight.state(t_star)[2], xi_eq), 0, 0)[0]
            window = 2 * xn / abs(xd_star)
            assert abs(tr.t[0] - t_star) <= window + 1e-15 * t_star, (dx, du, tr.t[0], t_star, window)
            # the recorded speed is the flight's at the recorded time: x'(t*) + x'' (t - t*), to rounding
            speed_tol = 1.1 * abs(x2) * abs(tr.t[0] - t_star) + 8 * EPS * (abs(start.xdot) + gamma * tr.t[0]
                                                                            + abs(start.xidot))
            assert abs(tr.xdot[0] + xd_star) <= speed_tol, (dx, du, tr.xdot[0], -xd_star, speed_tol)

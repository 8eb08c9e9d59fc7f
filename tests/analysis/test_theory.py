"""The paper's closed forms (bounce.analysis.theory), the fitting helpers (bounce.analysis.fitting) and the reference's
free flight (bounce.analysis.reference), each tested once: against the paper's numbers, sympy/mpmath, the
simulator, or a synthetic sequence with a known answer.
"""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest

from bounce import Deviations, Parameters, State, simulate
from bounce.analysis import fitting, reference, theory
from bounce.exact.flight import gap
from bounce.exact.oscillator import make_oscillator
from bounce.analysis.sticky import sticky_duration


# --------------------------------------------------------------------------- sec. 2, 8: numbers of the paper

def test_rest_coefficient_is_0969_for_mu_001():
    """Sec. 8.1: r = 0.969... for mu = 0.01 (eq. rest-coefficient-function-of-mu)."""
    assert math.floor(theory.rest_coefficient_function_of_mu(0.01) * 1000) == 969


def test_t_c_is_523():
    """Sec. 8.2: t_c = 5.23... (gamma = mu = 0.01 inferred, Ydot0 = -0.1)."""
    assert f"{theory.t_c(0.01, 0.01):.2f}" == "5.23" and math.floor(theory.t_c(0.01, 0.01) * 100) == 523


@pytest.mark.parametrize("mu", [0.0, 0.01, 0.5, 0.999999])
def test_T_xi_against_mpmath(mu):
    with mpmath.workdps(30):
        expect = float(mpmath.pi / mpmath.sqrt(1 - mpmath.mpf(mu) ** 2))
    assert theory.T_xi(mu) == pytest.approx(expect, rel=4e-16)


def test_T_xi_is_the_compiled_kernels_half_period():
    """T_xi evaluates natural_frequency's Python body (no kernel load): the bits of the compiled frequency the engines
    use, on both branches of its formula and near mu = 1."""
    from bounce.exact.oscillator import natural_frequency

    mus = np.concatenate([np.random.default_rng(7).uniform(0.0, 1.0, 20000), [0.0, 1e-16, 0.5, 0.5 - 1e-17, 1 - 1e-16]])
    assert all(theory.T_xi(m) == math.pi / natural_frequency(m) for m in mus)


def test_char_times():
    T_psi, T_x, T_d = theory.char_times(0.02, 0.3)
    assert T_psi == pytest.approx(5.0) and T_x == theory.T_xi(0.3) and T_d == pytest.approx(1 / 0.3)
    assert theory.char_times(0.02, 0.0)[2] == math.inf


@pytest.mark.parametrize("mu", [1.0, 1.5, 2.0])
def test_over_damped_double_impact_is_totally_inelastic(mu):
    """mu >= 1: no half period (T_xi = inf) and r = 0, the limits from below (sec. 8.1: totally inelastic)."""
    assert theory.T_xi(mu) == math.inf and theory.rest_coefficient_function_of_mu(mu) == 0.0
    assert theory.rest_coefficient_function_of_mu(1 - 1e-9) < 1e-100
    assert theory.u_c(0.01, mu) == pytest.approx(3 * 0.01 / mu)


def test_u_c_limits_and_continuity_of_our_r():
    g = 1e-5
    assert theory.u_c(g, 0.0) == pytest.approx(3 * math.pi * g) and theory.u_c(g, 1e-9) == pytest.approx(3 * math.pi * g)
    for mu in (0.01, 0.3, 0.9):
        uc = theory.u_c(g, mu)
        r0 = theory.rest_coefficient_function_of_mu(mu)
        assert abs((1.0 - mu * uc / (3.0 * g)) - r0) < 1e-15
        assert theory.our_r(uc * (1 - 1e-12), g, mu) == pytest.approx(r0, abs=1e-10)
        assert float(theory.our_r(2 * uc, g, mu)) == r0
        assert float(theory.our_r(uc / 2, g, mu, com=True)) == pytest.approx(1 - 2 * mu * uc / 2 / (3 * g))
    assert np.all(theory.our_r(np.geomspace(1e-9, 1.0, 5), g, 0.0) == 1.0)  # mu = 0: no dissipation


def test_E_min_and_energy_against_state():
    g = 0.03
    assert theory.E_min(g) == -g * g / 2
    p = Parameters(g, 0.2)
    s = State(0.0, 0.1, 1 - 2 * g + 0.004, -0.05)  # x, xdot, y, ydot
    xi, psid, xid = (s.y - s.x - 1) / 2, (s.ydot + s.xdot) / 2, (s.ydot - s.xdot) / 2
    assert theory.tot_mech_energy(xi, xid, psid, g) == pytest.approx(s.energy(p), rel=1e-13)


@pytest.mark.parametrize("g, mu", [(0.02, 0.7), (0.01, 0.0), (0.1, 1.3)])
def test_min_sticky_energy_by_mpmath(g, mu):
    """Lemma Min-sticky-energy: eq. sticky-energy on the boundary of eq. z-constraint, minimised in mpmath
    (findroot of its derivative), against eqs. min-sticky-energy and ydot-min-Esticky."""
    with mpmath.workdps(40):
        def E(yd):
            return yd**2 / 4 + (4 * mpmath.mpf(g) - 2 * mpmath.mpf(mu) * yd) ** 2 / 8 - mpmath.mpf(g) ** 2 / 2

        ymin = mpmath.findroot(lambda y: mpmath.diff(E, y), 0.0)
        assert mpmath.diff(E, ymin, 2) > 0
        emin = float(E(ymin))
    yds, z = theory.ydot_min_Esticky(g, mu)
    assert theory.min_sticky_energy(g, mu) == pytest.approx(emin, rel=1e-14)
    assert yds == pytest.approx(float(ymin), rel=1e-14, abs=1e-300)
    assert z == pytest.approx(4 * g - 2 * mu * yds, rel=1e-14)
    assert theory.sticky_energy(yds, z, g) == pytest.approx(emin, rel=1e-13)


# --------------------------------------------------------------------------- sec. 3: sticky oscillator

@pytest.mark.parametrize("mu", [0.0, 0.3, math.sqrt(2.0), 2.0])
def test_sticky_modes_are_the_roots(mu):
    kind, lam, omega = theory.sticky_modes(mu)
    roots = np.roots([1.0, mu, 0.5])
    tol = 4 * math.sqrt(2.2e-16)  # a double root (mu = sqrt 2) moves by ~sqrt(eps) under rounding of mu^2 - 2
    assert lam == pytest.approx(-max(roots.real), abs=tol) and omega == pytest.approx(abs(roots.imag).max(), abs=tol)
    assert kind == ("oscillatory" if mu * mu < 2 else "critical" if mu * mu == 2 else "overdamped")


@pytest.mark.parametrize("mu", [0.0, 0.3, math.sqrt(2.0), 2.0])
def test_sticky_fundamental_solves_the_sticky_oscillator(mu):
    t = np.linspace(0.0, 6.0, 601)
    h = t[1] - t[0]
    for f, f0, fp0 in zip(theory.sticky_fundamental(mu, t), (1.0, 0.0), (0.0, 1.0)):
        assert abs(f[0] - f0) < 1e-15 and abs((f[1] - f[0]) / h - fp0) < 2 * h
        d1 = (f[2:] - f[:-2]) / (2 * h)
        d2 = (f[2:] - 2 * f[1:-1] + f[:-2]) / h**2
        assert np.max(np.abs(d2 + mu * d1 + f[1:-1] / 2)) < 1e-4


def test_sticky_ends_of_the_domain():
    assert theory.eps_star(0.01, 0.0) == (0.0, 2 * math.pi * math.sqrt(2))
    assert theory.eps_star(0.01, 1.5)[0] == math.inf and theory.sticky_duration_infimum(1.5) == math.inf
    assert math.isnan(theory.t_c(0.01, 1.5))
    assert theory.sticky_duration_infimum(0.0) == pytest.approx(math.pi * math.sqrt(2))


def test_t_c_equals_simulator():
    for g, m in [(0.01, 0.01), (0.02, 0.05)]:
        assert math.isfinite(theory.t_c(g, m))
        assert abs(theory.t_c(g, m) - sticky_duration(g, m)) <= 1e-12 * sticky_duration(g, m)


def test_t_c_gamma_band_brackets_the_level():
    lo, hi = theory.t_c_gamma_band(0.01, 5.23, 5.24, (0.005, 0.015))
    assert lo < 0.01 < hi and theory.t_c(lo, 0.01) == pytest.approx(5.23, abs=1e-9)


def test_sticky_onset_is_on_the_sticky_line():
    """eq. sticky-cond-Y: x'' = 0 there, and x''' = -alpha/2 < 0 (an onset)."""
    g, mu, alpha = 0.02, 0.4, 0.003
    a, eta = theory.sticky_onset(g, mu, alpha)
    acc, jerk = theory.contact_derivatives(a, eta, g, mu)
    assert abs(acc) < 1e-17 and jerk == pytest.approx(-alpha / 2, rel=1e-12)


# --------------------------------------------------------------------------- sec. 6: Theorem main_thm

def test_correction_exponent():
    assert theory.correction_exponent(0.01) == 1.0 and theory.correction_exponent(1.5) == pytest.approx(1.0)
    assert theory.correction_exponent(2.0) == pytest.approx(3 * (2 - math.sqrt(2)) / 2 / 2)
    assert theory.correction_exponent(5.0) == pytest.approx(0.06126, abs=1e-5)
    assert theory.correction_exponent(0.0) == 1.0


def test_equilibrium_rates():
    r = theory.equilibrium_rates(0.3)
    assert r == {"energy": pytest.approx(0.2), "xdot": pytest.approx(0.1), "spring": pytest.approx(0.15)}
    lam = (2.0 - math.sqrt(2.0)) / 2
    assert theory.equilibrium_rates(2.0)["spring"] == pytest.approx(lam)
    assert theory.energy_prefactor(0.01, 0.3) == pytest.approx(9e-4 / 0.36)


def test_limits_of_the_proof():
    assert theory.limitex3dot(0.01, 0.3) == (-0.02, pytest.approx(0.006))
    assert theory.delta(0.01, 0.3) == pytest.approx(0.001)
    assert theory.restituzione(0.01, 0.3) == pytest.approx(10.0)
    assert theory.tau_asymptotic(1000, 0.3) == pytest.approx(0.01)


def test_contact_derivatives_match_finite_differences():
    """x'', x''' just after an impact against the numerical derivative of x(t)."""
    from bounce.sampling import sample_trajectory

    p = Parameters(0.01, 0.3)
    tr = simulate(p, State.from_psi_xi(0.5, 0.0, 0.0, 0.0), max_events=5)
    k = 2
    ts = tr.t[k] + 1e-3 * np.arange(1, 6)
    x = sample_trajectory(tr, ts)["x"]
    s = ts - tr.t[k]
    a = np.column_stack([s, s**2 / 2, s**3 / 6, s**4 / 24, s**5 / 120])
    coef = np.linalg.solve(a, x)
    xdd, xddd = theory.contact_derivatives(tr.xidot[k], tr.eta[k], p.gamma, p.mu)
    assert coef[0] == pytest.approx(tr.xdot[k], rel=1e-6)
    assert coef[1] == pytest.approx(xdd, rel=1e-4, abs=1e-8)
    assert coef[2] == pytest.approx(xddd, rel=1e-2, abs=1e-6)


def test_rigid_ball_collapse_time():
    u0, r, g = 0.3, 0.9, 0.01
    k = np.arange(2000)
    assert math.fsum(2 * u0 * r ** (k + 1) / g) == pytest.approx(theory.geometric_map_collapse_time(u0, r, g), rel=1e-12)
    assert theory.geometric_map_collapse_time(u0, 1.0, g) == math.inf
    assert theory.onefifth_rest_coeff(32.0, 1.0e5) == pytest.approx(0.8)  # (32e-5)^(1/5) = 2 x 0.1


# --------------------------------------------------------------------------- bounce.analysis.fitting

def test_fit_limit_recovers_known_limits():
    n = np.arange(1.0, 2e5)
    t = 300.0 * np.log(n)  # t_n ~ (3/mu) ln n, mu = 0.01
    fit = {"n_min": 1000, "settle": 0.1, "min_span": 10.0, "points": 400, "map_orders": 3, "slow_powers": 2}
    for L in (1.0, 1.003):
        q = L + 0.7 * np.log(n) / n - 2.0 / n
        f = fitting.fit_limit(n, t, q, 0.01, fit)
        assert abs(f["limit"] - L) < 1e-9 and f["limit_err"] < 1e-8
        assert f["exponent"] == pytest.approx(1.0, abs=0.01)
    # over-damped: slow spring term e^{-lam t}, t = (3/mu) ln n  ->  n^{-3 lam/mu}
    mu = 2.0
    p = theory.correction_exponent(mu)
    t = 1.5 * np.log(n)
    q = 1.0 - 0.3 * n**-p + 0.05 * n ** (-2 * p) + 0.2 / n
    f = fitting.fit_limit(n, t, q, mu, fit)
    assert abs(f["limit"] - 1.0) < 1e-8
    assert abs(f["exponent"] - p) <= max(3 * f["exponent_err"], 0.02 * p) and f["exponent_err"] < 0.1 * p


def test_fit_basis_returns_its_coefficients():
    """The coefficients come back with the fit (no function attribute): the map terms are recovered."""
    n = np.geomspace(1e3, 1e6, 300)
    q = 1.0 + 0.7 * np.log(n) / n - 2.0 / n
    f = fitting.fit_basis(n, 300.0 * np.log(n), q, 0.01, 3, 2)
    assert f.limit == pytest.approx(1.0, abs=1e-10) and f.coef[1] == pytest.approx(0.7, rel=1e-4)
    assert f.coef[2] == pytest.approx(-2.0, rel=1e-3) and f.rms < 1e-12


def test_tail_exponent_of_uniform_sample():
    rng = np.random.default_rng(0)
    r = np.sort(rng.uniform(0, 1, 200000))[:300]
    p, err, C = fitting.tail_exponent(r, 20, 300)
    assert abs(p - 1) < 0.15 and abs(C - 200000) / 200000 < 0.5  # ranks are correlated: loose


def test_loglog_fits_and_rates():
    x = np.geomspace(1e-5, 1e-2, 7)
    slope, icpt, err = fitting.fit_loglog(x, 0.3 * x**1.6)
    assert slope == pytest.approx(1.6) and math.exp(icpt) == pytest.approx(0.3) and err < 1e-12
    assert fitting.loglog_slope(x, x**-4) == pytest.approx(-4.0)
    n = np.arange(1.0, 1e4)
    t = 10 * np.log(n)
    r, drift = fitting.fit_rate(t, np.exp(-0.2 * t), n)
    assert r == pytest.approx(0.2) and drift < 1e-10


def test_tail_limit_of_the_expansion():
    n = np.arange(1000.0, 20000.0)
    L, err = fitting.tail_limit(n, 2.0 + 3 * np.log(n) / n + 1 / n**2)
    assert L == pytest.approx(2.0, abs=1e-10) and err < 1e-9


def test_richardson_derivative():
    with mpmath.workdps(40):
        v, err = fitting.richardson_derivative(lambda t: mpmath.mpf(t) ** 3 * (5 - mpmath.mpf(t)), 3, 1e-4)
    assert float(v) == pytest.approx(30.0, rel=1e-9) and float(err) < 1e-3


# --------------------------------------------------------------------------- bounce.analysis.reference: free flight

@pytest.mark.parametrize("mu", [0.05, 1.0, 2.5])
def test_free_flight_matches_simulator_flight_and_reverses(mu):
    """The mpmath free flight agrees with eq. (F) of bounce.exact.flight for t > 0 and undoes itself backward."""
    g = 0.02
    s = (0.3, -0.1, 0.05, 0.01)
    params, coefs = make_oscillator(mu)
    for t in (0.01, 0.7, 3.0):
        fwd = reference.free_flight(g, mu, *s, t)
        x_f, v_f, scale = gap(t, *s, g, params, coefs)[:3]
        assert abs(float(fwd.x) - x_f) <= 8 * 2.2e-16 * scale
        assert abs(float(fwd.u) - v_f) <= 1e-14
        back = reference.free_flight(g, mu, fwd.x, fwd.u, fwd.a, fwd.eta, -t)
        assert all(abs(b - mpmath.mpf(v)) < mpmath.mpf(10) ** -30 for b, v in zip((back.x, back.u, back.a, back.eta), s))


def test_backward_contact_reaches_the_contact():
    g, mu = 0.01, 0.3
    a, eta = theory.sticky_onset(g, mu, g)
    start, T = reference.backward_contact(g, mu, a, eta, 0, 0.4)
    end = reference.free_flight(g, mu, start.x, start.u, start.a, start.eta, T)
    assert abs(end.x) < 1e-40 and abs(end.u) < 1e-40 and start.x > 0
    assert Deviations(*start.floats()).x > 0


# --------------------------------------------------------------------------- Discussion: the nonlinear spring

LAWS = [(1.0, 0.5, 0.5), (2.0, 1.0, 0.0), (0.5, 0.5, 1.0)]  # (rho, a, b)


@pytest.mark.parametrize("rho, a, b", LAWS)
def test_nonlin_equilibrium_xi_balances_gravity_and_is_the_energy_minimum(rho, a, b):
    from bounce.springs import PowerSpring

    g = 0.01
    xi = theory.nonlin_equilibrium_xi(g, rho, a)
    assert xi < 0 and math.isclose(rho * abs(xi) ** (a + 1), g, rel_tol=1e-14)
    spring = PowerSpring(rho=rho, a=a, b=b)
    assert math.isclose(xi, spring.xi_eq(g), rel_tol=1e-15)
    # at rest on the floor (psi = xi) eq. nonlin-energy is minimal at xi_eq, with the solver's E_m
    def E(x):
        return theory.nonlin_energy(x, 0.0, x, 0.0, g, rho, a)

    assert math.isclose(E(xi), spring.energy_min(g), rel_tol=1e-14)
    h = 1e-3 * abs(xi)
    assert E(xi - h) > E(xi) and E(xi + h) > E(xi)


def test_nonlin_forms_reduce_to_the_linear_ones():
    g, mu = 0.01, 0.3
    assert theory.nonlin_equilibrium_xi(g, 1.0, 0.0) == -g
    xi, xid, psid = -0.02, 0.003, -0.001
    assert math.isclose(theory.nonlin_energy(xi, xid, xi, psid, g, 1.0, 0.0), theory.tot_mech_energy(xi, xid, psid, g),
                        rel_tol=1e-15)
    assert theory.nonlin_energy_rate(xi, xid, mu, 0.0) == -2 * mu * xid**2  # eq. energy-dissipation
    assert math.isclose(theory.nonlin_alpha_limit(g, mu, 1.0, 0.0, 0.0), mu / (3 * g), rel_tol=1e-15)
    # the scaling of the Discussion: (gamma/rho)^(b/(a+1)) = |xi_eq|^b
    assert math.isclose(theory.nonlin_alpha_limit(g, mu, 2.0, 0.5, 0.5),
                        mu / (3 * g) * abs(theory.nonlin_equilibrium_xi(g, 2.0, 0.5)) ** 0.5, rel_tol=1e-14)


@pytest.mark.parametrize("rho, a, b", LAWS)
def test_nonlin_energy_rate_against_finite_differences(rho, a, b):
    """dE/dt of eq. nonlin-energy along an mpmath solution of eq. eq-motion-nonlin-psi-xi (Taylor ODE solver)
    equals -2 mu xi'^2 |xi|^b (central differences at 30 digits, h = 1e-6: error O(h^2) ~ 1e-12 relative)."""
    with mpmath.workdps(30):
        _check_nonlin_energy_rate(rho, a, b)


def _check_nonlin_energy_rate(rho, a, b):
    g, mu = 0.01, 0.3

    def rhs(t, y):
        _, psid, xi, xid = y
        return [psid, -g, xid, -rho * xi * abs(xi) ** a - 2 * mu * xid * abs(xi) ** b]

    sol = mpmath.odefun(rhs, 0, [mpmath.mpf("0.05"), mpmath.mpf("0.01"), mpmath.mpf("-0.06"), mpmath.mpf("0.02")])

    def E(t):
        psi, psid, xi, xid = sol(t)
        return psid**2 / 2 + xid**2 / 2 + rho / (a + 2) * abs(xi) ** (a + 2) + g * psi

    h = mpmath.mpf("1e-6")
    for t in (mpmath.mpf("0.3"), mpmath.mpf("0.7")):
        fd = (E(t + h) - E(t - h)) / (2 * h)
        _, _, xi, xid = sol(t)
        rate = theory.nonlin_energy_rate(float(xi), float(xid), mu, b)
        assert rate < 0 and abs(float(fd) / rate - 1) < 1e-9
        assert abs(float(fd) / (rate / 2) - 1) > 0.5  # the printed -mu xi'^2 |xi|^b is off by a factor 2


def test_nonlinear_cycle_loss_reduces_to_the_linear_law_and_gives_the_one_fifth_law():
    """theory.nonlin_cycle_loss: a = b = 0, rho = 1 gives mu pi for every u (the first order of
    exp(-mu T_xi), eq. rest-coefficient-function-of-mu); Hertz gives (u/U)^(1/5) with U = theory.onefifth_U,
    and U scales as rho^3 mu^-5 (the scaling of the single cycle)."""
    import math

    import numpy as np

    from bounce.analysis import theory

    u = np.geomspace(1e-8, 1.0, 9)
    np.testing.assert_allclose(theory.nonlin_cycle_loss(u, 0.01, 1.0, 0.0, 0.0), 0.01 * math.pi, rtol=1e-14)
    U = theory.onefifth_U(0.3, 2.0)
    np.testing.assert_allclose(theory.nonlin_cycle_loss(u, 0.3, 2.0, 0.5, 0.5), (u / U) ** 0.2, rtol=1e-13)
    assert math.isclose(theory.onefifth_U(0.15, 4.0) / U, 2.0**3 * 2.0**5, rel_tol=1e-12)

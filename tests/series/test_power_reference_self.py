"""Tests of the independent power-law reference (tests/power_reference.py) itself.

What makes it trustworthy, each a test that can fail:

* linear law (rho, a, b) = (1, 0, 0): it agrees with the closed-form mpmath reference
  (tests/reference.py, 50 digits) to 1e-40, crossing series and all, and with bounce's exact
  float64 solver to the float64 floor (1e-14 relative, eta against its own size);
* its two precisions (50 and 64 digits) and two crossing-series degrees agree to 1e-44;
* it solves the stated equation: E of eq. ``nonlin-energy`` never rises along a flight that crosses
  xi = 0, its rate is -2 mu xi'^2 |xi|^b (central difference), and the impact conserves E;
* Hertz (a = b = 1/2) and two other laws work from moderate post-impact states (flights crossing
  xi = 0) and deep near equilibrium (xi - xi_eq = 1e-13, flights ~1e-6), where an independent
  integrator (mpmath.odefun at 25 digits, xi stays away from 0) gives the same flight;
* a constructed shallow dip 1e-30 below the floor is found, one 1e-30 above it is not an impact;
* the paper's drop (spring at rest length, a rest point of the spring) lands at sqrt(2 psi0/gamma).
"""

from __future__ import annotations

import mpmath
import pytest
from mpmath import mp, mpf

import power_reference as PR
from bounce.analysis import reference as R
from bounce import Deviations, Parameters, simulate

GAMMA = MU = 0.01
LAWS = {"hertz": (1.0, 0.5, 0.5), "a1-b0": (1.0, 1.0, 0.0), "a1/4-b3/2": (2.0, 0.25, 1.5)}
# moderately excited post-impact state (x, x', xi', xi): the spring swings through xi = 0 and x
# has a near miss (interior minimum ~2e-3) before the impact at tau ~ 13
MODERATE = (0.0, 0.12, -0.06, -0.04)


def rel(a, b):
    return mpf(0) if a == b else abs((a - b) / b)


def deep_state(rho, a, dps=80):
    """Post-impact state 1e-13 from the equilibrium: x' = 1e-8, xi' = 2e-9, xi = xi_eq + 1e-13."""
    with mp.workdps(dps):
        return (0.0, 1e-8, 2e-9, PR.xi_equilibrium(GAMMA, rho, a, dps) + mpf("1e-13"))


@pytest.fixture(scope="module")
def hertz_moderate():
    return PR.reference_first_impact(GAMMA, MU, *LAWS["hertz"], *MODERATE)


@pytest.mark.parametrize("u, a, eta", [(0.3, -0.2, 0.05), (2.3e-8, -1.1e-8, 3.0e-13)])
def test_linear_law_matches_closed_form_reference(u, a, eta):
    with mp.workdps(60):
        xi = mpf(eta) - mpf(GAMMA)
    got = PR.reference_first_impact(GAMMA, MU, 1.0, 0.0, 0.0, 0.0, u, a, xi)
    tau, st = R.flight_step(GAMMA, MU, 0.0, u, a, eta)
    with mp.workdps(50):
        assert rel(got["tau"], tau) < 1e-40
        assert rel(got["xdot"], st.u) < 1e-40
        assert rel(got["xidot"], st.a) < 1e-40
        assert rel(got["eta"], st.eta) < 1e-35  # eta = xi + gamma, a difference of O(gamma) terms


def test_linear_law_matches_bounce_exact_solver():
    u, a, eta = 0.3, -0.2, 0.05
    tr = simulate(Parameters(GAMMA, MU), Deviations(0.0, u, a, eta), max_events=1)
    with mp.workdps(60):
        xi = mpf(eta) - mpf(GAMMA)
    got = PR.reference_first_impact(GAMMA, MU, 1.0, 0.0, 0.0, 0.0, u, a, xi)
    assert tr.kind[0] == 0
    for key, value in (("tau", tr.tau[0]), ("xdot", tr.xdot[0]), ("xidot", tr.xidot[0]), ("eta", tr.eta[0])):
        assert float(rel(mpf(float(value)), got[key])) < 1e-14, key


def test_two_precisions_and_two_crossing_degrees_agree(hertz_moderate, monkeypatch):
    hi = PR.reference_first_impact(GAMMA, MU, *LAWS["hertz"], *MODERATE, dps=64)
    monkeypatch.setattr(PR, "CROSSING_DEGREE", 28)  # smaller crossing windows, different matching points
    other = PR.reference_first_impact(GAMMA, MU, *LAWS["hertz"], *MODERATE)
    with mp.workdps(64):
        for key in ("tau", "xdot", "xidot", "xi", "x_min_interior"):
            assert rel(hertz_moderate[key], hi[key]) < 1e-44, key
            assert rel(hertz_moderate[key], other[key]) < 1e-44, key


def test_energy_never_rises_and_dissipates_at_the_derived_rate(hertz_moderate):
    with mp.workdps(PR.DPS):
        fl = PR.make_flight(GAMMA, MU, *LAWS["hertz"], *MODERATE)
        tau = hertz_moderate["tau"]
        law = fl.law
        times = [tau * k / 200 for k in range(201)]
        energies = [fl.energy(t) for t in times]
        crossings = sum(1 for seg in fl.segments if isinstance(seg, PR.Crossing))
        assert crossings >= 2  # the flight does pass the non-analytic point
        slack = mpf(10) ** -40
        assert all(e1 <= e0 + slack for e0, e1 in zip(energies, energies[1:]))
        assert energies[-1] < energies[0] - mpf("1e-6")  # it does dissipate
        h = mpf(10) ** -12
        for t in times[7::40]:
            _, _, xi, xid = fl.state(t)
            rate = (fl.energy(t + h) - fl.energy(t - h)) / (2 * h)
            assert rel(rate, -2 * law.mu * xid**2 * abs(xi) ** law.b) < 1e-18
        # the impact exchanges psi' and xi': E is the same just after it
        r = hertz_moderate
        after = law.energy(mpf(0), r["xdot"] + r["xidot"], r["xi"], r["xidot"])
        assert rel(after, r["energy_end"]) < 1e-45


@pytest.mark.parametrize("law", sorted(LAWS))
def test_drop_with_spring_at_rest_length_is_a_free_fall(law):
    """xi = xi' = 0 is a rest point of the spring: the paper's drop lands at sqrt(2 psi0 / gamma)."""
    r = PR.reference_first_impact(GAMMA, MU, *LAWS[law], 6.0, 0.0, 0.0, 0.0)
    with mp.workdps(PR.DPS):
        t1 = mp.sqrt(2 * mpf(6) / mpf(GAMMA))
        assert rel(r["tau"], t1) < 1e-45
        assert rel(r["xdot"], mpf(GAMMA) * t1) < 1e-45 and rel(r["xidot"], -mpf(GAMMA) * t1) < 1e-45
        assert r["xi"] == 0


@pytest.mark.parametrize("law", sorted(LAWS))
def test_moderate_flight_crosses_spring_rest_length_and_impacts(law):
    rho, a, b = LAWS[law]
    r = PR.reference_first_impact(GAMMA, MU, rho, a, b, *MODERATE)
    with mp.workdps(PR.DPS):
        fl = PR.make_flight(GAMMA, MU, rho, a, b, *MODERATE)
        x, psid, xi, xid = fl.state(r["tau"])
        assert abs(x) < mpf(10) ** -45
        assert psid - xid < 0  # x' < 0 at the impact
        assert r["xdot"] == -(psid - xid) and r["xidot"] == psid and r["xi"] == xi
        assert any(isinstance(seg, PR.Crossing) for seg in fl.segments)
        assert r["energy_end"] <= r["energy_start"]
        # before the impact x > 0 on a grid (the certified search is the real guarantee)
        assert all(fl.x(r["tau"] * k / 64) > 0 for k in range(1, 64))


def _odefun_flight(rho, a, b, state, dps=25):
    """The same flight by mpmath.odefun (xi < 0 throughout: an analytic field), tau by findroot.

    Integrates the displacement d = xi - xi(0), so that x = x0 + psi'0 t - gamma t^2/2 - d keeps
    all digits although x ~ 1e-14 and xi ~ 1e-2."""
    with mp.workdps(dps):
        x0, xd0, xid0, xi0 = (PR.M(v) for v in state)
        g, mu, rho, a, b = (mpf(v) for v in (GAMMA, MU, rho, a, b))
        psid0 = xd0 + xid0

        def field(t, y):  # y = (d, d'), |xi| = -(xi0 + d)
            r = -(xi0 + y[0])
            return [y[1], rho * r ** (a + 1) - 2 * mu * y[1] * r**b]

        sol = mpmath.odefun(field, 0, [mpf(0), xid0])

        def x(t):
            return x0 + psid0 * t - g * t * t / 2 - sol(t)[0]

        tau = mpmath.findroot(x, 2 * xd0 / (2 * g))
        d, xid = sol(tau)
        return tau, xid - (psid0 - g * tau), psid0 - g * tau, xi0 + d


@pytest.mark.parametrize("law", sorted(LAWS))
def test_deep_near_equilibrium_matches_independent_integrator(law):
    rho, a, b = LAWS[law]
    state = deep_state(rho, a)
    r = PR.reference_first_impact(GAMMA, MU, rho, a, b, *state)
    tau, xdot, xidot, xi = _odefun_flight(rho, a, b, state)  # 25 digits
    with mp.workdps(40):
        assert 0.9e-6 < r["tau"] < 1.1e-6
        assert rel(r["tau"], tau) < 1e-22
        assert rel(r["xdot"], xdot) < 1e-22
        assert rel(r["xidot"], xidot) < 1e-22
        assert rel(r["eta"], xi - PR.xi_equilibrium(GAMMA, rho, a, 40)) < 1e-12  # ~1e-13 from xi ~ 1e-2 at 25 digits
        assert r["x_min_interior"] == mp.inf


@pytest.mark.parametrize("depth, is_hit", [(mpf("1e-30"), True), (mpf("-1e-30"), False)])
def test_shallow_dip_is_neither_skipped_nor_invented(hertz_moderate, depth, is_hit):
    """Start before the flight's interior minimum with x shifted so that the minimum sits
    ``depth`` below the floor (x_min = -depth): the first impact is in the dip iff depth > 0."""
    with mp.workdps(PR.DPS):
        t_min, x_min = hertz_moderate["t_min_interior"], hertz_moderate["x_min_interior"]
        assert x_min < 1e-2  # the flight does have a near miss to move
        fl = PR.make_flight(GAMMA, MU, *LAWS["hertz"], *MODERATE)
        t_s = t_min / 2
        x, psid, xi, xid = fl.state(t_s)
        start = (x - x_min - depth, psid - xid, xid, xi)
    r = PR.reference_first_impact(GAMMA, MU, *LAWS["hertz"], *start)
    with mp.workdps(PR.DPS):
        width = mp.sqrt(8 * abs(depth) / 1e-3)  # generous: x'' >~ 1e-3 at the minimum
        in_dip = abs(r["tau"] - (t_min - t_s)) < width
        assert in_dip == is_hit
        if not is_hit:
            assert r["tau"] > t_min - t_s + width  # the impact comes after the near miss ...
            assert rel(r["x_min_interior"], -depth) < 1e-10  # ... which is reported, 1e-30 above the floor

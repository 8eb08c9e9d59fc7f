"""The sticky phase of the power-law spring (bounce.series.sticky) and its events.

Independent checks: the closed-form linear solver (bounce.simulate, eqs. y-eq-sticky,
force-on-the-floor, cond_di_distacco) for a = b = 0, rho = 1; the mpmath sticky reference of
tests/power_reference.py (its own Taylor steps at 40 digits, written from the Discussion's
equations) for Hertz and rho = 2, a = 1, b = 0; scipy's DOP853 for a sticky phase that crosses
the rest length xi = 0 (outside the reference's reach).
"""

from __future__ import annotations

import os

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st
from mpmath import mp, mpf
from scipy.integrate import solve_ivp

import power_reference as PR
from bounce import Deviations, Parameters, State, simulate
from bounce.exact.events import floor_force as linear_floor_force
from bounce.series.events import simulate_power
from bounce.series.flight import at_rest_is_sticky, floor_force
from bounce.series.taylor import L_XI_EQ, law_array
from bounce.springs.power import PowerSpring

STICKY_START, DETACH = 2, 3
REL = 1e-14
EPS = np.finfo(float).eps
LINEAR = PowerSpring(1.0, 0.0, 0.0)
HERTZ = PowerSpring(1.0, 0.5, 0.5)
MAX_EXAMPLES = int(os.environ.get("BOUNCE_HYPOTHESIS_EXAMPLES", "25"))
SETTINGS = settings(deadline=None, max_examples=MAX_EXAMPLES, suppress_health_check=[HealthCheck.too_slow])


def law_of(spring, gamma, mu):
    return law_array(spring.rho, spring.a, spring.b, mu, gamma)


def rel_state_error(tr, ref, i, gamma):
    """|differences| of t, xi', eta at record i, relative to t and to |xi'| + |eta| + gamma."""
    scale = abs(ref.xidot[i]) + abs(ref.eta[i]) + gamma
    return (abs(tr.t[i] - ref.t[i]) / max(ref.t[i], 1e-300), abs(tr.xidot[i] - ref.xidot[i]) / scale,
            abs(tr.eta[i] - ref.eta[i]) / scale)


def linear_starts(p):
    """eq. sticky-ic (F = 0, F' < 0) and a rest state pressed onto the floor (F = -gamma/2) with
    the upper mass rising (F' > 0): both detach after a sticky phase for the parameters used."""
    g, mu = p.gamma, p.mu
    v = 30.0 * g  # F = -gamma/2, F' = gamma (30 - 1.5 mu) > 0
    return [State.sticky_ic(p, eps=0.0), Deviations(x=0.0, xdot=0.0, xidot=v, eta=1.5 * g - 2.0 * mu * v)]


# ------------------------------------------------------------------ linear law: closed form
@pytest.mark.parametrize("gamma, mu", [(0.01, 0.0), (0.01, 0.01), (0.01, 0.1), (0.05, 0.01), (0.1, 0.0),
                                       (0.3, 0.0), (1e-5, 0.1), (1e-5, 0.5), (1e-5, 1.0)])
def test_linear_law_sticky_phase_matches_closed_form(gamma, mu):
    """a = b = 0, rho = 1: the sticky start, the detach and the impact after it (time, xi', eta)
    to 1e-14 of the closed form (eq. y-eq-sticky; the flight after the detach is a cubic
    lift-off, F = 0, F' > 0).  Event times also within 4 kappa of the closed form, kappa =
    noise(F) / |F'| at the detach: the rounding-level condition of a root of F, which for a
    phase of 0.018 time units with F' ~ 3e-4 (gamma = 1e-5, mu = 1) is ~5e-14 relative."""
    p = Parameters(gamma, mu)
    for start in linear_starts(p):
        ref = simulate(p, start, max_events=3)
        tr = simulate_power(p, LINEAR, start, max_events=3)
        assert ref.kind_names == tr.kind_names, (ref.kind_names, tr.kind_names, tr.stop_reason)
        assert tr.kind_names[:2] == ("sticky_start", "detach")
        # a detach time is a root of F: its rounding-level condition is the noise of F over F'
        F, Fp = linear_floor_force(ref.xidot[1], ref.eta[1], gamma, mu)
        kappa = 8 * EPS * (abs(ref.eta[1]) + 2 * mu * abs(ref.xidot[1]) + 2 * gamma) / abs(Fp)
        for i in range(3):
            err = rel_state_error(tr, ref, i, gamma)
            assert err[0] <= REL + (4 * kappa / ref.t[i] if i else 0.0) and max(err[1:]) <= REL, (i, err, kappa)
        assert tr.xdot[1] == 0.0


@pytest.mark.parametrize("gamma, mu", [(0.01, 0.5), (0.05, 0.1), (0.3, 1.0), (0.01, 0.0)])
def test_linear_law_infinite_sticky_phase(gamma, mu):
    """Rest near the equilibrium: both solvers prove the phase infinite (sticky_forever); the
    power-law proof (sticky energy) is exact for mu = 0 and sufficient otherwise."""
    p = Parameters(gamma, mu)
    start = Deviations(x=0.0, xdot=0.0, xidot=0.1 * gamma, eta=0.2 * gamma)
    ref = simulate(p, start, max_events=3)
    tr = simulate_power(p, LINEAR, start, max_events=3)
    assert ref.stop_reason == tr.stop_reason == "sticky_forever"
    assert ref.kind_names == tr.kind_names == ("sticky_start",)


@pytest.mark.parametrize("xi", [0.0, 1e-200])
@pytest.mark.parametrize("gamma, mu", [(1e-6, 1.0), (1e-12, 1.0), (1e-6, 0.5), (0.01, 1.0), (0.01, 0.0)])
def test_linear_law_sticky_start_at_natural_length(gamma, mu, xi):
    """At rest on the floor with the spring at its natural length (psi = xi = 0: xi0 = 0 and xi' = 0, the
    series' state scale max(|xi0|, |xi'|) is zero): the phase is proved infinite as by the closed form. The
    analytic law's Cauchy disc took that zero scale (plus 1e-300) and divided by its radius^4 = 0
    (ZeroDivisionError, found by benchmarks/fuzz_cli.py at mu = 1); the state's own scale is kept otherwise (a
    larger Rz made the sticky phases at gamma = 1e-5 take 1000 times more steps)."""
    p = Parameters(gamma, mu)
    start = State.from_psi_xi(xi, 0.0, xi, 0.0)
    ref = simulate(p, start, max_events=3)
    tr = simulate_power(p, LINEAR, start, max_events=3)
    assert ref.stop_reason == tr.stop_reason == "sticky_forever"
    assert ref.kind_names == tr.kind_names == ("sticky_start",)


def test_sticky_phase_crosses_the_rest_length_with_a_small_damping_exponent():
    """a = 2.5, b = 1/8 from a spring compressed to zero length (x = y = 0): the sticky phase passes xi = 0, where its
    steps move eta by less than half an ulp; xi formed without the compensation term froze at 5.6e-16, outside the
    crossing window (6.6e-16 wide for b = 1/8), and the phase stalled (RuntimeError after 4e5 steps; found by the
    fuzz of stop 28).  Now it detaches and the ball flies."""
    tr = simulate(Parameters(0.01, 0.01, PowerSpring(1.0, 2.5, 0.125)), State(0.0, 0.0, 0.0, 0.0), max_events=4)
    assert tr.kind_names == ("sticky_start", "detach", "impact", "impact"), (tr.kind_names, tr.stop_reason)


def test_never_detach_criterion_is_sharp_without_damping():
    """mu = 0, linear law: F's maximum over the sticky orbit is eta_amp - 2 gamma with
    eta_amp = sqrt(eta^2 + 2 xi'^2) (eta'' = -eta/2); just below the level the phase is proved
    infinite, just above it detaches (within one period)."""
    gamma = 0.05
    p = Parameters(gamma, 0.0)
    for amp, expected in ((2.0 * gamma * (1 - 1e-9), "sticky_forever"), (2.0 * gamma * (1 + 1e-9), "max_events")):
        start = Deviations(x=0.0, xdot=0.0, xidot=amp / np.sqrt(2.0), eta=0.0)
        tr = simulate_power(p, LINEAR, start, max_events=2)
        assert tr.stop_reason == expected, (amp, tr.kind_names, tr.stop_reason)
        if expected == "max_events":
            assert tr.kind_names == ("sticky_start", "detach") and tr.t[1] < 2 * np.pi * np.sqrt(2.0)


# ------------------------------------------------------------------ mpmath reference
STICKY_CASES = {  # (spring, gamma, mu, xi, xi'): at rest on the floor with F < 0, xi < 0 throughout
    "hertz_detach": (HERTZ, 0.01, 0.5, -0.0696, -0.2),
    "a1b0_detach": (PowerSpring(2.0, 1.0, 0.0), 0.05, 0.5, -0.2372, -0.3),
    "hertz_never": (HERTZ, 0.01, 0.5, -0.10, 0.0),
}


@pytest.mark.parametrize("case", list(STICKY_CASES))
def test_sticky_phase_matches_reference(case):
    """Detach time to 1e-14 relative and the state there to 1e-14 of |xi'| + |eta| + gamma (the
    reference's xi' and xi at 40 digits, fed the solver's own start xi = xi_eq + eta exactly);
    a phase the solver proves infinite has F < 0 all along the reference up to t = 60."""
    spring, gamma, mu, xi, v = STICKY_CASES[case]
    law = law_of(spring, gamma, mu)
    xi_eq = float(law[L_XI_EQ])
    eta = xi - xi_eq
    assert at_rest_is_sticky(v, eta, law)
    tr = simulate_power(Parameters(gamma, mu, spring), spring, Deviations(0.0, 0.0, v, eta), max_events=2)
    with mp.workdps(40):
        ref = PR.reference_sticky(gamma, mu, spring.rho, spring.a, spring.b, v, mpf(xi_eq) + mpf(eta), 60.0, dps=40)
        if ref["t_detach"] is None:
            assert tr.stop_reason == "sticky_forever" and tr.kind_names == ("sticky_start",)
            assert ref["F_max"] < 0
            return
        assert tr.kind_names == ("sticky_start", "detach"), (tr.kind_names, tr.stop_reason)
        td = ref["t_detach"]
        assert abs(mpf(tr.t[1]) - td) <= REL * td, (tr.t[1], td)
        eta_ref = ref["xi"] - mpf(xi_eq)
        scale = abs(ref["xidot"]) + abs(eta_ref) + gamma
        assert abs(mpf(tr.eta[1]) - eta_ref) <= REL * scale
        assert abs(mpf(tr.xidot[1]) - ref["xidot"]) <= REL * scale


def test_sticky_reference_two_precisions_agree():
    """The reference's own truncation and rounding: 40 and 60 digits agree far below 1e-14."""
    spring, gamma, mu, xi, v = STICKY_CASES["hertz_detach"]
    a = PR.reference_sticky(gamma, mu, spring.rho, spring.a, spring.b, v, xi, 60.0, dps=40)
    b = PR.reference_sticky(gamma, mu, spring.rho, spring.a, spring.b, v, xi, 60.0, dps=60)
    with mp.workdps(60):
        assert abs(a["t_detach"] - b["t_detach"]) <= mpf(10) ** -30 * b["t_detach"]
        assert abs(a["xidot"] - b["xidot"]) <= mpf(10) ** -30


# ------------------------------------------------------------------ xi = 0 inside a sticky phase
def sticky_dense(spring, gamma, mu, xi, v, t_end):
    """DOP853 on the sticky equation xi'' = -(gamma + f + 2 mu xi' |xi|^b)/2 with the detach event F = 0 up."""
    def rhs(t, y):
        return [y[1], -(gamma + spring.rho * y[0] * abs(y[0]) ** spring.a + 2 * mu * y[1] * abs(y[0]) ** spring.b) / 2]

    def force(t, y):
        return spring.rho * y[0] * abs(y[0]) ** spring.a + 2 * mu * y[1] * abs(y[0]) ** spring.b - gamma

    force.terminal, force.direction = True, 1
    sol = solve_ivp(rhs, (0.0, t_end), [xi, v], method="DOP853", rtol=1e-13, atol=1e-15, events=force)
    return sol.t_events[0][0], sol.y_events[0][0]


def test_sticky_phase_crossing_the_rest_length():
    """Hertz: the upper mass rises fast enough to stretch the spring through xi = 0 (the
    non-analytic point, crossed in a window) before the pull detaches the lower mass (xi > 0).
    Against DOP853 at rtol 1e-13 (a check of the window, not of the last digits)."""
    gamma, mu, xi, v = 0.05, 0.3, -0.1, 0.3
    law = law_of(HERTZ, gamma, mu)
    eta = xi - float(law[L_XI_EQ])
    tr = simulate_power(Parameters(gamma, mu, HERTZ), HERTZ, Deviations(0.0, 0.0, v, eta), max_events=3)
    assert tr.kind_names[:2] == ("sticky_start", "detach")
    xi_d = float(law[L_XI_EQ]) + tr.eta[1]
    assert xi_d > 0.0
    td, (xi_ref, v_ref) = sticky_dense(HERTZ, gamma, mu, xi, v, 10.0)
    assert abs(tr.t[1] - td) <= 1e-9 * td
    assert abs(xi_d - xi_ref) <= 1e-9 and abs(tr.xidot[1] - v_ref) <= 1e-9


# ------------------------------------------------------------------ invariants
@SETTINGS
@given(xi_over_eq=st.floats(-0.9, 1.7), v=st.floats(-0.4, 0.4), mu=st.sampled_from([0.0, 0.1, 0.5, 1.0]),
       gamma=st.sampled_from([0.01, 0.05]), spring=st.sampled_from([HERTZ, PowerSpring(2.0, 1.0, 0.0),
                                                                     PowerSpring(0.5, 0.25, 1.0)]))
@example(xi_over_eq=0.0, v=0.390625, mu=1.0, gamma=0.01, spring=HERTZ)  # detach at xi = 1.6e-4: was a zero-length loop
def test_sticky_records_follow_the_rules(xi_over_eq, v, mu, gamma, spring):
    """From any rest state on the floor: a sticky phase is recorded iff the mass stays
    (at_rest_is_sticky); it ends in a detach (x' = 0, F = 0 to rounding, F' >= 0) or a stop;
    E - E_m (eq. nonlin-energy) never rises from record to record, and x' = 0 at both ends."""
    law = law_of(spring, gamma, mu)
    xi_eq = float(law[L_XI_EQ])
    eta = xi_over_eq * xi_eq - xi_eq
    tr = simulate_power(Parameters(gamma, mu, spring), spring, Deviations(0.0, 0.0, v, eta), max_events=6,
                        t_max=400.0)
    stays = at_rest_is_sticky(v, eta, law)
    assert (len(tr) > 0 and tr.kind[0] == STICKY_START) == stays
    for i, k in enumerate(tr.kind):
        if k == DETACH:
            assert tr.kind[i - 1] == STICKY_START and tr.xdot[i] == 0.0
            F, Fp, noise_F, noise_Fp = floor_force(tr.xidot[i], tr.eta[i], law)
            assert abs(F) <= noise_F and Fp >= -noise_Fp, (F, Fp, noise_F, noise_Fp)
        if k == STICKY_START:
            assert tr.xdot[i] == 0.0
            # never straight back onto the floor at the detach's own instant (a zero-length sticky loop)
            assert not (i > 0 and tr.kind[i - 1] == DETACH and tr.t[i] == tr.t[i - 1])
    e = tr.energy_excess
    assert np.all(np.diff(e) <= 1e-12 * np.maximum(e[:-1], gamma**2))


@pytest.mark.parametrize("spring", [HERTZ, PowerSpring(0.5, 0.25, 1.0)], ids=["hertz", "rho0.5_a0.25_b1"])
def test_never_detach_criterion_is_sharp_without_damping_power_law(spring):
    """mu = 0: F = f(xi) - gamma is largest at the upper turning point xi_up of the sticky orbit, and
    F(xi_up) = 0 at xi_up = |xi_eq| (f(|xi_eq|) = gamma).  From the equilibrium with the sticky
    energy that reaches xi_up = |xi_eq| (1 -+ 1e-8): proved infinite just below, a detach just above
    (v^2 = Bg(xi_up - xi_eq), Bg(e) = V(xi_eq + e) - V(xi_eq) + gamma e, V = rho |xi|^(a+2)/(a+2))."""
    gamma = 0.05
    xi_eq = spring.xi_eq(gamma)

    def potential(xi):
        return spring.rho * abs(xi) ** (spring.a + 2) / (spring.a + 2)

    for factor, expected in ((1 - 1e-8, "sticky_forever"), (1 + 1e-8, "max_events")):
        e_up = -xi_eq * factor - xi_eq
        v = np.sqrt(potential(xi_eq + e_up) - potential(xi_eq) + gamma * e_up)
        tr = simulate_power(Parameters(gamma, 0.0, spring), spring, Deviations(0.0, 0.0, v, 0.0), max_events=2)
        assert tr.stop_reason == expected, (factor, tr.kind_names, tr.stop_reason)
        if expected == "max_events":
            assert tr.kind_names == ("sticky_start", "detach")
            assert abs(xi_eq + tr.eta[1] + xi_eq) <= 1e-6 * -xi_eq  # at the turning point |xi_eq|


@pytest.mark.parametrize("g, mu, T", [(0.01, 0.3, 0.4), (1e-3, 1.5, 0.1)])
def test_sticky_onset_from_a_flight_classified_as_the_linear_model(g, mu, T):
    """a = b = 0, rho = 1: the constructed sticky onset of test_events (a flight ending with
    x = x' = x'' = 0, x''' < 0; eq. sticky-condition) gives the same records as the closed form:
    sticky_start within twice the contact window of T (the shared classifier, bounce.exact.events.contact,
    fed the whole flight's rounding scale), then the same end of the sticky phase."""
    from contacts import constructed_contact, rounding_level

    d = constructed_contact(g, mu, mu * g, 0.0, T)
    ref = simulate(Parameters(g, mu), d, max_events=2, t_max=1e3)
    tr = simulate_power(Parameters(g, mu), LINEAR, d, max_events=2, t_max=1e3)
    assert tr.kind_names == ref.kind_names and tr.stop_reason == ref.stop_reason, (tr.kind_names, ref.kind_names)
    window = (6 * rounding_level(d, g, T) / (mu * g)) ** (1 / 3)
    assert tr.kind[0] == STICKY_START and abs(tr.t[0] - T) <= 2 * window and tr.xdot[0] == 0.0


def test_t_max_inside_a_sticky_phase():
    """A sticky phase still running at t_max stops with t_max (not a guessed detach): the Hertz
    case of the reference test detaches at t = 5.5057...; with t_max = 3 and 6 the records differ
    only by the detach."""
    spring, gamma, mu, xi, v = STICKY_CASES["hertz_detach"]
    start = Deviations(0.0, 0.0, v, xi - spring.xi_eq(gamma))
    short = simulate_power(Parameters(gamma, mu, spring), spring, start, max_events=3, t_max=3.0)
    longer = simulate_power(Parameters(gamma, mu, spring), spring, start, max_events=3, t_max=6.0)
    assert short.stop_reason == "t_max" and short.kind_names == ("sticky_start",)
    assert longer.kind_names[:2] == ("sticky_start", "detach") and 5.5 < longer.t[1] < 5.51

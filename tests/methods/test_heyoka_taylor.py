"""The heyoka peer (bounce.methods.heyoka_taylor) against bounce's exact solver and the mpmath references.

* linear law, the paper's drop (gamma = mu = 0.01, psi(0) = 6): impact times agree with the exact
  solver to 1e-12 while the chaotic transient leaves them that close (13 impacts; heyoka's ~1e-15
  one-step errors grow ~10x per impact there), and flight by flight from the exact post-impact
  states for the first 15 impacts (tau, x' and xi' after the impact to 1e-12);
* linear law deep in the asymptotic regime (state after 1e5 impacts): 15 flights to 1e-12;
* Hertz (a = b = 1/2): the first impact from a moderate and from a deep state agrees with the
  independent mpmath reference (tests/power_reference.py) to 1e-12;
* failures are reported, not raised: the paper's drop has the spring exactly at rest length, where
  the Taylor coefficients of |xi|^(1/2) are not finite (stall at impact 0); a cooldown longer than
  the flights skips impacts (missed_impact);
* samples of y (continuous output) agree with the exact solver's to 1e-12;
* bad settings get one line naming the setting.
* its fastest use (:func:`heyoka_taylor.impacts`, the impact rule in the event callback: what
  benchmarks/bench_power.py times) finds the same impacts as :func:`heyoka_taylor.run` to 1e-12, in the
  same number of Taylor steps, as does the step loop that prices its event handling (:func:`heyoka_taylor.event_cost`);
  its integrator-only cost (:func:`heyoka_taylor.step_cost`) takes the steps asked.
"""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest
from mpmath import mp, mpf

import power_reference as PR
from bounce import Deviations, Parameters, State, simulate
from bounce.methods import registry
from bounce.methods import heyoka_taylor as HT
from bounce.methods.base import SYMBOLIC_LAW
from bounce.springs import SPRING_LAWS

pytest.importorskip("heyoka")

GAMMA = MU = 0.01
DROP = State.from_psi_xi(6.0, 0.0, 0.0, 0.0)


HERTZ = Parameters(GAMMA, MU, SPRING_LAWS["power"](rho=1.0, a=0.5, b=0.5))


def run(params, initial, setting=None, **kw):
    return registry()["heyoka"].run(params, initial, setting, **kw)


def rel(a, b):
    return np.abs((np.asarray(a, float) - np.asarray(b, float)) / np.asarray(b, float))


def test_registered_for_both_laws():
    """heyoka runs every law with a symbolic form (bounce.methods.base.SYMBOLIC_LAW): both laws of the package."""
    spec = registry()["heyoka"]
    assert spec is HT.METHOD and spec.needs is SYMBOLIC_LAW
    assert spec.supports(HERTZ) and spec.supports(Parameters(GAMMA, MU))


def test_listing_the_methods_does_not_load_heyoka():
    """Discovery imports every method module: heyoka (~2.4 s) loads at the integrator's first use only."""
    code = ("import sys, bounce.methods as m; m.registry(); print('heyoka._core' in sys.modules); "
            "m.registry()['heyoka'].run; import bounce.methods.heyoka_taylor as h; h.hy.make_vars; "
            "print('heyoka._core' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["False", "True"]


def test_linear_drop_matches_exact_solver():
    p = Parameters(GAMMA, MU)
    exact = simulate(p, DROP, max_events=16)
    res = run(p, DROP, max_events=16)
    assert res.failure == "" and len(res.t) == 16
    assert rel(res.t[:13], exact.t[:13]).max() < 1e-12
    # flight by flight from the exact post-impact states: no chaotic amplification
    starts = [DROP] + [Deviations(0.0, exact.xdot[k], exact.xidot[k], exact.eta[k]) for k in range(14)]
    for k, start in enumerate(starts):
        one = run(p, start, max_events=1)
        assert one.failure == ""
        assert rel(one.t[0], exact.tau[k]) < 1e-12, k
        assert rel(one.xdot[0], exact.xdot[k]) < 1e-12, k
        assert rel(one.extra["xidot"][0], exact.xidot[k]) < 1e-12, k


def test_linear_deep_asymptotic_flights_match_exact_solver():
    p = Parameters(GAMMA, MU)
    tr = simulate(p, DROP, max_events=100_015)
    k0 = 100_000
    start = Deviations(0.0, tr.xdot[k0 - 1], tr.xidot[k0 - 1], tr.eta[k0 - 1])
    res = run(p, start, max_events=15)
    assert res.failure == ""
    assert tr.tau[k0] < 1e-2  # deep: flights ~3/(mu n)
    assert rel(np.diff(res.t, prepend=0.0), tr.tau[k0:k0 + 15]).max() < 1e-12
    assert rel(res.xdot, tr.xdot[k0:k0 + 15]).max() < 1e-12


@pytest.mark.parametrize("kind", ["moderate", "deep"])
def test_hertz_first_impact_matches_mpmath_reference(kind):
    xi_eq = HERTZ.xi_eq
    if kind == "moderate":  # swings through xi = 0 (the non-analytic point) before the impact
        x, xdot, xidot, eta = 0.0, 0.12, -0.06, -0.04 - xi_eq
    else:  # 1e-13 from the static equilibrium, flight ~1e-6
        x, xdot, xidot, eta = 0.0, 1e-8, 2e-9, 1e-13
    res = run(HERTZ, Deviations(x, xdot, xidot, eta), max_events=1)
    assert res.failure == ""
    with mp.workdps(60):
        xi = mpf(xi_eq) + mpf(eta)  # exactly the xi heyoka starts from
    ref = PR.reference_first_impact(GAMMA, MU, 1.0, 0.5, 0.5, x, xdot, xidot, xi)
    assert rel(res.t[0], float(ref["tau"])) < 1e-12
    assert rel(res.xdot[0], float(ref["xdot"])) < 1e-12
    assert rel(res.extra["xidot"][0], float(ref["xidot"])) < 1e-12
    eta_ref = float(ref["xi"] - mpf(xi_eq))
    assert abs(res.extra["eta"][0] - eta_ref) < 1e-12 * max(abs(eta_ref), 1e-6 * abs(xi_eq))


def test_spring_at_rest_length_is_reported_as_stall():
    res = run(HERTZ, DROP, max_events=5)
    assert res.failure == "stall" and res.failure_index == 0
    assert "err_nf_state" in res.extra["reason"]


def test_cooldown_longer_than_the_flights_is_a_missed_impact():
    deep = Deviations(0.0, 1e-8, 2e-9, 1e-13)  # flights ~1e-6
    ok = run(HERTZ, deep, max_events=20)
    assert ok.failure == "" and len(ok.t) == 20
    res = run(HERTZ, deep, {"cooldown": 1e-5}, max_events=20)
    assert res.failure == "missed_impact" and res.failure_index == 0  # the start is a restart: cooldown armed
    assert "skipped" in res.extra["reason"]


def test_automatic_cooldown_outlasts_the_flights_below_its_threshold():
    """heyoka's automatic cooldown after an impact is 10 eps/x' (measured); flights last ~x'/gamma, so it
    skips the next impact once x' < sqrt(10 eps gamma) = 4.7e-9 and not above (module docstring)."""
    eps = np.finfo(float).eps
    threshold = math.sqrt(10.0 * eps * GAMMA)
    above = run(HERTZ, Deviations(0.0, 2.0 * threshold, -threshold, 0.0), max_events=200)
    assert above.failure == "" and len(above.t) == 200
    assert above.extra["cooldown"] == pytest.approx(10.0 * eps / above.xdot[-1], rel=1e-3)
    below = run(HERTZ, Deviations(0.0, 0.6 * threshold, -0.3 * threshold, 0.0), max_events=200)
    assert below.failure == "missed_impact" and below.failure_index == 0


@pytest.mark.parametrize("start, cooldown, k", [
    (Deviations(0.02, 0.0, 0.0, -0.2), 1.2, 1),  # flight 1 (0.98 long) dips and comes back up through the floor
    (Deviations(0.0, 0.2, -0.3, 0.0), 3.0, 0),  # flight 0 (2.1) dips, turns at x ~ -0.9 and falls again
])
def test_skipped_dip_is_a_missed_impact(start, cooldown, k):
    """missed_impact (b): a fixed cooldown longer than flight k, whose x goes down through the floor and then
    turns (the spring pulls the lower mass up), skips impact k; x then has a minimum below the floor inside
    the flight, reported as the missed impact k with the impacts before it kept.  The second start never
    comes back up to the floor, so an event on x = 0 upwards (this check until 2026-11) would not have
    fired: only the flight bound (a) would have seen it.  With heyoka's own cooldown both starts run clean
    and find the exact solver's impacts."""
    p = Parameters(GAMMA, MU)
    exact = simulate(p, start, max_events=4)
    assert exact.tau[k] < cooldown  # the cooldown armed at impact k - 1 (k = 0: the restart) covers flight k
    clean = run(p, start, max_events=4)
    assert clean.failure == "" and rel(clean.t, exact.t).max() < 1e-12
    res = run(p, start, {"cooldown": cooldown}, max_events=4)
    assert res.failure == "missed_impact" and res.failure_index == k
    assert "minimum below the floor" in res.extra["reason"]
    assert len(res.t) == k and rel(res.t, exact.t[:k]).max(initial=0.0) < 1e-12


@pytest.mark.parametrize("setting, word", [({"tol": 0.0}, "tol"), ({"cooldown": -1.0}, "cooldown"),
                                           ({"rho": 2.0}, "unknown"), ({"tolerance": 1e-9}, "unknown")])
def test_bad_settings_name_the_setting(setting, word):
    with pytest.raises(ValueError, match=word):
        run(Parameters(GAMMA, MU), DROP, setting, max_events=1)


def test_samples_of_y_match_exact_solver():
    p = Parameters(GAMMA, MU)
    times = np.linspace(0.0, 120.0, 41)  # across the first impacts of the drop
    res = run(p, DROP, max_events=10, sample_times=times)
    exact = registry()["exact"].run(p, DROP, max_events=10, sample_times=times)
    assert not np.isnan(res.y).any()
    assert np.abs(res.y - exact.y).max() < 1e-12


@pytest.mark.parametrize("params, k0", [(Parameters(GAMMA, MU), 20), (HERTZ, 2000)])
def test_fastest_use_finds_the_same_impacts_as_run(params, k0):
    """impacts() (one propagation, the impact rule in the event callback: the speed benchmark's heyoka)
    integrates what run() does: the same impacts, times and post-impact states to 1e-12, from a state
    of the drop where both follow the exact solver (linear: 20 impacts in, Hertz: 2000); it stops at
    max_events, and finds no impact after t_end."""
    drop = State.from_psi_xi(6.0, 0.0, params.xi_eq, 0.0)
    tr = simulate(params, drop, max_events=k0)
    start = Deviations(0.0, tr.xdot[-1], tr.xidot[-1], tr.eta[-1])
    ref = run(params, start, max_events=50)
    assert ref.failure == ""
    t, xdot, xidot, eta, cpu, steps = HT.impacts(params, start, 50, 10.0 * ref.t[-1])
    assert len(t) == 50 and cpu >= 0.0
    assert rel(t, ref.t).max() < 1e-12
    assert rel(xdot, ref.xdot).max() < 1e-12
    assert rel(xidot, ref.extra["xidot"]).max() < 1e-12
    assert np.abs(eta - ref.extra["eta"]).max() < 1e-12 * np.abs(ref.extra["eta"]).max()
    t_half = HT.impacts(params, start, 50, 0.5 * (ref.t[24] + ref.t[25]))[0]
    assert len(t_half) == 25 and rel(t_half, ref.t[:25]).max() < 1e-12
    assert steps == ref.extra["steps"] >= 50  # one propagation each (run's non-terminal event cuts no step)


@pytest.mark.parametrize("params, k0", [(Parameters(GAMMA, MU), 20), (HERTZ, 2000)])
def test_event_cost_loop_finds_the_impacts_of_the_fastest_use(params, k0):
    """event_cost's step loop (the terminal event without a callback, the impact rule in Python between steps:
    bench_power's measure of heyoka's event handling) integrates what impacts() does: the same impact times and
    steps (to 2 %: its steps are bounded, see event_cost), from a restart on the floor (its priming step counted,
    its event not an impact; 30 impacts from a state where heyoka follows the exact solver, as in the test above)
    and from the drop (5 impacts: the transient is chaotic; the linear drop's
    first flight is an exact polynomial); the matched loop runs the rule as often."""
    drop = State.from_psi_xi(6.0, 0.0, 0.0 if params is not HERTZ else params.xi_eq, 0.0)
    tr = simulate(params, drop, max_events=k0)
    for start, restart in ((Deviations(0.0, tr.xdot[-1], tr.xidot[-1], tr.eta[-1]), 1), (drop, 0)):
        t, *_, steps = HT.impacts(params, start, 30, 1e4)
        r = HT.event_cost(params, start, 30)
        assert r["impacts"] == 30 and abs(r["steps"] - restart - steps) <= 0.02 * steps
        k = 30 if restart else 5  # the drop's transient is chaotic: heyoka's step sequences part it after a few
        assert rel(r["t"][:k], t[:k]).max() < 1e-12
        assert r["rules_matched"] == 30 + restart and r["cpu_events"] >= 0.0 and r["cpu_matched"] >= 0.0


@pytest.mark.parametrize("params", [Parameters(GAMMA, MU), HERTZ])
@pytest.mark.parametrize("floor_check", [False, True])
def test_step_cost_takes_the_steps_asked_without_the_impact_rule(params, floor_check):
    """step_cost (heyoka's integrator-only cost per step, bench_power's cost split) takes exactly the steps asked
    in one propagation from the drop's state, the floor's callback (floor_check) running at most at the one
    crossing of the floor; the spring exactly at rest length (Hertz: not finite) raises instead of a short count."""
    drop = State.from_psi_xi(6.0, 0.0, params.xi_eq, 0.0)
    steps, cpu, calls = HT.step_cost(params, drop, 300, floor_check=floor_check)
    assert steps == 300 and cpu >= 0.0
    assert calls <= (2 if floor_check else 0)
    if params is HERTZ:
        with pytest.raises(RuntimeError, match="of 300 steps"):
            HT.step_cost(params, State.from_psi_xi(6.0, 0.0, 0.0, 0.0), 300)

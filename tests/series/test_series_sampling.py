"""Dense output of the power-law spring (bounce.sampling with spring=PowerSpring).

Independent checks: the closed-form linear sampler for a = b = 0, rho = 1 (the same records
sampled both ways), the mpmath flight and sticky references of tests/power_reference.py at
sample points, and a hypothesis property: in flight x never dips below the floor beyond
rounding (the sampler does not clip x, so a skipped impact would show).
"""

from __future__ import annotations

import os

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from mpmath import mp, mpf

import power_reference as PR
from bounce import Deviations, Parameters, State, simulate
from bounce.series.events import simulate_power
from bounce.series.taylor import L_XI_EQ, law_array
from bounce.sampling import sample, sample_trajectory
from bounce.springs.power import PowerSpring

LINEAR = PowerSpring(1.0, 0.0, 0.0)
HERTZ = PowerSpring(1.0, 0.5, 0.5)
KEYS = ("x", "xdot", "y_minus_yeq", "ydot")
MAX_EXAMPLES = int(os.environ.get("BOUNCE_HYPOTHESIS_EXAMPLES", "25"))
SETTINGS = settings(deadline=None, max_examples=MAX_EXAMPLES, suppress_health_check=[HealthCheck.too_slow])


def state_scale(s, gamma):
    """Rounding scale of a sample: the magnitudes of its four components and gamma."""
    return np.abs(s["x"]) + np.abs(s["xdot"]) + np.abs(s["y_minus_yeq"]) + np.abs(s["ydot"]) + gamma


@pytest.mark.parametrize("gamma, mu", [(0.01, 0.01), (0.01, 0.0), (0.05, 0.1)])
@pytest.mark.parametrize("start", ["sticky_ic", "drop"])
def test_linear_law_matches_closed_form_sampler(gamma, mu, start):
    """The linear solver's records sampled by the closed forms and by the series steps of the power
    law with a = b = 0, rho = 1 (sticky phase, detach, lift-off, flights): equal to 1e-14 of the
    sample's scale at 2001 times, including the event times themselves."""
    p = Parameters(gamma, mu)
    initial = State.sticky_ic(p, eps=0.0) if start == "sticky_ic" else State.from_psi_xi(1.0, 0.0, 0.0, 0.0)
    tr = simulate(p, initial, max_events=25)
    end = tr.t_valid if np.isfinite(tr.t_valid) else 50.0
    times = np.concatenate([np.linspace(0.0, end, 2001), tr.t[tr.t <= end]])
    closed = sample_trajectory(tr, times)
    series = sample(gamma, mu, initial.deviations(p), tr.t, tr.kind, tr.xdot, tr.xidot, tr.eta, times,
                    tr.t_valid, spring=LINEAR)
    scale = state_scale(closed, gamma)
    for k in KEYS:
        err = np.abs(series[k] - closed[k]) / scale
        assert np.all(err <= 1e-14), (k, float(err.max()), float(times[np.argmax(err)]))


def test_power_trajectory_sampled_through_the_front_and_nan_after_t_valid():
    """sample_trajectory takes the power law (it refused it before): a Hertz run with a sticky
    phase; the sample at each event time is the recorded state (x = 0 there, y - y_eq = 2 eta),
    samples past t_valid are NaN."""
    gamma, mu = 0.01, 0.5
    xi_eq = HERTZ.xi_eq(gamma)
    p = Parameters(gamma, mu, HERTZ)
    tr = simulate(p, Deviations(0.0, 0.0, -0.2, -0.0696 - xi_eq), max_events=6)
    assert tr.kind_names[:2] == ("sticky_start", "detach")
    s = sample_trajectory(tr, np.concatenate([tr.t, [tr.t_valid + 1.0]]))
    n = len(tr)
    assert np.all(np.abs(s["x"][:n]) <= 1e-15)
    assert np.allclose(s["y_minus_yeq"][:n], 2.0 * tr.eta, rtol=0, atol=1e-15)
    assert np.allclose(s["ydot"][:n], tr.xdot + 2.0 * tr.xidot, rtol=0, atol=1e-15)
    assert all(np.isnan(s[k][n]) for k in KEYS)


@pytest.mark.parametrize("spring", [HERTZ, PowerSpring(2.0, 1.0, 0.0)], ids=["hertz", "rho2_a1_b0"])
def test_samples_match_mpmath_flight_reference(spring):
    """A flight from the floor (moderately excited) sampled at 7 interior times: x, x', y - y_eq
    and y' against the mpmath flight of tests/power_reference.py to 1e-14 of the sample's scale."""
    gamma, mu = 0.01, 0.1
    x0, u, a, eta = 0.0, 0.3, 0.1, 0.02
    tr = simulate_power(Parameters(gamma, mu, spring), spring, Deviations(x0, u, a, eta), max_events=1)
    times = tr.t[0] * np.array([0.01, 0.1, 0.3, 0.5, 0.7, 0.9, 0.999])
    s = sample(gamma, mu, Deviations(x0, u, a, eta), tr.t, tr.kind, tr.xdot, tr.xidot, tr.eta, times,
               tr.t_valid, spring=spring)
    xi_eq = float(law_array(spring.rho, spring.a, spring.b, mu, gamma)[L_XI_EQ])
    scale = state_scale(s, gamma)
    with mp.workdps(50):
        fl = PR.make_flight(gamma, mu, spring.rho, spring.a, spring.b, x0, u, a, mpf(xi_eq) + mpf(eta))
        for j, t in enumerate(times):
            x, psid, xi, xid = fl.state(mpf(t))
            ref = {"x": x, "xdot": psid - xid, "y_minus_yeq": x + 2 * (xi - mpf(xi_eq)), "ydot": psid + xid}
            for k in KEYS:
                assert abs(mpf(s[k][j]) - ref[k]) <= 1e-14 * scale[j], (k, t, s[k][j], ref[k])


def test_sticky_samples_match_mpmath_sticky_reference():
    """Inside a Hertz sticky phase: y - y_eq = 2 eta and y' = 2 xi' at 5 times against the mpmath
    sticky reference run to each time; x = x' = 0."""
    gamma, mu, xi, v = 0.01, 0.5, -0.0696, -0.2
    xi_eq = HERTZ.xi_eq(gamma)
    tr = simulate_power(Parameters(gamma, mu, HERTZ), HERTZ, Deviations(0.0, 0.0, v, xi - xi_eq), max_events=2)
    assert tr.kind_names == ("sticky_start", "detach")
    times = tr.t[1] * np.array([0.05, 0.3, 0.5, 0.8, 0.99])
    s = sample(gamma, mu, Deviations(0.0, 0.0, v, xi - xi_eq), tr.t, tr.kind, tr.xdot, tr.xidot, tr.eta, times,
               tr.t_valid, spring=HERTZ)
    assert np.all(s["x"] == 0.0) and np.all(s["xdot"] == 0.0)
    with mp.workdps(40):
        xi0 = mpf(xi_eq) + mpf(xi - xi_eq)
        for j, t in enumerate(times):
            ref = PR.reference_sticky(gamma, mu, 1.0, 0.5, 0.5, v, xi0, float(t), dps=40)
            assert ref["t_detach"] is None
            scale = abs(ref["xidot"]) + abs(ref["xi"] - mpf(xi_eq)) + gamma
            assert abs(mpf(s["y_minus_yeq"][j]) - 2 * (ref["xi"] - mpf(xi_eq))) <= 2e-14 * scale
            assert abs(mpf(s["ydot"][j]) - 2 * ref["xidot"]) <= 2e-14 * scale


@SETTINGS
@given(psi0=st.floats(0.05, 2.0), xi0=st.floats(-0.3, 0.3), xidot0=st.floats(-0.5, 0.5),
       mu=st.sampled_from([0.0, 0.05, 0.5]), spring=st.sampled_from([HERTZ, PowerSpring(0.5, 0.25, 1.0)]))
def test_x_never_below_the_floor_in_flight(psi0, xi0, xidot0, mu, spring):
    """Between recorded events the sampled x stays >= 0 up to rounding (4 eps of the sample's
    scale): the sampler does not clip, so an impact skipped by the solver or a sample taken on the
    wrong side of a contact would show as x < 0 (the flights cross xi = 0 for many draws)."""
    gamma = 0.05
    p = Parameters(gamma, mu, spring)
    initial = State.from_psi_xi(psi0 + xi0, 0.0, xi0, xidot0)  # x = psi0 > 0
    tr = simulate(p, initial, max_events=40)
    times = np.linspace(0.0, tr.t_valid if np.isfinite(tr.t_valid) else tr.t[-1], 1501)
    s = sample_trajectory(tr, times)
    flying = ~np.isnan(s["x"])
    assert np.all(s["x"][flying] >= -4 * np.finfo(float).eps * state_scale(s, gamma)[flying])


def test_cli_samples_a_power_law_run_with_a_sticky_phase(tmp_path):
    """python -m bounce simulate --spring power ... --dt-sample: a Hertz rest state pressed onto the
    floor (y0 = 2 xi + 1, xi = -0.0696, ydot0 = 2 xi' = -0.4) goes sticky, detaches and flies; the
    file holds the events and the samples, x = 0 on the sticky phase and x > 0 after the lift-off."""
    import subprocess
    import sys

    import xarray as xr

    out = tmp_path / "hertz.nc"
    run = subprocess.run(
        [sys.executable, "-m", "bounce", "simulate", "--gamma", "0.01", "--mu", "0.5", "--spring", "power",
         "--rho", "1", "--a", "0.5", "--b", "0.5", "--x0", "0", "--xdot0", "0", "--y0", "0.8608", "--ydot0", "-0.4",
         "--events", "5", "--dt-sample", "0.05", "--out", str(out)],
        capture_output=True, text=True, timeout=300,
    )
    assert run.returncode == 0, run.stderr
    with xr.open_dataset(out) as ds:
        kinds = list(ds["kind"].values[:2])
        t_detach = float(ds["t"].values[1])
        t, x = ds["time"].values, ds["sampled_x"].values
    assert kinds == [2, 3]
    assert np.all(x[t < t_detach] == 0.0) and np.all(x[(t > t_detach + 1.0) & (t < t_detach + 5.0)] > 0.0)

"""Reduced models and the predictability horizon (bounce.methods.rigid, contact_switch, horizon).

Each test states the theory it checks; the tolerances come from that theory
(rounding, o(Xdot^2) defects, delta^2 scaling), not from what passes.
"""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest

from bounce import Deviations, Parameters, simulate
from bounce.analysis import theory
from bounce.methods import contact_switch, rigid
from bounce.studies import horizon
from bounce.methods.base import MethodResult

EPS = 2.0**-52


def drop(gamma, mu, psi0):
    return Parameters(gamma, mu), Deviations(x=psi0, xdot=0.0, xidot=0.0, eta=gamma)


# --------------------------------------------------------------------------- rigid ball


@pytest.mark.parametrize("r", [0.5, 0.9, theory.rest_coefficient_function_of_mu(0.01)])
@pytest.mark.parametrize("gamma, psi0", [(0.01, 6.0), (1e-5, 0.25)])
def test_constant_r_collapse_time(r, gamma, psi0):
    """Introduction: t_inf = t_1 + 2 u_1/(gamma (1 - r)), u_1 = r u_0 (the geometric series of the flights).
    The run must end in failure 'collapse' at that time to rounding (a few ulps of t_inf)."""
    p, ini = drop(gamma, 0.01, psi0)
    res = rigid.run_constant(p, ini, {"r": r}, max_events=100_000)
    assert isinstance(res, MethodResult)
    assert res.failure == "collapse"
    u0 = math.sqrt(2.0 * gamma * psi0)
    t1 = u0 / gamma
    t_inf = t1 + 2.0 * r * u0 / (gamma * (1.0 - r))
    assert abs(res.t_end - t_inf) <= 8 * EPS * t_inf, (res.t_end, t_inf)
    # the failure index is the first impact whose flight is below the resolution of t
    k = res.failure_index
    assert 0 < k < len(res.t)
    assert 2.0 * res.xdot[k] / gamma <= EPS * res.t[k] < 2.0 * res.xdot[k - 1] / gamma / r


def test_fifth_law_flight_sum_converges():
    """Remark x-xbeta-map with beta = 6/5: u_n ~ 5^5 U/(n + c)^5 with c = 5 (U/u_0)^{1/5}, so the remaining
    flight time t_inf - t_n = sum_{k>n} 2 u_k/gamma ~ 2 5^5 U/(4 gamma (n + c)^4): a convergent sum (collapse).
    Tail fit: log-log slope -4 and the predicted prefactor, both from the run itself."""
    p, ini = drop(0.01, 0.01, 6.0)
    res = rigid.run_fifth(p, ini, {}, max_events=2_000_000)
    assert res.failure == "collapse"
    U = res.setting["U"]
    # default U: r(u_0) = e^{-mu T_xi}
    assert abs(res.extra["r_n"][0] - theory.rest_coefficient_function_of_mu(0.01)) < 1e-12
    u0 = res.extra["u_0"]
    c = 5.0 * (U / u0) ** 0.2
    n = np.arange(1, len(res.t) + 1)
    tail = res.t_end - res.t
    sel = (n >= 3000) & (n <= 30000)
    slope = np.polyfit(np.log(n[sel] + c), np.log(tail[sel]), 1)[0]
    assert abs(slope + 4.0) < 0.02, slope
    pref = tail[sel] * (n[sel] + c) ** 4 / (2 * 5**5 * U / (4 * p.gamma))
    assert np.all(np.abs(pref - 1.0) < 0.02), (pref.min(), pref.max())


def test_our_r_is_continuous_and_does_not_collapse():
    """Eq. our-r: r(u_c) = e^{-mu T_xi} from both sides; below u_c, u_n ~ 3 gamma/(mu n): no collapse."""
    gamma, mu = 0.01, 0.01
    uc = theory.u_c(gamma, mu)
    assert abs((1.0 - mu * uc / (3.0 * gamma)) - theory.rest_coefficient_function_of_mu(mu)) < 1e-15
    p, ini = drop(gamma, mu, 6.0)
    res = rigid.run_our_r(p, ini, {}, max_events=200_000)
    assert res.failure == ""
    n = len(res.xdot)
    assert abs(n * res.xdot[-1] * mu / (3.0 * gamma) - 1.0) < 2e-3


def test_time_of_contact_ends_in_elastic_bouncing():
    """Luding-McNamara: r < 1 while the last flight exceeds t_c, then r = 1 for ever (permanent contact)."""
    p, ini = drop(0.01, 0.01, 6.0)
    res = rigid.run_time_of_contact(p, ini, {}, max_events=5000)
    k = res.extra["index_contact"]
    assert k > 0 and res.failure == ""
    assert np.all(res.extra["r_n"][k:] == 1.0) and np.all(res.extra["r_n"][:k] < 1.0)
    assert 2.0 * res.xdot[k - 1] / p.gamma < res.setting["t_c"] < 2.0 * res.xdot[k - 2] / p.gamma


def test_rigid_samples_are_the_parabolas():
    """y = psi + 1 with psi the release parabola before t_1 and u_n s - gamma s^2/2 after impact n."""
    p, ini = drop(0.01, 0.01, 6.0)
    ts = np.array([0.0, 10.0, 50.0, 120.0])
    res = rigid.run_constant(p, ini, {}, max_events=50, sample_times=ts)
    assert res.y[0] == 7.0 and abs(res.y[1] - (7.0 - 0.5 * 0.01 * 100.0)) < 1e-14
    s = 50.0 - res.t[0]
    assert abs(res.extra["psi"][2] - (res.xdot[0] * s - 0.005 * s * s)) < 1e-12


# --------------------------------------------------------------------------- asymptotic map


@functools.lru_cache(maxsize=None)
def long_exact(gamma, mu, psi0, n):
    p, ini = drop(gamma, mu, psi0)
    tr = simulate(p, ini, max_events=n)
    assert (tr.kind == 0).all()
    return tr


@pytest.mark.parametrize("variant", ["paper", "cubic"])
@pytest.mark.parametrize("gamma, mu, psi0", [(0.01, 0.01, 6.0), (1e-5, 2.0, 0.25)])
def test_asymptotic_map_tracks_exact_xdot(gamma, mu, psi0, variant):
    """Eq. restituzione from the exact state at n0 = 1e4 to n0 + 1e5.

    Theory: the exact sequence obeys the map up to defects d_k = X_{k+1} - M(X_k) that are o(X_k^2), i.e.
    eps_k = d_k/(alpha X_k^2) -> 0 (alpha = mu/(3 gamma)); the map contracts relative errors
    (M'(X) X/M(X) = (1 - 2 alpha X)/(1 - alpha X) < 1), so the relative error after N steps is at most
    sum_k |d_k|/X_{k+1}.  Checked: eps_k decreases along the run, the map's error stays within that bound at
    every n, and it is smaller from n0 = 1e4 than from n0 = 1e3."""
    n0, N = 10_000, 100_000
    p, ini = drop(gamma, mu, psi0)
    ex = long_exact(gamma, mu, psi0, n0 + N + 1)
    alpha = mu / (3.0 * gamma)
    X = ex.xdot[n0 - 1 : n0 + N]
    res = rigid.run_asymptotic(p, ini, {"n0": n0, "variant": variant}, max_events=n0 + N)
    Xm = res.xdot[n0 - 1 : n0 + N]
    assert Xm[0] == X[0]
    rel = np.abs(Xm / X - 1.0)
    if variant == "paper":
        M = (1.0 - alpha * X[:-1]) * X[:-1]
    else:
        tau = (2.0 * X[:-1] / gamma) / (1.0 + np.sqrt(1.0 - 4.0 * alpha * X[:-1]))
        M = X[:-1] - mu * gamma * tau**2 / 3.0
    d = X[1:] - M
    eps_k = np.abs(d) / (alpha * X[:-1] ** 2)
    assert eps_k[-1000:].mean() < 0.5 * eps_k[:1000].mean()  # o(X^2): the defects die out
    assert eps_k[-1000:].mean() < 1e-2
    bound = np.cumsum(np.abs(d) / X[1:])
    assert np.all(rel[1:] <= bound * (1.0 + 1e-9) + 4 * EPS * np.arange(1, N + 1))
    # starting later is better (the defects are o(X^2))
    early = rigid.run_asymptotic(p, ini, {"n0": 1000, "variant": variant}, max_events=n0 + N)
    rel_early = abs(early.xdot[-1] / X[-1] - 1.0)
    assert rel[-1] < rel_early
    # flight time: Xdot_n/tau_n -> gamma, so the map's flights match the exact ones to the same order
    tau_exact = ex.tau[n0 : n0 + N]
    assert abs(res.extra["tau_map"][-1] / tau_exact[-1] - 1.0) < 3 * max(rel[-1], 1e-4)


def test_asymptotic_map_rejects_early_start():
    """In the double-impact regime of the rest-coeff drop mu Xdot/(3 gamma) ~ 0.7: eq. restituzione does not apply."""
    p, ini = drop(1e-5, 0.01, 0.25)
    with pytest.raises(ValueError, match="too early"):
        rigid.run_asymptotic(p, ini, {"n0": 2}, max_events=10)


# --------------------------------------------------------------------------- contact switch


def test_contact_switch_converges_as_delta_to_zero():
    """Section 8.2: eps-solutions converge to the sticky solution, so the switch error must vanish with delta.
    Late, the micro-bounces carry x ~ Xdot tau ~ Xdot^2/gamma: expect max|y - y_exact| ~ delta^2/gamma
    (a factor >= 30 per decade of delta) and the energy left out ~ delta^2/4; each switch removes exactly
    Xdot^2/4 (y, y' kept, x' -> 0)."""
    p, ini = drop(0.01, 0.01, 6.0)
    T = 3500.0  # the switch at delta = 1e-5 comes at n ~ 3 gamma/(mu delta) = 3e5, t ~ (3/mu) ln(n/4.2) ~ 3360
    ex = simulate(p, ini, max_events=1_000_000, t_max=T)
    grid = np.linspace(0.0, T, 5001)
    from bounce.sampling import sample_trajectory

    s_ex = sample_trajectory(ex, grid)
    y_ex = p.y_eq + s_ex["y_minus_yeq"]
    e_ex = contact_switch.energy_excess_samples(s_ex, p.gamma)
    errs, e_errs = [], []
    # delta must stay below the speeds of the chaotic transient's macroscopic impacts (down to ~7e-3
    # here, depending on the rounding history): only then does the switch happen in the asymptotic
    # regime, where the delta^2 law holds
    deltas = (1e-3, 1e-4, 1e-5)
    for delta in deltas:
        res = contact_switch.run(p, ini, {"delta": delta}, max_events=1_000_000, t_max=T, sample_times=grid)
        assert res.extra["n_switches"] >= 1 and res.extra["stop_reason"] == "sticky_forever"
        u = res.xdot[-1]  # the switching impact
        assert u < delta
        assert abs(res.extra["energy_removed"][0] - u * u / 4.0) <= 1e-12 * u * u
        assert res.extra["n_impacts"] < np.count_nonzero(ex.kind == 0)
        errs.append(np.nanmax(np.abs(res.y - y_ex)))
        e_errs.append(np.nanmax(np.abs(contact_switch.energy_excess_samples(res.extra["samples"], p.gamma) - e_ex)))
    assert errs[0] > 30 * errs[1] > 900 * errs[2], errs
    assert errs[0] < deltas[0] ** 2 / p.gamma  # measured 0.36 delta^2/gamma
    for delta, e in zip(deltas, e_errs):
        assert e <= 1.5 * delta**2 / 4.0, (delta, e)


def test_contact_switch_with_zero_delta_is_exact():
    p, ini = drop(1e-5, 2.0, 0.25)
    ex = simulate(p, ini, max_events=3000)
    res = contact_switch.run(p, ini, {"delta": 0.0}, max_events=3000)
    assert res.extra["n_switches"] == 0
    np.testing.assert_allclose(res.t, ex.t, rtol=4 * EPS)
    np.testing.assert_array_equal(res.xdot, ex.xdot)


def test_exact_cost_grows_like_exp_mu_t_over_3():
    """tau_n ~ 3/(mu n) (Theorem main_thm) => t_n ~ (3/mu) ln n: ln n against t_n has slope mu/3."""
    tr = long_exact(0.01, 0.01, 6.0, 110_001)
    n = np.arange(1, len(tr) + 1)
    sel = n >= 10_000
    b = np.polyfit(tr.t[sel], np.log(n[sel]), 1)[0]
    assert abs(b / (0.01 / 3.0) - 1.0) < 2e-3, b


# --------------------------------------------------------------------------- predictability horizon


def test_hp_flight_matches_bounce_first_impacts():
    """The mpmath reference (at 30 digits) and the long-double flights agree with bounce where all are exact
    (before any amplification)."""
    p, ini = drop(0.01, 0.01, 6.0)
    ref = horizon.reference_trajectory(0.01, 0.01, ini, 3, 30)
    f64 = simulate(p, ini, max_events=3)
    err = horizon.rel_diff(f64.t, ref["t"])
    assert np.all(err < 1e-14), err
    ld = horizon.longdouble_trajectory(0.01, 0.01, ini, 3)
    assert np.all(horizon.rel_diff(ld["t"], ref["t"]) < 1e-17)


def test_horizon_overdamped_covers_the_whole_run():
    """gamma = 1e-5, mu = 2 from psi(0) = 0.25: no chaotic transient, float64 follows the exact impacts throughout."""
    gamma, mu = 1e-5, 2.0
    _, ini = drop(gamma, mu, 0.25)
    n = 150
    ref = horizon.reference_trajectory(gamma, mu, ini, n, 30)
    f64 = horizon._float64_run(gamma, mu, ini, n)
    assert ref["n"] == n == f64["n"]
    err = horizon.rel_diff(f64["t"], ref["t"])
    assert horizon.horizon_index(err, 1e-8) == n
    assert err.max() < 1e-14


def test_horizon_chaotic_transient():
    """gamma = mu = 0.01 from psi(0) = 6: the float64 trajectory leaves the exact one (1e-8 relative in t_n)
    after ~15-25 impacts; longer working precision moves the horizon out (about ln(eps_64/eps)/lambda)."""
    gamma, mu = 0.01, 0.01
    _, ini = drop(gamma, mu, 6.0)
    n = 45
    ref = horizon.reference_trajectory(gamma, mu, ini, n, 40)
    f64 = horizon._float64_run(gamma, mu, ini, n)
    ld = horizon.longdouble_trajectory(gamma, mu, ini, n)
    h64 = horizon.horizon_index(horizon.rel_diff(f64["t"], ref["t"]), 1e-8)
    hld = horizon.horizon_index(horizon.rel_diff(ld["t"], ref["t"]), 1e-8)
    assert 15 <= h64 <= 25, h64
    assert hld > h64, (hld, h64)


def test_yardstick_reach_stops_where_the_self_check_decorrelates():
    """Comparisons stop at the first impact where the dps_low self-check is off the yardstick by more than 1e-4
    (beyond, nothing bounds the yardstick's own error); a self-check that never departs keeps every impact."""
    t_ref = np.arange(1.0, 101.0)
    growth = 1e-30 * np.exp(np.arange(100.0))  # an error growing by e per impact, from 1e-30
    k = horizon.yardstick_reach(t_ref * (1 + growth), t_ref, 100)
    assert growth[k - 1] > 1e-4 >= growth[k - 2]
    assert horizon.yardstick_reach(t_ref, t_ref, 100) == 100
    assert horizon.yardstick_reach(t_ref * (1 + growth), t_ref, 20) == 20


def test_least_model_reference_reads_a_thinned_scene():
    """least_model's reference is the scene's dataset.  A scene thinned to its first events plus log-spaced ones
    (keep) gives the asymptotic laws n tau_n mu/3, n Xdot_n mu/(3 gamma) at its kept impacts bit for bit as the
    unthinned scene does at the same impacts, and the exact solver's own output meets it with error 0."""
    from bounce.studies.reduced import _Output, _Reference
    from bounce.scenes import scene_dataset

    spec = {"gamma": 1e-5, "mu": 2.0, "initial": {"psi": 0.25, "psidot": 0.0, "xi": 0.0, "xidot": 0.0},
            "stop": {"events": 6000}}
    qoi = {"asymptotic_laws": {"tol": 1e-3, "n_min": 1000, "points": 50}}
    params = Parameters(1e-5, 2.0)
    full = _Reference(params, scene_dataset(spec), qoi)
    thin = _Reference(params, scene_dataset(dict(spec, keep={"first": 500, "log_samples": 300})), qoi)
    assert thin.n_impacts == full.n_impacts == 6000
    idx = thin.points(qoi["asymptotic_laws"])
    assert 20 <= idx.size <= 50 and idx.min() >= 1000 and idx.max() <= 5998
    assert np.all(np.isin(idx, thin.kept_impacts))
    a_thin = thin.values["asymptotic_laws"]
    a_full = thin.extract("asymptotic_laws", qoi["asymptotic_laws"], full.output)  # full records, same impacts
    assert np.array_equal(a_thin, a_full)
    p, ini = drop(1e-5, 2.0, 0.25)
    exact_out = _Output.from_traj(simulate(p, ini, max_events=6000))
    assert thin.error("asymptotic_laws", qoi["asymptotic_laws"], exact_out) == 0.0

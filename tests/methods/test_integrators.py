"""General-purpose comparison methods (scipy solve_ivp, DEM penalty + Verlet, Moreau--Jean) against the
exact solver: accuracy at tight settings, observed convergence orders, deliberately triggered failures,
the MethodResult contract.  Drop gamma = mu = 0.01 from psi(0) = 6 (paper, fig. rigid-fall).

Orders are read as least-squares slopes of log(error) over a sweep, with the error of each setting an
RMS over a few start states (psi(0) = 6 + U(0, 0.01), or sub-step offsets of one contact): time-stepping
schemes locate contacts only to the step, so a single run's error depends on where the contact falls in
the step grid and a single halving can give any ratio; averaged over that phase the order shows.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from bounce import Parameters, State
from bounce.methods import exact, moreau_jean, penalty, registry, scipy_ivp
from bounce.methods.base import FAILURES, MethodResult
from bounce.springs import SPRING_LAWS

GAMMA = MU = 0.01
P = Parameters(GAMMA, MU)
DROP = State.from_psi_xi(6.0, 0.0, 0.0, 0.0)
N5 = 5
rng = np.random.default_rng(1)
PSIS = tuple(6.0 + rng.uniform(0.0, 0.01, 6))


def drop(psi0=6.0):
    return State.from_psi_xi(psi0, 0.0, 0.0, 0.0)


def exact_times(state, n=N5):
    return exact.run(P, state, max_events=n).t


def max_rel(t, t_ref):
    assert t.size >= t_ref.size, f"only {t.size} impacts, expected {t_ref.size}"
    return float(np.max(np.abs(t[: t_ref.size] - t_ref) / t_ref))


def slope(x, y):
    return float(np.polyfit(np.log(x), np.log(y), 1)[0])


def rms_over_phases(run, setting, n=N5):
    errs = [max_rel(run(P, drop(ps), setting, max_events=n).t, exact_times(drop(ps), n)) for ps in PSIS]
    return float(np.sqrt(np.mean(np.square(errs))))


# --------------------------------------------------------------------------- contract

METHODS = {
    "scipy": (scipy_ivp, {"solver": "RK45", "rtol": 1e-6, "atol": 1e-9}),
    "penalty": (penalty, {"stiffness": 1e5, "omega_dt": 0.1}),
    "moreau-jean": (moreau_jean, {"dt": 1e-3}),
}


@pytest.mark.parametrize("name", sorted(METHODS))
def test_contract(name):
    """Registered under its name; MethodResult fields; y sampled (NaN after the stop); no raise."""
    module, setting = METHODS[name]
    assert registry()[name] is module.METHOD
    samples = np.array([[0.0, 10.0], [30.0, 1e6]])  # any shape; the last one lies after the stop
    r = module.run(P, DROP, setting, max_events=3, sample_times=samples)
    assert isinstance(r, MethodResult) and r.method == name
    assert r.t.shape == r.xdot.shape == (3,) and r.t.dtype == r.xdot.dtype == np.float64
    assert np.all(np.diff(r.t) > 0) and np.all(r.xdot > 0)
    assert r.failure in FAILURES and r.failure == "" and r.failure_index == -1
    assert math.isfinite(r.cpu_time) and r.cpu_time >= 0.0
    assert r.t_end >= r.t[-1]
    assert r.y.shape == samples.shape and np.isnan(r.y[1, 1])
    y_ex = exact.run(P, DROP, max_events=3, sample_times=samples[:, :1].ravel()).y
    assert np.allclose(r.y[:, 0], y_ex, atol=1e-5)  # before the first impact: smooth flight
    assert r.setting == setting


@pytest.mark.parametrize("name, setting", [
    ("scipy", {"solver": "RK45", "rtol": 1e-2, "atol": 1e-4}),
    ("scipy", {"solver": "LSODA", "rtol": 1e-3, "atol": 1e-5}),
    ("penalty", {"stiffness": 1e4, "omega_dt": 2.5}),
    ("penalty", {"stiffness": 10.0, "omega_dt": 0.01}),
    ("moreau-jean", {"dt": 1e-3, "restitution": 0.0}),
])
def test_failure_is_reported_not_raised(name, setting):
    module = METHODS[name][0]
    # LSODA's stall (test_scipy_lsoda_stall_and_budget) starts after ~480 impacts on some CPUs: room for it
    r = module.run(P, DROP, setting, max_events=2000 if setting.get("solver") == "LSODA" else 500)
    assert r.failure in FAILURES[1:] and 0 <= r.failure_index <= r.t.size
    assert r.t.size == r.xdot.size


# --------------------------------------------------------------------------- scipy

def test_scipy_tight_reproduces_exact():
    """DOP853 at rtol 1e-12: the first 5 impact times to 100 rtol (tolerance proportionality, measured ~1e-12)."""
    r = scipy_ivp.run(P, DROP, {"solver": "DOP853", "rtol": 1e-12, "atol": 1e-14}, max_events=N5)
    assert r.failure == ""
    assert max_rel(r.t, exact_times(DROP)) < 1e-10


def test_scipy_tolerance_proportionality():
    """RK45: error of the first 5 impact times ~ rtol^1 (observed slope 1.0; band 0.75..1.25)."""
    rtols = np.array([1e-5, 1e-6, 1e-7, 1e-8])
    errs = [rms_over_phases(scipy_ivp.run, {"solver": "RK45", "rtol": r, "atol": 1e-3 * r}) for r in rtols]
    assert 0.75 < slope(rtols, errs) < 1.25, errs
    assert errs[-1] < 100 * rtols[-1]


def dip_state(delta):
    """A state whose free flight dips delta below the floor ~2 time units later, with x'' = 0.04 > 0 at
    the bottom: x = -delta, x' = 0, xi = 0.05 (spring stretched), psi' = xi' = 0, integrated backwards."""
    xi = 0.05
    s_bottom = np.array([-delta, 0.0, (xi - delta) + xi + 1.0, 0.0])
    rhs = scipy_ivp.dynamics(P)[0]
    back = solve_ivp(rhs, (0.0, -2.0), s_bottom, method="DOP853", rtol=1e-13, atol=1e-15)
    return State(*back.y[:, -1])


def test_scipy_missed_impact_detected():
    """Loose RK45 steps over a 5e-4 dip the exact solver resolves as an impact: reported as missed_impact;
    at rtol 1e-8 the same flight gives the exact impact."""
    st = dip_state(5e-4)
    t_ex = exact_times(st, 2)
    assert 1.5 < t_ex[0] < 2.0
    loose = scipy_ivp.run(P, st, {"solver": "RK45", "rtol": 1e-2, "atol": 1e-6}, max_events=2)
    assert loose.failure == "missed_impact" and loose.failure_index == 0 and loose.t.size == 0
    tight = scipy_ivp.run(P, st, {"solver": "RK45", "rtol": 1e-8, "atol": 1e-11}, max_events=2)
    assert tight.failure == "" and max_rel(tight.t, t_ex) < 1e-6


def test_scipy_plain_restart_stalls_divided_does_not():
    """The restart trap: from the floor with a tiny upward speed (flight 1e-3 shorter than the first step),
    the plain event x = 0 re-triggers at the restart; the divided difference x/(t - t_r) does not."""
    st = State(0.0, 1e-5, P.y_eq, 0.0)
    for solver in ("RK45", "DOP853"):
        plain = scipy_ivp.run(P, st, {"solver": solver, "rtol": 1e-10, "atol": 1e-12, "restart": "plain"},
                              max_events=200)
        assert plain.failure == "stall" and plain.failure_index == scipy_ivp.STALL_COUNT
        good = scipy_ivp.run(P, st, {"solver": solver, "rtol": 1e-10, "atol": 1e-12}, max_events=200)
        assert good.failure == "" and np.all(np.diff(good.t) > 9e-4)
        ref = exact.run(P, st, max_events=200).t
        assert max_rel(good.t, ref) < 1e-6


def test_scipy_lsoda_stall_and_budget():
    """LSODA's interpolant does not pass through the restart state at loose rtol: zero-length flights
    (stall); a Radau run at rtol 1e-12 stops on its CPU budget inside a single solve_ivp call."""
    r = scipy_ivp.run(P, DROP, {"solver": "LSODA", "rtol": 1e-3, "atol": 1e-5}, max_events=2000)
    assert r.failure == "stall"
    b = scipy_ivp.run(P, DROP, {"solver": "Radau", "rtol": 1e-12, "atol": 1e-14, "cpu_budget": 0.2}, max_events=20)
    assert b.failure == "budget" and b.cpu_time < 0.5


def test_scipy_energy_gain_at_loose_tolerance():
    """RK45 at rtol 1e-2 gains energy over the first flights (E - E_m up by > 1e-3 relative)."""
    r = scipy_ivp.run(P, DROP, {"solver": "RK45", "rtol": 1e-2, "atol": 1e-4}, max_events=100)
    assert r.failure == "energy_gain" and r.failure_index < 10


# --------------------------------------------------------------------------- penalty

def test_penalty_model_error_order_half_in_stiffness():
    """At resolved steps (omega dt = 0.01) the error against the rigid floor is the soft model's:
    a delay ~ pi/sqrt(k_n) per contact, so ~ k_n^-1/2 (observed slope -0.51; band -0.65..-0.35);
    at k_n = 1e6 the first 5 impact times within 2e-4 (measured 4.6e-5)."""
    ks = np.array([1e4, 1e5, 1e6])
    t_ex = exact_times(DROP)
    errs = [max_rel(penalty.run(P, DROP, {"stiffness": k, "omega_dt": 0.01}, max_events=N5).t, t_ex) for k in ks]
    assert -0.65 < slope(ks, errs) < -0.35, errs
    assert errs[-1] < 2e-4


def test_penalty_verlet_order_two_per_contact():
    """One contact at fixed k_n: the exit-speed error against omega dt = 1e-3, RMS over 32 sub-step
    offsets of the entry, falls as (omega dt)^2 (observed slope 2.05; band 1.7..2.4)."""
    k, v, J = 1e4, 0.3, 32
    dt0 = 0.2 / math.sqrt(k)
    starts = [State(v * dt0 * (j + 0.5) / J, -v, P.y_eq, -v) for j in range(J)]
    ref = [penalty.run(P, s, {"stiffness": k, "omega_dt": 1e-3}, max_events=1).xdot[0] for s in starts]
    ws = np.array([0.2, 0.1, 0.05, 0.025])
    errs = []
    for w in ws:
        e = [abs(penalty.run(P, s, {"stiffness": k, "omega_dt": w}, max_events=1).xdot[0] - r) / r
             for s, r in zip(starts, ref)]
        errs.append(np.sqrt(np.mean(np.square(e))))
    assert 1.7 < slope(ws, errs) < 2.4, errs


def test_penalty_coarse_step_and_soft_floor_fail():
    """omega dt = 2.5 > 2 (Verlet unstable for the contact spring): energy pumped in the first contact;
    with the energy check off, the pumped energy drives the mass through the floor (x < -0.1 L) within
    50 contacts.  k_n = 10: the overlap |x'|/sqrt(k_n) ~ 0.11 exceeds the 0.1 L limit at once."""
    coarse = penalty.run(P, DROP, {"stiffness": 1e4, "omega_dt": 2.5}, max_events=50)
    assert coarse.failure == "energy_gain" and coarse.failure_index == 0
    unchecked = penalty.run(P, DROP, {"stiffness": 1e4, "omega_dt": 2.5, "energy_tol": math.inf}, max_events=50)
    assert unchecked.failure == "fell_through"
    assert np.nanmax(unchecked.extra["energy_excess"]) > 2 * (DROP.energy(P) - P.energy_min)
    soft = penalty.run(P, DROP, {"stiffness": 10.0, "omega_dt": 0.01}, max_events=10)
    assert soft.failure == "fell_through" and soft.failure_index == 0


def test_penalty_energy_gain_at_moderate_step():
    """omega dt = 0.4: per-contact energy errors ~ (omega dt)^2 exceed the dissipation per flight early."""
    r = penalty.run(P, DROP, {"stiffness": 1e4, "omega_dt": 0.4}, max_events=10000)
    assert r.failure == "energy_gain" and r.failure_index < 500


def test_penalty_permanent_contact_where_flights_reach_contact_time():
    """k_n = 1e4, omega dt = 0.03: the bounce dies on the soft floor (endless_contact) once the exact
    flight time ~ 3/(mu n) has shrunk to the contact's own time scale 2 pi/sqrt(k_n) (within x10)."""
    k = 1e4
    r = penalty.run(P, DROP, {"stiffness": k, "omega_dt": 0.03}, max_events=10**5)
    assert r.failure == "endless_contact"
    n = r.failure_index + 1
    tau_exact = 3.0 / (MU * n)
    assert 0.1 < tau_exact / (2 * math.pi / math.sqrt(k)) < 10.0, (n, tau_exact)


# --------------------------------------------------------------------------- Moreau--Jean

def test_moreau_jean_order_one():
    """Impacts located to the step: first 5 impact times with error ~ dt^1 (observed slope 0.96; band
    0.7..1.3), and within 0.2 dt relative (measured 0.04 dt) at dt = 1.25e-4."""
    dts = np.array([4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4, 1.25e-4])
    errs = [rms_over_phases(moreau_jean.run, {"dt": h}) for h in dts]
    assert 0.7 < slope(dts, errs) < 1.3, errs
    assert errs[-1] < 0.2 * dts[-1]


def test_moreau_jean_breaks_when_flights_reach_the_step():
    """dt = 1e-2: runs through the chaotic transient, then fails (energy_gain) once the exact flight
    time 3/(mu n) is comparable to the step (0.5..3 dt); a wrong asymptotic constant before that."""
    h = 1e-2
    r = moreau_jean.run(P, DROP, {"dt": h}, max_events=10**5)
    assert r.failure == "energy_gain"
    tau_exact = 3.0 / (MU * (r.failure_index + 1))
    assert 0.5 < tau_exact / h < 3.0


def test_moreau_jean_inelastic_floor_rests():
    """restitution 0: the lower mass stays on the floor -- a contact that never ends (endless_contact)."""
    r = moreau_jean.run(P, DROP, {"dt": 1e-3, "restitution": 0.0}, max_events=200)
    assert r.failure == "endless_contact"


def test_budgets_stop_time_stepping():
    for module, setting in ((moreau_jean, {"dt": 1e-6, "cpu_budget": 0.02}),
                            (penalty, {"stiffness": 1e8, "omega_dt": 0.01, "cpu_budget": 0.02})):
        r = module.run(P, DROP, setting, max_events=10**5)
        assert r.failure == "budget" and r.cpu_time < 0.2


# --------------------------------------------------------------------------- measurement layer

def _methods_slice(methods: dict, kind: str, block: str | None = None) -> dict:
    """A study's slice of a ``methods`` section, validated and defaulted by config/schema.yaml as in the pipeline."""
    from bounce.pipeline.config import load_schema, validated
    from bounce.studies.base import study_slice

    schema = {**load_schema(), "required": ["methods"]}
    return study_slice(validated({"methods": methods}, schema)["methods"], kind, block)


def test_compare_datasets_and_figures(tmp_path):
    """A tiny work-precision and stability-map spec: every variable has units and long_name, the exact row
    scores zero error, failures are recorded, both figures are written."""
    from bounce.studies import compare

    methods = {
        "scenes": {"drop": {"gamma": GAMMA, "mu": MU, "initial": {"psi": 6.0, "psidot": 0.0, "xi": 0.0, "xidot": 0.0}}},
        "work_precision": {
            "scene": "drop", "n_h": 3, "y_window": {"t": [0.0, 60.0], "samples": 61},
            "one_step": {"impacts": [0, 5]}, "transient_budget": 2.0, "long": {"events": 300, "cpu_budget": 0.2},
            "asymptotic": {"n": [200], "window": 50, "n_min": 100, "spread_runs": 2},
            "timing": {"min_total": 0.0, "max_repeats": 1},
            "sweeps": [
                {"method": "scipy", "curves": {"solver": ["RK45"]}, "vary": {"rtol": [1e-4, 1e-7], "atol": [1e-6, 1e-9]}},
                {"method": "penalty", "curves": {"stiffness": ["1.0e4"]}, "vary": {"omega_dt": [0.4, 0.1]}},
                {"method": "moreau-jean", "vary": {"dt": [1e-3]}},
            ],
        },
        "stability_map": {"scene": "drop", "events": 3000, "cpu_budget": 0.2, "starts": [0, 1000], "flights": 500,
                          "sweeps": [{"method": "moreau-jean", "vary": {"dt": [1e-2]}},
                                     {"method": "penalty", "curves": {"stiffness": [1e4]}, "vary": {"omega_dt": [0.4]}}]},
    }
    spec_wp = _methods_slice(methods, "work_precision")
    spec_sm = _methods_slice(methods, "stability_map")
    wp = compare.work_precision(spec_wp)
    sm = compare.stability_map(spec_sm)
    for ds in (wp, sm):
        for name, var in ds.variables.items():
            assert "long_name" in var.attrs and "units" in var.attrs, name
    assert wp.sizes["run"] == 6 and list(wp["method"].values[:2]) == ["exact", "scipy"]
    assert float(wp["err_impact_times"][0]) == 0.0 and float(wp["err_y_rms"][0]) == 0.0
    tight, loose = float(wp["err_impact_times"][2]), float(wp["err_impact_times"][1])
    assert 0.0 < tight < loose < 1e-2
    assert wp["setting"].values[3] == '{"omega_dt": 0.4, "stiffness": 10000.0}'  # "1.0e4" read as a number
    assert sm["failure"].dims == ("run", "start") and set(sm["failure"].values.ravel()) <= set(FAILURES)
    # penalty at omega_dt = 0.4 through the chaotic transient: where the energy first rises moves with one ulp of
    # psi(0) (168, 259, 107 for psi(0) = 6, 6 (1 +- 2^-52); 50, 153, 8 with the linear force written as
    # -x/2 - gamma - 1/2 + y/2 before the law's f(xi) replaced it): a pin of this trajectory, not a tolerance
    assert sm["failure"].values[1, 0] == "energy_gain" and sm["failure_index"].values[1, 0] == 168
    deep = int(sm["n_impacts"].values[0, 1])  # Moreau-Jean dt = 1e-2 from the exact state after impact 1000
    assert deep == 1500 and sm["n_tracked"].values[0, 1] >= 1000
    compare.plot_work_precision(wp, spec_wp, [tmp_path / "wp.png"])
    compare.plot_stability_map(sm, spec_sm, [tmp_path / "sm.png"])
    assert (tmp_path / "wp.png").stat().st_size > 0 and (tmp_path / "sm.png").stat().st_size > 0
    head = compare.headline(wp, 1e-3)
    assert head["scipy"]["cpu_ratio_transient"] > 1.0


HERTZ_DROP = {"gamma": GAMMA, "mu": MU, "spring": {"law": "power", "rho": 1.0, "a": 0.5, "b": 0.5},
              "initial": {"psi": 6.0, "psidot": 0.0, "xi": -0.046415888336127795, "xidot": 0.0}}


def test_compare_on_the_hertz_spring(tmp_path):
    """The studies on a power-law scene: bounce's power-law solver is the reference (its row scores 0),
    heyoka at machine tolerance tracks the first impacts to ~1e-12 and a loose tolerance does worse; no
    y window (no dense output for the power law); the asymptotic constant is normalised by alpha gamma;
    a method that needs the closed-form solver (the linear spring) is refused with its name."""
    pytest.importorskip("heyoka")
    from bounce.studies import compare
    from bounce.analysis.theory import nonlin_alpha_limit

    heyoka = [{"method": "heyoka", "vary": {"tol": [1e-6, 2.0**-52]}}]
    methods = {
        "scenes": {"hertz": HERTZ_DROP},
        "work_precision": {"scene": "hertz", "n_h": 5, "one_step": {"impacts": [0, 50]}, "transient_budget": 2.0,
                           "long": {"events": 1200, "cpu_budget": 2.0},
                           "asymptotic": {"n": [1000], "window": 50, "n_min": 1000, "spread_runs": 2},
                           "timing": {"min_total": 0.0, "max_repeats": 1}, "sweeps": heyoka},
        "stability_map": {"scene": "hertz", "events": 1500, "cpu_budget": 2.0, "starts": [0, 1000], "flights": 300,
                          "sweeps": heyoka},
    }
    spec_wp = _methods_slice(methods, "work_precision")
    wp = compare.work_precision(spec_wp)
    assert list(wp["method"].values) == ["exact", "heyoka", "heyoka"] and wp.attrs["spring_law"] == "power"
    assert float(wp["err_impact_times"][0]) == 0.0 and np.isnan(wp["err_y_rms"].values).all()
    loose, tight = float(wp["err_impact_times"][1]), float(wp["err_impact_times"][2])
    assert tight < 1e-12 and tight < loose
    assert float(wp["err_one_step_max"][2]) < 1e-12
    hertz = Parameters(GAMMA, MU, SPRING_LAWS["power"](1.0, 0.5, 0.5))
    assert wp.attrs["asym_scale"] == MU * hertz.spring.damping_factor(hertz.xi_eq) / 3.0  # mu g(xi_eq)/3
    assert wp.attrs["asym_scale"] == pytest.approx(GAMMA * nonlin_alpha_limit(GAMMA, MU, 1.0, 0.5, 0.5), rel=4e-16)
    assert abs(float(wp["asym_constant_ref"][0]) - 1.0) < 0.3  # n tau_n alpha gamma near its limit 1 at n = 1000
    spec_sm = _methods_slice(methods, "stability_map")
    sm = compare.stability_map(spec_sm)
    assert (sm["failure"].values == "").all() and (sm["n_impacts"].values == [[1500, 1300]] * 2).all()
    compare.plot_work_precision(wp, spec_wp, [tmp_path / "wp.png"])
    compare.plot_stability_map(sm, spec_sm, [tmp_path / "sm.png"])
    assert (tmp_path / "wp.png").stat().st_size > 0 and (tmp_path / "sm.png").stat().st_size > 0
    methods["stability_map"]["sweeps"] = [{"method": "contact-switch", "vary": {"delta": [1e-6]}}]
    with pytest.raises(ValueError, match="method 'contact-switch' does not simulate the 'power' spring.*closed-form"):
        compare.stability_map(_methods_slice(methods, "stability_map"))

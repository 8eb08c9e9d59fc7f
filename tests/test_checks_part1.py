"""Unit tests of the checks main-theorem, static-equilibrium, restitution and rigid-collapse.

Small scenes (<= 3e4 events) keep this file fast.  Every check is shown able to fail: a
dataset doctored to follow a wrong law flips the verdict of the row that tests the law.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from bounce.checks import asymptotics, equilibrium, registry, restitution, rigid_models
from bounce.checks.base import NOT_REPRODUCED, REPRODUCED, VERDICTS, read_verdicts
from bounce.scenes import scene_dataset

UD = {"gamma": 0.01, "mu": 0.01, "initial": {"psi": 6.0, "psidot": 0.0, "xi": 0.0, "xidot": 0.0},
      "stop": {"events": 30000}, "keep": {"first": 3000, "log_samples": 1000}}
OD = {"gamma": 1e-5, "mu": 2.0, "initial": {"psi": 0.25, "psidot": 0.0, "xi": 0.0, "xidot": 0.0},
      "stop": {"events": 30000}, "keep": {"first": 3000, "log_samples": 1000}}
REST = {"gamma": 1e-5, "mu": 0.01, "initial": {"psi": 0.25, "psidot": 0.0, "xi": 0.0, "xidot": 0.0},
        "stop": {"events": 200000}}
ODFULL = dict(OD, stop={"events": 3000}, keep=None)

SPECS = {
    "main-theorem": {"fit": {"n_min": 1000}, "atlas": {"mu": [0.3, 2.0], "gamma": [1e-3], "psi0": 0.25,
                                                       "events": 20000}, "plot_points": 100},
    "static-equilibrium": {"asymptotic_min_events": 20000, "limit_bracket": 0.01},
    "restitution": {},
    "rigid-collapse": {"onefifth_bounces": 30000, "our_r_bounces": 30000, "tail_window": [1000, 5000]},
}


@pytest.fixture(scope="module")
def scenes():
    return {"ud": scene_dataset(UD, "ud"), "od": scene_dataset(OD, "od"), "rest": scene_dataset(REST, "rest"),
            "odfull": scene_dataset(ODFULL, "odfull"), "odall": scene_dataset(dict(OD, keep=None, stop={"events": 100000}), "od")}


def inputs_for(name, scenes):
    return {"main-theorem": [scenes["ud"], scenes["od"]],
            "static-equilibrium": [scenes["ud"], scenes["od"], scenes["rest"]],
            "restitution": [scenes["rest"], scenes["odfull"]],
            "rigid-collapse": [scenes["ud"]]}[name]


def rows(ds):
    return {v.claim: v for v in read_verdicts(ds)}


def row(ds, start):
    hits = [v for c, v in rows(ds).items() if c.startswith(start)]
    assert len(hits) == 1, (start, list(rows(ds)))
    return hits[0]


@pytest.fixture(scope="module")
def results(scenes):
    reg = registry()
    return {name: reg[name].run(SPECS[name], inputs_for(name, scenes)) for name in SPECS}


# --------------------------------------------------------------------------- contract

@pytest.mark.parametrize("name", list(SPECS))
def test_registered_and_rows_well_formed(name, results):
    check = registry()[name]
    assert check.name == name and check.title
    ds = results[name]
    vs = read_verdicts(ds)
    assert vs, "a check must produce verdict rows"
    for v in vs:
        assert v.verdict in VERDICTS
        for field in ("claim", "paper_ref", "computed", "expected", "measured", "tolerance"):
            assert isinstance(getattr(v, field), str) and getattr(v, field).strip(), (name, field, v)
    for var in ds.variables.values():
        assert "units" in var.attrs and "long_name" in var.attrs, var.name


@pytest.mark.parametrize("name", list(SPECS))
def test_plot_writes_png_and_pdf(name, results, tmp_path):
    outs = [tmp_path / f"{name}.png", tmp_path / f"{name}.pdf"]
    registry()[name].plot(results[name], SPECS[name], outs)
    assert all(p.exists() and p.stat().st_size > 1000 for p in outs)


def test_all_paper_claims_reproduced_on_small_scenes(results):
    """On the small scenes every non-erratum row is reproduced or (too short a run) not checkable."""
    for name, ds in results.items():
        for v in read_verdicts(ds):
            printed = "printed" in v.claim or "Beyond the paper: a rigid ball" in v.claim
            if not printed:
                assert v.verdict != NOT_REPRODUCED, (name, v)


# --------------------------------------------------------------------------- main-theorem

def test_exponent_theory():
    assert asymptotics.exponent_theory(0.01) == 1.0 and asymptotics.exponent_theory(1.5) == pytest.approx(1.0)
    assert asymptotics.exponent_theory(2.0) == pytest.approx(3 * (2 - math.sqrt(2)) / 2 / 2)
    assert asymptotics.exponent_theory(5.0) == pytest.approx(0.06126, abs=1e-5)


def test_core_derivatives_match_finite_differences():
    """Xddot, Xdddot of the brief, against the numerical derivative of x(t) just after an impact."""
    from bounce import Parameters, State, simulate
    from bounce.sampling import sample_trajectory

    p = Parameters(0.01, 0.3)
    tr = simulate(p, State.from_psi_xi(0.5, 0.0, 0.0, 0.0), max_events=5)
    k = 2
    h = 1e-3
    ts = tr.t[k] + h * np.arange(1, 6)
    x = sample_trajectory(tr, ts)["x"]
    # polynomial fit x = xdot s + a s^2/2 + b s^3/6 (+ s^4, s^5)
    s = ts - tr.t[k]
    a = np.column_stack([s, s**2 / 2, s**3 / 6, s**4 / 24, s**5 / 120])
    coef = np.linalg.solve(a, x)
    xdd, xddd = asymptotics.core_derivatives(tr.xidot[k], tr.eta[k], p.gamma, p.mu)
    assert coef[0] == pytest.approx(tr.xdot[k], rel=1e-6)
    assert coef[1] == pytest.approx(xdd, rel=1e-4, abs=1e-8)
    assert coef[2] == pytest.approx(xddd, rel=1e-2, abs=1e-6)


def test_restart_reproduces_thinned_events(scenes):
    """dataset_series on a thinned dataset gives the same tau_n, Xdot_(n+1) as the full simulation."""
    full = scene_dataset(dict(UD, keep=None))
    s_thin = asymptotics.dataset_series(scenes["ud"])
    s_full = asymptotics.dataset_series(full)
    idx = np.searchsorted(s_full["n"], s_thin["n"])
    assert np.array_equal(s_full["n"][idx], s_thin["n"])
    assert np.array_equal(s_full["tau"][idx], s_thin["tau"])
    assert np.array_equal(s_full["xdot_next"][idx], s_thin["xdot_next"])


def test_fit_limit_recovers_known_limits():
    n = np.arange(1.0, 2e5)
    t = 300.0 * np.log(n)  # t_n ~ (3/mu) ln n, mu = 0.01
    fit = dict(asymptotics.DEFAULT_FIT, n_min=1000)
    for L in (1.0, 1.003):
        q = L + 0.7 * np.log(n) / n - 2.0 / n
        f = asymptotics.fit_limit(n, t, q, 0.01, fit)
        assert abs(f["limit"] - L) < 1e-9 and f["limit_err"] < 1e-8
        assert f["exponent"] == pytest.approx(1.0, abs=0.01)
    # over-damped: slow spring term e^{-lam t}, t = (3/mu) ln n  ->  n^{-3 lam/mu}
    mu = 2.0
    p = asymptotics.exponent_theory(mu)
    t = 1.5 * np.log(n)
    q = 1.0 - 0.3 * n**-p + 0.05 * n ** (-2 * p) + 0.2 / n
    f = asymptotics.fit_limit(n, t, q, mu, fit)
    assert abs(f["limit"] - 1.0) < 1e-8
    assert abs(f["exponent"] - p) <= max(3 * f["exponent_err"], 0.02 * p) and f["exponent_err"] < 0.1 * p


def test_main_theorem_flips_on_wrong_flight_law(scenes):
    """tau_n ~ 6/(mu n) (all flights doubled) must fail the tau row and leave the Xdot row alone.

    Complete records: in a thinned file the tail is re-simulated from the stored states."""
    bad = scenes["odall"].copy(deep=True)
    bad["tau"] = bad["tau"] * 2.0
    spec = dict(SPECS["main-theorem"], atlas=None)
    ds = asymptotics.run(spec, [bad])
    assert row(ds, "tau_n ~ 3/(mu n) [od]").verdict == NOT_REPRODUCED
    assert row(ds, "Xdot_n ~ 3 gamma/(mu n) [od]").verdict == REPRODUCED
    assert row(ds, "Xdot_n / tau_n -> gamma [od]").verdict == NOT_REPRODUCED
    good = asymptotics.run(spec, [scenes["odall"]])
    assert row(good, "tau_n ~ 3/(mu n) [od]").verdict == REPRODUCED


def _with_exponent(ds, p_new, mu=2.0):
    """The scene with the correction of n tau_n mu/3 re-scaled from n^-p_th to n^-p_new (equal at n = 1000)."""
    bad = ds.copy(deep=True)
    n = bad["event"].values.astype(float)[1:]
    tau = bad["tau"].values.copy()
    q = n * tau[1:] * mu / 3.0
    tau[1:] *= 1.0 + (q - 1.0) * ((n / 1000.0) ** (asymptotics.exponent_theory(mu) - p_new) - 1.0) / q
    bad["tau"] = ("event", tau, bad["tau"].attrs)
    return bad


def test_main_theorem_flips_on_wrong_decay_exponent(scenes):
    """A correction decaying like n^-0.7 (n^-0.3) instead of the n^-0.439 of mu = 2 fails the exponent row."""
    spec = dict(SPECS["main-theorem"], atlas=None)
    good = asymptotics.run(spec, [scenes["odall"]])
    assert row(good, "n tau_n mu/3 - 1 decays like n^-p").verdict == REPRODUCED
    ds = asymptotics.run(spec, [_with_exponent(scenes["odall"], 0.7)])
    assert row(ds, "n tau_n mu/3 - 1 decays like n^-p").verdict == NOT_REPRODUCED
    ds = asymptotics.run(spec, [_with_exponent(scenes["odall"], 0.3)])
    assert row(ds, "n tau_n mu/3 - 1 decays like n^-p").verdict != REPRODUCED


# --------------------------------------------------------------------------- static-equilibrium

def test_equilibrium_flips_on_energy_increase(scenes):
    bad = scenes["rest"].copy(deep=True)
    e = bad["energy_excess"].values.copy()
    e[500] = e[499] * (1 + 1e-12)
    bad["energy_excess"] = ("event", e, bad["energy_excess"].attrs)
    ds = equilibrium.run(SPECS["static-equilibrium"], [bad])
    assert row(ds, "E never increases").verdict == NOT_REPRODUCED
    assert row(equilibrium.run(SPECS["static-equilibrium"], [scenes["rest"]]), "E never increases").verdict == REPRODUCED


def test_equilibrium_flips_on_wrong_rates(scenes):
    """Xdot_n decaying like n^-1/2 (rate mu/6 in t) fails the Xdot rate row."""
    bad = scenes["ud"].copy(deep=True)
    n = bad["event"].values + 1.0
    bad["xdot"] = bad["xdot"] * np.sqrt(n)
    ds = equilibrium.run(SPECS["static-equilibrium"], [bad])
    assert row(ds, "Xdot_n -> 0 exponentially").verdict == NOT_REPRODUCED
    good = equilibrium.run(SPECS["static-equilibrium"], [scenes["ud"]])
    assert row(good, "Xdot_n -> 0 exponentially").verdict == REPRODUCED
    assert row(good, "lim E = -gamma/2").verdict == NOT_REPRODUCED  # the erratum stays an erratum


# --------------------------------------------------------------------------- restitution

def test_restitution_flips_on_wrong_plateau(scenes):
    bad = scenes["rest"].copy(deep=True)
    tau = bad["tau"].values.copy()
    m = np.arange(1, 200)
    tau[2 * m] *= 0.99**m  # r_m 1 % low over the double-impact regime
    bad["tau"] = ("event", tau, bad["tau"].attrs)
    ds = restitution.run({}, [bad])
    assert row(ds, "Initially r_n").verdict == NOT_REPRODUCED
    assert row(restitution.run({}, [scenes["rest"]]), "Initially r_n").verdict == REPRODUCED


def test_restitution_flips_on_wrong_small_u_law(scenes):
    bad = scenes["rest"].copy(deep=True)
    bad["xdot"] = bad["xdot"] / 1.05  # speeds 5 % low for their restitution: 1 - r = 1.05 mu u/(3 gamma)
    ds = restitution.run({}, [bad])
    assert row(ds, "Small-u branch of eq. our-r").verdict == NOT_REPRODUCED
    assert row(restitution.run({}, [scenes["rest"]]), "Small-u branch of eq. our-r").verdict == REPRODUCED


def test_restitution_flips_on_overdamped_from_above(scenes):
    bad = scenes["odfull"].copy(deep=True)
    bad["y_minus_yeq"] = -bad["y_minus_yeq"]
    ds = restitution.run({}, [bad])
    assert row(ds, "The over-damped spring shrinks").verdict == NOT_REPRODUCED
    assert row(restitution.run({}, [scenes["odfull"]]), "The over-damped spring shrinks").verdict == REPRODUCED


def test_our_r_is_continuous_at_uc():
    g, mu = 1e-5, 0.01
    uc = 3 * g / mu * (1 - restitution.r_double(mu))
    assert restitution.our_r(uc * (1 - 1e-12), g, mu) == pytest.approx(restitution.r_double(mu), abs=1e-10)


# --------------------------------------------------------------------------- rigid-collapse

def test_rigid_flips_on_wrong_closed_form(scenes, monkeypatch):
    real = rigid_models.constant_r

    def wrong(t1, v1, r, gamma, bounces):
        out = real(t1, v1, r, gamma, bounces)
        out["t_sum"] = out["t_sum"] * (1 + 1e-9)
        return out

    monkeypatch.setattr(rigid_models, "constant_r", wrong)
    ds = rigid_models.run(SPECS["rigid-collapse"], [scenes["ud"]])
    assert row(ds, "A rigid ball with constant r").verdict == NOT_REPRODUCED


def test_rigid_flips_on_wrong_exponent(scenes, monkeypatch):
    """A map with beta = 3/2 (n^2 u_n -> const) must fail the beta = 6/5 rows."""
    real = rigid_models.iterate_map
    monkeypatch.setattr(rigid_models, "iterate_map",
                        lambda u0, step, bounces: real(u0, lambda x: x - 1e-1 * x**1.5, bounces))
    ds = rigid_models.run(SPECS["rigid-collapse"], [scenes["ud"]])
    assert row(ds, "With r(u) = 1 - (u/U)^(1/5)").verdict == NOT_REPRODUCED
    assert row(ds, "... so the sum").verdict == NOT_REPRODUCED


def test_rigid_flips_on_collapsing_dimer(scenes):
    """A 'dimer' whose impact times grow twice as fast in ln n fails the no-collapse row."""
    bad = scenes["ud"].copy(deep=True)
    bad["t"] = bad["t"] * 2.0
    ds = rigid_models.run(SPECS["rigid-collapse"], [bad])
    assert row(ds, "The two-mass ball has no inelastic collapse").verdict == NOT_REPRODUCED

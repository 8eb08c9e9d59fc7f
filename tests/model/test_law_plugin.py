"""A spring law is a plug-in: a Duffing spring defined only in this module runs through every general-purpose
method and the CLI, with no other file touched.

The law (f(xi) = xi + k xi^3, g = 1, V = xi^2/2 + k xi^4/4: a hardening spring, no exact solver) is one
frozen dataclass with its numba physics, its parameter and its symbolic form (the contract of
bounce.springs.base), registered in bounce.springs.SPRING_LAWS for the test alone (:func:`registered`).
Protects: every method whose capability the law has runs it (scipy, penalty, Moreau-Jean, heyoka: the
methods call the law, not a right-hand side of their own); its physics holds there (E - E_m never rises
beyond the method's energy tolerance along the impacts); k = 0 reproduces the linear law's impacts, to the
bit through the same method (the same floats: xi + 0 xi^3 = xi) and to 1e-12 against the exact solver;
k > 0 is a different spring (the impacts move); the CLI's options, its --method path, the netCDF attributes
and the config schema follow the registry.
"""

from __future__ import annotations

import contextlib
from dataclasses import dataclass

import numpy as np
import pytest
import xarray as xr
from numba import njit

from bounce import Parameters, State, simulate
from bounce.methods import registry
from bounce.methods.base import FAILURES
from bounce.springs import LINEAR, SPRING_LAWS, Parameter, Physics, SpringLaw

GAMMA, MU = 0.05, 0.05
DROP = State.from_psi_xi(1.0, 0.0, 0.0, 0.0)
EVENTS = 12
#: settings of the methods: accurate enough that the impacts of two methods agree (compared below)
SETTINGS = {
    "scipy": {"solver": "DOP853", "rtol": 1e-11, "atol": 1e-13},
    "penalty": {"stiffness": 1e6, "omega_dt": 0.05},
    "moreau-jean": {"dt": 1e-4},
    "heyoka": {},
}


@njit
def _force(xi, c):
    return xi + c[0] * xi * xi * xi


@njit
def _stiffness(xi, c):
    return 1.0 + 3.0 * c[0] * xi * xi


@njit
def _damping(xi, c):
    return 1.0


@njit
def _potential(xi, c):
    return 0.5 * xi * xi + 0.25 * c[0] * xi * xi * xi * xi


@dataclass(frozen=True)
class DuffingSpring(SpringLaw):
    """f(xi) = xi + k xi^3, g = 1: no exact solver (``solver`` None), xi_eq by the contract's default bisection."""

    name = "duffing"
    summary = "a hardening Duffing spring xi'' = -xi - k xi^3 - 2 mu xi' (defined in a test)"
    PARAMETERS = (Parameter("k", "cubic stiffness of the Duffing spring", 0.0, 1e3),)
    physics = Physics(_force, _stiffness, _damping, _potential)

    k: float

    def symbolic(self, module, xi):
        return xi + self.k * xi * xi * xi, 1.0


@contextlib.contextmanager
def registered(law: type[SpringLaw]):
    """``law`` in the registry while the block runs (every derived interface sees it), removed after."""
    assert law.name not in SPRING_LAWS
    SPRING_LAWS[law.name] = law
    try:
        yield law
    finally:
        del SPRING_LAWS[law.name]


@pytest.fixture
def duffing():
    with registered(DuffingSpring) as law:
        yield law


def general_purpose_methods(params) -> list[str]:
    """The methods of the registry that can run ``params.spring`` and take the settings above."""
    return sorted(name for name, spec in registry().items() if spec.supports(params) and name in SETTINGS)


def impact_energies(result, params) -> np.ndarray:
    """E - E_m just after each impact the method reports: its own record, or (heyoka) from the post-impact
    x', xi', eta at x = 0 (eq. ``nonlin-energy``, the law's divergence)."""
    if "energy_excess" in result.extra:
        return np.asarray(result.extra["energy_excess"])
    u, v, eta = result.xdot, result.extra["xidot"], result.extra["eta"]
    return np.array([0.5 * (b * b + (a + b) ** 2) + params.spring.divergence(e, params.gamma)
                     for a, b, e in zip(u, v, eta)])


def energy_tolerance(name: str) -> float:
    """The method's own bound on a rise of E - E_m (relative): its energy_tol setting, or heyoka's ~1e-12 (its
    Taylor integrator at machine tolerance; measured rises < 1e-14)."""
    from importlib import import_module

    module = {"scipy": "scipy_ivp", "penalty": "penalty", "moreau-jean": "moreau_jean"}.get(name)
    return import_module(f"bounce.methods.{module}").DEFAULTS["energy_tol"] if module else 1e-12


def test_the_law_lives_only_here():
    """The Duffing law is not in the package: registering it is what makes it visible."""
    assert "duffing" not in SPRING_LAWS
    with registered(DuffingSpring):
        assert SPRING_LAWS["duffing"] is DuffingSpring
    assert "duffing" not in SPRING_LAWS


def test_its_physics_and_equilibrium(duffing):
    law = DuffingSpring(k=2.0)
    xi_eq = law.xi_eq(GAMMA)
    assert abs(law.restoring(xi_eq) + GAMMA) <= 2e-16 * GAMMA  # the default bisection: f(xi_eq) = -gamma
    assert -GAMMA < xi_eq < 0.0  # a hardening spring sags less than the linear one
    h = 1e-4  # central differences of these polynomials are exact up to their h^2 terms, k xi h^2 and k h^2
    for xi in (-0.3, 0.1, 0.7):
        v_diff = (law.potential(xi + h) - law.potential(xi - h)) / (2 * h)
        f_diff = (law.restoring(xi + h) - law.restoring(xi - h)) / (2 * h)
        assert abs(v_diff - (law.restoring(xi) + law.k * xi * h * h)) < 1e-11  # V' = f
        assert abs(f_diff - (law.stiffness(xi) + law.k * h * h)) < 1e-11  # f' = stiffness
    with pytest.raises(Exception, match=r"spring k must be a finite number \(allowed range: \[0, 1000\]"):
        DuffingSpring(k=-1.0)


def test_every_general_purpose_method_runs_it(duffing):
    """scipy, penalty, Moreau-Jean and heyoka run the Duffing drop (each has the capability the law offers:
    numba physics, a symbolic form), E - E_m never rises beyond the method's tolerance along the impacts and
    falls overall (dissipation), and the methods agree on the first impacts (within the soft-contact and
    time-stepping methods' own errors)."""
    params = Parameters(GAMMA, MU, DuffingSpring(k=2.0))
    names = general_purpose_methods(params)
    assert names == ["heyoka", "moreau-jean", "penalty", "scipy"]
    assert not registry()["exact"].supports(params)  # no exact solver: the exact method declines it
    results = {}
    for name in names:
        res = registry()[name].run(params, DROP, SETTINGS[name], max_events=EVENTS)
        assert res.failure == "" and len(res.t) == EVENTS, (name, res.failure, res.extra.get("reason"))
        e = impact_energies(res, params)
        running_min = np.minimum.accumulate(np.concatenate([[params.spring.excess(GAMMA, DROP.deviations(params))], e]))
        assert np.all(e <= running_min[:-1] * (1.0 + energy_tolerance(name))), (name, e)
        assert e[-1] < 0.9 * e[0], name
        results[name] = res.t
    reference = results["heyoka"]  # Taylor integration at machine tolerance
    assert np.max(np.abs(results["scipy"][:4] / reference[:4] - 1.0)) < 1e-9
    for name in ("penalty", "moreau-jean"):  # contacts located to the step / soft: ~1e-4 relative here
        assert np.max(np.abs(results[name][:4] / reference[:4] - 1.0)) < 1e-3, name


def test_k_zero_is_the_linear_law(duffing):
    """Duffing with k = 0 is the linear spring: each method gives the linear law's impacts to the bit (the same
    floats: xi + 0 xi^3 = xi, xi_eq = -gamma by bisection), and heyoka agrees with the exact solver to 1e-12
    over the first impacts (the chaotic transient amplifies rounding after them); with k = 2 the impacts move."""
    zero, linear = Parameters(GAMMA, MU, DuffingSpring(k=0.0)), Parameters(GAMMA, MU, LINEAR)
    assert zero.xi_eq == linear.xi_eq == -GAMMA
    exact = simulate(linear, DROP, max_events=EVENTS).t
    for name in general_purpose_methods(zero):
        a = registry()[name].run(zero, DROP, SETTINGS[name], max_events=EVENTS)
        b = registry()[name].run(linear, DROP, SETTINGS[name], max_events=EVENTS)
        if name == "heyoka":  # a different expression (x + 0 x^3) of the same field: equal to rounding
            assert np.max(np.abs(a.t[:6] / exact[:6] - 1.0)) < 1e-12
        else:
            assert np.array_equal(a.t, b.t) and np.array_equal(a.xdot, b.xdot), name
    hard = registry()["scipy"].run(Parameters(GAMMA, MU, DuffingSpring(k=2.0)), DROP, SETTINGS["scipy"],
                                   max_events=3)
    assert np.all(np.abs(hard.t[1:] / exact[1:3] - 1.0) > 1e-4)  # the first impact is before the spring acts


def _cli(tmp_path, *args, out="run.nc"):
    from bounce.cli import main

    path = tmp_path / out
    status = main(["simulate", "--gamma", str(GAMMA), "--mu", str(MU), "--psi0", "1", "--psidot0", "0", "--xi0", "0",
                   "--xidot0", "0", "--events", str(EVENTS), *args, "--out", str(path)])
    return status, path


def test_cli_runs_it_with_a_general_purpose_method(duffing, tmp_path, capsys):
    """``--spring duffing --k 2`` (options from the registry) with ``--method scipy``: the impacts the method
    reports, in netCDF with the law's attributes; the method's own run gives the same records."""
    status, path = _cli(tmp_path, "--spring", "duffing", "--k", "2", "--method", "scipy")
    assert status == 0, capsys.readouterr().err
    line = capsys.readouterr().out.strip()
    assert line.startswith(f"bounce: {EVENTS} impacts by method scipy") and str(path) in line
    ds = xr.open_dataset(path)
    assert (ds.attrs["spring_law"], ds.attrs["spring_k"], ds.attrs["method"]) == ("duffing", 2.0, "scipy")
    assert ds.attrs["failure"] == "none" and "cpu" not in " ".join(ds.attrs)
    params = Parameters(GAMMA, MU, DuffingSpring(k=2.0))
    direct = registry()["scipy"].run(params, DROP, max_events=EVENTS)
    assert np.array_equal(ds["t"].values, direct.t) and np.array_equal(ds["xdot"].values, direct.xdot)
    ds.close()


@pytest.mark.parametrize("args, words", [
    (["--spring", "duffing", "--k", "2"], "the duffing spring has no exact solver: choose a general-purpose method"),
    (["--spring", "duffing", "--k", "2", "--method", "exact"], "has no exact solver"),
    (["--spring", "duffing", "--k", "2", "--method", "contact-switch"], "--method must be one of heyoka, "
                                                                          "moreau-jean, penalty, scipy for the duffing"),
    (["--spring", "duffing"], "--spring duffing needs --k (allowed ranges: k in [0, 1000])"),
    (["--spring", "duffing", "--k", "-1", "--method", "scipy"], "spring k must be a finite number (allowed range: [0, 1000]"),
    (["--k", "1"], "--k: only with --spring duffing"),
    (["--spring", "duffing", "--k", "1", "--method", "scipy", "--stream"], "--stream: only with the exact solver"),
])
def test_cli_refuses_in_one_line_and_writes_nothing(duffing, tmp_path, capsys, args, words):
    status, path = _cli(tmp_path, *args)
    err = capsys.readouterr().err.strip()
    assert status == 2 and words in err and len(err.splitlines()) == 1, err
    assert not path.exists()


def test_config_schema_follows_the_registry(duffing):
    """The schema's spring fragment is built from the registry: a Duffing scene has the right shape (law and k
    within its interval), and the validator refuses it for what the pipeline needs, an exact solver."""
    import jsonschema

    from bounce.pipeline.config import ConfigError, _check_scenes, load_schema

    spring = load_schema()["$defs"]["spring"]
    assert "duffing" in spring["properties"]["law"]["enum"]
    validator = jsonschema.Draft202012Validator(spring)
    assert validator.is_valid({"law": "duffing", "k": 2.0})
    assert not validator.is_valid({"law": "duffing", "k": 2.0e3}) and not validator.is_valid({"law": "duffing"})
    scene = {"gamma": GAMMA, "mu": MU, "spring": {"law": "duffing", "k": 2.0},
             "initial": {"psi": 1.0, "psidot": 0.0, "xi": 0.0, "xidot": 0.0}, "stop": {"events": 10}}
    with pytest.raises(ConfigError, match="scenes.d: .*'duffing' has no exact solver"):
        _check_scenes({"scenes": {"d": scene}})


def test_failures_are_named(duffing):
    """A method run into trouble on the new law reports it (contract 3 of bounce.methods.base), not a raise."""
    params = Parameters(GAMMA, MU, DuffingSpring(k=2.0))
    res = registry()["penalty"].run(params, DROP, {"stiffness": 1e4, "omega_dt": 2.5}, max_events=EVENTS)
    assert res.failure in FAILURES[1:]

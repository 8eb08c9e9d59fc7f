"""The model layer (bounce.springs): a spring law is one module plus one registry line.

Protects: the linear law's equilibrium and E_m against the paper's closed forms (eqs. equilibrium,
Emin), the law's round trip through config specs and netCDF attributes, and the refusals (unknown
law, unknown parameter, a law the exact solver does not support) as one-line InputErrors.
"""

import math

import numpy as np

import pytest
from hypothesis import given
from hypothesis import strategies as st

from bounce import Parameters, State, simulate
from bounce.errors import InputError
from bounce.io import from_dataset, to_dataset
from bounce.springs import LINEAR, SPRING_LAWS, SpringLaw, spring_from_attrs, spring_from_spec


def test_default_law_is_linear():
    assert Parameters(0.01, 0.01).spring is LINEAR
    assert spring_from_spec(None) is LINEAR and spring_from_spec({}) is LINEAR


@given(st.floats(1e-12, 0.49), st.floats(-10.0, 10.0))
def test_linear_law_matches_the_paper(gamma, xi):
    p = Parameters(gamma, 0.1)
    assert p.xi_eq == -gamma  # eq. equilibrium
    assert p.y_eq == 1.0 - 2.0 * gamma
    assert p.energy_min == -0.5 * gamma * gamma  # eq. Emin (gamma**2 may round differently from gamma*gamma)
    # E_m is the minimum of V(xi) + gamma xi (the energy at rest on the floor, psi = xi)
    assert LINEAR.potential(xi) + gamma * xi >= p.energy_min - 1e-15 * max(1.0, xi * xi)
    # V' = f (central difference of a quadratic is exact up to rounding)
    h = 1e-3
    assert math.isclose((LINEAR.potential(xi + h) - LINEAR.potential(xi - h)) / (2 * h), LINEAR.restoring(xi),
                        rel_tol=1e-9, abs_tol=1e-9)


def test_registry_names_match_classes():
    for name, law in SPRING_LAWS.items():
        assert issubclass(law, SpringLaw) and law.name == name


def test_attrs_round_trip_through_netcdf():
    p = Parameters(0.01, 0.01)
    traj = simulate(p, State.from_psi_xi(1.0, 0.0, 0.0, 0.0), max_events=3)
    ds = to_dataset(traj)
    assert ds.attrs["spring_law"] == "linear"
    assert spring_from_attrs(ds.attrs) == LINEAR
    assert from_dataset(ds).params == p


@pytest.mark.parametrize("spec, words", [
    ({"law": "cubic"}, "spring law must be one of"),
    ({"law": "linear", "rho": 2.0}, "takes the parameters"),
])
def test_bad_spec_is_one_line_naming_it(spec, words):
    with pytest.raises(InputError, match=words) as err:
        spring_from_spec(spec)
    assert "\n" not in str(err.value)


def test_a_law_without_an_exact_solver_is_refused_by_simulate():
    """simulate runs the solver the law declares (SpringLaw.solver); a law that declares none is refused in one line
    naming the way out (a general-purpose method)."""
    class Cubic(SpringLaw):
        name = "cubic"

        def xi_eq(self, gamma):
            return -gamma ** (1 / 3)

    with pytest.raises(InputError, match="'cubic' has no exact solver.*general-purpose method") as err:
        simulate(Parameters(0.01, 0.01, Cubic()), State.from_psi_xi(1.0, 0.0, 0.0, 0.0), max_events=3)
    assert "\n" not in str(err.value)


@pytest.mark.parametrize("args, words", [
    (["--spring", "power", "--rho", "1", "--a", "0.5"], "--spring power needs --b"),
    (["--spring", "power", "--rho", "-1", "--a", "0.5", "--b", "0.5"], "spring rho must be a finite number (allowed range: (0, inf)"),
    (["--spring", "power", "--rho", "1", "--a", "-0.5", "--b", "0.5"], "spring a must be a finite number (allowed range: [0, 50]"),
    (["--rho", "2"], "only with --spring power"),
    (["--spring", "power", "--rho", "1", "--a", "0.5", "--b", "nan"], "--b: must be a finite number (allowed range: [0, 50])"),
    (["--spring", "power", "--rho", "nan", "--a", "0.5", "--b", "0.5"], "--rho: must be a finite number (allowed range: (0, inf))"),
])
def test_cli_refuses_bad_law_with_one_line_and_no_file(tmp_path, capsys, args, words):
    from bounce.cli import main

    out = tmp_path / "run.nc"
    status = main(["simulate", "--gamma", "0.01", "--mu", "0.01", "--psi0", "1", "--psidot0", "0", "--xi0", "0",
                   "--xidot0", "0", "--events", "10", *args, "--out", str(out)])
    err = capsys.readouterr().err.strip()
    assert status == 2 and words in err and len(err.splitlines()) == 1
    assert not out.exists()


def test_power_law_runs_through_simulate_and_netcdf(tmp_path):
    """The power law goes through the same front (simulate) and file format; its law is in the attributes."""
    from bounce.springs import spring_from_spec

    p = Parameters(0.01, 0.01, spring_from_spec({"law": "power", "rho": 1.0, "a": 0.5, "b": 0.5}))
    traj = simulate(p, State.from_psi_xi(1.0, 0.0, p.xi_eq, 0.0), max_events=200)
    assert len(traj) == 200 and set(traj.kind_names) == {"impact"}
    assert traj.params.spring.name == "power" and np.all(np.diff(traj.t) > 0)
    ds = to_dataset(traj)
    assert (ds.attrs["spring_law"], ds.attrs["spring_a"]) == ("power", 0.5)
    assert from_dataset(ds).params == p

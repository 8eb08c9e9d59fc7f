"""bounce against the independent mpmath reference (tests/reference.py).

One flight at a time: from a float64 state taken from a bounce trajectory, both
solvers get the *same* doubles (the reference converts them exactly), so the
reference result is the exact image of that state and every difference is
bounce's own error.  Tolerance 1e-14 relative (about 45 ulps) on the flight
time tau and on each component of the post-impact state (xdot, xidot, eta),
eta measured against its own size, as the task prescribes: a solver that is
exact to rounding commits a few ulps per flight.

One exception, by necessity: an output whose float64 floor exceeds 1e-14
cannot be delivered to 1e-14 by any float64 algorithm.  The floor has two parts,
both computed by the reference at 50 digits: the conditioning kappa * 2^-53
(kappa = relative change per relative change of the input doubles: perturbing
the inputs by half an ulp already moves the output that far), and the change
that one ulp of tau causes (the flight time is returned as a double, and the
state is the state at that double).  Such outputs (eta in the double-impact and
chaotic transients, where xi(tau) + gamma is a small difference of O(gamma)
terms) must be within COND_FACTOR = 2 of that floor (measured: at most 1.01);
tau and every deep-asymptotic output meet 1e-14 outright.  Meeting 1e-14 there
too would need extended precision in the impact map.

Whole trajectories: see :func:`test_predictability_horizon`.
"""

from __future__ import annotations

import functools
import random

import numpy as np
import pytest
from mpmath import mp, mpf

from bounce.analysis import reference as R
from bounce import Deviations, Parameters, State, simulate

REL = 1e-14  # task tolerance, see module docstring
COND_FACTOR = 2.0  # ... unless the output's own conditioning forbids it (module docstring)
GAMMAS = (0.01, 1e-5)
MUS = (0.01, 1.0, 2.0)
N_LONG = 1_000_000  # events of the long run that gives the deep asymptotic states
EARLY = (0, 1, 2)  # states after the first impacts (plus the drop itself)
TRANSIENT = tuple(range(20, 51))  # states after impacts 20..50
DEEP = tuple(range(N_LONG - 10, N_LONG))  # states after impacts ~1e6


@functools.lru_cache(maxsize=None)
def states_from_drop(gamma, mu):
    """Float64 post-impact states (u, a, eta) of the drop from psi(0) = 6, by event index."""
    p = Parameters(gamma, mu)
    tr = simulate(p, State.from_psi_xi(6.0, 0.0, 0.0, 0.0), max_events=N_LONG)
    assert tr.stop_reason == "max_events" and (tr.kind == 0).all()
    wanted = EARLY + TRANSIENT + DEEP
    return {k: (float(tr.xdot[k]), float(tr.xidot[k]), float(tr.eta[k])) for k in wanted}


def rel_err(got, ref):
    return float(abs((mpf(got) - ref) / ref))


def compare_one_flight(gamma, mu, x0, u, a, eta):
    """Relative errors of bounce's one flight from (x0, u, a, eta) vs the reference."""
    p = Parameters(gamma, mu)
    one = simulate(p, Deviations(x=x0, xdot=u, xidot=a, eta=eta), max_events=1)
    assert one.kind_names == ("impact",), one.kind_names
    tau, st = R.flight_step(gamma, mu, x0, u, a, eta)
    with mp.workdps(R.DPS):
        errs = {
            "tau": rel_err(one.tau[0], tau),
            "xdot": rel_err(one.xdot[0], st.u),
            "xidot": rel_err(one.xidot[0], st.a),
            "eta": rel_err(one.eta[0], st.eta),
        }
        # Diagnostic only (not asserted here): the error that one ulp of tau
        # alone causes in each output, |d q / d tau| ulp(tau) / |q| -- the floor
        # of any solver that returns tau as a double and the state at that tau.
        fl = R.Flight(*(mpf(v) for v in (gamma, mu, x0, u, a, eta)))
        xi, xid = fl.xi(tau)
        x2 = -mpf(gamma) - (-xi - 2 * mpf(mu) * xid)  # x'' = -gamma - xi''
        ulp = mpf(np.spacing(float(tau)))
        floor = {"tau": 0.0, "xdot": float(abs(x2 * ulp / st.u)),
                 "xidot": float(abs(gamma * ulp / st.a)), "eta": float(abs(xid * ulp / st.eta))}
        ref = {"tau": tau, "xdot": st.u, "xidot": st.a, "eta": st.eta}
        got = {"tau": one.tau[0], "xdot": one.xdot[0], "xidot": one.xidot[0], "eta": one.eta[0]}
    return errs, floor, ref, got


def check_states(gamma, mu, cases):
    """Compare each (label, (x0, u, a, eta)) case; collect every violation of REL."""
    bad = []
    worst = {q: 0.0 for q in ("tau", "xdot", "xidot", "eta")}
    for label, (x0, u, a, eta) in cases:
        errs, floor, ref, got = compare_one_flight(gamma, mu, x0, u, a, eta)
        kappa = None
        for q, e in errs.items():
            worst[q] = max(worst[q], e)
            if not e <= REL:
                if kappa is None:
                    kappa = dict(zip(errs, R.condition_numbers(gamma, mu, x0, u, a, eta)))
                if e <= COND_FACTOR * (kappa[q] * 2.0**-53 + floor[q]):
                    continue  # at the float64 floor of this output (module docstring)
                bad.append(
                    f"gamma={gamma!r} mu={mu!r} {label} state (x, u, a, eta) = "
                    f"({float(x0).hex()}, {float(u).hex()}, {float(a).hex()}, {float(eta).hex()}): "
                    f"{q} ref {mp.nstr(ref[q], 17)} got {float(got[q])!r} rel err {e:.2e} "
                    f"[condition number x 2^-53 = {kappa[q] * 2.0**-53:.1e}; one ulp of tau alone gives {floor[q]:.1e}]"
                )
    return bad, worst


@pytest.mark.parametrize("mu", MUS)
@pytest.mark.parametrize("gamma", GAMMAS)
@pytest.mark.parametrize("regime", ["early", "transient", "deep"])
def test_one_flight_matches_reference(gamma, mu, regime):
    """tau, xdot, xidot, eta after one flight agree with the reference to 1e-14 relative."""
    states = states_from_drop(gamma, mu)
    if regime == "early":
        d = State.from_psi_xi(6.0, 0.0, 0.0, 0.0).deviations(Parameters(gamma, mu))
        cases = [("drop from psi(0)=6", (d.x, d.xdot, d.xidot, d.eta))]
        cases += [(f"after impact {k}", (0.0,) + states[k]) for k in EARLY]
    elif regime == "transient":
        cases = [(f"after impact {k}", (0.0,) + states[k]) for k in TRANSIENT]
    else:
        cases = [(f"after impact {k}", (0.0,) + states[k]) for k in DEEP]
    bad, worst = check_states(gamma, mu, cases)
    assert not bad, f"{len(bad)} violations of {REL:g} (worst {worst}):\n" + "\n".join(bad)


# ---------------------------------------------------------------------------
# whole trajectories
# ---------------------------------------------------------------------------

TOL_TRACK = 1e-8  # task: "follows the mpmath trajectory to 1e-8 relative in impact times"
NOISE = REL  # relative per-step error injected into the exact trajectories (see below)
SEEDS = (0, 1, 2)

# (gamma, mu, psi(0), number of impacts compared)
TRAJ_CASES = [
    (0.01, 0.01, 6.0, 150),   # paper fig. rigid-fall: chaotic transient
    (1e-5, 0.01, 0.25, 170),  # paper fig. rest-coeff: long double-impact regime, then chaos
    (0.01, 2.0, 6.0, 80),     # over-damped: no chaotic transient (paper, fig. overdamped)
]


def horizon(t_a, t_b):
    """Number of leading impacts whose times agree to TOL_TRACK relative."""
    for k, (ta, tb) in enumerate(zip(t_a, t_b)):
        if not abs(mpf(ta) - tb) <= TOL_TRACK * abs(tb):
            return k
    return len(t_b)


def noisy_horizon(gamma, mu, start, t_ref, seed):
    """Horizon of the exact dynamics when every post-impact state component is
    multiplied by (1 + NOISE * uniform(-1, 1)): an exact trajectory with errors
    of the size a float64 solver is allowed per flight."""
    rng = random.Random(seed)
    with mp.workdps(R.DPS):
        st = R.Dev(*(mpf(v) for v in start))
        t = mpf(0)
        for k, tk in enumerate(t_ref):
            tau, st = R.flight_step(gamma, mu, st.x, st.u, st.a, st.eta)
            t += tau
            if not abs(t - tk) <= TOL_TRACK * abs(tk):
                return k
            f = lambda v: v * (1 + NOISE * (2 * rng.random() - 1))  # noqa: E731
            st = R.Dev(st.x, f(st.u), f(st.a), f(st.eta))
    return len(t_ref)


@functools.lru_cache(maxsize=None)
def reference_run(gamma, mu, psi0, n):
    """Start state, exact impact times and post-impact states from psi(0) = psi0."""
    d0 = State.from_psi_xi(psi0, 0.0, 0.0, 0.0).deviations(Parameters(gamma, mu))
    start = (d0.x, d0.xdot, d0.xidot, d0.eta)
    t_ref, _, states = R.trajectory(gamma, mu, R.Dev(*start), n)
    return start, t_ref, states


@functools.lru_cache(maxsize=None)
def float64_horizon(gamma, mu, psi0, n):
    tr = simulate(Parameters(gamma, mu), State.from_psi_xi(psi0, 0.0, 0.0, 0.0), max_events=n)
    assert (tr.kind == 0).all()
    return horizon(tr.t, reference_run(gamma, mu, psi0, n)[1])


@pytest.mark.parametrize("gamma, mu, psi0, n", TRAJ_CASES)
def test_predictability_horizon(gamma, mu, psi0, n):
    """float64 follows the exact trajectory (impact times to 1e-8 relative) at
    least as long as the exact dynamics itself does under per-flight errors of
    the size the one-flight tests allow.

    The transient is chaotic: near-grazing flights multiply state errors by
    large factors, so *any* finite-precision solver loses the exact trajectory
    after some number of impacts.  The lower bound H_lb is measured, not tuned:
    it is the horizon of the exact (mpmath) dynamics when each post-impact
    state component gets a relative error of NOISE = 1e-14 per flight (random
    sign; three seeds, minimum taken) -- the per-flight accuracy demanded of
    bounce by the one-flight tests, ~45 times the unit roundoff.  A solver
    whose per-flight errors stay within that budget cannot lose the trajectory
    earlier, up to the luck of the error direction, which the minimum over
    seeds covers.  (Measured: gamma = mu = 0.01 from psi(0) = 6: H_lb ~ 17,
    bounce ~ 18, the first ~10 impacts being the regular double-impact regime;
    gamma = 1e-5, mu = 0.01 from psi(0) = 0.25: H_lb ~ 118, bounce ~ 120-124;
    mu = 2 is not chaotic and H = n.)
    """
    start, t_ref, _ = reference_run(gamma, mu, psi0, n)
    h64 = float64_horizon(gamma, mu, psi0, n)
    h_lb = min(noisy_horizon(gamma, mu, start, t_ref, seed) for seed in SEEDS)
    assert h64 >= h_lb, f"float64 horizon {h64} < exact-dynamics horizon {h_lb} with {NOISE:g} noise per flight"


@pytest.mark.parametrize("gamma, mu, psi0, n", TRAJ_CASES)
def test_one_flight_beyond_horizon(gamma, mu, psi0, n):
    """Past the horizon, every flight of the exact trajectory, started from the
    reference's state rounded to float64 (fed to both solvers), is still exact
    to 1e-14 relative, as in :func:`test_one_flight_matches_reference`."""
    _, _, states = reference_run(gamma, mu, psi0, n)
    h64 = float64_horizon(gamma, mu, psi0, n)
    cases = [(f"after exact impact {k}", (0.0,) + states[k].floats()[1:]) for k in range(max(h64 - 1, 0), n - 1)]
    bad, worst = check_states(gamma, mu, cases)
    assert not bad, f"{len(bad)} violations of {REL:g} (worst {worst}):\n" + "\n".join(bad)


def test_impacts_at_a_given_precision():
    """reference.impacts_at: the same impacts as trajectory(), at the digits asked for.  At DPS it is trajectory()
    itself (bit for bit); at 30 digits on the over-damped drop (no chaotic amplification) the impact times
    agree with the 50-digit ones to the 30-digit rounding (eps_30 ~ 1e-30, times a few hundred flights);
    eps is 2^(1 - prec) of the 30-digit context; the caller's precision is left as it was."""
    gamma, mu, n = 1e-5, 2.0, 40
    start = R.Dev(0.25, 0.0, 0.0, gamma)
    t50, _, states = R.trajectory(gamma, mu, start, n)
    at50 = R.impacts_at(gamma, mu, start, n, R.DPS)
    assert at50["stop"] == "max_events" and at50["n"] == n
    assert at50["t"] == t50 and at50["xdot"] == [s.u for s in states]
    prec = mp.prec
    at30 = R.impacts_at(gamma, mu, start, n, 30)
    assert mp.prec == prec
    assert 1e-31 < float(at30["eps"]) < 1e-29
    with mp.workdps(60):
        err = max(abs(a / b - 1) for a, b in zip(at30["t"], t50))
    assert 0 < err < 1e-27, err

"""Hypothesis properties of whole dimer-gas runs (bounce.gas.simulate_gas), columns and rings.

Random small gases (2 to 4 grains, mu in [0, 0.95], springs excited, gaps from 1e-9 to 1.6), 150
events each with a snapshot after every event.  For every run:

* order is kept: no grain passes its neighbour and x_0 >= 0, at every event and at 48 times inside
  every interval between events, the grains moved there by this file's own float64 closed forms
  (gas_reference.free_motion): a contact the engine skipped would show as a negative gap between its
  events (dense sampling);
* the total energy never rises from event to event, and equals the initial energy minus the energy
  the springs dissipated, the integral of 2 mu xi'^2 over every grain's free flights (eq.
  ``energy-dissipation``; gas_reference.dissipation: quadrature, or the closed-form energy identity
  over flights of thousands of periods);
* on the ring the momentum sum (psi_k') is conserved.

Tolerances: positions to 16 ulps of the terms that make them, plus the way the masses travel in the
rounding of the reported event times that bound an interval; energies to
1e-12 of the initial energy (150 events of rounding plus the quadrature); momentum to 1e-14 of
sum |psi'|.  The draw is fixed (derandomized, tests/conftest.py); ``BOUNCE_GAS_EXAMPLES`` draws more.
"""

from __future__ import annotations

import os

import numpy as np
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

import gas_reference as R
from bounce.gas import GasParameters, GasState, simulate_gas
from bounce.gas.simulate import energy_excess

EPS = 2.0**-52
EVENTS = 150
SAMPLES = 48
EXAMPLES = int(os.environ.get("BOUNCE_GAS_EXAMPLES", "40"))
SETTINGS = settings(deadline=None, max_examples=EXAMPLES, suppress_health_check=[HealthCheck.too_slow])


@st.composite
def gases(draw, geometry):
    """(params, state) of a valid gas: springs within the energy bound, grains ordered without overlap."""
    n = draw(st.integers(2, 4))
    mu = draw(st.one_of(st.sampled_from([0.0, 0.05, 0.5]), st.floats(0.0, 0.95)))
    gamma = draw(st.floats(1e-3, 0.05)) if geometry == "column" else 0.0
    amp = st.floats(-0.15, 0.15)
    xi = np.array(draw(st.lists(amp, min_size=n, max_size=n)))
    xidot = np.array(draw(st.lists(amp, min_size=n, max_size=n)))
    psidot = np.array(draw(st.lists(st.floats(-0.3, 0.3), min_size=n, max_size=n)))
    gaps = np.array(draw(st.lists(st.floats(-9.0, 0.2).map(lambda e: 10.0**e), min_size=n, max_size=n)))
    psi = np.empty(n)
    psi[0] = (gaps[0] if geometry == "column" else 0.0) + xi[0]
    for k in range(1, n):
        top = psi[k - 1] + xi[k - 1] + 1.0  # y_{k-1}, as GasState.check forms it
        psi[k] = top + gaps[k] + xi[k]
        while psi[k] - xi[k] < top:  # a tiny gap lost to rounding
            psi[k] = np.nextafter(psi[k], np.inf)
    ell = None
    if geometry == "ring":
        ell = psi[-1] + xi[-1] + 1.0 - (psi[0] - xi[0]) + gaps[0]
    p = GasParameters(n, geometry, gamma, mu, ell)
    return p, GasState(psi, psidot, xi, xidot)


def check_run(p, state):
    res = simulate_gas(p, state, max_events=EVENTS, t_max=1e4, snapshot_every=1)
    # sticky: a pressed pair contact at the rounding level of its positions (bounce.gas.dimer), checked up to it
    assert res.stop_reason in ("max_events", "t_max", "no_more_events", "overlap", "sticky"), res.message
    n_ev = len(res)
    x0, u0, a0, eta0 = state.deviations(p.gamma)
    # the states after every event, with the initial one first: (field, event, grain)
    snaps = {k: np.vstack([v0[None, :], res.snapshots[k]]) for k, v0 in
             (("x", x0), ("xdot", u0), ("xidot", a0), ("eta", eta0))}
    times = np.concatenate([[0.0], res.t])
    wrap = p.ell or 0.0
    # order at the events and inside every interval (dense samples of the free motion), to 16 ulps of
    # the terms that make the positions (the engine's own and the sampler's rounding) plus what the masses
    # travel in the rounding of the reported times that bound the interval
    for m in range(n_ev):
        tau = times[m + 1] - times[m]
        t = np.linspace(0.0, tau, SAMPLES)
        speeds = np.abs(snaps["xdot"][m]) + 2 * np.abs(snaps["xidot"][m]) + 2 * np.abs(snaps["eta"][m]) + p.gamma * tau
        travel = np.max(speeds) * 2 * (np.spacing(times[m + 1]) + np.spacing(times[m]))
        xs, ys, scales = [], [], []
        for k in range(p.n):
            xk, yk, _, sk = R.free_motion(p.gamma, p.mu, *(snaps[f][m, k] for f in ("x", "xdot", "xidot", "eta")), t)
            xs.append(xk)
            ys.append(yk)
            scales.append(sk + np.abs(snaps["x"][m, k]))
        xs, ys, scales = np.array(xs), np.array(ys), 16 * EPS * np.array(scales) + travel
        gaps = xs[1:] - ys[:-1] + scales[1:] + scales[:-1]
        assert gaps.min(initial=0.0) >= 0.0, f"interval {m}: a grain passed its neighbour by {-gaps.min():.3g}"
        if p.geometry == "ring":
            seam = xs[0] + wrap - ys[-1] + scales[0] + scales[-1] + 16 * EPS * wrap
            assert seam.min() >= 0.0, f"interval {m}: the last grain passed the first by {-seam.min():.3g}"
        else:
            assert np.min(xs[0] + scales[0]) >= 0.0, f"interval {m}: grain 0 below the floor by {-xs[0].min():.3g}"
    # energy: never rises, and equals E0 minus the dissipated energy
    energy = energy_excess(p, snaps).sum(axis=1)
    assert np.all(np.diff(energy) <= 1e-13 * energy[0]), "the energy rose across an event"
    dissipated = np.zeros(n_ev + 1)
    for m in range(n_ev):
        tau = times[m + 1] - times[m]
        dissipated[m + 1] = dissipated[m] + sum(
            R.dissipation(p.gamma, p.mu, snaps["xidot"][m, k], snaps["eta"][m, k], tau) for k in range(p.n))
    assert np.max(np.abs(energy - (energy[0] - dissipated))) <= 1e-12 * energy[0]
    if p.geometry == "ring":
        momentum = (snaps["xdot"] + snaps["xidot"]).sum(axis=1)
        # each psi' = x' + xi' is rounded to eps of its terms, which cancel in a grain at rest with a
        # compressed spring: the scale is the terms' magnitudes (|psi'| summed gave 1e-16 against a drift
        # of 1.1e-16 on a two-grain ring at zero momentum, a drawn case pinned below)
        scale = (np.abs(snaps["xdot"]) + np.abs(snaps["xidot"])).sum(axis=1).max()
        assert np.max(np.abs(momentum - momentum[0])) <= 1e-14 * scale + 1e-300
    return res


@SETTINGS
@given(gases("column"))
def test_column_properties(case):
    check_run(*case)


@SETTINGS
@given(gases("ring"))
@example((GasParameters(n=2, geometry="ring", gamma=0.0, mu=0.0, ell=1.7510999999999999),
          GasState(psi=np.array([0.0, 0.876]), psidot=np.array([0.0, 0.0]), xi=np.array([0.0, -0.125]),
                   xidot=np.array([0.0, 0.0]))))
def test_ring_properties(case):
    check_run(*case)

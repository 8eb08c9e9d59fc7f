"""Sweep ``contact-monte-carlo``: the compiled per-sample loop (issue 22) gives the bits of ``simulate`` per sample.

:func:`reference_compute` is the sweep's ``compute`` before issue 22, verbatim but for names (a Python loop:
``simulate``, ``np.bincount``, ``_contact_scales``, ``np.histogram``); the compiled loop must return the same
arrays, to the bit, on the pipeline's own samples and on samples that stick (whose tables of mu/sqrt(2) the
event loop then builds itself, 37 sticky phases and 7 detaches), with 1, 2 and 100 events per sample.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml

from bounce.analysis.anomalies import _contact_scales
from bounce.exact.oscillator import make_oscillator
from bounce.kinds import KIND_NAMES
from bounce.model import Deviations, Parameters, State
from bounce.pipeline.config import validated
from bounce.simulate import simulate
from bounce.sweeps import contact_monte_carlo as mc

ROOT = Path(__file__).resolve().parents[2]
SPEC = validated(yaml.safe_load((ROOT / "config" / "config.yaml").read_text()))["sweeps"]["contact-monte-carlo"]


def reference_compute(spec: dict, inputs: dict) -> dict:
    """contact_monte_carlo.compute before issue 22."""
    m = len(inputs["gamma"])
    events = int(spec["events"])
    counts = np.zeros((m, len(KIND_NAMES)), dtype=np.int64)
    min_ratio = np.full(m, np.nan)
    min_margin = np.full(m, np.nan)
    ratio_hist = np.zeros((len(mc.REGIMES), mc.RATIO_EDGES.size - 1), dtype=np.int64)
    margin_hist = np.zeros((len(mc.REGIMES), mc.MARGIN_EDGES.size - 1), dtype=np.int64)
    ref = np.empty(events)
    mar = np.empty(events)
    for i in range(m):
        g, mu = float(inputs["gamma"][i]), float(inputs["mu"][i])
        x, u, a, eta = (float(inputs[k][i]) for k in ("x", "xdot", "xidot", "eta"))
        tr = simulate(Parameters(g, mu), Deviations(x, u, a, eta), max_events=events)
        n = len(tr)
        counts[i] = np.bincount(tr.kind, minlength=len(KIND_NAMES))
        params, coefs = make_oscillator(mu)
        _contact_scales(x, u, a, eta, tr.tau, tr.xdot, tr.xidot, tr.eta, tr.kind, g, mu, params, coefs,
                        ref[:n], mar[:n])
        ok = np.isfinite(ref[:n])
        if ok.any():
            r, v = ref[:n][ok], mar[:n][ok]
            min_ratio[i], min_margin[i] = r.min(), v.min()
            reg = int(inputs["damping_regime"][i])
            ratio_hist[reg] += np.histogram(r, mc.RATIO_EDGES)[0]
            margin_hist[reg] += np.histogram(np.minimum(v, mc.MARGIN_EDGES[-1]), mc.MARGIN_EDGES)[0]
    return {**{k: np.asarray(inputs[k]) for k in ("gamma", "mu", "damping_regime", "energy")},
            "counts": counts, "min_ratio": min_ratio, "min_margin": min_margin,
            "ratio_hist": ratio_hist, "margin_hist": margin_hist}


def _assert_same_bits(got: dict, want: dict) -> None:
    assert sorted(got) == sorted(want)
    for k in want:
        assert got[k].dtype == want[k].dtype and got[k].shape == want[k].shape, k
        assert got[k].tobytes() == want[k].tobytes(), k


@pytest.mark.parametrize("events", [1, 2, 100])
def test_pipeline_samples_give_the_bits_of_simulate(events):
    spec = dict(SPEC, events=events)
    inputs = mc.prepare(spec, np.arange(200, 290))
    _assert_same_bits(mc.compute(spec, inputs), reference_compute(spec, inputs))


def _hand_made_inputs() -> dict:
    """Starts that stick at once (pressed on the floor; the static equilibrium: sticky for ever), that stick after
    impacts (gamma = mu = 0.05, eq. sticky-ic), at rest pulled up (lifts off), and ordinary drops, for every regime
    (mu/sqrt(2) over-damped from mu = 2 on: the sticky modes)."""
    rows = []
    for gamma, mu in [(0.01, 0.01), (0.05, 0.05), (0.1, 0.5), (0.2, 1.0), (0.3, 1.5), (0.01, 2.0), (0.3, 3.0)]:
        reg = 0 if mu < 1.0 else (1 if mu == 1.0 else 2)
        for x, u, a, eta in [(0.0, 0.0, 0.0, 0.0), (0.0, 0.0, -0.01, -0.025), (0.0, 0.0, 0.0, gamma + 0.05),
                             (0.0, 0.0, -2.0 * mu * gamma, gamma), (0.3, 0.1, 0.05, -0.02)]:
            rows.append((gamma, mu, reg, 0.0, x, u, a, eta))
        for eps in (0.0, 1e-3):  # eq. sticky-ic: sticks at once (eps = 0), detaches or not
            d = State.sticky_ic(Parameters(gamma, mu), eps=eps).deviations(Parameters(gamma, mu))
            rows.append((gamma, mu, reg, 0.0, d.x, d.xdot, d.xidot, d.eta))
    for gamma in (1e-5, 0.01, 0.05, 0.1):  # the paper's detaching sticky-ic (gamma = mu = 0.01: t_c = 5.23)
        p = Parameters(gamma, 0.01)
        d = State.sticky_ic(p, eps=0.0).deviations(p)
        rows.append((gamma, 0.01, 0, 0.0, d.x, d.xdot, d.xidot, d.eta))
    cols = np.array(rows).T
    keys = ("gamma", "mu", "damping_regime", "energy", "x", "xdot", "xidot", "eta")
    inputs = {k: c for k, c in zip(keys, cols)}
    inputs["damping_regime"] = inputs["damping_regime"].astype(np.int64)
    return inputs


def test_sticking_samples_give_the_bits_of_simulate():
    spec = dict(SPEC, events=50)
    inputs = _hand_made_inputs()
    got, want = mc.compute(spec, inputs), reference_compute(spec, inputs)
    _assert_same_bits(got, want)
    sticky = want["counts"][:, KIND_NAMES.index("sticky_start")]
    assert np.count_nonzero(sticky) >= 10 and np.count_nonzero(want["counts"][:, KIND_NAMES.index("detach")]) >= 3
    assert np.isnan(want["min_ratio"]).any() and not np.isnan(want["min_ratio"]).all()


def test_refuses_what_simulate_refuses():
    spec = dict(SPEC, events=10)
    inputs = {k: v.copy() for k, v in _hand_made_inputs().items()}
    inputs["mu"][3] = 2e8  # above MU_MAX
    with pytest.raises(Exception) as got:
        mc.compute(spec, inputs)
    with pytest.raises(Exception) as want:
        reference_compute(spec, inputs)
    assert type(got.value) is type(want.value) and str(got.value) == str(want.value)

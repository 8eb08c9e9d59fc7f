"""The disordered phase of fig. very_rigid_poincare (bounce.checks.paper_figures): the return-map measure on
constructed sequences whose answer is known."""

import numpy as np
import xarray as xr

from bounce.checks.paper_figures import disordered_phase, unexplained

ROTATION = 0.97 * np.array([[np.cos(0.3), -np.sin(0.3)], [np.sin(0.3), np.cos(0.3)]])


def _iterate(start, n, matrix=ROTATION):
    states = [np.asarray(start, dtype=float)]
    for _ in range(n - 1):
        states.append(states[-1] @ matrix)
    return np.array(states)


def _contacts(states):
    return xr.Dataset({"y_minus_yeq": ("event", states[:, 0]), "ydot": ("event", states[:, 1])})


def test_a_linear_map_leaves_nothing_unexplained_and_noise_leaves_nearly_all():
    assert unexplained(_iterate([1.0, 0.5], 50)) < 1e-25
    noise = np.random.default_rng(3).normal(size=(400, 2))
    assert unexplained(noise) > 0.95


def test_the_phase_runs_from_the_zigzag_break_to_the_first_patterned_window():
    zigzag = _iterate([0.1, 1.0], 60, matrix=np.array([[0.99, 0.0], [0.0, -0.99]]))
    rng = np.random.default_rng(7)
    noise = rng.normal(scale=0.3, size=(80, 2)) * np.linspace(1.0, 0.3, 80)[:, None]
    noise[0, 1] = abs(noise[0, 1]) * np.sign(zigzag[-1, 1])  # the first state after the zig-zag keeps its sign
    spiral = _iterate(noise[-1] * 0.1, 200)
    phase = disordered_phase(_contacts(np.concatenate([zigzag, noise, spiral])), window=20, pattern_max=0.1)
    assert phase.start == 59  # Ydot of records 59 and 60 share a sign: the zig-zag's first break
    assert phase.fractions[0] > 0.5 and phase.fractions[-1] < 0.1
    assert 59 + 80 <= phase.end <= 59 + 80 + 20  # the first window wholly in the spiral explains it
    assert phase.zigzag < 1e-20
    assert phase.rms_second < phase.rms_first

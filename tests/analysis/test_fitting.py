"""bounce.analysis.fitting's limits of the map eq. mappa: Richardson extrapolation (richardson_ln) and the correction's decay
exponent (correction_decay), on sequences with known limits and corrections; the fast forms of its helpers (log_select,
settle_index, column_max_abs) against their definitions."""

from __future__ import annotations

import numpy as np
import pytest

from bounce.analysis.fitting import column_max_abs, correction_decay, log_select, richardson_ln, settle_index


def _sequence(n, L=1.0, c=2.0, d=-3.0, p=1.0, second=5.0):
    """L + n^-p (c ln n + d) + second (ln n/n)^2: Lemma Giorgio's expansion with a next order."""
    return L + n**-p * (c * np.log(n) + d) + second * (np.log(n) / n) ** 2


def test_richardson_cancels_the_ln_n_over_n_and_1_over_n_terms():
    n = np.arange(1000.0, 1_000_001.0)
    L, err = richardson_ln(n, _sequence(n, second=0.0))
    assert abs(L - 1.0) < 1e-12 and err < 1e-12  # exact for L + (c ln n + d)/n (up to rounding)
    L, err = richardson_ln(n, _sequence(n))
    assert abs(L - 1.0) < 1e-8 and abs(L - 1.0) <= err  # the next order: O(ln^2 n/n^2), bounded by the error
    q = _sequence(n)
    assert abs(q[-1] - 1.0) > 1e-5  # the raw sequence is far from its limit


def test_richardson_on_thinned_records_and_too_short_windows():
    n = np.unique(np.round(np.geomspace(1000.0, 1e6, 3000)))
    L, err = richardson_ln(n, _sequence(n))
    assert abs(L - 1.0) < 1e-8
    short = n < 3000  # the extrapolation needs n_top/8 (its error's points) inside the records
    assert np.isnan(richardson_ln(n[short], _sequence(n[short]))[0])

@pytest.mark.parametrize("p", [0.7, 1.0, 1.5])
def test_correction_decay_recovers_the_exponent(p):
    n = np.arange(1000.0, 1_000_001.0)
    s = log_select(n, n[0], n[-1], 2000)
    est, err, L = correction_decay(n[s], _sequence(n[s], p=p, second=0.0))
    assert abs(est - p) < 1e-4 and abs(L - 1.0) < 1e-8
    assert abs(est - p) <= err < 0.5  # conservative: late windows of a fast correction hit the rounding floor


def test_log_select_is_the_log_spaced_pick_of_the_samples_inside_the_window():
    """log_select's bisection against its definition on sorted arrays with repeats, gaps and windows inside, across
    and outside the samples: the samples in [lo, hi], and among them the first one at or after each of k log-spaced
    values (the last one if none is)."""
    rng = np.random.default_rng(3)
    for trial in range(400):
        n = np.cumsum(rng.integers(trial % 2, 5, int(rng.integers(0, 300)))).astype(float) + 1.0
        top = n[-1] + 5.0 if n.size else 10.0
        lo, hi = np.sort(rng.uniform(0.5, top, 2))
        if trial % 5 == 0:
            lo, hi = hi, lo  # an empty window
        k = int(rng.integers(1, 100))
        inside = np.nonzero((n >= lo) & (n <= hi))[0]
        expected = inside[:0] if inside.size == 0 else inside[np.unique(
            np.minimum(np.searchsorted(n[inside], np.geomspace(lo, hi, k)), inside.size - 1))]
        got = log_select(n, lo, hi, k)
        assert got.dtype == expected.dtype and np.array_equal(got, expected), trial


def test_settle_index_scanned_in_blocks_is_its_definition():
    """settle_index's backward scan in blocks against its definition on the whole array (the last sample with
    |q/ref - 1| > threshold or NaN, plus one): settled, never settled, NaN, the last bad sample on a block's edge."""
    rng = np.random.default_rng(5)
    for trial in range(300):
        size = int(rng.integers(0, 400))
        q = 1.0 + rng.normal(0.0, 0.2, size) * np.geomspace(1.0, 1e-4, size)
        if trial % 3 == 0 and size:
            q[rng.integers(0, size)] = np.nan
        ref, threshold = float(rng.uniform(0.9, 1.1)), float(rng.choice([0.0, 1e-3, 0.05, 0.2, 10.0]))
        bad = np.nonzero(~(np.abs(q / ref - 1.0) <= threshold))[0]
        expected = 0 if bad.size == 0 else int(bad[-1]) + 1
        for block in (1, 2, 7, 64, 1 << 15):
            assert settle_index(q, ref, threshold, block) == expected, (trial, block)


def test_column_max_abs_is_the_max_over_axis_0():
    """column_max_abs against np.abs(a).max(axis=0): the same numbers (a max is exact), NaN and inf propagated."""
    rng = np.random.default_rng(6)
    for rows, cols in ((1, 1), (7, 3), (2000, 5), (400, 7)):
        a = rng.normal(0.0, 1.0, (rows, cols)) * 10.0 ** rng.integers(-300, 300, (rows, cols))
        a[0, 0] = -0.0
        if rows > 3:
            a[3, -1], a[2, 0] = np.nan, -np.inf
        assert np.array_equal(column_max_abs(a), np.abs(a).max(axis=0), equal_nan=True)

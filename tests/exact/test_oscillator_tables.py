"""bounce.exact.oscillator: the compiled table builder gives the bits of the former Python/numpy builder.

The tables ``(params, coefs)`` of :func:`bounce.exact.oscillator.build_oscillator` (since issue 22 built by the
numba function :func:`bounce.exact.oscillator.oscillator_tables`) must be the same bits as those of the numpy
builder they replace, kept here (and only here) as :func:`reference_oscillator`: every flight, sticky phase and
sweep result downstream is then unchanged to the last bit.  Compared with ``np.array_equal`` for mu = 0, tiny,
the regime boundaries (1 exactly, its float neighbours), the points where log2(rho) sits on a half-integer
(sigma = 2^round(log2 rho) decided by a tie of rounding), 10 .. 1e8 and many log-uniform draws.

The degree table coefs[3] holds q-grid values chosen by comparisons ``log tail <= log(2^-55 smallest sum)``; the
reference sums the Taylor series with numpy's ``power`` (SIMD, not libm's pow) and a BLAS product, the compiled
builder with Horner, so the *sums* differ by a few ulps: the tables agree as long as no comparison falls within
those ulps of a tie.  :func:`test_degree_decisions_are_far_from_ties` measures both: the logs of the sums differ
by < 3e-14, the deciding comparisons are > 1.7e-6 from a tie (over MUS), 6e7 times farther.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
import pytest

from bounce.exact.oscillator import (
    N_COEFS, SERIES_Q, build_oscillator, make_oscillator, natural_frequency, oscillator_tables,
)

UNDER, CRITICAL, OVER = 0.0, 1.0, 2.0


# --------------------------------------------------------------------------- the former builder (numpy)

def reference_oscillator(mu: float) -> tuple[np.ndarray, np.ndarray]:
    """The Python/numpy build_oscillator of bounce.exact.oscillator before issue 22, verbatim but for names."""
    mu = float(mu)
    if mu < 1.0:
        branch, freq = UNDER, natural_frequency(mu)
        rho, lslow, lfast = 1.0, mu, mu
    elif mu == 1.0:
        branch, freq = CRITICAL, 0.0
        rho, lslow, lfast = 1.0, 1.0, 1.0
    else:
        branch, freq = OVER, natural_frequency(mu)
        lfast = mu + freq
        lslow = 1.0 / lfast
        rho = lfast
    sigma = 2.0 ** round(math.log2(rho))
    params = np.array([mu, rho, branch, freq, lslow, lfast, sigma], dtype=np.float64)

    def series(z0: float, z1: float) -> np.ndarray:
        z = [z0, z1 / sigma]
        m = mu / sigma
        for k in range(N_COEFS - 1):
            z.append((-2.0 * m * (k + 1) * z[k + 1] - z[k] / sigma**2) / ((k + 2) * (k + 1)))
        return np.array(z)

    c, s = series(1.0, 0.0), series(0.0, 1.0)
    coefs = np.zeros((4, N_COEFS))
    coefs[0, 2:] = -c[2:N_COEFS]
    coefs[1, 2:] = -s[2:N_COEFS]
    k = np.arange(1, N_COEFS)
    coefs[2, 1:] = -(k + 1) * s[2 : N_COEFS + 1] * sigma
    coefs[3] = _reference_thresholds(rho, sigma, coefs[:3])
    return params, coefs


_Q_GRID = np.geomspace(1e-14, SERIES_Q, 600)
_K_ROWS = np.arange(2, N_COEFS - 1)[:, None]
_LOG_TAIL = (np.log(2.0 * (3 * _K_ROWS + 4)) + (_K_ROWS + 1) * np.log(_Q_GRID)[None, :]
             - np.cumsum(np.log(np.arange(1, N_COEFS + 1)))[_K_ROWS])
_TAIL_VALID = _K_ROWS + 1 >= 3.0 * _Q_GRID[None, :]


@lru_cache(maxsize=4)
def _grid_powers(rho: float, sigma: float) -> np.ndarray:
    t = _Q_GRID / rho * sigma
    powers = t[:, None] ** np.arange(N_COEFS)[None, :]
    powers.flags.writeable = False
    return powers


def _reference_log_room(rho, sigma, coefs):
    smallest = np.min(np.abs(_grid_powers(rho, sigma) @ coefs.T), axis=1)
    with np.errstate(divide="ignore"):
        return np.log(2.0**-55 * smallest)


def _reference_thresholds(rho: float, sigma: float, coefs: np.ndarray) -> np.ndarray:
    q = _Q_GRID
    log_room = _reference_log_room(rho, sigma, coefs)
    ok = _TAIL_VALID & (_LOG_TAIL <= log_room[None, :])
    first_bad = np.where(ok.all(axis=1), q.size, np.argmin(ok, axis=1))
    last_good = np.where(first_bad > 0, q[np.maximum(first_bad - 1, 0)], 0.0)
    thresholds = np.zeros(N_COEFS)
    thresholds[2 : N_COEFS - 1] = np.where(first_bad == q.size, q[-1], last_good)
    thresholds[N_COEFS - 1] = SERIES_Q
    return thresholds


# --------------------------------------------------------------------------- the damping values compared

def _half_integer_log2_mus() -> list[float]:
    """mu (> 1) whose rho = mu + kappa lies next to 2^(k + 1/2), where round(log2 rho) is decided by a tie."""
    out = []
    for k in (0, 1, 3, 10, 26):
        r = 2.0 ** (k + 0.5)
        mu = 0.5 * (r + 1.0 / r)  # rho(mu) = r
        for d in range(-3, 4):
            out.append(mu + d * math.ulp(mu))
    return out


def _mus() -> list[float]:
    fixed = [0.0, 5e-324, 1e-300, 1e-16, 2.0**-27, 1e-8, 0.01, 0.3, 0.5, 0.5 - 2**-54, 1 / math.sqrt(2),
             math.nextafter(1.0, 0.0), 1.0, math.nextafter(1.0, 2.0), 1.0 + 1e-12, 1.0 + 1e-8, 1.0 + 1e-4,
             math.sqrt(2.0), 2.0, 10.0, 100.0, 1e3, 1e6, 1e8, 1e8 / math.sqrt(2.0), 1e12, 1e100]
    rng = np.random.default_rng(22)
    drawn = list(10.0 ** rng.uniform(-12.0, 8.0, 3000)) + list(rng.uniform(0.0, 3.0, 1000))
    return fixed + _half_integer_log2_mus() + drawn + [m / math.sqrt(2.0) for m in drawn[:500]]


MUS = _mus()


def test_tables_are_the_bits_of_the_former_builder():
    """params and coefs (the degree table coefs[3] included) equal to the bit, for every mu of MUS."""
    differ = []
    for mu in MUS:
        params, coefs = build_oscillator(mu)
        ref_params, ref_coefs = reference_oscillator(mu)
        if not (np.array_equal(params, ref_params) and np.array_equal(coefs, ref_coefs)
                and params.dtype == ref_params.dtype and coefs.shape == ref_coefs.shape):
            differ.append(mu)
    assert not differ, f"{len(differ)} of {len(MUS)} dampings differ, e.g. mu = {differ[:5]!r}"


def test_compiled_builder_and_cached_front_agree():
    """oscillator_tables (called from compiled loops), build_oscillator and make_oscillator: the same bits."""
    for mu in (0.0, 0.5, 1.0, 3.0, 1e8):
        a, b, c = oscillator_tables(mu), build_oscillator(mu), make_oscillator(mu)
        for x, y, z in zip(a, b, c):
            assert np.array_equal(x, y) and np.array_equal(y, z)
        assert not c[0].flags.writeable and not c[1].flags.writeable


def _horner_log_room(rho, sigma, coefs):
    """log(2^-55 smallest sum) as oscillator_tables forms it: Horner at every grid point, no FMA."""
    t = _Q_GRID / rho * sigma
    smallest = np.full(t.size, np.inf)
    for j in range(3):
        acc = np.full(t.size, coefs[j, N_COEFS - 1])
        for k in range(N_COEFS - 2, -1, -1):
            acc = acc * t + coefs[j, k]
        smallest = np.minimum(smallest, np.abs(acc))
    with np.errstate(divide="ignore"):
        return np.log(2.0**-55 * smallest)


def test_degree_decisions_are_far_from_ties():
    """The two builders' log(2^-55 smallest sum) differ by < 1e-13 (a few ulps of the log), and every comparison
    that decides a degree threshold (each row's grid points up to its first bad one) lies > 1e-7 from a tie
    (measured: 1.7e-6 at mu = 0.376 over MUS), so the tables agree for a structural reason, not by luck."""
    worst, spread = math.inf, 0.0
    for mu in MUS[::7]:
        ref_params, ref_coefs = reference_oscillator(mu)
        rho, sigma = ref_params[1], ref_params[6]
        log_room = _reference_log_room(rho, sigma, ref_coefs[:3])
        horner = _horner_log_room(rho, sigma, ref_coefs[:3])
        assert np.array_equal(np.isfinite(log_room), np.isfinite(horner))
        finite = np.isfinite(log_room)
        spread = max(spread, float(np.max(np.abs(log_room[finite] - horner[finite]), initial=0.0)))
        diff = log_room[None, :] - _LOG_TAIL  # >= 0: good
        ok = _TAIL_VALID & (diff >= 0)
        deciding = np.cumprod(np.concatenate([np.ones((ok.shape[0], 1), bool), ok[:, :-1]], axis=1), axis=1) > 0
        checked = deciding & _TAIL_VALID & np.isfinite(diff)
        worst = min(worst, float(np.min(np.abs(diff[checked]), initial=math.inf)))
    assert spread < 1e-13, spread
    assert worst > 1e-7, worst


@pytest.mark.parametrize("mu", [1e155, 1e300, float(np.finfo(float).max)])
def test_refuses_damping_whose_rate_overflows(mu):
    """mu + sqrt(mu^2 - 1) overflows (mu above ~1.3e154): refused (the numpy builder raised OverflowError)."""
    with pytest.raises(ValueError, match="mu must be"):
        build_oscillator(mu)

"""Helpers shared by the time-stepping methods (penalty, Moreau-Jean): failure codes, the
integer state slots of their kernels, the chunked driver with its CPU budget, the spring law's
physics as kernel arguments, energy and interpolation kernels.

The kernels take the law's numba functions (:class:`bounce.springs.base.Physics`) as arguments:
numba compiles a kernel once per law (per process: a kernel specialised on a function argument is
not cached on disk) and inlines the law's functions, so a kernel runs as fast as with the linear
right-hand side written inline (measured: a Verlet loop, 4.73 ns per step either way)."""

from __future__ import annotations

import time

import numpy as np
from numba import njit

from .base import FAILURES

F_OK = FAILURES.index("")
F_FELL = FAILURES.index("fell_through")
F_GAIN = FAILURES.index("energy_gain")
F_ENDLESS = FAILURES.index("endless_contact")
#: integer state slots common to the kernels (a kernel may append its own)
N_STEP, IN_CONTACT, N_CONTACT, I_SAMPLE, FAIL, FAIL_IDX, DONE = range(7)
N_COMMON_SLOTS = 7


def drive(advance, ist, budget: float) -> tuple[str, int, float]:
    """Call ``advance()`` (one chunk of steps) until a failure, completion or the CPU ``budget``
    (process seconds); return (failure, failure index, CPU time)."""
    failure, index = "", -1
    start = time.process_time()
    while True:
        advance()
        if ist[FAIL] != F_OK:
            failure, index = FAILURES[ist[FAIL]], int(ist[FAIL_IDX])
            break
        if ist[DONE]:
            break
        if time.process_time() - start > budget:
            failure, index = "budget", int(ist[N_CONTACT])
            break
    return failure, index, time.process_time() - start


def law_arguments(params) -> tuple:
    """(force, stiffness, damping, potential, c, xi_eq, V(xi_eq)): the spring law of ``params`` as the kernels take it."""
    law = params.spring
    xi_eq = params.xi_eq
    return (*law.physics, law.coefficients, xi_eq, law.potential(xi_eq))


@njit(inline="always")
def energy_excess(x, u, y, v, gamma, potential, c, xi_eq, v_eq):
    """E - E_m = xi'^2/2 + psi'^2/2 + V(xi) - V(xi_eq) + gamma (xi - xi_eq) + gamma x (eq. ``nonlin-energy``; no spring
    energy of a soft floor).  The spring's part is the difference of V as written (absolute rounding
    ~eps (|V(xi)| + |V(xi_eq)|): 1e-20 for the linear law at gamma = 0.01, far below the methods' energy_tol)."""
    a = 0.5 * (v - u)
    p = 0.5 * (v + u)
    xi = 0.5 * ((y - x) - 1.0)
    return 0.5 * (a * a + p * p) + (potential(xi, c) - v_eq + gamma * (xi - xi_eq)) + gamma * x


@njit(cache=True, inline="always")
def hermite_value(y0, y1, d0, d1, s):
    """Cubic Hermite interpolant on [0, 1] (values y0, y1, scaled slopes d0, d1) at s."""
    s2 = s * s
    s3 = s2 * s
    return (2 * s3 - 3 * s2 + 1) * y0 + (s3 - 2 * s2 + s) * d0 + (-2 * s3 + 3 * s2) * y1 + (s3 - s2) * d1


@njit(cache=True, inline="always")
def sample_step(ist, samples, y_samples, t0, t1, h, y, y1, v, v1):
    """y at the sorted sample times in (t0, t1] (t0 included for the very first step) from the step's cubic
    Hermite interpolant (step h, values y, y1, slopes v, v1); advances the sample slot."""
    ns = samples.shape[0]
    while ist[I_SAMPLE] < ns and samples[ist[I_SAMPLE]] <= t1:
        ts = samples[ist[I_SAMPLE]]
        if ts >= t0:
            y_samples[ist[I_SAMPLE]] = hermite_value(y, y1, h * v, h * v1, (ts - t0) / h)
        ist[I_SAMPLE] += 1


@njit(cache=True, inline="always")
def fell_through(ist, x1, u1, max_pen):
    """True, with the failure recorded against the current contact, when the step overflowed or
    went below the floor by more than ``max_pen``."""
    if abs(x1) < 1e300 and abs(u1) < 1e300 and x1 >= -max_pen:
        return False
    ist[FAIL] = F_FELL
    ist[FAIL_IDX] = max(ist[N_CONTACT] - 1, 0) if ist[IN_CONTACT] else ist[N_CONTACT]
    return True


def sorted_samples(sample_times):
    """(sorted sample times, order) or (empty array, None)."""
    if sample_times is None:
        return np.empty(0), None
    s = np.asarray(sample_times, dtype=float).ravel()
    order = np.argsort(s, kind="stable")
    return np.ascontiguousarray(s[order]), order


def unsort(values, order, shape):
    """Undo :func:`sorted_samples` on ``values``."""
    out = np.empty_like(values)
    out[order] = values
    return out.reshape(shape)

"""Helpers shared by the time-stepping methods (penalty, Moreau-Jean): failure codes, the
integer state slots of their kernels, the chunked driver with its CPU budget, the spring law's
physics bound into their kernels, energy and interpolation kernels.

A kernel is written once, as a template that calls the spring law's physics by the names of
:class:`bounce.springs.base.Physics` (``force``, ``stiffness``, ``damping``, ``potential``, each of (xi, c));
:func:`with_physics` compiles it once per law with the law's numba functions bound to those names.
numba inlines them, so a kernel runs as fast as with the linear right-hand side written inline
(measured: a Verlet loop, 4.73 ns per step either way), and caches it on disk like every other
kernel: compiled once per environment, not once per process (issue 22).  Passing the law's functions
as kernel arguments instead would compile the kernel again in every process (~1-2 s per kernel and law):
numba keys its cache index on a function argument's identity, which is new in every process."""

from __future__ import annotations

import functools
import hashlib
import inspect
import time
import types

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


#: the law's physics as a kernel template names it; :func:`with_physics` binds them per law (unbound here: a
#: template is never compiled as it stands)
force = stiffness = damping = potential = None


@functools.cache
def with_physics(template, law_type):
    """The kernel ``template`` (a plain function) compiled with ``law_type``'s physics bound to the names
    ``force``, ``stiffness``, ``damping``, ``potential`` (module docstring); once per template and law.

    Cached on disk under ``<template>[<law name>-<digest>]``: the digest is that of the source files of the
    law's physics, so that editing a law defined outside the package (whose files do not key
    :mod:`bounce._jit_cache`'s directory) compiles its kernels afresh; a law with no source file on disk
    (defined in a notebook) is compiled without a cache."""
    files = {inspect.getsourcefile(f.py_func) for f in law_type.physics}
    try:
        digest = hashlib.sha256(b"".join(open(f, "rb").read() for f in sorted(files))).hexdigest()[:12]
    except (OSError, TypeError):
        digest = None
    bound = dict(template.__globals__)
    bound.update(law_type.physics._asdict())
    kernel = types.FunctionType(template.__code__, bound, template.__name__, template.__defaults__)
    kernel.__qualname__ = f"{template.__qualname__}[{law_type.name}-{digest}]"
    kernel.__doc__ = template.__doc__
    return njit(cache=digest is not None)(kernel)


def law_arguments(params) -> tuple:
    """(c, xi_eq, V(xi_eq)): the spring law's numbers of ``params`` as the kernels take them (its physics is
    bound into the kernel by :func:`with_physics`)."""
    law = params.spring
    xi_eq = params.xi_eq
    return law.coefficients, xi_eq, law.potential(xi_eq)


def initial_energy_excess(st, params) -> float:
    """E - E_m at the state ``st`` (:func:`energy_excess`'s arithmetic, run by Python: the same bits, no compile)."""
    return energy_excess.py_func(st.x, st.xdot, st.y, st.ydot, params.gamma, params.spring.physics.potential,
                                 *law_arguments(params))


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

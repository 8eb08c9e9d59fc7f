"""Helpers shared by the time-stepping methods (penalty, Moreau-Jean)."""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True, inline="always")
def energy_excess(x, u, y, v, gamma):
    """E - E_m = xi'^2/2 + psi'^2/2 + (xi + gamma)^2/2 + gamma x (no spring energy of a soft floor)."""
    a = 0.5 * (v - u)
    p = 0.5 * (v + u)
    eta = 0.5 * ((y - x) - 1.0) + gamma
    return 0.5 * (a * a + p * p + eta * eta) + gamma * x


@njit(cache=True, inline="always")
def hermite_value(y0, y1, d0, d1, s):
    """Cubic Hermite interpolant on [0, 1] (values y0, y1, scaled slopes d0, d1) at s."""
    s2 = s * s
    s3 = s2 * s
    return (2 * s3 - 3 * s2 + 1) * y0 + (s3 - 2 * s2 + s) * d0 + (-2 * s3 + 3 * s2) * y1 + (s3 - s2) * d1


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

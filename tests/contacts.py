"""Contacts constructed backwards from a prescribed touch with the mpmath reference (the tests of
:mod:`bounce.exact.events` and of the series solver's linear limit share them)."""

from __future__ import annotations

from mpmath import mp, mpf

from bounce import Deviations
from bounce.analysis import reference as R

EPS = 2.0**-52


def reference_flight(g, mu, x0, u, a, eta):
    """The reference's closed-form flight from the same doubles (converted exactly)."""
    return R.Flight(*(mpf(v) for v in (g, mu, x0, u, a, eta)))


def constructed_contact(g, mu, a, A, T):
    """Start state (doubles) a time T before a contact with x = x' = 0, x'' = A, xi' = a there
    (xi = A + g - 2 mu a, so that x'' = -g - xi'' = A), evolved back with the reference."""
    with mp.workdps(60):
        xi = mpf(A) + mpf(g) - 2 * mpf(mu) * mpf(a)
        touch = reference_flight(g, mu, 0.0, 0.0, a, xi + mpf(g))
        s = mpf(-T)
        xi_s, xid_s = touch.xi(s)
        return Deviations(*(float(v) for v in (touch.x(s), touch.xdot(s), xid_s, xi_s + mpf(g))))


def rounding_level(d, g, T):
    """xn = 4 eps scale of x near the contact (scale: the magnitudes of the terms of eq. (F))."""
    return 4 * EPS * (d.x + abs(d.xdot) * T + abs(d.xidot) * T + abs(d.eta) + g * T * T)

"""An independent high-precision reference for gases of two-mass grains (not a test module).

Written from the model's equations (paper section 2, issue 23), sharing no code with ``bounce``:
per grain psi'' = -gamma and xi'' + 2 mu xi' + xi = 0 in closed form (mpmath, DPS digits, the three
damping branches), the floor (x_0 = psi_0 - xi_0 = 0, column) with the paper's rule psi' <-> xi'
(eq. ``collision-rule``), and pairs of neighbours (x_{k+1} = y_k, the ring's seam with + ell) whose
touching masses exchange their velocities, written in the masses' velocities (y' = psi' + xi',
x' = psi' - xi'), not in the engine's deviation variables.

Root search: a march of certified steps.  Every contact function f (the floor height, a pair's gap)
has |f''| <= B on t >= 0 with B from this module's own bound: for z'' + 2 mu z' + z = 0,
z^2 + z'^2 never increases, so |z| and |z'| stay below A = sqrt(z0^2 + z0'^2) and
|z''| = |z + 2 mu z'| <= (1 + 2 mu) A; so B = gamma + (1 + 2 mu) A (floor) or (1 + 2 mu) A_s
(pair, s = xi_i + xi_j).  From f > 0 the step to the first root of f + f' h - B h^2/2 cannot pass a
root of f; the march stops when f is below 10^-(DPS - 5) of its scale and polishes by Newton.  A
pair whose centres separate (Dpsi' > 0) cannot meet after (A_s - s - gap)/Dpsi' (|s| <= A_s), which
bounds its march.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from mpmath import mp, mpf

DPS = 50


@dataclass
class Grain:
    """psi, psi', xi, xi' of one grain at the reference's current time (mpf)."""

    psi: mpf
    psid: mpf
    xi: mpf
    xid: mpf


def oscillator(mu, z0, zd0, t):
    """(z(t), z'(t)) of z'' + 2 mu z' + z = 0 from (z0, zd0), closed form."""
    if mu < 1:
        w = mp.sqrt(1 - mu * mu)
        e = mp.exp(-mu * t)
        c, s = mp.cos(w * t), mp.sin(w * t)
        b = (zd0 + mu * z0) / w
        z = e * (z0 * c + b * s)
        zd = e * (-mu * (z0 * c + b * s) + w * (-z0 * s + b * c))
        return z, zd
    if mu == 1:
        e = mp.exp(-t)
        b = zd0 + z0
        return e * (z0 + b * t), e * (b - z0 - b * t)
    k = mp.sqrt(mu * mu - 1)
    l1, l2 = -mu + k, -mu - k  # roots of r^2 + 2 mu r + 1
    c1 = (zd0 - l2 * z0) / (l1 - l2)
    c2 = (l1 * z0 - zd0) / (l1 - l2)
    e1, e2 = mp.exp(l1 * t), mp.exp(l2 * t)
    return c1 * e1 + c2 * e2, c1 * l1 * e1 + c2 * l2 * e2


class Gas:
    """A gas at time ``t``: grains, geometry ('column' or 'ring'), gamma, mu, ell; :meth:`step` applies the
    next event and returns it."""

    def __init__(self, geometry, gamma, mu, ell, grains, t=0):
        self.geometry, self.gamma, self.mu = geometry, mpf(gamma), mpf(mu)
        self.ell = mpf(ell) if ell is not None else mpf(0)
        self.grains = grains
        self.t = mpf(t)

    @classmethod
    def from_deviations(cls, geometry, gamma, mu, ell, x, u, a, eta, t=0):
        """From float64 (x, x', xi', xi + gamma) per grain, converted exactly, combined at DPS digits."""
        with mp.workdps(DPS):
            g = mpf(gamma)
            grains = []
            for xk, uk, ak, ek in zip(x, u, a, eta):
                xi = mpf(ek) - g
                grains.append(Grain(mpf(xk) + xi, mpf(uk) + mpf(ak), xi, mpf(ak)))
            return cls(geometry, gamma, mu, ell, grains, mpf(t))

    def at(self, k, t):
        """(psi, psi', xi, xi') of grain k at time self.t + t."""
        g = self.grains[k]
        xi, xid = oscillator(self.mu, g.xi, g.xid, t)
        return g.psi + g.psid * t - self.gamma * t * t / 2, g.psid - self.gamma * t, xi, xid

    def magnitude(self, k, t):
        """The size of the terms of x_k(t) and y_k(t): |psi| + |psi'| t + gamma t^2/2 + |xi| + |xi'| + 1."""
        g = self.grains[k]
        return abs(g.psi) + abs(g.psid) * t + self.gamma * t * t / 2 + abs(g.xi) + abs(g.xid) + 1

    def contacts(self):
        """(slot, i, j, shift) of every contact: the floor is slot n-1 of the column (i = -1)."""
        n = len(self.grains)
        out = [(k, k, k + 1, mpf(0)) for k in range(n - 1)]
        if self.geometry == "column":
            out.append((n - 1, -1, 0, mpf(0)))
        else:
            out.append((n - 1, n - 1, 0, self.ell))
        return out

    def function(self, i, j, shift, t):
        """(f, f', scale) of a contact at self.t + t: the floor height x_0, or the gap x_j + shift - y_i;
        scale: the magnitude of the terms that make f."""
        pj, pdj, xj, xdj = self.at(j, t)
        if i < 0:
            return pj - xj, pdj - xdj, self.magnitude(j, t)
        pi, pdi, xi, xdi = self.at(i, t)
        f = (pj - xj + shift) - (pi + xi + 1)
        return f, (pdj - xdj) - (pdi + xdi), self.magnitude(i, t) + self.magnitude(j, t) + shift

    def march(self, i, j, shift):
        """The certified march towards a contact's first root, as a generator: it yields (t, done) where
        f > 0 on (0, t) is proved, done = True once t is the root (polished); it ends without a root when
        the pair's centres separate beyond any contact (module docstring)."""
        mu = self.mu
        if i < 0:
            g = self.grains[0]
            B = self.gamma + (1 + 2 * mu) * mp.sqrt(g.xi**2 + g.xid**2)
            t_end = None
        else:
            gi, gj = self.grains[i], self.grains[j]
            s, sd = gi.xi + gj.xi, gi.xid + gj.xid
            amp = mp.sqrt(s * s + sd * sd)
            B = (1 + 2 * mu) * amp
            f0 = self.function(i, j, shift, mpf(0))[0]
            dpsi = gj.psid - gi.psid
            t_end = (amp - s - f0) / dpsi if dpsi > 0 else None
            if t_end is not None and t_end <= 0:
                return
        tol = mpf(10) ** (5 - DPS)
        t = mpf(0)
        f, v, scale = self.function(i, j, shift, t)
        if f <= tol * scale:
            if v < 0:
                yield mpf(0), True
                return
            if v == 0 or B == 0:
                raise ValueError("reference: a contact at rest; not supported")
            t = v / B  # f(h) >= v h - B h^2/2 > 0 on (0, 2 v / B)
            f, v, scale = self.function(i, j, shift, t)
        while f > tol * scale:
            if B == 0:
                h = f / -v if v < 0 else None
            elif v < 0:
                h = 2 * f / (mp.sqrt(v * v + 2 * B * f) - v)
            else:
                h = (v + mp.sqrt(v * v + 2 * B * f)) / B
            if h is None or (t_end is not None and t + h > t_end):
                return
            t += h
            yield t, False
            f, v, scale = self.function(i, j, shift, t)
        for _ in range(5):  # Newton polish
            t -= f / v
            f, v, scale = self.function(i, j, shift, t)
        yield t, True

    def next_contact(self):
        """(slot, tau, i, j, shift) of the first contact to come, or None: the contacts' marches advanced
        together, always the one that is least far, until one reaches its root before every other's
        certified time."""
        marches = {c: self.march(*c[1:]) for c in self.contacts()}
        where = {c: mpf(0) for c in marches}
        found = {}
        while marches:
            c = min(marches, key=lambda c: where[c])
            if found and where[c] >= min(found.values()):
                break
            try:
                t, done = next(marches[c])
            except StopIteration:
                del marches[c]
                continue
            if done:
                found[c] = t
                del marches[c]
            else:
                where[c] = t
        if not found:
            return None
        c = min(found, key=found.get)
        return (c[0], found[c]) + c[1:]

    def step(self):
        """Apply the next event: returns (slot, tau, speed) and moves every grain to the event's time."""
        with mp.workdps(DPS):
            best = self.next_contact()
            if best is None:
                return None
            slot, tau, i, j, shift = best
            self.grains = [Grain(*self.at(k, tau)) for k in range(len(self.grains))]
            self.t += tau
            if i < 0:
                g = self.grains[0]
                speed = -(g.psid - g.xid)
                g.psid, g.xid = g.xid, g.psid  # eq. collision-rule
            else:
                gi, gj = self.grains[i], self.grains[j]
                ydot_i, xdot_i = gi.psid + gi.xid, gi.psid - gi.xid
                xdot_j, ydot_j = gj.psid - gj.xid, gj.psid + gj.xid
                speed = ydot_i - xdot_j
                ydot_i, xdot_j = xdot_j, ydot_i  # the touching masses exchange their velocities
                gi.psid, gi.xid = (ydot_i + xdot_i) / 2, (ydot_i - xdot_i) / 2
                gj.psid, gj.xid = (ydot_j + xdot_j) / 2, (ydot_j - xdot_j) / 2
            return slot, tau, speed

    def deviations(self):
        """Per grain (x, x', xi', eta = xi + gamma) as mpf."""
        return [(g.psi - g.xi, g.psid - g.xid, g.xid, g.xi + self.gamma) for g in self.grains]

    def energy(self):
        """Total E - n E_m = sum of (xi'^2 + psi'^2 + (xi + gamma)^2)/2 + gamma x (eq. tot-mech-energy)."""
        return sum((g.xid**2 + g.psid**2 + (g.xi + self.gamma) ** 2) / 2 + self.gamma * (g.psi - g.xi)
                   for g in self.grains)


# --------------------------------------------------------------------------- float64 closed forms (numpy)

def oscillator_np(mu, z0, zd0, t):
    """(z(t), z'(t)) of z'' + 2 mu z' + z = 0 in float64 (numpy; t an array), the closed forms above."""
    t = np.asarray(t, dtype=np.float64)
    if mu < 1.0:
        w = np.sqrt(1.0 - mu * mu)
        e = np.exp(-mu * t)
        c, s = np.cos(w * t), np.sin(w * t)
        b = (zd0 + mu * z0) / w
        return e * (z0 * c + b * s), e * (-mu * (z0 * c + b * s) + w * (-z0 * s + b * c))
    if mu == 1.0:
        e = np.exp(-t)
        b = zd0 + z0
        return e * (z0 + b * t), e * (b - z0 - b * t)
    k = np.sqrt(mu * mu - 1.0)
    l1, l2 = -1.0 / (mu + k), -(mu + k)
    c1 = (zd0 - l2 * z0) / (l1 - l2)
    c2 = (l1 * z0 - zd0) / (l1 - l2)
    e1, e2 = np.exp(l1 * t), np.exp(l2 * t)
    return c1 * e1 + c2 * e2, c1 * l1 * e1 + c2 * l2 * e2


def free_motion(gamma, mu, x, u, a, eta, t):
    """Heights of the lower and upper mass (x(t), y(t)), xi'(t) and the magnitude of the terms that make
    them (their rounding is a few ulps of it) for a grain moving freely from (x, x', xi', xi + gamma)
    at t = 0 (float64, t an array)."""
    xi0 = eta - gamma
    psi0, psid0 = x + xi0, u + a
    xi, xid = oscillator_np(mu, xi0, a, t)
    psi = psi0 + psid0 * t - 0.5 * gamma * t * t
    scale = abs(psi0) + abs(psid0) * t + 0.5 * gamma * t * t + abs(xi0) + abs(xi) + 1.0
    return psi - xi, psi + xi + 1.0, xid, scale


GAUSS = np.polynomial.legendre.leggauss(12)


def dissipation(gamma, mu, a, eta, tau):
    """The energy a grain's spring dissipates in a free flight of duration tau from (xi', xi + gamma):
    the integral of 2 mu xi'(t)^2 (eq. energy-dissipation), by 12-point Gauss-Legendre on pieces of
    length at most 1/(2 max(1, mu)) (the integrand is entire and varies on the time scale
    1/max(1, 2 mu): the rule's error is below 1e-15 relative) for flights up to 25 such pieces; for
    longer ones (thousands of spring periods) by the oscillator's energy identity
    d/dt (xi^2 + xi'^2)/2 = -2 mu xi'^2 between the flight's ends, in closed form."""
    pieces = int(np.ceil(2.0 * tau * max(1.0, mu)))
    if pieces > 25:
        xi, xid = oscillator_np(mu, eta - gamma, a, tau)
        xi0 = eta - gamma
        return float(0.5 * (xi0 * xi0 + a * a) - 0.5 * (xi * xi + xid * xid))
    edges = np.linspace(0.0, tau, max(pieces, 1) + 1)
    nodes, weights = GAUSS
    half = 0.5 * np.diff(edges)
    t = (0.5 * (edges[:-1] + edges[1:]))[:, None] + half[:, None] * nodes[None, :]
    xid = oscillator_np(mu, eta - gamma, a, t)[1]
    return float(np.sum(2.0 * mu * xid * xid * weights[None, :] * half[:, None]))

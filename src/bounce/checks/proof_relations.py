"""Check ``proof-relations``: relations the proofs use without a row elsewhere (sections 2, 5, 6).

1. eq. Xdot-is-Otau, Xdot_n = O(tau_{n-1}), over the whole run (transient included).  The proof's mean-value step
   -Xdot_n = Xdot_{n-1} + x''(eta_{n-1}) tau_{n-1} with Xdot_{n-1} >= 0 gives Xdot_n <= tau_{n-1} sup(-x'') over the
   flight; x'' = -gamma + xi + 2 mu xi' (eq. eq-motion-psi-xi) and (xi + gamma)^2/2 + xi'^2/2 <= E - E_m (eq. Emin),
   non-increasing, make the constant explicit: B = 2 gamma + sqrt(2 e (1 + 4 mu^2)), e = E - E_m at the flight's
   start (bounded by the previous kept record).  The limit Xdot_n/tau_n -> gamma is errata/limit-xdot-over-tau's.
2. eq. jump: [dE/dt(t_n)] = -2 mu [xi'^2(t_n)] = 2 mu Xdot_n ydot(t_n) (eq. xidot2-jump) <= C tau_{n-1}, along a
   run: xi'(t_n^-) from the closed-form flight of the previous record (not from the collision rule), and
   C_n = 4 mu B_n sqrt(e_n) (|ydot| <= 2 sqrt(E - E_m)).  errata/xidot2-jump checks eq. xidot2-jump at one impact.
3. the y-equation of eq. dimensionless-eq-motion from eq. dimensional-eq-motion (algebra/dimensionless-equations
   checks the x-equation only).
4. eq. k-derivative_jump for k >= 4: the paper gives no bar c_k beyond k = 3.  Differentiating eq.
   dimensionless-eq-motion k - 2 times, the jumps obey [x^(k)] + [y^(k)] = 0 (k >= 2) and D_k = [x^(k)] - [y^(k)] =
   -2 mu D_(k-1) - D_(k-2), D_0 = 0, D_1 = 2 Xdot_n, so bar c_k = (-1)^(k-1) U_(k-1)(mu) (Chebyshev, second kind);
   compared with one-sided derivatives of the mpmath free flight (bounce.analysis.reference) at recorded impacts.
"""

from __future__ import annotations

from functools import cached_property
from types import SimpleNamespace

import numpy as np
import xarray as xr

from .._registry import lazy_import
from ..analysis import reference
from ..analysis.theory import E_min, tot_mech_energy
from ..exact.flight import flight_spring
from ..exact.oscillator import fundamental, make_oscillator
from ..kinds import IMPACT
from . import base
from .base import PAPER, Check, Falsifier, Verdict, claim, judge, on_scenes, variable, with_variable

NAME = "proof-relations"
EPS = float(np.finfo(float).eps)

sp = lazy_import("sympy")


# --------------------------------------------------------------------------- closed forms of this group

def flight_to(eta, xidot, g: float, mu: float, tau) -> tuple[np.ndarray, np.ndarray]:
    """(eta, xi') after free flights of length ``tau`` from the records' (eta = xi + g, xi'), by the solver's own
    oscillator (:func:`bounce.exact.oscillator.fundamental`, :func:`bounce.exact.flight.flight_spring`: a few ulps
    for every mu >= 0, the critical mu = 1 included); the spring is free between impacts (eq. eq-motion-psi-xi)."""
    params, coefs = make_oscillator(mu)
    out = np.empty((2, np.size(tau)))
    for k, (e, a, t) in enumerate(zip(np.atleast_1d(eta), np.atleast_1d(xidot), np.atleast_1d(tau))):
        omc, _, _, c, S, Sd = fundamental(float(t), params, coefs)
        out[:, k] = flight_spring(float(e), float(a), g, omc, c, S, Sd)
    return out[0], out[1]


def jump_coefficients(mu, kmax: int) -> list:
    """bar c_k of eq. k-derivative_jump, k = 0..kmax, derived with sympy from eq. dimensionless-eq-motion.

    The jumps J_k = [x^(k)], K_k = [y^(k)] of a solution whose only discontinuity is [x'] = 2 Xdot_n (eq.
    collision-rule-jump; x, y and y' continuous) obey the (k - 2)-th derivative of each equation of motion (the
    constants drop out); returns J_k/Xdot_n."""
    X = sp.Symbol("Xdot_n", positive=True)
    J, K = [sp.Integer(0), 2 * X], [sp.Integer(0), sp.Integer(0)]
    for k in range(2, kmax + 1):
        J.append(sp.expand(-mu * J[k - 1] - J[k - 2] / 2 + K[k - 2] / 2 + mu * K[k - 1]))
        K.append(sp.expand(-mu * K[k - 1] - K[k - 2] / 2 + J[k - 2] / 2 + mu * J[k - 1]))
    return [sp.simplify(j / X) for j in J], [sp.simplify(k_ / X) for k_ in K]


def _y_equation(Y, s, g, mu, constant):
    """y'' + mu y' + y/2 - (-gamma + constant + x/2 + mu x'), X(s) the lower mass."""
    X = sp.Function("X")(s)
    return (sp.diff(Y, s, 2) + mu * sp.diff(Y, s) + Y / 2) - (-g + constant + X / 2 + mu * sp.diff(X, s))


def printed_y_equation(Y, s, g, mu):
    """The y-equation of eq. dimensionless-eq-motion as printed, left minus right side."""
    return _y_equation(Y, s, g, mu, sp.Rational(1, 2))


def y_equation_with_x_constant(Y, s, g, mu):
    """The y-equation with the x-equation's constant -1/2 in place of +1/2 (a misprint the row must catch)."""
    return _y_equation(Y, s, g, mu, -sp.Rational(1, 2))


def jumps_y_smooth(mu, kmax: int):
    """The jumps as a derivation that treats y as smooth would get them (the falsifier of row
    jump-coefficients-high-orders): the x-equation differentiated without [y^(k)], and [y^(k)] = 0."""
    X = sp.Symbol("Xdot_n", positive=True)
    J = [sp.Integer(0), 2 * X]
    for k in range(2, kmax + 1):
        J.append(sp.expand(-mu * J[k - 1] - J[k - 2] / 2))
    return [sp.simplify(j / X) for j in J], [sp.Integer(0)] * (kmax + 1)


# --------------------------------------------------------------------------- the measurement

class Measurements(base.Measurements):
    """Per scene: the impacts' Xdot_n/tau_{n-1} against B_n, the jumps of dE/dt; the sympy derivations; the one-sided
    derivatives at the first recorded impacts."""

    @cached_property
    def runs(self) -> list:
        return [self._run(ds) for ds in self.scenes]

    def _run(self, ds) -> SimpleNamespace:
        g, mu = float(ds.attrs["gamma"]), float(ds.attrs["mu"])
        ev = ds["event"].values
        kind = ds["kind"].values
        xdot, tau, e = ds["xdot"].values, ds["tau"].values, ds["energy_excess"].values
        xidot, eta, ydot = ds["xidot"].values, ds["eta"].values, ds["ydot"].values
        x0, xd0, a0, eta0 = (float(ds.attrs[k]) for k in ("x0", "xdot0", "xidot0", "eta0"))
        e0 = tot_mech_energy(eta0 - g, a0, xd0 + a0, g, x=x0) - E_min(g)
        e_start = np.concatenate([[e0], e[:-1]])  # E - E_m at the kept record before: >= e at the flight's start
        imp = kind == IMPACT
        B = 2 * g + np.sqrt(2 * e_start * (1 + 4 * mu * mu))
        before = np.where(ev == 0, max(0.0, -xd0), 0.0)  # -Xdot_{n-1} term: 0 after an event (xdot >= 0 there)
        ratio = xdot / tau
        bound = B + before / tau
        # jumps of dE/dt at impacts whose previous event is recorded: xi'(t_n^-) from the closed-form flight
        pair = np.flatnonzero(imp[1:] & (np.diff(ev) == 1)) + 1
        eta_pre, xid_pre = flight_to(eta[pair - 1], xidot[pair - 1], g, mu, tau[pair])
        jump = -2 * mu * (xidot[pair] ** 2 - xid_pre**2)
        predicted = 2 * mu * xdot[pair] * ydot[pair]
        scale = (np.abs(eta[pair - 1] - g) + np.abs(xidot[pair - 1])) * (1 + tau[pair])
        budget = float(self.spec["jump_ulps"]) * EPS * 2 * mu * scale * (np.abs(xid_pre) + np.abs(xidot[pair]) + scale)
        C = 4 * mu * B[pair] * np.sqrt(e[pair])
        return SimpleNamespace(
            name=str(ds.attrs.get("scene", "scene")), g=g, mu=mu, n=ev + 1.0, imp=imp, ratio=ratio, bound=bound,
            nsim=int(ds.attrs.get("n_events_simulated", ev.size)), pair=pair, jump=jump, predicted=predicted,
            budget=budget, C=C, tau_pair=tau[pair], xi_gap=np.abs(eta_pre - eta[pair]),
            state=[(xdot[i], xidot[i], eta[i]) for i in np.flatnonzero(imp)[: int(self.spec["derivative_impacts"])]])

    @cached_property
    def coefficients(self) -> SimpleNamespace:
        """bar c_k (sympy, symbolic mu) and the Chebyshev closed form."""
        mu = sp.Symbol("mu", positive=True)
        kmax = int(self.spec["kmax"])
        J, K = jump_coefficients(mu, kmax)
        closed = [None, None] + [sp.expand((-1) ** (k - 1) * sp.chebyshevu(k - 1, mu)) for k in range(2, kmax + 1)]
        return SimpleNamespace(mu=mu, kmax=kmax, J=J, K=K, closed=closed)

    @cached_property
    def one_sided(self) -> list:
        """[x^(k)]/Xdot_n and [y^(k)]/Xdot_n, k = 2..kmax, at the first impacts of each scene: mpmath's central
        differences (mp.diff, step h and h/2: their difference is the error) at t = 0 of x and y of the free flight
        from the state after the impact minus the free flight from the state before it (x' -> -x', xi' -> xi' + x':
        eq. collision-rule), both in bounce.analysis.reference (50 digits)."""
        from mpmath import mp, mpf

        kmax, h = int(self.spec["kmax"]), mpf(self.spec["derivative_step"])
        out = []
        for r in self.runs:
            for xd, a, eta in r.state:
                def gap(t, coordinate):
                    post = reference.free_flight(r.g, r.mu, 0, xd, a, eta, t)
                    pre = reference.free_flight(r.g, r.mu, 0, -xd, a + xd, eta, t)
                    if coordinate == "x":
                        return post.x - pre.x
                    return (post.x + 2 * post.eta) - (pre.x + 2 * pre.eta)  # y = x + 2 (eta - gamma) + 1

                vals = {(step, c): [mp.diff(lambda t: gap(t, c), 0, k, h=step) / mpf(xd) for k in range(2, kmax + 1)]
                        for step in (h, h / 2) for c in ("x", "y")}
                out.append(SimpleNamespace(
                    scene=r.name, mu=r.mu, Xdot=float(xd),
                    x=[float(v) for v in vals[(h / 2, "x")]], y=[float(v) for v in vals[(h / 2, "y")]],
                    err=[float(abs(p - q) + abs(u - w)) for p, q, u, w in
                         zip(vals[(h, "x")], vals[(h / 2, "x")], vals[(h, "y")], vals[(h / 2, "y")])]))
        return out

    @cached_property
    def y_equation(self) -> SimpleNamespace:
        """eq. dimensional-eq-motion's y-equation under x = L X(s), y = L Y(s), t = s sqrt(m/(2k)), divided by 2kL."""
        g, mu, L, k, m, nu, grav = sp.symbols("gamma mu L k m nu g", positive=True)
        s = sp.Symbol("s", positive=True)
        X, Y = sp.Function("X")(s), sp.Function("Y")(s)
        ts = sp.sqrt(m / (2 * k))
        dim_y = m * L * sp.diff(Y, s, 2) / ts**2 - (-grav * m - k * (L * Y - L * X - L)
                                                     - nu * L * (sp.diff(Y, s) - sp.diff(X, s)) / ts)
        scaled = sp.simplify(dim_y.subs({grav: g * 2 * L * k / m, nu: mu * sp.sqrt(2 * k * m)}) / (2 * k * L))
        residual = sp.simplify(sp.expand(scaled - printed_y_equation(Y, s, g, mu)))
        return SimpleNamespace(scaled=scaled, residual=residual)

    @cached_property
    def data(self) -> xr.Dataset:
        kp = int(self.spec["plot_points"])
        names = [r.name for r in self.runs]
        ns = len(self.runs)
        arr = {k: np.full((ns, kp), np.nan) for k in ("n", "ratio", "bound", "jn", "jump_tau", "C", "jump_err")}
        for i, r in enumerate(self.runs):
            idx = np.unique(np.clip(np.searchsorted(r.n, np.geomspace(1, r.n[-1], kp)), 0, r.n.size - 1))
            arr["n"][i, :idx.size] = r.n[idx]
            arr["ratio"][i, :idx.size] = r.ratio[idx] / r.g
            arr["bound"][i, :idx.size] = r.bound[idx] / r.g
            if r.pair.size:
                jdx = np.unique(np.clip(np.searchsorted(r.n[r.pair], np.geomspace(1, r.n[r.pair][-1], kp)), 0,
                                        r.pair.size - 1))
                arr["jn"][i, :jdx.size] = r.n[r.pair][jdx]
                arr["jump_tau"][i, :jdx.size] = r.jump[jdx] / r.tau_pair[jdx]
                arr["C"][i, :jdx.size] = r.C[jdx]
                arr["jump_err"][i, :jdx.size] = np.abs(r.jump - r.predicted)[jdx] / r.budget[jdx]
        ds = xr.Dataset(coords={"scene": ("scene", np.array(names, dtype=object), {"long_name": "input scene",
                                                                                  "units": "1"})})
        ds["scene_gamma"] = variable("scene", [r.g for r in self.runs], "gamma")
        ds["scene_mu"] = variable("scene", [r.mu for r in self.runs], "mu")
        for key, ln in (("n", "impact index n of the sample"), ("ratio", "Xdot_n/(gamma tau_{n-1})"),
                        ("bound", "B_n/gamma, B_n = 2 gamma + sqrt(2 e (1 + 4 mu^2))"),
                        ("jn", "impact index n of the jump samples"),
                        ("jump_tau", "[dE/dt(t_n)]/tau_{n-1}"), ("C", "C_n = 4 mu B_n sqrt(E - E_m)"),
                        ("jump_err", "|[dE/dt] - 2 mu Xdot_n ydot(t_n)| / its rounding budget")):
            ds[f"sample_{key}"] = variable(("scene", "sample"), arr[key], ln)
        kmax = int(self.spec["kmax"])
        ks = np.arange(2, kmax + 1)
        ds = ds.assign_coords(k=("k", ks, {"long_name": "derivative order k", "units": "1"}))
        probes = self.one_sided
        ds["probe_mu"] = variable("probe", [p.mu for p in probes], "mu of the probed impact")
        ds["probe_cbar"] = variable(("probe", "k"), [p.x for p in probes], "[x^(k)(t_n)]/Xdot_n (mpmath mp.diff)")
        ds["probe_err"] = variable(("probe", "k"), [p.err for p in probes], "its error (two step sizes)")
        c = self.coefficients
        ds["cbar_derived"] = variable(("probe", "k"), [[float(c.J[k].subs(c.mu, p.mu)) for k in ks] for p in probes],
                                      "bar c_k derived with sympy")
        ds.attrs.update(check=NAME)
        return ds


# --------------------------------------------------------------------------- the claims

CLAIMS: list = []

SUPERELASTIC = Falsifier(
    "records of a superelastic collision rule: every xdot record (Xdot_n) multiplied by 3, flights kept",
    doctor=on_scenes(lambda ds: with_variable(ds, "xdot", 3.0 * ds["xdot"].values)))


@claim(CLAIMS, "xdot-is-O-tau", PAPER, "thm:static-equilibrium", falsifier=SUPERELASTIC)
def xdot_is_O_tau(m, spec) -> dict:
    out = {}
    for r in m.runs:
        q = r.ratio[r.imp] / r.bound[r.imp]
        worst = int(np.argmax(q))
        tail = r.ratio[r.imp][-1] / r.g
        out[r.name] = Verdict(
            f"Xdot_n = O(tau_(n-1)) over the whole run: Xdot_n <= B tau_(n-1) [{r.name}]",
            "sec. 6, eq. Xdot-is-Otau (mean-value step of its proof)",
            f"scene {r.name} (gamma = {r.g:g}, mu = {r.mu:g}, {r.nsim} events, {int(r.imp.sum())} impact records): "
            "Xdot_n/tau_(n-1) at every recorded impact against B = 2 gamma + sqrt(2 e (1 + 4 mu^2)), e = E - E_m at "
            "the previous record (eq. Emin, E non-increasing: sup -x'' <= B on the flight)",
            "max Xdot_n/(B tau_(n-1)) <= 1 (and Xdot_n/tau_(n-1) -> gamma: errata/limit-xdot-over-tau)",
            f"max Xdot_n/(B tau_(n-1)) = {q[worst]:.4g} at n = {r.n[r.imp][worst]:.0f}; max Xdot_n/(gamma tau_(n-1)) "
            f"= {np.max(r.ratio[r.imp]) / r.g:.4g}; last = {tail:.6g}",
            f"1 + {spec['ratio_ulps']:g} eps: the bound is the proof's inequality, rounding of the ratio aside. It fails "
            "if an impact's velocity is not bounded by the acceleration over the flight before it (a velocity "
            "gained at the impact, as with restitution > 1)",
            judge(bool(np.all(q <= 1 + float(spec["ratio_ulps"]) * EPS))))
    return out


@claim(CLAIMS, "energy-rate-jump", PAPER, "thm:static-equilibrium", falsifier=SUPERELASTIC)
def energy_rate_jump(m, spec) -> dict:
    out = {}
    for r in m.runs:
        if r.pair.size < 3:
            continue
        dev = np.abs(r.jump - r.predicted)
        ok_formula = bool(np.all(dev <= r.budget))
        q = r.jump / (r.C * r.tau_pair)
        ok_bound = bool(np.all(q <= 1.0))
        rel = float(np.max(dev / np.maximum(np.abs(r.predicted), r.budget)))
        out[r.name] = Verdict(
            f"[dE/dt(t_n)] = 2 mu Xdot_n ydot(t_n) <= C tau_(n-1) at every impact [{r.name}]",
            "sec. 6, eqs. xidot2-jump and jump (proof of Lemma xidot(t)-goes-to-0)",
            f"scene {r.name}: {r.pair.size} impacts whose previous event is recorded; xi'(t_n^-) from the closed-form "
            "free spring over tau_(n-1) from the previous record (not the collision rule), [dE/dt] = -2 mu "
            "(xi'(t_n^+)^2 - xi'(t_n^-)^2); C_n = 4 mu B_n sqrt(E - E_m) (|ydot| <= 2 sqrt(E - E_m), B_n of row "
            "xdot-is-O-tau)",
            "[dE/dt] = 2 mu Xdot_n ydot(t_n); max [dE/dt]/(C tau_(n-1)) <= 1",
            f"max |[dE/dt] - 2 mu Xdot_n ydot|/max(|2 mu Xdot_n ydot|, budget) = {rel:.3g}; max [dE/dt]/(C tau_(n-1)) "
            f"= {np.max(q):.4g}; max deviation/budget = {np.max(dev / r.budget):.3g}; the propagated xi matches the record to {np.max(r.xi_gap):.2g}",
            f"{spec['jump_ulps']:g} eps x 2 mu s (|xi'_-| + |xi'_+| + s), s = (|xi| + |xi'|)(1 + tau) at the previous "
            "record (rounding of the closed-form flight, growing with its duration); the bound is "
            "the proof's inequality",
            judge(ok_formula and ok_bound))
    return out


@claim(CLAIMS, "dimensionless-y-equation", PAPER, "sec:model-description", falsifier=Falsifier(
    "the y-equation with the x-equation's constant (-gamma - 1/2) patched in as the printed form",
    patch=lambda: {"printed_y_equation": y_equation_with_x_constant}))
def dimensionless_y_equation(m, spec) -> Verdict:
    y = m.y_equation
    return Verdict(
        "With L, sqrt(m/(2k)), gamma = gm/(2Lk), mu = nu/sqrt(2km), the y-equation of eq. dimensional-eq-motion becomes "
        "y'' + mu y' + y/2 = -gamma + 1/2 + x/2 + mu x'",
        "sec. 2, eqs. dimensional-eq-motion, dimensionless-eq-motion (second line)",
        "sympy: x = L X(s), y = L Y(s), t = s sqrt(m/(2k)) in m y'' = -gm - k(y - x - L) - nu(y' - x'), divided by 2kL, "
        "minus the printed equation (algebra/dimensionless-equations does the x-equation)",
        "difference 0", f"difference {sp.sstr(y.residual)}", "exact (sympy simplify)", judge(y.residual == 0))


@claim(CLAIMS, "jump-coefficients-high-orders", PAPER, "sec:Proof-main-th", falsifier=Falsifier(
    "the jumps derived with y treated as smooth ([y^(k)] = 0 on the right side of the x-equation)",
    patch=lambda: {"jump_coefficients": jumps_y_smooth}))
def jump_coefficients_high_orders(m, spec) -> Verdict:
    c = m.coefficients
    ks = range(4, c.kmax + 1)
    printed = {2: -2 * c.mu, 3: 4 * c.mu**2 - 1}
    ok_low = all(sp.simplify(c.J[k] - printed[k]) == 0 for k in (2, 3))
    ok_sym = all(sp.simplify(c.J[k] + c.K[k]) == 0 and sp.simplify(c.J[k] - c.closed[k]) == 0
                 for k in range(2, c.kmax + 1))
    worst, ok_num = 0.0, len(m.one_sided) > 0
    tol_rel = float(spec["derivative_tolerance"])
    for p in m.one_sided:
        for i, k in enumerate(range(2, c.kmax + 1)):
            expect = float(c.J[k].subs(c.mu, p.mu))
            dev = max(abs(p.x[i] - expect), abs(p.y[i] + expect))
            tol = 10 * p.err[i] + tol_rel * max(1.0, abs(expect))
            worst = max(worst, dev / tol)
            ok_num = ok_num and dev <= tol
    values = "; ".join(f"c_{k} = {sp.sstr(c.J[k])}" for k in ks)
    return Verdict(
        "eq. k-derivative_jump for k = 4.." + str(c.kmax) + ": [x^(k)] = -[y^(k)] = bar c_k Xdot_n with bar c_k = "
        "(-1)^(k-1) U_(k-1)(mu) (the paper prints k = 2, 3 only)",
        "sec. 5, eq. k-derivative_jump",
        "sympy: the jumps of eq. dimensionless-eq-motion differentiated k - 2 times from [x'] = 2 Xdot_n; numbers: "
        f"mpmath mp.diff (orders 2..{c.kmax}) of the free flights after and before {len(m.one_sided)} recorded impacts "
        f"of the scenes (50 digits, step {spec['derivative_step']:g} and half)",
        "k = 2, 3 as printed; [x^(k)] + [y^(k)] = 0; bar c_k = (-1)^(k-1) U_(k-1)(mu); the numbers agree",
        f"{values}; k = 2, 3 {'as printed' if ok_low else 'differ from the print'}; closed form "
        f"{'holds' if ok_sym else 'fails'}; numbers: max deviation/tolerance = {worst:.3g}",
        f"sympy exact; numbers: 10 x (change of mp.diff with the step halved) + {tol_rel:g} x max(1, |bar c_k|) "
        "(a floor: the 50-digit rounding share at order 8 is far below it)",
        judge(ok_low and ok_sym and ok_num))


# --------------------------------------------------------------------------- the figure

def plot(ds: xr.Dataset, spec: dict, outputs) -> None:
    from ..figures.common import WIDTH, legend_below, plt, save, tex_num

    fig, axes = plt.subplots(2, 2, figsize=(WIDTH, 5.6))
    (a1, a2), (a3, a4) = axes
    for i, name in enumerate(ds["scene"].values):
        lab = r"%s ($\gamma=%s$, $\mu=%s$)" % (name, tex_num(ds["scene_gamma"][i]), tex_num(ds["scene_mu"][i]))
        col = f"C{i}"
        n = ds["sample_n"].values[i]
        a1.loglog(n, ds["sample_ratio"].values[i], color=col, lw=1, label=lab)
        a1.loglog(n, ds["sample_bound"].values[i], color=col, ls="--", lw=1)
        jn = ds["sample_jn"].values[i]
        a2.loglog(jn, np.abs(ds["sample_jump_tau"].values[i]), color=col, lw=1)
        a2.loglog(jn, ds["sample_C"].values[i], color=col, ls="--", lw=1)
        a3.loglog(jn, ds["sample_jump_err"].values[i], color=col, marker=".", ms=2, ls="none")
    a1.axhline(1.0, color="k", lw=0.6, ls=":")
    a1.set_xlabel(r"impact index $n$")
    a1.set_ylabel(r"ratio to $\gamma$ (dimensionless)")
    a1.set_title(r"(a) eq. Xdot-is-Otau: $\dot X_n/\tau_{n-1}\leq B_n$" "\n"
                 r"solid: $\dot X_n/(\gamma\tau_{n-1})$, dashed: $B_n/\gamma$", fontsize=8)
    a2.set_xlabel(r"impact index $n$")
    a2.set_ylabel(r"$|[\dot E(t_n)]|/\tau_{n-1}$ ($2kL^2$/time$^2$)")
    a2.set_title(r"(b) eq. jump: $[\dot E(t_n)]\leq C_n\tau_{n-1}$" "\n"
                 r"solid: $|[\dot E(t_n)]|/\tau_{n-1}$, dashed: $C_n$", fontsize=8)
    a3.axhline(1.0, color="r", lw=0.8, ls="--")
    a3.set_xlabel(r"impact index $n$")
    a3.set_ylabel(r"$|[\dot E]-2\mu\dot X_n\dot y(t_n)|$ / budget")
    a3.set_title("(c) eq. xidot2-jump along the run\n(red dashed: the tolerance, a rounding budget)", fontsize=8)
    k = ds["k"].values
    mus = ds["probe_mu"].values
    for j, mu in enumerate(sorted(set(mus.tolist()))):
        sel = np.flatnonzero(mus == mu)
        a4.plot(k, ds["cbar_derived"].values[sel[0]], color=f"C{j}", lw=1, label=r"$(-1)^{k-1}U_{k-1}(\mu)$, $\mu=%g$" % mu)
        for s in sel:
            a4.plot(k, ds["probe_cbar"].values[s], color=f"C{j}", marker="o", ms=3, ls="none")
    a4.set_yscale("symlog", linthresh=1.0)
    a4.set_xlabel(r"derivative order $k$")
    a4.set_ylabel(r"$\bar c_k=[x^{(k)}(t_n)]/\dot X_n$ (time$^{1-k}$)")
    a4.set_title("(d) eq. k-derivative_jump: sympy (lines),\nmp.diff at recorded impacts (dots)", fontsize=8)
    a4.legend(fontsize=5.5)
    fig.suptitle("proof-relations: Xdot = O(tau), the jump of dE/dt, the jump coefficients "
                 r"(units: lengths $L$, times $\sqrt{m/2k}$)", fontsize=9)
    fig.tight_layout()
    legend_below(fig, *a1.get_legend_handles_labels())
    save(fig, outputs)


TITLE = "Relations of the proofs: Xdot_n = O(tau_(n-1)), the jump of dE/dt, the y-equation, bar c_k for k >= 4"
CHECK = Check(NAME, Measurements, tuple(CLAIMS), plot, TITLE)

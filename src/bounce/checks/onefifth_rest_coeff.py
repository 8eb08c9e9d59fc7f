"""Check ``onefifth-rest-coeff``: the 1/5 law (eq. onefifth-rest-coeff) and the Hertz spring of the Discussion.

Inputs: the gathered sweep ``hertz-restitution`` (one well-separated impact of the Hertz ball, a = b = 1/2, over
a grid of impact speeds u and gravities gamma; r = psi' after the double impact / u) and a Hertz scene (repeated
impacts near equilibrium, the Discussion's asymptotic map).  Claims:

1. ``exponent`` (paper): on the smallest gamma (gravity-free limit) and u in ``fit_u``, ln(1 - r) = ln C + p ln u
   + k_1 u^(1/5) + k_2 u^(2/5) (the law's O((u/U)^(2/5)) term is a relative u^(1/5), and one order more) gives
   p = 1/5.
2. ``U-first-order`` (beyond): 1 - r = (u/U)^(1/5) + c (u/U)^(2/5) fitted with the exponent fixed gives U; the
   energy of one undamped compression-expansion cycle (:func:`bounce.analysis.theory.onefifth_U`, first order in mu, the
   exact leading term by scaling) predicts it.
3. ``gravity-breaks`` (beyond): below a speed u_b(gamma) the measured r leaves the fitted law by more than
   ``break_deviation``: gravity accelerates the centre of mass during the contact time T_c ~ u^(-1/5), leaving
   the spring moving (xi'/u = -gamma T_c/u, recorded), and the single-cycle law breaks where that is comparable
   with 1 - r ~ u^(1/5), i.e. gamma u^(-6/5) ~ u^(1/5): u_b ~ gamma^(5/7).  The log-log slope of the measured
   u_b against gamma is compared with 5/7, within the resolution of the u grid (the break lies between the grid
   point u_b and the next one up, a step s = ln(u_(i+1)/u_i): the slope is known to the interval those steps allow).
   Measured on the default sweep (41 speeds, gamma = 1e-12 .. 1e-4): local slopes 0.83, 0.75, 0.75, a fitted slope
   ~0.78, above 5/7 by more than the grid's resolution: a known failure of our scaling (see the claim).
4. ``repeated-impacts`` (paper, the Discussion's conclusion): for repeated impacts close to equilibrium the
   restitution r_n = Xdot_(n+1)/Xdot_n of consecutive impacts obeys the map eq. mappa, 1 - r_n = alpha Xdot_n
   (slope 1 in u, not 1/5), and the 1/5 law with the U of claim 2 overestimates 1 - r_n by orders of magnitude:
   the law "may be accurate only in the case of well-separated impacts".

Errors: every fitted number's error is the largest of its formal least-squares error, its change when the fit
window's ends move in by a factor ``window_factor`` and its change when the law's expansion has one term less
(exponent) or more (U) (nothing else); tolerances are ``sigmas`` times that.
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import xarray as xr

from ..kinds import IMPACT
from ..analysis.fitting import fit_loglog, scaled_lstsq
from ..analysis.theory import nonlin_alpha_limit, onefifth_U, rest_coefficient_function_of_mu
from .base import (BEYOND, NOT_CHECKABLE, PAPER, Check, Falsifier, Verdict, claim, judge, on_named, on_scenes, variable,
                   with_variable)

NAME = "onefifth-rest-coeff"
SUBJECT = "sec:Discussion"
FIFTH = 0.2


def _lstsq_with_se(a: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Coefficients of min |a c - y| and their formal standard errors."""
    coef, resid = scaled_lstsq(a, y)
    dof = max(y.size - a.shape[1], 1)
    cov = np.linalg.pinv(a.T @ a) * float(resid @ resid) / dof
    return coef, np.sqrt(np.maximum(np.diag(cov), 0.0))


def _exponent_fit(u, loss, orders: int = 2) -> tuple[float, float]:
    """p and its formal error in ln(loss) = ln C + p ln u + sum_k k_j u^(j/5), j = 1..orders (the law's relative
    corrections: (u/U)^(2/5) over (u/U)^(1/5) is u^(1/5))."""
    cols = [np.ones_like(u), np.log(u)] + [u ** (FIFTH * j) for j in range(1, orders + 1)]
    coef, se = _lstsq_with_se(np.column_stack(cols), np.log(loss))
    return float(coef[1]), float(se[1])


def _law_fit(u, loss, orders: int = 2) -> tuple[np.ndarray, float]:
    """Coefficients of loss = sum_k c_k u^(k/5), k = 1..orders, and the relative formal error of c_1."""
    coef, se = _lstsq_with_se(np.column_stack([u ** (FIFTH * k) for k in range(1, orders + 1)]), loss)
    return coef, float(se[0] / abs(coef[0]))


def _windowed(u, loss, lo, hi, factor, fit):
    """fit on [lo, hi] and on [lo factor, hi] and [lo, hi/factor]: (main, [variants])."""
    def on(a, b):
        s = (u >= a) & (u <= b)
        return fit(u[s], loss[s]) if s.sum() >= 5 else None
    return on(lo, hi), [v for v in (on(lo * factor, hi), on(lo, hi / factor)) if v is not None]


def _single_impacts(sw: xr.Dataset, spec: dict) -> SimpleNamespace:
    """Fits of the 1/5 law on the gravity-free row, the law's deviation and the break speed of every row."""
    g = sw["gamma"].values
    j0 = int(np.argmin(g))
    u_all, r_all = sw["arrival"].values, sw["r"].values
    ok = (sw["complete"].values == 1) & np.isfinite(r_all) & (r_all < 1.0)
    u, loss = u_all[ok[:, j0], j0], 1.0 - r_all[ok[:, j0], j0]
    lo, hi = (float(v) for v in spec["fit_u"])
    fac = float(spec["window_factor"])
    (p, p_se), pv = _windowed(u, loss, lo, hi, fac, _exponent_fit)
    pv.append(_windowed(u, loss, lo, hi, fac, lambda x, y: _exponent_fit(x, y, 1))[0])  # one order less
    (coef, c_rel), cv = _windowed(u, loss, lo, hi, fac, _law_fit)
    third = _windowed(u, loss, lo, hi, fac, lambda x, y: _law_fit(x, y, 3))[0]
    p_err = max([p_se] + [abs(v[0] - p) for v in pv])
    c_err = max([c_rel] + [abs(v[0][0] / coef[0] - 1.0) for v in cv] + [abs(third[0][0] / coef[0] - 1.0)])
    U = float(coef[0]) ** -5.0
    law = coef[0] * u_all**FIFTH + coef[1] * u_all ** (2 * FIFTH)
    dev = np.where(ok, np.abs((1.0 - r_all) / law - 1.0), np.inf)  # an unfinished contact: broken
    tol = float(spec["break_deviation"])
    u_break = np.full(g.size, np.nan)
    for j in range(g.size):  # from the top of the fit window down: the first speed where the law is off by > tol
        below = np.nonzero((u_all[:, j] <= hi) & (dev[:, j] > tol))[0]
        if below.size:
            u_break[j] = u_all[below[-1], j]
    mu, rho = float(sw.attrs["mu"]), float(sw.attrs["spring_rho"])
    return SimpleNamespace(gamma=g, j0=j0, u=u_all, r=r_all, dev=dev, p=p, p_err=p_err, U=U, U_err=5.0 * c_err * U,
                           c2=float(coef[1]), U_theory=onefifth_U(mu, rho), u_break=u_break, mu=mu, rho=rho,
                           residual=sw["residual"].values, n_fit=int(((u >= lo) & (u <= hi)).sum()), lo=lo, hi=hi)


def _repeated_impacts(ds: xr.Dataset, spec: dict) -> SimpleNamespace:
    """r_n = Xdot_(n+1)/Xdot_n of consecutive impacts n >= fit_n_min of a Hertz scene."""
    a_ = ds.attrs
    gamma, mu, rho = float(a_["gamma"]), float(a_["mu"]), float(a_["spring_rho"])
    a, b = float(a_["spring_a"]), float(a_["spring_b"])
    ev, kind, xdot = ds["event"].values.astype(np.int64), ds["kind"].values, ds["xdot"].values
    pair = (np.diff(ev) == 1) & (kind[:-1] == IMPACT) & (kind[1:] == IMPACT) & (ev[:-1] + 1 >= int(spec["fit_n_min"]))
    i = np.nonzero(pair)[0]
    u, r = xdot[i], xdot[i + 1] / xdot[i]
    alpha = nonlin_alpha_limit(gamma, mu, rho, a, b)
    out = SimpleNamespace(name=str(a_.get("scene", "scene")), gamma=gamma, mu=mu, rho=rho, a=a, b=b, u=u, r=r,
                          alpha=alpha, hertz=(a == 0.5 and b == 0.5), n_pairs=int(i.size))
    good = r < 1.0
    if good.sum() >= 20:
        out.slope, _, out.slope_se = fit_loglog(u[good], 1.0 - r[good])
        out.map_ratio = float(np.median((1.0 - r[good]) / (alpha * u[good])))
        out.law_ratio = float(np.min((u[good] / onefifth_U(mu, rho)) ** FIFTH / (1.0 - r[good])))
    else:
        out.slope = out.slope_se = out.map_ratio = out.law_ratio = math.nan
    return out


def measure(spec: dict, inputs: list) -> SimpleNamespace:
    sw, scene = inputs
    s = _single_impacts(sw, spec)
    rep = _repeated_impacts(scene, spec)
    data = xr.Dataset(coords={"u": ("u", sw["u"].values, {"long_name": "nominal impact speed", "units": "1"}),
                              "gamma": ("gamma", s.gamma, {"long_name": "gravity gamma", "units": "1"})})
    data["arrival"] = variable(("u", "gamma"), s.u, "impact speed u (single impact, spring at rest)")
    data["r"] = variable(("u", "gamma"), s.r, "restitution psi' after the double impact / u")
    data["law_deviation"] = variable(("u", "gamma"), np.where(np.isfinite(s.dev), s.dev, np.nan),
                                     "|(1 - r)/fitted law - 1| (nan: contact not finished in two impacts)")
    data["u_break"] = variable("gamma", s.u_break, "largest u below the fit window where the law is off by > break_deviation")
    data["repeated_u"] = variable("pair", rep.u, f"Xdot_n of consecutive impacts of {rep.name}")
    data["repeated_r"] = variable("pair", rep.r, "r_n = Xdot_(n+1)/Xdot_n")
    data.attrs.update(check=NAME, mu=s.mu, spring_rho=s.rho, exponent=s.p, exponent_err=s.p_err, U=s.U,
                      U_err=s.U_err, U_theory=s.U_theory, c2=s.c2, fit_u_lo=s.lo, fit_u_hi=s.hi,
                      fit_gamma=float(s.gamma[s.j0]), linear_r=rest_coefficient_function_of_mu(s.mu),
                      repeated_scene=rep.name, repeated_alpha=rep.alpha, repeated_mu=rep.mu, repeated_rho=rep.rho,
                      repeated_gamma=rep.gamma)
    ctx = (f"sweep hertz-restitution (a = b = 1/2, rho = {s.rho:g}, mu = {s.mu:g}); fit on gamma = "
           f"{s.gamma[s.j0]:g}, {s.n_fit} speeds u in [{s.lo:g}, {s.hi:g}]")
    return SimpleNamespace(single=s, rep=rep, data=data, ctx=ctx)


CLAIMS: list = []
SWEEP = "hertz-restitution"


def _quarter_law(sw):
    """Single impacts of a 1/4 law: 1 - r times u^0.05 (exponent 1/5 + 0.05)."""
    return with_variable(sw, "r", 1.0 - (1.0 - sw["r"].values) * sw["arrival"].values ** 0.05)


def _lossier(sw):
    """Single impacts losing 5 % more: 1 - r times 1.05 (the same power, U / 1.05^5)."""
    return with_variable(sw, "r", 1.0 - 1.05 * (1.0 - sw["r"].values))


def _gravity_mislabelled(sw):
    """The sweep's gravities recorded as gamma^0.9: the breaks scale as gamma^(slope/0.9)."""
    return sw.assign_coords(gamma=("gamma", sw["gamma"].values ** 0.9, sw["gamma"].attrs))


def _speeds_low(ds):
    """Repeated impacts whose speeds are 10 % low for their loss: 1 - r_n = 1.1 alpha Xdot_n."""
    return with_variable(ds, "xdot", ds["xdot"].values / 1.1)


@claim(CLAIMS, "exponent", PAPER, SUBJECT,
       falsifier=Falsifier("single impacts of a 1/4 law (1 - r x u^0.05: exponent off by 0.05)",
                           on_named(SWEEP, _quarter_law)))
def exponent(m, spec) -> Verdict:
    s, k = m.single, float(spec["sigmas"])
    return Verdict(
        "a Hertz spring (a = b = 1/2) gives r(u) = 1 - (u/U)^(1/5) + O((u/U)^(2/5)) for well-separated impacts",
        "eq. onefifth-rest-coeff; Discussion ('may be justified ... in a single compression-expansion cycle')",
        f"{m.ctx}: p in ln(1 - r) = ln C + p ln u + k_1 u^(1/5) + k_2 u^(2/5) (the law's relative corrections), "
        "r = psi' after the double impact / u", "p = 1/5", f"p = {s.p:.6f} +- {s.p_err:.2g}",
        f"|p - 1/5| <= {k:g} x error (largest of the formal LSQ error, the change when a window end moves in "
        f"x{spec['window_factor']:g} and the change with one correction less)", judge(abs(s.p - FIFTH) <= k * s.p_err))


@claim(CLAIMS, "U-first-order", BEYOND, SUBJECT,
       falsifier=Falsifier("single impacts losing 5 % more (1 - r x 1.05: U / 1.05^5)", on_named(SWEEP, _lossier)))
def u_first_order(m, spec) -> Verdict:
    s, k = m.single, float(spec["sigmas"])
    return Verdict(
        "U of the 1/5 law is the energy of one undamped compression-expansion cycle: U = (4 rho/5)^3/(4 mu I)^5, "
        "I = (2/5) B(3/5, 3/2)", "eq. onefifth-rest-coeff (Discussion; theory.nonlin_cycle_loss)",
        f"{m.ctx}: 1 - r = (u/U)^(1/5) + c (u/U)^(2/5) by least squares, U = c_1^-5",
        f"U = {s.U_theory:.8g}", f"U = {s.U:.8g} +- {s.U_err:.2g} (relative {s.U / s.U_theory - 1:+.2g})",
        f"|U - U_theory| <= {k:g} x error (5 x the relative error of c_1: formal, window ends x{spec['window_factor']:g}, "
        "one more order u^(3/5))", judge(abs(s.U - s.U_theory) <= k * s.U_err))


@claim(CLAIMS, "gravity-breaks", BEYOND, SUBJECT,
       known_failure="on the default sweep (41 speeds, gamma = 1e-12, 1e-9, 1e-6, 1e-4) the breaks' local slopes are "
                     "0.83, 0.75, 0.75 and the fitted slope ~0.78, above 5/7 = 0.714 by more than the grid's "
                     "resolution (+-0.04): gamma T_c/u against 1 - r is the leading order in (u/U)^(1/5), which is up "
                     "to 0.2 at the breaks (u_b ~ 2e-3 at gamma = 1e-4), so the scaling u_b ~ gamma^(5/7) is not "
                     "reached over this range; the CI-sized grid (16 speeds) cannot resolve the difference",
       falsifier=Falsifier("the sweep's gravities recorded as gamma^0.9 (the breaks' slope x 1.11)",
                           on_named(SWEEP, _gravity_mislabelled)))
def gravity_breaks(m, spec) -> Verdict:
    s = m.single
    found = np.isfinite(s.u_break)
    listing = ", ".join(f"gamma = {g:g}: u_b = {ub:.3g}" for g, ub in zip(s.gamma, s.u_break))
    text = ("the single-impact law breaks at small u by gravity: u_b ~ gamma^(5/7) (gamma T_c/u with T_c ~ u^(-1/5) "
            "comparable with 1 - r ~ u^(1/5))")
    if found.sum() < 2:
        return Verdict(text, "eq. onefifth-rest-coeff", m.ctx, "slope 5/7", f"{listing}: fewer than two breaks inside "
                       "the u grid", "none: nothing to fit", NOT_CHECKABLE)
    lg, lu = np.log(s.gamma[found]), np.log(s.u_break[found])
    slope = float(np.polyfit(lg, lu, 1)[0])
    step = float(np.log(s.u[1, 0] / s.u[0, 0]))
    # ln of the true break = ln u_b + e_j, 0 <= e_j < step: the least-squares slope moves by sum_j w_j e_j
    w = (lg - lg.mean()) / float(np.sum((lg - lg.mean()) ** 2))
    lo, hi = slope + step * float(w[w < 0].sum()), slope + step * float(w[w > 0].sum())
    return Verdict(
        text, "eq. onefifth-rest-coeff (our analysis of the Discussion's single cycle)",
        f"{m.ctx}: u_b = the largest u below the fit window where |(1 - r)/law - 1| > {spec['break_deviation']:g}, "
        f"per gamma; slope of ln u_b against ln gamma", "slope 5/7 = 0.714",
        f"{listing}; slope = {slope:.4f}, with the breaks anywhere in their grid steps [{lo:.4f}, {hi:.4f}]",
        f"5/7 in [{lo:.4f}, {hi:.4f}]: each break lies between its grid point and the next one up (a step of "
        f"{step:.3g} in ln u), which moves the fitted slope by at most these amounts (nothing else: no model allowance)",
        judge(lo <= 5.0 / 7.0 <= hi))


@claim(CLAIMS, "repeated-impacts", PAPER, SUBJECT,
       falsifier=Falsifier("repeated impacts whose speeds are 10 % low for their loss (Xdot / 1.1: 1 - r_n = "
                           "1.1 alpha Xdot_n)", on_scenes(_speeds_low)))
def repeated_impacts(m, spec) -> Verdict:
    rep = m.rep
    tol, factor = float(spec["map_slope_tolerance"]), float(spec["law_factor"])
    text = ("the 1/5 law fails for repeated impacts close to equilibrium: there 1 - r_n = alpha Xdot_n (the map "
            "eq. mappa), as for the linear spring")
    ref = "Discussion ('may be accurate only in the case of well-separated impacts')"
    if not rep.hertz or not math.isfinite(rep.slope):
        return Verdict(text, ref, f"scene {rep.name}", "a Hertz scene with >= 20 consecutive impacts past fit_n_min",
                       f"a = {rep.a:g}, b = {rep.b:g}, {rep.n_pairs} pairs", "none", NOT_CHECKABLE)
    return Verdict(
        text, ref,
        f"scene {rep.name} (rho = {rep.rho:g}, gamma = {rep.gamma:g}, mu = {rep.mu:g}): r_n = Xdot_(n+1)/Xdot_n over "
        f"{rep.n_pairs} consecutive impacts n >= {spec['fit_n_min']}, Xdot_n in [{rep.u.min():.3g}, {rep.u.max():.3g}]; "
        "log-log slope of 1 - r_n against Xdot_n; the 1/5 law with U = theory.onefifth_U(mu, rho) (claim U-first-order)",
        f"slope 1 (not 1/5); (1 - r_n)/(alpha Xdot_n) -> 1; (u/U)^(1/5) >= {factor:g} (1 - r_n)",
        f"slope = {rep.slope:.5f} +- {rep.slope_se:.1g}; median (1 - r_n)/(alpha Xdot_n) = {rep.map_ratio:.5f}; "
        f"min (u/U)^(1/5)/(1 - r_n) = {rep.law_ratio:.3g}",
        f"|slope - 1| <= {tol:g} (the map's next order, O(Xdot ln n), over the window), |ratio - 1| <= {tol:g}; the law "
        f"off by >= x{factor:g}", judge(abs(rep.slope - 1.0) <= tol and abs(rep.map_ratio - 1.0) <= tol
                                        and rep.law_ratio >= factor))


def plot(ds: xr.Dataset, spec: dict, outputs) -> None:
    """Restitution against impact speed: linear exp(-mu T_xi), Hertz measured (single impacts per gamma; repeated
    impacts near equilibrium), the fitted 1/5 law and the map 1 - alpha u."""
    from ..figures.common import WIDTH, plt, save, tex_num

    at = ds.attrs
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(WIDTH, 3.8), constrained_layout=True)
    u_line = np.geomspace(float(np.nanmin(ds["arrival"].values)), float(np.nanmax(ds["arrival"].values)), 200)
    law = at["c2"] * u_line ** (2 * FIFTH) + (u_line / at["U"]) ** FIFTH
    for j, g in enumerate(ds["gamma"].values):
        u, r = ds["arrival"].values[:, j], ds["r"].values[:, j]
        lab = rf"Hertz, single impact, $\gamma={tex_num(g)}$"
        style = dict(marker="osv^D"[j % 5], ms=4.5 - 0.6 * j, mfc="none", ls="none", color=f"C{j}", label=lab)
        a1.semilogx(u, r, **style)
        a2.loglog(u, np.where(r < 1, 1 - r, np.nan), **style)
    ru, rr = ds["repeated_u"].values, ds["repeated_r"].values
    lab_rep = rf"Hertz, repeated impacts ({at['repeated_scene']}, $\mu={at['repeated_mu']:g}$)"
    a1.semilogx(ru, rr, ".", ms=1, color="0.4", label=lab_rep)
    a2.loglog(ru, np.where(rr < 1, 1 - rr, np.nan), ".", ms=1, color="0.4", label=lab_rep)
    u_rep = np.geomspace(float(np.min(ru)), float(np.max(ru)), 20) if ru.size else np.array([])
    a2.loglog(u_rep, at["repeated_alpha"] * u_rep, "k:", lw=1, label=r"map: $1-r=\alpha u$")
    fit_lab = rf"1/5 law fitted: $U={at['U']:.4g}\pm{at['U_err']:.1g}$, $p={at['exponent']:.4f}\pm{at['exponent_err']:.1g}$"
    a1.semilogx(u_line, 1 - law, "k-", lw=0.8, label=fit_lab)
    a2.loglog(u_line, law, "k-", lw=0.8, label=fit_lab)
    r_lin = at["linear_r"]
    a1.axhline(r_lin, color="C3", ls="--", lw=0.8, label=rf"linear spring: $r = e^{{-\mu T_\xi}}={r_lin:.4f}$")
    a2.axhline(1 - r_lin, color="C3", ls="--", lw=0.8)
    for ax in (a1, a2):
        ax.axvspan(at["fit_u_lo"], at["fit_u_hi"], color="0.9", zorder=-1)
        ax.set_xlabel(r"impact speed $u$ (units $L/\sqrt{m/2k}$)")
    a1.set_ylim(0.0, 1.05)
    a1.set_ylabel(r"restitution $r$")
    a2.set_ylabel(r"$1-r$")
    a2.set_ylim(1e-7, 3.0)
    a1.set_title(r"(a) $r(u)$; shaded: fit window ($\gamma$ smallest); $r<0$: gravity wins", fontsize=8)
    a2.set_title(r"(b) $1-r$: slope $1/5$ (single) against 1 (repeated)", fontsize=8)
    handles, labels = a2.get_legend_handles_labels()
    extra = [(h, lb) for h, lb in zip(*a1.get_legend_handles_labels()) if lb not in labels]
    fig.legend(handles + [h for h, _ in extra], labels + [lb for _, lb in extra], fontsize=6, ncol=2, loc="outside lower center")
    fig.suptitle(rf"eq. onefifth-rest-coeff: Hertz spring $a=b=1/2$, $\rho={at['spring_rho']:g}$, $\mu={at['mu']:g}$",
                 fontsize=9)
    save(fig, outputs)


TITLE = "Discussion: the 1/5 law of a Hertz spring for well-separated impacts, and its failure near equilibrium"
CHECK = Check(NAME, measure, tuple(CLAIMS), plot, TITLE)

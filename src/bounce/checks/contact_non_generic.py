"""Theorem contact-non-generic (paper sections 2, 3 and 7): zero-speed contacts are non-generic.

Three measurements, each against the event classifier of :mod:`bounce.exact.events`:

1. **Monte-Carlo.**  The sweep ``contact-monte-carlo`` (its gathered file, a declared
   input): random initial conditions over many energies E - E_m = gamma^2 * 10^U and
   dampings mu in three regimes (under-, critically, over-damped), each run for its
   ``events`` events.  Expected: no
   ``sticky_start`` and no ``grazing`` at all.  For every impact n the arrival
   speed |Xdot_n| is compared with two scales: the launch speed of the flight
   that ends at it, v_ref = max(|Xdot_{n-1}|, |Xdot_n|) (|xdot(0)| for the first
   flight), and the classifier's rounding window v_tol (below).  The low tail of
   the ratio's distribution, N(|Xdot_n|/v_ref < r) ~ r^p, is fitted (on the sweep's
   histogram: the empirical CDF at its quarter-decade bin edges that bracket the ranks
   ``tail_fit``, :func:`bounce.analysis.anomalies.binned_tail_exponent`): p > 0 means
   no atom at zero speed.  (Asymptotically, near a grazing a dip of depth d below
   the floor gives a speed ~ sqrt(d), so p -> 2; the sampled ratios, >= 1e-2, are
   not yet in that tail and give a larger p.)  Extrapolating the margin
   |Xdot_n|/v_tol's tail linearly (p = 1, an upper estimate for any p >= 1; from the lower
   edge of the margin's bin, an over-estimate again) to 1
   estimates how many contacts of the whole sample were expected inside the
   window (<< 1: the expected anomaly count is 0).

2. **Constructed anomalous contacts.**  A state on the sticky line of eq.
   sticky-cond-Y (x = xdot = 0, Y = 1 + 2 gamma - 2 mu Ydot, Ydot < 4 mu gamma,
   i.e. alpha = 4 gamma mu - Ydot > 0) is evolved *backward* in time by the free
   flight (own closed form in mpmath, valid for t < 0) for a short T; near the
   onset x(t) = -alpha t^3/12 - gamma t^4/24 + ..., positive on (-T, 0) for
   T < 2 alpha/gamma (checked on a grid).  Forward simulation from that state must
   give ``sticky_start`` at t = T.  Likewise a state with x = xdot = 0, x'' > 0
   (eq. swishes) must give ``grazing``.  Constructed grazings followed to rest (Theorem
   Finite-number-swishes) are the experiment ``swish-runs`` (a rule of its own).

3. **Where the classifier switches.**  The same construction with an arrival
   speed v (pre-contact xdot = -v) on the sticky line: ``sticky_start`` for
   v << v_tol, ``impact`` for v >> v_tol.

The classifier (events.py docstring): x is known to xn = 4 eps scale (scale = sum
of the magnitudes of the terms of eq. (F)); a contact is tangential if
v^2 <= 32 |x''| xn or |v|^3 <= 288 |x'''| xn^2, i.e. v <= v_tol = max(sqrt(32|x''|xn),
(288 |x'''| xn^2)^(1/3)); it hides the contact time within delta2 = sqrt(2 xn/|x''|),
delta3 = (6 xn/|x'''|)^(1/3).
"""

from __future__ import annotations

import dataclasses
import math
from functools import cached_property
from types import SimpleNamespace

import numpy as np
import xarray as xr
from mpmath import mp, mpf

from ..analysis import reference
from ..analysis.anomalies import binned_tail_exponent, construct_contact, monte_carlo_summary, sample_parameters
from ..kinds import GRAZING, IMPACT, KIND_NAMES, STICKY_START
from ..exact.events import contact_window
from ..model import Deviations, Parameters
from ..simulate import simulate
from ..analysis.theory import E_min, contact_derivatives, min_sticky_energy, sticky_onset
from . import base
from .base import (IDENTITY, NOT_CHECKABLE, PAPER, SELF_TEST, Check, Experiment, Falsifier, Verdict, claim, judge,
                   on_named, variable)

NAME = "contact-non-generic"
MONTE_CARLO = "contact-monte-carlo"  # the sweep whose gathered file holds the Monte Carlo (config sweeps)
SWISH_KEYS = ("swish_params", "swish_acc_over_gamma", "swish_ydot_over_gamma", "swish_events", "swish_energy_stop")


def hexs(*values) -> str:
    return "(" + ", ".join(float(v).hex() for v in values) + ")"


# --------------------------------------------------------------------------- constructions

def constructed(spec: dict, kind: str):
    """Random sticky onsets (kind 'sticky') or grazings (kind 'grazing'), backward-evolved, simulated forward."""
    rng = np.random.default_rng(int(spec["seed"]) + (1 if kind == "sticky" else 2))
    n = int(spec["n_constructed"])
    gamma, mu, _ = sample_parameters(rng, n, spec)
    lo, hi = spec["alpha_over_gamma"]
    size = gamma * 10.0 ** rng.uniform(math.log10(lo), math.log10(hi), n)  # alpha (sticky) or x'' (grazing)
    frac = rng.uniform(0.05, 0.5, n)
    t_cap = float(spec["T_max"])
    rows = {k: np.empty(n) for k in ("T", "acc", "jerk", "scale", "window", "t_first", "x0")}
    first_kind = np.empty(n, dtype=np.int8)
    second_kind = np.full(n, -1, dtype=np.int8)
    starts = []
    for i in range(n):
        g, m = float(gamma[i]), float(mu[i])
        with mp.workdps(40):
            if kind == "sticky":
                a_pre, eta = sticky_onset(mpf(g), mpf(m), mpf(size[i]))
                T = frac[i] * min(2.0 * size[i] / g, t_cap)
            else:
                ydot = mpf(rng.uniform(-3.0, 3.0)) * g
                a_pre = ydot / 2
                eta = 2 * mpf(g) - 2 * mpf(m) * a_pre + mpf(size[i])  # x'' = eta + 2 mu a - 2 gamma = size
                jerk = float(a_pre) + 2 * m * float(-(eta - g) - 2 * m * a_pre)
                T = frac[i] * min(3.0 * size[i] / abs(jerk) if jerk > 0 else t_cap, t_cap)
            start, T, acc, jerk, scale = construct_contact(g, m, a_pre, eta, 0, T)
        _, _, d2, d3 = contact_window(scale, acc, jerk)
        tr = simulate(Parameters(g, m), start, max_events=2, t_max=T + 100.0)
        rows["T"][i], rows["acc"][i], rows["jerk"][i], rows["scale"][i] = T, acc, jerk, scale
        rows["window"][i] = min(d2, d3)
        rows["x0"][i] = start.x
        rows["t_first"][i] = tr.t[0] if len(tr) else np.nan
        first_kind[i] = tr.kind[0] if len(tr) else -1
        if len(tr) > 1:
            second_kind[i] = tr.kind[1]
        starts.append(start)
    return dict(gamma=gamma, mu=mu, size=size, first_kind=first_kind, second_kind=second_kind, starts=starts, **rows)


def swish_runs(spec: dict) -> xr.Dataset:
    """Experiment ``swish-runs`` (Theorem Finite-number-swishes): runs that start by grazing (constructed as
    above), followed to rest.

    Per (gamma, mu) of ``swish_params``, grazings with x''/gamma in ``swish_acc_over_gamma`` and
    Ydot/gamma in ``swish_ydot_over_gamma`` (Ydot = 2 xi' at the contact, eta = 2 gamma - 2 mu xi' + x'');
    each simulated for at most ``swish_events`` events, until E - E_m < ``swish_energy_stop`` (E_min - E_m).
    Recorded per run: the grazing and sticky events, the least E - E_m at one of them, and the first event
    after which E - E_m < E_min - E_m (Lemma Min-sticky-energy), past which the theorem's proof forbids
    any further grazing.
    """
    rows = []
    for g, mu in (tuple(map(float, p)) for p in spec["swish_params"]):
        e_threshold = min_sticky_energy(g, mu) - E_min(g)  # E_min - E_m = 2 gamma^2/(1 + 2 mu^2)
        for acc in spec["swish_acc_over_gamma"]:
            for ydot in spec["swish_ydot_over_gamma"]:
                with mp.workdps(40):
                    a_pre = mpf(ydot) * g / 2
                    eta = 2 * mpf(g) - 2 * mpf(mu) * a_pre + mpf(acc) * g
                    start, T, *_ = construct_contact(g, mu, a_pre, eta, 0, 0.5)
                tr = simulate(Parameters(g, mu), start, max_events=int(spec["swish_events"]),
                              energy_stop=float(spec["swish_energy_stop"]) * e_threshold)
                anomalous = np.flatnonzero((tr.kind == GRAZING) | (tr.kind == STICKY_START))
                below = np.flatnonzero(tr.energy_excess < e_threshold)
                rows.append((g, mu, float(acc), float(ydot), T, int(tr.kind[0]), int((tr.kind == GRAZING).sum()),
                             int(anomalous.size),
                             float(np.min(tr.energy_excess[anomalous])) / e_threshold if anomalous.size else np.nan,
                             int(anomalous[-1]) if anomalous.size else -1, int(below[0]) if below.size else -1,
                             float(tr.energy_excess[0]) / e_threshold, len(tr)))
    cols = list(zip(*rows))
    names = (("gamma", "gamma of the run", "f8"), ("mu", "mu of the run", "f8"),
             ("acc_over_gamma", "x''/gamma at the constructed grazing", "f8"),
             ("ydot_over_gamma", "Ydot/gamma at the constructed grazing", "f8"),
             ("T", "time of the constructed grazing", "f8"),
             ("first_kind", "kind of the first event", "i1"), ("n_graze", "grazing events of the run", "i8"),
             ("n_anomalous", "grazing and sticky_start events of the run", "i8"),
             ("min_anomalous_energy", "least (E - E_m)/(E_min - E_m) at a grazing or sticky onset (nan: none)", "f8"),
             ("last_anomalous", "index of the last grazing or sticky onset (-1: none)", "i8"),
             ("first_below", "first event with E - E_m < E_min - E_m (-1: none)", "i8"),
             ("e0", "(E - E_m)/(E_min - E_m) after the first event", "f8"), ("events", "events simulated", "i8"))
    return xr.Dataset({name: variable("run", np.array(col, dtype=dt), ln, **({"flag_values": [0, 1, 2, 3],
                                                                               "flag_meanings": " ".join(KIND_NAMES)}
                                                                              if name == "first_kind" else {}))
                       for (name, ln, dt), col in zip(names, cols)},
                      attrs={"title": "Theorem Finite-number-swishes: constructed grazings followed to rest"})


def near_grazing(spec: dict) -> dict:
    """Contact speeds of starts near a constructed grazing: the height lowered by h on a midpoint grid of [0, H].

    Per (gamma, mu) of ``swish_params``: the exponent k of measure{h : |Xdot_1(h)| < delta} ~ delta^k from the
    ranked speeds v_(j), j = lo..hi of ``near_fit`` (the measure below v_(j) is j - 1/2 grid cells), over the whole
    range and over its lower and upper halves (in log j), and the fit extrapolated to the classifier's window v_tol.
    """
    n = int(spec["near_n"])
    lo, hi = (int(v) for v in spec["near_fit"])
    mid = int(round(math.sqrt(lo * hi)))
    out = {key: [] for key in ("k", "k_low", "k_high", "decades", "count_at_window")}
    for g, mu in (tuple(map(float, p)) for p in spec["swish_params"]):
        with mp.workdps(40):
            eta = 2 * mpf(g) + mpf(spec["near_acc_over_gamma"]) * g
            start, T, acc, jerk, scale = construct_contact(g, mu, mpf(0), eta, 0, 0.5)
        H = float(spec["near_height_over_gamma"]) * g
        h = -H * (np.arange(n) + 0.5) / n  # lowered starts; raised ones miss the floor near T (no slow contact there)
        v = np.sort([abs(simulate(Parameters(g, mu), Deviations(start.x + dh, start.xdot, start.xidot, start.eta),
                                  max_events=1).xdot[0]) for dh in h])
        rank = np.arange(1, n + 1) - 0.5

        def slope(a, b):
            return float(np.polyfit(np.log(v[a - 1:b]), np.log(rank[a - 1:b]), 1)[0])

        k = slope(lo, hi)
        c = float(np.exp(np.mean(np.log(rank[lo - 1:hi]) - k * np.log(v[lo - 1:hi]))))
        out["k"].append(k)
        out["k_low"].append(slope(lo, mid))
        out["k_high"].append(slope(mid, hi))
        out["decades"].append(float(np.log10(v[hi - 1] / v[lo - 1])))
        out["count_at_window"].append(c * contact_window(scale, acc, jerk)[1] ** k)
    out = {key: np.array(val) for key, val in out.items()}
    out["decades"] = float(out["decades"].min())
    return out


def speed_scan(spec: dict):
    """Arrival speed v = ratio * v_tol on the sticky line: which kind does the classifier give?"""
    g, m = spec["scan_gamma_mu"]
    alpha = float(spec["scan_alpha_over_gamma"]) * g
    T = float(spec["scan_T"])
    ratios = np.geomspace(*spec["scan_ratio"], int(spec["scan_n"]))
    with mp.workdps(40):
        a_pre, eta = sticky_onset(mpf(g), mpf(m), mpf(alpha))
        _, T, acc, jerk, scale = construct_contact(g, m, a_pre, eta, 0, T)
    _, v_tol, _, _ = contact_window(scale, acc, jerk)
    kinds = np.empty(ratios.size, dtype=np.int8)
    speeds = np.empty(ratios.size)
    for i, r in enumerate(ratios):
        with mp.workdps(40):
            start, T_i, *_ = construct_contact(g, m, a_pre, eta, mpf(r * v_tol), T)
        tr = simulate(Parameters(g, m), start, max_events=1, t_max=T_i + 10.0)
        kinds[i] = tr.kind[0] if len(tr) else -1
        speeds[i] = abs(tr.xdot[0]) if len(tr) else np.nan
    return dict(ratios=ratios, kinds=kinds, speeds=speeds, v_tol=v_tol, gamma=g, mu=m, alpha=alpha, T=T,
                acc=acc, jerk=jerk, scale=scale)


# --------------------------------------------------------------------------- run

class Measurements(base.Measurements):
    """The Monte Carlo and the runs to rest (read from their files), the probes (run on first use, so one
    claim runs only what it needs)."""

    @cached_property
    def mc(self) -> dict:
        return monte_carlo_summary(self.named[MONTE_CARLO], int(self.spec["tail_fit"][1]))

    @cached_property
    def sticky(self) -> dict:
        return constructed(self.spec, "sticky")

    @cached_property
    def graze(self) -> dict:
        return constructed(self.spec, "grazing")

    @cached_property
    def swish(self) -> xr.Dataset:
        return self.named["swish-runs"]

    @cached_property
    def near(self) -> dict:
        return near_grazing(self.spec)

    @cached_property
    def scan(self) -> dict:
        return speed_scan(self.spec)

    @cached_property
    def tails(self) -> SimpleNamespace:
        """Tail fits of the Monte Carlo: N(< r) ~ r^p of both ratios; the expected count inside the window."""
        mc = self.mc
        lo, hi = self.spec["tail_fit"]
        p_ratio, p_ratio_err, c_ratio = binned_tail_exponent(mc["ratio_hist"], mc["ratio_edges"], lo, hi)
        p_margin, p_margin_err, _ = binned_tail_exponent(mc["margin_hist"], mc["margin_edges"], lo, hi)
        # N(margin < m) ~ m^p below the k-th smallest margin m_(k); p >= 1 for any density that is finite at
        # zero (p = 2 for the square-root fold of near-grazing flights), so the linear extrapolation is an
        # upper estimate
        k_lo = int(lo)
        low = float(mc["tail_margin_lower"][k_lo - 1])
        return SimpleNamespace(lo=lo, hi=hi, p_ratio=p_ratio, p_ratio_err=p_ratio_err, c_ratio=c_ratio, p_margin=p_margin,
                               p_margin_err=p_margin_err, k_lo=k_lo,
                               expected_in_window=k_lo / low if low > 0 else math.inf)

    def where(self, i) -> str:
        mc = self.mc
        return (f"sample {i} (gamma = {mc['gamma'][i]:.3g}, mu = {mc['mu'][i]:.3g}, "
                f"(E-E_m)/gamma^2 = {mc['dE'][i] / mc['gamma'][i] ** 2:.3g})")

    @cached_property
    def data(self) -> xr.Dataset:
        return _dataset(self, self.spec)


# --------------------------------------------------------------------------- falsifiers

def _mc_recorded_as(kind: int):
    """A doctor of the Monte Carlo: one impact of its first run recorded as ``kind`` (a classifier whose window takes
    a fast contact for a tangential one)."""
    def doctor(ds):
        counts = ds["counts"].values.copy()
        counts[0, kind] += 1
        counts[0, IMPACT] -= 1
        ds["counts"] = (ds["counts"].dims, counts, ds["counts"].attrs)
        return ds
    return on_named(MONTE_CARLO, doctor)


def _margin_inside(ds):
    """The first run's least margin |Xdot_n|/v_tol at 0.5: one impact resolved inside the classifier's window."""
    margin = ds["min_margin"].values.copy()
    margin[0] = 0.5
    ds["min_margin"] = (ds["min_margin"].dims, margin, ds["min_margin"].attrs)
    return ds


def _grazing_below_emin(ds):
    """The first run's least grazing energy 1 % below E_min - E_m (a grazing the proof's energy argument forbids)."""
    e = ds["min_anomalous_energy"].values.copy()
    e[0] = 0.99
    ds["min_anomalous_energy"] = (ds["min_anomalous_energy"].dims, e, ds["min_anomalous_energy"].attrs)
    return ds


def _speeds_power(power: float):
    """simulate swapped for one whose contact speeds are |Xdot|^power (near a grazing: |h|^(power/2), not |h|^(1/2))."""
    real = simulate

    def run(*args, **kwargs):
        tr = real(*args, **kwargs)
        return dataclasses.replace(tr, xdot=np.sign(tr.xdot) * np.abs(tr.xdot) ** power)
    return {"simulate": run}


def _onset_off_line():
    """eq. sticky-cond-Y with eta 1e-2 gamma high: the constructed 'onsets' have x'' = 1e-2 gamma (grazings)."""
    real = sticky_onset
    return {"sticky_onset": lambda gamma, mu, alpha: (real(gamma, mu, alpha)[0], real(gamma, mu, alpha)[1] + gamma / 100)}


def _arrival_speed(v_over_gamma: float):
    """construct_contact swapped for one whose backward flights arrive at v = v_over_gamma * gamma, not at rest."""
    real = construct_contact
    return {"construct_contact": lambda gamma, mu, a_pre, eta, v, T, *rest:
            real(gamma, mu, a_pre, eta, v + v_over_gamma * gamma, T, *rest)}


def _window_wide(factor: float):
    """The documented window with xn = factor x 4 eps scale: v_tol sqrt(factor) (x'' > 0) or factor^(2/3) (on the
    sticky line, x'' = 0) times larger."""
    real = contact_window
    return {"contact_window": lambda scale, acc, jerk: real(factor * scale, acc, jerk)}


CLAIMS: list = []
SUBJECT = "thm:contact-non-generic"


@claim(CLAIMS, "no-sticky-start", SELF_TEST, SUBJECT,
       falsifier=Falsifier("one Monte-Carlo impact recorded as a sticky start", _mc_recorded_as(STICKY_START)))
def no_sticky_start(m, spec) -> Verdict:
    n_sticky, n_ev = int(m.mc["counts"][:, STICKY_START].sum()), int(m.mc["counts"].sum())
    return Verdict(
        claim="The classifier reports no sticky event in generic runs (a self-test: a zero-measure set is never "
              "sampled, so this row checks for spurious classifications, not the theorem; see near-grazing-measure)",
        paper_ref="thm:contact-non-generic, eq. sticky-condition",
        computed=f"Monte-Carlo (sweep {MONTE_CARLO}): {len(m.mc['gamma'])} random initial conditions (seed "
                 f"{m.mc['seed']}; gamma log-uniform, mu under/critically/over-damped, (E-E_m)/gamma^2 log-uniform), "
                 f"{m.mc['events']} events each: count of sticky_start",
        expected="0",
        measured=f"{n_sticky} sticky_start in {n_ev} events",
        tolerance=f"exactly 0: the expected number of contacts inside the classifier's rounding window, "
                  f"extrapolated linearly (an upper estimate) from the lower edge of the bin of the {m.tails.k_lo}-th "
                  f"smallest margin, is "
                  f"{m.tails.expected_in_window:.2g} << 1",
        verdict=judge(n_sticky == 0))


@claim(CLAIMS, "no-grazing", SELF_TEST, SUBJECT,
       falsifier=Falsifier("one Monte-Carlo impact recorded as a grazing", _mc_recorded_as(GRAZING)))
def no_grazing(m, spec) -> Verdict:
    n_graze, n_ev = int(m.mc["counts"][:, GRAZING].sum()), int(m.mc["counts"].sum())
    return Verdict(
        claim="The classifier reports no grazing in generic runs (a self-test, as no-sticky-start)",
        paper_ref="thm:contact-non-generic, eq. swishes, thm:Finite-number-swishes",
        computed="same Monte-Carlo: count of grazing events",
        expected="0",
        measured=f"{n_graze} grazing in {n_ev} events",
        tolerance=f"exactly 0 (expected count inside the window {m.tails.expected_in_window:.2g})",
        verdict=judge(n_graze == 0))


@claim(CLAIMS, "near-grazing-measure", PAPER, SUBJECT,
       falsifier=Falsifier("contact speeds near the grazing growing like |h|^0.55 instead of |h|^0.5 (k = 1.82)",
                           patch=lambda: _speeds_power(1.1)))
def near_grazing_measure(m, spec) -> Verdict:
    nr, tl, mc = m.near, m.tails, m.mc
    k, k_lo, k_hi = nr["k"], nr["k_low"], nr["k_high"]
    tol = float(spec["near_exponent_tol"])
    lo, hi = spec["near_fit"]
    ok = bool(np.all(np.abs(k - 2.0) <= tol) and np.all(np.abs(k_lo - k_hi) <= tol))
    return Verdict(
        claim="Zero-speed contacts have zero measure: the measure of states whose contact speed is below delta "
              "vanishes as delta -> 0",
        paper_ref="thm:contact-non-generic (zero Lebesgue measure), eq. swishes",
        computed=f"around a constructed grazing (x''/gamma = {spec['near_acc_over_gamma']}, Ydot = 0) for (gamma, mu) "
                 f"in {spec['swish_params']}: start height lowered by h on a {spec['near_n']}-point midpoint grid of "
                 f"[0, H] (raised starts miss the floor there), H = {spec['near_height_over_gamma']:g} gamma; the measure of {{h: |Xdot_1(h)| < delta}} "
                 f"~ delta^k fitted through the ranked speeds k = {lo}..{hi} (count - 1/2 = measure / cell)",
        expected="k = 2 (square-root fold at a grazing: Xdot^2 = 2 x'' |h| to first order, so the measure is ~ delta^2 "
                 "and extrapolates to 0; a positive-measure set of zero-speed contacts would give k = 0)",
        measured="k = " + ", ".join(f"{v:.5f}" for v in k) + "; lower/upper half of the fit range: "
                 + ", ".join(f"{a:.5f}/{b:.5f}" for a, b in zip(k_lo, k_hi))
                 + f"; delta spans {nr['decades']:.2g} decade(s), the measure {math.log10((hi - 0.5) / (lo - 0.5)):.2g}; "
                 f"extrapolated measure at the classifier's window "
                 f"v_tol: {np.max(nr['count_at_window']):.2g} grid cells; Monte-Carlo ({mc['n_contacts']} impacts) "
                 f"low-tail exponent of |Xdot_n|/v_ref {tl.p_ratio:.2f} +- {tl.p_ratio_err:.2f} (CDF at the "
                 f"{m.mc['bin_width']:g}-decade bin edges around ranks {tl.lo}..{tl.hi}; not yet in the "
                 f"asymptotic range: smallest ratio {np.nanmin(mc['min_ratio']):.2g})",
        tolerance=f"|k - 2| <= {tol:g} and the two half-range slopes agree to {tol:g}: the first-order fold is "
                  f"exact up to O(h/H0) corrections, and over the fit range the half-range slopes differ by < 1e-3",
        verdict=judge(ok))


@claim(CLAIMS, "impacts-outside-window", SELF_TEST, SUBJECT,
       falsifier=Falsifier("one Monte-Carlo run's least margin |Xdot_n|/v_tol at 0.5 (an impact inside the window)",
                           on_named(MONTE_CARLO, _margin_inside)))
def impacts_outside_window(m, spec) -> Verdict:
    mc, tl = m.mc, m.tails
    j_min = int(np.nanargmin(mc["min_margin"]))
    return Verdict(
        claim="Every Monte-Carlo impact is resolved far outside the classifier's rounding window",
        paper_ref="thm:contact-non-generic; events.py (tangential contacts)",
        computed="margin |Xdot_n| / v_tol with v_tol = max(sqrt(32|x''| xn), (288|x'''| xn^2)^(1/3)), "
                 "xn = 4 eps scale of eq. (F) at the contact",
        expected="min margin > 1",
        measured=f"min margin {mc['min_margin'][j_min]:.3g} at " + m.where(j_min)
                 + f"; tail exponent {tl.p_margin:.2f} +- {tl.p_margin_err:.2f}",
        tolerance="1 = the classifier's threshold itself",
        verdict=judge(mc["min_margin"][j_min] > 1.0))


@claim(CLAIMS, "constructed-sticky-onsets", SELF_TEST, SUBJECT,
       falsifier=Falsifier("the onsets constructed with eta 1e-2 gamma above the sticky line of eq. sticky-cond-Y",
                           patch=_onset_off_line))
def constructed_sticky_onsets(m, spec) -> Verdict:
    sticky = m.sticky
    # constructed sticky onsets
    ok_kind = sticky["first_kind"] == STICKY_START
    terr = np.abs(sticky["t_first"] - sticky["T"])
    ok_time = terr <= 2.0 * sticky["window"]
    bad = np.flatnonzero(~(ok_kind & ok_time))
    # Rounding the constructed start to float64 moves it off the sticky plane; where the exact
    # (50-digit) flight of the *rounded* start then hits the floor faster than the classifier's
    # window v_tol, an impact is the right answer.  Only the other cases are failures.
    off_plane = []
    for i in bad:
        s_i = sticky["starts"][i]
        g_i, m_i = float(sticky["gamma"][i]), float(sticky["mu"][i])
        if sticky["first_kind"][i] != IMPACT:
            continue
        ex = reference.free_flight(g_i, m_i, s_i.x, s_i.xdot, s_i.xidot, s_i.eta, sticky["t_first"][i])
        acc_i, jerk_i = contact_derivatives(float(ex.a), float(ex.eta), g_i, m_i)
        xn_i, v_tol_i, _, _ = contact_window(sticky["scale"][i], acc_i, jerk_i)
        # the rounded start really meets the floor there (x = 0 to rounding), faster than v_tol
        if abs(float(ex.x)) <= 10.0 * xn_i and abs(float(ex.u)) > v_tol_i:
            off_plane.append(i)
    bad = np.setdiff1d(bad, np.array(off_plane, dtype=bad.dtype))
    msg = (f"{int((ok_kind & ok_time).sum())}/{ok_kind.size} sticky_start at |t - T| <= 2 delta3; "
           f"{len(off_plane)} impacts where the rounded start's exact contact speed exceeds v_tol (correct)")
    if bad.size:
        i = int(bad[0])
        s = sticky["starts"][i]
        kname = KIND_NAMES[sticky["first_kind"][i]] if sticky["first_kind"][i] >= 0 else "none"
        msg += (f"; first failure: gamma = {float(sticky['gamma'][i])!r}, mu = {float(sticky['mu'][i])!r}, alpha = "
                f"{float(sticky['size'][i])!r}, T = {float(sticky['T'][i])!r}, start Deviations(x, xdot, xidot, eta) = "
                f"{hexs(s.x, s.xdot, s.xidot, s.eta)}: got {kname} at t = {float(sticky['t_first'][i])!r}; "
                f"failures have alpha/gamma <= {np.max(sticky['size'][bad] / sticky['gamma'][bad]):.3g}")
        g, mu = float(sticky["gamma"][i]), float(sticky["mu"][i])
        ex = reference.free_flight(g, mu, s.x, s.xdot, s.xidot, s.eta, sticky["t_first"][i])
        acc, jerk = contact_derivatives(float(ex.a), float(ex.eta), g, mu)
        _, v_tol, _, _ = contact_window(sticky["scale"][i], acc, jerk)
        tr = simulate(Parameters(g, mu), s, max_events=1)
        msg += (f"; there the exact speed of the rounded start state is |x'| = {abs(float(ex.u)):.3g} < v_tol = "
                f"{v_tol:.3g}, but the simulator's contact speed is {abs(tr.xdot[0]):.3g} (a regression of this kind "
                f"once came from the Newton polish of flight.first_contact; see tests/exact/test_flight.py)")
    return Verdict(
        claim="A state backward-evolved from a sticky onset reaches the floor in a sticky event at t = T",
        paper_ref="eqs. sticky-condition, sticky-cond-Y; sec. 7 (states on S reached by T^-)",
        computed=f"{ok_kind.size} random onsets (alpha/gamma log-uniform in {spec['alpha_over_gamma']}),"
                 " backward flight by T < 2 alpha/gamma (mpmath, 40 digits), rounded to float64, simulated forward",
        expected="first event sticky_start at t = T (or an impact, if the exact flight of the rounded start "
                 "reaches the floor faster than the classifier's window v_tol)",
        measured=msg,
        tolerance="|t - T| <= 2 delta3, delta3 = (6 xn/|x'''|)^(1/3) the classifier's hidden window at xn = 4 eps "
                  "scale (doubled: the rounded start state moves the tangency by as much)",
        verdict=judge(bad.size == 0))


@claim(CLAIMS, "constructed-grazings", SELF_TEST, SUBJECT,
       falsifier=Falsifier("the grazings' backward flights arriving at 1e-6 gamma instead of at rest",
                           patch=lambda: _arrival_speed(1e-6)))
def constructed_grazings(m, spec) -> Verdict:
    graze = m.graze
    ok_kind = graze["first_kind"] == GRAZING
    terr_g = np.abs(graze["t_first"] - graze["T"])
    ok_time = terr_g <= 2.0 * graze["window"]
    bad = np.flatnonzero(~(ok_kind & ok_time))
    msg = f"{int((ok_kind & ok_time).sum())}/{ok_kind.size} grazing at |t - T| <= 2 min(delta2, delta3)"
    if bad.size:
        i = int(bad[0])
        s = graze["starts"][i]
        kname = KIND_NAMES[graze["first_kind"][i]] if graze["first_kind"][i] >= 0 else "none"
        msg += (f"; first failure: gamma = {float(graze['gamma'][i])!r}, mu = {float(graze['mu'][i])!r}, x'' = {float(graze['size'][i])!r}, "
                f"T = {float(graze['T'][i])!r}, start {hexs(s.x, s.xdot, s.xidot, s.eta)}: got {kname} at "
                f"t = {float(graze['t_first'][i])!r}")
    return Verdict(
        claim="A state backward-evolved from a grazing (x = xdot = 0, x'' > 0) grazes the floor at t = T",
        paper_ref="eq. swishes",
        computed=f"{ok_kind.size} random grazings (x''/gamma log-uniform in {spec['alpha_over_gamma']}), "
                 "backward flight by T, simulated forward",
        expected="first event grazing at t = T",
        measured=msg,
        tolerance="|t - T| <= 2 min(delta2, delta3), delta2 = sqrt(2 xn/|x''|) (classifier window, doubled as above)",
        verdict=judge(bad.size == 0))


@claim(CLAIMS, "finitely-many-grazings", PAPER, "thm:Finite-number-swishes",
       falsifier=Falsifier("one run with a grazing at E - E_m 1 % below E_min - E_m",
                           on_named("swish-runs", _grazing_below_emin)))
def finitely_many_grazings(m, spec) -> Verdict:
    runs = m.swish  # experiment swish-runs
    started = runs["first_kind"].values == GRAZING
    first_below = runs["first_below"].values
    reached = first_below >= 0
    # every grazing/sticky event at E >= E_min (the proof's energy argument) and none after E < E_min
    e_anom = runs["min_anomalous_energy"].values
    e_low = float(np.nanmin(e_anom)) if np.isfinite(e_anom).any() else math.inf
    after = (runs["last_anomalous"].values > first_below) & reached
    tol = 1e-9  # rounding of (E - E_m)/(E_min - E_m) ~ 1 for states known to float64 (as lem:Min-sticky-energy)
    ok = bool(started.all() and reached.all() and not after.any() and e_low >= 1 - tol)
    return Verdict(
        claim="Any initial condition generates a solution with at most a finite number of grazings",
        paper_ref="thm:Finite-number-swishes (proof: no collapse, and E falls below E_min of lem:Min-sticky-energy)",
        computed=f"{runs.sizes['run']} runs (experiment swish-runs) constructed to graze at t = T (x''/gamma in {spec['swish_acc_over_gamma']}, "
                 f"Ydot/gamma in {spec['swish_ydot_over_gamma']}, (gamma, mu) in {spec['swish_params']}), "
                 f"until E - E_m < {spec['swish_energy_stop']} (E_min - E_m) (at most {spec['swish_events']} events): grazings, their energy, the event after which E < E_min",
        expected="each run starts with a grazing, E falls below E_min after finitely many events, every grazing "
                 "(or sticky onset) has E >= E_min and none follows the fall below E_min",
        measured=f"{int(started.sum())}/{started.size} start with a grazing; grazings per run "
                 f"{runs['n_graze'].values.tolist()}; E(0)/E_min (excess over E_m) up to "
                 f"{float(runs['e0'].max()):.3g}; E < E_min after events {first_below.tolist()} "
                 f"(-1: not within the run); min (E - E_m)/(E_min - E_m) at a grazing {e_low:.6g}; "
                 f"runs with a grazing after E < E_min: {int(after.sum())}",
        tolerance=f"exact counts; energy ratio >= 1 - {tol:g} (rounding of E - E_m for float64 states)",
        verdict=judge(ok))


@claim(CLAIMS, "classifier-switch", SELF_TEST, SUBJECT,
       falsifier=Falsifier("the scan's window v_tol 100 x too large (xn = 1000 x the documented 4 eps scale): the claim "
                           "resolves v_tol to the scan's spacing, a factor 32 on 5 points over 6 decades, 1.8 on the "
                           "config's 25 (tests/checks/test_contact_non_generic.py: v_tol 22 x flips it there)",
                           patch=lambda: _window_wide(1000.0)))
def classifier_switch(m, spec) -> Verdict:
    scan = m.scan
    r, k = scan["ratios"], scan["kinds"]
    tangential_low = bool(np.all(k[r <= 0.25] == STICKY_START))
    impact_high = bool(np.all(k[r >= 4.0] == IMPACT))
    switch = r[np.flatnonzero(k == IMPACT)[0]] if np.any(k == IMPACT) else np.nan
    return Verdict(
        claim="The classifier calls a contact tangential exactly below its rounding window v_tol",
        paper_ref="events.py docstring (approximation at the rounding level); eq. sticky-condition",
        computed=f"arrival speed v = ratio * v_tol on the sticky line (gamma = {scan['gamma']}, mu = {scan['mu']}, "
                 f"alpha = {scan['alpha']:.3g}), v_tol = {scan['v_tol']:.3g}, backward flight T = {scan['T']:.3g}",
        expected="sticky_start for v <= v_tol/4, impact for v >= 4 v_tol",
        measured=f"sticky for all ratios <= 1/4: {tangential_low}; impact for all ratios >= 4: {impact_high}; "
                 f"first impact at ratio {switch:.3g}",
        tolerance="factor 4 either side: v_tol is recomputed here from the scale of eq. (F) at T, the simulator "
                  "evaluates it at its own (rounding-shifted) contact point",
        verdict=judge(tangential_low and impact_high))


@claim(CLAIMS, "nowhere-dense", IDENTITY, SUBJECT,
       why_identity="a topological statement about a set of zero measure: no finite sample of states or runs can "
                    "contradict (or show) it, so the row records that it is not checkable")
def nowhere_dense(m, spec) -> Verdict:
    return Verdict(
        claim="Nowhere density of the anomalous set",
        paper_ref="thm:contact-non-generic (nowhere dense)",
        computed="-",
        expected="every neighbourhood of a generic state contains no anomalous state",
        measured="a topological property of a zero-measure set; a finite sample cannot test it",
        tolerance="-",
        verdict=NOT_CHECKABLE)


def _dataset(m, spec: dict) -> xr.Dataset:
    mc, sticky, graze, scan, tl = m.mc, m.sticky, m.graze, m.scan, m.tails
    lo, hi = tl.lo, tl.hi
    n_mc = len(mc["gamma"])
    data = xr.Dataset(
        {
            "mc_gamma": variable("sample", mc["gamma"], "gamma of the Monte-Carlo sample"),
            "mc_mu": variable("sample", mc["mu"], "mu of the Monte-Carlo sample"),
            "mc_regime": variable("sample", mc["regime"].astype(np.int8), "damping regime", flag_values=[0, 1, 2],
                            flag_meanings="under_damped critically_damped over_damped"),
            "mc_energy_excess": variable("sample", mc["dE"], "initial E - E_m"),
            "mc_count": variable(("sample", "kind"), mc["counts"], "number of events of each kind"),
            "mc_min_ratio": variable("sample", mc["min_ratio"], "smallest |Xdot_n| / launch speed of its flight"),
            "mc_min_margin": variable("sample", mc["min_margin"], "smallest |Xdot_n| / v_tol (classifier window)"),
            "tail_ratio": variable("rank", mc["tail_ratio"], "ranked smallest |Xdot_n| / launch speed over the sample",
                                   comment="at the upper edge of its histogram bin (sweep contact-monte-carlo)"),
            "tail_margin": variable("rank", mc["tail_margin"], "ranked smallest |Xdot_n| / v_tol over the sample",
                                    comment="at the upper edge of its histogram bin (sweep contact-monte-carlo)"),
            "st_gamma": variable("onset", sticky["gamma"], "gamma of the constructed sticky onset"),
            "st_mu": variable("onset", sticky["mu"], "mu of the constructed sticky onset"),
            "st_alpha": variable("onset", sticky["size"], "alpha_s = 4 gamma mu - Ydot_s of the onset"),
            "st_T": variable("onset", sticky["T"], "backward flight time T"),
            "st_x0": variable("onset", sticky["x0"], "height of the backward-evolved start state"),
            "st_t_first": variable("onset", sticky["t_first"], "time of the first simulated event"),
            "st_first_kind": variable("onset", sticky["first_kind"], "kind of the first simulated event",
                                flag_values=list(range(len(KIND_NAMES))), flag_meanings=" ".join(KIND_NAMES)),
            "st_window": variable("onset", sticky["window"], "classifier time window min(delta2, delta3) at the onset"),
            "st_jerk": variable("onset", sticky["jerk"], "x''' at the onset"),
            "gr_gamma": variable("graze", graze["gamma"], "gamma of the constructed grazing"),
            "gr_mu": variable("graze", graze["mu"], "mu of the constructed grazing"),
            "gr_acc": variable("graze", graze["size"], "x'' at the grazing"),
            "gr_T": variable("graze", graze["T"], "backward flight time T"),
            "gr_t_first": variable("graze", graze["t_first"], "time of the first simulated event"),
            "gr_first_kind": variable("graze", graze["first_kind"], "kind of the first simulated event",
                                flag_values=list(range(len(KIND_NAMES))), flag_meanings=" ".join(KIND_NAMES)),
            "gr_window": variable("graze", graze["window"], "classifier time window min(delta2, delta3) at the grazing"),
            "scan_ratio": variable("scan", scan["ratios"], "arrival speed / v_tol"),
            "scan_kind": variable("scan", scan["kinds"], "kind of the simulated contact", flag_values=list(range(len(KIND_NAMES))),
                            flag_meanings=" ".join(KIND_NAMES)),
            "scan_recorded_speed": variable("scan", scan["speeds"], "|xdot| recorded after the contact"),
        },
        coords={"kind": ("kind", np.array(KIND_NAMES, dtype=object), {"long_name": "event kind", "units": "1"})},
        attrs={"check": NAME, "n_samples": n_mc, "events_per_sample": mc["events"], "seed": mc["seed"],
               "n_contacts": mc["n_contacts"], "tail_exponent_ratio": tl.p_ratio, "tail_prefactor_ratio": tl.c_ratio,
               "tail_exponent_ratio_err": tl.p_ratio_err, "tail_exponent_margin": tl.p_margin,
               "expected_in_window": tl.expected_in_window,
               "scan_v_tol": scan["v_tol"], "scan_gamma": scan["gamma"], "scan_mu": scan["mu"],
               "tail_fit_lo": int(lo), "tail_fit_hi": int(hi)},
    )
    return data


# --------------------------------------------------------------------------- plot

def plot(ds: xr.Dataset, spec: dict, outputs) -> None:
    from ..figures.common import WIDTH, plt, save

    fig, axs = plt.subplots(2, 2, figsize=(WIDTH, 5.6))
    # (a) low tails
    ax = axs[0, 0]
    for var, lab, c in (("tail_ratio", r"$|\dot X_n|/v_\mathrm{ref}$", "C0"), ("tail_margin", r"$|\dot X_n|/v_\mathrm{tol}$", "C1")):
        t = ds[var].values  # ranked, each at the upper edge of its histogram bin
        edge = np.unique(t)
        ax.loglog(edge, np.searchsorted(t, edge, side="right"), "o-", ms=3, lw=0.6, color=c, label=lab)
    hi = int(ds.attrs["tail_fit_hi"])
    t = ds["tail_ratio"].values
    p, C = ds.attrs["tail_exponent_ratio"], ds.attrs["tail_prefactor_ratio"]  # the fit of the verdicts
    rr = np.geomspace(t[0], t[min(hi, t.size) - 1], 20)
    ax.loglog(rr, C * rr**p, "k-", lw=0.7, label=r"fit $N\propto r^{%.2f}$" % p)
    ax.axvline(1.0, color="C1", ls=":", lw=0.8)
    ax.set_xlabel(r"ratio $r$")
    ax.set_ylabel(r"impacts with ratio $< r$ (at the bin edges)")
    n_anom = int(ds["mc_count"].values[:, 1:3].sum())
    ax.set_title("(a) Monte-Carlo low tails: {:,} runs,\n{:,} impacts, {} sticky/grazing events"
                 .format(ds.sizes["sample"], int(ds.attrs["n_contacts"]), n_anom), fontsize=8)
    ax.legend(fontsize=6.5, loc="lower right")
    # (b) per-sample minima vs energy, in units of the anomaly threshold E_min - E_m (Lemma Min-sticky-energy)
    ax = axs[0, 1]
    mu = ds["mc_mu"].values
    e = ds["mc_energy_excess"].values / (2.0 * ds["mc_gamma"].values ** 2 / (1.0 + 2.0 * mu**2))
    for reg, c, lab in ((0, "C0", r"$\mu<1$"), (1, "C2", r"$\mu=1$"), (2, "C3", r"$\mu>1$")):
        s = ds["mc_regime"].values == reg
        ax.loglog(e[s], ds["mc_min_ratio"].values[s], ".", ms=2, color=c, label=lab)
    ax.axvline(1.0, color="k", ls="--", lw=0.7)
    ax.set_xlabel(r"$(E(0)-E_m)/(E_{min}-E_m)$")
    ax.set_ylabel(r"$\min_n |\dot X_n|/v_\mathrm{ref}$ per run")
    ax.set_title("(b) smallest contact speed per run\n(left of dashed: no anomaly possible)", fontsize=8)
    ax.legend(fontsize=6.5, loc="lower left", markerscale=3)
    # (c) constructed contacts
    ax = axs[1, 0]
    markers = {STICKY_START: ("o", "C2", "sticky_start"), GRAZING: ("s", "C0", "grazing"), IMPACT: ("x", "C3", "impact")}
    for pre, size, lab_x in (("st", "st_alpha", "onset"), ("gr", "gr_acc", "graze")):
        xval = ds[size].values / ds[f"{pre}_gamma"].values
        err = np.abs(ds[f"{pre}_t_first"].values - ds[f"{pre}_T"].values) / ds[f"{pre}_window"].values
        kinds = ds[f"{pre}_first_kind"].values
        for kd, (mk, c, name) in markers.items():
            s = kinds == kd
            if s.any():
                ax.loglog(xval[s], np.maximum(err[s], 1e-6), mk, ms=3 if pre == "st" else 2.5, color=c,
                          mfc="none" if pre == "gr" else c,
                          label=f"{'onset' if pre == 'st' else 'grazing'} -> {name}")
    ax.axhline(2.0, color="k", ls="--", lw=0.7)
    ax.set_ylim(top=6.0)
    ax.set_xlabel(r"$\alpha_s/\gamma$ (onsets), $\ddot x/\gamma$ (grazings)")
    ax.set_ylabel(r"$|t_1 - T|$ / classifier window")
    ax.set_title("(c) constructed anomalous contacts (dashed: tolerance)", fontsize=8)
    ax.legend(fontsize=6, loc="upper center", ncol=2)
    # (d) speed scan
    ax = axs[1, 1]
    r, k = ds["scan_ratio"].values, ds["scan_kind"].values
    for kd, (mk, c, name) in markers.items():
        s = k == kd
        if s.any():
            ax.semilogx(r[s], k[s], mk, color=c, ms=4, label=name)
    ax.axvline(1.0, color="k", ls=":", lw=0.8)
    ax.set_yticks([0, 1, 2])
    ax.set_yticklabels(["impact", "grazing", "sticky"])
    ax.set_ylim(-0.5, 2.5)
    ax.set_xlabel(r"arrival speed $v / v_\mathrm{tol}$")
    ax.set_ylabel("classified as")
    ax.set_title(r"(d) sticky-line arrival, $\gamma=%g$, $\mu=%g$" % (ds.attrs["scan_gamma"], ds.attrs["scan_mu"]),
                 fontsize=8)
    fig.suptitle(f"Check {NAME}: Theorem contact-non-generic (dimensionless units)", fontsize=9)
    fig.tight_layout()
    save(fig, outputs)


CHECK = Check(NAME, Measurements, tuple(CLAIMS), plot,
              title="Theorem contact-non-generic: zero-speed contacts are non-generic",
              experiments=(Experiment("swish-runs", SWISH_KEYS, swish_runs),))

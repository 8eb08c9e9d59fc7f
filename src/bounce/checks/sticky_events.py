"""Theorem Finite-number-sticky-ev exercised: runs with several sticky events, and the count bound of its proof.

The proof bounds the count by energy: every finite sticky event dissipates at least D > 0 (Lemma
td-ts-bound and the expansion of its proof), and no sticky event starts below E_min (Lemma
Min-sticky-energy), so a run whose first sticky onset has energy E(s_1) has at most

    N <= 1 + (E(s_1) - E_min) / D,

D the least energy (mu/2) int_{t_s}^{t_d} ydot^2 (eq. energy-dissipation with xi' = ydot/2 in contact)
that a finite sticky phase with onset energy in [E_min, E(s_1)] dissipates.  D is computed from the
sticky phase's closed form over a grid of onsets alpha_s in (eps*, alpha_max]
(:func:`bounce.analysis.theory.least_sticky_dissipation`, the bound :func:`bounce.analysis.theory.sticky_count_bound`): a grid
minimum is at least the infimum, so the bound computed is never looser than the proof's.  This group holds the
theorem's bound; claim group sticky-lemmas counts sticky events in the Monte Carlo and eq. sticky-ic's family.

Runs with several sticky events.  For mu > 0 a second sticky onset after a detach is a codimension-2
event in the parameters (gamma scales out: three conditions x = x' = x'' = 0 at the landing on the two
parameters (alpha_s, mu)); Newton from a scan found none, and the mu = 0 solution below is isolated
(its Jacobian is regular), so the constructed orbit is the conservative one:

* mu = 0 (outside the theorem, which assumes dissipation): every sticky phase is symmetric (s = R(d),
  R the time reversal ydot -> -ydot) and a flight from the detach state d with psi' = xi' = 0 at its
  midpoint t_h lands at R(d), a sticky onset.  With x = x' = 0, eta = 2 gamma, xi' = a at d: psi' = a - gamma t,
  xi' = a cos t - gamma sin t (xi = gamma cos t + a sin t), so t_h = a/gamma with tan(u) = u, u = a/gamma.
  The orbit onset -> sticky -> detach -> flight of 2u -> onset is periodic: infinitely many sticky events,
  which the theorem's bound allows only because D = 0 at mu = 0.  The exact (mpmath) flight is checked to
  land on a sticky onset; the simulator, started at the onset, is run for ``events`` events (<= 20: a
  short probe), and follows the unstable orbit for as many sticky events as rounding allows.
* mu > 0 in ``mu``: a run has one sticky event (a second is non-generic), so the bound is tested where it is
  tightest for one.  A detach state is itself on the sticky line (F = 0, x'' = 0), so E(t_d) >= E_min and a
  run's own onset gives 1 + (E(s_1) - E_min)/D >= 2: the bound is 2 exactly when the sticky event dissipates D
  and detaches at E_min.  Each run starts at the onset of least dissipation (alpha_D, among the onsets with E
  at most that of the conservative onset Ydot_s = -2 u gamma): its bound is 2 to ~1e-4, its sticky event
  dissipates D itself, so a damping a few % low (a dissipation below D) or a third sticky event refutes it.
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import xarray as xr
from mpmath import findroot, mp, mpf, tan

from ..analysis import reference
from ..analysis import theory
from ..kinds import DETACH, IMPACT, STICKY_START
from ..exact.events import STICKY_ONSET, contact_window
from ..model import Parameters, State
from ..simulate import simulate
from .base import BEYOND, PAPER, Check, Falsifier, Verdict, judge, recorded, variable

NAME = "sticky-events"


def symmetric_flight_root() -> float:
    """u > 0, the first positive root of tan u = u (the flight's half time in units of 1 at mu = 0), to 1e-30."""
    with mp.workdps(40):
        return findroot(lambda u: tan(u) - u, mpf("4.4934"))


def onset_run(gamma: float, mu: float, ydot_s: float, events: int):
    """The run from the sticky onset with lower-mass speed Ydot_s (eq. sticky-ic, eps = 0) for ``events`` events."""
    p = Parameters(gamma, mu)
    return simulate(p, State.sticky_ic(p, eps=0.0, ydot0=ydot_s), max_events=events)


def _damping_low():
    """Falsifier patch of sticky-count-bound: the runs simulated with mu 2 % below the mu of their bound."""
    real = onset_run
    return {"onset_run": lambda gamma, mu, ydot_s, events: real(gamma, 0.98 * mu, ydot_s, events)}


def measure(spec: dict, inputs=()) -> SimpleNamespace:
    rows: dict = {}
    gamma = float(spec["gamma"])
    n_events = int(spec["events"])
    u = symmetric_flight_root()
    a = float(u) * gamma  # xi' at the detach, = -xi' at the onset
    ydot_s = -2 * a

    # ---------------------------------------------------------------- mu = 0: the exact periodic sticky orbit
    with mp.workdps(40):
        land = reference.free_flight(mpf(gamma), 0, 0, 0, u * mpf(gamma), 2 * mpf(gamma), 2 * u)
        xdd_land = land.eta - 2 * mpf(gamma)  # x'' = eta - 2 gamma + 2 mu xi' at x = 0
        mid = [reference.free_flight(mpf(gamma), 0, 0, 0, u * mpf(gamma), 2 * mpf(gamma), 2 * u * k / 16).x
               for k in range(1, 16)]
        exact = (float(abs(land.x) / gamma), float(abs(land.u) / gamma), float(abs(xdd_land) / gamma),
                 float(min(mid) / gamma), float((land.a + u * mpf(gamma)) / gamma))
    tr0 = onset_run(gamma, 0.0, ydot_s, n_events)
    starts0 = np.flatnonzero(tr0.kind == STICKY_START)
    t_c0 = theory.t_c(gamma, 0.0, ydot_s)
    period = t_c0 + 2 * float(u)
    returns = np.diff(tr0.t[starts0]) - period  # empty with fewer than two sticky events
    off_period = f"{np.max(np.abs(returns)):.2g}" if returns.size else "- (no return)"
    e_drift = float(np.max(np.abs(tr0.energy_excess - tr0.energy_excess[0])) / tr0.energy_excess[0])
    # the classifier's windows at the landing (bounce.exact.events): its time is hidden within delta3, and the onset is
    # put on the sticky line, moving x'' by up to (STICKY_ONSET x'''^2 xn)^(1/3), i.e. z by twice that and E by z/4 times it
    jerk = float(u) * gamma  # |x'''| = |Ydot_s - 4 gamma mu|/2 at the onset
    xn, _, _, delta3 = contact_window(max(2 * a * float(u), 2 * gamma * float(u) ** 2), 0.0, jerk)
    e_window = 4 * gamma * (STICKY_ONSET * jerk**2 * xn) ** (1 / 3) / 2 / float(tr0.energy_excess[0])
    ok0 = (exact[0] < 1e-30 and exact[1] < 1e-30 and exact[2] < 1e-30 and exact[3] > 0 and abs(exact[4]) < 1e-30
           and starts0.size >= 2 and bool(np.all(np.abs(returns) <= 2 * delta3)) and e_drift <= e_window)
    rows["conservative-sticky-cycle"] = Verdict(
        claim="Without dissipation (mu = 0, outside the theorem) a solution can have infinitely many sticky events: "
              "the periodic orbit onset -> sticky phase -> detach -> flight of 2u (tan u = u) -> onset",
        paper_ref="thm:Finite-number-sticky-ev (its hypothesis mu > 0); lem:Min-sticky-energy",
        computed=f"u = {float(u):.15f}; the flight from the detach (x = x' = 0, xi' = u gamma, eta = 2 gamma), gamma = "
                 f"{gamma}, in mpmath (40 digits) at t = 2u and at 15 interior points; the simulator from the onset "
                 f"Ydot_s = -2 u gamma for {n_events} events",
        expected="landing with x = x' = x'' = 0 and xi' = -u gamma (the onset again), x > 0 in flight; the simulator's "
                 f"sticky onsets every t_c + 2u = {period:.10f}, energy constant",
        measured=f"landing |x|, |x'|, |x''| = {exact[0]:.1g}, {exact[1]:.1g}, {exact[2]:.1g} gamma, least interior "
                 f"x = {exact[3]:.4g} gamma, xi' + u gamma = {exact[4]:.1g}; simulator: {starts0.size} sticky events "
                 f"in {len(tr0)} events ({', '.join(tr0.kind_names[:6])}, ...), returns off the period by "
                 f"{off_period}, energy drift {e_drift:.2g} (relative); the orbit is unstable, "
                 "so rounding ends the cycle after the events shown",
        tolerance=f"1e-30 gamma (mpmath at 40 digits); returns within 2 delta3 = {2 * delta3:.2g} and energy within "
                  f"{e_window:.2g} relative: the classifier's time and x'' windows at a sticky landing (bounce.exact.events)",
        verdict=judge(ok0))

    # ---------------------------------------------------------------- mu > 0: the count against its bound
    counts, bounds, D_all, drops_min = [], [], [], []
    per_mu = {}
    for mu in (float(m) for m in spec["mu"]):
        excess_c = ydot_s**2 / 4 + (4 * gamma - 2 * mu * ydot_s) ** 2 / 8  # the conservative onset (eq. sticky-energy)
        alpha_1 = theory.least_sticky_dissipation(gamma, mu, excess_c, int(spec["n_alpha"]))[1]
        tr = onset_run(gamma, mu, 4 * gamma * mu - alpha_1, n_events)
        starts = np.flatnonzero(tr.kind == STICKY_START)
        detaches = np.flatnonzero(tr.kind == DETACH)
        excess_1 = float(tr.energy_excess[starts[0]])
        emin_excess = theory.min_sticky_energy(gamma, mu) - theory.E_min(gamma)
        try:
            D, alpha_D, alphas, _ = theory.least_sticky_dissipation(gamma, mu, excess_1, int(spec["n_alpha"]))
        except ValueError:  # every admissible onset sticks for ever: no finite sticky event has E(t_s) <= E(s_1)
            D, alpha_D, alphas = math.nan, math.nan, np.array([])
        bound = theory.sticky_count_bound(gamma, mu, excess_1, D)
        drops = [float(tr.energy_excess[s] - tr.energy_excess[d]) for s in starts for d in detaches[detaches > s][:1]]
        onset_ok = bool(np.all(tr.energy_excess[starts] >= emin_excess * (1 - 1e-12)))
        # D = nan (bound nan): the closed form admits no finite sticky phase at E <= E(s_1): not reproduced
        ok = starts.size <= bound and all(dr >= D * (1 - 1e-12) for dr in drops) and onset_ok
        counts.append(starts.size)
        bounds.append(bound)
        D_all.append(D)
        drops_min.append(min(drops) if drops else math.nan)
        per_mu[f"mu={mu:g}"] = Verdict(
            claim="Any solution has at most finitely many sticky events: N <= 1 + (E(s_1) - E_min)/D, D the least "
                  "energy a finite sticky event dissipates",
            paper_ref="thm:Finite-number-sticky-ev (its proof), lem:Min-sticky-energy, lem:td-ts-bound",
            computed=f"the onset of least dissipation alpha_s = {alpha_1 / gamma:.6g} gamma (gamma = {gamma}, mu = "
                     f"{mu:g}; among onsets with E <= E(-2 u gamma)) simulated for {n_events} events; D from the "
                     f"closed-form sticky phase over {alphas.size} onsets alpha_s in (eps*, alpha_max] with "
                     "E(t_s) <= E(s_1) (eq. energy-dissipation: (mu/2) int ydot^2)",
            expected="sticky events <= bound (here ~2, its least value for a run's own onset: the detach is on the "
                     "sticky line, so E(t_d) >= E_min); each finite sticky event dissipates >= D (here = D: the "
                     "run's onset is the minimiser); onsets at E >= E_min",
            measured=f"{starts.size} sticky events ({', '.join(tr.kind_names[:4])}, ...; stop {tr.stop_reason}); "
                     f"E(s_1) - E_m = {excess_1 / gamma**2:.6g} gamma^2, E_min - E_m = {emin_excess / gamma**2:.6g} "
                     f"gamma^2, D = {D / gamma**2:.4g} gamma^2 (at alpha_s = {alpha_D / gamma:.4g} gamma; D/mu = "
                     f"{D / mu / gamma**2:.4g} gamma^2: at a fixed E(s_1) the bound grows like 1/mu), bound {bound:.6g}; dissipated per "
                     f"sticky event {[round(d / gamma**2, 6) for d in drops]} gamma^2, relative to D - 1: "
                     f"{[float(f'{d / D - 1:.2g}') for d in drops]}"
                     + ("" if math.isfinite(D) else "; no onset with E <= E(s_1) has a finite sticky phase at this mu "
                        "(closed form), yet the run detaches"),
            tolerance="exact count; dissipation 1e-12 relative (the closed form's energy identity and the simulator's "
                      "energy records agree to ~1e-14); onset energies 1e-12 relative",
            verdict=judge(ok))
    rows["sticky-count-bound"] = per_mu
    mus = np.array([float(m) for m in spec["mu"]])
    data = xr.Dataset({
        "mu": variable("run", mus, "damping mu of the run"),
        "sticky_count": variable("run", np.array(counts), "sticky events in the run"),
        "count_bound": variable("run", np.array(bounds), "1 + (E(s_1) - E_min)/D (proof of thm:Finite-number-sticky-ev)"),
        "least_dissipation": variable("run", np.array(D_all) / gamma**2, "D / gamma^2"),
        "conservative_sticky_times": variable("cycle_onset", tr0.t[starts0], "sticky onsets of the mu = 0 run"),
        "conservative_times": variable("cycle_event", tr0.t, "events of the mu = 0 run"),
        "conservative_kind": variable("cycle_event", tr0.kind.astype(np.int8), "event kind (0 impact, 2 sticky start, "
                                      "3 detach)"),
    }, attrs={"check": NAME, "gamma": gamma, "period": period, "u": float(u)})
    return SimpleNamespace(rows=rows, data=data)


CLAIMS: list = []
recorded(CLAIMS, "conservative-sticky-cycle", BEYOND, "thm:Finite-number-sticky-ev",
         falsifier=Falsifier("the flight's half time u = 4.5, 0.15 % off the root 4.4934 of tan u = u: the exact flight "
                             "misses the sticky onset", patch=lambda: {"symmetric_flight_root": lambda: mpf("4.5")}))
recorded(CLAIMS, "sticky-count-bound", PAPER, "thm:Finite-number-sticky-ev",
         falsifier=Falsifier("each run simulated with mu 2 % below the mu its bound is computed for: its sticky event "
                             "dissipates ~2 % less than D", patch=_damping_low))


def plot(ds: xr.Dataset, spec: dict, outputs) -> None:
    from ..figures.common import WIDTH, plt, save, tex_num

    fig, axs = plt.subplots(1, 2, figsize=(WIDTH, 3.0))
    ax = axs[0]
    t, kind = ds["conservative_times"].values, ds["conservative_kind"].values
    lanes = {STICKY_START: ("sticky start", "C3", "v"), DETACH: ("detach", "C2", "^"), IMPACT: ("impact", "C0", "|")}
    for row, (k, (lab, c, mk)) in enumerate(lanes.items()):
        ax.plot(t[kind == k], np.full(np.count_nonzero(kind == k), row), mk, color=c, ms=7)
    ax.set_yticks(range(len(lanes)), [lab for lab, _, _ in lanes.values()])
    ax.set_ylim(-0.6, len(lanes) - 0.4)
    ax.invert_yaxis()
    P = ds.attrs["period"]
    for j in range(int(t.max() // P) + 1):
        ax.axvline(j * P, color="0.6", lw=0.6, ls=":")
    impacts = t[kind == IMPACT]
    if impacts.size:
        ax.annotate(f"{impacts.size} impacts within $\\Delta t={tex_num(np.ptp(impacts), 2)}$", (impacts[0], 2),
                    xytext=(0.6, 0.16), textcoords="axes fraction", fontsize=6, ha="center", va="center",
                    arrowprops={"arrowstyle": "->", "lw": 0.6, "color": "0.3"})
    ax.text(0.02, 0.03, f"dotted: multiples of the period $t_c+2u={P:.4f}$", transform=ax.transAxes, fontsize=6)
    ax.set_xlabel(r"$t$  [$\sqrt{m/2k}$]")
    n_sticky = int(np.count_nonzero(kind == STICKY_START))
    ax.set_title(f"(a) $\\mu=0$: {n_sticky} sticky events, then\nrounding leaves the unstable cycle", fontsize=8)
    ax = axs[1]
    mu, counts = ds["mu"].values, ds["sticky_count"].values
    ax.semilogx(mu, ds["count_bound"].values, "s-", color="C1", label="bound $1+(E(s_1)-E_{min})/D$")
    ax.semilogx(mu, counts, "o", color="C0", label="sticky events in the run")
    ax.set_ylim(0, 1.6 * max(float(np.nanmax(ds["count_bound"].values)), float(counts.max())))
    ax.yaxis.get_major_locator().set_params(integer=True)
    ax.set_xlabel(r"$\mu$")
    ax.set_ylabel("sticky events")
    per_run = "one sticky event" if counts.max() == counts.min() == 1 else f"{counts.min()}-{counts.max()} sticky events"
    ax.set_title(f"(b) thm. Finite-number-sticky-ev ($\\gamma={tex_num(ds.attrs['gamma'])}$):\n{per_run} per run, "
                 "and its bound", fontsize=8)
    ax.legend(fontsize=6, loc="upper left")
    fig.suptitle(f"Check {NAME}: (a) the mu = 0 cycle, a sticky event every period until rounding ends it; (b) a mu > 0 "
                 "run has one\n(a second onset is codimension 2), against the proof's bound, ~2 at the onset of least "
                 "dissipation",
                 fontsize=8)
    fig.tight_layout()
    save(fig, outputs)


CHECK = Check(NAME, measure, tuple(CLAIMS), plot, title="Sticky events counted: several in one run, and the bound")

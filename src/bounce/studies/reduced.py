"""Reduced models against the dimer: where each one stops, and the cheapest model per pipeline scene.

:func:`reduced_vs_dimer` -- the same drop with each rigid-ball model of
:mod:`bounce.methods.rigid` and with the exact dimer:

* time to rest: the first impact after which the energy above the rest state,
  relative to its initial value, is below ``threshold`` (dimer: (E - E_m)/(E_0 - E_m),
  eqs. ``tot-mech-energy``, ``Emin``; rigid ball: u_n^2/u_0^2, E = u^2/2 above rest);
  and the model's own end: inelastic collapse time t_inf (constant r, 1/5 law),
  "permanent contact" (time-of-contact model: first elastic impact), none (our-r);
* r_n per macroscopic bounce: the dimer's r_n = f_{n+1}/f_n with f_n = tau_{2n}
  (eqs. ``Falcon-rest-coeff``, ``my-time-of-flight``: impacts in pairs, the double
  impact); for the rigid models each impact is a macroscopic bounce, f_n = tau_n;
* impact counts (dimer impacts are micro-impacts: two per macroscopic bounce in
  the double-impact regime).

:func:`least_model` -- for each pipeline scene (config ``scenes``) and the
quantities its figures show (``qoi``, each with a tolerance), the cheapest method
whose error against the exact solver is within the tolerance:

* ``y_t``: y(t) on a time window (fig. rigid-fall), max |y - y_exact| in L;
* ``r_n``: the restitution coefficients of fig. rest-coeff, max |r_n - r_n,exact|;
* ``impact_states``: the states after each contact (figs. very_rigid_poincare*),
  max relative error of Xdot_n; the method must also deliver Y_n, Ydot_n at every
  impact (exact solver, contact switch);
* ``asymptotic_laws``: n tau_n mu/3 and n Xdot_n mu/(3 gamma) at log-spaced n (fig.
  asymptotic-laws), max absolute error.

Candidates: the exact solver; the contact switch with the *largest* delta of the
ladder that meets every tolerance; the asymptotic map with the *smallest* n0 of
its ladder that does; the four rigid-ball models with their default settings
(both flight rules of eq. ``our-r``).  Cost: CPU time (process time, best of
``repeats``); a method less than 25 % cheaper than the exact solver is a tie
(timing noise), broken in favour of the exact solver.  Beyond the predictability horizon of a chaotic transient
(:mod:`bounce.studies.horizon`) the float64 exact solution is itself only one
member of a family of equally valid trajectories; a pointwise tolerance there
can be met only by a method that reproduces the float64 solver bit for bit.
A contact switch that never switches, or an asymptotic map whose n0 is beyond
the scene's impacts, *is* the exact solver and is not counted as a reduced model.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from ..analysis.theory import T_xi
from ..kinds import IMPACT
from ..methods import contact_switch, exact, rigid
from ..model import Deviations, InputError, Parameters
from ..paths import scene_file
from ..sampling import sample_trajectory
from ..simulate import simulate
from .base import Study

#: CPU ratios below this count as a tie, broken in favour of the exact solver
TIE = 1.25

RIGID_MODELS = (
    ("rigid-constant-r", rigid.run_constant, {}),
    ("rigid-fifth", rigid.run_fifth, {}),
    ("rigid-our-r", rigid.run_our_r, {"flight": "rigid"}),
    ("rigid-our-r/dimer-flight", rigid.run_our_r, {"flight": "dimer"}),
    ("time-of-contact", rigid.run_time_of_contact, {}),
)


# --------------------------------------------------------------------------- reduced vs dimer


def _falcon_r(t_impacts: np.ndarray, paired: bool, n_max: int) -> np.ndarray:
    """r_n = f_{n+1}/f_n, n = 1..n_max; tau_n = t_{n+1} - t_n (tau_0 the release), f_n = tau_{2n} if paired."""
    tau = np.diff(np.concatenate([[0.0], t_impacts]))
    f = tau[0::2] if paired else tau
    r = np.full(n_max, np.nan)
    n = np.arange(1, n_max + 1)
    ok = n + 1 < f.size
    r[ok] = f[n[ok] + 1] / f[n[ok]]
    return r


#: a dimer contact is a double impact while its inner flight is within this fraction of T_xi
#: (the criterion of check restitution, its default ``double_band``)
DOUBLE_BAND = 0.25


def _double_impacts(t_impacts: np.ndarray, mu: float) -> int:
    """Leading contacts m = 1, 2, ... that are double impacts: inner flight tau_{2m-1} within DOUBLE_BAND of
    T_xi = pi/sqrt(1 - mu^2) (eq. char-times); beyond them f_n = tau_{2n} is not a macroscopic flight."""
    tau = np.diff(np.concatenate([[0.0], t_impacts]))
    inner = tau[1::2] / T_xi(mu) if mu < 1.0 else np.zeros(0)
    ok = np.abs(inner - 1.0) <= DOUBLE_BAND
    return int(ok.size if ok.all() else np.argmin(ok))


def _thin(x: np.ndarray, y: np.ndarray, k: int) -> tuple[np.ndarray, np.ndarray]:
    if x.size <= k:
        return x, y
    idx = np.unique(np.concatenate([np.arange(min(200, x.size)), np.geomspace(1, x.size, k).astype(np.int64) - 1]))
    return x[idx], y[idx]


def reduced_vs_dimer(spec: dict) -> xr.Dataset:
    """Each rigid model against the dimer for each drop of ``spec`` (config ``reduced.vs_dimer``)::

        {"drops": {"underdamped": {"gamma": 0.01, "mu": 0.01, "psi0": 6.0},
                   "rest-coeff": {"gamma": 1e-5, "mu": 0.01, "psi0": 0.25}},
         "threshold": 1e-3, "max_events": 2000000, "t_max": 1e5, "n_bounces": 100, "curve_points": 600}
    """
    drops = list(spec["drops"])
    models = ["dimer"] + [m[0] for m in RIGID_MODELS]
    th = float(spec["threshold"])
    max_events = int(spec["max_events"])
    t_max = float(spec["t_max"])
    nb = int(spec["n_bounces"])
    kc = int(spec["curve_points"])
    shape = (len(drops), len(models))
    t_rest = np.full(shape, np.nan)
    n_rest = np.full(shape, -1, dtype=np.int64)
    t_end_model = np.full(shape, np.nan)
    n_total = np.zeros(shape, dtype=np.int64)
    r_n = np.full(shape + (nb,), np.nan)
    t_b = np.full(shape + (nb,), np.nan)
    curve_t = np.full(shape + (kc + 200,), np.nan)
    curve_e = np.full(shape + (kc + 200,), np.nan)
    end_kind = np.empty(shape, dtype=object)
    doubles = np.zeros(len(drops), dtype=np.int64)
    rigid.warm_up()
    for i, name in enumerate(drops):
        d = spec["drops"][name]
        g, m, psi0 = float(d["gamma"]), float(d["mu"]), float(d["psi0"])
        p = Parameters(g, m)
        ini = Deviations(x=psi0, xdot=0.0, xidot=0.0, eta=g)
        for j, model in enumerate(models):
            if model == "dimer":
                tr = simulate(p, ini, max_events=max_events, t_max=t_max)
                imp = tr.kind == IMPACT
                t = tr.t[imp]
                e0 = 0.5 * g * g + g * psi0  # E(0) - E_m
                e = tr.energy_excess[imp] / e0
                paired = True
                end_kind[i, j] = "none (no collapse; E -> E_m as t -> inf)"
                doubles[i] = _double_impacts(t, m)
            else:
                run, setting = dict((mm[0], (mm[1], mm[2])) for mm in RIGID_MODELS)[model]
                res = run(p, ini, setting, max_events=max_events, t_max=t_max)
                t = res.t
                e = res.extra["energy"] / (0.5 * res.extra["u_0"] ** 2)
                paired = False
                if res.failure == "collapse":
                    t_end_model[i, j] = res.t_end
                    end_kind[i, j] = "inelastic collapse"
                elif model == "time-of-contact" and np.isfinite(res.extra["t_contact"]):
                    t_end_model[i, j] = res.extra["t_contact"]
                    end_kind[i, j] = "permanent contact (elastic micro-bounces, u* = %.3g)" % res.extra["u_contact"]
                else:
                    end_kind[i, j] = "none (bounces for ever, u_n ~ 3 gamma/(mu n))"
            n_total[i, j] = t.size
            below = np.flatnonzero(e < th)
            if below.size:
                t_rest[i, j] = t[below[0]]
                n_rest[i, j] = below[0] + 1
            if paired:
                r_n[i, j] = _falcon_r(t, paired, nb)
            else:  # r_n = u_{n+1}/u_n: the coefficient applied at impact n + 1 (= f_{n+1}/f_n for tau = 2u/gamma)
                ra = res.extra["r_n"]
                k = min(nb, ra.size - 1)
                r_n[i, j, :k] = ra[1 : k + 1]
            tb = t[0::2] if paired else t
            k = min(nb, tb.size)
            t_b[i, j, :k] = tb[:k]
            ct, ce = _thin(t, e, kc)
            curve_t[i, j, : ct.size] = ct
            curve_e[i, j, : ce.size] = ce
    dm = ("case", "model")
    u = {"units": "1"}
    return xr.Dataset(
        {
            "t_rest": (dm, t_rest, {"long_name": f"first impact time with energy above rest < {th:g} of its initial "
                                                 "value", "units": "sqrt(m/2k)"}),
            "n_rest": (dm, n_rest, {"long_name": "impacts up to t_rest (dimer: micro-impacts)", **u}),
            "t_model_end": (dm, t_end_model, {"long_name": "collapse time t_inf, or start of permanent contact "
                                                           "(time-of-contact model)", "units": "sqrt(m/2k)"}),
            "model_end": (dm, end_kind.astype(str), {"long_name": "how the model's bouncing ends"}),
            "n_impacts": (dm, n_total, {"long_name": "impacts computed (to max_events, t_max or collapse)", **u}),
            "r_n": (dm + ("bounce",), r_n, {"long_name": "dimer: r_n = f_{n+1}/f_n, f_n = tau_{2n}; rigid models: "
                                                            "r_n = u_{n+1}/u_n", **u}),
            "t_bounce": (dm + ("bounce",), t_b, {"long_name": "time of macroscopic bounce n (dimer: t_{2n-1})",
                                                 "units": "sqrt(m/2k)"}),
            "curve_t": (dm + ("k",), curve_t, {"long_name": "impact times (thinned)", "units": "sqrt(m/2k)"}),
            "curve_energy": (dm + ("k",), curve_e, {"long_name": "energy above rest / its initial value, just after "
                                                                 "each impact (thinned)", **u}),
            "double_impacts": (("case",), doubles, {
                "long_name": "leading dimer contacts that are double impacts (inner flight within "
                             f"{DOUBLE_BAND:g} T_xi of T_xi): the dimer's r_n is meaningful for n < this", **u}),
            "gamma": (("case",), [float(spec["drops"][k]["gamma"]) for k in drops], {"long_name": "gamma", **u}),
            "mu": (("case",), [float(spec["drops"][k]["mu"]) for k in drops], {"long_name": "mu", **u}),
            "psi0": (("case",), [float(spec["drops"][k]["psi0"]) for k in drops],
                     {"long_name": "psi(0)", "units": "L"}),
        },
        coords={"case": drops, "model": models, "bounce": np.arange(1, nb + 1)},
        attrs={"title": "Rigid-ball restitution models against the two-mass ball", "threshold": th,
               "t_max": t_max, "max_events": max_events, "Conventions": "CF-1.10"},
    )


def plot_reduced_vs_dimer(ds: xr.Dataset, spec: dict, outputs) -> None:
    """Energy above rest against t (left) and r_n against the macroscopic bounce (right), one row per drop.

    The dimer's r_n = f_{n+1}/f_n (f_n = tau_{2n}) is drawn only while its contacts are double
    impacts (n < ``double_impacts``): beyond, tau_{2n} is no longer a macroscopic flight and the
    ratio means nothing.  The r_n axis spans every value drawn (nothing is clipped)."""
    from ..figures.common import WIDTH, label_time, plt, save, tex_num

    drops = list(ds["case"].values)
    fig, axes = plt.subplots(len(drops), 2, figsize=(WIDTH, 2.7 * len(drops)), squeeze=False)
    styles = {"dimer": dict(color="k", lw=1.2)}
    labels = {"dimer": "two-mass ball (exact)", "rigid-constant-r": r"rigid, $r=e^{-\mu T_\xi}$",
              "rigid-fifth": r"rigid, $r=1-(u/U)^{1/5}$", "rigid-our-r": "rigid, eq. our-r",
              "rigid-our-r/dimer-flight": r"eq. our-r, $\tau=u/\gamma$ below $u_c$",
              "time-of-contact": r"time of contact, $t_c=T_\xi$"}
    bounce = ds["bounce"].values
    for i, drop in enumerate(drops):
        d = ds.sel(case=drop)
        a1, a2 = axes[i]
        paired = int(d["double_impacts"])
        drawn = []
        for j, model in enumerate(ds["model"].values):
            st = dict(styles.get(model, dict(color=f"C{j - 1}", lw=0.8)))
            st["zorder"] = 3 if model == "dimer" else 2
            ct, ce = d["curve_t"].sel(model=model).values, d["curve_energy"].sel(model=model).values
            ok = np.isfinite(ct) & (ce > 0)
            a1.semilogy(ct[ok], ce[ok], label=labels.get(model, model), **st)
            te = float(d["t_model_end"].sel(model=model))
            if np.isfinite(te):
                a1.axvline(te, ls=":", lw=0.8, color=st["color"])
            r = d["r_n"].sel(model=model).values
            keep = np.isfinite(r) & ((bounce < paired) if model == "dimer" else True)
            a2.plot(bounce[keep], r[keep], "o" if model == "dimer" else "-", ms=2.5, color=st["color"],
                    lw=st["lw"], zorder=st["zorder"])
            drawn.append(r[keep])
        drawn = np.concatenate(drawn)
        if drawn.size:
            pad = 0.05 * max(np.ptp(drawn), 0.05)
            a2.set_ylim(drawn.min() - pad, drawn.max() + pad)
        a2.axvline(paired - 0.5, color="k", lw=0.6, ls="--")
        ends = np.concatenate([d["t_model_end"].values, d["t_rest"].values])
        ends = ends[np.isfinite(ends)]
        a1.set_xlim(0.0, 1.25 * ends.max() if ends.size else None)
        a1.axhline(ds.attrs["threshold"], color="0.5", lw=0.5, ls="--")
        a1.set_ylim(1e-12, 3)
        label_time(a1)
        a1.set_ylabel(r"$(E-E_{\rm rest})/(E_0-E_{\rm rest})$")
        a1.set_title(r"(%s) $\gamma=%s$, $\mu=%s$, $\psi(0)=%s$:" "\n" r"energy (dotted: collapse/contact)"
                     % ("abcdefgh"[2 * i], tex_num(float(d["gamma"])), tex_num(float(d["mu"])),
                        tex_num(float(d["psi0"]))), fontsize=7)
        a2.set_xscale("log")
        # the note on the side of the dashed line with more room, inside the axes
        lo, hi = a2.get_xlim()
        right_half = np.log(paired - 0.5) - np.log(lo) > 0.5 * (np.log(hi) - np.log(lo))
        a2.text(paired - 0.5, 0.4, "dimer: double impacts end \n(contact %d); no $r_n$ beyond " % (paired + 1)
                if right_half else " dimer: double impacts end\n (contact %d); no $r_n$ beyond" % (paired + 1),
                transform=a2.get_xaxis_transform(), fontsize=6, va="center", ha="right" if right_half else "left")
        a2.set_xlabel(r"macroscopic bounce $n$")
        a2.set_ylabel(r"$r_n$")
        a2.set_title(r"(%s) $r_n$: dimer $f_{n+1}/f_n$, $f_n=\tau_{2n}$ (dots);" "\n" r"rigid models $u_{n+1}/u_n$ "
                     "(lines)" % "abcdefgh"[2 * i + 1], fontsize=7)
    handles, labs = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labs, loc="lower center", ncol=3, fontsize=7, frameon=False)
    fig.suptitle("Rigid-ball restitution models against the two-mass ball (time in $\\sqrt{m/2k}$; $E_{\\rm rest}$: "
                 "$E_m=-\\gamma^2/2$ for the dimer, 0 for the rigid ball)", fontsize=8)
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    save(fig, outputs)


# --------------------------------------------------------------------------- least model per scene


def _asym_points(candidates: np.ndarray, n_min: int, n_max: int, points: int) -> np.ndarray:
    """About ``points`` log-spaced impact indices in [n_min, n_max] among ``candidates`` (the impacts the
    reference dataset keeps): the nearest candidate to each point of a log grid, each once."""
    pool = candidates[(candidates >= n_min) & (candidates <= n_max)]
    if pool.size == 0:
        return pool
    grid = np.geomspace(max(n_min, 1), max(n_max, n_min, 1), points)
    k = np.clip(np.searchsorted(pool, grid), 1, pool.size - 1) if pool.size > 1 else np.zeros(points, dtype=int)
    if pool.size > 1:
        k = np.where(np.abs(pool[k - 1] - grid) <= np.abs(pool[k] - grid), k - 1, k)
    return np.unique(pool[k])


class _Reference:
    """The exact solver's trajectory of a scene, read from the scene's netCDF (made by the scene rule,
    possibly thinned to its first events plus log-spaced ones), and its quantities of interest.

    Every QoI reads what the dataset keeps: y_t, r_n and impact_states the complete prefix of its records
    (:func:`bounce.io.complete_prefix`; all of them for an unthinned scene), asymptotic_laws the kept impacts,
    one record per point: at impact index e (0-based), n tau_n mu/3 = e tau[e] mu/3 with the record's own
    flight time tau[e] = t_e - t_(e-1) (the solver's, not a difference of two rounded times), and n Xdot_n mu/(3 gamma) with n = e + 1 from its rebound speed.
    Impact indices are event indices less the non-impact events before them, exact when every non-impact
    event is kept (the thinned scenes keep their first events, and are impacts only after them).
    """

    def __init__(self, params, ds: xr.Dataset, qoi: dict):
        from ..io import complete_prefix, sample_dataset

        self.params, self.qoi = params, qoi
        kind = ds["kind"].values
        events = ds["event"].values if "event" in ds.coords else np.arange(kind.size)
        prefix = complete_prefix(ds)
        imp = kind == IMPACT
        self.n_impacts = int(ds.attrs.get("n_events_simulated", kind.size)) - int(np.count_nonzero(~imp))
        self.kept_impacts = (events - np.cumsum(~imp))[imp]
        self.kept_tau, self.kept_xdot = ds["tau"].values[imp], ds["xdot"].values[imp]
        pre = imp[:prefix]
        self.output = _Output(ds["t"].values[:prefix][pre], ds["xdot"].values[:prefix][pre], True,
                              lambda times: sample_dataset(ds, times)["y"], True, ds["tau"].values[:prefix][pre])
        self.values = {name: self.reference_value(name, cfg) for name, cfg in qoi.items()}

    def points(self, cfg) -> np.ndarray:
        """Impact indices of the asymptotic laws: kept impacts in [n_min, last impact - 1]."""
        return _asym_points(self.kept_impacts, int(cfg["n_min"]), self.n_impacts - 2, int(cfg["points"]))

    def reference_value(self, name, cfg):
        if name != "asymptotic_laws":
            return self.extract(name, cfg, self.output)
        p, idx = self.params, self.points(cfg)
        rec = np.searchsorted(self.kept_impacts, idx)
        a = idx * self.kept_tau[rec] * p.mu / 3.0
        b = (idx + 1) * self.kept_xdot[rec] * p.mu / (3.0 * p.gamma)
        return np.concatenate([a, b])

    def extract(self, name, cfg, out):
        p = self.params
        if name == "y_t":
            return out.y_at(np.linspace(*cfg["window"], int(cfg["samples"])))
        if name == "r_n":
            return _falcon_r(out.t, out.paired, int(cfg["n_max"]))
        if name == "impact_states":
            n = self.output.xdot.size if cfg["n_max"] is None else int(cfg["n_max"])
            xd = np.full(n, np.nan)
            k = min(n, out.xdot.size)
            xd[:k] = out.xdot[:k]
            return {"xdot": xd, "has_y": out.has_states}
        if name == "asymptotic_laws":
            idx = self.points(cfg)
            a, b = np.full(idx.size, np.nan), np.full(idx.size, np.nan)
            ok = idx < out.t.size
            ii = idx[ok]
            a[ok] = ii * out.tau[ii] * p.mu / 3.0  # n tau_n mu/3, tau_n = t_{n+1} - t_n
            b[ok] = (ii + 1) * out.xdot[ii] * p.mu / (3.0 * p.gamma)  # n Xdot_n mu/(3 gamma), n = ii + 1
            return np.concatenate([a, b])
        raise InputError(f"unknown quantity of interest {name!r}")

    def error(self, name, cfg, out) -> float:
        ref = self.values[name]
        got = self.extract(name, cfg, out)
        if name == "impact_states":
            if not got["has_y"]:
                return math.inf
            r, g = ref["xdot"], got["xdot"]
            if np.any(np.isnan(g) & np.isfinite(r)):
                return math.inf
            return float(np.nanmax(np.abs(g - r) / r))
        if np.any(np.isnan(got) & np.isfinite(ref)):
            return math.inf
        return float(np.nanmax(np.abs(got - ref)))


class _Output:
    """What a method delivers, in the form the QoIs read: impact times, rebound speeds and flight times
    (the solver's own where it has them, else differences of the impact times)."""

    def __init__(self, t, xdot, paired, y_func, has_states, tau=None):
        self.t, self.xdot, self.paired, self.y_at, self.has_states = t, xdot, paired, y_func, has_states
        self.tau = np.diff(t, prepend=0.0) if tau is None else tau

    @classmethod
    def from_traj(cls, traj):
        imp = traj.kind == IMPACT

        def y_at(times):
            return traj.params.y_eq + sample_trajectory(traj, times)["y_minus_yeq"]

        return cls(traj.t[imp], traj.xdot[imp], True, y_at, True, traj.tau[imp])


def _candidate_output(name, res, params, initial, run, setting, stop) -> _Output:
    if name == "exact":
        return _Output.from_traj(simulate(params, initial, max_events=stop["events"], t_max=stop["t_max"]))
    if name == "contact-switch":
        return _Output.from_traj(res.extra["trajectory"])

    def y_at(times):
        r = run(params, initial, setting, max_events=stop["events"], t_max=stop["t_max"], sample_times=times)
        return r.y

    paired = name == "asymptotic-map"
    return _Output(res.t, res.xdot, paired, y_at, False)


def least_model(spec: dict) -> xr.Dataset:
    """Cheapest method per scene within the scene's tolerances (module docstring).  ``spec``
    (config ``reduced.least_model`` plus ``scene_specs``: the config's ``scenes`` section)::

        {"repeats": 3, "deltas": [...], "n0s": [...],
         "scenes": {"rigid-fall": {"qoi": {"y_t": {"tol": 0.01, "window": [0, 420], "samples": 4201}}}, ...},
         "scene_specs": {"rigid-fall": {"gamma": ..., "mu": ..., "initial": ..., "stop": ...}, ...},
         "scene_files": {"rigid-fall": "results/data/rigid-fall.nc", ...}}

    The reference of each scene is its dataset (``scene_files``, made by the scene rule), not a rerun.
    """
    from ..io import read_dataset
    from ..scenes import scene_initial, scene_parameters, scene_stop

    rigid.warm_up()
    scenes = list(spec["scenes"])
    deltas = sorted((float(d) for d in spec["deltas"]), reverse=True)
    n0s = sorted(int(n) for n in spec["n0s"])
    repeats = int(spec["repeats"])
    cands = ["exact", "contact-switch", "asymptotic-map"] + [m[0] for m in RIGID_MODELS]
    shape = (len(scenes), len(cands))
    err = np.full(shape, np.nan)
    cpu = np.full(shape, np.nan)
    meets = np.zeros(shape, dtype=np.int8)
    setting_s = np.full(shape, "", dtype=object)
    note = np.full(shape, "", dtype=object)
    ladder_d_err = np.full((len(scenes), len(deltas)), np.nan)
    ladder_d_cpu = np.full((len(scenes), len(deltas)), np.nan)
    ladder_n_err = np.full((len(scenes), len(n0s)), np.nan)
    ladder_n_cpu = np.full((len(scenes), len(n0s)), np.nan)
    chosen = np.full(len(scenes), "", dtype=object)
    why = np.full(len(scenes), "", dtype=object)
    tol_text = np.full(len(scenes), "", dtype=object)
    for i, sc in enumerate(scenes):
        sspec = spec["scene_specs"][sc]
        qoi = spec["scenes"][sc]["qoi"]
        params = scene_parameters(sspec)
        initial = scene_initial(sspec, params)
        stop = scene_stop(sspec)
        stop = {"events": int(stop["events"]), "t_max": float(stop["t_max"])}
        ref = _Reference(params, read_dataset(spec["scene_files"][sc]), qoi)
        n_ref_impacts = ref.n_impacts
        distinct = np.ones(len(cands), dtype=bool)  # False: reproduces the exact solver (not a reduced model)
        tol_text[i] = "; ".join(f"{k}: {v['tol']:g}" for k, v in qoi.items())

        def evaluate(name, run, setting):
            res = run(params, initial, setting, max_events=stop["events"], t_max=stop["t_max"])
            out = _candidate_output(name, res, params, initial, run, setting, stop)
            errs = {q: ref.error(q, cfg, out) for q, cfg in qoi.items()}
            ok = all(errs[q] <= cfg["tol"] for q, cfg in qoi.items())
            worst = max(errs[q] / cfg["tol"] for q, cfg in qoi.items())  # in units of the tolerance
            return res, errs, ok, worst

        def timed(run, setting):
            return min(run(params, initial, setting, max_events=stop["events"], t_max=stop["t_max"]).cpu_time
                       for _ in range(repeats))

        # exact
        j = cands.index("exact")
        res, errs, ok, worst = evaluate("exact", exact.run, {})
        err[i, j], meets[i, j], cpu[i, j], setting_s[i, j] = worst, ok, timed(exact.run, {}), "{}"
        # contact switch: the largest delta that meets every tolerance
        j = cands.index("contact-switch")
        best = None
        for k, dl in enumerate(deltas):
            res, errs, ok, worst = evaluate("contact-switch", contact_switch.run, {"delta": dl})
            ladder_d_err[i, k], ladder_d_cpu[i, k] = worst, res.cpu_time
            if ok and best is None:
                best = (dl, worst, res)
        if best is not None:
            dl, worst, res = best
            err[i, j], meets[i, j], setting_s[i, j] = worst, 1, f"delta={dl:g}"
            cpu[i, j] = timed(contact_switch.run, {"delta": dl})
            note[i, j] = (f"first switch at t = {res.extra['switch_t'][0]:.6g}" if res.extra["n_switches"]
                          else "never switches within the scene (it is the exact solver)")
            distinct[j] = bool(res.extra["n_switches"])
        else:
            k = int(np.nanargmin(ladder_d_err[i])) if np.isfinite(ladder_d_err[i]).any() else 0
            err[i, j], cpu[i, j] = ladder_d_err[i, k], ladder_d_cpu[i, k]
            note[i, j] = f"no delta in [{deltas[-1]:g}, {deltas[0]:g}] meets the tolerance"
        # asymptotic map: the smallest n0 that meets every tolerance
        j = cands.index("asymptotic-map")
        best = None
        for k, n0 in enumerate(n0s):
            if n0 >= n_ref_impacts:
                continue  # the map would never run: that is the exact solver
            try:
                res, errs, ok, worst = evaluate("asymptotic-map", rigid.run_asymptotic, {"n0": n0})
            except InputError as exc:
                note[i, j] = f"n0 = {n0}: {exc}"
                continue
            ladder_n_err[i, k], ladder_n_cpu[i, k] = worst, res.cpu_time
            if ok:
                best = (n0, worst)
                break
        if best is not None:
            n0, worst = best
            err[i, j], meets[i, j], setting_s[i, j] = worst, 1, f"n0={n0}"
            cpu[i, j] = timed(rigid.run_asymptotic, {"n0": n0})
        else:
            fin = np.isfinite(ladder_n_err[i])
            if fin.any():
                k = int(np.flatnonzero(fin)[np.argmin(ladder_n_err[i][fin])])
                err[i, j], cpu[i, j], setting_s[i, j] = ladder_n_err[i, k], ladder_n_cpu[i, k], f"n0={n0s[k]}"
            else:
                err[i, j] = math.inf
            note[i, j] = note[i, j] or (f"no n0 in {n0s} below the scene's {n_ref_impacts} impacts meets the "
                                        "tolerance")
        # rigid-ball models, default settings
        for name, run, setting in RIGID_MODELS:
            j = cands.index(name)
            res, errs, ok, worst = evaluate(name, run, setting)
            err[i, j], meets[i, j], setting_s[i, j] = worst, ok, str(setting or "{}")
            cpu[i, j] = timed(run, setting) if ok else res.cpu_time
            if "impact_states" in qoi:
                note[i, j] = "no spring: delivers no Y_n, Ydot_n"
        ok_j = np.flatnonzero((meets[i] == 1) & distinct)
        jbest = int(ok_j[np.argmin(cpu[i, ok_j])])
        j_ex = cands.index("exact")
        if jbest != j_ex and meets[i, j_ex] and cpu[i, j_ex] <= TIE * cpu[i, jbest]:
            jbest = j_ex  # a near-tie (timing noise): the exact solver, which has no modelling error
        chosen[i] = f"{cands[jbest]} ({setting_s[i, jbest]})"
        others = ", ".join(cands[j] for j in ok_j if j != jbest)
        # no CPU seconds here (results carry none): they are the variable cpu, in the study's timing file
        why[i] = (f"meets {tol_text[i]} with error {err[i, jbest]:.3g} x tol, chosen by its CPU time"
                  + (f"; also meeting: {others}" if others else "; nothing else meets it")
                  + (f"; {note[i, jbest]}" if note[i, jbest] else ""))
    sc = ("scene", "candidate")
    u = {"units": "1"}
    return xr.Dataset(
        {
            "error": (sc, err, {"long_name": "largest error over the scene's QoIs, in units of each QoI's tolerance "
                                             "(<= 1 meets)", **u}),
            "cpu": (sc, cpu, {"long_name": "CPU time (best of repeats for methods that meet)", "units": "s"}),
            "meets": (sc, meets, {"long_name": "meets every tolerance of the scene", **u}),
            "setting": (sc, setting_s.astype(str), {"long_name": "setting used"}),
            "note": (sc, note.astype(str), {"long_name": "remark"}),
            "chosen": (("scene",), chosen.astype(str), {"long_name": "cheapest method meeting the tolerances"}),
            "why": (("scene",), why.astype(str), {"long_name": "why it was chosen"}),
            "tolerance": (("scene",), tol_text.astype(str), {"long_name": "tolerances per quantity of interest"}),
            "ladder_delta_error": (("scene", "delta"), ladder_d_err, {"long_name": "contact switch: error / tol", **u}),
            "ladder_delta_cpu": (("scene", "delta"), ladder_d_cpu, {"long_name": "contact switch: CPU", "units": "s"}),
            "ladder_n0_error": (("scene", "n0"), ladder_n_err, {"long_name": "asymptotic map: error / tol", **u}),
            "ladder_n0_cpu": (("scene", "n0"), ladder_n_cpu, {"long_name": "asymptotic map: CPU", "units": "s"}),
        },
        coords={"scene": scenes, "candidate": cands, "delta": np.array(deltas), "n0": np.array(n0s)},
        attrs={"title": "Least model per pipeline scene: cheapest method within the scene's tolerances",
               "repeats": repeats, "Conventions": "CF-1.10"},
    )


#: quantity of interest -> what its error measures (the errors of least_model's _Reference.error)
QOI_TEXT = {
    "y_t": r"$y(t)$: max abs. error [$L$]",
    "r_n": r"$r_n$ (fig. rest-coeff): max abs. error",
    "impact_states": r"$\dot X_n$ at every impact: max rel. error",
    "asymptotic_laws": r"$n\tau_n\mu/3$, $n\dot X_n\mu/3\gamma$: max abs. error",
}


SETTING_NAMES = {"n0": "$n_0$", "delta": r"$\delta$"}


def _candidate_text(name: str, setting: str) -> str:
    """'exact', '{}' -> 'exact solver'; 'asymptotic-map', 'n0=10000' -> 'asymptotic map, n0 = 1e4'."""
    from ..figures.common import tex_num

    words = {"exact": "exact solver"}.get(name, name.replace("-", " "))
    setting = setting.strip().strip("{}").replace("'", "")
    if not setting:
        return words
    parts = []
    for item in setting.replace(":", "=").split(","):
        key, _, value = (p.strip() for p in item.partition("="))
        try:
            value = "$%s$" % tex_num(float(value))
        except ValueError:
            pass
        parts.append("%s = %s" % (SETTING_NAMES.get(key, key), value))
    return words + ", " + ", ".join(parts)


def plot_least_model(ds: xr.Dataset, spec: dict, outputs) -> None:
    """Error (in units of the scene's tolerance, worst over its quantities of interest) against CPU
    time per scene and candidate; the cheapest one that meets every tolerance circled.

    The exact solver is the reference: its error is 0 by construction, not a measurement, so it
    is a dashed vertical line (its CPU time) and a star in the bottom strip ("reference"), with
    any candidate that reproduces it exactly (the contact switch that never switches).  A
    candidate that cannot deliver a quantity (no spring: no Y_n) or fails has infinite error:
    top strip.  Panel titles give each scene's quantities of interest and tolerances."""
    from matplotlib.lines import Line2D
    from matplotlib.ticker import LogLocator, NullFormatter

    from ..figures.common import WIDTH, plt, save, tex_num

    scenes = list(ds["scene"].values)
    cands = list(ds["candidate"].values)
    ncol = 3
    nrow = math.ceil((len(scenes) + 1) / ncol)
    fig, axes = plt.subplots(nrow, ncol, figsize=(WIDTH, 2.7 * nrow), squeeze=False)
    markers = "*os^vDPX"
    err_all = ds["error"].values
    finite = err_all[np.isfinite(err_all) & (err_all > 0)]
    lo = 10.0 ** (math.floor(math.log10(min(finite.min(), 1e-2))) - 1) if finite.size else 1e-3
    hi = 10.0 ** (math.ceil(math.log10(max(finite.max(), 1e2))) + 1) if finite.size else 1e3
    zero_y, inf_y = lo / 30.0, hi * 30.0  # the two strips, outside the measured range

    def y_of(e):
        return inf_y if not np.isfinite(e) else (zero_y if e == 0 else e)

    for k, sc in enumerate(scenes):
        ax = axes[k // ncol][k % ncol]
        d = ds.sel(scene=sc)
        for j, c in enumerate(cands):
            e = float(d["error"].sel(candidate=c))
            t = float(d["cpu"].sel(candidate=c))
            if not np.isfinite(t):
                continue
            if c == "exact":
                ax.axvline(t, color="k", lw=0.7, ls="--")
            filled = bool(int(d["meets"].sel(candidate=c)))
            ax.loglog(t, y_of(e), markers[j % len(markers)], color=f"C{j}", ms=6 if c == "exact" else 4,
                      mfc=None if filled else "none", zorder=3)
        ax.axhspan(lo / 100, lo, color="0.92", zorder=0)
        ax.axhspan(hi, hi * 100, color="0.92", zorder=0)
        ax.axhline(1.0, color="C3", lw=0.7, ls="-")
        ch = str(d["chosen"].values).split(" (")[0]
        ax.loglog(float(d["cpu"].sel(candidate=ch)), y_of(float(d["error"].sel(candidate=ch))),
                  "o", ms=12, mfc="none", color="k", mew=0.8, zorder=4)
        qois = [q.split(":") for q in str(d["tolerance"].values).split("; ")]
        lines = ["%s, tol $%s$" % (QOI_TEXT.get(q.strip(), q), tex_num(float(tol))) for q, tol in qois]
        chosen = _candidate_text(ch, str(d["setting"].sel(candidate=ch).values))
        ax.set_title("(%s) %s\n%s\nchosen: %s" % ("abcdefghijklmnop"[k], sc, "\n".join(lines), chosen), fontsize=6)
        ts = d["cpu"].values[np.isfinite(d["cpu"].values)]
        if ts.size:
            ax.set_xlim(ts.min() / 3, ts.max() * 3)
        ax.set_xlabel("CPU time [s]", fontsize=7)
        ax.set_ylabel("error / tolerance", fontsize=7)
        ax.set_ylim(lo / 100, hi * 100)
        ticks = [10.0**k for k in range(round(math.log10(lo)) + 2, round(math.log10(hi)) - 1) if k % 3 == 0]
        ax.set_yticks([zero_y] + ticks + [inf_y])
        ax.set_yticklabels(["reference"] + ["$%s$" % tex_num(v) for v in ticks] + [r"$\infty$"], fontsize=6)
        ax.yaxis.set_minor_locator(plt.NullLocator())
        ax.xaxis.set_major_locator(LogLocator(numticks=4))
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.tick_params(axis="x", labelsize=6)
    leg_ax = axes[len(scenes) // ncol][len(scenes) % ncol]
    leg_ax.axis("off")
    for k in range(len(scenes) + 1, nrow * ncol):
        axes[k // ncol][k % ncol].axis("off")
    handles = [Line2D([], [], marker=markers[j % len(markers)], color=f"C{j}", lw=0, ms=4,
                      label=_candidate_text(c, "")) for j, c in enumerate(cands)]
    handles += [Line2D([], [], marker="o", color="k", mfc="none", lw=0, ms=8, label="chosen (cheapest meeting it)"),
                Line2D([], [], color="C3", lw=0.7, label="tolerance (error / tol = 1)"),
                Line2D([], [], color="k", lw=0.7, ls="--", label="exact solver's CPU time")]
    leg_ax.legend(handles=handles, loc="center", fontsize=6, frameon=False,
                  title="filled: meets every tolerance\nhollow: does not", title_fontsize=6)
    fig.suptitle("Least model per scene: error, in units of the scene's tolerance (worst quantity), against CPU "
                 "time.\nThe exact solver is the reference (error 0 by construction, not measured): bottom strip; "
                 "top strip: cannot deliver the quantity or failed", fontsize=7)
    fig.tight_layout()
    save(fig, outputs)


def _least_model_scenes(config: dict) -> list:
    return list(config["reduced"]["least_model"]["scenes"])


def _least_model_slice(config: dict) -> dict:
    """The least-model settings plus the specs and datasets of the scenes it names (validated to exist)."""
    lm = config["reduced"]["least_model"]
    return dict(lm, scene_specs={name: config["scenes"][name] for name in lm["scenes"]},
                scene_files={name: scene_file(name) for name in lm["scenes"]})


STUDIES = (
    Study("reduced-vs-dimer", reduced_vs_dimer, plot_reduced_vs_dimer, lambda c: c["reduced"]["vs_dimer"],
          caption=("Rigid-ball models (constant r, eq. onefifth-rest-coeff, eq. our-r, time of contact) against the"
                   " dimer on the paper's drops.")),
    Study("least-model", least_model, plot_least_model, _least_model_slice, scenes=_least_model_scenes, timed=True,
          caption="The cheapest model meeting an explicit tolerance on each scene's quantity of interest."),
)

"""Sweep ``alpha-atlas``: the Discussion's asymptotic map for the power-law spring over a grid of (a, b).

For every cell (a, b, constants) -- a and b from their lists, the constants (rho, gamma, mu) from a short
list -- the power-law dimer (eq. ``eq-motion-nonlin-psi-xi``) starts with its spring at the static
equilibrium xi_eq = -(gamma/rho)^(1/(a+1)) (eq. ``nonlin-equilibrium-xi``), at rest, the lower mass
``drop`` x |xi_eq| above the floor, and is simulated for ``events`` events (exact to rounding,
:mod:`bounce.series.events`; a run that stops early, e.g. at a sticky onset, leaves its cell not determined).
On the impacts n >= ``fit_n_min`` two sequences are fitted:

* q_n = n Xdot_n alpha, alpha = mu (3 gamma)^-1 (gamma/rho)^(b/(a+1)) (the Discussion: alpha_n -> alpha in
  the map eq. ``mappa``, so Lemma Giorgio's gives n Xdot_n alpha -> 1);
* q_n = Xdot_n/(gamma tau_n) (Xdot_n/tau_n -> gamma; derivation in :mod:`bounce.checks.nonlinear`).

Their limit L by Richardson extrapolation (:func:`bounce.analysis.fitting.richardson_ln`: the ln n/n and 1/n terms
cancelled) with its error, on every impact; on ``points`` log-spaced impacts the least-squares tail fit
(:func:`bounce.analysis.fitting.tail_limit`) as an independent second estimate, and the decay exponent p of
q_n - L ~ n^-p (c ln n + d) (:func:`bounce.analysis.fitting.correction_decay`, with the spring's relaxation near
equilibrium as further columns: eq. y-eq-sticky rescaled by :func:`bounce.analysis.theory.nonlin_sticky_scaling`, a
correction n^(-3/2) when oscillatory; Lemma Giorgio's: p = 1).  The theory predicts L = 1 in every cell;
cells with b > a converge slowest (measured: a = 0, b = 1.5 is still in its transient at 1e6 events).
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from ..kinds import IMPACT
from ..analysis.fitting import correction_decay, log_select, richardson_ln, spring_columns, tail_limit
from ..model import Parameters, State
from ..simulate import simulate
from ..springs.power import PowerSpring
from ..analysis.theory import nonlin_alpha_limit, nonlin_equilibrium_xi, nonlin_sticky_scaling
from .base import ITEM, Sweep

NAME = "alpha-atlas"
QUANTITIES = ("alpha", "flight")
QUANTITY_LABELS = {"alpha": "n Xdot_n alpha", "flight": "Xdot_n / (gamma tau_n)"}
FIT_KEYS = ("limit", "limit_err", "tail_limit", "exponent", "exponent_err", "last")


def _grid(spec: dict) -> tuple[np.ndarray, np.ndarray, list]:
    return np.asarray(spec["a"], float), np.asarray(spec["b"], float), list(spec["constants"])


def size(spec: dict) -> int:
    a, b, consts = _grid(spec)
    return a.size * b.size * len(consts)


def prepare(spec: dict, items: np.ndarray) -> dict:
    """(a, b, rho, gamma, mu) of each cell: item k = (i_a * n_b + i_b) * n_constants + i_c."""
    a, b, consts = _grid(spec)
    rest, ic = np.divmod(np.asarray(items, dtype=np.int64), len(consts))
    ia, ib = np.divmod(rest, b.size)
    table = np.array([[c["rho"], c["gamma"], c["mu"]] for c in consts], dtype=float)
    return {"a": a[ia], "b": b[ib], "rho": table[ic, 0], "gamma": table[ic, 1], "mu": table[ic, 2]}


def measure_cell(a: float, b: float, rho: float, gamma: float, mu: float, spec: dict) -> dict:
    """The fitted limits of one cell (see the module docstring); NaN where no fit window of a decade exists."""
    xi_eq = nonlin_equilibrium_xi(gamma, rho, a)
    start = State.from_psi_xi(xi_eq + float(spec["drop"]) * abs(xi_eq), 0.0, xi_eq, 0.0)
    traj = simulate(Parameters(gamma, mu, PowerSpring(rho, a, b)), start, max_events=int(spec["events"]))
    n = np.arange(1.0, len(traj) + 1.0)
    alpha = nonlin_alpha_limit(gamma, mu, rho, a, b)
    sel = np.flatnonzero((n >= float(spec["fit_n_min"])) & (traj.kind == IMPACT))  # the fitted impacts
    out = {"n_events": len(traj), "complete": int(traj.stop_reason == "max_events"), "alpha_theory": alpha}
    mu_eff, scale = nonlin_sticky_scaling(gamma, mu, rho, a, b)  # the spring's relaxation, fitted along
    nn, xdot, t = n[sel], traj.xdot[sel], traj.t[sel]
    series = {"alpha": nn * xdot * alpha, "flight": xdot / (gamma * traj.tau[sel])}
    for name, qq in series.items():
        fit = dict.fromkeys(FIT_KEYS, math.nan)
        if out["complete"] and nn.size >= 20 and nn[-1] / nn[0] >= 10.0:
            fit["limit"], fit["limit_err"] = richardson_ln(nn, qq)
            s = log_select(nn, nn[0], nn[-1], int(spec["points"]))  # least squares on log-spaced impacts
            fit["tail_limit"] = tail_limit(nn[s], qq[s])[0]
            spring = np.column_stack(spring_columns(t[s] * scale, mu_eff, 2))
            fit["exponent"], fit["exponent_err"], _ = correction_decay(nn[s], qq[s], spring)
            fit["last"] = float(qq[-1])
        out[name] = fit
    return out


def compute(spec: dict, inputs: dict) -> dict:
    m = len(inputs["a"])
    out = {k: np.full((m, len(QUANTITIES)), np.nan) for k in FIT_KEYS}
    out.update(n_events=np.zeros(m, np.int64), complete=np.zeros(m, np.int8), alpha_theory=np.full(m, np.nan))
    for c in range(m):
        cell = measure_cell(*(float(inputs[k][c]) for k in ("a", "b", "rho", "gamma", "mu")), spec)
        for k in ("n_events", "complete", "alpha_theory"):
            out[k][c] = cell[k]
        for j, name in enumerate(QUANTITIES):
            for key in FIT_KEYS:
                out[key][c, j] = cell[name][key]
    return out


_Q = (ITEM, "quantity")
VARIABLES = {
    "limit": (_Q, "limit L of q_n by Richardson extrapolation (ln n/n and 1/n cancelled; theory: L = 1)", "1", None),
    "limit_err": (_Q, "error of L: change of the extrapolation when its points move by a factor 2", "1", None),
    "tail_limit": (_Q, "limit of q_n by least squares on (1, ln n/n, 1/n, ...) (second estimate)", "1", None),
    "exponent": (_Q, "decay exponent p of q_n - L ~ n^-p (c ln n + d) (theory: 1)", "1", None),
    "exponent_err": (_Q, "error of p: change under window variants", "1", None),
    "last": (_Q, "q_n at the last impact", "1", None),
    "n_events": ((ITEM,), "events simulated", "1", None),
    "complete": ((ITEM,), "1 if the run reached its event cap (no early stop)", "1", None),
    "alpha_theory": ((ITEM,), "alpha = mu (3 gamma)^-1 (gamma/rho)^(b/(a+1)) (Discussion)", "1", None),
}


def finish(ds: xr.Dataset, spec: dict) -> xr.Dataset:
    """The items reshaped to the (a, b, constants) grid, with coordinates and the settings in the attributes."""
    a, b, consts = _grid(spec)
    shape = (a.size, b.size, len(consts))
    out = xr.Dataset(attrs=dict(ds.attrs))
    for name, var in ds.data_vars.items():
        out[name] = xr.Variable(("a", "b", "constants") + var.dims[1:], var.values.reshape(shape + var.shape[1:]),
                                var.attrs)
    table = {k: np.array([c[k] for c in consts], float) for k in ("rho", "gamma", "mu")}
    out = out.assign_coords(
        a=xr.Variable(("a",), a, {"long_name": "exponent a of the restoring force rho xi |xi|^a", "units": "1"}),
        b=xr.Variable(("b",), b, {"long_name": "exponent b of the damping 2 mu xi' |xi|^b", "units": "1"}),
        constants=xr.Variable(("constants",), np.arange(len(consts)), {"long_name": "index of (rho, gamma, mu)",
                                                                        "units": "1"}),
        rho=xr.Variable(("constants",), table["rho"], {"long_name": "stiffness rho of the power law", "units": "1"}),
        gamma=xr.Variable(("constants",), table["gamma"], {"long_name": "gravity gamma", "units": "1"}),
        mu=xr.Variable(("constants",), table["mu"], {"long_name": "damping mu", "units": "1"}),
        quantity=xr.Variable(("quantity",), np.array(QUANTITIES, dtype=object),
                             {"long_name": "q_n: " + "; ".join(f"{k} = {v}" for k, v in QUANTITY_LABELS.items()),
                              "units": "1"}),
    )
    out.attrs.update(events=int(spec["events"]), fit_n_min=int(spec["fit_n_min"]), drop=float(spec["drop"]),
                     err_max=float(spec["err_max"]), exponent_err_max=float(spec["exponent_err_max"]))
    limit_ok, exponent_ok = determined(out)
    flags = {"units": "1", "flag_values": np.array([0, 1], dtype=np.int8), "flag_meanings": "not_determined determined"}
    out["determined"] = xr.Variable(out["limit"].dims, limit_ok.astype(np.int8), {
        "long_name": f"1 if L is determined: finite, its error max(limit_err, |L - tail_limit|) <= err_max = "
                     f"{spec['err_max']:g}", **flags})
    out["exponent_determined"] = xr.Variable(out["limit"].dims, exponent_ok.astype(np.int8), {
        "long_name": f"1 if the decay exponent is determined: L determined and exponent_err <= exponent_err_max = "
                     f"{spec['exponent_err_max']:g}", **flags})
    return out


def determined(ds: xr.Dataset) -> tuple[np.ndarray, np.ndarray]:
    """(limit determined, exponent determined) per cell and quantity, by the thresholds in the attributes: a limit whose
    error, the larger of the extrapolation's change and its distance to the tail fit, exceeds ``err_max`` is still in
    its transient (no decade of the asymptotic regime within the events).  One rule for the figure and the check."""
    L = ds["limit"].values
    err = np.maximum(ds["limit_err"].values, np.abs(L - ds["tail_limit"].values))
    with np.errstate(invalid="ignore"):
        limit_ok = np.isfinite(L) & (err <= float(ds.attrs["err_max"]))
        return limit_ok, limit_ok & (ds["exponent_err"].values <= float(ds.attrs["exponent_err_max"]))


def plot(ds: xr.Dataset, spec: dict, outputs) -> None:
    """|L - 1| over (a, b) for each quantity and set of constants, the decay exponent written in each cell."""
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm

    from ..figures.common import WIDTH, save, tex_num

    a, b = ds["a"].values, ds["b"].values
    nc = ds.sizes["constants"]
    fig, axes = plt.subplots(2, nc, figsize=(WIDTH, 1.0 + 1.6 * 2), squeeze=False, constrained_layout=True)
    limit_ok, exponent_ok = determined(ds)
    dev = np.where(limit_ok, np.abs(ds["limit"].values - 1.0), np.nan)  # the cells the check leaves out: grey
    finite = dev[np.isfinite(dev) & (dev > 0)]
    norm = LogNorm(vmin=max(finite.min(), 1e-12), vmax=max(finite.max(), 1e-11)) if finite.size else None
    for j, q in enumerate(QUANTITIES):
        for c in range(nc):
            ax = axes[j, c]
            z = dev[:, :, c, j].T  # rows b, columns a
            ax.set_facecolor("0.85")  # grey: not determined
            mesh = ax.pcolormesh(np.arange(a.size + 1), np.arange(b.size + 1), np.where(z > 0, z, np.nan),
                                 cmap="viridis", norm=norm)
            p = np.where(exponent_ok, ds["exponent"].values, np.nan)[:, :, c, j].T
            for ib in range(b.size):
                for ia in range(a.size):
                    if np.isfinite(p[ib, ia]):
                        ax.text(ia + 0.5, ib + 0.5, f"{p[ib, ia]:.2f}", ha="center", va="center", fontsize=5,
                                color="w")
            ax.set_xticks(np.arange(a.size) + 0.5, [f"{v:g}" for v in a], fontsize=6)
            ax.set_yticks(np.arange(b.size) + 0.5, [f"{v:g}" for v in b], fontsize=6)
            ax.set_xlabel("$a$", fontsize=7)
            lab = r"$\lim n\dot X_n\alpha$" if q == "alpha" else r"$\lim \dot X_n/(\gamma\tau_n)$"
            ax.set_ylabel(f"{lab}\n$b$" if c == 0 else "$b$", fontsize=7)
            ax.set_title(rf"({'abcdefghijkl'[j * nc + c]}) $\rho={tex_num(ds['rho'][c])}$, "
                         rf"$\gamma={tex_num(ds['gamma'][c])}$, $\mu={tex_num(ds['mu'][c])}$", fontsize=7)
            ax.grid(False)
    fig.colorbar(mesh, ax=axes, shrink=0.8, label=r"$|L-1|$ (Richardson)")
    fig.suptitle(f"power-law spring: the Discussion's limits over (a, b), ${tex_num(ds.attrs['events'])}$ events per cell "
                 f"\n(numbers: decay exponent of the correction, theory 1; grey: not determined, limit error above "
                 f"{ds.attrs['err_max']:g}: check nonlinear-atlas leaves these cells out)", fontsize=7)
    save(fig, outputs)


def estimated_memory_mb(spec: dict) -> int:
    """Peak memory of one worker: the records (49 bytes per event) and ~6 per-impact arrays."""
    return math.ceil(100 * int(spec["events"]) / 1e6) + 300


SWEEP = Sweep(NAME, "The Discussion's asymptotic map for the power-law spring over (a, b): fitted limits",
              size, prepare, compute, VARIABLES, finish, plot, estimated_memory_mb)

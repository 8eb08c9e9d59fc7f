"""Check ``nonlinear-atlas``: the Discussion's asymptotic map over a grid of power laws (a, b), from the sweep
``alpha-atlas`` (:mod:`bounce.sweeps.alpha_atlas`; its gathered file is the only input).

1. ``alpha-limit`` (paper): lim n Xdot_n alpha = 1, alpha = mu (3 gamma)^-1 (gamma/rho)^(b/(a+1)), in every
   fitted cell;
2. ``flight-law`` (beyond): lim Xdot_n/(gamma tau_n) = 1 in every fitted cell;
3. ``correction-decay`` (beyond): the correction decays like n^-p (c ln n + d) with p = 1 (Lemma Giorgio's).

A cell's limit is the Richardson extrapolation of the sweep; its error is the larger of the extrapolation's own
change (points moved by a factor 2) and its distance to the independent least-squares tail fit, and the tolerance
``sigmas`` times that.  Cells whose run stopped early, had no decade of impacts past fit_n_min, or whose limit error exceeds
the sweep's ``err_max`` (still in the transient) are not determined (the decay exponent also where its error exceeds
``exponent_err_max``): the sweep marks them (its variables ``determined``, :func:`bounce.sweeps.alpha_atlas.determined`),
its figure greys exactly them, and the claims, "for every power law", are then not checkable (``judge_every``).
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import xarray as xr

from .base import BEYOND, NOT_CHECKABLE, PAPER, Check, Falsifier, Verdict, claim, judge_every, on_named, variable

NAME = "nonlinear-atlas"
SUBJECT = "sec:Discussion"


def _cells(ds: xr.Dataset) -> list[str]:
    a, b, rho, g, mu = (ds[k].values for k in ("a", "b", "rho", "gamma", "mu"))
    return [f"(a={a[i]:g}, b={b[j]:g}, rho={rho[c]:g}, gamma={g[c]:g}, mu={mu[c]:g})"
            for i in range(a.size) for j in range(b.size) for c in range(rho.size)]


def measure(spec: dict, inputs: list) -> SimpleNamespace:
    (ds,) = inputs
    k = float(spec["sigmas"])
    names = _cells(ds)
    shape = (len(names), ds.sizes["quantity"])
    L = ds["limit"].values.reshape(shape)
    err = np.maximum(ds["limit_err"].values.reshape(shape), np.abs(L - ds["tail_limit"].values.reshape(shape)))
    p, p_err = ds["exponent"].values.reshape(shape), ds["exponent_err"].values.reshape(shape)
    # the cells the sweep determines (sweeps.alpha_atlas.determined: its err_max, exponent_err_max); the others are
    # left out, and the sweep's figure greys exactly them
    ok, keep = (ds[v].values.reshape(shape).astype(bool) for v in ("determined", "exponent_determined"))
    L, err = np.where(ok, L, np.nan), np.where(ok, err, np.nan)
    p, p_err = np.where(keep, p, np.nan), np.where(keep, p_err, np.nan)
    data = xr.Dataset(coords={"cell": ("cell", np.array(names, dtype=object), {"long_name": "(a, b, rho, gamma, mu)",
                                                                              "units": "1"}),
                              "quantity": ("quantity", ds["quantity"].values, {"long_name": "fitted sequence q_n",
                                                                                "units": "1"})})
    data["limit"] = variable(("cell", "quantity"), L, "Richardson limit L (theory 1)")
    data["limit_err"] = variable(("cell", "quantity"), err, "error of L: max(Richardson change, |L - tail fit|)")
    data["exponent"] = variable(("cell", "quantity"), p, "decay exponent of the correction (theory 1)")
    data["exponent_err"] = variable(("cell", "quantity"), p_err, "its error (window variants)")
    grid = np.meshgrid(ds["a"].values, ds["b"].values, np.arange(ds["rho"].size), indexing="ij")
    for name, values, long_name in (("cell_a", grid[0], "exponent a of the cell's law"),
                                    ("cell_b", grid[1], "exponent b of the cell's law"),
                                    ("cell_constants", grid[2], "index of the cell's (rho, gamma, mu)")):
        data[name] = variable(("cell",), values.ravel(), long_name)
    data.attrs.update(check=NAME, sigmas=k, events=int(ds.attrs["events"]),
                      constants="; ".join(f"rho = {r:g}, gamma = {g:g}, mu = {m:g}" for r, g, m in
                                          zip(ds["rho"].values, ds["gamma"].values, ds["mu"].values)))
    ctx = (f"sweep alpha-atlas: {len(names)} cells, {int(ds.attrs['events']):.3g} events each from xi_eq, fits on "
           f"impacts n >= {int(ds.attrs['fit_n_min'])}")
    return SimpleNamespace(names=names, L=L, err=err, p=p, p_err=p_err, k=k, data=data, ctx=ctx,
                           quantities=list(ds["quantity"].values))


def _atlas_verdict(m, quantity: str, value, err, target: float, text: str, ref: str, what: str) -> Verdict:
    j = m.quantities.index(quantity)
    v, e = value[:, j], err[:, j]
    fitted = np.isfinite(v) & np.isfinite(e)
    missing = [m.names[i] for i in np.nonzero(~fitted)[0]]
    none = f"; not determined: {', '.join(missing)}" if missing else "; every cell determined"
    if not fitted.any():
        return Verdict(text, ref, m.ctx, f"{what} = {target:g}", "no fitted cell" + none, "none", NOT_CHECKABLE)
    z = np.abs(v[fitted] - target) / np.maximum(e[fitted], np.finfo(float).tiny)
    worst = int(np.nonzero(fitted)[0][int(np.argmax(z))])
    within = np.abs(v - target) <= m.k * e
    bad = [m.names[i] for i in np.nonzero(fitted & ~within)[0]]
    return Verdict(
        text, ref, f"{m.ctx}: {what} per cell",
        f"{what} = {target:g} in every cell",
        f"{int(fitted.sum())}/{fitted.size} cells fitted; max |{what} - {target:g}| = "
        f"{np.max(np.abs(v[fitted] - target)):.2g}; worst in units of its error: {m.names[worst]}: {v[worst]:.10g} +- "
        f"{e[worst]:.2g}" + (f"; outside: {', '.join(bad)}" if bad else "") + none,
        f"|{what} - {target:g}| <= {m.k:g} x the cell's error in every cell; a cell outside refutes the claim, an "
        "undetermined cell leaves it not checkable (judge_every: the policy of main-theorem/atlas-*)",
        judge_every(within, fitted))


# --------------------------------------------------------------------------- falsifiers (contract, point 4)

ATLAS = "alpha-atlas"  # the sweep whose gathered file is the input


def _limit_high(quantity: str):
    """A doctor of the sweep: both estimates of the limit of ``quantity`` (Richardson and tail fit) 2 % high in every
    cell, as for a law off by 2 %."""
    def doctor(ds):
        for key in ("limit", "tail_limit"):
            ds[key].loc[{"quantity": quantity}] = 1.02 * ds[key].sel(quantity=quantity)
        return ds
    return doctor


def _exponent_low(ds):
    """The decay exponents of n Xdot_n alpha - L 0.5 below the fitted ones in every cell (a correction n^-0.5)."""
    ds["exponent"].loc[{"quantity": "alpha"}] = ds["exponent"].sel(quantity="alpha") - 0.5
    return ds


CLAIMS: list = []


@claim(CLAIMS, "alpha-limit", PAPER, SUBJECT,
       falsifier=Falsifier("lim n Xdot_n alpha 2 % high in every cell (both estimates): alpha off by 2 %",
                           on_named(ATLAS, _limit_high("alpha"))))
def alpha_limit(m, spec) -> Verdict:
    return _atlas_verdict(m, "alpha", m.L, m.err, 1.0,
                          "alpha_n -> mu (3 gamma)^-1 (gamma/rho)^(b/(a+1)) for every power law: lim n Xdot_n alpha = 1",
                          "Discussion (map eq. mappa, Lemma Giorgio's)", "L")


@claim(CLAIMS, "flight-law", BEYOND, SUBJECT,
       falsifier=Falsifier("lim Xdot_n/(gamma tau_n) 2 % high in every cell (both estimates)",
                           on_named(ATLAS, _limit_high("flight"))))
def flight_law(m, spec) -> Verdict:
    return _atlas_verdict(m, "flight", m.L, m.err, 1.0, "Xdot_n / tau_n -> gamma for every power law",
                          "beyond the paper (Discussion: 'the same asymptotic law as the linear case')", "L")


@claim(CLAIMS, "correction-decay", BEYOND, SUBJECT,
       falsifier=Falsifier("the decay exponents of n Xdot_n alpha - L 0.5 below the fitted ones in every cell (a "
                           "correction n^-0.5 (c ln n + d)); a shift of 0.2 stays within 3 sigma of the small test "
                           "atlas, where p is known to +-0.14 and +-0.29", on_named(ATLAS, _exponent_low)))
def correction_decay(m, spec) -> Verdict:
    return _atlas_verdict(m, "alpha", m.p, m.p_err, 1.0,
                          "the correction to n Xdot_n alpha decays like n^-1 (c ln n + d) for every power law",
                          "Lemma Giorgio's (expansion of the map eq. mappa)", "p")


def _tex_constants(text: str) -> str:
    """'rho = 1, gamma = 0.01, mu = 0.3' (the dataset's constant set) in mathtext: '$\\rho=1$, $\\gamma=0.01$, ...'."""
    from ..figures.common import tex_num

    return ", ".join(f"$\\{name.strip()}={tex_num(float(value))}$" for name, value in
                     (part.split("=") for part in text.split(",")))


def plot(ds: xr.Dataset, spec: dict, outputs) -> None:
    """One a x b heat map per quantity (rows) and constant set (columns): the cell's deviation from the claimed value
    in units of its error, clipped at twice the tolerance; cells the check could not determine hatched grey."""
    from matplotlib.colors import Normalize

    from ..figures.common import WIDTH, plt, save, tex_num

    k = float(ds.attrs["sigmas"])
    a_values, b_values = np.unique(ds["cell_a"].values), np.unique(ds["cell_b"].values)
    constants = str(ds.attrs["constants"]).split("; ")
    shape = (a_values.size, b_values.size, len(constants))
    rows = [(ds["limit"].sel(quantity="alpha"), ds["limit_err"].sel(quantity="alpha"),
             r"$\lim n\dot X_n\alpha$ (claim alpha-limit)"),
            (ds["limit"].sel(quantity="flight"), ds["limit_err"].sel(quantity="flight"),
             r"$\lim \dot X_n/(\gamma\tau_n)$ (flight-law)"),
            (ds["exponent"].sel(quantity="alpha"), ds["exponent_err"].sel(quantity="alpha"),
             "decay exponent p (correction-decay)")]
    fig, axes = plt.subplots(len(rows), len(constants), figsize=(WIDTH, 6.4), constrained_layout=True, squeeze=False)
    norm = Normalize(-2.0 * k, 2.0 * k)
    for r, (value, error, label) in enumerate(rows):
        z = ((value.values - 1.0) / error.values).reshape(shape)
        for c, title in enumerate(constants):
            ax = axes[r, c]
            zc = z[:, :, c].T  # rows b, columns a
            mesh = ax.pcolormesh(np.arange(a_values.size + 1), np.arange(b_values.size + 1),
                                 np.clip(zc, -2.0 * k, 2.0 * k), cmap="RdBu_r", norm=norm)
            for j, i in zip(*np.nonzero(~np.isfinite(zc))):
                ax.add_patch(plt.Rectangle((i, j), 1, 1, facecolor="0.85", hatch="///", edgecolor="0.5", lw=0))
            for j, i in zip(*np.nonzero(np.isfinite(zc))):
                text = f"{zc[j, i]:.1f}".replace("-0.0", "0.0")
                ax.text(i + 0.5, j + 0.5, text, ha="center", va="center", fontsize=6,
                        color="w" if abs(zc[j, i]) > 1.2 * k else "k")
            ax.set_xticks(np.arange(a_values.size) + 0.5, [f"{v:g}" for v in a_values], fontsize=6)
            ax.set_yticks(np.arange(b_values.size) + 0.5, [f"{v:g}" for v in b_values], fontsize=6)
            ax.grid(False)
            if r == len(rows) - 1:
                ax.set_xlabel("spring exponent $a$", fontsize=7)
            if c == 0:
                ax.set_ylabel("damping exponent $b$", fontsize=7)
            letter = "abcdefghijklmnopqrstuvwxyz"[r * len(constants) + c]
            ax.set_title((label if c == 0 else "") + f"\n({letter}) {_tex_constants(title)}", fontsize=7)
    bar = fig.colorbar(mesh, ax=axes, shrink=0.6)
    bar.set_label(f"(value $-$ 1)/error, clipped at $\\pm{2 * k:g}$ (tolerance $\\pm{k:g}$)", fontsize=8)
    fig.suptitle(f"power-law spring: fitted limits over $(a, b)$, sweep alpha-atlas (${tex_num(ds.attrs['events'])}$ "
                 "events per cell); hatched: not determined (the check leaves the cell out)", fontsize=8)
    save(fig, outputs)


TITLE = "Discussion: the asymptotic map of the power-law spring over (a, b) (sweep alpha-atlas)"
CHECK = Check(NAME, measure, tuple(CLAIMS), plot, TITLE)

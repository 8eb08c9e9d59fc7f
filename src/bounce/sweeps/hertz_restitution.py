"""Sweep ``hertz-restitution``: the restitution of one well-separated impact of the Hertz ball against its speed.

The data behind eq. ``onefifth-rest-coeff`` (the 1/5 law the Discussion says a Hertz spring, a = b = 1/2,
justifies "by computing the energy dissipated in a single compression-expansion cycle").  For every cell
(u, gamma) of a log grid of impact speeds u and a list of gravities gamma, the power-law dimer arrives
with its spring at rest at its rest length (xi = xi' = 0, the state a long flight leaves it in: a free
fall does not load the spring) and the centre of mass falling at u: the lower mass is released
``lead_time`` x u above the floor at speed u, so it arrives at sqrt(u^2 + 2 gamma lead_time u) ~ u (the
arrival speed is recorded: the first record's x').  The first impact swaps psi' and xi' (eq.
``collision-rule``), the spring compresses and re-expands, and the second impact (x = 0 again) swaps
back: r = psi' after the second impact / u, eq. ``proper-rest-coeff``'s double impact.  Two events are
simulated per cell (exact to rounding, :mod:`bounce.series.events`).

Without gravity the spring is back at its rest length at the second impact and leaves at rest; with
gravity the centre of mass has fallen during the contact time T_c and the spring still moves:
xi'/u = -gamma T_c/u after the second impact (recorded as ``residual``), which is where gravity breaks
the single-cycle law (checked in ``bounce.checks.onefifth_rest_coeff``; the fit of U and the exponent is there).
Gravity must stay >= ~1e-12 for u up to 1: below, the second impact falls within rounding of the spring's
return to rest length (xi = 0, the law's non-analytic point), and the solver stops with ``slow_crossing``
(recorded as ``complete = 0``, never a guessed r).

Each run stops at t_max = lead_time + CONTACT_SPAN A/u at the latest, A = (5 u^2/(4 rho))^(2/5) the gravity-free
compression amplitude (V(A) = u^2/2), A/u the contact's time scale: the measured contact times are at most
3.2 A/u over the grid (config/config.yaml), so both events fall well inside.  The bound is what keeps each
run in the power law's supported domain (:mod:`bounce.springs.power`, domain 5): after the second impact
the ball would fly ~2u/gamma, up to 2e12 time units, which the domain refuses to follow unbounded.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from ..kinds import IMPACT
from ..model import Parameters, State
from ..simulate import simulate
from ..springs.power import PowerSpring
from ..analysis.theory import nonlin_cycle_loss
from .base import ITEM, Sweep, axis

NAME = "hertz-restitution"
HERTZ = 0.5  # a = b = 1/2
#: the runs' horizon past the arrival, in units of the contact's time scale A/u (measured contact times <= 3.2)
CONTACT_SPAN = 100.0


def size(spec: dict) -> int:
    return int(spec["u"]["n"]) * len(spec["gamma"])


def prepare(spec: dict, items: np.ndarray) -> dict:
    """(u, gamma) of each cell: item k is (u_i, gamma_j) with k = i * n_gamma + j."""
    us, gammas = axis(spec["u"]), np.asarray(spec["gamma"], dtype=float)
    i, j = np.divmod(np.asarray(items, dtype=np.int64), gammas.size)
    return {"u": us[i], "gamma": gammas[j]}


def compute(spec: dict, inputs: dict) -> dict:
    mu, rho, lead = float(spec["mu"]), float(spec["rho"]), float(spec["lead_time"])
    m = len(inputs["u"])
    out = {k: np.full(m, np.nan) for k in ("arrival", "r", "contact_time", "residual", "loss_first_order")}
    out["complete"] = np.zeros(m, dtype=np.int8)
    for c in range(m):
        u, gamma = float(inputs["u"][c]), float(inputs["gamma"][c])
        params = Parameters(gamma, mu, PowerSpring(rho, HERTZ, HERTZ))
        scale = (1.25 * u * u / rho) ** 0.4 / u  # A/u
        traj = simulate(params, State.from_psi_xi(lead * u, -u, 0.0, 0.0), max_events=2,
                        t_max=lead + CONTACT_SPAN * scale)
        arrival = float(traj.xdot[0])  # x' reverses at the impact: the arrival speed of the lower mass
        out["arrival"][c] = arrival
        out["loss_first_order"][c] = float(nonlin_cycle_loss(arrival, mu, rho, HERTZ, HERTZ))
        if len(traj) == 2 and bool(np.all(traj.kind == IMPACT)):
            out["complete"][c] = 1
            out["r"][c] = float(traj.xdot[1] + traj.xidot[1]) / arrival  # psi' = x' + xi' after the 2nd impact
            out["contact_time"][c] = float(traj.tau[1])
            out["residual"][c] = float(traj.xidot[1]) / arrival
    return out


VARIABLES = {
    "arrival": ((ITEM,), "impact speed u: the lower mass's speed at the first impact (spring at rest)", "1", None),
    "r": ((ITEM,), "restitution r = psi' after the second impact / u (the double impact)", "1", None),
    "contact_time": ((ITEM,), "contact time T_c: first to second impact", "1", None),
    "residual": ((ITEM,), "spring velocity xi' after the second impact / u (0 without gravity)", "1", None),
    "loss_first_order": ((ITEM,), "1 - r to first order in mu, gravity-free (theory.nonlin_cycle_loss)", "1", None),
    "complete": ((ITEM,), "1 if both events are impacts (the run did not stop early)", "1", None),
}


def finish(ds: xr.Dataset, spec: dict) -> xr.Dataset:
    """The items reshaped to the (u, gamma) grid, with the law's constants in the attributes."""
    us, gammas = axis(spec["u"]), np.asarray(spec["gamma"], dtype=float)
    out = xr.Dataset(attrs=dict(ds.attrs))
    for name, var in ds.data_vars.items():
        out[name] = xr.Variable(("u", "gamma"), var.values.reshape(us.size, gammas.size), var.attrs)
    out = out.assign_coords(
        u=xr.Variable(("u",), us, {"long_name": "nominal impact speed (centre of mass, before the fall of "
                                                "lead_time x u)", "units": "1"}),
        gamma=xr.Variable(("gamma",), gammas, {"long_name": "gravity gamma = g m / (2 L k)", "units": "1"}))
    out.attrs.update(mu=float(spec["mu"]), spring_rho=float(spec["rho"]), spring_a=HERTZ, spring_b=HERTZ,
                     lead_time=float(spec["lead_time"]))
    return out


def plot(ds: xr.Dataset, spec: dict, outputs) -> None:
    """(1 - r)/(first-order loss) and the residual spring velocity against u, one curve per gamma."""
    import matplotlib.pyplot as plt

    from ..figures.common import WIDTH, save, tex_num

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(WIDTH, 2.8), constrained_layout=True)
    for j, gamma in enumerate(ds["gamma"].values):
        u = ds["arrival"].values[:, j]
        a1.semilogx(u, (1.0 - ds["r"].values[:, j]) / ds["loss_first_order"].values[:, j], "o-", ms=2.5,
                    label=rf"$\gamma={tex_num(gamma)}$")
        a2.loglog(u, np.abs(ds["residual"].values[:, j]), "o-", ms=2.5, label=rf"$\gamma={tex_num(gamma)}$")
    a1.axhline(1.0, color="k", lw=0.6)
    a1.set_ylim(0.5, 1.5)
    a1.set(xlabel=r"impact speed $u$ (units $L/\sqrt{m/2k}$)", ylabel=r"$(1-r)\,/\,$first-order cycle loss")
    a1.set_title("(a) single Hertz impact: measured over the gravity-free law", fontsize=8)
    a2.set(xlabel=r"impact speed $u$ (units $L/\sqrt{m/2k}$)", ylabel=r"$|\dot\xi|/u$ after the contact")
    a2.set_title(r"(b) spring left moving by gravity ($=\gamma T_c/u$)", fontsize=8)
    for ax in (a1, a2):
        ax.legend(fontsize=6)
    fig.suptitle(rf"Hertz spring $a=b=1/2$, $\rho={ds.attrs['spring_rho']:g}$, $\mu={ds.attrs['mu']:g}$: "
                 "restitution of one well-separated impact", fontsize=8)
    save(fig, outputs)


def estimated_memory_mb(spec: dict) -> int:
    """Two events per cell: the interpreter and numba dominate."""
    return 300


SWEEP = Sweep(NAME, "Restitution of one well-separated impact of the Hertz ball against its speed (eq. onefifth-rest-coeff)",
              size, prepare, compute, VARIABLES, finish, plot, estimated_memory_mb)

"""Sweep ``dimer-gas-collapse``: the gas of deformable grains where the rigid gas collapses (beyond the paper).

The paper's point, carried to a gas (its introduction and Discussion; Paparella and Passoni's follow-up): grains with
an internal degree of freedom do not collapse.  For every item, one random state of n points on a ring
(:func:`bounce.analysis.gas_rings.ring_points`, velocities scaled by ``speed``) runs twice:

* as rigid points with constant restitution r (:func:`~bounce.analysis.gas_rings.run_rigid_ring`: to collapse,
  cooled by ``cooling`` or ``max_collisions`` per grain) -- the twin whose collapse time the dimers must outlast;
* as dimers (:mod:`bounce.gas.dimer`, exact to rounding) whose single-impact restitution exp(-mu T_xi) is r
  (:func:`~bounce.analysis.gas_rings.mu_of_restitution`), springs at rest, on a ring of circumference 2n (the same
  free length per grain), for ``collisions`` x n collisions: how the run ended, its last time, its smallest interval
  between successive collisions (0: two within half an ulp of t), and its collision rates (collisions per unit time)
  over the first and the last tenth of the collisions.

``speed`` keeps the gas in the paper's very rigid regime: a free time ~1/speed between collisions against a contact
time ~pi, and internal energies far below the 1/8 at which a dimer's masses could pass (the engine's overlap stop).
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from ..analysis.gas_rings import dimer_state, mu_of_restitution, ring_points, run_rigid_ring
from ..gas.model import GasParameters
from ..gas.simulate import GasRun
from .base import ITEM, Sweep, rn_grid, rn_prepare, rn_size

NAME = "dimer-gas-collapse"
STOPS = ("max_events", "t_max", "no_more_events", "overlap", "sticky", "collapse", "root_finder_failed")


def compute(spec: dict, inputs: dict) -> dict:
    seed, speed = int(spec["seed"]), float(spec["speed"])
    m = len(inputs["r"])
    out = {"rigid_outcome": np.zeros(m, dtype=np.int8), "rigid_t_end": np.zeros(m), "rigid_collisions": np.zeros(m),
           "dimer_stop": np.zeros(m, dtype=np.int8), "dimer_collisions": np.zeros(m), "dimer_t_end": np.zeros(m),
           "dimer_min_interval": np.zeros(m), "dimer_rate_early": np.zeros(m), "dimer_rate_late": np.zeros(m)}
    for c in range(m):
        r, n = float(inputs["r"][c]), int(inputs["n"][c])
        x, v = ring_points(n, np.random.default_rng([seed, int(inputs["item"][c])]), speed)
        out["rigid_outcome"][c], out["rigid_collisions"][c], out["rigid_t_end"][c] = run_rigid_ring(
            r, x, v, float(spec["cooling"]), int(spec["check_every"]), int(spec["max_collisions"]))
        d = _rates(r, x, v, int(spec["collisions"]))
        for name, value in d.items():
            out[name][c] = value
    return out


def _rates(r: float, x: np.ndarray, v: np.ndarray, collisions: int) -> dict:
    """The dimer run's outcome, with its collision rates over the first and last tenth of its collisions."""
    n = x.size
    total = collisions * n
    run = GasRun(GasParameters(n, "ring", 0.0, mu_of_restitution(r), ell=2.0 * n), dimer_state(x, v), math.inf, 0)
    parts = []
    while run.events < total and not run.finished:
        rec, k, _ = run.step(min(max(n * 50, 1 << 16), total - run.events))
        parts.append(rec.t[:k].copy())
    t = np.concatenate(parts) if parts else np.zeros(0)
    tenth = max(t.size // 10, 2)
    early = (tenth - 1) / (t[tenth - 1] - t[0]) if t.size >= tenth and t[tenth - 1] > t[0] else math.nan
    late = (tenth - 1) / (t[-1] - t[-tenth]) if t.size >= tenth and t[-1] > t[-tenth] else math.inf
    return {"dimer_stop": STOPS.index(run.stop), "dimer_collisions": t.size / n,
            "dimer_t_end": float(t[-1]) if t.size else 0.0,
            "dimer_min_interval": float(np.diff(t).min()) if t.size > 1 else math.nan,
            "dimer_rate_early": early, "dimer_rate_late": late}


VARIABLES = {
    "rigid_outcome": ((ITEM,), "rigid twin: 0 collapse, 1 cooled by the factor cooling, 2 collision cap", "1", None),
    "rigid_t_end": ((ITEM,), "rigid twin: time of its last collision (its collapse time if it collapsed)", "1", None),
    "rigid_collisions": ((ITEM,), "rigid twin: collisions per grain", "1", None),
    "dimer_stop": ((ITEM,), "dimer gas: why the run ended (0 max_events: its whole budget; 3 overlap, 4 sticky, "
                            "6 root_finder_failed: engine stops)", "1", None),
    "dimer_collisions": ((ITEM,), "dimer gas: collisions per grain", "1", None),
    "dimer_t_end": ((ITEM,), "dimer gas: time of its last collision", "1", None),
    "dimer_min_interval": ((ITEM,), "dimer gas: smallest interval between successive collisions (0: within half an "
                                    "ulp of t)", "1", None),
    "dimer_rate_early": ((ITEM,), "dimer gas: collisions per unit time over its first tenth of collisions", "1", None),
    "dimer_rate_late": ((ITEM,), "dimer gas: collisions per unit time over its last tenth of collisions", "1", None),
}


def finish(ds: xr.Dataset, spec: dict) -> xr.Dataset:
    """The items on the (r, n, sample) grid, with mu(r) and the settings."""
    r, ns, samples = rn_grid(spec)
    out = xr.Dataset(attrs=dict(ds.attrs))
    for name, var in ds.data_vars.items():
        out[name] = xr.Variable(("r", "n", "sample"), var.values.reshape(r.size, ns.size, samples), var.attrs)
    out["mu"] = xr.Variable(("r",), np.array([mu_of_restitution(float(x)) for x in r]),
                            {"long_name": "dimer damping mu with exp(-mu T_xi) = r", "units": "1"})
    out = out.assign_coords(
        r=xr.Variable(("r",), r, {"long_name": "restitution coefficient r", "units": "1"}),
        n=xr.Variable(("n",), ns, {"long_name": "number of grains", "units": "1"}),
        sample=xr.Variable(("sample",), np.arange(samples), {"long_name": "initial state", "units": "1"}))
    out.attrs.update(samples=samples, seed=int(spec["seed"]), speed=float(spec["speed"]),
                     collisions=int(spec["collisions"]), cooling=float(spec["cooling"]))
    return out


def plot(ds: xr.Dataset, spec: dict, outputs) -> None:
    """Per run: the dimer gas's last time against its rigid twin's collapse time, and its late collision rate."""
    import matplotlib.pyplot as plt

    from ..figures.common import WIDTH, save

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(WIDTH, 2.8), constrained_layout=True)
    for i, r in enumerate(ds["r"].values):
        for j, n in enumerate(ds["n"].values):
            collapsed = ds["rigid_outcome"].values[i, j] == 0
            t_rigid, t_dimer = ds["rigid_t_end"].values[i, j], ds["dimer_t_end"].values[i, j]
            a1.loglog(t_rigid[collapsed], t_dimer[collapsed], "o", ms=3, mfc="none", label=f"r={r:g}, n={n}")
            a2.semilogx(ds["dimer_rate_early"].values[i, j], ds["dimer_rate_late"].values[i, j], "o", ms=3, mfc="none",
                        label=f"r={r:g}, n={n}")
    lim = a1.get_xlim()
    a1.plot(lim, lim, "k-", lw=0.6, label="dimer time = rigid collapse time")
    a1.set(xlabel=r"rigid twin's collapse time  [$\sqrt{m/2k}$]",
           ylabel=r"dimers' last collision  [$\sqrt{m/2k}$]")
    a1.set_title("(a) the dimers go on past the rigid collapse", fontsize=8)
    a2.set(xscale="log", yscale="log", xlabel=r"collision rate, first tenth  [$1/\sqrt{m/2k}$]",
           ylabel=r"collision rate, last tenth  [$1/\sqrt{m/2k}$]")
    a2.set_title("(b) the dimers' collision rate does not diverge", fontsize=8)
    for ax in (a1, a2):
        ax.legend(fontsize=5)
    fig.suptitle(f"dimers (exp(-mu T_xi) = r) from the states where rigid points collapse; "
                 f"{int(ds.attrs['collisions'])} collisions per grain each", fontsize=8)
    save(fig, outputs)


def estimated_memory_mb(spec: dict) -> int:
    """The event times of one run: 8 bytes x collisions x the most grains, plus the interpreter."""
    return 300 + int(8 * int(spec["collisions"]) * max(spec["n"]) / 2**20)


SWEEP = Sweep(NAME, "Dimer gas where the rigid gas collapses: time goes on, collision rates stay finite (beyond the paper)",
              rn_size, rn_prepare, compute, VARIABLES, finish, plot, estimated_memory_mb)

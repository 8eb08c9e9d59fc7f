# ---
# jupyter:
#   jupytext:
#     formats: py:percent
#     text_representation:
#       extension: .py
#       format_name: percent
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # bounce: overview of the pipeline's results
#
# Browse what `snakemake --cores 2` wrote to `results/`: the per-scene event datasets (netCDF),
# the data behind each figure of Cherubini, Metafune & Paparella, *On the Stopping Time of a
# Bouncing Ball*, and a simulation rerun inline with a changed parameter.
#
# Set `BOUNCE_RESULTS` to read another results folder (the tests point it at the CI-sized run).

# %%
import os
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import xarray as xr

from bounce import Parameters, State, simulate
from bounce.io import sample_dataset, to_dataset

RESULTS = Path(os.environ.get("BOUNCE_RESULTS", Path.cwd().parent / "results"))
DATA = RESULTS / "data"
sorted(p.name for p in DATA.glob("*.nc"))

# %% [markdown]
# ## One scene: the free fall of fig. rigid-fall
# Each dataset has one record per event (impact, grazing, sticky start, detach) with the state
# just after it; units and long names follow CF conventions, provenance sits in the attributes.

# %%
fall = xr.open_dataset(DATA / "rigid-fall.nc")
print({k: fall.attrs[k] for k in ("gamma", "mu", "x0", "y0", "stop_reason", "bounce_version", "git_commit")})
fall[["t", "tau", "xdot", "y_minus_yeq", "energy_excess"]].to_dataframe().head(10)

# %% [markdown]
# The trajectory between events is sampled in closed form from the records alone (no stored dense output):

# %%
t = np.linspace(0.0, float(fall["t"][-1]), 20000)
s = sample_dataset(fall, t)
fig, ax = plt.subplots(figsize=(8, 3))
ax.plot(t, s["y"], label="y(t)")
ax.plot(t, s["x"], label="x(t)")
ax.plot(fall["t"], 0 * fall["t"], "k.", ms=3, label="impacts")
ax.set_xlabel("t")
ax.legend();

# %% [markdown]
# ## Restitution coefficient (fig. rest-coeff): r_n = f_{n+1}/f_n, f_n = tau_{2n}

# %%
rc = xr.open_dataset(DATA / "rest-coeff.nc")
f = rc["tau"].values[0::2]
r = f[2:41] / f[1:40]
mu = rc.attrs["mu"]
print("first r_n:", np.round(r[:5], 5), " exp(-mu T_xi) =", np.exp(-mu * np.pi / np.sqrt(1 - mu**2)))

# %% [markdown]
# ## Asymptotic laws (Theorem main_thm): n tau_n mu/3 -> 1

# %%
for name in ("asymptotic-underdamped", "asymptotic-overdamped"):
    ds = xr.open_dataset(DATA / f"{name}.nc")
    n = ds["event"].values
    law = n[1:] * ds["tau"].values[1:] * ds.attrs["mu"] / 3
    print(f"{name}: events simulated {ds.attrs['n_events_simulated']}, n tau_n mu/3 at the last = {law[-1]:.6f}")

# %% [markdown]
# ## Sticky solutions (section 8.2)

# %%
conv = xr.open_dataset(DATA / "sticky-convergence.nc")
conv.to_dataframe()

# %% [markdown]
# ## Change a parameter and rerun one simulation inline
# Here: the drop of fig. rigid-fall with ten times the damping.  The same call is what the
# pipeline's `simulate` rule runs for every scene of `config/config.yaml`.  With this damping the lower
# mass chatters on the floor late in the drop: the 2,000 events of `max_events` are spent at t = 340,
# before `t_max` = 420 (`stop_reason` says which stop was met), and the curves are drawn up to the last
# event (`t_valid`); raise `max_events` to go further.

# %%
p = Parameters(gamma=0.01, mu=0.1)
traj = simulate(p, State.from_psi_xi(6.0, 0.0, 0.0, 0.0), max_events=2000, t_max=420.0)
ds = to_dataset(traj)
print(ds.attrs["stop_reason"], ds.sizes["event"], "events up to t =", round(float(ds.attrs["t_valid"]), 1),
      "; E - E_m at the end:", float(ds["energy_excess"][-1]))
t = np.linspace(0.0, float(ds.attrs["t_valid"]), 20000)
s = sample_dataset(ds, t)
fig, ax = plt.subplots(figsize=(8, 3))
ax.plot(t, s["y"], label="y(t), mu = 0.1")
ax.plot(t, s["x"], label="x(t), mu = 0.1")
ax.set_xlabel("t")
ax.legend();

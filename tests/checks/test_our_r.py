"""Claim group our-r: the erratum row our-r-centre-of-mass (eq. our-r's small-u branch read in the rigid ball's own
speed) flips for the corrected coefficient, 1 - 2 mu u/(3 gamma); our-r-band is refuted by a wrong large-u branch
(its band against the predicted edges); the one policy that decides a drop's band (band_structure), on the scene and
on every mu of the sweep (band-across-mu)."""

from __future__ import annotations

import functools
from pathlib import Path

import numpy as np
import xarray as xr

from bounce.checks import our_r
from bounce.checks.base import NOT_CHECKABLE, NOT_REPRODUCED, REPRODUCED
from bounce.claims_cli import group_spec
from bounce.scenes import scene_dataset

ROOT = Path(__file__).resolve().parents[2]
#: the scene rest of tests/checks/test_claims.py: fig. rest-coeff's drop, complete records
REST = {"gamma": 1e-5, "mu": 0.01, "initial": {"psi": 0.25, "psidot": 0.0, "xi": 0.0, "xidot": 0.0},
        "stop": {"events": 200000}}


def _spec():
    return group_spec("our-r", {}, ROOT)


@functools.cache
def _measured():
    return our_r.measure(_spec(), [scene_dataset(REST, "rest")])


def test_small_u_branch_in_the_centre_of_mass_speed():
    m, sp = _measured(), _spec()
    (printed,) = our_r.our_r_centre_of_mass(m, sp).values()
    (corrected,) = our_r.centre_of_mass_row(m, sp, 2.0, "corrected").values()
    assert printed.verdict == NOT_REPRODUCED and corrected.verdict == REPRODUCED


def _band(ds):
    sp = _spec()
    (v,) = our_r.our_r_band(our_r.measure(sp, [ds]), sp).values()
    return v


def test_our_r_band_flips_when_the_large_u_branch_is_off():
    """Landing speeds of the double-impact bounces 0.3 % lower per bounce (r ~ 0.966 instead of 0.969, 1 - r 10 % off):
    the band reaches past its predicted upper edge gamma (ln(1/thr) + 1)/(2 mu) to the largest simulated speed, so
    the row is refuted, not left not checkable for want of bounces above the band."""
    ds = scene_dataset(REST, "rest")
    assert _band(ds).verdict == REPRODUCED
    xd = ds["xdot"].values.copy()
    m = np.arange(1, 60)
    xd[2 * m - 2] *= 0.997**m
    ds["xdot"] = (ds["xdot"].dims, xd, ds["xdot"].attrs)
    assert _band(ds).verdict == NOT_REPRODUCED


#: one drop's band, in units of u_c = 1: [u1, u2] = [1e-3, 10] against predicted edges [0.9e-3, 1.1e-3], [5, 20]
BAND = dict(u1=1e-3, u2=10.0, uc=1.0, small=(0.9e-3, 1e-3, 1.1e-3), large=(5.0, 20.0), below=100, above=100,
            u_min=1e-5, u_max=30.0, least=10)


def test_band_structure_decides_only_a_drop_that_samples_past_both_predicted_edges():
    assert our_r.band_structure(**BAND) == (True, True, True)
    # the drop starts below the predicted upper edge: its band is not decided, holding or not
    assert our_r.band_structure(**dict(BAND, u_max=15.0, u2=15.0, above=0)) == (True, False, False)
    assert our_r.band_structure(**dict(BAND, u_max=15.0, u2=3.0)) == (False, False, False)
    # sampled, but a holding band with too few bounces beyond an edge: not decided; a failing one is
    assert our_r.band_structure(**dict(BAND, above=3)) == (True, True, False)
    assert our_r.band_structure(**dict(BAND, u2=25.0, above=3)) == (False, True, True)
    # the band must straddle u_c
    assert our_r.band_structure(**dict(BAND, uc=0.5e-3))[0] is False
    # no bounce with the spring term above thr - thr^2: no predicted lower edge in the drop, not decided
    assert our_r.band_structure(**dict(BAND, small=(np.inf, np.inf, np.inf)))[1:] == (False, False)


def _sweep(**changes) -> xr.Dataset:
    """A gathered our-r-band file of three drops (mu = 0.01, 0.02, 0.05) whose bands are BAND's scaled by u_c."""
    mu = np.array([0.01, 0.02, 0.05])
    uc = np.array([9.3e-5, 9.2e-5, 8.9e-5])
    values = {"u1": BAND["u1"], "u2": BAND["u2"], "u_min": BAND["u_min"], "u_max": BAND["u_max"],
              "u1_predicted_low": BAND["small"][0], "u1_predicted": BAND["small"][1],
              "u1_predicted_high": BAND["small"][2], "u2_predicted_low": BAND["large"][0],
              "u2_predicted_high": BAND["large"][1]}
    data = {k: ("mu", v * uc) for k, v in values.items()}
    data.update(u_c=("mu", uc), bounces_below_band=("mu", np.full(3, 100)), bounces_above_band=("mu", np.full(3, 100)))
    ds = xr.Dataset(data, coords={"mu": mu}, attrs={"sweep": "our-r-band", "gamma": 1e-5, "psi0": 0.25,
                                                     "events": 200000, "our_r_threshold": 0.05})
    for k, v in changes.items():
        ds[k] = ("mu", np.asarray(v, dtype=ds[k].dtype))
    return ds


def _across(ds):
    sp = _spec()
    (v,) = our_r.band_across_mu(our_r.measure(sp, [ds]), sp).values()
    return v


def test_band_across_mu_is_judged_for_every_mu():
    """judge_every: every decided mu holds -> reproduced; one decided mu fails -> not reproduced; one mu whose drop
    does not reach past the predicted upper edge (the slightest damping: u2 = gamma (ln 20 + 1)/(2 mu) above the
    drop's first landing) -> not checkable, however its band looks."""
    uc = _sweep()["u_c"].values
    assert _across(_sweep()).verdict == REPRODUCED
    assert _across(_sweep(u2=[10.0 * uc[0], 25.0 * uc[1], 10.0 * uc[2]])).verdict == NOT_REPRODUCED
    unsampled = _across(_sweep(u_max=[15.0 * uc[0], 30.0 * uc[1], 30.0 * uc[2]], u2=[15.0 * uc[0], 10 * uc[1], 10 * uc[2]]))
    assert unsampled.verdict == NOT_CHECKABLE and "mu = 0.01: not decided" in unsampled.measured

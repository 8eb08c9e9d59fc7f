"""Figure helpers: the one number format of figure texts, and figure files readable like the rest."""

import os

import pytest

from bounce.figures.common import plt, save, tex_num


@pytest.mark.parametrize("value, text", [
    (0.01, "0.01"), (2.0, "2"), (1e-5, "10^{-5}"), (-1e-5, "-10^{-5}"), (2.5e-5, r"2.5\times10^{-5}"),
    (200000, r"2\times10^{5}"), (0.969, "0.969"),
])
def test_tex_num_never_prints_e_notation(value, text):
    assert tex_num(value) == text


def test_saved_figures_follow_the_umask_not_mkstemp(tmp_path):
    old = os.umask(0o022)
    try:
        fig, ax = plt.subplots()
        ax.plot([0, 1], [0, 1])
        outs = [tmp_path / "fig-x.png", tmp_path / "fig-x.pdf"]
        save(fig, outs)
    finally:
        os.umask(old)
    for out in outs:
        assert out.stat().st_mode & 0o777 == 0o644
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fig-x.pdf", "fig-x.png"]  # no temporary left


@pytest.mark.parametrize("mu", [0.01, 0.03, 0.1])
def test_rigid_fall_inset_is_derived_from_the_run(mu):
    """The dashed box of fig. rigid-fall frames a landing of this run with several impacts (a fixed box was
    empty once mu changed); for the paper's gamma = mu = 0.01 it is the paper's box, t = 336-352."""
    import numpy as np

    from bounce import Parameters, State, simulate
    from bounce.figures.trajectories import _landing_box
    from bounce.io import sample_dataset, to_dataset
    from bounce.kinds import IMPACT

    ds = to_dataset(simulate(Parameters(0.01, mu), State.from_psi_xi(6.0, 0.0, 0.0, 0.0), max_events=100000,
                             t_max=420.0))
    box = _landing_box(ds, 0.0, 420.0)
    (t0, t1), (y0, y1) = box["t"], box["y"]
    t, kind = ds["t"].values, ds["kind"].values
    assert np.count_nonzero((kind == IMPACT) & (t >= t0) & (t <= t1)) >= 2
    x = sample_dataset(ds, np.linspace(t0, t1, 2000))["x"]
    assert y0 < 0 < y1 and np.any((x > 0.2 * y1) & (x < y1))  # the hops are drawn inside the box
    if mu == 0.01:
        assert abs(t0 - 336.0) < 1.0 and abs(t1 - 352.0) < 1.0

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

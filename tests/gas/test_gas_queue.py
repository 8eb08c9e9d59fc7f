"""The gas engines' event queue (bounce.gas.queue): the top is the first key in the order (hi, lo, slot)."""

import numpy as np
import pytest

from bounce.gas.queue import build, empty_queue, top, update


@pytest.mark.parametrize("m", [1, 2, 3, 5, 16, 17, 100])
def test_top_is_the_minimum_after_every_update(m):
    """Random updates with many ties of hi, of (hi, lo) and with inf keys: the top is always the minimum of
    (hi, lo, slot) over all slots, and a tree rebuilt from the keys is the tree the updates left."""
    rng = np.random.default_rng(m)
    tree, khi, klo = empty_queue(m)
    assert top(tree, khi) == 0
    for _ in range(2000):
        s = int(rng.integers(m))
        hi = float(rng.integers(0, 4)) if rng.random() < 0.5 else float(rng.random())
        lo = float(rng.integers(-1, 2)) * 1e-17
        if rng.random() < 0.1:
            hi, lo = np.inf, 0.0
        update(s, hi, lo, tree, khi, klo)
        assert top(tree, khi) == min((khi[k], klo[k], k) for k in range(m))[2]
    rebuilt = tree.copy()
    build(rebuilt, khi, klo)
    assert np.array_equal(rebuilt[1:], tree[1:])

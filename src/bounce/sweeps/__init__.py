"""Parameter studies at scale: one module per sweep, sharded by the pipeline, gathered into one netCDF.

``registry()`` maps each sweep's name (its key under ``sweeps:`` in config/config.yaml) to its
:class:`~bounce.sweeps.base.Sweep`.  See :mod:`bounce.sweeps.base` for the contract.
"""

from __future__ import annotations

import functools

from .._registry import discover, find
from .base import Sweep


@functools.cache
def registry() -> dict[str, Sweep]:
    return discover(__name__, __path__, "SWEEP", Sweep)


def get(name: str) -> Sweep:
    """The sweep ``name``, importing only its own module (what a shard, gather or figure job needs)."""
    return find(__name__, __path__, "SWEEP", Sweep, name)

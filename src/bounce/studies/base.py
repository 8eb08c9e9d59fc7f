"""The contract of a study (one module of :mod:`bounce.studies`, discovered by its ``STUDY``, or ``STUDIES``
for a module holding a family):

1. ``build(spec) -> xr.Dataset`` makes the study's dataset from ``config(validated config)``, its slice;
2. ``plot(ds, spec, outputs)`` draws its figure from that dataset alone;
3. ``scenes(config)`` names the scene datasets it reads (declared inputs of its rule, their paths in the slice);
4. ``caption`` says what its figure shows (every study is beyond the paper);
5. ``timed``: it measures CPU time (budgets, the cheapest model), so its dataset and figure are timing files,
   not byte-reproducible by design (its CPU seconds also go to results/timing/methods/<study>-cpu.nc).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable


@dataclass(frozen=True)
class Study:
    """One study: ``build(spec)`` makes the dataset, ``plot(ds, spec, outputs)`` its figure (contract above)."""

    name: str
    build: Callable
    plot: Callable
    config: Callable[[dict], dict]
    caption: str
    scenes: Callable[[dict], list] = lambda config: []
    timed: bool = False


def study_slice(methods: dict, kind: str, block: str | None = None) -> dict:
    """The slice of ``config['methods']`` one study of :mod:`bounce.studies.compare` reads: its block
    (``block``, default ``kind``) under the key ``kind`` and the one scene it names."""
    spec = methods[block or kind]
    return {"scenes": {spec["scene"]: methods["scenes"][spec["scene"]]}, kind: spec}

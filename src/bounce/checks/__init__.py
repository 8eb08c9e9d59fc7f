"""The paper's claims, one module per claim group; a group is discovered by its ``CHECK`` attribute.

Each group lists its claims in ``CLAIMS`` (small functions, or declarative entries, with their kind
and subject as data); see :mod:`bounce.checks.base` for the contract.  No module here imports another.
"""

from __future__ import annotations

from pathlib import PurePosixPath

from .._registry import discover, find
from ..paths import sticky_dataset
from .base import Check

#: the named group of datasets a claim group may list in its ``inputs``: the eps = 0 run and the eps_convergence
#: runs of config ``sticky`` (rule sticky_run)
STICKY_RUNS = "sticky-runs"


def registry() -> dict[str, Check]:
    """name -> Check for every module of this package that defines ``CHECK``."""
    return discover(__name__, __path__, "CHECK", Check)


def get(name: str) -> Check:
    """The claim group ``name``, importing only its own module (what a pipeline job needs)."""
    return find(__name__, __path__, "CHECK", Check, name)


def input_files(name: str, config: dict, data: str = "results/data", sweeps: str = "results/sweeps") -> list[str]:
    """The files claim group ``name`` reads, in order: its declared inputs (config ``checks.<name>.inputs``: a
    scene is results/data/<scene>.nc, ``sticky-runs`` the sticky runs, a sweep its gathered file
    results/sweeps/<sweep>.nc), then its experiments (results/data/checks/<name>/<experiment>.nc, rule
    check_experiment).  The rule check (workflow/rules/checks.smk) and ``python -m bounce check`` use it."""
    data, sweeps = PurePosixPath(data), PurePosixPath(sweeps)
    files = []
    for item in config["checks"][name]["inputs"]:
        if item == STICKY_RUNS:
            eps = [0.0] + [float(e) for e in config["sticky"]["eps_convergence"] if float(e) != 0.0]
            files += [data / f"{sticky_dataset(e)}.nc" for e in eps]
        elif item in config.get("sweeps", {}):
            files.append(sweeps / f"{item}.nc")
        else:
            files.append(data / f"{item}.nc")
    files += [data / "checks" / name / f"{e.name}.nc" for e in registry()[name].experiments]
    return [str(f) for f in files]

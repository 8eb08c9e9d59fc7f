"""The contract of a validation check (issue: every checkable claim of the paper).

A check module in ``bounce.checks`` defines ``CHECK = Check(name, run, plot)``:

1. ``run(spec, inputs) -> xr.Dataset``: ``spec`` is its config slice
   (``config["checks"][name]``), ``inputs`` the scene datasets it names.  It
   returns the measured numbers as variables (units, long_name) *and* the
   verdict table made by :func:`verdict_dataset`.
2. ``plot(ds, spec, outputs)`` draws the figure that backs the verdicts from the
   dataset alone, saving to every path in ``outputs`` (PNG and PDF).
3. Each verdict compares a measured number with the paper's expectation under a
   stated tolerance whose origin is said in ``tolerance`` (physics or a measured
   error budget, never "what passes").  ``not checkable`` says why in ``measured``.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, fields
from typing import Callable

import numpy as np
import xarray as xr

REPRODUCED = "reproduced"
NOT_REPRODUCED = "not reproduced"
NOT_CHECKABLE = "not checkable"
VERDICTS = (REPRODUCED, NOT_REPRODUCED, NOT_CHECKABLE)


@dataclass(frozen=True)
class Verdict:
    """One row of the validation table."""

    claim: str
    paper_ref: str  # theorem / lemma / eq. label of the paper
    computed: str  # what was computed, in words
    expected: str
    measured: str
    tolerance: str  # value and where it comes from
    verdict: str

    def __post_init__(self) -> None:
        if self.verdict not in VERDICTS:
            raise ValueError(f"verdict must be one of {VERDICTS}, got {self.verdict!r}")


@dataclass(frozen=True)
class Check:
    name: str
    run: Callable
    plot: Callable
    title: str = ""


def judge(ok: bool) -> str:
    return REPRODUCED if ok else NOT_REPRODUCED


def verdict_dataset(verdicts: list[Verdict], data: xr.Dataset | None = None, title: str = "") -> xr.Dataset:
    """The check's numbers plus its verdicts as string variables on the dimension ``claim``."""
    ds = data.copy() if data is not None else xr.Dataset()
    for f in fields(Verdict):
        ds[f"verdict_{f.name}"] = ("claim", np.array([getattr(v, f.name) for v in verdicts], dtype=object),
                                   {"long_name": f"validation table: {f.name.replace('_', ' ')}", "units": "1"})
    ds.attrs.update(title=title or ds.attrs.get("title", ""), Conventions="CF-1.10")
    return ds


def read_verdicts(ds: xr.Dataset) -> list[Verdict]:
    """The verdict rows stored by :func:`verdict_dataset`."""
    n = ds.sizes.get("claim", 0)
    return [Verdict(**{f.name: str(ds[f"verdict_{f.name}"].values[i]) for f in fields(Verdict)}) for i in range(n)]


def as_dict(v: Verdict) -> dict:
    return asdict(v)

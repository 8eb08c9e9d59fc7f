"""Claims as a list: the contract of a claim group (one module of ``bounce.checks``).

Modelled on scikit-learn's estimator checks: one small function per property, collected in a
list, each returning one verdict (or one per input scene), with what the claim *is* kept as data:

* ``kind``: ``paper`` (a statement of the paper), ``erratum`` (the paper's text as printed, with
  the corrected form in the row; its verdict says whether the printed form holds), ``beyond``
  (ours: rates, corrected forms, consequences the paper does not state), ``self-test`` (the
  solver's own classifier or error model) or ``identity`` (a definition or a consistency identity: a
  statement no input could contradict, e.g. a series against its own closed form; it has no falsifier,
  says why in ``why_identity``, and is never counted as reproduced);
* ``subject``: the theorem, lemma, figure or equation the claim backs (an id of config
  ``report.subjects``); the report groups by it;
* ``known_failure``: why the verdict is expected to be ``not reproduced`` (an erratum, or a
  statement of the paper the dynamics contradicts), empty otherwise.  Tests read it;
* ``statement``: when several claims (of one group or several) test one statement of the paper, the key they share
  (e.g. ``Xddot-limit``: on the drops, over the atlas, through the proof's identities); the report counts the
  statement once;
* ``falsifier``: a :class:`Falsifier`, the perturbation of the claim's inputs under which its verdict
  must flip (every kind but ``identity`` declares one; tests/checks/test_claims.py::test_falsifier_flips
  runs each, and fails when the verdict stays).

A module defines ``CHECK = Check(name, measure, CLAIMS, plot, title)``:

1. ``measure(spec, inputs) -> m``: ``spec`` is its config slice (``config["checks"][name]``, schema
   defaults applied), ``inputs`` the datasets it names.  ``m`` carries what the claims need and,
   as ``m.data``, the measured numbers as an ``xr.Dataset`` (units, long_name) for the figure.
   Expensive parts may be lazy (``functools.cached_property``) so that one claim runs alone.
2. each :class:`Claim` in ``CLAIMS``: ``judge(m, spec)`` returns a :class:`Verdict` or a dict
   label -> Verdict (one per scene); each verdict compares a measured number with the paper's
   expectation under a stated tolerance whose origin is said in ``tolerance`` (physics or a
   measured error budget, never "what passes"); ``not checkable`` says why in ``measured``.
3. ``plot(ds, spec, outputs)`` draws the figure behind the verdicts from the dataset alone; a group whose evidence
   is exact algebra has no figure (``plot`` None: no curve to draw, and the rows say all a table image would).
4. every claim can fail: its :class:`Falsifier` doctors the inputs (records of a wrong law, a shifted parameter,
   the printed form in place of the corrected one) so that its verdict flips (:func:`falsify`, :func:`unflipped`);
   a claim no input could contradict is of kind ``identity`` and says why.

No module of ``bounce.checks`` imports another: shared closed forms live in :mod:`bounce.analysis.theory`,
fitting in :mod:`bounce.analysis.fitting`, mpmath in :mod:`bounce.analysis.reference`, experiments shared by several
claim groups in :mod:`bounce.analysis.anomalies`.

Every experiment is in the graph (the probe budget).  A claim group simulates nothing long itself:

* a scene it reads is named in config ``checks.<name>.inputs`` (``results/data/<scene>.nc``), and so is a
  sweep's gathered file (``results/sweeps/<sweep>.nc``, config ``sweeps``);
* a long simulation of its own (a Monte Carlo, runs followed to rest, a long asymptotic run) is an
  :class:`Experiment` in ``Check.experiments``: run by the rule ``check_experiment`` of
  workflow/rules/checks.smk into ``results/data/checks/<name>/<experiment>.nc`` from the config keys it
  declares (so a config edit reruns exactly it), and read by ``measure`` like any other input;
* inside a claim only *probes* remain: constructed states followed for at most :data:`PROBE_EVENTS`
  events per :func:`bounce.simulate.simulate` call (a classifier probe, one sticky phase, the restart of
  a thinned record).  tests/checks/test_claims.py::test_probe_budget counts the events of every call of every
  group on small inputs and fails above the budget.

``measure`` tells its inputs apart with :func:`split_inputs`: scenes in declared order, the others by the
name in their attributes (``sweep`` or ``experiment``).
"""

from __future__ import annotations

import copy
import sys
from dataclasses import asdict, dataclass, fields, replace
from typing import Callable

import numpy as np
import xarray as xr

REPRODUCED = "reproduced"
NOT_REPRODUCED = "not reproduced"
NOT_CHECKABLE = "not checkable"
VERDICTS = (REPRODUCED, NOT_REPRODUCED, NOT_CHECKABLE)

PAPER, ERRATUM, BEYOND, SELF_TEST, IDENTITY = "paper", "erratum", "beyond", "self-test", "identity"
KINDS = (PAPER, ERRATUM, BEYOND, SELF_TEST, IDENTITY)


@dataclass(frozen=True)
class Verdict:
    """One row of the validation table; ``claim_id``, ``kind`` and ``subject`` are stamped by :meth:`Check.verdicts`."""

    claim: str
    paper_ref: str  # theorem / lemma / eq. label of the paper
    computed: str  # what was computed, in words
    expected: str
    measured: str
    tolerance: str  # value and where it comes from
    verdict: str
    claim_id: str = ""
    kind: str = ""
    subject: str = ""
    statement: str = ""  # the paper statement several claims test together ("" = the claim's own id)

    def __post_init__(self) -> None:
        if self.verdict not in VERDICTS:
            raise ValueError(f"verdict must be one of {VERDICTS}, got {self.verdict!r}")
        if self.kind and self.kind not in KINDS:
            raise ValueError(f"kind must be one of {KINDS}, got {self.kind!r}")


@dataclass(frozen=True)
class Falsifier:
    """What must flip a claim's verdict: the claim can fail, and this shows it.

    ``what`` says the perturbation in words (a wrong law, a shifted parameter, a corrupted record, the printed form in
    place of the corrected one).  It is applied by one of, or both:

    * ``doctor(inputs, spec) -> (inputs, spec)``: the group's input datasets (in the order ``measure`` gets them) and
      config slice, perturbed; it copies what it changes, never modifies its arguments;
    * ``patch() -> {name: replacement}``: names of the claim's own module (its group's) swapped while the group measures and the
      claim judges (a printed formula in place of the corrected one, for claims that read no data).

    ``labels``: the per-scene rows that must flip (empty: every row the true inputs decide).  A row flips when
    ``reproduced`` becomes ``not reproduced``, or, for a row whose true verdict is ``not reproduced`` (an erratum, a
    known failure), the other way round: the doctored inputs follow the printed form.  See :func:`falsify`.
    """

    what: str
    doctor: Callable | None = None
    patch: Callable | None = None
    labels: tuple = ()

    def __post_init__(self) -> None:
        if not self.what.strip() or (self.doctor is None and self.patch is None):
            raise ValueError("a falsifier says what it perturbs and how (doctor or patch)")


@dataclass(frozen=True)
class Claim:
    """One checkable property: its id (unique in its group), kind, subject, the function that judges it and its
    falsifier (or, for kind ``identity``, why it has none)."""

    id: str
    kind: str
    subject: str
    judge: Callable
    known_failure: str = ""
    falsifier: Falsifier | None = None
    why_identity: str = ""
    statement: str = ""

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"claim {self.id}: kind must be one of {KINDS}, got {self.kind!r}")
        if self.kind == ERRATUM and not self.known_failure:
            raise ValueError(f"claim {self.id}: an erratum says what is wrong in known_failure")
        if (self.kind == IDENTITY) != bool(self.why_identity.strip()):
            raise ValueError(f"claim {self.id}: an identity (and only an identity) says in why_identity why no input "
                             "could falsify it")
        if self.kind == IDENTITY and self.falsifier is not None:
            raise ValueError(f"claim {self.id}: an identity has no falsifier")


def claim(registry: list, id: str, kind: str, subject: str, known_failure: str = "",
          falsifier: Falsifier | None = None, why_identity: str = "", statement: str = "") -> Callable:
    """Decorator: append the function as a :class:`Claim` to ``registry`` (the module's ``CLAIMS``)."""
    def add(fn):
        registry.append(Claim(id, kind, subject, fn, known_failure, falsifier, why_identity, statement))
        return fn
    return add


def recorded(registry: list, id: str, kind: str, subject: str, known_failure: str = "",
             falsifier: Falsifier | None = None, why_identity: str = "", statement: str = "") -> None:
    """A declarative claim: its verdict row is recorded by the group's measurement in ``m.rows[id]`` (a Verdict, or
    a dict label -> Verdict; absent: no row).  For groups whose formulas share one computation step by step."""
    def from_measurement(m, spec):
        return m.rows.get(id, {})
    from_measurement.__name__ = id.replace("-", "_")
    registry.append(Claim(id, kind, subject, from_measurement, known_failure, falsifier, why_identity, statement))


#: the most events one simulate() call inside a claim may follow (a constructed probe); longer runs are
#: experiments or scenes, produced by a rule (see the module docstring)
PROBE_EVENTS = 20


@dataclass(frozen=True)
class Experiment:
    """A long simulation of a claim group, produced by its own rule as netCDF and read back by ``measure``.

    ``run(spec)`` gets the group's config slice restricted to ``keys`` and returns the dataset (its
    attribute ``experiment`` names it, see :func:`split_inputs`)."""

    name: str
    keys: tuple
    run: Callable

    def spec(self, group_spec: dict) -> dict:
        """The part of the group's config slice this experiment depends on."""
        return {k: group_spec[k] for k in self.keys}

    def dataset(self, group_spec: dict) -> xr.Dataset:
        ds = self.run(self.spec(group_spec))
        ds.attrs["experiment"] = self.name
        return ds


def split_inputs(inputs) -> tuple[list, dict]:
    """(scene datasets in declared order, {name: dataset} of sweeps' gathered files and experiments)."""
    scenes, named = [], {}
    for ds in inputs:
        key = ds.attrs.get("experiment") or ds.attrs.get("sweep")
        if key:
            named[str(key)] = ds
        else:
            scenes.append(ds)
    return scenes, named


class Measurements:
    """Base of a claim group's ``measure`` (point 1 of the contract) for groups whose claims read different parts:
    ``Measurements(spec, inputs)`` keeps the config slice ``spec`` and the inputs split by :func:`split_inputs`
    (``scenes``, ``named``); a subclass adds each measurement as a :func:`functools.cached_property` (one claim
    runs only what it reads) and ``data``, the dataset of the figure.  The subclass itself is the ``measure``
    passed to :class:`Check`."""

    def __init__(self, spec: dict, inputs=()):
        self.spec = spec
        self.scenes, self.named = split_inputs(inputs)


@dataclass(frozen=True)
class Check:
    """A claim group: its measurements, its claims in order, its figure, the experiments it reads."""

    name: str
    measure: Callable
    claims: tuple
    plot: Callable | None
    title: str = ""
    experiments: tuple = ()

    def experiment(self, name: str) -> Experiment:
        return next(e for e in self.experiments if e.name == name)

    def claim_ids(self) -> list[str]:
        return [f"{self.name}/{c.id}" for c in self.claims]

    def verdicts(self, m, spec: dict, only: str | None = None) -> list[Verdict]:
        """The verdict rows of every claim (or of the claim with id ``only``), stamped with id, kind, subject."""
        rows = []
        for c in self.claims:
            if only is not None and c.id != only:
                continue
            out = c.judge(m, spec)
            labelled = out.items() if isinstance(out, dict) else [(None, out)]
            for label, v in labelled:
                cid = f"{self.name}/{c.id}" + (f"[{label}]" if label is not None else "")
                rows.append(replace(v, claim_id=cid, kind=c.kind, subject=c.subject, statement=c.statement))
        return rows

    def run(self, spec: dict, inputs) -> xr.Dataset:
        """Measure, judge every claim, and return the numbers with the verdict table."""
        m = self.measure(spec, inputs)
        return verdict_dataset(self.verdicts(m, spec), m.data, title=self.title)


def _scene(ds) -> bool:
    return not (ds.attrs.get("experiment") or ds.attrs.get("sweep"))


def on_scenes(fn: Callable) -> Callable:
    """A falsifier's ``doctor``: ``fn(ds) -> ds`` applied to a deep copy of every scene among the inputs (the sweeps'
    files and the experiments kept); it returns the dataset, changed or not."""
    def doctor(inputs, spec):
        return [fn(ds.copy(deep=True)) if _scene(ds) else ds for ds in inputs], spec
    return doctor


def on_named(name: str, fn: Callable) -> Callable:
    """A falsifier's ``doctor``: ``fn(ds) -> ds`` applied to a deep copy of the sweep's gathered file or the experiment
    called ``name`` among the inputs."""
    def doctor(inputs, spec):
        if not any(ds.attrs.get("experiment") == name or ds.attrs.get("sweep") == name for ds in inputs):
            raise ValueError(f"falsifier: no input named {name!r}")
        return [fn(ds.copy(deep=True)) if name in (ds.attrs.get("experiment"), ds.attrs.get("sweep")) else ds
                for ds in inputs], spec
    return doctor


def on_input(i: int, fn: Callable) -> Callable:
    """A falsifier's ``doctor``: ``fn(ds) -> ds`` applied to a deep copy of input ``i`` (in the order ``measure`` gets
    them), for a group whose scenes play different parts."""
    def doctor(inputs, spec):
        inputs = list(inputs)
        inputs[i] = fn(inputs[i].copy(deep=True))
        return inputs, spec
    return doctor


def on_spec(fn: Callable) -> Callable:
    """A falsifier's ``doctor``: ``fn(spec) -> spec`` on a deep copy of the group's config slice."""
    def doctor(inputs, spec):
        return list(inputs), fn(copy.deepcopy(spec))
    return doctor


def with_variable(ds: xr.Dataset, name: str, values) -> xr.Dataset:
    """``ds`` with variable ``name`` replaced by ``values`` (same dims and attributes): for doctoring records."""
    ds[name] = (ds[name].dims, np.asarray(values), ds[name].attrs)
    return ds


def rise_once(ds: xr.Dataset, name: str = "energy_excess", at: int = 500, by: float = 1e-12) -> xr.Dataset:
    """``ds`` with record ``at`` of ``name`` raised ``by`` (relative) above its predecessor: a quantity that must never
    rise, rising once (the falsifier of the monotonicity claims, e.g. E - E_m)."""
    v = ds[name].values.copy()
    v[at] = v[at - 1] * (1.0 + by)
    return with_variable(ds, name, v)


def _label(v: Verdict) -> str:
    return v.claim_id[v.claim_id.index("[") + 1:-1] if "[" in v.claim_id else ""


def falsify(check: Check, claim_id: str, spec: dict, inputs) -> list[Verdict]:
    """The rows of claim ``claim_id`` of ``check`` judged on its falsifier's doctored inputs (the patches of the
    group's module applied only while the group measures and judges)."""
    c = next(c for c in check.claims if c.id == claim_id)
    f = c.falsifier
    inputs, spec = f.doctor(list(inputs), spec) if f.doctor else (list(inputs), spec)
    module = sys.modules[check.measure.__module__]  # the group's module: its measure and claims live there
    swaps = f.patch() if f.patch else {}
    saved = {name: getattr(module, name) for name in swaps}
    try:
        for name, value in swaps.items():
            setattr(module, name, value)
        return check.verdicts(check.measure(spec, inputs), spec, only=claim_id)
    finally:
        for name, value in saved.items():
            setattr(module, name, value)


def unflipped(true_rows: list[Verdict], doctored_rows: list[Verdict], labels=()) -> list[str]:
    """Why the doctored rows do not falsify the true ones (empty: they do).  Each row the true inputs decide (or each
    row named in ``labels``) must turn from reproduced to not reproduced, or from not reproduced to reproduced."""
    flip = {REPRODUCED: NOT_REPRODUCED, NOT_REPRODUCED: REPRODUCED}
    doctored = {_label(v): v.verdict for v in doctored_rows}
    wanted = [v for v in true_rows if (_label(v) in labels if labels else v.verdict in flip)]
    if not wanted:
        return [f"no row to flip: the true rows are {[(v.claim_id, v.verdict) for v in true_rows]}"]
    problems = []
    for v in wanted:
        got = doctored.get(_label(v), "no row")
        if v.verdict not in flip or got != flip[v.verdict]:
            problems.append(f"{v.claim_id}: {v.verdict} on the true inputs, {got} on the doctored ones")
    return problems


def variable(dims, values, long_name: str, units: str = "1", **extra) -> tuple:
    """(dims, array, attrs) of a dataset variable with its long name and units (CF), for ``xr.Dataset``."""
    return (dims, np.asarray(values), {"long_name": long_name, "units": units, **extra})


def judge(ok: bool) -> str:
    return REPRODUCED if ok else NOT_REPRODUCED


def judge_every(ok, determined) -> str:
    """The one policy of a claim "for every cell" of a grid (``ok``, ``determined``: booleans per cell; ``ok`` is read
    where determined): a determined cell that fails refutes it (not reproduced); if every determined cell passes but
    some cell is not determined the claim is not shown for every cell (not checkable); no cell determined: not
    checkable."""
    ok, determined = np.asarray(ok, dtype=bool), np.asarray(determined, dtype=bool)
    if not determined.any():
        return NOT_CHECKABLE
    if not ok[determined].all():
        return NOT_REPRODUCED
    return REPRODUCED if determined.all() else NOT_CHECKABLE


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
    stored = [f.name for f in fields(Verdict) if f"verdict_{f.name}" in ds]  # files written before a field existed
    return [Verdict(**{name: str(ds[f"verdict_{name}"].values[i]) for name in stored}) for i in range(n)]


def as_dict(v: Verdict) -> dict:
    return asdict(v)

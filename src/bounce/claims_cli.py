"""``python -m bounce check CLAIM_ID``: run one claim (or ``--list`` them) from the config, alone.

CLAIM_ID is ``group/claim`` (e.g. ``static-equilibrium/energy-limit``) or a whole group (``errata``).
The group's config slice is read from ``--config`` (default ``config/config.yaml``, with
``--configfile`` overlays as in Snakemake), validated against ``config/schema.yaml`` with its
defaults applied (as the pipeline does), and its input datasets are read from ``--data``
(default ``results/data``; a sweep's gathered file from ``results/sweeps``, the group's experiments from
``results/data/checks/<group>/``): run the pipeline (or ``snakemake results/data/<scene>.nc``) first.
Prints one line per verdict row; exit status 0 if no row is ``not reproduced`` unexpectedly
(a claim with a ``known_failure`` is expected to be not reproduced), 1 otherwise, 2 on bad input
(one line, as ``python -m bounce simulate``: bad arguments raise :class:`bounce.errors.UsageError`).
"""

from __future__ import annotations

import copy
import sys
from pathlib import Path

import yaml

from .checks.base import NOT_REPRODUCED


def apply_defaults(instance: dict, schema: dict) -> dict:
    """Validate ``instance`` against ``schema`` (JSON Schema 2020-12) filling in the schema's defaults, as
    snakemake's ``validate(config, schema, set_default=True)`` does; returns the filled copy."""
    from .pipeline.config import jsonschema

    Draft202012Validator, validators = jsonschema.Draft202012Validator, jsonschema.validators

    def set_defaults(validator, properties, inst, sch):
        if isinstance(inst, dict):
            for prop, sub in properties.items():
                if "default" in sub:
                    inst.setdefault(prop, copy.deepcopy(sub["default"]))
        yield from Draft202012Validator.VALIDATORS["properties"](validator, properties, inst, sch)

    filled = copy.deepcopy(instance)
    Validator = validators.extend(Draft202012Validator, {"properties": set_defaults})
    Validator(schema).validate(filled)
    return filled


def group_spec(name: str, overrides: dict, root: str | Path = ".") -> dict:
    """The config slice of claim group ``name`` as the pipeline would pass it, with ``overrides`` in place of the
    slice of ``config/config.yaml`` (schema defaults filled in).  For tests and one-off runs."""
    root = Path(root)
    config = yaml.safe_load((root / "config" / "config.yaml").read_text())
    config["checks"][name] = {"inputs": [], **copy.deepcopy(overrides)}
    schema = yaml.safe_load((root / "config" / "schema.yaml").read_text())
    return apply_defaults(config, schema)["checks"][name]


def load_config(paths: list[str], schema_path: str) -> dict:
    """config.yaml merged with overlays (dicts updated recursively), validated, defaults applied."""
    def merge(a: dict, b: dict) -> dict:
        for k, v in b.items():
            a[k] = merge(a[k], v) if isinstance(v, dict) and isinstance(a.get(k), dict) else v
        return a

    config: dict = {}
    for p in paths:
        config = merge(config, yaml.safe_load(Path(p).read_text()) or {})
    return apply_defaults(config, yaml.safe_load(Path(schema_path).read_text()))


def main(argv=None) -> int:
    from .checks import input_files, registry
    from .errors import OneLineParser
    from .io import read_dataset

    parser = OneLineParser(prog="python -m bounce check", description=__doc__.splitlines()[0])
    parser.add_argument("claim", nargs="?", help="group/claim id, or a group name")
    parser.add_argument("--list", action="store_true", help="list every claim id with its kind and subject")
    parser.add_argument("--config", nargs="+", default=["config/config.yaml"], help="config file(s), later ones overlay")
    parser.add_argument("--schema", default="config/schema.yaml")
    parser.add_argument("--data", default="results/data", help="directory of the input datasets")
    args = parser.parse_args(argv)
    groups = registry()
    if args.list or not args.claim:
        for g in groups.values():
            for c in g.claims:
                print(f"{g.name}/{c.id}\t{c.kind}\t{c.subject}" + (f"\tknown failure: {c.known_failure}"
                                                                    if c.known_failure else ""))
        return 0
    name, _, only = args.claim.partition("/")
    if name not in groups:
        print(f"error: no claim group {name!r}; groups: {', '.join(sorted(groups))}", file=sys.stderr)
        return 2
    group = groups[name]
    if only and only not in [c.id for c in group.claims]:
        print(f"error: group {name} has no claim {only!r}; claims: {', '.join(c.id for c in group.claims)}",
              file=sys.stderr)
        return 2
    from .pipeline.config import jsonschema

    try:
        config = load_config(args.config, args.schema)
    except jsonschema.ValidationError as exc:
        where = "/".join(str(p) for p in exc.absolute_path)
        print(f"error: config {where}: {exc.message}", file=sys.stderr)
        return 2
    spec = config["checks"][name]
    # the files the rule check reads: datasets under --data, sweeps' gathered files beside it
    paths = [Path(p) for p in input_files(name, config, args.data, str(Path(args.data).parent / "sweeps"))]
    missing = [str(p) for p in paths if not p.exists()]
    if missing:
        print(f"error: input datasets missing: {', '.join(missing)} (run the pipeline first)", file=sys.stderr)
        return 2
    m = group.measure(spec, [read_dataset(p) for p in paths])
    rows = group.verdicts(m, spec, only=only or None)
    expected = {f"{name}/{c.id}": bool(c.known_failure) for c in group.claims}
    surprise = False
    for v in rows:
        print(f"{v.verdict:15s} {v.claim_id} [{v.kind}, {v.subject}]: {v.claim}\n    measured {v.measured}; "
              f"expected {v.expected}; tolerance {v.tolerance}")
        surprise |= v.verdict == NOT_REPRODUCED and not expected[v.claim_id.split("[")[0]]
    return 1 if surprise else 0

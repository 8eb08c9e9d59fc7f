"""The pipeline's config contract: `config/config.yaml` validated against `config/schema.yaml`.

One source of truth for every parameter.  :func:`validated` stops a run before any job starts,
with one line naming the key, when the config has

1. a key the schema does not know (every object of the schema is closed);
2. a number that is NaN or infinite (JSON Schema's ``number`` admits both: here it does not),
   or outside its range (the schema's ``minimum``/``maximum``, with the reason in its
   ``description``);
3. a scene whose state the model refuses (below the floor, ...) or that lies outside its spring law's
   supported domain (equilibrium below the floor, ...): every scene is built with :mod:`bounce.model`'s own
   validation and :func:`bounce.model.check_supported`, so the pipeline and the CLI refuse the same inputs;
4. a dangling or shadowing cross-reference: a figure, study or check naming a dataset that no
   rule produces, or a scene named like a derived dataset.

It fills in the schema's ``default`` values, so code reads ``spec["key"]``, never
``spec.get(key, default)``: the defaults live in the schema only.
"""

from __future__ import annotations

import copy
import math
import sys
from pathlib import Path

import yaml

from ..errors import InputError


def _import_jsonschema():
    """jsonschema, imported without its optional rfc3987_syntax (a lark grammar built at import, ~2.7 s, for the
    "iri" format checker; config/schema.yaml uses no format, and every snakemake parse and check job would pay it).

    The module is hidden only while jsonschema imports (its format module tries it once, then does without the
    checker): whoever imports rfc3987_syntax later gets it.  A no-op when jsonschema is already imported."""
    hide = "rfc3987_syntax" not in sys.modules
    if hide:
        sys.modules["rfc3987_syntax"] = None  # makes `import rfc3987_syntax` raise ImportError
    try:
        import jsonschema
    finally:
        if hide:
            del sys.modules["rfc3987_syntax"]
    return jsonschema


jsonschema = _import_jsonschema()

SCHEMA = Path(__file__).resolve().parents[3] / "config" / "schema.yaml"

#: datasets made by rules other than `simulate` (`sticky-runs`: the group of per-eps runs under
#: results/data/sticky/); a scene may take none of these names, nor `sticky` (that folder)
DERIVED_DATASETS = ("sticky-runs", "sticky-convergence", "sticky-inference")
RESERVED_SCENE_NAMES = DERIVED_DATASETS + ("sticky",)


class ConfigError(InputError):
    """The config breaks its contract; the message is one line naming the key."""


def _is_finite_number(checker, instance) -> bool:
    return (isinstance(instance, (int, float)) and not isinstance(instance, bool)
            and math.isfinite(instance))


def _is_integer(checker, instance) -> bool:
    if isinstance(instance, bool):
        return False
    if isinstance(instance, int):
        return True
    return isinstance(instance, float) and math.isfinite(instance) and instance.is_integer()


_TYPES = jsonschema.Draft202012Validator.TYPE_CHECKER.redefine_many(
    {"number": _is_finite_number, "integer": _is_integer})


def _fill_defaults(validator_class):
    """A validator that also sets each property's ``default`` where the instance lacks it."""
    validate_properties = validator_class.VALIDATORS["properties"]

    def properties(validator, props, instance, schema):
        if isinstance(instance, dict):
            for name, sub in props.items():
                if "default" in sub and name not in instance:
                    instance[name] = copy.deepcopy(sub["default"])
        yield from validate_properties(validator, props, instance, schema)

    return jsonschema.validators.extend(validator_class, {"properties": properties}, type_checker=_TYPES)


_Validator = _fill_defaults(jsonschema.Draft202012Validator)


def _where(path) -> str:
    return ".".join(str(p) for p in path) or "(top level)"


def _describe(error: jsonschema.ValidationError) -> str:
    """One line: the key, what is wrong, what is allowed."""
    where = _where(error.absolute_path)
    schema = error.schema if isinstance(error.schema, dict) else {}
    why = f" ({schema['description']})" if "description" in schema else ""
    if error.validator == "additionalProperties":
        allowed = sorted(schema.get("properties", {}))
        unknown = sorted(set(error.instance) - set(allowed))
        hint = f"; allowed: {', '.join(allowed)}" if allowed else ""
        return f"{where}: unknown key {', '.join(map(repr, unknown))}{hint}"
    if error.validator == "required":
        return f"{where}: {error.message}"
    if error.validator == "type" and isinstance(error.instance, float) and not math.isfinite(error.instance):
        return f"{where}: must be a finite number, got {error.instance!r}{why}"
    if error.validator in ("minimum", "exclusiveMinimum", "maximum", "exclusiveMaximum"):
        op = {"minimum": ">=", "exclusiveMinimum": ">", "maximum": "<=", "exclusiveMaximum": "<"}[error.validator]
        return f"{where}: must be {op} {error.validator_value}, got {error.instance!r}{why}"
    return f"{where}: {error.message}{why}"


def _best_error(errors):
    """The deepest error (the one naming the most specific key); for oneOf, its best branch."""
    error = jsonschema.exceptions.best_match(errors)
    while error is not None and error.context:
        error = jsonschema.exceptions.best_match(error.context)
    return error


def load_schema(path: Path | str = SCHEMA) -> dict:
    """The schema of ``path`` with its ``spring`` definition built from the law registry
    (:func:`bounce.springs.schema_fragment`: a law is one registry line, its config keys follow)."""
    from ..springs import schema_fragment

    with open(path) as fh:
        schema = yaml.safe_load(fh)
    schema["$defs"]["spring"] = {**schema["$defs"]["spring"], **schema_fragment()}
    return schema


def _check_scenes(config: dict) -> None:
    """Build every scene's parameters and initial state with the model's own validation, inside the supported
    domain (:func:`bounce.model.check_supported`)."""
    from ..model import check_supported
    from ..scenes import gas_scene_start, scene_initial, scene_parameters

    for section, scenes in (("scenes", config.get("scenes", {})),
                            ("methods.scenes", config.get("methods", {}).get("scenes", {}))):
        for name, spec in scenes.items():
            if section == "scenes" and (name in RESERVED_SCENE_NAMES or name in config.get("sweeps", {})):
                raise ConfigError(f"scenes.{name}: the name is taken by a derived dataset "
                                  f"({', '.join(RESERVED_SCENE_NAMES)} or a sweep's gathered file); choose another")
            try:
                params = scene_parameters(spec)
                if params.spring.solver is None:
                    raise InputError(f"spring law {params.spring.name!r} has no exact solver (bounce.springs), which "
                                     f"simulates every scene")
                check_supported(params, scene_initial(spec, params).deviations(params))
            except InputError as err:
                raise ConfigError(f"{section}.{name}: {err}") from None
    for name, spec in config.get("gas_scenes", {}).items():
        try:
            gas_scene_start(spec)
        except InputError as err:
            raise ConfigError(f"gas_scenes.{name}: {err}") from None


def _check_references(config: dict) -> None:
    """Every name a figure, study or check uses must be a dataset some rule produces."""
    scenes = set(config.get("scenes", {}))
    datasets = scenes | set(DERIVED_DATASETS) | set(config.get("sweeps", {}))  # a sweep: its gathered file

    def need(where: str, name: str, pool: set, what: str) -> None:
        if name not in pool:
            raise ConfigError(f"{where}: no {what} named {name!r} (known: {', '.join(sorted(pool)) or 'none'})")

    for fig, spec in config.get("figures", {}).items():
        if "scene" in spec:
            need(f"figures.{fig}.scene", spec["scene"], scenes, "scene")
        if "gas_scene" in spec:
            need(f"figures.{fig}.gas_scene", spec["gas_scene"], set(config.get("gas_scenes", {})), "gas scene")
    for scene in config.get("reduced", {}).get("least_model", {}).get("scenes", {}):
        need(f"reduced.least_model.scenes.{scene}", scene, scenes, "scene")
    methods = config.get("methods", {})
    for study in ("work_precision", "stability_map", "work_precision_hertz", "stability_map_hertz"):
        if study in methods:
            need(f"methods.{study}.scene", methods[study]["scene"], set(methods.get("scenes", {})),
                 "scene in methods.scenes")
    for check, spec in config.get("checks", {}).items():
        for i, name in enumerate(spec.get("inputs", [])):
            need(f"checks.{check}.inputs[{i}]", name, datasets, "dataset")


def _check_report(config: dict) -> None:
    """config ``report.sections`` lists every subject of ``report.subjects`` once; ``report.choices`` name keys."""
    report = config.get("report", {})
    subjects = report.get("subjects", {})
    listed = [s for sec in report.get("sections", {}).values() for s in sec["subjects"]]
    unknown = sorted(set(listed) - set(subjects))
    twice = sorted({s for s in listed if listed.count(s) > 1})
    missing = [s for s in subjects if s not in listed]
    if unknown or twice or missing:
        raise ConfigError(f"report.sections must list every subject of report.subjects once: unknown {unknown}, "
                          f"listed twice {twice}, missing {missing}")
    report_choices(config)


def report_choices(config: dict) -> list[dict]:
    """config ``report.choices``, each with ``values``: [key, value] pairs of the keys it names, in their order (dotted
    paths into the whole config, defaults filled; pairs, not a mapping, so that the rule's JSON keeps the order), for
    the article's front matter."""
    out = []
    for i, c in enumerate(config.get("report", {}).get("choices", [])):
        values = []
        for key in c["keys"]:
            node = config
            for part in key.split("."):
                if not isinstance(node, dict) or part not in node:
                    raise ConfigError(f"report.choices[{i}].keys: {key!r} is not a key of the config")
                node = node[part]
            values.append([key, node])
        out.append({"text": c["text"], "values": values})
    return out


#: settings that several slices carry (each rule takes only its own slice) and that must agree: the sweep
#: ``our-r-band`` measures per mu what the checks ``restitution`` and ``our-r`` measure on the one drop
SHARED_SETTINGS = (
    ("checks.restitution.plateau_flight", "checks.our-r.plateau_flight", "sweeps.our-r-band.plateau_flight"),
    ("checks.restitution.double_band", "checks.our-r.double_band", "sweeps.our-r-band.double_band"),
    ("checks.our-r.our_r_threshold", "sweeps.our-r-band.our_r_threshold"),
)


def _value_at(config: dict, dotted: str):
    node = config
    for part in dotted.split("."):
        if not isinstance(node, dict) or part not in node:
            return None
        node = node[part]
    return node


def _check_shared(config: dict) -> None:
    """The slices of :data:`SHARED_SETTINGS` agree (where the config has them)."""
    for keys in SHARED_SETTINGS:
        present = [(k, _value_at(config, k)) for k in keys if _value_at(config, k) is not None]
        if len({v for _, v in present}) > 1:
            raise ConfigError("these settings must be equal (one measurement, several slices): "
                              + ", ".join(f"{k} = {v}" for k, v in present))


def validated(config: dict, schema: dict | None = None) -> dict:
    """A deep copy of ``config`` with the schema's defaults filled in, or :class:`ConfigError`."""
    config = copy.deepcopy(dict(config))
    validator = _Validator(schema if schema is not None else load_schema())
    error = _best_error(validator.iter_errors(config))
    if error is not None:
        raise ConfigError(_describe(error))
    _check_scenes(config)
    _check_references(config)
    _check_shared(config)
    _check_report(config)
    return config

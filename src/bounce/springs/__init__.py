"""Spring laws as plug-ins: one module per law, one line in :data:`SPRING_LAWS` (the contract:
:mod:`bounce.springs.base`).  The CLI's ``--spring`` options, the config schema's ``spring`` fragment
(:func:`schema_fragment`) and the netCDF attributes are derived from the registry.

>>> from bounce.springs import spring_from_spec
>>> spring_from_spec(None).name
'linear'
>>> spring_from_spec({"law": "linear"}).attrs()
{'spring_law': 'linear'}
"""

from __future__ import annotations

from ..errors import InputError
from .base import Parameter, Physics, SpringLaw
from .linear import LINEAR, LinearSpring
from .power import PowerSpring

#: law name -> class (the registry: one line per law)
SPRING_LAWS: dict[str, type[SpringLaw]] = {
    LinearSpring.name: LinearSpring,
    PowerSpring.name: PowerSpring,
}

__all__ = ["LINEAR", "SPRING_LAWS", "LinearSpring", "Parameter", "Physics", "PowerSpring", "SpringLaw",
           "schema_fragment", "spring_from_attrs", "spring_from_spec"]


def spring_from_spec(spec: dict | None) -> SpringLaw:
    """The law of a config/CLI spec ``{"law": NAME, <parameter>: value, ...}``; linear when absent."""
    if not spec:
        return LINEAR
    spec = dict(spec)
    name = spec.pop("law", "linear")
    try:
        law = SPRING_LAWS[name]
    except (KeyError, TypeError):
        raise InputError(f"spring law must be one of {sorted(SPRING_LAWS)}, got {name!r}") from None
    expected = [p.name for p in law.PARAMETERS]
    if sorted(spec) != sorted(expected):
        raise InputError(f"spring law {name!r} takes the parameters {expected}, got {sorted(spec)}")
    return law(**spec)


def spring_from_attrs(attrs: dict) -> SpringLaw:
    """The law recorded in netCDF global attributes by :meth:`SpringLaw.attrs` (linear for older files)."""
    name = attrs.get("spring_law", "linear")
    prefix = "spring_"
    params = {k[len(prefix):]: float(v) for k, v in attrs.items() if k.startswith(prefix) and k != "spring_law"}
    return spring_from_spec({"law": name, **params})


def schema_fragment() -> dict:
    """The JSON schema of a ``spring`` spec (config/schema.yaml's ``$defs.spring``, injected by
    :func:`bounce.pipeline.config.load_schema`): ``law`` one of the registry's names, then exactly that law's
    parameters, each with its interval (:meth:`bounce.springs.base.Parameter.schema`)."""
    return {
        "description": "the spring law (bounce.springs): " + "; ".join(
            f"{name}: {law.summary}" for name, law in SPRING_LAWS.items()) + ". The paper's linear spring when absent",
        "type": "object",
        "required": ["law"],
        "properties": {"law": {"enum": list(SPRING_LAWS)}},
        "allOf": [
            {"if": {"properties": {"law": {"const": name}}},
             "then": {"additionalProperties": False, "required": [p.name for p in law.PARAMETERS],
                      "properties": {"law": {}, **{p.name: p.schema() for p in law.PARAMETERS}}}}
            for name, law in SPRING_LAWS.items()
        ],
    }

"""Spring laws as plug-ins: one module per law, one line in :data:`SPRING_LAWS`.

>>> from bounce.springs import spring_from_spec
>>> spring_from_spec(None).name
'linear'
>>> spring_from_spec({"law": "linear"}).attrs()
{'spring_law': 'linear'}
"""

from __future__ import annotations

from ..errors import InputError
from .base import SpringLaw
from .linear import LINEAR, LinearSpring
from .power import PowerSpring

#: law name -> class (the registry: one line per law)
SPRING_LAWS: dict[str, type[SpringLaw]] = {
    LinearSpring.name: LinearSpring,
    PowerSpring.name: PowerSpring,
}

__all__ = ["LINEAR", "SPRING_LAWS", "LinearSpring", "PowerSpring", "SpringLaw", "spring_from_attrs", "spring_from_spec"]


def spring_from_spec(spec: dict | None) -> SpringLaw:
    """The law of a config/CLI spec ``{"law": NAME, <parameter>: value, ...}``; linear when absent."""
    if not spec:
        return LINEAR
    spec = dict(spec)
    name = spec.pop("law", "linear")
    try:
        law = SPRING_LAWS[name]
    except KeyError:
        raise InputError(f"spring law must be one of {sorted(SPRING_LAWS)}, got {name!r}") from None
    try:
        return law(**spec)
    except TypeError:
        allowed = sorted(law.__dataclass_fields__)
        raise InputError(f"spring law {name!r} takes the parameters {allowed}, got {sorted(spec)}") from None


def spring_from_attrs(attrs: dict) -> SpringLaw:
    """The law recorded in netCDF global attributes by :meth:`SpringLaw.attrs` (linear for older files)."""
    name = attrs.get("spring_law", "linear")
    prefix = "spring_"
    params = {k[len(prefix):]: float(v) for k, v in attrs.items() if k.startswith(prefix) and k != "spring_law"}
    return spring_from_spec({"law": name, **params})

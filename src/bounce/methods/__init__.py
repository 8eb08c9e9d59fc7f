"""Methods of simulating the ball, behind one interface (:mod:`bounce.methods.base`);
discovered by their ``METHOD`` attribute."""

from __future__ import annotations

import importlib
import pkgutil

from .base import MethodSpec


def registry() -> dict[str, MethodSpec]:
    """name -> MethodSpec for every module of this package that defines ``METHOD``."""
    found = {}
    for info in pkgutil.iter_modules(__path__):
        if info.name == "base":
            continue
        module = importlib.import_module(f"{__name__}.{info.name}")
        spec = getattr(module, "METHOD", None)
        if isinstance(spec, MethodSpec):
            found[spec.name] = spec
    return found

"""Validation checks, one module per claim group; discovered by their ``CHECK`` attribute.

See :mod:`bounce.checks.base` for the contract.
"""

from __future__ import annotations

import importlib
import pkgutil

from .base import Check


def registry() -> dict[str, Check]:
    """name -> Check for every module of this package that defines ``CHECK``."""
    found = {}
    for info in pkgutil.iter_modules(__path__):
        if info.name == "base":
            continue
        module = importlib.import_module(f"{__name__}.{info.name}")
        check = getattr(module, "CHECK", None)
        if isinstance(check, Check):
            found[check.name] = check
    return found

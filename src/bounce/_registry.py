"""Plugin discovery shared by bounce.checks and bounce.methods."""

from __future__ import annotations

import importlib
import pkgutil


def discover(package: str, path, attribute: str, kind: type) -> dict:
    """name -> object for every module of ``package`` whose ``attribute`` is a ``kind``."""
    found = {}
    for info in pkgutil.iter_modules(path):
        if info.name == "base":
            continue
        obj = getattr(importlib.import_module(f"{package}.{info.name}"), attribute, None)
        if isinstance(obj, kind):
            found[obj.name] = obj
    return found

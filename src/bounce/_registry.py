"""Plugin discovery shared by bounce.checks and bounce.methods."""

from __future__ import annotations

import importlib
import pkgutil


def discover(package: str, path, attribute: str, kind: type) -> dict:
    """name -> object for every module of ``package`` whose ``attribute`` is a ``kind``
    (or whose ``attribute + 'S'`` is a tuple of them, for modules holding a family)."""
    found = {}
    for info in pkgutil.iter_modules(path):
        if info.name == "base":
            continue
        module = importlib.import_module(f"{package}.{info.name}")
        objs = [getattr(module, attribute, None), *getattr(module, attribute + "S", ())]
        for obj in objs:
            if isinstance(obj, kind):
                found[obj.name] = obj
    return found

"""Plugin discovery shared by bounce.checks and bounce.methods."""

from __future__ import annotations

import importlib
import importlib.util
import pkgutil
import sys


def discover(package: str, path, attribute: str, kind: type, family: str | None = None) -> dict:
    """name -> object for every module of ``package`` whose ``attribute`` is a ``kind``
    (or whose ``family``, default ``attribute + 'S'``, is a tuple of them, for modules holding a family)."""
    found = {}
    for info in pkgutil.iter_modules(path):
        if info.name == "base" or info.name.startswith("_"):
            continue
        module = importlib.import_module(f"{package}.{info.name}")
        objs = [getattr(module, attribute, None), *getattr(module, family or attribute + "S", ())]
        for obj in objs:
            if isinstance(obj, kind):
                found[obj.name] = obj
    return found


def find(package: str, path, attribute: str, kind: type, name: str, family: str | None = None):
    """The plugin ``name`` of ``package``, importing only its own module when that module is named for it (``name``
    with ``-`` as ``_``: check ``main-theorem`` in ``main_theorem.py``), else every module (:func:`discover`).

    A pipeline job runs one plugin: importing the others (scipy.optimize, the figures, sympy's loaders) would cost it
    about a second of CPU.  KeyError, as ``discover(...)[name]``, when no module defines it."""
    own = name.replace("-", "_")
    if any(info.name == own for info in pkgutil.iter_modules(path)):
        module = importlib.import_module(f"{package}.{own}")
        for obj in [getattr(module, attribute, None), *getattr(module, family or attribute + "S", ())]:
            if isinstance(obj, kind) and obj.name == name:
                return obj
    return discover(package, path, attribute, kind, family)[name]


def lazy_import(name: str):
    """The module ``name``, executed at its first attribute access (importlib.util.LazyLoader).

    Discovery imports every plugin module; a plugin whose heavy dependency only its own measurement
    needs (sympy ~1 s, heyoka ~2.4 s) imports it this way, so parsing the workflow and every other job do not pay it."""
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.find_spec(name)
    if spec is None:
        raise ModuleNotFoundError(f"No module named {name!r}", name=name)
    loader = importlib.util.LazyLoader(spec.loader)
    spec.loader = loader
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    loader.exec_module(module)
    return module

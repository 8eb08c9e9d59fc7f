"""Methods of simulating the ball, behind one interface (:mod:`bounce.methods.base`);
discovered by their ``METHOD`` attribute."""

from __future__ import annotations

from .._registry import discover
from .base import MethodSpec


def registry() -> dict[str, MethodSpec]:
    """name -> MethodSpec for every module of this package that defines ``METHOD``."""
    return discover(__name__, __path__, "METHOD", MethodSpec)

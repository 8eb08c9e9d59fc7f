"""Validation checks, one module per claim group; discovered by their ``CHECK`` attribute.

See :mod:`bounce.checks.base` for the contract.
"""

from __future__ import annotations

from .._registry import discover
from .base import Check


def registry() -> dict[str, Check]:
    """name -> Check for every module of this package that defines ``CHECK``."""
    return discover(__name__, __path__, "CHECK", Check)

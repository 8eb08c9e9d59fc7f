"""The paper's claims, one module per claim group; a group is discovered by its ``CHECK`` attribute.

Each group lists its claims in ``CLAIMS`` (small functions, or declarative entries, with their kind
and subject as data); see :mod:`bounce.checks.base` for the contract.  No module here imports another.
"""

from __future__ import annotations

from .._registry import discover
from .base import Check


def registry() -> dict[str, Check]:
    """name -> Check for every module of this package that defines ``CHECK``."""
    return discover(__name__, __path__, "CHECK", Check)

"""The tests' name for the one high-precision reference, :mod:`bounce.reference` (kept so that
``import reference as R`` in the tests keeps working; add reference code there, not here)."""

from bounce.reference import *  # noqa: F401,F403
from bounce.reference import DPS, M, RootSearchError, _hp  # noqa: F401

"""Point numba's on-disk cache at a directory keyed by the numerical core's source.

numba's ``cache=True`` invalidates a cached kernel only when *its own* file
changes, not when a function it inlines from another module does, so an edit
to, say, flight.py would silently keep running the old event loop.  Keying the
cache directory by a hash of every module that kernels may read (:func:`kernel_sources`) makes any edit of
them start a fresh cache (kernels may then share helpers and constants across files safely).  The folders and
modules downstream of the numerical core (:data:`DOWNSTREAM`: claims, figures, the pipeline glue, the command
lines) define no kernel and are never read by one (the data flow goes one way), so editing them keeps the
compiled kernels: tests/test_layout.py::test_downstream_modules_define_no_kernel keeps that true.
Set BOUNCE_NUMBA_CACHE_DIR to choose the parent directory (default: $XDG_CACHE_HOME or ~/.cache, then /tmp).
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

#: the parts of the package downstream of the kernels (folders and top-level modules), left out of the cache key
DOWNSTREAM = ("checks", "figures", "pipeline", "cli.py", "claims_cli.py", "gas_cli.py", "__main__.py")


def kernel_sources(here: Path | None = None) -> list[Path]:
    """Every module of the package but those :data:`DOWNSTREAM` of the kernels, sorted."""
    here = here or Path(__file__).parent
    return [p for p in sorted(here.rglob("*.py")) if p.relative_to(here).parts[0] not in DOWNSTREAM]


def configure() -> str:
    """Set numba.config.CACHE_DIR (before the kernels are decorated); return it."""
    import numba

    here = Path(__file__).parent
    digest = hashlib.sha256()
    for path in kernel_sources(here):
        digest.update(str(path.relative_to(here)).encode())
        digest.update(path.read_bytes())
    base = os.environ.get("BOUNCE_NUMBA_CACHE_DIR") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache"), "bounce-numba"
    )
    for parent in (base, os.path.join("/tmp", "bounce-numba")):
        path = os.path.join(parent, digest.hexdigest()[:16])
        try:
            os.makedirs(path, exist_ok=True)
        except OSError:
            continue
        numba.config.CACHE_DIR = path
        return path
    return numba.config.CACHE_DIR

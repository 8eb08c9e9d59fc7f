"""Point numba's on-disk cache at a directory keyed by the numerical core's source.

numba's ``cache=True`` invalidates a cached kernel only when *its own* file
changes, not when a function it inlines from another module does, so an edit
to, say, flight.py would silently keep running the old event loop.  Keying the
cache directory by a hash of every module of the package makes any edit start
a fresh cache (kernels may then share helpers across files safely).  Set BOUNCE_NUMBA_CACHE_DIR to choose the parent
directory (default: $XDG_CACHE_HOME or ~/.cache, then /tmp).
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

def configure() -> str:
    """Set numba.config.CACHE_DIR (before the kernels are decorated); return it."""
    import numba

    here = Path(__file__).parent
    digest = hashlib.sha256()
    for path in sorted(here.rglob("*.py")):
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

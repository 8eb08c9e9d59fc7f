"""Counting the calls a numba kernel makes to its module's kernels (for the benchmarks' step counts).

A kernel's ``.py_func`` runs as Python and looks its callees up as module globals at each call, so
replacing them by counting wrappers counts them; the compiled kernels are untouched.
"""

from __future__ import annotations

import collections
import contextlib


@contextlib.contextmanager
def counting(module, names, replace=None):
    """Within the block, ``module.<name>`` for each of ``names`` counts its calls into the yielded Counter,
    and ``module.<key>`` is ``replace[key]`` (e.g. a caller's ``.py_func``, so that its callees are counted
    too); everything is restored on exit."""
    replace = replace or {}
    counts = collections.Counter()
    originals = {name: getattr(module, name) for name in (*names, *replace)}

    def wrapped(name):
        def call(*args):
            counts[name] += 1
            return originals[name](*args)
        return call

    try:
        for name in names:
            setattr(module, name, wrapped(name))
        for name, f in replace.items():
            setattr(module, name, f)
        yield counts
    finally:
        for name, f in originals.items():
            setattr(module, name, f)

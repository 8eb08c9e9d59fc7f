"""SIGINT while the command line starts: one line and status 130, not the traceback of the imports it cut.

``python -m bounce`` imports the package (numba, numpy) and then :mod:`bounce.cli` (xarray, netCDF4) for
about a second before :func:`bounce.cli.main` handles signals; an interrupt there printed 20 to 33 lines of
traceback (issue 25).  Only the command line is concerned: ``import bounce`` in a program keeps its
KeyboardInterrupt.
"""

from __future__ import annotations

import contextlib
import os
import sys

EXIT_SIGINT = 130


def starting_the_cli() -> bool:
    """Is this interpreter starting the command line?  Python sets ``sys.argv[0]`` to ``"-m"`` while it imports
    the package of ``python -m bounce`` ("while the module file is being located", python(1)); the console
    script is the other way in."""
    return sys.argv[:1] == ["-m"] or os.path.basename(sys.argv[0]) == "bounce"


@contextlib.contextmanager
def interrupt_ends_the_cli(cli: bool = True):
    """With ``cli``: a KeyboardInterrupt inside ends the process with one line and status 130."""
    try:
        yield
    except KeyboardInterrupt:
        if not cli:
            raise
        print("error: interrupted (SIGINT) while starting; nothing was written", file=sys.stderr)
        sys.exit(EXIT_SIGINT)

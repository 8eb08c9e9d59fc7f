"""SIGINT while the command line starts: one line and status 130, not the traceback of the imports it cut.

``python -m bounce`` imports the package (numba, numpy) and then :mod:`bounce.cli` (xarray, netCDF4) for
about a second before :func:`bounce.cli.main` handles signals; an interrupt there printed 20 to 33 lines of
traceback (issue 25).  Only the command line is concerned: ``import bounce`` in a program keeps its
KeyboardInterrupt.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading

EXIT_SIGINT = 130


def starting_the_cli() -> bool:
    """Is this interpreter starting the command line?  Python sets ``sys.argv[0]`` to ``"-m"`` while it imports
    the package of ``python -m bounce`` ("while the module file is being located", python(1)); the console
    script is the other way in."""
    return sys.argv[:1] == ["-m"] or os.path.basename(sys.argv[0]) == "bounce"


def _end_while_starting(signum, frame) -> None:
    """SIGINT while starting: nothing is written yet, so the process ends here, with one line."""
    os.write(2, b"error: interrupted (SIGINT) while starting; nothing was written\n")
    os._exit(EXIT_SIGINT)


@contextlib.contextmanager
def interrupt_ends_the_cli(cli: bool = True):
    """With ``cli``: SIGINT inside ends the process with one line and status 130.

    A handler, not ``except KeyboardInterrupt``: the exception raised inside a callback of the import machinery
    (``_get_module_lock``'s weakref callback) is printed as "Exception ignored" and dropped, and the run went on to
    exit 0 (found by tests/test_cli.py under load).  A SIGINT the process was started ignoring stays ignored."""
    previous = signal.getsignal(signal.SIGINT)
    if not cli or previous is signal.SIG_IGN or threading.current_thread() is not threading.main_thread():
        yield
        return
    signal.signal(signal.SIGINT, _end_while_starting)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous if previous is not None else signal.default_int_handler)

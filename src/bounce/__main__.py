"""``python -m bounce`` (and the ``bounce`` script): the command-line interface of :mod:`bounce.cli`."""

import sys

from ._interrupted import interrupt_ends_the_cli


def run() -> int:
    """Import the command line (a second of numba, xarray and netCDF4) and run it; SIGINT meanwhile gives
    one line (:mod:`bounce._interrupted`), then :func:`bounce.cli.main` handles it."""
    with interrupt_ends_the_cli():
        from .cli import main
    return main()


if __name__ == "__main__":
    sys.exit(run())

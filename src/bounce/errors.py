"""The exceptions of bad input: a parameter outside its allowed range (the message names both), and a bad
command line (raised by :class:`OneLineParser`, printed by the command line as one line)."""

import argparse


class InputError(ValueError):
    """A parameter outside its allowed range; the message names both."""


class UsageError(Exception):
    """Bad command-line input; the message is the one line printed after 'error: '."""


class OneLineParser(argparse.ArgumentParser):
    """An ArgumentParser that raises UsageError instead of printing its usage and exiting (``bounce simulate``,
    ``bounce check``)."""

    def error(self, message):
        raise UsageError(message)

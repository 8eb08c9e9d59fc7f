"""The one exception of bad input: a parameter outside its allowed range (the message names both)."""


class InputError(ValueError):
    """A parameter outside its allowed range; the message names both."""

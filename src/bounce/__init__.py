"""bounce: exact event-driven replication of Cherubini, Metafune & Paparella,
"On the Stopping Time of a Bouncing Ball"."""

from ._interrupted import interrupt_ends_the_cli as _interrupt_ends_the_cli
from ._interrupted import starting_the_cli as _starting_the_cli

with _interrupt_ends_the_cli(_starting_the_cli()):  # python -m bounce: SIGINT while numba loads gives one line
    from ._jit_cache import configure as _configure_jit_cache

    _configure_jit_cache()  # before any kernel is decorated

    from ._version import __version__
    from .model import Deviations, InputError, Parameters, State
    from .simulate import simulate
    from .trajectory import Trajectory

__all__ = ["Deviations", "InputError", "Parameters", "State", "Trajectory", "simulate", "__version__"]

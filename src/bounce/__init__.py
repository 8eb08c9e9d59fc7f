"""bounce: exact event-driven replication of Cherubini, Metafune & Paparella,
"On the Stopping Time of a Bouncing Ball"."""

from ._jit_cache import configure as _configure_jit_cache

_configure_jit_cache()  # before any kernel is decorated

from .model import Deviations, InputError, Parameters, State
from .simulate import simulate  # noqa: E402
from .trajectory import Trajectory  # noqa: E402
from ._version import __version__  # noqa: E402

__all__ = ["Deviations", "InputError", "Parameters", "State", "Trajectory", "simulate", "__version__"]

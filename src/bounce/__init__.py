"""bounce: exact event-driven replication of Cherubini, Metafune & Paparella,
"On the Stopping Time of a Bouncing Ball"."""

from .model import Deviations, InputError, Parameters, State
from .simulate import Trajectory, simulate

__version__ = "0.1.0"
__all__ = ["Deviations", "InputError", "Parameters", "State", "Trajectory", "simulate", "__version__"]

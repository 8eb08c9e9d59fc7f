"""Gases of grains (issue 23): the exact event-driven engine of n two-mass grains (dimers), in a column on
the floor or on a ring, and its rigid counterpart with a constant restitution (and the TC model).

Engines: :mod:`bounce.gas.dimer`, :mod:`bounce.gas.rigid`; their shared queue and slots:
:mod:`bounce.gas.queue`, :mod:`bounce.gas.common`; inputs: :mod:`bounce.gas.model`; the Python front:
:mod:`bounce.gas.simulate`; netCDF: :mod:`bounce.gas.io`; the command line ``python -m bounce gas``:
:mod:`bounce.gas_cli` (in the command-line layer).
"""

from .common import KIND_NAMES, STOP_NAMES
from .model import GasParameters, GasState, RigidParameters, RigidState
from .simulate import GasResult, GasRun, energy_excess, simulate_gas, simulate_rigid

__all__ = ["GasParameters", "GasResult", "GasRun", "GasState", "KIND_NAMES", "RigidParameters", "RigidState",
           "STOP_NAMES", "energy_excess", "simulate_gas", "simulate_rigid"]

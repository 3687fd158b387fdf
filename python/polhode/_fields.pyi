# Generated from polhode._core.QUANTITIES by `python scripts/fields_stub.py`: do not edit.
# The fields of polhode.Trajectory and polhode.dask.DaskTrajectory, for type checkers; at
# run time polhode._fields makes the same class from the same table.

from dataclasses import dataclass
from typing import Generic, TypeVar

import numpy as np
from numpy.typing import NDArray

__all__ = ["Fields"]

_A = TypeVar("_A")

@dataclass(frozen=True, eq=False, repr=False)
class Fields(Generic[_A]):
    t: NDArray[np.float64]
    omega: _A
    """Angular velocity, body axes (rad/s)."""
    omega_space: _A | None
    """Angular velocity, space axes (rad/s)."""
    quaternion: _A | None
    """Body-to-space orientation, scalar-last quaternion (x, y, z, w), its sign continuous in
    time."""
    angular_momentum_space: _A | None
    """Angular momentum, space axes (conserved without torque); with rotors, the total (kg
    m^2/s)."""
    angular_momentum_body: _A
    """Angular momentum, body axes; with rotors, the total (kg m^2/s)."""
    energy: _A
    """Rotational kinetic energy; with rotors, the total (their spin included) (J)."""
    rotor_rates: _A | None
    """Each rotor's angular velocity relative to the body, body axes (a wheel's along its axis)
    (rad/s)."""

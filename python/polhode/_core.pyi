"""Type stubs for the compiled core (checked by ``python -m mypy.stubtest polhode._core``)."""

from collections.abc import Callable
from typing import Any, final

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "InertiaError",
    "MassProperties",
    "PolhodeError",
    "free_rotation",
    "principal",
    "simulate",
]

class PolhodeError(ValueError): ...
class InertiaError(PolhodeError): ...

@final
class MassProperties:
    @staticmethod
    def point_masses(
        masses: NDArray[np.float64], positions: NDArray[np.float64]
    ) -> MassProperties: ...
    @staticmethod
    def mesh(
        vertices: NDArray[np.float64],
        faces: NDArray[np.int64],
        density: float | None = None,
        mass: float | None = None,
        shell: bool = False,
        fix_winding: bool = False,
    ) -> MassProperties: ...
    @staticmethod
    def point(mass: float) -> MassProperties: ...
    @staticmethod
    def sphere(mass: float, radius: float) -> MassProperties: ...
    @staticmethod
    def spherical_shell(mass: float, radius: float) -> MassProperties: ...
    @staticmethod
    def cuboid(mass: float, size: NDArray[np.float64]) -> MassProperties: ...
    @staticmethod
    def cylinder(mass: float, radius: float, length: float) -> MassProperties: ...
    @staticmethod
    def tube(
        mass: float, inner_radius: float, outer_radius: float, length: float
    ) -> MassProperties: ...
    @staticmethod
    def cone(mass: float, radius: float, height: float) -> MassProperties: ...
    @staticmethod
    def ellipsoid(mass: float, semi_axes: NDArray[np.float64]) -> MassProperties: ...
    @staticmethod
    def rod(mass: float, length: float) -> MassProperties: ...
    @staticmethod
    def disk(mass: float, radius: float) -> MassProperties: ...
    @staticmethod
    def torus(mass: float, major_radius: float, minor_radius: float) -> MassProperties: ...
    @staticmethod
    def capsule(mass: float, radius: float, length: float) -> MassProperties: ...
    @staticmethod
    def from_inertia(
        mass: float, inertia: NDArray[np.float64], center_of_mass: NDArray[np.float64]
    ) -> MassProperties: ...
    @property
    def mass(self) -> float: ...
    @property
    def center_of_mass(self) -> NDArray[np.float64]: ...
    @property
    def inertia(self) -> NDArray[np.float64]: ...
    @property
    def second_moment(self) -> NDArray[np.float64]: ...
    def inertia_about(
        self, point: NDArray[np.float64], axes: NDArray[np.float64] | None = None
    ) -> NDArray[np.float64]: ...
    def principal(
        self, rtol: float | None = None
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int64]]: ...
    def translated(self, offset: NDArray[np.float64]) -> MassProperties: ...
    def rotated(self, rotation: NDArray[np.float64]) -> MassProperties: ...
    def scaled(self, mass_scale: float, length_scale: float) -> MassProperties: ...
    def combined(self, other: MassProperties) -> MassProperties: ...
    def angular_momentum(self, omega: NDArray[np.float64]) -> NDArray[np.float64]: ...
    def kinetic_energy(self, omega: NDArray[np.float64]) -> float: ...

def principal(
    inertia: NDArray[np.float64], rtol: float | None = None
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int64]]: ...
def simulate(
    moments: NDArray[np.float64],
    omega0: NDArray[np.float64],
    quaternion0: NDArray[np.float64],
    times: NDArray[np.float64],
    *,
    t0: float,
    method: str,
    dt: float | None,
    order: int,
    rtol: float,
    atol: float | None,
    torque: tuple[Any, ...] | None,
    with_attitude: bool,
    max_steps: int,
    progress: Callable[[float], object] | None = None,
    axes: NDArray[np.float64] | None = None,
) -> tuple[
    NDArray[np.float64],
    NDArray[np.float64] | None,
    NDArray[np.float64] | None,
    NDArray[np.float64],
    NDArray[np.float64],
    NDArray[np.uint64],
]: ...
def free_rotation(
    moments: tuple[float, float, float], omega0: tuple[float, float, float]
) -> dict[str, Any]: ...

"""Type stubs for the compiled core (checked by ``python -m mypy.stubtest polhode._core``)."""

from collections.abc import Callable, Sequence
from typing import Any, final

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "METHODS",
    "QUANTITIES",
    "SOLIDS",
    "MassProperties",
    "cancel_all",
    "cancel_epoch",
    "check_motion",
    "check_rotor",
    "check_torque",
    "fastest_rate",
    "free_rotation",
    "merge_vertices",
    "point_masses_inertia",
    "principal",
    "simulate",
]

METHODS: dict[str, str]
QUANTITIES: tuple[dict[str, Any], ...]
SOLIDS: dict[str, tuple[tuple[str, int], ...]]

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
    def solid(
        kind: str, mass: float, **parameters: float | NDArray[np.float64]
    ) -> MassProperties: ...
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
    def angular_momentum_body(self, omega: NDArray[np.float64]) -> NDArray[np.float64]: ...
    def kinetic_energy(self, omega: NDArray[np.float64]) -> float: ...
    def parts(self) -> _Parts: ...
    @staticmethod
    def from_parts(
        mass: float,
        center_of_mass: _Triple,
        center_of_mass_low: _Triple,
        isotropic: float,
        factor: tuple[_Triple, _Triple, _Triple],
    ) -> MassProperties: ...
    def __reduce__(self) -> tuple[Callable[..., MassProperties], _Parts]: ...

_Triple = tuple[float, float, float]
_Parts = tuple[float, _Triple, _Triple, float, tuple[_Triple, _Triple, _Triple]]

def merge_vertices(
    vertices: NDArray[np.float64], faces: NDArray[np.int64]
) -> tuple[NDArray[np.float64], NDArray[np.int64]]: ...
def point_masses_inertia(
    masses: NDArray[np.float64], positions: NDArray[np.float64] | NDArray[np.float32]
) -> NDArray[np.float64]: ...
def principal(
    inertia: NDArray[np.float64], rtol: float | None = None, continuous: bool = False
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int64]]: ...
def simulate(
    body: NDArray[np.float64] | MassProperties | list[MassProperties],
    omega0: NDArray[np.float64],
    t: NDArray[np.float64],
    *,
    orientation0: NDArray[np.float64] | None = None,
    t0: float = 0.0,
    method: str = "auto",
    dt: float | None = None,
    order: int = 4,
    rtol: float = 1e-10,
    atol: float | None = None,
    torque: Any = None,
    orientation: bool = True,
    max_steps: int = 100_000_000,
    progress: Callable[[float], object] | None = None,
    rotors: Sequence[Any] | None = None,
    every_step: bool = False,
) -> dict[str, Any]: ...
def fastest_rate(
    body: NDArray[np.float64] | MassProperties | list[MassProperties],
    omega0: NDArray[np.float64],
    t_end: float,
    *,
    orientation0: NDArray[np.float64] | None = None,
    t0: float = 0.0,
    method: str = "auto",
    dt: float | None = None,
    order: int = 4,
    rtol: float = 1e-10,
    atol: float | None = None,
    torque: Any = None,
    rotors: Sequence[Any] | None = None,
) -> dict[str, Any]: ...
def check_rotor(rotor: Any) -> None: ...
def check_torque(torque: Any) -> None: ...
def cancel_all() -> None: ...
def cancel_epoch() -> int: ...
def check_motion(
    body: NDArray[np.float64] | MassProperties | list[MassProperties],
    omega0: NDArray[np.float64],
    *,
    rotors: Sequence[Any] | None = None,
) -> None: ...
def free_rotation(
    moments: tuple[float, float, float], omega0: tuple[float, float, float]
) -> dict[str, Any]: ...

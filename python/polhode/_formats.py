"""Engine formats of mass properties: MuJoCo's ``fullinertia`` and ``<inertial>``, URDF's
``<inertia>`` and ``<inertial>``.

The work of :meth:`polhode.Body.from_fullinertia`, :meth:`~polhode.Body.from_urdf_inertia`,
:meth:`~polhode.Body.to_fullinertia`, :meth:`~polhode.Body.to_urdf_inertia`,
:meth:`~polhode.Body.to_mjcf` and :meth:`~polhode.Body.to_urdf_inertial`. The body type is
passed in: :mod:`polhode.bodies` imports this module.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from polhode._coerce import as_array, as_scalar
from polhode.errors import PolhodeError

__all__ = [
    "URDF_KEYS",
    "fixed_axis_rpy",
    "from_fullinertia",
    "from_urdf_inertia",
    "fullinertia",
    "mjcf_inertial",
    "number",
    "numbers",
    "urdf_inertia",
    "urdf_inertial",
]

#: The attributes of URDF's ``<inertia>``, in its order.
URDF_KEYS = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")


def number(value: Any) -> str:
    """The shortest decimal that reads back to the same double (``repr``), never ``-0.0``:
    what every file polhode writes holds (``-0.0 + 0.0`` is ``0.0`` in IEEE arithmetic, and
    every other number is unchanged)."""
    return repr(float(value) + 0.0)


def numbers(values: Any) -> str:
    """Space-separated :func:`number` s."""
    return " ".join(number(v) for v in values)


def fixed_axis_rpy(matrix: NDArray[np.float64]) -> tuple[float, float, float]:
    """Roll, pitch, yaw (fixed axes: R = Rz(yaw) Ry(pitch) Rx(roll)) of a rotation matrix,
    with pitch in [-pi/2, pi/2].

    The yaw comes from the first column (cos p (cos y, sin y, .)); the matrix is then turned
    back by that yaw, Rz(-y) R = Ry(p) Rx(r), and pitch and roll read from that product. Near
    gimbal lock (cos p -> 0) the yaw alone is ill-determined, but the roll is taken from the
    matrix with that very yaw removed, so the three angles reproduce R to rounding; at gimbal
    lock exactly the yaw is whatever atan2 gives for the round-off (0 for exact zeros) and the
    roll carries the rest. No warning either way (scipy's as_euler warns there).
    """
    r = np.asarray(matrix, dtype=float)
    yaw = math.atan2(r[1, 0], r[0, 0])
    c, s = math.cos(yaw), math.sin(yaw)
    # Rows of Rz(-yaw) R: [c s 0; -s c 0; 0 0 1] R.
    m00 = c * r[0, 0] + s * r[1, 0]
    m11 = -s * r[0, 1] + c * r[1, 1]
    m12 = -s * r[0, 2] + c * r[1, 2]
    pitch = math.atan2(-r[2, 0], m00)
    roll = math.atan2(-m12, m11)
    return roll, pitch, yaw


def _from_six(
    body_type: Any, mass: float, tensor: Any, center_of_mass: Any, element: Any, whole: str
) -> Any:
    """``body_type.from_inertia`` on a tensor made of six numbers, its errors renamed after
    them: a non-finite element by ``element(i, j)`` (i <= j), the tensor as a whole by
    ``whole``."""
    try:
        return body_type.from_inertia(mass, tensor, center_of_mass)
    except PolhodeError as error:
        if error.argument != "inertia":
            raise
        message = error.message
        for i in range(3):
            for j in range(3):
                name = element(min(i, j), max(i, j))
                message = message.replace(f"`inertia[{i}, {j}]`", f"`{name}`")
        message = message.replace("`inertia`", f"`{whole}`")
        first = message.split("`")[1] if "`" in message else whole
        raise type(error)(message, argument=first.split("[")[0], body=error.body) from None


def from_fullinertia(body_type: Any, mass: float, fullinertia: Any, center_of_mass: Any) -> Any:
    """:meth:`polhode.Body.from_fullinertia`."""
    xx, yy, zz, xy, xz, yz = as_array("fullinertia", fullinertia, (6,))
    tensor = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
    # The six numbers as the tensor: its errors name `fullinertia` (the element, for a
    # non-finite one), the argument given.
    order = {(0, 0): 0, (1, 1): 1, (2, 2): 2, (0, 1): 3, (0, 2): 4, (1, 2): 5}
    return _from_six(
        body_type,
        mass,
        tensor,
        center_of_mass,
        lambda i, j: f"fullinertia[{order[i, j]}]",
        "fullinertia",
    )


def from_urdf_inertia(
    body_type: Any, mass: float, elements: tuple[Any, ...], center_of_mass: Any
) -> Any:
    """:meth:`polhode.Body.from_urdf_inertia`: ``elements`` (ixx, ixy, ixz, iyy, iyz, izz)."""
    v = [as_scalar(n, x) for n, x in zip(URDF_KEYS, elements, strict=True)]
    tensor = np.array([[v[0], v[1], v[2]], [v[1], v[3], v[4]], [v[2], v[4], v[5]]])
    keys = {(0, 0): "ixx", (0, 1): "ixy", (0, 2): "ixz", (1, 1): "iyy", (1, 2): "iyz",
            (2, 2): "izz"}
    return _from_six(body_type, mass, tensor, center_of_mass, lambda i, j: keys[i, j], "inertia")


def fullinertia(inertia: NDArray[np.float64]) -> NDArray[np.float64]:
    """(6,) MuJoCo ``fullinertia`` order of a tensor: I_xx, I_yy, I_zz, I_xy, I_xz, I_yz."""
    i = inertia
    return np.array([i[0, 0], i[1, 1], i[2, 2], i[0, 1], i[0, 2], i[1, 2]])


def urdf_inertia(inertia: NDArray[np.float64]) -> dict[str, float]:
    """URDF's ``<inertia>`` attributes of a tensor."""
    i = inertia
    values = (i[0, 0], i[0, 1], i[0, 2], i[1, 1], i[1, 2], i[2, 2])
    return {k: float(v) for k, v in zip(URDF_KEYS, values, strict=True)}


def mjcf_inertial(body: Any) -> str:
    """:meth:`polhode.Body.to_mjcf`."""
    p = body.principal()
    w_last = p.rotation.as_quat()
    quat = (w_last[3], w_last[0], w_last[1], w_last[2])
    return (
        f'<inertial pos="{numbers(body.center_of_mass)}" quat="{numbers(quat)}" '
        f'mass="{numbers([body.mass])}" diaginertia="{numbers(p.moments)}"/>'
    )


def urdf_inertial(body: Any) -> str:
    """:meth:`polhode.Body.to_urdf_inertial`."""
    p = body.principal()
    rpy = fixed_axis_rpy(p.axes)
    m = [number(x) for x in p.moments]
    return (
        "<inertial>\n"
        f'  <origin xyz="{numbers(body.center_of_mass)}" rpy="{numbers(rpy)}"/>\n'
        f'  <mass value="{numbers([body.mass])}"/>\n'
        f'  <inertia ixx="{m[0]}" ixy="0" ixz="0" iyy="{m[1]}" iyz="0" izz="{m[2]}"/>\n'
        "</inertial>"
    )

"""Rigid bodies: mass, centre of mass and inertia of point masses, solids and composites."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from polhode import _core, _display, _shapes
from polhode._coerce import as_array, as_rotation_matrix, as_scalar
from polhode.errors import ShapeError
from polhode.principal_axes import Principal

__all__ = ["Body"]


_URDF_KEYS = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")


def _numbers(values: Any) -> str:
    """Space-separated shortest round-trip decimals."""
    return " ".join(repr(float(v)) for v in values)


def _fixed_axis_rpy(matrix: NDArray[np.float64]) -> tuple[float, float, float]:
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


def _as_faces(faces: Any) -> NDArray[np.int64]:
    """(M, 3) integer vertex indices as a C-contiguous int64 array."""
    if faces is None or isinstance(faces, str | bytes):
        raise TypeError(
            f"Expected `faces` to be an array of vertex indices, got {type(faces).__name__}."
        )
    try:
        array = np.asarray(faces)
    except (TypeError, ValueError) as error:
        raise TypeError(
            f"Expected `faces` to be an array of vertex indices, got {type(faces).__name__}."
        ) from error
    if array.dtype.kind not in "iu" and not (array.size == 0 and array.dtype.kind == "f"):
        raise TypeError(f"Expected `faces` to be an array of integers, got dtype {array.dtype}.")
    if array.ndim != 2 or array.shape[1] != 3:
        shape = "(" + ", ".join(str(d) for d in array.shape) + (",)" if array.ndim == 1 else ")")
        raise ShapeError(f"Expected `faces` to have shape (M, 3), got {shape}.", argument="faces")
    if array.dtype.kind == "u" and array.size and int(array.max()) > np.iinfo(np.int64).max:
        raise ShapeError(
            f"Expected `faces` to hold vertex indices, got {int(array.max())}.", argument="faces"
        )
    return np.ascontiguousarray(array, dtype=np.int64)


def _as_flag(name: str, value: Any) -> bool:
    if not isinstance(value, bool | np.bool_):
        raise TypeError(f"Expected `{name}` to be a bool, got {type(value).__name__}.")
    return bool(value)


class Body:
    """A rigid body: mass, centre of mass and inertia, all in the body's own axes.

    Immutable. Build one with a constructor (``Body.cylinder(...)``), move it with
    :meth:`translated` and :meth:`rotated`, and add bodies to make composites (each part is
    shifted to the combined centre of mass). Internally the second moments about the centre of
    mass are kept in a square-root form, so composites keep the small moments of needles and the
    tiny anisotropy of nearly spherical bodies.

    Examples
    --------
    >>> import polhode as ph
    >>> handle = ph.Body.cylinder(1.0, 0.02, 0.3)
    >>> bar = ph.Body.cylinder(0.5, 0.02, 0.2).rotated([[1, 0, 0], [0, 0, -1], [0, 1, 0]])
    >>> t_handle = handle + bar.translated([0.0, 0.0, 0.15])
    >>> p = t_handle.principal()
    >>> bool(p.moments[0] < p.moments[1] < p.moments[2])
    True
    """

    __slots__ = ("_core", "_shape")

    def __init__(self, core: _core.MassProperties, shape: _shapes.Shape | None = None) -> None:
        if not isinstance(core, _core.MassProperties):
            raise TypeError(
                "Body is built with a constructor such as Body.sphere or Body.point_masses, "
                f"not from {type(core).__name__}."
            )
        self._core = core
        # What it looks like (polhode._shapes), for drawing only; None: no geometry given.
        self._shape = shape

    # --- constructors ---------------------------------------------------------------------

    @classmethod
    def point_masses(cls, masses: Any, positions: Any) -> Body:
        """Point masses: ``masses`` (N,) at ``positions`` (N, 3)."""
        m = as_array("masses", masses, (None,))
        r = as_array("positions", positions, (None, 3))
        if r.shape[0] != m.shape[0]:
            raise ShapeError(
                f"Expected `positions` to have shape ({m.shape[0]}, 3) to match `masses`, "
                f"got ({r.shape[0]}, 3).",
                argument="positions",
            )
        return cls(_core.MassProperties.point_masses(m, r))

    @classmethod
    def mesh(
        cls,
        vertices: Any,
        faces: Any,
        density: float | None = None,
        mass: float | None = None,
        shell: bool = False,
        fix_winding: bool = False,
    ) -> Body:
        """A uniform solid bounded by a closed triangle mesh, or a thin shell on its surface.

        ``vertices`` (N, 3) are points in body coordinates and ``faces`` (M, 3) integer vertex
        indices, wound counter-clockwise seen from outside. Give exactly one of ``density``
        (mass per volume, or per area with ``shell=True``) and ``mass``.

        A solid mesh must be closed and consistently wound (every edge traversed once in each
        direction); nested closed shells (a cavity wound inward) add with their signs. An
        inside-out mesh (negative volume) raises unless ``fix_winding=True``, which reverses
        every face. With ``shell=True`` the mass lies on the surface (uniform surface density,
        thickness -> 0), and the mesh need not be closed.

        The integrals are exact for the polyhedron and taken about the vertex mean, so a mesh
        far from the origin keeps its digits.
        """
        v = as_array("vertices", vertices, (None, 3))
        f = _as_faces(faces)
        return cls(
            _core.MassProperties.mesh(
                v,
                f,
                None if density is None else as_scalar("density", density),
                None if mass is None else as_scalar("mass", mass),
                _as_flag("shell", shell),
                _as_flag("fix_winding", fix_winding),
            )
        )

    @classmethod
    def from_trimesh(
        cls,
        mesh: Any,
        density: float | None = None,
        mass: float | None = None,
        shell: bool = False,
        fix_winding: bool = False,
    ) -> Body:
        """A body from a ``trimesh.Trimesh`` (or anything with ``vertices`` and ``faces``).

        See :meth:`mesh`; trimesh's own ``density`` is not used: give ``density`` or ``mass``.
        """
        try:
            vertices, faces = mesh.vertices, mesh.faces
        except AttributeError as error:
            raise TypeError(
                "Expected `mesh` to have `vertices` and `faces` (a trimesh.Trimesh), "
                f"got {type(mesh).__name__}."
            ) from error
        return cls.mesh(vertices, faces, density, mass, shell, fix_winding)

    @classmethod
    def sphere(cls, mass: float, radius: float) -> Body:
        """A solid sphere centred on the origin: I = 2/5 m r^2."""
        return cls(
            _core.MassProperties.sphere(as_scalar("mass", mass), as_scalar("radius", radius))
        )

    @classmethod
    def spherical_shell(cls, mass: float, radius: float) -> Body:
        """A thin spherical shell centred on the origin: I = 2/3 m r^2."""
        return cls(
            _core.MassProperties.spherical_shell(
                as_scalar("mass", mass), as_scalar("radius", radius)
            )
        )

    @classmethod
    def cuboid(cls, mass: float, size: Any) -> Body:
        """A solid cuboid (a box) centred on the origin, with full edge lengths ``size`` =
        (a, b, c) along x, y, z: I_x = m (b^2 + c^2)/12."""
        return cls(
            _core.MassProperties.cuboid(as_scalar("mass", mass), as_array("size", size, (3,)))
        )

    @classmethod
    def cylinder(cls, mass: float, radius: float, length: float) -> Body:
        """A solid cylinder along z, centred on the origin (its faces at z = -+length/2):
        I_z = m r^2/2, I_x = I_y = m (3 r^2 + L^2)/12."""
        return cls(
            _core.MassProperties.cylinder(
                as_scalar("mass", mass), as_scalar("radius", radius), as_scalar("length", length)
            )
        )

    @classmethod
    def tube(cls, mass: float, inner_radius: float, outer_radius: float, length: float) -> Body:
        """A thick-walled tube along z, centred on the origin: I_z = m (r1^2 + r2^2)/2."""
        return cls(
            _core.MassProperties.tube(
                as_scalar("mass", mass),
                as_scalar("inner_radius", inner_radius),
                as_scalar("outer_radius", outer_radius),
                as_scalar("length", length),
            )
        )

    @classmethod
    def cone(cls, mass: float, radius: float, length: float) -> Body:
        """A solid cone along z whose origin is the centre of its base: base disc in the plane
        z = 0, apex at z = length, centre of mass at z = length/4 (the one solid not centred on
        the origin, so that a top's pivot, its apex, is at (0, 0, length)):
        I_z = 3/10 m r^2, I_x = 3/20 m r^2 + 3/80 m L^2 about the centre of mass."""
        return cls(
            _core.MassProperties.cone(
                as_scalar("mass", mass), as_scalar("radius", radius), as_scalar("length", length)
            )
        )

    @classmethod
    def ellipsoid(cls, mass: float, semi_axes: Any) -> Body:
        """A solid ellipsoid centred on the origin, with semi-axes (a, b, c) along x, y, z:
        I_x = m (b^2 + c^2)/5."""
        return cls(
            _core.MassProperties.ellipsoid(
                as_scalar("mass", mass), as_array("semi_axes", semi_axes, (3,))
            )
        )

    @classmethod
    def rod(cls, mass: float, length: float) -> Body:
        """A thin rod along z, centred on the origin: I_x = I_y = m L^2/12, I_z = 0."""
        return cls(_core.MassProperties.rod(as_scalar("mass", mass), as_scalar("length", length)))

    @classmethod
    def disk(cls, mass: float, radius: float) -> Body:
        """A thin disc in the xy plane, centred on the origin: I_z = m r^2/2,
        I_x = I_y = m r^2/4."""
        return cls(_core.MassProperties.disk(as_scalar("mass", mass), as_scalar("radius", radius)))

    @classmethod
    def torus(cls, mass: float, major_radius: float, minor_radius: float) -> Body:
        """A solid torus about z, centred on the origin: I_z = m (R^2 + 3 a^2/4),
        I_x = m (R^2/2 + 5 a^2/8)."""
        return cls(
            _core.MassProperties.torus(
                as_scalar("mass", mass),
                as_scalar("major_radius", major_radius),
                as_scalar("minor_radius", minor_radius),
            )
        )

    @classmethod
    def capsule(cls, mass: float, radius: float, length: float) -> Body:
        """A cylinder of ``length`` along z capped by two hemispheres of ``radius``, centred on
        the origin (total length ``length + 2 radius``)."""
        return cls(
            _core.MassProperties.capsule(
                as_scalar("mass", mass), as_scalar("radius", radius), as_scalar("length", length)
            )
        )

    @classmethod
    def from_inertia(cls, mass: float, inertia: Any, center_of_mass: Any = (0.0, 0.0, 0.0)) -> Body:
        """A body from its mass, inertia tensor about its centre of mass, and that centre.

        The tensor must be symmetric, positive semidefinite and satisfy I1 + I2 >= I3 (each to a
        relative tolerance of about 16 eps tr(I)/2); planar and collinear bodies are valid.
        """
        return cls(
            _core.MassProperties.from_inertia(
                as_scalar("mass", mass),
                as_array("inertia", inertia, (3, 3)),
                as_array("center_of_mass", center_of_mass, (3,)),
            )
        )

    @classmethod
    def from_fullinertia(
        cls, mass: float, fullinertia: Any, center_of_mass: Any = (0.0, 0.0, 0.0)
    ) -> Body:
        """A body from MuJoCo's ``fullinertia`` 6-vector (I_xx, I_yy, I_zz, I_xy, I_xz, I_yz).

        The six numbers are tensor elements about the centre of mass in body axes (products of
        inertia as tensor elements, I_xy = -sum m x y), as MuJoCo reads them.
        """
        xx, yy, zz, xy, xz, yz = as_array("fullinertia", fullinertia, (6,))
        tensor = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
        return cls.from_inertia(mass, tensor, center_of_mass)

    @classmethod
    def from_urdf_inertia(
        cls,
        mass: float,
        *,
        ixx: float,
        ixy: float,
        ixz: float,
        iyy: float,
        iyz: float,
        izz: float,
        center_of_mass: Any = (0.0, 0.0, 0.0),
    ) -> Body:
        """A body from URDF/SDF ``<inertia ixx ixy ixz iyy iyz izz>`` (tensor elements about
        the centre of mass, in body axes: an ``<origin>`` with ``rpy="0 0 0"``)."""
        v = [
            as_scalar(n, x) for n, x in zip(_URDF_KEYS, (ixx, ixy, ixz, iyy, iyz, izz), strict=True)
        ]
        tensor = np.array([[v[0], v[1], v[2]], [v[1], v[3], v[4]], [v[2], v[4], v[5]]])
        return cls.from_inertia(mass, tensor, center_of_mass)

    # --- properties -----------------------------------------------------------------------

    @property
    def mass(self) -> float:
        """Total mass."""
        return self._core.mass

    @property
    def center_of_mass(self) -> NDArray[np.float64]:
        """(3,) centre of mass in body coordinates."""
        return self._core.center_of_mass

    @property
    def inertia(self) -> NDArray[np.float64]:
        """(3, 3) inertia tensor about the centre of mass, in body axes (I_xy = -sum m x y)."""
        return self._core.inertia

    @property
    def second_moment(self) -> NDArray[np.float64]:
        """(3, 3) second-moment matrix sum m r r^T about the centre of mass."""
        return self._core.second_moment

    def inertia_about(self, point: Any, axes: Any = None) -> NDArray[np.float64]:
        """(3, 3) inertia tensor about ``point`` (body coordinates).

        ``axes``, if given, is a rotation (scipy Rotation, (3, 3) matrix or xyzw quaternion)
        whose columns are the new axes in body coordinates; the result is then
        ``A.T @ I_point @ A``.
        """
        p = as_array("point", point, (3,))
        a = None if axes is None else as_rotation_matrix("axes", axes)
        return self._core.inertia_about(p, a)

    def principal(self, rtol: float | None = None) -> Principal:
        """Principal moments (ascending) and axes about the centre of mass.

        Moments whose gap is at most ``rtol`` (default 8 eps) times the anisotropic part of the
        second moments count as equal: they are returned equal, flagged in ``multiplicity``, and
        their axes are the canonical ones closest to the body's own axes.
        """
        tolerance = None if rtol is None else as_scalar("rtol", rtol)
        moments, axes, multiplicity = self._core.principal(tolerance)
        return Principal(moments, axes, multiplicity)

    def angular_momentum_body(self, omega: Any) -> NDArray[np.float64]:
        """(3,) angular momentum I w about the centre of mass in body axes, ``omega`` in body
        axes."""
        return self._core.angular_momentum_body(as_array("omega", omega, (3,)))

    def kinetic_energy(self, omega: Any) -> float:
        """Rotational kinetic energy w . I w / 2."""
        return self._core.kinetic_energy(as_array("omega", omega, (3,)))

    # --- engine formats ---------------------------------------------------------------------

    def to_fullinertia(self) -> NDArray[np.float64]:
        """(6,) MuJoCo ``fullinertia`` order: I_xx, I_yy, I_zz, I_xy, I_xz, I_yz.

        Tensor elements about the centre of mass in body axes (I_xy = -sum m x y).
        """
        i = self.inertia
        return np.array([i[0, 0], i[1, 1], i[2, 2], i[0, 1], i[0, 2], i[1, 2]])

    def to_urdf_inertia(self) -> dict[str, float]:
        """URDF/SDF ``<inertia>`` attributes {ixx, ixy, ixz, iyy, iyz, izz}: tensor elements
        about the centre of mass in body axes (I_xy = -sum m x y)."""
        i = self.inertia
        values = (i[0, 0], i[0, 1], i[0, 2], i[1, 1], i[1, 2], i[2, 2])
        return {k: float(v) for k, v in zip(_URDF_KEYS, values, strict=True)}

    def to_mjcf(self) -> str:
        """A MuJoCo ``<inertial>`` element: centre of mass, the principal frame as a ``quat``
        (w, x, y, z, MuJoCo's order) and the principal moments as ``diaginertia``."""
        p = self.principal()
        w_last = p.rotation.as_quat()
        quat = (w_last[3], w_last[0], w_last[1], w_last[2])
        return (
            f'<inertial pos="{_numbers(self.center_of_mass)}" quat="{_numbers(quat)}" '
            f'mass="{_numbers([self.mass])}" diaginertia="{_numbers(p.moments)}"/>'
        )

    def to_urdf_inertial(self) -> str:
        """A URDF ``<inertial>`` element: the centre of mass and the principal frame as the
        ``<origin xyz rpy>`` (fixed-axis roll, pitch, yaw: R = Rz(y) Ry(p) Rx(r)), and the
        principal moments as a diagonal ``<inertia>``.

        The angles reproduce the principal frame to rounding, gimbal lock (pitch = +-pi/2)
        included, where the yaw is chosen from the round-off and the roll carries the rest."""
        p = self.principal()
        rpy = _fixed_axis_rpy(p.axes)
        m = [repr(float(x)) for x in p.moments]
        return (
            "<inertial>\n"
            f'  <origin xyz="{_numbers(self.center_of_mass)}" rpy="{_numbers(rpy)}"/>\n'
            f'  <mass value="{_numbers([self.mass])}"/>\n'
            f'  <inertia ixx="{m[0]}" ixy="0" ixz="0" iyy="{m[1]}" iyz="0" izz="{m[2]}"/>\n'
            "</inertial>"
        )

    # --- moving and combining -------------------------------------------------------------

    def translated(self, offset: Any) -> Body:
        """The same body moved by ``offset`` (body coordinates)."""
        d = as_array("offset", offset, (3,))
        return Body(self._core.translated(d), _shapes.moved(self._shape, np.eye(3), d))

    def rotated(self, rotation: Any) -> Body:
        """The same body rotated about the origin of body coordinates (``x_new = R x``).

        ``rotation`` is a scipy Rotation, a (3, 3) matrix or an (x, y, z, w) quaternion.
        """
        r = as_rotation_matrix("rotation", rotation)
        return Body(self._core.rotated(r), _shapes.moved(self._shape, r, np.zeros(3)))

    def scaled(self, mass_scale: float = 1.0, length_scale: float = 1.0) -> Body:
        """The same body with masses times ``mass_scale`` and lengths times ``length_scale``."""
        s = as_scalar("length_scale", length_scale)
        return Body(
            self._core.scaled(as_scalar("mass_scale", mass_scale), s),
            _shapes.moved(self._shape, s * np.eye(3), np.zeros(3)),
        )

    def __add__(self, other: object) -> Body:
        if isinstance(other, Body):
            core = self._core.combined(other._core)
            if self._shape is None and other._shape is None:
                return Body(core)
            return Body(core, _shapes.of(self) + _shapes.of(other))
        return NotImplemented

    def __radd__(self, other: object) -> Body:
        # sum(bodies) starts from 0.
        if isinstance(other, int) and not isinstance(other, bool) and other == 0:
            return self
        return NotImplemented

    def __repr__(self) -> str:
        return (
            f"Body(mass={_display.number(self.mass)}, "
            f"center_of_mass={_display.vector(self.center_of_mass)}, "
            f"principal_moments={_display.vector(self.principal().moments)})"
        )

    def _repr_html_(self) -> str:
        p = self.principal()
        return _display.html_table(
            "Body",
            [
                ("mass", _display.number(self.mass)),
                ("center of mass", _display.vector(self.center_of_mass)),
                ("inertia (about the centre of mass)", _display.html_matrix(self.inertia)),
                ("principal moments", _display.vector(p.moments)),
                ("multiplicity", _display.vector(p.multiplicity)),
                ("principal axes (columns)", _display.html_matrix(p.axes)),
            ],
        )


# The solids, meshes and point masses remember their shape, for drawing (polhode._shapes).
for _kind in (*_shapes.SOLIDS, "mesh", "point_masses"):
    setattr(Body, _kind, classmethod(_shapes.recording(_kind, getattr(Body, _kind).__func__)))

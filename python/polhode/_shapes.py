"""What a :class:`~polhode.Body` looks like: the parts it was built from, for drawing.

A body remembers the shapes it was made of (a solid with its dimensions, a triangle mesh, point
masses), each placed in body coordinates by ``x_body = A x_part + b`` (``A`` a rotation times a
length scale). :meth:`Body.translated`, :meth:`Body.rotated`, :meth:`Body.scaled` and ``+``
carry the parts along. A body with no geometry (``Body.from_inertia``) is drawn as its
equivalent ellipsoid: the uniform solid ellipsoid with the same mass, centre of mass and
inertia.

:func:`surface` turns the parts into polygons in body coordinates (closed surfaces for the
solids), which :func:`polhode.plot.animate` turns in space. Nothing here takes part in the mass
properties: those come from the core.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]

#: The solids whose shape a body records, by constructor name.
SOLIDS = (
    "sphere",
    "spherical_shell",
    "cuboid",
    "cylinder",
    "tube",
    "cone",
    "ellipsoid",
    "rod",
    "disk",
    "torus",
    "capsule",
)


@dataclass(frozen=True)
class Part:
    """One shape: ``kind`` (a solid's constructor name, ``"mesh"``, ``"point_masses"``),
    its parameters in its own frame, and its placement ``x_body = matrix @ x_part + offset``."""

    kind: str
    params: dict[str, Any]
    matrix: Array
    offset: Array

    def moved(self, matrix: Array, offset: Array) -> Part:
        """The part after ``x -> matrix @ x + offset`` in body coordinates."""
        return Part(self.kind, self.params, matrix @ self.matrix, matrix @ self.offset + offset)


Shape = tuple[Part, ...]


def part(kind: str, **params: Any) -> Shape:
    """A body of one part at the origin of its own frame."""
    return (Part(kind, params, np.eye(3), np.zeros(3)),)


def moved(shape: Shape | None, matrix: Any, offset: Any) -> Shape | None:
    """Every part after ``x -> matrix @ x + offset`` (None stays None)."""
    if shape is None:
        return None
    m = np.asarray(matrix, dtype=np.float64)
    b = np.asarray(offset, dtype=np.float64)
    return tuple(p.moved(m, b) for p in shape)


def recording(kind: str, constructor: Callable[..., Any]) -> Callable[..., Any]:
    """A classmethod body that calls ``constructor`` and records its shape on the result.

    The parameters are those the constructor was called with, by name (its signature binds
    them), as float arrays; the constructor has checked them already.
    """
    signature = inspect.signature(constructor)

    def build(cls: Any, *args: Any, **kwargs: Any) -> Any:
        body = constructor(cls, *args, **kwargs)
        bound = signature.bind(cls, *args, **kwargs)
        bound.apply_defaults()
        names = list(signature.parameters)[1:]
        if kind != "mesh":
            params = {
                name: np.asarray(bound.arguments[name], dtype=np.float64)
                for name in names
                if name not in ("mass", "density")
                and not isinstance(bound.arguments[name], bool | None)
            }
        else:
            params = {
                "vertices": np.asarray(bound.arguments["vertices"], dtype=np.float64),
                "faces": np.asarray(bound.arguments["faces"], dtype=np.int64),
            }
        body._shape = part(kind, **params)
        return body

    build.__name__ = constructor.__name__
    build.__qualname__ = constructor.__qualname__
    build.__doc__ = constructor.__doc__
    build.__wrapped__ = constructor  # type: ignore[attr-defined]
    build.__signature__ = signature  # type: ignore[attr-defined]
    return build


def equivalent_ellipsoid(mass: float, center_of_mass: Array, principal: Any) -> Shape:
    """The uniform solid ellipsoid with this mass, centre and inertia (semi-axes along the
    principal axes: ``a_k^2 = 5 (I_i + I_j - I_k) / (2 m)``)."""
    moments = np.asarray(principal.moments, dtype=np.float64)
    total = float(np.sum(moments))
    squares = 5.0 * (total - 2.0 * moments) / (2.0 * mass) if mass > 0 else np.zeros(3)
    semi_axes = np.sqrt(np.maximum(squares, 0.0))
    return (
        Part(
            "ellipsoid",
            {"semi_axes": semi_axes},
            np.asarray(principal.axes, dtype=np.float64),
            np.asarray(center_of_mass, dtype=np.float64),
        ),
    )


def of(body: Any) -> Shape:
    """The parts of ``body``, or its equivalent ellipsoid if it has no geometry."""
    if body._shape is not None:
        return body._shape
    return equivalent_ellipsoid(body.mass, body.center_of_mass, body.principal())


# -------------------------------------------------------------------------------------------------
# Surfaces
# -------------------------------------------------------------------------------------------------


def _revolve(rho: Sequence[float], z: Sequence[float], n: int) -> list[Array]:
    """Quadrilaterals of the surface swept by the profile (rho, z) about the z axis."""
    phi = np.linspace(0.0, 2.0 * np.pi, n + 1)
    c, s = np.cos(phi), np.sin(phi)
    r = np.asarray(rho, dtype=np.float64)
    h = np.asarray(z, dtype=np.float64)
    # Points (profile k, angle j).
    points = np.stack(
        [
            r[:, None] * c[None, :],
            r[:, None] * s[None, :],
            np.broadcast_to(h[:, None], (r.size, n + 1)),
        ],
        axis=-1,
    )
    quads = np.stack(
        [points[:-1, :-1], points[:-1, 1:], points[1:, 1:], points[1:, :-1]], axis=2
    ).reshape(-1, 4, 3)
    return list(quads)


def _arc(radius: float, start: float, stop: float, n: int, z0: float = 0.0) -> tuple[Array, Array]:
    """Profile of a circular arc about (0, z0), angles from the +z axis."""
    theta = np.linspace(start, stop, n)
    return radius * np.sin(theta), z0 + radius * np.cos(theta)


def _solid_polygons(kind: str, p: dict[str, Any], n: int) -> list[Array]:
    """Polygons (each (k, 3)) of a solid's surface in its own frame."""
    if kind in ("sphere", "spherical_shell"):
        rho, z = _arc(float(p["radius"]), np.pi, 0.0, n // 2 + 1)
        return _revolve(rho, z, n)
    if kind == "ellipsoid":
        rho, z = _arc(1.0, np.pi, 0.0, n // 2 + 1)
        scale = np.asarray(p["semi_axes"], dtype=np.float64)
        return [q * scale for q in _revolve(rho, z, n)]
    if kind == "cuboid":
        a, b, c = np.asarray(p["size"], dtype=np.float64) / 2.0
        corners = np.array([[x, y, w] for x in (-a, a) for y in (-b, b) for w in (-c, c)])
        faces = ((0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3))
        return [corners[list(f)] for f in faces]
    if kind in ("cylinder", "rod", "disk"):
        if kind == "rod":
            length = float(p["length"])
            radius = length / 60.0
        elif kind == "disk":
            radius = float(p["radius"])
            length = radius / 30.0
        else:
            radius, length = float(p["radius"]), float(p["length"])
        h = length / 2.0
        return _revolve([0.0, radius, radius, 0.0], [-h, -h, h, h], n)
    if kind == "tube":
        r1, r2, h = float(p["inner_radius"]), float(p["outer_radius"]), float(p["length"]) / 2.0
        return _revolve([r1, r2, r2, r1, r1], [-h, -h, h, h, -h], n)
    if kind == "cone":
        r, length = float(p["radius"]), float(p["length"])
        return _revolve([0.0, r, 0.0], [0.0, 0.0, length], n)
    if kind == "capsule":
        r, h = float(p["radius"]), float(p["length"]) / 2.0
        lower = _arc(r, np.pi, np.pi / 2, n // 4 + 1, -h)
        upper = _arc(r, np.pi / 2, 0.0, n // 4 + 1, h)
        return _revolve(np.r_[lower[0], upper[0]], np.r_[lower[1], upper[1]], n)
    if kind == "torus":
        big, small = float(p["major_radius"]), float(p["minor_radius"])
        theta = np.linspace(0.0, 2.0 * np.pi, n // 2 + 1)
        return _revolve(big + small * np.cos(theta), small * np.sin(theta), n)
    raise ValueError(f"No surface for a {kind!r}.")


def _part_polygons(p: Part, n: int, point_radius: float) -> list[Array]:
    """Polygons of one part in its own frame."""
    if p.kind == "mesh":
        vertices = np.asarray(p.params["vertices"], dtype=np.float64)
        return list(vertices[np.asarray(p.params["faces"], dtype=np.int64)])
    if p.kind == "point_masses":
        masses = np.asarray(p.params["masses"], dtype=np.float64)
        positions = np.asarray(p.params["positions"], dtype=np.float64)
        biggest = float(np.max(masses)) if masses.size else 1.0
        polygons: list[Array] = []
        ball = _solid_polygons("sphere", {"radius": 1.0}, 10)
        for m, r in zip(masses, positions, strict=True):
            size = point_radius * np.cbrt(m / biggest) if biggest > 0 else point_radius
            polygons += [q * size + r for q in ball]
        return polygons
    return _solid_polygons(p.kind, p.params, n)


def extent(shape: Shape) -> float:
    """A length of the body's size: the largest distance of a part's reference point or mesh
    vertex, or a solid's largest dimension."""
    sizes = [0.0]
    points = []
    for p in shape:
        scale = float(np.linalg.norm(p.matrix, 2))
        points.append(p.offset)
        if p.kind == "mesh" or p.kind == "point_masses":
            key = "vertices" if p.kind == "mesh" else "positions"
            local = np.asarray(p.params[key], dtype=np.float64).reshape(-1, 3)
            points.extend(local @ p.matrix.T + p.offset)
        else:
            sizes.append(scale * max(float(np.max(np.abs(v))) for v in p.params.values()))
    cloud = np.asarray(points, dtype=np.float64)
    spread = (
        float(np.max(np.linalg.norm(cloud - cloud.mean(axis=0), axis=1))) if cloud.size else 0.0
    )
    return max(spread, *sizes)


def surface(shape: Shape, resolution: int = 24) -> list[Array]:
    """The polygons (each (k, 3), body coordinates) of every part of ``shape``.

    ``resolution`` is the number of segments around a circle. Point masses are drawn as balls
    whose volume goes with their mass, the largest of radius 1/15 of the body's size.
    """
    point_radius = extent(shape) / 15.0 or 1.0
    polygons: list[Array] = []
    for p in shape:
        polygons += [q @ p.matrix.T + p.offset for q in _part_polygons(p, resolution, point_radius)]
    return polygons

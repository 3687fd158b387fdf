"""Mesh files: STL, OBJ, PLY, OFF, glTF and GLB (``polhode.io.MESH_FORMATS``), read by trimesh,
each part as a body."""

from __future__ import annotations

import os
from collections.abc import Sequence

from polhode._meshes import read_bodies
from polhode.bodies import Body

__all__ = ["read_mesh"]


def read_mesh(
    path: str | os.PathLike[str],
    *,
    density: float | None = None,
    mass: float | None = None,
    shell: bool = False,
    scale: float | Sequence[float] = 1.0,
    fix_winding: bool = False,
) -> dict[str, Body]:
    """The meshes of a file, each as a body, by the names the file gives them.

    Reads STL (ascii and binary), OBJ, PLY, OFF, glTF and GLB (by the extension) with
    trimesh's loaders; the mass properties are polhode's exact mesh integrals. Each part is
    placed by the file's scene graph (a glTF node's transform; an OBJ file has one part per
    object), then scaled. Vertices at the same position are merged, so that a triangle soup
    (STL) closes, and vertices that differ by exporters' noise (within 2^-40 of the part's
    bounding-box diagonal) count as one for the check that a solid is closed (see
    :meth:`polhode.Body.mesh`).

    Parameters
    ----------
    path : str or os.PathLike
        The mesh file.
    density, mass : float
        Exactly one: the density of every part (mass per volume, or per area with
        ``shell=True``), or the total mass of the file, shared between the parts in proportion
        to their volumes (areas).
    shell : bool
        Mass on the surfaces (a thin shell) rather than in the volumes; the meshes need not
        then be closed.
    scale : float or (3,) floats
        Length scale applied to the vertices, e.g. 0.001 for a file in millimetres read in
        metres; three numbers scale each axis (a negative one mirrors).
    fix_winding : bool
        Turn an inside-out part (faces wound clockwise seen from outside) the right way out
        instead of raising.

    Returns
    -------
    dict[str, Body]
        One body per mesh part (in the file's coordinates, scaled); ``Body.from_file`` is their
        sum.

    Raises
    ------
    FileNotFoundError
        No such file.
    polhode.errors.FileFormatError
        Not a mesh of a known format, no triangles, or a part that is open (unless
        ``shell=True``), inside out or of zero volume; the message names the file and the part.
    polhode.errors.ArgumentError, NonPositiveError, NonFiniteError
        Bad ``density``, ``mass`` or ``scale``; an ArgumentError naming ``scale`` where the
        scaled mesh is beyond double precision (or flat to rounding) and the file's own is not.

    Examples
    --------
    >>> import os, tempfile
    >>> import polhode as ph
    >>> off = ("OFF\\n4 4 0\\n0 0 0\\n1 0 0\\n0 1 0\\n0 0 1\\n"
    ...        "3 0 2 1\\n3 0 1 3\\n3 0 3 2\\n3 1 2 3\\n")
    >>> path = os.path.join(tempfile.mkdtemp(), "tetrahedron.off")
    >>> with open(path, "w") as handle:
    ...     _ = handle.write(off)
    >>> parts = ph.io.read_mesh(path, density=6.0)
    >>> [(name, round(body.mass, 12)) for name, body in parts.items()]
    [('tetrahedron.off', 1.0)]
    """
    return read_bodies(
        Body,
        path,
        density=density,
        mass=mass,
        shell=shell,
        scale=scale,
        fix_winding=fix_winding,
    )

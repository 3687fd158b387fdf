"""Rigid bodies: mass, centre of mass and inertia of point masses, solids and composites."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from polhode import _core, _display, _formats, _shapes, _spatial
from polhode._atoms import atom_masses, atoms_of
from polhode._coerce import as_array, as_faces, as_flag, as_rotation_matrix, as_scalar
from polhode._meshes import read_bodies
from polhode.errors import ArgumentError, NonPositiveError, ShapeError
from polhode.principal_axes import Principal

__all__ = ["SPATIAL_CONVENTIONS", "Body"]

#: Block orders of :meth:`Body.spatial_inertia`: Featherstone's and Drake's angular first,
#: Pinocchio's linear first.
SPATIAL_CONVENTIONS = ("featherstone", "drake", "pinocchio")


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

    def __reduce__(self) -> tuple[type[Body], tuple[Any, ...]]:
        # Pickling and copy.deepcopy, at every protocol: the core's stored numbers (bit for
        # bit, checked again on loading) and the shape it was built from.
        return (type(self), (self._core, self._shape))

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
        direction). For that check only, vertices at the same position are one vertex, and so
        are vertices within 2^-40 (9.1e-13) of the bounding-box diagonal of each other in every
        coordinate: a triangle soup closes, and so does a file whose exporter wrote a 0 as 3e-17
        in the next facet, while a gap of 1e-11 of the size does not (real edges are longer
        than 1e-9 of it); the integrals use the vertices as given. An open mesh's error says
        where the openings are, how long and how wide, and tells a crack (triangles that do not
        share vertices) from a hole. Nested closed shells (a cavity wound inward) add with their
        signs. An
        inside-out mesh (negative volume) raises unless ``fix_winding=True``, which reverses
        every face. With ``shell=True`` the mass lies on the surface (uniform surface density,
        thickness -> 0), and the mesh need not be closed.

        The integrals are exact for the polyhedron and taken about the vertex mean, so a mesh
        far from the origin keeps its digits.
        """
        v = as_array("vertices", vertices, (None, 3))
        f = as_faces(faces)
        return cls(
            _core.MassProperties.mesh(
                v,
                f,
                None if density is None else as_scalar("density", density),
                None if mass is None else as_scalar("mass", mass),
                as_flag("shell", shell),
                as_flag("fix_winding", fix_winding),
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

        See :meth:`mesh`. Without ``density`` and ``mass``, a solid takes the mesh's own
        ``density`` (``mesh.density``: the one set on it, else trimesh's default 1.0, as
        trimesh's own ``mesh.mass_properties`` does); a shell needs ``density`` (per area) or
        ``mass``.

        Examples
        --------
        >>> import trimesh
        >>> import polhode as ph
        >>> box = trimesh.creation.box(extents=[0.2, 0.1, 0.05])
        >>> box.density = 2700.0                       # aluminium, kg/m^3
        >>> round(ph.Body.from_trimesh(box).mass, 12)  # 2700 x 0.001 m^3
        2.7
        """
        try:
            vertices, faces = mesh.vertices, mesh.faces
        except AttributeError as error:
            raise TypeError(
                "Expected `mesh` to have `vertices` and `faces` (a trimesh.Trimesh), "
                f"got {type(mesh).__name__}."
            ) from error
        if density is None and mass is None and not as_flag("shell", shell):
            own = getattr(mesh, "density", None)
            if own is None:
                raise ArgumentError(
                    "give exactly one of `density` and `mass` (the mesh has no `density` of "
                    "its own), got neither.",
                    argument="density",
                )
            density = as_scalar("density", own)
            if not (np.isfinite(density) and density > 0):
                raise NonPositiveError(
                    f"Expected the mesh's own `density` (mesh.density) to be positive and "
                    f"finite, got {density}; give `density` or `mass`.",
                    argument="density",
                )
        return cls.mesh(vertices, faces, density, mass, shell, fix_winding)

    @classmethod
    def solid(cls, kind: str, mass: float, **parameters: Any) -> Body:
        """The analytic solid named ``kind`` by its parameters: ``Body.solid("cylinder", 1.0,
        radius=0.1, length=0.5)`` is ``Body.cylinder(1.0, 0.1, 0.5)``.

        The kinds and their parameters (each a number, or a vector along x, y, z of three) are
        those of the named constructors below, and ``"point"`` (no parameters: a point mass at
        the origin). An unknown kind is an ``ArgumentError`` naming ``kind`` and the kinds there
        are; a missing or unknown parameter is a ``TypeError``.

        Examples
        --------
        >>> import polhode as ph
        >>> float(ph.Body.solid("sphere", 2.0, radius=0.5).inertia[0, 0])  # 2/5 m r^2
        0.2
        """
        if not isinstance(kind, str):
            raise TypeError(f"Expected `kind` to be a string, got {type(kind).__name__}.")
        table = _core.SOLIDS.get(kind)
        if table is None:  # the core's error names the kinds it knows
            return cls(_core.MassProperties.solid(kind, as_scalar("mass", mass)))
        values = {
            name: as_scalar(name, parameters[name])
            if width == 1
            else as_array(name, parameters[name], (width,))
            for name, width in table
            if name in parameters
        }
        unknown = sorted(set(parameters) - set(values))
        if unknown:
            takes = ", ".join(name for name, _ in table) or "no parameters"
            raise TypeError(f"Body.solid: a {kind} takes {takes}; got {', '.join(unknown)}.")
        body = cls(_core.MassProperties.solid(kind, as_scalar("mass", mass), **values))
        if kind in _shapes.SOLIDS:  # drawn as the named constructor's body is
            body._shape = _shapes.part(kind, **{k: np.asarray(v) for k, v in values.items()})
        return body

    @classmethod
    def sphere(cls, mass: float, radius: float) -> Body:
        """A solid sphere centred on the origin: I = 2/5 m r^2."""
        return cls.solid("sphere", mass, radius=radius)

    @classmethod
    def spherical_shell(cls, mass: float, radius: float) -> Body:
        """A thin spherical shell centred on the origin: I = 2/3 m r^2."""
        return cls.solid("spherical_shell", mass, radius=radius)

    @classmethod
    def cuboid(cls, mass: float, size: Any) -> Body:
        """A solid cuboid (a box) centred on the origin, with full edge lengths ``size`` =
        (a, b, c) along x, y, z: I_x = m (b^2 + c^2)/12."""
        return cls.solid("cuboid", mass, size=size)

    @classmethod
    def cylinder(cls, mass: float, radius: float, length: float) -> Body:
        """A solid cylinder along z, centred on the origin (its end faces at z = -length/2 and
        z = length/2): I_z = m r^2/2, I_x = I_y = m (3 r^2 + L^2)/12."""
        return cls.solid("cylinder", mass, radius=radius, length=length)

    @classmethod
    def tube(cls, mass: float, inner_radius: float, outer_radius: float, length: float) -> Body:
        """A thick-walled tube along z, centred on the origin: I_z = m (r1^2 + r2^2)/2."""
        return cls.solid(
            "tube", mass, inner_radius=inner_radius, outer_radius=outer_radius, length=length
        )

    @classmethod
    def cone(cls, mass: float, radius: float, length: float) -> Body:
        """A solid cone along z whose origin is the centre of its base: base disc in the plane
        z = 0, apex at z = length, centre of mass at z = length/4 (the one solid not centred on
        the origin, so that a top's pivot, its apex, is at (0, 0, length)):
        I_z = 3/10 m r^2, I_x = 3/20 m r^2 + 3/80 m L^2 about the centre of mass."""
        return cls.solid("cone", mass, radius=radius, length=length)

    @classmethod
    def ellipsoid(cls, mass: float, semi_axes: Any) -> Body:
        """A solid ellipsoid centred on the origin, with semi-axes (a, b, c) along x, y, z:
        I_x = m (b^2 + c^2)/5."""
        return cls.solid("ellipsoid", mass, semi_axes=semi_axes)

    @classmethod
    def rod(cls, mass: float, length: float) -> Body:
        """A thin rod along z, centred on the origin: I_x = I_y = m L^2/12, I_z = 0."""
        return cls.solid("rod", mass, length=length)

    @classmethod
    def disk(cls, mass: float, radius: float) -> Body:
        """A thin disc in the xy plane, centred on the origin: I_z = m r^2/2,
        I_x = I_y = m r^2/4."""
        return cls.solid("disk", mass, radius=radius)

    @classmethod
    def torus(cls, mass: float, major_radius: float, minor_radius: float) -> Body:
        """A solid torus about z, centred on the origin: I_z = m (R^2 + 3 a^2/4),
        I_x = m (R^2/2 + 5 a^2/8)."""
        return cls.solid("torus", mass, major_radius=major_radius, minor_radius=minor_radius)

    @classmethod
    def capsule(cls, mass: float, radius: float, length: float) -> Body:
        """A cylinder of ``length`` along z capped by two hemispheres of ``radius``, centred on
        the origin (total length ``length + 2 radius``)."""
        return cls.solid("capsule", mass, radius=radius, length=length)

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
        return _formats.from_fullinertia(cls, mass, fullinertia, center_of_mass)

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
        elements = (ixx, ixy, ixz, iyy, iyz, izz)
        return _formats.from_urdf_inertia(cls, mass, elements, center_of_mass)

    # --- molecules ------------------------------------------------------------------------

    @classmethod
    def from_atoms(cls, symbols: Any, positions: Any, *, masses: Any = "most_abundant") -> Body:
        """A molecule: atoms given by element symbol (or isotope, or atomic number) and position.

        Masses in u (daltons) from the ``periodictable`` package: ``"most_abundant"`` (default)
        takes each element's most abundant isotope (AME 2020 masses; CIAAW abundances), the
        masses rotational spectroscopy needs for the main isotopologue; ``"average"`` takes the
        standard atomic weight (CIAAW 2021, abridged), as for bulk properties; an array (N,)
        gives the masses directly. A label with a mass number always means that isotope:
        ``"13C"``, ``"2H"`` (or ``"D"``), ``"T"``, ``"37Cl"``.

        Parameters
        ----------
        symbols : sequence of str or int
            N labels: ``"C"``, ``"Cl"``, ``"13C"``, ``"D"``, ``"T"``, or atomic numbers (case
            matters: ``"CL"`` is not chlorine).
        positions : (N, 3) array_like
            Positions, in angstrom for :mod:`polhode.molecule`'s default units.
        masses : {"most_abundant", "average"} or (N,) array_like, optional
            Which masses, or the masses themselves (the labels are still checked).

        Returns
        -------
        Body
            Point masses at the atoms.

        Raises
        ------
        ArgumentError
            An unknown element or isotope, naming ``symbols[i]``; an element with no natural
            abundance (``"most_abundant"``) or no standard atomic weight (``"average"``): give
            its isotope; an unknown ``masses`` choice.
        ShapeError
            No atoms; ``positions`` not (N, 3); ``masses`` not (N,).
        NonFiniteError
            A non-finite position, naming ``positions[i, k]``.
        TypeError
            ``symbols`` a single string, or holding something else than labels.

        Examples
        --------
        >>> import polhode as ph
        >>> positions = [[0, 0, 0.1173], [0, 0.7572, -0.4692], [0, -0.7572, -0.4692]]
        >>> water = ph.Body.from_atoms(["O", "H", "H"], positions)
        >>> round(water.mass, 6)  # 16O + 2 x 1H
        18.010565
        >>> round(ph.Body.from_atoms(["O", "D", "D"], positions).mass, 4)  # heavy water
        20.0231
        >>> round(ph.Body.from_atoms(["O", "H", "H"], positions, masses="average").mass, 3)
        18.015
        >>> ph.Body.from_atoms([8, 1, 1], positions).mass == water.mass  # atomic numbers
        True
        """
        labels, values = atom_masses(symbols, masses)
        r = as_array("positions", positions, (None, 3))
        if r.shape[0] != len(labels):
            raise ShapeError(
                f"Expected `positions` to have shape ({len(labels)}, 3) to match `symbols`, "
                f"got ({r.shape[0]}, 3).",
                argument="positions",
            )
        return cls.point_masses(values, r)

    @classmethod
    def from_molecule(
        cls,
        molecule: Any,
        *,
        masses: Any = "most_abundant",
        format: str | None = None,
        conformer: int = -1,
    ) -> Body:
        """A molecule from a file or from another library's molecule (duck-typed).

        ``molecule`` may be a path (read by ASE's ``ase.io.read``: XYZ, PDB, CIF, mol, SDF and
        the other formats ASE knows, the structure ``conformer`` of the file, by default the
        first; ``format`` as ASE names it, guessed from the extension by default), an ASE
        ``Atoms``, an MDAnalysis
        ``AtomGroup`` or ``Universe`` (its ``elements``, at the current frame), or an RDKit
        ``Mol`` (the conformer ``conformer``, isotopes as set on its atoms; only the atoms the
        Mol holds: add hydrogens with ``Chem.AddHs`` before embedding). Positions in angstrom,
        as all three give them; masses as in :meth:`from_atoms` (the other library's own masses
        are not used: pass them as ``masses=`` to use them). Reading a file needs ASE
        (``pip install 'polhode[chem]'``).

        Parameters
        ----------
        molecule : str, os.PathLike, ase.Atoms, MDAnalysis AtomGroup or rdkit Mol
            The molecule.
        masses : {"most_abundant", "average"} or (N,) array_like, optional
            As in :meth:`from_atoms`.
        format : str, optional
            ASE's name of the file format (``ase.io.formats.ioformats``), for a path only.
        conformer : int, optional
            For a file, the index of its structure (0 the first; a multi-frame XYZ, PDB or
            trajectory holds several); for an RDKit Mol, the conformer id. Default -1: the
            first (RDKit's default conformer). An ASE ``Atoms`` or an MDAnalysis group holds one
            structure and takes none.

        Returns
        -------
        Body

        Raises
        ------
        TypeError
            Anything else than the four kinds above.
        FileNotFoundError
            A path that does not exist.
        polhode.errors.FileFormatError
            A file ASE cannot read (naming the file; ``argument`` is ``"molecule"``).
        ArgumentError
            An RDKit Mol without conformers, an MDAnalysis group without elements, an unknown
            element; a ``conformer`` the file or the Mol does not hold, or one given with an
            ASE ``Atoms`` or an MDAnalysis group; an unknown ``format``, or one without a
            file.

        Examples
        --------
        >>> import ase.build
        >>> import polhode as ph
        >>> from polhode.molecule import rotor_type
        >>> rotor_type(ph.Body.from_molecule(ase.build.molecule("NH3")))
        'oblate'
        """
        labels, positions = atoms_of(molecule, format, conformer)
        return cls.from_atoms(labels, positions, masses=masses)

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
        return _formats.fullinertia(self.inertia)

    def to_urdf_inertia(self) -> dict[str, float]:
        """URDF/SDF ``<inertia>`` attributes {ixx, ixy, ixz, iyy, iyz, izz}: tensor elements
        about the centre of mass in body axes (I_xy = -sum m x y)."""
        return _formats.urdf_inertia(self.inertia)

    def to_mjcf(self) -> str:
        """A MuJoCo ``<inertial>`` element: centre of mass, the principal frame as a ``quat``
        (w, x, y, z, MuJoCo's order) and the principal moments as ``diaginertia``."""
        return _formats.mjcf_inertial(self)

    def to_urdf_inertial(self) -> str:
        """A URDF ``<inertial>`` element: the centre of mass and the principal frame as the
        ``<origin xyz rpy>`` (fixed-axis roll, pitch, yaw: R = Rz(y) Ry(p) Rx(r)), and the
        principal moments as a diagonal ``<inertia>``.

        The angles reproduce the principal frame to rounding, gimbal lock (pitch = +-pi/2)
        included, where the yaw is chosen from the round-off and the roll carries the rest."""
        return _formats.urdf_inertial(self)

    # --- mesh files and spatial inertia (polhode.io reads robot descriptions) ---------------

    @classmethod
    def from_file(
        cls,
        path: Any,
        *,
        density: float | None = None,
        mass: float | None = None,
        shell: bool = False,
        scale: Any = 1.0,
        fix_winding: bool = False,
    ) -> Body:
        """A uniform body from a mesh file: STL (ascii and binary), OBJ, PLY, OFF, glTF or GLB.

        The file is read by trimesh's loaders (``pip install 'polhode[mesh]'``); the mass
        properties are polhode's exact mesh integrals. A file holding several meshes (glTF
        nodes, OBJ objects, STL solids) gives their composite; :func:`polhode.io.read_mesh`
        returns the parts by name, and this body is their sum.

        Parameters
        ----------
        path : str or os.PathLike
            The mesh file (its extension says the format).
        density, mass : float
            Exactly one: mass per volume (per area with ``shell=True``), or the total mass.
        shell : bool
            The mass on the surface (a thin shell; the mesh need not be closed).
        scale : float or (3,) floats
            Applied to the coordinates (0.001 reads millimetres as metres); three numbers
            scale each axis, a negative one mirrors.
        fix_winding : bool
            Turn an inside-out mesh the right way out instead of raising.

        Raises
        ------
        FileNotFoundError
            No such file.
        polhode.errors.FileFormatError
            Not a mesh, no triangles, an open mesh (without ``shell=True``), an inside-out or
            zero-volume one; the message names the file and the part.
        polhode.errors.ArgumentError
            A ``scale`` whose mesh is beyond double precision (or flat to rounding) where the
            file's own is not, or a bad ``density``, ``mass`` or ``scale``.

        Examples
        --------
        >>> import os, tempfile
        >>> import polhode as ph
        >>> off = ("OFF\\n8 12 0\\n0 0 0\\n1 0 0\\n1 1 0\\n0 1 0\\n0 0 1\\n1 0 1\\n1 1 1\\n"
        ...        "0 1 1\\n3 0 2 1\\n3 0 3 2\\n3 4 5 6\\n3 4 6 7\\n3 0 1 5\\n3 0 5 4\\n"
        ...        "3 1 2 6\\n3 1 6 5\\n3 2 3 7\\n3 2 7 6\\n3 3 0 4\\n3 3 4 7\\n")
        >>> path = os.path.join(tempfile.mkdtemp(), "cube.off")
        >>> with open(path, "w") as handle:
        ...     _ = handle.write(off)
        >>> cube = ph.Body.from_file(path, mass=6.0, scale=0.5)  # a 0.5 m cube of 6 kg
        >>> cube.center_of_mass.tolist(), round(float(cube.inertia[0, 0]), 12)
        ([0.25, 0.25, 0.25], 0.25)
        """
        parts = list(
            read_bodies(
                cls,
                path,
                density=density,
                mass=mass,
                shell=shell,
                scale=scale,
                fix_winding=fix_winding,
            ).values()
        )
        return sum(parts[1:], parts[0])

    def spatial_inertia(
        self, point: Any = None, *, convention: str = "featherstone", inverse: bool = False
    ) -> NDArray[np.float64]:
        """The (6, 6) spatial inertia about ``point``, in body axes.

        With c the centre of mass relative to ``point``, [c] its cross-product matrix
        ([c] v = c x v), m the mass and I_p the inertia tensor about ``point``
        (I_p = I_c + m [c][c]^T):

        - ``"featherstone"`` (angular block first, for spatial vectors (omega, v)):
          ``[[I_p, m [c]], [m [c]^T, m 1]]``;
        - ``"drake"``: Drake's ``SpatialInertia.CopyToFullMatrix6()``, the same matrix
          (Drake's spatial vectors are also angular first);
        - ``"pinocchio"`` (linear block first, for (v, omega)), Pinocchio's
          ``Inertia.matrix()``: ``[[m 1, -m [c]], [m [c], I_p]]``.

        Parameters
        ----------
        point : (3,) array-like, optional
            The reference point in body coordinates; default the origin of the body's
            coordinates (a robot link's frame origin, where URDF and MJCF express a link's
            spatial inertia). Pass ``body.center_of_mass`` for the centroidal one.
        convention : {"featherstone", "drake", "pinocchio"}
            The order of the blocks.
        inverse : bool
            Return the inverse (the spatial compliance), from its closed form:
            ``[[I_c^-1, -I_c^-1 [c]], [[c] I_c^-1, 1/m - [c] I_c^-1 [c]]]`` (Featherstone
            order). A body with a zero principal moment (a rod, a point mass) has none
            (InertiaError).

        Examples
        --------
        >>> import numpy as np
        >>> import polhode as ph
        >>> rod = ph.Body.cylinder(2.0, 0.01, 1.0).translated([0.0, 0.0, 0.5])
        >>> s = rod.spatial_inertia()  # about the end of the rod
        >>> round(float(s[0, 0]), 6), s[3:, 3:].tolist()[0], float(s[0, 4])
        (0.666717, [2.0, 0.0, 0.0], -1.0)
        >>> bool(np.allclose(rod.spatial_inertia(inverse=True) @ s, np.eye(6)))
        True
        """
        if convention not in SPATIAL_CONVENTIONS:
            raise ArgumentError(
                f"Expected `convention` to be one of {', '.join(SPATIAL_CONVENTIONS)}, "
                f"got {convention!r}.",
                argument="convention",
            )
        return _spatial.spatial_inertia(self, point, inverse, convention == "pinocchio")

    @classmethod
    def from_spatial_inertia(
        cls,
        matrix: Any,
        point: Any = None,
        *,
        convention: str = "featherstone",
        rtol: float = 1e-12,
    ) -> Body:
        """A body from its (6, 6) spatial inertia about ``point`` (body coordinates; default
        the origin), in the block order of ``convention`` (see :meth:`spatial_inertia`).

        The matrix is checked: symmetric, its mass block m times the identity with m > 0, its
        coupling block m times a cross-product matrix (skew), each to ``rtol`` times the
        largest entry; the rotational inertia about the centre of mass it implies must be a
        valid inertia tensor (positive semidefinite, triangle inequality) to within the
        rounding of its recovery, 16 eps ||I_p|| (a point mass, rod or flat body away from
        ``point`` is put back on that boundary). Each failure raises a typed error naming
        ``matrix``.

        The format holds the inertia about ``point``, I_p = I_c + m [c][c]^T; recovering I_c
        subtracts, so a point far from the centre of mass costs digits (the error is about
        eps ||I_p||, not eps ||I_c||). ``point=body.center_of_mass`` loses none.

        Raises
        ------
        polhode.errors.ShapeError
            Not (6, 6).
        polhode.errors.NonFiniteError, NonPositiveError
            A NaN or infinity; a mass block that is not positive.
        polhode.errors.InertiaError
            Not symmetric, a mass block that is not m 1, a coupling block that is not skew, or
            an implied inertia tensor that is not one.

        Examples
        --------
        >>> import numpy as np
        >>> import polhode as ph
        >>> body = ph.Body.cuboid(3.0, [0.1, 0.2, 0.3]).translated([0.1, 0.0, 0.2])
        >>> again = ph.Body.from_spatial_inertia(body.spatial_inertia(convention="pinocchio"),
        ...                                      convention="pinocchio")
        >>> float(np.abs(again.inertia - body.inertia).max()) < 1e-16  # I_p - m [c][c]^T
        True
        >>> bool(np.allclose(again.center_of_mass, [0.1, 0.0, 0.2], rtol=1e-15, atol=0))
        True
        """
        if convention not in SPATIAL_CONVENTIONS:
            raise ArgumentError(
                f"Expected `convention` to be one of {', '.join(SPATIAL_CONVENTIONS)}, "
                f"got {convention!r}.",
                argument="convention",
            )
        return _spatial.from_spatial_inertia(cls, matrix, point, rtol, convention == "pinocchio")

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

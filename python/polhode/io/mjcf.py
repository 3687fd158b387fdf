"""MJCF: the bodies of a MuJoCo model as MuJoCo's compiler gives them (or, with
``as_written=True``, as the file writes them), parsed by MuJoCo's ``MjSpec``."""

from __future__ import annotations

import os
import warnings
from dataclasses import dataclass

import numpy as np

from polhode._coerce import as_flag, density_or_mass
from polhode._files import fspath
from polhode.bodies import Body
from polhode.errors import ArgumentError, FileFormatError, PolhodeError, RobotFileWarning
from polhode.io._mjcf_compile import CompiledBody, body_names, compile_bodies
from polhode.io._mjcf_written import mjcf_links, mjcf_spec, read_as_written
from polhode.io._robot import Links

__all__ = ["LegacyMeshInertia", "legacy_mesh_inertia", "mjcf_links", "read_mjcf"]


def read_mjcf(
    path: str | os.PathLike[str],
    *,
    as_written: bool = False,
    merge_fixed: bool | None = None,
    strict: bool = False,
    density: float | None = None,
    mass: float | None = None,
) -> Links:
    """The bodies of a MuJoCo MJCF file, each in its own frame, with the mass, centre of mass
    and inertia MuJoCo's compiler gives them.

    MuJoCo parses the file (``mujoco.MjSpec.from_file``: includes, defaults and classes);
    polhode computes every mass property, as MuJoCo 4.0.0's compiler defines it:

    - ``inertiafromgeom``: ``"auto"`` (the default) takes a body's ``<inertial>``, or its geoms
      if it has none; ``"true"`` its geoms even if it has one (the ``<inertial>`` stays when
      no geom counts); ``"false"`` the ``<inertial>`` only;
    - the geoms counted are those of a group in ``inertiagrouprange`` and of mass above 1e-14,
      each of mass ``mass`` or ``density`` times its volume (its area with ``shellinertia``);
      MuJoCo drops a ``mass`` given to a geom of volume at most 1e-14 (a plane, a tiny
      sphere) without a word, and so does polhode, with a note;
    - spheres, capsules, cylinders, ellipsoids, boxes (``fromto`` too), height fields (as
      MuJoCo's box), primitives fitted to a mesh, and meshes: binary STL, OBJ (MuJoCo takes
      the faces of the first object only) and MSH, their vertices rounded to float32 as
      MuJoCo stores them, moved by ``refpos``, ``refquat`` and ``scale``, integrated as the
      mesh's ``inertia`` says: ``"exact"``, ``"convex"`` (the hull), ``"shell"`` exactly,
      and ``"legacy"`` (MuJoCo 4.0.0's default) by MuJoCo's own formula, which over-counts
      the volume of non-convex meshes (:func:`legacy_mesh_inertia` says by how much);
    - geoms inside ``<frame>``s, and frames that ``scale`` their contents (with
      ``massscale``; one scale for the three axes);
    - ``boundmass`` and ``boundinertia`` (they also turn a negative mass or moment into 0),
      ``balanceinertia``, and ``settotalmass`` last, static bodies too.

    A body of no mass is not a :class:`Body`: it is named in ``frames`` of the result. A body
    MuJoCo refuses (a moving body whose mass or a principal moment is below 1e-15, a tensor
    that breaks the triangle inequality, a geom or mesh it cannot compile) is left out and
    named, with the reason, in one :class:`polhode.RobotFileWarning` and in ``left_out``;
    ``strict=True`` raises the first as a FileFormatError instead.

    MuJoCo's own eigensolver stops early (at 1e-12 absolute, or a rotation under 1.4e-6
    rad), so its tensors can differ from these, the exact ones, by up to about 1.5e-6 times
    the spread of the principal moments; masses, centres and principal moments agree to
    round-off. With ``alignfree``, MuJoCo moves a free body's frame onto its centre of mass;
    the values here stay in the body's frame as the file writes it.

    Parameters
    ----------
    path : str or os.PathLike
        The MJCF (MuJoCo XML) file.
    as_written : bool
        Read the file's own values instead, before MuJoCo's compiler changes them: each
        declared ``<inertial>`` as it is, the geoms of bodies without one (polhode's exact
        integrals for every mesh), no bounds, no ``settotalmass``; a tensor no body can
        have raises. The audit compares these with the geometry.
    merge_fixed : bool, optional
        Fuse the bodies without joints into their parents, as MuJoCo's ``fusestatic`` does
        (MuJoCo decides which: a body referenced elsewhere or ``fuse="false"`` stays); a
        body fused into the world is dropped with its mass, as in MuJoCo. The fused bodies
        are listed in ``merged``. Default: as the file's ``<compiler fusestatic>`` says
        (false unless it says so).
    strict : bool
        Raise a FileFormatError for the first body MuJoCo refuses, or whose negative mass
        or moment it raises to 0, instead of leaving it out with a warning.
    density : float, optional
        With ``as_written=True``: one density for the geoms of every body without an
        inertial (instead of the geoms' own ``density`` and ``mass``).
    mass : float, optional
        With ``as_written=True``: the total mass of the bodies without an inertial, shared
        in proportion to the volumes of their geoms.

    Returns
    -------
    polhode.io.Links
        ``{name: Body}`` by body name in the file's order (an unnamed body as ``"body K"``,
        K its MuJoCo body id without fusing, or ``"body K (unnamed)"`` if a body is named
        ``"body K"``), the world left out; with ``frames``, ``left_out``, ``merged`` and
        ``notes``.

    Raises
    ------
    FileNotFoundError
        No such file.
    polhode.errors.FileFormatError
        MuJoCo cannot parse the file (its message, with the body around the line it names),
        an ``<inertial>`` with both ``diaginertia`` and ``fullinertia``, a stretching
        ``<frame>``; with ``strict=True`` a body MuJoCo refuses; with ``as_written=True`` a
        declared inertial that is not one, or a geom whose mass properties cannot be
        computed. ``link`` and ``field`` name the body and the attribute.
    polhode.errors.ArgumentError
        ``density`` or ``mass`` without ``as_written=True``, or both; ``merge_fixed`` with
        ``as_written=True``.

    Warns
    -----
    polhode.RobotFileWarning
        Bodies left out (MuJoCo refuses them), negative masses or moments read as 0.

    Examples
    --------
    >>> import os, tempfile
    >>> import polhode as ph
    >>> xml = '''<mujoco><compiler inertiafromgeom="true"/><worldbody>
    ...   <body name="arm"><joint/><inertial pos="0 0 0.1" mass="2" diaginertia="0.02 0.02 0.01"/>
    ...     <geom type="box" size="0.05 0.05 0.2" pos="0 0 0.2" density="500"/></body>
    ...   <body name="mount"/>
    ... </worldbody></mujoco>'''
    >>> path = os.path.join(tempfile.mkdtemp(), "m.xml")
    >>> with open(path, "w") as handle:
    ...     _ = handle.write(xml)
    >>> bodies = ph.io.read_mjcf(path)       # as MuJoCo simulates it: the box, 500 x 0.004
    >>> round(bodies["arm"].mass, 12), bodies["arm"].center_of_mass.tolist(), list(bodies.frames)
    (2.0, [0.0, 0.0, 0.2], ['mount'])
    >>> written = ph.io.read_mjcf(path, as_written=True)   # the <inertial> as written
    >>> written["arm"].center_of_mass.tolist()
    [0.0, 0.0, 0.1]
    """
    path = fspath(path)
    as_flag("as_written", as_written)
    as_flag("strict", strict)
    if merge_fixed is not None:
        as_flag("merge_fixed", merge_fixed)
    if as_written:
        if merge_fixed:
            raise ArgumentError(
                "merge_fixed fuses bodies as MuJoCo compiles them: it does not apply with "
                "as_written=True.",
                argument="merge_fixed",
            )
        rho, total = density_or_mass(density, mass, required=False)
        bodies = read_as_written(path, rho, total)
        frames = {
            n: "no mass as written" for n in body_names(mjcf_spec(path))[1:] if n not in bodies
        }
        return Links(bodies, path=path, frames=frames)
    if density is not None or mass is not None:
        raise ArgumentError(
            "density and mass replace the masses the file gives its geoms, which MuJoCo "
            "never does: they need as_written=True.",
            argument="density" if density is not None else "mass",
        )
    spec = mjcf_spec(path)
    fuse = bool(spec.compiler.fusestatic) if merge_fixed is None else bool(merge_fixed)
    records = compile_bodies(spec, path, fuse=fuse)
    return _result(path, records, strict)


def _result(path: str, records: list[CompiledBody], strict: bool) -> Links:
    """The compiled bodies as Links; the warning (or, strict, the error) for the
    bodies left out and the values MuJoCo changes."""
    names = {r.index: r.name for r in records}
    into = {r.index: r.merged_into for r in records}
    out = Links(path=path)
    refused: dict[str, tuple[str, str]] = {}
    clamped: dict[str, tuple[str, str]] = {}
    for r in records:
        if r.notes:
            out.notes[r.name] = list(r.notes)
        if r.merged_into is not None:
            target = r.merged_into
            while into.get(target) is not None:  # merged into a body merged in turn
                target = into[target]  # type: ignore[assignment]
            out.merged[r.name] = names.get(target, "world")
            continue
        if r.problem is not None:
            refused[r.name] = r.problem
            continue
        if r.clamped is not None:
            clamped[r.name] = r.clamped
            out.notes.setdefault(r.name, []).append(r.clamped[1])
        body = None
        try:
            body = r.body()
        except PolhodeError as error:
            refused[r.name] = ("inertial", error.message)
            continue
        if body is None:
            out.frames[r.name] = (
                "mass 0: a moving body whose mass is on the bodies fixed to it"
                if r.moving
                else "mass 0: a body without joints"
            )
        else:
            out[r.name] = body
    if strict:
        for name, (field, reason) in list(refused.items()) + list(clamped.items()):
            raise FileFormatError(
                f"{path}: body {name!r}: {field}: {reason}", path=path, link=name, field=field
            )
    out.left_out = {name: f"{field}: {reason}" for name, (field, reason) in refused.items()}
    if refused or clamped:
        parts = []
        if refused:
            listed = "; ".join(f"{n!r} ({why})" for n, why in out.left_out.items())
            parts.append(
                f"{len(refused)} {'body' if len(refused) == 1 else 'bodies'} left out "
                f"(MuJoCo refuses the model for {'it' if len(refused) == 1 else 'them'}): "
                f"{listed}"
            )
        if clamped:
            listed = "; ".join(f"{n!r} ({why})" for n, (_, why) in clamped.items())
            parts.append(f"read as MuJoCo compiles it: {listed}")
        warnings.warn(
            RobotFileWarning(f"{path}: " + ". ".join(parts) + ".", path=path, links=out.left_out),
            stacklevel=3,
        )
    return out


@dataclass(frozen=True)
class LegacyMeshInertia:
    """A body whose inertial MuJoCo computes with ``legacy`` mesh inertia (MuJoCo 4.0.0's
    default), against the exact integrals of the same meshes.

    Attributes
    ----------
    body : str
        The body.
    meshes : tuple of str
        Its meshes in ``legacy`` mode.
    legacy : Body or None
        The body as MuJoCo compiles it (None if MuJoCo refuses it).
    exact : Body or None
        The body with those meshes integrated exactly (None if a mesh has no exact volume:
        it is open or inconsistently wound).
    reason : str or None
        Why ``exact`` (or ``legacy``) is None.

    Examples
    --------
    >>> import polhode as ph
    >>> from polhode.io import LegacyMeshInertia
    >>> found = LegacyMeshInertia("arm", ("arm_mesh",), ph.Body.sphere(1.3, 0.1),
    ...                           ph.Body.sphere(1.0, 0.1), None)
    >>> round(found.mass_error, 12), round(found.inertia_error, 12)
    (0.3, 0.3)
    """

    body: str
    meshes: tuple[str, ...]
    legacy: Body | None
    exact: Body | None
    reason: str | None

    @property
    def mass_error(self) -> float:
        """(legacy - exact) / exact mass: what MuJoCo's legacy integral adds (NaN when either
        is missing)."""
        if self.legacy is None or self.exact is None:
            return float("nan")
        return (self.legacy.mass - self.exact.mass) / self.exact.mass

    @property
    def inertia_error(self) -> float:
        """||I_legacy - I_exact|| / ||I_exact|| (Frobenius, about each one's centre of mass,
        in the body's axes; NaN when either is missing)."""
        if self.legacy is None or self.exact is None:
            return float("nan")
        exact = self.exact.inertia
        return float(np.linalg.norm(self.legacy.inertia - exact) / np.linalg.norm(exact))

    @property
    def center_error(self) -> float:
        """Distance between the two centres of mass (NaN when either is missing)."""
        if self.legacy is None or self.exact is None:
            return float("nan")
        return float(np.linalg.norm(self.legacy.center_of_mass - self.exact.center_of_mass))


def legacy_mesh_inertia(path: str | os.PathLike[str]) -> dict[str, LegacyMeshInertia]:
    """The bodies of an MJCF file whose inertial MuJoCo computes from meshes in its
    ``legacy`` mode (the default of ``<mesh inertia>`` in MuJoCo 4.0.0), each as MuJoCo
    compiles it and with those meshes integrated exactly (as ``inertia="exact"`` would,
    but polhode's exact integral even where MuJoCo refuses ``exact``, and none for a mesh
    that is not closed). MuJoCo's legacy integral sums the pyramids from the faces' centroid
    in absolute value: it is exact for meshes seen whole from that point, and over-counts
    the others (a U-shaped prism by 23 %).

    Bodies are compiled as :func:`read_mjcf` does (without fusing); ``mass_error``,
    ``inertia_error`` and ``center_error`` say by how much the two differ.

    Parameters
    ----------
    path : str or os.PathLike
        The MJCF file.

    Returns
    -------
    dict[str, LegacyMeshInertia]
        By body name, in the file's order; bodies without legacy meshes are not in it.

    Examples
    --------
    >>> import os, tempfile
    >>> import polhode as ph
    >>> u = [(0, 0), (3, 0), (3, 3), (2, 3), (2, 1), (1, 1), (1, 3), (0, 3)]   # a U prism
    >>> vertices = " ".join(f"{x} {y} {z}" for z in (0, 1) for x, y in u)
    >>> caps = [(0, 1, 4), (0, 4, 5), (1, 2, 4), (2, 3, 4), (0, 5, 7), (5, 6, 7)]
    >>> faces = [f[::-1] for f in caps] + [tuple(i + 8 for i in f) for f in caps]
    >>> faces += [f for i in range(8) for f in ((i, (i + 1) % 8, (i + 1) % 8 + 8),
    ...                                         (i, (i + 1) % 8 + 8, i + 8))]
    >>> xml = f'''<mujoco><asset><mesh name="u" vertex="{vertices}"
    ...   face="{" ".join(str(i) for f in faces for i in f)}"/></asset>
    ...   <worldbody><body name="u"><freejoint/><geom type="mesh" mesh="u"/></body>
    ... </worldbody></mujoco>'''
    >>> path = os.path.join(tempfile.mkdtemp(), "u.xml")
    >>> with open(path, "w") as handle:
    ...     _ = handle.write(xml)
    >>> found = ph.io.legacy_mesh_inertia(path)["u"]
    >>> round(found.exact.mass), round(found.legacy.mass, 2), f"{found.mass_error:.1%}"
    (7000, 8617.54, '23.1%')
    """
    path = fspath(path)
    spec = mjcf_spec(path)
    legacy = {r.name: r for r in compile_bodies(spec, path, fuse=False)}
    exact = {
        r.name: r for r in compile_bodies(mjcf_spec(path), path, fuse=False, exact_legacy=True)
    }
    out: dict[str, LegacyMeshInertia] = {}
    for name, record in legacy.items():
        if not record.legacy:
            continue
        other = exact[name]
        reason = None
        mj = None if record.problem else _body_or_none(record)
        if record.problem:
            reason = f"MuJoCo refuses the body: {record.problem[1]}"
        ex = None if other.problem else _body_or_none(other)
        if other.problem:
            reason = other.problem[1]
        meshes = tuple(dict.fromkeys(record.legacy))
        out[name] = LegacyMeshInertia(name, meshes, mj, ex, reason)
    return out


def _body_or_none(record: CompiledBody) -> Body | None:
    try:
        return record.body()
    except PolhodeError:
        return None

"""MJCF bodies as MuJoCo 4.0.0's compiler gives them (user_objects.cc mjCBody::Compile,
InertiaFromGeom; user_model.cc's checks, settotalmass and fusestatic), from the file's MjSpec.

For each body, in this order:

1. its inertial: the explicit ``<inertial>`` (``diaginertia`` turned by its orientation, or
   ``fullinertia``), unless ``inertiafromgeom`` is ``true`` and a geom is selected, or its geoms'
   (``true``, or ``auto`` for a body without ``<inertial>``): the geoms whose group is in
   ``inertiagrouprange`` and whose mass is above 1e-14 (:mod:`polhode.io._mjcf_geoms`);
2. ``boundmass`` and ``boundinertia`` (on the principal moments; a negative mass or moment
   becomes 0, since both default to 0), then the triangle inequality, which
   ``balanceinertia`` fixes by taking the mean moment;
3. bodies without joints fused into their parent when ``fusestatic`` (or ``merge_fixed``)
   asks, MuJoCo deciding which (its own ``MjSpec.fuse_static`` on a copy of the spec: a body
   referenced elsewhere, ``fuse="false"``... stays);
4. the moving bodies (with joints) MuJoCo refuses: mass and every principal moment at least
   mjMINVAL (1e-15), in the body or a descendant reached through bodies without joints;
5. ``settotalmass``: every mass and inertia times one factor, static bodies too.

A body MuJoCo would refuse (a geom it cannot compile, a tensor it rejects, a moving body of no
mass) gets a ``problem`` and stays out of the result; the rest is read.
"""

from __future__ import annotations

import importlib
import os
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from polhode.bodies import Body
from polhode.errors import FileFormatError, PolhodeError
from polhode.io._links import placed, symmetric
from polhode.io._mjcf_geoms import (
    EPS,
    FileLevelError,
    GeomError,
    Meshes,
    Placement,
    frame_placement,
    geom_inertial,
    orientation,
)
from polhode.io._mujoco_mesh import quat_matrix

__all__ = ["MINVAL", "CompiledBody", "body_names", "compile_bodies"]

#: MuJoCo's mjMINVAL: the least mass and principal moment of a moving body.
MINVAL = 1e-15


@dataclass
class CompiledBody:
    """One body as MuJoCo compiles it: mass, centre and tensor (about the centre) in the
    body's own frame; ``problem`` (field, reason) if MuJoCo refuses it; the meshes its
    inertial integrates in ``legacy`` mode; notes; and what fusing needs (its parent's index,
    its placement in the parent, whether it has joints)."""

    name: str
    index: int
    parent: int
    moving: bool
    rotation: NDArray[np.float64]
    offset: NDArray[np.float64]
    mass: float = 0.0
    center: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))
    tensor: NDArray[np.float64] = field(default_factory=lambda: np.zeros((3, 3)))
    moments: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))
    problem: tuple[str, str] | None = None
    clamped: tuple[str, str] | None = None
    legacy: tuple[str, ...] = ()
    notes: list[str] = field(default_factory=list)
    merged_into: int | None = None
    geoms: Body | None = None  # its selected geoms' sum, in its frame
    always: bool = False  # inertiafromgeom="true": its geoms replace its <inertial>
    fused: bool = False  # bodies were fused into it

    def body(self) -> Body | None:
        """The Body, or None for a body of no mass."""
        if not self.mass > 0:
            return None
        return Body.from_inertia(self.mass, self.tensor, self.center)


def body_names(spec: Any) -> list[str]:
    """The names of the spec's bodies by index (the world first): an unnamed body is
    "body K" (K its index, MuJoCo's body id when nothing is fused), or "body K (unnamed)" if
    a body is named so."""
    taken = {body.name for body in spec.bodies if body.name}
    names = []
    for index, body in enumerate(spec.bodies):
        name = body.name
        if not name:
            name = f"body {index}"
            while name in taken:
                name += " (unnamed)"
        names.append(name)
    return names


def compile_bodies(
    spec: Any, path: str, *, fuse: bool, exact_legacy: bool = False
) -> list[CompiledBody]:
    """Every body of the spec but the world, as MuJoCo compiles it (see the module)."""
    mujoco = importlib.import_module("mujoco")
    names = body_names(spec)
    index_of = {b: k for k, b in enumerate(spec.bodies)}
    meshes = Meshes(spec, os.path.dirname(os.path.abspath(path)), exact_legacy)
    scales: dict[int, Placement] = {0: Placement()}
    out: list[CompiledBody] = []
    for k, spec_body in enumerate(spec.bodies):
        if k == 0:
            continue
        parent = index_of[spec_body.parent]
        record = CompiledBody(
            names[k], k, parent, len(spec_body.joints) > 0, np.eye(3), np.zeros(3)
        )
        out.append(record)
        try:
            outer = _place(spec_body, scales[parent], record)
            scales[k] = outer
            _inertial(mujoco, spec_body, record, meshes, outer, path)
        except FileLevelError as error:
            raise FileFormatError(
                f"{path}: body {record.name!r}: {error.field}: {error.message}",
                path=path,
                link=record.name,
                field=error.field,
            ) from None
        except GeomError as error:
            record.problem = (error.field, error.message)
            scales.setdefault(k, scales[parent])
        except FileFormatError:
            raise
        except PolhodeError as error:  # a sum or placement beyond double precision
            record.problem = ("inertial", error.message)
            scales.setdefault(k, scales[parent])
    by_index = {b.index: b for b in out}
    if fuse:
        try:
            _fuse(mujoco, spec, names, by_index)
        except ValueError as error:  # MuJoCo cannot fuse the model at all
            if isinstance(error, PolhodeError):
                raise
            raise FileFormatError(
                f"{path}: MuJoCo cannot fuse its static bodies: {str(error).strip()}",
                path=path,
                field="compiler.fusestatic",
            ) from error
    _check_moving(by_index)
    total = float(spec.compiler.settotalmass)
    if total > 0:
        kept = [b for b in out if b.problem is None and b.merged_into is None]
        mass = sum(b.mass for b in kept)
        factor = max(MINVAL, total / max(MINVAL, mass))
        for b in kept:
            b.mass *= factor
            b.tensor = b.tensor * factor
            b.moments = b.moments * factor
    return out


def _place(spec_body: Any, parent: Placement, record: CompiledBody) -> Placement:
    """The body's placement in its parent (through the frames between) and the scale of
    everything in it."""
    rotation, offset, scale, mass = frame_placement(spec_body)
    quat = orientation(spec_body.compiler, spec_body.quat, spec_body.alt)
    record.rotation = rotation @ quat_matrix(quat)
    record.offset = parent.scale * (
        offset + rotation @ (scale * np.asarray(spec_body.pos, dtype=float))
    )
    return Placement(parent.scale * scale, parent.mass * mass)


def _inertial(
    mujoco: Any,
    spec_body: Any,
    record: CompiledBody,
    meshes: Meshes,
    outer: Placement,
    path: str,
) -> None:
    """Steps 1 and 2 of the module for one body."""
    compiler = spec_body.compiler
    flag = compiler.inertiafromgeom
    always = flag == mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_TRUE
    auto = flag == mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_AUTO
    explicit = bool(spec_body.explicitinertial)
    # The explicit inertial: (mass, centre, principal moments, their axes).
    declared = _declared(spec_body, record, outer, path) if explicit else None
    inertial = declared
    if always or (auto and not explicit):
        low, high = (int(x) for x in compiler.inertiagrouprange)
        parts: list[Body] = []
        for n, geom in enumerate(spec_body.geoms):
            if not low <= geom.group <= high:
                continue
            label = f"geom {geom.name!r}" if geom.name else f"geom[{n}]"
            share = geom_inertial(geom, label, meshes, outer)
            record.legacy += share.legacy if share.body is not None else ()
            record.notes += [f"{label}: {note}" for note in share.notes]
            if share.body is not None and share.body.mass > EPS:
                parts.append(share.body)
        record.always = always
        if parts:
            total = sum(parts[1:], parts[0])
            record.geoms = total
            moments, axes = _principal(total.inertia)
            inertial = (total.mass, total.center_of_mass, moments, axes, total.inertia)
        elif declared is None:
            inertial = None
    if inertial is None:
        # No inertial: MuJoCo puts the (empty) inertial frame at the body's own pos and quat.
        quat = orientation(compiler, spec_body.quat, spec_body.alt)
        inertial = (
            0.0,
            outer.scale * np.asarray(spec_body.pos, dtype=float),
            np.zeros(3),
            quat_matrix(quat),
            np.zeros((3, 3)),
        )
    mass, center, moments, axes, tensor = inertial
    source = "inertial"  # the field a broken tensor came from
    if inertial is declared:
        full = not np.isnan(np.asarray(spec_body.fullinertia, dtype=float)[0])
        source = "inertial.fullinertia" if full else "inertial.diaginertia"
    bounded_mass = max(mass, float(compiler.boundmass))
    bounded = np.maximum(moments, float(compiler.boundinertia))
    if mass < 0 or np.any(moments < 0):
        record.clamped = (
            "inertial.mass" if mass < 0 else "inertial.diaginertia",
            f"MuJoCo turns its negative {'mass' if mass < 0 else 'moments'} "
            f"({mass:g} kg, moments {np.asarray(moments).tolist()}) into "
            f"{bounded_mass:g} kg, moments {bounded.tolist()} (boundmass, boundinertia)",
        )
    if bounded_mass < 0 or np.any(bounded < 0):
        raise GeomError("inertial", "mass and inertia cannot be negative.")
    a, b, c = (float(x) for x in bounded)  # floats: a sum past the largest double is inf
    if a + b < c or a + c < b or b + c < a:
        if compiler.balanceinertia:
            bounded = np.full(3, (a + b + c) / 3.0)
        else:
            raise GeomError(
                source,
                f"its principal moments {bounded.tolist()} break the triangle inequality "
                "A + B >= C, which MuJoCo refuses ('balanceinertia' would average them).",
            )
    if not np.array_equal(bounded, moments):
        tensor = axes @ np.diag(bounded) @ axes.T
    record.mass = bounded_mass
    record.center = np.asarray(center, dtype=float)
    record.tensor = symmetric(tensor)
    record.moments = bounded


def _declared(
    spec_body: Any, record: CompiledBody, outer: Placement, path: str
) -> tuple[
    float, NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]
]:
    """The explicit ``<inertial>``, scaled by the body's frames."""
    compiler = spec_body.compiler
    diagonal = np.asarray(spec_body.inertia, dtype=float)
    full = np.asarray(spec_body.fullinertia, dtype=float)
    center = np.asarray(spec_body.ipos, dtype=float)
    if not np.all(np.isfinite(center)):
        raise FileLevelError("inertial.pos", f"expected 3 finite numbers, got {center.tolist()}.")
    if not np.isnan(full[0]):
        if np.any(diagonal != 0):
            raise FileFormatError(
                f"{path}: body {record.name!r}: inertial: both diaginertia "
                f"{diagonal.tolist()} and fullinertia {full.tolist()} are given (MuJoCo "
                "refuses the model); give one.",
                path=path,
                link=record.name,
                field="inertial.diaginertia",
            )
        if not np.all(np.isfinite(full)):
            raise FileLevelError(
                "inertial.fullinertia", f"expected finite numbers, got {full.tolist()}."
            )
        xx, yy, zz, xy, xz, yz = full
        tensor = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
        moments, axes = _principal(tensor)
        if moments.min() < EPS and not (
            float(compiler.boundinertia) > 0
            and moments.min() >= -EPS * max(1.0, abs(moments).max())
        ):
            raise GeomError(
                "inertial.fullinertia",
                f"its eigenvalues {moments.tolist()} are not all positive, which MuJoCo "
                "refuses ('inertia must have positive eigenvalues').",
            )
    else:
        if not np.all(np.isfinite(diagonal)):
            raise FileLevelError(
                "inertial.diaginertia", f"expected finite numbers, got {diagonal.tolist()}."
            )
        axes = quat_matrix(orientation(compiler, spec_body.iquat, spec_body.ialt))
        moments = diagonal
        tensor = axes @ np.diag(diagonal) @ axes.T
    mass = float(spec_body.mass)
    if not np.isfinite(mass):
        raise FileLevelError("inertial.mass", f"expected a finite mass, got {mass}.")
    s, m = outer.scale, outer.mass
    return mass * m, center * s, moments * m * s * s, axes, tensor * (m * s * s)


def _principal(tensor: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Principal moments and axes (columns, a rotation) of a symmetric tensor."""
    moments, axes = np.linalg.eigh(symmetric(tensor))
    if np.linalg.det(axes) < 0:
        axes[:, 0] = -axes[:, 0]
    return moments, axes


def _fuse(mujoco: Any, spec: Any, names: list[str], by_index: dict[int, CompiledBody]) -> None:
    """Bodies without joints into their parents, as MuJoCo's fusestatic (step 3)."""
    kept = _kept_after_fusing(mujoco, spec, names)
    # Children before parents: the deepest bodies first (indices follow the tree order).
    for k in sorted(by_index, reverse=True):
        child = by_index[k]
        if names[k] in kept:
            continue
        parent = by_index.get(child.parent)
        child.merged_into = child.parent
        if parent is None:  # fused into the world: its mass is dropped
            continue
        parent.legacy += child.legacy
        parent.notes += [f"{child.name} (merged): {note}" for note in child.notes]
        if child.problem is not None and parent.problem is None:
            parent.problem = (
                child.problem[0],
                f"body {child.name!r}, merged into it: {child.problem[1]}",
            )
        parent.fused = True
        if child.geoms is not None:
            moved_geoms = placed(child.geoms, child.rotation, child.offset)
            parent.geoms = moved_geoms if parent.geoms is None else parent.geoms + moved_geoms
        if child.mass > 0 and not parent.always:
            moved = placed(
                Body.from_inertia(child.mass, child.tensor, child.center),
                child.rotation,
                child.offset,
            )
            if parent.mass > 0:
                moved = Body.from_inertia(parent.mass, parent.tensor, parent.center) + moved
            parent.mass = moved.mass
            parent.center = moved.center_of_mass
            parent.tensor = moved.inertia
            parent.moments = np.linalg.eigvalsh(moved.inertia)
    # With inertiafromgeom="true", MuJoCo infers the fused body's inertial again from all its
    # geoms (its own and those fused into it), and the <inertial>s of the bodies fused into it
    # are lost; with no geom at all, the body keeps its own.
    for b in by_index.values():
        if b.fused and b.always and b.geoms is not None and b.merged_into is None:
            b.mass = b.geoms.mass
            b.center = b.geoms.center_of_mass
            b.tensor = b.geoms.inertia
            b.moments = np.linalg.eigvalsh(b.tensor)
    # A merged body's own children now hang from the body it went into.
    for b in by_index.values():
        target = b.parent
        while target in by_index and by_index[target].merged_into is not None:
            step = by_index[target]
            b.rotation = step.rotation @ b.rotation
            b.offset = step.offset + step.rotation @ b.offset
            target = step.merged_into  # type: ignore[assignment]
        b.parent = target


def _kept_after_fusing(mujoco: Any, spec: Any, names: list[str]) -> set[str]:
    """The names of the bodies MuJoCo keeps when it fuses the static ones: its own
    ``fuse_static`` on a copy whose unnamed bodies get names (unnamed bodies cannot be
    referenced, so a name changes nothing). If the copy cannot be fused (a mesh MuJoCo
    cannot load), its meshes are replaced by tetrahedra first: MuJoCo decides by structure
    (joints, references, ``fuse``), masses only matter for gravity compensation."""
    if not hasattr(spec, "fuse_static"):
        raise ImportError(
            "fusing static bodies as MuJoCo does needs MuJoCo's MjSpec.fuse_static (MuJoCo "
            ">= 3.16): pip install 'mujoco>=4'."
        )
    for attempt in range(2):
        copy = spec.copy()
        for k, b in enumerate(copy.bodies):
            if not b.name:
                b.name = names[k]
        if attempt == 1:
            for mesh in copy.meshes:
                mesh.file = ""
                mesh.uservert = [0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1]
                mesh.userface = []
        try:
            copy.fuse_static()
        except Exception:  # MuJoCo's errors are ValueErrors with its message
            if attempt == 1:
                raise
            continue
        return {b.name for b in copy.bodies}
    raise AssertionError("unreachable")


def _check_moving(by_index: dict[int, CompiledBody]) -> None:
    """Step 4: moving bodies whose mass or a principal moment is below mjMINVAL, with no
    descendant through bodies without joints that has them, are refused."""
    children: dict[int, list[int]] = {}
    for b in by_index.values():
        if b.merged_into is None:
            children.setdefault(b.parent, []).append(b.index)

    def valid(k: int) -> bool:
        b = by_index[k]
        if b.problem is None and b.mass >= MINVAL and np.all(b.moments >= MINVAL):
            return True
        return any(not by_index[c].moving and valid(c) for c in children.get(k, []))

    for b in by_index.values():
        if b.moving and b.merged_into is None and b.problem is None and not valid(b.index):
            b.problem = (
                "inertial",
                f"MuJoCo refuses a moving body of mass {b.mass:g} and principal moments "
                f"{np.asarray(b.moments).tolist()}: the mass and inertia of moving bodies "
                "must be at least mjMINVAL (1e-15), in the body or in a body fixed to it",
            )

"""``polhode inertia``: the mass properties of a mesh file, of a robot description's links or of
a molecule (with its rotational constants)."""

from __future__ import annotations

import argparse
import csv
import json
import os
import sys
import warnings
from typing import Any

import numpy as np

import polhode as ph
from polhode._atoms import ase_readers, formula
from polhode._formats import number
from polhode.cli._common import UsageError, check_file, json_numbers

#: ``polhode inertia``: robot descriptions by extension (then URDF or MJCF by the XML's root
#: element), meshes by ``polhode.io.MESH_FORMATS``; any other file is a molecule read by ASE.
ROBOT_EXTENSIONS = ("urdf", "xml", "mjcf")


#: The options of ``polhode inertia`` that apply to some kinds of file only:
#: option -> (attribute, kinds).
INERTIA_OPTIONS = {
    "--density": ("density", ("mesh", "urdf", "mjcf")),
    "--mass": ("mass", ("mesh", "urdf", "mjcf")),
    "--scale": ("scale", ("mesh",)),
    "--shell": ("shell", ("mesh",)),
    "--fix-winding": ("fix_winding", ("mesh",)),
    "--merge-fixed": ("merge_fixed", ("urdf",)),
    "--strict": ("strict", ("urdf",)),
    "--masses": ("masses", ("molecule",)),
    "--unit": ("unit", ("molecule",)),
    "--format": ("format", ("molecule",)),
    "--frames": ("frames", ("molecule",)),
}


#: Where a molecule's atomic masses come from (Body.from_atoms), as ``polhode inertia`` says.
MASS_SOURCES = {
    "most_abundant": "most abundant isotopes (AME 2020 masses, CIAAW abundances; periodictable)",
    "average": "standard atomic weights (CIAAW 2021; periodictable)",
}


#: The option behind each argument the readers' errors can name.
INERTIA_ARGUMENTS = {
    "density": "--density",
    "mass": "--mass",
    "scale": "--scale",
    "masses": "--masses",
    "point": "--point",
}


_KIND_NAMES = {"mesh": "mesh files", "urdf": "URDF", "mjcf": "MJCF", "molecule": "molecule files"}


_LABEL = 21  # the width of the labels of `polhode inertia`'s text output


def _file_kind(args: argparse.Namespace) -> str:
    """``mesh``, ``urdf``, ``mjcf`` or ``molecule`` (``--format`` means a molecule)."""
    from polhode.io import MESH_FORMATS
    from polhode.io._links import format_of

    if args.format is not None:
        return "molecule"
    extension = os.path.splitext(args.file)[1].lower().lstrip(".")
    if extension in MESH_FORMATS:
        return "mesh"
    if extension in ROBOT_EXTENSIONS:
        return format_of(args.file)
    return "molecule"


def _check_inertia(args: argparse.Namespace, kind: str) -> None:
    """Options given for another kind of file, a mesh without a density or a mass, and the
    --frames file, before any work."""
    for option, (name, kinds) in INERTIA_OPTIONS.items():
        value = getattr(args, name)
        if value is not None and value is not False and kind not in kinds:
            applies = " and ".join(_KIND_NAMES[k] for k in kinds)
            raise UsageError(
                option, f"applies to {applies} only; {args.file!r} is read as {_KIND_NAMES[kind]}."
            )
    if kind == "mesh" and args.density is None and args.mass is None:
        raise UsageError("--density", "a mesh file needs --density or --mass.")
    if args.frames is not None:
        check_file("--frames", args.frames)
        if os.path.abspath(args.frames) == os.path.abspath(args.file):
            raise UsageError("--frames", f"{args.frames!r} is the file read.")


def _words(values: Any) -> str:
    return " ".join(f"{float(x) + 0.0:.9g}" for x in np.ravel(values))  # + 0.0: no -0


def _properties(body: ph.Body, args: argparse.Namespace) -> dict[str, Any]:
    """One body's mass properties as plain numbers (its JSON), with --point and --spatial."""
    p = body.principal()
    out: dict[str, Any] = {
        "mass": body.mass,
        "center_of_mass": body.center_of_mass.tolist(),
        "inertia": body.inertia.tolist(),
        "principal_moments": p.moments.tolist(),
        "principal_axes": p.axes.tolist(),
    }
    point = [0.0, 0.0, 0.0] if args.point is None else list(args.point)
    if args.point is not None:
        out["inertia_about_point"] = {"point": point, "inertia": body.inertia_about(point).tolist()}
    if args.spatial is not None:
        matrix = body.spatial_inertia(point, convention=args.spatial)
        out["spatial_inertia"] = {
            "convention": args.spatial,
            "point": point,
            "matrix": matrix.tolist(),
        }
    return out


def _print_matrix(label: str, matrix: Any) -> None:
    """A matrix in aligned columns, its label on the first row."""
    cells = [[f"{float(x) + 0.0:.9g}" for x in row] for row in np.asarray(matrix)]
    widths = [max(len(cell) for cell in column) for column in zip(*cells, strict=True)]
    for i, row in enumerate(cells):
        text = "  ".join(f"{cell:>{w}}" for cell, w in zip(row, widths, strict=True))
        print(f"{label if i == 0 else '':{_LABEL}s}{text}")


def _print_extras(props: dict[str, Any], axes: str) -> None:
    """--point's tensor and --spatial's matrix of one body, if asked for."""
    if "inertia_about_point" in props:
        about = props["inertia_about_point"]
        _print_matrix("inertia about point", about["inertia"])
        print(f"{'':{_LABEL}s}(about {_words(about['point'])}, in {axes})")
    if "spatial_inertia" in props:
        spatial = props["spatial_inertia"]
        _print_matrix("spatial inertia", spatial["matrix"])
        order = "linear" if spatial["convention"] == "pinocchio" else "angular"
        print(
            f"{'':{_LABEL}s}({spatial['convention']}: {order} block first; about "
            f"{_words(spatial['point'])}, in {axes})"
        )


def _print_body(props: dict[str, Any]) -> None:
    """One body's mass properties, as ``polhode inertia`` prints them."""
    print(f"{'mass':{_LABEL}s}{props['mass']:.9g}")
    print(f"{'centre of mass':{_LABEL}s}{_words(props['center_of_mass'])}")
    _print_matrix("inertia", props["inertia"])
    print(f"{'':{_LABEL}s}(about the centre of mass, in the file's axes; I_xy = -sum m x y)")
    print(
        f"{'principal moments':{_LABEL}s}{_words(props['principal_moments'])}   "
        "(ascending: I1, I2, I3)"
    )
    _print_matrix("principal axes", props["principal_axes"])
    print(f"{'':{_LABEL}s}(the columns: axes 1, 2, 3, in the file's axes)")
    _print_extras(props, "the file's axes")


def _read_molecule(args: argparse.Namespace, every_frame: bool) -> tuple[list[str], Any]:
    """(symbols, positions (T, N, 3)) of a molecule file's first frame, or of all its frames,
    read by ASE; a FileFormatError naming the file if it cannot be read."""
    ase_io = ase_readers()
    from polhode.io import MESH_FORMATS

    path = args.file
    try:
        read = ase_io.read(path, index=":" if every_frame else 0, format=args.format)
    except Exception as error:  # ASE's readers raise whatever their parsers do
        known = ", ".join("." + e for e in (*MESH_FORMATS, *ROBOT_EXTENSIONS))
        raise ph.FileFormatError(
            f"{path}: could not read a molecule with ASE ({type(error).__name__}: {error}). "
            f"Meshes and robot descriptions are known by their extension ({known}), any other "
            "file is read as a molecule (--format names ASE's format).",
            path=path,
        ) from error
    frames = read if isinstance(read, list) else [read]
    if not frames or len(frames[0]) == 0:
        raise ph.FileFormatError(f"{path}: holds no atoms.", path=path)
    symbols = list(frames[0].get_chemical_symbols())
    for t, atoms in enumerate(frames[1:], start=1):
        if list(atoms.get_chemical_symbols()) != symbols:
            raise ph.FileFormatError(
                f"{path}: frame {t} holds other atoms ({atoms.get_chemical_formula()}, "
                f"{len(atoms)}) than frame 0 ({frames[0].get_chemical_formula()}, "
                f"{len(symbols)}): --frames follows the same atoms through every frame.",
                path=path,
                field=f"frame {t}",
            )
    return symbols, np.stack([atoms.get_positions() for atoms in frames])


def _molecule(args: argparse.Namespace, result: dict[str, Any]) -> tuple[ph.Body, Any]:
    """The molecule (the file's first frame), its rotational constants put in ``result``, and
    with --frames the principal axes of every frame, followed in time (else None)."""
    from polhode._atoms import atom_masses
    from polhode.molecule import asymmetry, rotational_constants, rotor_type

    choice = args.masses or "most_abundant"
    symbols, positions = _read_molecule(args, every_frame=args.frames is not None)
    try:
        _, masses = atom_masses(symbols, choice)
    except ph.PolhodeError as error:  # an element the table does not know, or has no mass for
        raise ph.FileFormatError(
            f"{args.file}: {error.message}", path=args.file, field=error.argument
        ) from error
    body = ph.Body.from_atoms(symbols, positions[0], masses=masses)
    result.update(
        atoms=len(symbols),
        formula=formula(symbols),
        masses=choice,
        mass_source=MASS_SOURCES[choice],
        units={"length": "angstrom", "mass": "u"},
    )
    if body.principal().moments[2] > 0:
        unit = args.unit or "MHz"
        a, b, c = rotational_constants(body, unit=unit)
        kind = rotor_type(body)
        result["rotational_constants"] = {"unit": unit, "A": a, "B": b, "C": c}
        result["asymmetry"] = None if kind == "spherical" else asymmetry(body)
        result["rotor_type"] = kind
    else:  # one atom, or atoms at one point: no rotation, no spectrum
        result.update(rotational_constants=None, asymmetry=None, rotor_type=None)
    series = None
    if args.frames is not None:
        series = ph.principal(ph.point_masses_inertia(masses, positions), continuous=True)
        result["frames"] = {"count": int(positions.shape[0]), "csv": args.frames}
    return body, series


def _write_frames(path: str, series: ph.Principal) -> None:
    """Each frame's principal moments and axes (followed from frame to frame) as CSV: axes
    numbered 1, 2, 3 as their moments ascend in frame 0, each column's unit in its header
    (the axes' components are unit vectors' x, y, z in the file's axes)."""
    header = ["frame", *(f"moment_{k} (u angstrom^2)" for k in (1, 2, 3))]
    header += [f"axis_{k}_{c}" for k in (1, 2, 3) for c in "xyz"]
    axes = np.swapaxes(series.axes, 1, 2).reshape(-1, 9)  # axes[:, :, 0]'s x, y, z, then ...
    with open(path, "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(header)
        for t, (moments, row) in enumerate(zip(series.moments, axes, strict=True)):
            writer.writerow([t, *(number(x) for x in (*moments, *row))])


def _read_inertia(args: argparse.Namespace) -> tuple[dict[str, Any], Any]:
    """The result of ``polhode inertia`` (its JSON) and the molecule's series (or None)."""
    kind = _file_kind(args)
    _check_inertia(args, kind)
    result: dict[str, Any] = {"file": args.file, "kind": kind}
    series = None
    if kind == "mesh":
        from polhode.io import read_mesh

        parts = read_mesh(
            args.file,
            density=args.density,
            mass=args.mass,
            scale=1.0 if args.scale is None else args.scale,
            shell=bool(args.shell),
            fix_winding=bool(args.fix_winding),
        )
        bodies = list(parts.values())
        result.update(_properties(sum(bodies[1:], bodies[0]), args))
        if len(parts) > 1:
            result["parts"] = {name: _properties(b, args) for name, b in parts.items()}
    elif kind in ("urdf", "mjcf"):
        from polhode.io import read_mjcf, read_urdf

        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", ph.RobotFileWarning)
            if kind == "urdf":
                links = read_urdf(
                    args.file,
                    density=args.density,
                    mass=args.mass,
                    merge_fixed=bool(args.merge_fixed),
                    strict=bool(args.strict),
                )
            elif args.density is None and args.mass is None:  # as MuJoCo compiles it
                links = read_mjcf(
                    args.file, merge_fixed=bool(args.merge_fixed), strict=bool(args.strict)
                )
            else:  # the file's masses replaced: as written
                links = read_mjcf(
                    args.file, density=args.density, mass=args.mass, as_written=True
                )
        for warning in caught:
            if issubclass(warning.category, ph.RobotFileWarning):
                print(
                    f"polhode inertia: warning: {warning.message} (`polhode audit "
                    f"{args.file}` checks every link.)",
                    file=sys.stderr,
                )
            else:  # not ours: through the filters again
                warnings.warn_explicit(
                    warning.message, warning.category, warning.filename, warning.lineno
                )
        result["frames"] = dict(getattr(links, "frames", {}))
        result["left_out"] = dict(getattr(links, "left_out", {}))
        if args.merge_fixed:
            result["merged"] = dict(getattr(links, "merged", {}))
        result["links"] = {name: _properties(b, args) for name, b in links.items()}
    else:
        body, series = _molecule(args, result)
        result.update(_properties(body, args))
    return result, series


def run(args: argparse.Namespace) -> int:
    """The mass properties of a mesh file, of a robot description's links or of a molecule;
    2 for a file that cannot be read."""
    path = args.file
    try:
        if not os.path.exists(path):
            raise FileNotFoundError(f"{path}: no such file.")
        if os.path.isdir(path):
            raise IsADirectoryError(f"{path}: is a folder, expected a file.")
        result, series = _read_inertia(args)
    except UsageError:
        raise
    except ph.PolhodeError as error:
        option = INERTIA_ARGUMENTS.get(error.argument or "")
        if option is not None and not isinstance(error, ph.FileFormatError):
            raise UsageError(option, str(error)) from None
        message = str(error) if path in str(error) else f"{path}: {error}"
        robot = os.path.splitext(path)[1].lower().lstrip(".") in ROBOT_EXTENSIONS
        if isinstance(error, ph.FileFormatError) and error.link is not None and robot:
            message += f" (`polhode audit {path}` checks every link.)"
        print(f"polhode inertia: error: {message}", file=sys.stderr)
        return 2
    except (ImportError, OSError) as error:  # a missing extra; the file or a file it names
        message = str(error) if path in str(error) else f"{path}: {error}"
        print(f"polhode inertia: error: {message}", file=sys.stderr)
        return 2
    if series is not None:
        _write_frames(args.frames, series)
    if args.json:
        print(json.dumps(json_numbers(result)))
    else:
        _print_inertia(result)
    return 0


def _print_links(result: dict[str, Any]) -> None:
    """A robot description's links: a row each, then --point's and --spatial's matrices."""
    links = result["links"]
    what = "link" if result["kind"] == "urdf" else "body"
    noun = what if len(links) == 1 else "bodies" if what == "body" else "links"
    print(
        f"{result['file']}: {result['kind'].upper()}, {len(links)} {noun} with mass (the "
        "declared inertials, or from the geometry; each in its own frame: the centre of mass, "
        "and the inertia about it in the frame's axes)"
    )
    if not links:
        return
    names = ("mass", "com_x", "com_y", "com_z", "ixx", "iyy", "izz", "ixy", "ixz", "iyz")
    rows = [[what, *names]]
    for name, props in links.items():
        i = np.asarray(props["inertia"])
        row = [props["mass"], *props["center_of_mass"]]
        row += [i[0, 0], i[1, 1], i[2, 2], i[0, 1], i[0, 2], i[1, 2]]
        rows.append([name, *(f"{float(x) + 0.0:.9g}" for x in row)])
    widths = [max(len(cell) for cell in column) for column in zip(*rows, strict=True)]
    for row in rows:
        cells = [f"{row[0]:{widths[0]}s}"]
        cells += [f"{cell:>{w}s}" for cell, w in zip(row[1:], widths[1:], strict=True)]
        print("  ".join(cells))
    for name, props in links.items():
        if "inertia_about_point" in props or "spatial_inertia" in props:
            print(f"\n{name}")
            _print_extras(props, f"the {what}'s frame")


def _print_inertia(result: dict[str, Any]) -> None:
    """The text output of ``polhode inertia``."""
    kind = result["kind"]
    if kind in ("urdf", "mjcf"):
        _print_links(result)
        return
    if kind == "mesh":
        parts = result.get("parts", {})
        print(f"{result['file']}: mesh" + (f", {len(parts)} parts (their sum)" if parts else ""))
    else:
        print(
            f"{result['file']}: molecule {result['formula']}, {result['atoms']} atoms; "
            f"angstrom and u; masses: {result['mass_source']}"
        )
    _print_body(result)
    for name, props in result.get("parts", {}).items():
        print(
            f"{'part ' + name:{_LABEL}s}mass {props['mass']:.9g}, centre of mass "
            f"{_words(props['center_of_mass'])}"
        )
    if kind != "molecule":
        return
    constants = result["rotational_constants"]
    if constants is None:
        print(f"{'rotational constants':{_LABEL}s}none (all moments zero: no rotation)")
    else:
        a = "- (linear)" if constants["A"] is None else f"{constants['A']:.9g}"
        print(
            f"{'rotational constants':{_LABEL}s}A {a}  B {constants['B']:.9g}  "
            f"C {constants['C']:.9g}  {constants['unit']}"
        )
        kappa = result["asymmetry"]
        shown = "undefined (a spherical top)" if kappa is None else f"{kappa:.9g}"
        print(f"{'asymmetry (Ray)':{_LABEL}s}{shown}")
        print(f"{'rotor type':{_LABEL}s}{result['rotor_type']}")
    if "frames" in result:
        frames = result["frames"]
        print(
            f"\n{frames['count']} frames: principal moments and axes of each written to "
            f"{frames['csv']} (followed from frame to frame: no sign flips, no swaps)"
        )

"""Atoms: their masses (the ``periodictable`` package) and the molecules of other libraries.

The low level of :meth:`polhode.Body.from_atoms` and :meth:`polhode.Body.from_molecule`, and
of :mod:`polhode.io.molecule`: element symbols, isotopes and atomic numbers to masses in u
(AME 2020 isotope masses, CIAAW 2021 standard atomic weights and the CIAAW isotopic
compositions, as :mod:`polhode.molecule` says), and the symbols and positions (angstrom) of a
molecule file read by ASE, an ASE ``Atoms``, an MDAnalysis group or an RDKit ``Mol``. Nothing
here builds a body.
"""

from __future__ import annotations

import numbers
import os
import re
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from polhode._coerce import as_array, as_integer
from polhode._files import keeping_interrupts
from polhode.errors import ArgumentError, FileFormatError, ShapeError

#: The named choices of atomic masses (``Body.from_atoms(masses=...)``).
MASS_CHOICES = ("most_abundant", "average")

# Elements with a CIAAW standard atomic weight: Z = 1..83 but Tc and Pm, and Th, Pa, U. The
# others have no characteristic terrestrial isotopic composition (periodictable gives them the
# mass number of a long-lived isotope, which is not an atomic weight).
_STANDARD_WEIGHT = (set(range(1, 84)) - {43, 61}) | {90, 91, 92}
# periodictable 2.1 lists no abundances for uranium; CIAAW: 238U is 99.27 % of natural U.
_MOST_ABUNDANT_FALLBACK = {92: 238}
_LABEL = re.compile(r"^([0-9]+)?([A-Z][a-z]?)$")


# --- atoms to masses ----------------------------------------------------------------------------


def _element_of(label: str, index: int) -> tuple[Any, int | None]:
    """(periodictable element, mass number or None) of a label: ``"C"``, ``"13C"``, ``"D"``,
    ``"T"``."""
    import periodictable

    if label in ("D", "T"):
        return periodictable.H, 2 if label == "D" else 3
    match = _LABEL.match(label)
    if match is not None and match.group(2) in ("D", "T"):
        # Hydrogen-2 and -3 with their mass number written out: "2D" is D, "3D" is nothing
        # (periodictable's symbol("D") is an isotope, whose own isotopes crashed the check).
        implied = 2 if match.group(2) == "D" else 3
        if match.group(1) is not None and int(match.group(1)) != implied:
            raise ArgumentError(
                f"Expected `symbols[{index}]` to be a known isotope, got {label!r} "
                f"({match.group(2)} is hydrogen-{implied}).",
                argument="symbols",
            )
        return periodictable.H, implied
    element = None
    if match is not None:
        try:
            element = periodictable.elements.symbol(match.group(2))
        except ValueError:
            element = None
    if element is None or element.number == 0:
        raise ArgumentError(
            f"Expected `symbols[{index}]` to be an element symbol ('C', 'Cl'), an isotope "
            f"('13C', 'D', 'T') or an atomic number, got {label!r}.",
            argument="symbols",
        )
    number = None if match is None or match.group(1) is None else int(match.group(1))
    return element, number


def _parse(label: Any, index: int) -> tuple[Any, int | None]:
    """(periodictable element, mass number or None) of an atom's label or atomic number,
    checked: a known element, and a known isotope if a mass number is given."""
    import periodictable

    if isinstance(label, bool) or not isinstance(label, str | numbers.Integral):
        raise TypeError(
            f"Expected `symbols[{index}]` to be an element symbol or an atomic number, "
            f"got {type(label).__name__}."
        )
    if isinstance(label, numbers.Integral):
        z = int(label)
        if not 1 <= z <= 118:
            raise ArgumentError(
                f"Expected `symbols[{index}]` to be an atomic number from 1 to 118, got {z}.",
                argument="symbols",
            )
        return periodictable.elements[z], None
    element, number = _element_of(label, index)
    if number is not None and number not in element.isotopes:
        raise ArgumentError(
            f"Expected `symbols[{index}]` to be a known isotope, got {label!r} "
            f"({element.symbol} has mass numbers {element.isotopes[0]} to "
            f"{element.isotopes[-1]}).",
            argument="symbols",
        )
    return element, number


def _atom_mass(label: Any, choice: str, index: int) -> float:
    """The mass in u of one atom given by its label or atomic number."""
    element, number = _parse(label, index)
    if number is not None:
        return float(element[number].mass)
    if choice == "average":
        if element.number not in _STANDARD_WEIGHT:
            raise ArgumentError(
                f"{element.symbol} (`symbols[{index}]`) has no standard atomic weight: give "
                f"the isotope (e.g. '{element.isotopes[-1]}{element.symbol}') or the masses.",
                argument="symbols",
            )
        return float(element.mass)
    abundances = {n: element[n].abundance for n in element.isotopes}
    most = max(abundances, key=lambda n: abundances[n])
    if abundances[most] <= 0:
        if element.number not in _MOST_ABUNDANT_FALLBACK:
            raise ArgumentError(
                f"{element.symbol} (`symbols[{index}]`) has no natural isotopic abundance: "
                f"give the isotope (e.g. '{element.isotopes[-1]}{element.symbol}') or the "
                "masses.",
                argument="symbols",
            )
        most = _MOST_ABUNDANT_FALLBACK[element.number]
    return float(element[most].mass)


def _symbols_list(symbols: Any) -> list[Any]:
    if isinstance(symbols, str | bytes) or not isinstance(symbols, Sequence | np.ndarray):
        raise TypeError(
            "Expected `symbols` to be a sequence of element symbols or atomic numbers "
            f"(['O', 'H', 'H']), got {type(symbols).__name__}."
        )
    return [s.item() if isinstance(s, np.generic) else s for s in symbols]


def _key(label: Any, index: int) -> tuple[type, Any]:
    """A dictionary key for a label (its type too: True is not 1); a label of the wrong type
    raises here, with the message of :func:`_parse`."""
    if not isinstance(label, str | numbers.Integral):
        _parse(label, index)
    return type(label), label


def atom_masses(symbols: Any, masses: Any) -> tuple[list[Any], NDArray[np.float64]]:
    """The atoms' labels and masses (u) for :meth:`Body.from_atoms`."""
    labels = _symbols_list(symbols)
    if not labels:
        raise ShapeError(
            "Expected `symbols` to hold at least one atom, got none.", argument="symbols"
        )
    if isinstance(masses, str):
        if masses not in MASS_CHOICES:
            raise ArgumentError(
                f"Expected `masses` to be 'most_abundant', 'average' or an array of masses, "
                f"got {masses!r}.",
                argument="masses",
            )
        known: dict[Any, float] = {}  # each distinct label looked up once (proteins)
        keys = [_key(label, i) for i, label in enumerate(labels)]
        for i, (key, label) in enumerate(zip(keys, labels, strict=True)):
            if key not in known:
                known[key] = _atom_mass(label, masses, i)
        values = np.array([known[key] for key in keys])
        return labels, values
    checked: set[Any] = set()
    for i, label in enumerate(labels):
        key = _key(label, i)
        if key not in checked:
            _parse(label, i)  # the labels are checked even when the masses are given
            checked.add(key)
    values = as_array("masses", masses, (len(labels),))
    return labels, values


# --- molecules of other libraries ------------------------------------------------------------


def ase_readers() -> Any:
    """ASE's readers (``ase.io``), or an ImportError saying which extra installs ASE."""
    try:
        with keeping_interrupts("ase"):
            import ase.io
    except ImportError as error:
        raise ImportError(
            "Reading a molecule from a file needs ASE: pip install 'polhode[chem]'."
        ) from error
    return ase.io


def atoms_of(molecule: Any, format: Any, conformer: Any) -> tuple[list[Any], Any]:
    """(labels, positions in angstrom) of a path, an ASE Atoms, an MDAnalysis AtomGroup or
    Universe, or an RDKit Mol, duck-typed; ``conformer`` picks a file's structure or a Mol's
    conformer (-1: the first) and is refused for the others, which hold one."""
    conformer = as_integer("conformer", conformer)
    if format is not None and not isinstance(format, str):
        raise TypeError(
            f"Expected `format` to be ASE's name of a file format, got {type(format).__name__}."
        )
    if isinstance(molecule, str | os.PathLike):
        return _read_file(molecule, format, conformer)
    if format is not None:
        raise ArgumentError(
            f"Expected `format` only with a file, got {format!r} with a molecule of type "
            f"{type(molecule).__name__}.",
            argument="format",
        )
    if hasattr(molecule, "GetConformer") and hasattr(molecule, "GetAtoms"):  # RDKit Mol
        if molecule.GetNumConformers() == 0:
            raise ArgumentError(
                "Expected `molecule` (an RDKit Mol) to have 3D coordinates, got no conformer "
                "(embed one, e.g. AllChem.EmbedMolecule(Chem.AddHs(mol))).",
                argument="molecule",
            )
        try:
            positions = molecule.GetConformer(conformer).GetPositions()
        except Exception as error:  # RDKit: ValueError, or Boost's ArgumentError beyond an int
            ids = [c.GetId() for c in molecule.GetConformers()]
            raise ArgumentError(
                f"Expected `conformer` to be a conformer id of `molecule` ({_ids(ids)}), "
                f"got {conformer}.",
                argument="conformer",
            ) from error
        labels = []
        for atom in molecule.GetAtoms():
            isotope = atom.GetIsotope()
            labels.append(f"{isotope}{atom.GetSymbol()}" if isotope else atom.GetSymbol())
        return labels, positions
    group = getattr(molecule, "atoms", None)
    if group is not None and hasattr(group, "positions"):  # MDAnalysis AtomGroup or Universe
        _one_structure(conformer, "an MDAnalysis group (its current frame; move to another "
                       "with universe.trajectory[k])")
        try:
            elements = group.elements
        except Exception as error:
            raise ArgumentError(
                "Expected `molecule` (an MDAnalysis group) to have elements, got none (guess "
                "them: universe.guess_TopologyAttrs(to_guess=['elements'])).",
                argument="molecule",
            ) from error
        return [str(e).strip().capitalize() for e in elements], group.positions
    if hasattr(molecule, "get_chemical_symbols") and hasattr(molecule, "get_positions"):  # ASE
        _one_structure(conformer, "an ASE Atoms")
        return list(molecule.get_chemical_symbols()), molecule.get_positions()
    raise TypeError(
        "Expected `molecule` to be a path, an ASE Atoms, an MDAnalysis AtomGroup or an RDKit "
        f"Mol, got {type(molecule).__name__}."
    )


def _ids(ids: list[int]) -> str:
    if not ids:
        return "none"
    if ids == list(range(ids[0], ids[-1] + 1)):
        return f"{ids[0]} to {ids[-1]}" if len(ids) > 1 else f"{ids[0]}"
    return ", ".join(map(str, ids[:10])) + (", ..." if len(ids) > 10 else "")


def _one_structure(conformer: int, what: str) -> None:
    """A molecule of one structure takes no ``conformer`` (rather than ignoring it)."""
    if conformer != -1:
        raise ArgumentError(
            f"Expected no `conformer` with {what}, which holds one structure, got {conformer} "
            "(conformer selects a structure of a file or a conformer of an RDKit Mol).",
            argument="conformer",
        )


def _read_file(molecule: Any, format: str | None, conformer: int) -> tuple[list[Any], Any]:
    """A file read by ASE: its structure ``conformer`` (0 the first, -1 the first too)."""
    ase_io = ase_readers()
    path = os.fspath(molecule)
    if not os.path.exists(path):
        raise FileNotFoundError(f"No such file: {path!r} (`molecule`).")
    if format is not None and format not in ase_io.formats.ioformats:
        raise ArgumentError(
            f"Expected `format` to be the name of a format ASE reads (ase.io.formats.ioformats: "
            f"'xyz', 'proteindatabank', 'sdf', ...), got {format!r}.",
            argument="format",
        )
    if conformer < -1:
        raise ArgumentError(
            f"Expected `conformer` to be the index of a structure of the file (0 the first; "
            f"-1, the default, the first too), got {conformer}.",
            argument="conformer",
        )
    index = max(conformer, 0)

    def read(which: Any) -> Any:
        try:
            with keeping_interrupts("ase"):
                return ase_io.read(path, index=which, format=format)
        except Exception as error:  # ASE's readers raise whatever their parsers do
            raise FileFormatError(
                f"Could not read a molecule from {path!r} (`molecule`): {error}",
                argument="molecule",
                path=path,
            ) from error

    images = read(slice(index, index + 1))  # a list: empty past the last structure
    if not images:
        count = len(read(slice(None)))
        if count == 0:
            raise FileFormatError(
                f"Could not read a molecule from {path!r} (`molecule`): it holds no structure.",
                argument="molecule",
                path=path,
            )
        raise ArgumentError(
            f"Expected `conformer` to be the index of a structure of {path!r}, which holds "
            f"{count} ({'0 to ' + str(count - 1) if count > 1 else '0'}), got {conformer}.",
            argument="conformer",
        )
    atoms = images[0]
    return list(atoms.get_chemical_symbols()), atoms.get_positions()


def formula(symbols: list[str]) -> str:
    """Hill order: C, H, then the others alphabetically (without carbon, all alphabetically)."""
    counts: dict[str, int] = {}
    for s in symbols:
        counts[s] = counts.get(s, 0) + 1
    first = [s for s in ("C", "H") if s in counts] if "C" in counts else []
    order = first + sorted(s for s in counts if s not in first)
    return "".join(s + (str(counts[s]) if counts[s] > 1 else "") for s in order)

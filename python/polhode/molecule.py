"""Molecules: rotational constants, Ray's asymmetry and the rotor type of a body made of atoms.

Build the body with :meth:`polhode.Body.from_atoms` (element symbols and positions) or
:meth:`polhode.Body.from_molecule` (a file read by ASE, an ASE ``Atoms``, an MDAnalysis
``AtomGroup`` or an RDKit ``Mol``). By default positions are in angstrom and masses in unified
atomic mass units (u, daltons), as those libraries give them; ``length_unit`` and ``mass_unit``
say otherwise.

Atomic masses come from the ``periodictable`` package: isotope masses from the AME 2020 atomic
mass evaluation (M. Wang et al., Chinese Phys. C 45, 030003 (2021)), standard atomic weights
from CIAAW 2021 (abridged; T. Prohaska et al., Pure Appl. Chem. 94, 573 (2022)) and natural
abundances from the CIAAW isotopic compositions (which isotope is the most abundant).

The rotational constants are ``B = h / (8 pi^2 I)`` (a frequency) or ``h / (8 pi^2 c I)`` (a
wavenumber), with h, c and the atomic mass constant from CODATA through ``scipy.constants``;
``A >= B >= C`` belong to the principal moments ``I_a <= I_b <= I_c`` about the centre of mass.
They are the constants of the rigid geometry given (an equilibrium ``r_e`` structure gives
``A_e``, ``B_e``, ``C_e``); measured ground-state constants ``A_0``, ``B_0``, ``C_0`` differ
from them by the vibrational averaging, typically 0.1 to 3 per cent.

Examples
--------
>>> import polhode as ph
>>> from polhode.molecule import rotational_constants, rotor_type, asymmetry
>>> water = ph.Body.from_atoms(
...     ["O", "H", "H"], [[0, 0, 0.1173], [0, 0.7572, -0.4692], [0, -0.7572, -0.4692]]
... )
>>> rotor_type(water)
'asymmetric'
>>> a, b, c = rotational_constants(water, unit="cm-1")
>>> print(f"{a:.2f} {b:.2f} {c:.2f}")
27.38 14.59 9.52
>>> print(f"{asymmetry(water):.3f}")
-0.432
"""

from __future__ import annotations

import math
import numbers
import os
import re
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from polhode._coerce import as_array, as_scalar
from polhode.errors import ArgumentError, FileFormatError, ShapeError

if TYPE_CHECKING:
    from polhode.bodies import Body

__all__ = ["RotationalConstants", "asymmetry", "rotational_constants", "rotor_type"]

#: The default relative tolerance of :func:`rotor_type` and friends.
DEFAULT_RTOL = 1e-3

_MASS_CHOICES = ("most_abundant", "average")
_UNITS = ("MHz", "GHz", "cm-1")
_LENGTH_UNITS = ("angstrom", "nm", "pm", "bohr", "m")
_MASS_UNITS = ("u", "kg")

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


def _masses(symbols: Any, masses: Any) -> tuple[list[Any], NDArray[np.float64]]:
    """The atoms' labels and masses (u) for :meth:`Body.from_atoms`."""
    labels = _symbols_list(symbols)
    if not labels:
        raise ShapeError(
            "Expected `symbols` to hold at least one atom, got none.", argument="symbols"
        )
    if isinstance(masses, str):
        if masses not in _MASS_CHOICES:
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


def _atoms_of(molecule: Any, format: str | None, conformer: int) -> tuple[list[Any], Any]:
    """(labels, positions in angstrom) of a path, an ASE Atoms, an MDAnalysis AtomGroup or
    Universe, or an RDKit Mol, duck-typed."""
    if isinstance(molecule, str | os.PathLike):
        try:
            import ase.io
        except ImportError as error:  # pragma: no cover - ase is in the test extra
            raise ImportError(
                "Reading a molecule from a file needs ASE: pip install 'polhode[chem]'."
            ) from error
        path = os.fspath(molecule)
        if not os.path.exists(path):
            raise FileNotFoundError(f"No such file: {path!r} (`molecule`).")
        try:
            atoms = ase.io.read(path, index=0, format=format)
        except Exception as error:  # ASE's readers raise whatever their parsers do
            raise FileFormatError(
                f"Could not read a molecule from {path!r} (`molecule`): {error}",
                argument="molecule",
                path=path,
            ) from error
        return list(atoms.get_chemical_symbols()), atoms.get_positions()
    if hasattr(molecule, "GetConformer") and hasattr(molecule, "GetAtoms"):  # RDKit Mol
        if molecule.GetNumConformers() == 0:
            raise ArgumentError(
                "Expected `molecule` (an RDKit Mol) to have 3D coordinates, got no conformer "
                "(embed one, e.g. AllChem.EmbedMolecule(Chem.AddHs(mol))).",
                argument="molecule",
            )
        try:
            positions = molecule.GetConformer(conformer).GetPositions()
        except ValueError as error:
            raise ArgumentError(
                f"Expected `conformer` to be a conformer id of `molecule`, got {conformer}.",
                argument="conformer",
            ) from error
        labels = []
        for atom in molecule.GetAtoms():
            isotope = atom.GetIsotope()
            labels.append(f"{isotope}{atom.GetSymbol()}" if isotope else atom.GetSymbol())
        return labels, positions
    group = getattr(molecule, "atoms", None)
    if group is not None and hasattr(group, "positions"):  # MDAnalysis AtomGroup or Universe
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
        return list(molecule.get_chemical_symbols()), molecule.get_positions()
    raise TypeError(
        "Expected `molecule` to be a path, an ASE Atoms, an MDAnalysis AtomGroup or an RDKit "
        f"Mol, got {type(molecule).__name__}."
    )


# --- rotational constants ---------------------------------------------------------------------


class RotationalConstants(NamedTuple):
    """Rotational constants ``A >= B >= C`` in the unit asked for; unpacks as ``a, b, c``.

    ``A`` is None for a linear molecule (its moment about the axis is zero: rotation about the
    axis is no rotational degree of freedom), whose ``B`` and ``C`` are then equal.

    Examples
    --------
    >>> import polhode as ph
    >>> from polhode.molecule import rotational_constants
    >>> co = ph.Body.from_atoms(["C", "O"], [[0, 0, 0], [0, 0, 1.128323]])
    >>> a, b, c = rotational_constants(co, unit="GHz")
    >>> a is None, round(b, 3), b == c
    (True, 57.898, True)
    """

    A: float | None
    B: float
    C: float


def _choice(name: str, value: Any, choices: tuple[str, ...]) -> str:
    if not isinstance(value, str):
        raise TypeError(f"Expected `{name}` to be a string, got {type(value).__name__}.")
    if value not in choices:
        options = ", ".join(repr(c) for c in choices)
        raise ArgumentError(
            f"Expected `{name}` to be one of {options}, got {value!r}.", argument=name
        )
    return value


def _moments(body: Body, rtol: Any) -> tuple[NDArray[np.float64], float]:
    """The principal moments (ascending) of a body with some rotation, and the tolerance."""
    from polhode.bodies import Body

    if not isinstance(body, Body):
        raise TypeError(f"Expected `body` to be a polhode Body, got {type(body).__name__}.")
    tolerance = as_scalar("rtol", rtol)
    if not (math.isfinite(tolerance) and 0.0 <= tolerance < 1.0):
        raise ArgumentError(
            f"Expected `rtol` to be a number in [0, 1), got {tolerance}.", argument="rtol"
        )
    moments = body.principal().moments
    if not moments[2] > 0.0:
        raise ArgumentError(
            "Expected `body` to have a non-zero moment of inertia, got all three zero (a "
            "single atom, or atoms at one point): it has no rotational spectrum.",
            argument="body",
        )
    return moments, tolerance


def rotor_type(body: Body, *, rtol: float = DEFAULT_RTOL) -> str:
    """The kind of rotor: ``"linear"``, ``"spherical"``, ``"prolate"``, ``"oblate"`` or
    ``"asymmetric"``.

    With the principal moments ``I_a <= I_b <= I_c``: linear when ``I_a <= rtol**2 I_c`` (atoms
    off the axis by less than about ``rtol`` times half the molecule's length: the same
    geometric tolerance as the others, which are linear in the positions' errors while ``I_a``
    is quadratic); spherical when ``I_c - I_a <= rtol I_c``; prolate (symmetric top, ``A > B =
    C``) when ``I_c - I_b <= rtol I_c``; oblate (``A = B > C``) when ``I_b - I_a <= rtol I_c``;
    asymmetric otherwise.

    Parameters
    ----------
    body : Body
        The molecule (any body with a non-zero moment).
    rtol : float, optional
        Moments within ``rtol`` times the largest count as equal (default 1e-3, right for
        geometries given to 3 or 4 decimals in angstrom; a smaller value for more precise
        geometries).

    Returns
    -------
    str

    Raises
    ------
    ArgumentError
        A body whose moments are all zero (a single atom); ``rtol`` outside [0, 1).

    Examples
    --------
    >>> import polhode as ph
    >>> from polhode.molecule import rotor_type
    >>> rotor_type(ph.Body.from_atoms(["O", "C", "O"], [[0, 0, -1.16], [0, 0, 0], [0, 0, 1.16]]))
    'linear'
    >>> h, d = 1.09, 1.09 / 3**0.5
    >>> methane = [[0, 0, 0], [d, d, d], [d, -d, -d], [-d, d, -d], [-d, -d, d]]
    >>> rotor_type(ph.Body.from_atoms(["C", "H", "H", "H", "H"], methane))
    'spherical'
    """
    (i_a, i_b, i_c), tolerance = _moments(body, rtol)
    if i_a <= tolerance**2 * i_c:
        return "linear"
    if i_c - i_a <= tolerance * i_c:
        return "spherical"
    if i_c - i_b <= tolerance * i_c:
        return "prolate"
    if i_b - i_a <= tolerance * i_c:
        return "oblate"
    return "asymmetric"


def rotational_constants(
    body: Body,
    unit: str = "MHz",
    *,
    length_unit: str = "angstrom",
    mass_unit: str = "u",
    rtol: float = DEFAULT_RTOL,
) -> RotationalConstants:
    """Rotational constants ``A >= B >= C`` of a rigid molecule.

    ``B = h / (8 pi^2 I_b)`` in MHz or GHz, or ``h / (8 pi^2 c I_b)`` in cm-1, and likewise A
    from the smallest principal moment and C from the largest, with the CODATA values of h, c
    and the atomic mass constant (``scipy.constants``). A linear molecule (:func:`rotor_type`
    with the same ``rtol``) has ``A`` None, never an infinity.

    These are the constants of the geometry given: an equilibrium structure gives the
    equilibrium constants; measured ground-state constants differ by the vibrational averaging
    (for water about 2 per cent, for heavier molecules typically 0.1 to 1 per cent).

    Parameters
    ----------
    body : Body
        The molecule, e.g. from :meth:`Body.from_atoms` or :meth:`Body.from_molecule`.
    unit : {"MHz", "GHz", "cm-1"}, optional
        The unit of the constants (default MHz).
    length_unit : {"angstrom", "nm", "pm", "bohr", "m"}, optional
        The unit of the body's lengths (default angstrom, as ASE, MDAnalysis and RDKit give
        them).
    mass_unit : {"u", "kg"}, optional
        The unit of the body's masses (default u, daltons, as :meth:`Body.from_atoms` gives
        them).
    rtol : float, optional
        The tolerance of :func:`rotor_type` that decides a linear molecule (default 1e-3).

    Returns
    -------
    RotationalConstants
        ``(A, B, C)``, A None for a linear molecule.

    Raises
    ------
    ArgumentError
        An unknown unit; a body whose moments are all zero (a single atom).

    Examples
    --------
    Carbon monoxide at its equilibrium bond length (1.128323 angstrom): ``B_e`` =
    1.93128 cm-1 (Huber and Herzberg).

    >>> import polhode as ph
    >>> from polhode.molecule import rotational_constants
    >>> co = ph.Body.from_atoms(["C", "O"], [[0, 0, 0], [0, 0, 1.128323]])
    >>> a, b, c = rotational_constants(co, unit="cm-1")
    >>> a is None, round(b, 5), b == c
    (True, 1.93128, True)
    >>> round(rotational_constants(co).B)  # MHz
    57898
    """
    import scipy.constants as sc

    unit = _choice("unit", unit, _UNITS)
    length = _choice("length_unit", length_unit, _LENGTH_UNITS)
    mass = _choice("mass_unit", mass_unit, _MASS_UNITS)
    linear = rotor_type(body, rtol=rtol) == "linear"
    moments, _ = _moments(body, rtol)
    metres = {
        "angstrom": sc.angstrom,
        "nm": sc.nano,
        "pm": sc.pico,
        "bohr": sc.physical_constants["Bohr radius"][0],
        "m": 1.0,
    }[length]
    kilograms = {"u": sc.physical_constants["atomic mass constant"][0], "kg": 1.0}[mass]
    per_moment = sc.h / (8.0 * math.pi**2 * kilograms * metres**2)  # Hz times the moment
    scale = {"MHz": 1e-6, "GHz": 1e-9, "cm-1": 1.0 / (100.0 * sc.c)}[unit]
    a, b, c = (per_moment * scale / float(m) if m > 0 else math.inf for m in moments)
    if not (math.isfinite(b) and math.isfinite(c)) or not (linear or math.isfinite(a)):
        raise ArgumentError(
            "The rotational constants overflow double precision: the body's moments are "
            f"{moments.tolist()} {mass_unit} {length_unit}^2.",
            argument="body",
        )
    return RotationalConstants(None if linear else a, b, c)


def asymmetry(body: Body, *, rtol: float = DEFAULT_RTOL) -> float:
    """Ray's asymmetry parameter ``kappa = (2 B - A - C) / (A - C)``: -1 for a prolate
    symmetric top, +1 for an oblate one, between them for an asymmetric top.

    Computed from the moments without forming A (``kappa = (2 I_a I_c - I_b (I_a + I_c)) /
    (I_b (I_c - I_a))``), so a near-linear molecule gives a value near -1, and a linear one
    (:func:`rotor_type`) exactly -1, the prolate limit.

    Parameters
    ----------
    body : Body
        The molecule.
    rtol : float, optional
        The tolerance of :func:`rotor_type` (default 1e-3): a spherical top, whose kappa is
        0/0, raises.

    Returns
    -------
    float

    Raises
    ------
    ArgumentError
        A spherical top (kappa undefined), a body whose moments are all zero.

    Examples
    --------
    >>> import polhode as ph
    >>> from polhode.molecule import asymmetry
    >>> formaldehyde = ph.Body.from_atoms(
    ...     ["O", "C", "H", "H"],
    ...     [[0, 0, 1.205], [0, 0, 0], [0, 0.9429, -0.5876], [0, -0.9429, -0.5876]],
    ... )
    >>> print(f"{asymmetry(formaldehyde):.3f}")  # a near-prolate top
    -0.962
    """
    kind = rotor_type(body, rtol=rtol)
    if kind == "linear":
        return -1.0
    if kind == "spherical":
        raise ArgumentError(
            "Expected `body` not to be a spherical top (its asymmetry is 0/0): its moments are "
            f"equal within rtol = {rtol}.",
            argument="body",
        )
    (i_a, i_b, i_c), _ = _moments(body, rtol)
    return float((2.0 * i_a * i_c - i_b * (i_a + i_c)) / (i_b * (i_c - i_a)))

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
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from polhode._coerce import as_scalar
from polhode.bodies import Body
from polhode.errors import ArgumentError

__all__ = ["RotationalConstants", "asymmetry", "rotational_constants", "rotor_type"]

#: The default relative tolerance of :func:`rotor_type` and friends.
DEFAULT_RTOL = 1e-3

#: The units of :func:`rotational_constants`.
UNITS = ("MHz", "GHz", "cm-1")
_LENGTH_UNITS = ("angstrom", "nm", "pm", "bohr", "m")
_MASS_UNITS = ("u", "kg")


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

    unit = _choice("unit", unit, UNITS)
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

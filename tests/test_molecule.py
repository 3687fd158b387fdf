"""Molecules: Body.from_atoms / from_molecule (masses from periodictable, files and objects of
ASE, MDAnalysis and RDKit) and polhode.molecule (rotational constants, Ray's asymmetry, rotor
type), against atomic masses typed from AME 2020, a numpy formula written here, and measured
rotational constants from the literature (sources quoted at each molecule)."""

from __future__ import annotations

import doctest
import math

import ase.build
import ase.io
import MDAnalysis as mda
import numpy as np
import pytest
import scipy.constants as sc
from rdkit import Chem
from rdkit.Chem import AllChem

import polhode as ph
import polhode.molecule as molecule
from polhode.molecule import asymmetry, rotational_constants, rotor_type
from reference import EPS

# AME 2020 atomic masses in u (M. Wang et al., Chinese Phys. C 45, 030003 (2021), Table I),
# typed from the publication. periodictable keeps the rounded table (massround.mas20): 10
# significant digits, so they agree to 1e-9 (a thousand times below what a rotational
# constant measured to 1e-6 could see).
AME2020 = {
    "1H": 1.007825031898,
    "2H": 2.014101777844,
    "12C": 12.0,
    "13C": 13.003354835336,
    "14N": 14.003074004251,
    "16O": 15.994914619257,
    "35Cl": 34.968852694,
    "37Cl": 36.965902602,
    "238U": 238.050786936,
}


def water(r=0.9578, angle=104.4776):
    """H2O with its O-H length and H-O-H angle (degrees), in the yz plane."""
    a = math.radians(angle) / 2
    return [
        [0, 0, 0],
        [0, r * math.sin(a), -r * math.cos(a)],
        [0, -r * math.sin(a), -r * math.cos(a)],
    ]


def pyramid(r, angle):
    """N and three H of an NH3-like pyramid: bond length r, H-N-H angle (degrees)."""
    hh = 2 * r * math.sin(math.radians(angle) / 2)
    rho = hh / math.sqrt(3)
    h = math.sqrt(r * r - rho * rho)
    turns = np.radians([90.0, 210.0, 330.0])
    return [[0, 0, 0]] + [[rho * math.cos(t), rho * math.sin(t), -h] for t in turns]


def formaldehyde(r_co=1.205, r_ch=1.111, hch=116.133):
    a = math.radians(hch) / 2
    s, c = r_ch * math.sin(a), r_ch * math.cos(a)
    return [[0, 0, r_co], [0, 0, 0], [0, s, -c], [0, -s, -c]]


def numpy_constants(masses, positions, unit):
    """Rotational constants A >= B >= C from the textbook: the inertia tensor about the centre
    of mass, its eigenvalues, B = h / (8 pi^2 I) (u and angstrom to SI), in numpy."""
    m = np.asarray(masses, dtype=float)
    r = np.asarray(positions, dtype=float)
    r = r - (m @ r) / m.sum()
    inertia = np.einsum("k,kij->ij", m, np.einsum("ki,ki->k", r, r)[:, None, None] * np.eye(3))
    inertia -= np.einsum("k,ki,kj->ij", m, r, r)
    moments = np.linalg.eigvalsh(inertia) * sc.atomic_mass * sc.angstrom**2
    hertz = sc.h / (8 * np.pi**2 * moments)
    return hertz / {"MHz": 1e6, "GHz": 1e9, "cm-1": 100 * sc.c}[unit]


# --- masses -------------------------------------------------------------------------------


def test_most_abundant_masses_are_the_ame2020_isotope_masses():
    symbols = ["H", "D", "C", "13C", "N", "O", "Cl", "37Cl", "U", "2H", 6]
    expected = [
        AME2020[k]
        for k in ("1H", "2H", "12C", "13C", "14N", "16O", "35Cl", "37Cl", "238U", "2H", "12C")
    ]
    body = ph.Body.from_atoms(symbols, np.arange(33.0).reshape(11, 3))
    got = [ph.Body.from_atoms([s], [[0, 0, 0]]).mass for s in symbols]
    np.testing.assert_allclose(got, expected, rtol=1e-9)
    assert body.mass == pytest.approx(sum(expected), rel=1e-9)


def test_average_masses_are_the_standard_atomic_weights():
    # CIAAW 2021 abridged standard atomic weights: H 1.008, C 12.011, O 15.999, Cl 35.45.
    body = ph.Body.from_atoms(["C", "H", "H", "H", "Cl"], np.eye(5, 3), masses="average")
    assert body.mass == pytest.approx(12.011 + 3 * 1.008 + 35.45, rel=1e-12)
    # An isotope label keeps its isotope's mass in either mode.
    heavy = ph.Body.from_atoms(["D", "O"], [[0, 0, 0], [0, 0, 1]], masses="average")
    assert heavy.mass == pytest.approx(AME2020["2H"] + 15.999, rel=1e-12)
    # Given masses are used as they are.
    given = ph.Body.from_atoms(["O", "H", "H"], water(), masses=[16.0, 1.0, 1.0])
    assert given.mass == 18.0


def test_from_atoms_is_point_masses_at_the_atoms():
    rng = np.random.default_rng(0)
    positions = rng.normal(size=(6, 3))
    symbols = ["C", "O", "H", "H", "N", "S"]
    body = ph.Body.from_atoms(symbols, positions)
    masses = [ph.Body.from_atoms([s], [[0, 0, 0]]).mass for s in symbols]
    m = np.array(masses)
    com = m @ positions / m.sum()
    d = positions - com
    inertia = np.einsum("k,ij->ij", m * np.einsum("ki,ki->k", d, d), np.eye(3)) - np.einsum(
        "k,ki,kj->ij", m, d, d
    )
    np.testing.assert_allclose(body.center_of_mass, com, rtol=1e-13, atol=1e-15)
    assert np.abs(body.inertia - inertia).max() <= 64 * EPS * np.trace(inertia)


@pytest.mark.parametrize(
    ("symbols", "error", "pattern"),
    [
        (["O", "Xx", "H"], ph.ArgumentError, r"symbols\[1\].*'Xx'"),
        (["O", "CL"], ph.ArgumentError, r"symbols\[1\].*'CL'"),
        (["99C"], ph.ArgumentError, r"symbols\[0\].*known isotope.*99C"),
        (["H", 0], ph.ArgumentError, r"symbols\[1\].*from 1 to 118"),
        ([119], ph.ArgumentError, r"symbols\[0\].*from 1 to 118"),
        (["Tc"], ph.ArgumentError, r"Tc.*no natural isotopic abundance"),
        (["Og"], ph.ArgumentError, r"Og.*no natural isotopic abundance"),
        (["n"], ph.ArgumentError, r"symbols\[0\]"),
        # D and T are hydrogen-2 and -3: another mass number crashed with a bare TypeError.
        (["3D"], ph.ArgumentError, r"symbols\[0\].*'3D' \(D is hydrogen-2\)"),
        (["2T"], ph.ArgumentError, r"symbols\[0\].*'2T' \(T is hydrogen-3\)"),
        ([], ph.ShapeError, r"at least one atom"),
    ],
)
def test_bad_symbols_are_named(symbols, error, pattern):
    positions = np.zeros((len(symbols), 3))
    with pytest.raises(error, match=pattern) as raised:
        ph.Body.from_atoms(symbols, positions)
    assert raised.value.argument == "symbols"


def test_deuterium_and_tritium_with_their_mass_numbers():
    """'2D' and '3T' are D and T written out (they raised a bare TypeError)."""
    positions = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 0.74]])
    for written, short in (("2D", "D"), ("3T", "T")):
        a = ph.Body.from_atoms([written, "H"], positions)
        b = ph.Body.from_atoms([short, "H"], positions)
        assert a.mass == b.mass and np.array_equal(a.inertia, b.inertia)


def test_bad_atoms_input_is_named():
    with pytest.raises(TypeError, match="symbols"):
        ph.Body.from_atoms("H2O", water())
    with pytest.raises(TypeError, match=r"symbols\[1\]"):
        ph.Body.from_atoms(["O", True, "H"], water())
    with pytest.raises(TypeError, match=r"symbols\[2\]"):
        ph.Body.from_atoms(["O", "H", 1.0], water())
    with pytest.raises(TypeError, match=r"symbols\[0\]"):
        ph.Body.from_atoms([["O"], "H", "H"], water())
    with pytest.raises(TypeError, match=r"symbols\[1\]"):
        ph.Body.from_atoms(["O", ["H"], "H"], water(), masses=[16.0, 1.0, 1.0])
    with pytest.raises(ph.ArgumentError, match="no standard atomic weight") as error:
        ph.Body.from_atoms(["Tc", "O"], [[0, 0, 0], [0, 0, 1]], masses="average")
    assert error.value.argument == "symbols"
    # An isotope of an element without natural abundance is fine.
    assert ph.Body.from_atoms(["99Tc"], [[0, 0, 0]]).mass == pytest.approx(98.906, rel=1e-4)
    with pytest.raises(ph.ArgumentError, match="masses") as error:
        ph.Body.from_atoms(["O", "H", "H"], water(), masses="abundant")
    assert error.value.argument == "masses"
    with pytest.raises(ph.ShapeError) as error:
        ph.Body.from_atoms(["O", "H", "H"], water(), masses=[16.0, 1.0])
    assert error.value.argument == "masses"
    with pytest.raises(ph.NonPositiveError) as error:
        ph.Body.from_atoms(["O", "H", "H"], water(), masses=[16.0, 1.0, 0.0])
    assert error.value.argument == "masses"
    with pytest.raises(ph.ShapeError, match=r"\(3, 3\)") as error:
        ph.Body.from_atoms(["O", "H", "H"], water()[:2])
    assert error.value.argument == "positions"
    with pytest.raises(ph.ShapeError) as error:
        ph.Body.from_atoms(["O", "H", "H"], np.zeros((3, 2)))
    assert error.value.argument == "positions"
    bad = np.array(water())
    bad[2, 1] = np.nan
    with pytest.raises(ph.NonFiniteError, match=r"positions\[2, 1\]") as error:
        ph.Body.from_atoms(["O", "H", "H"], bad)
    assert error.value.argument == "positions"
    # A numpy array of symbols works like a list.
    assert ph.Body.from_atoms(np.array(["O", "H", "H"]), water()).mass == pytest.approx(
        AME2020["16O"] + 2 * AME2020["1H"]
    )


# --- rotational constants against a numpy formula ---------------------------------------------


@pytest.mark.parametrize("unit", ["MHz", "GHz", "cm-1"])
def test_rotational_constants_match_the_numpy_formula(unit):
    rng = np.random.default_rng(1)
    symbols = ["C", "C", "O", "H", "H", "H", "H", "N", "Cl"]
    positions = rng.normal(size=(len(symbols), 3)) * 1.5
    body = ph.Body.from_atoms(symbols, positions)
    masses = [ph.Body.from_atoms([s], [[0, 0, 0]]).mass for s in symbols]
    expected = numpy_constants(masses, positions, unit)  # ascending moments: A first
    got = rotational_constants(body, unit)
    assert got.A >= got.B >= got.C
    np.testing.assert_allclose(got, expected, rtol=1e-12)


def test_units_of_the_body_are_converted():
    positions = np.array(water())
    body = ph.Body.from_atoms(["O", "H", "H"], positions)
    expected = rotational_constants(body, "GHz")
    masses_kg = np.array([AME2020["16O"], AME2020["1H"], AME2020["1H"]]) * sc.atomic_mass
    for length_unit, scale in (
        ("nm", 0.1),
        ("pm", 100.0),
        ("m", 1e-10),
        ("bohr", sc.angstrom / sc.physical_constants["Bohr radius"][0]),
    ):
        si = ph.Body.point_masses(masses_kg, positions * scale)
        got = rotational_constants(si, "GHz", length_unit=length_unit, mass_unit="kg")
        np.testing.assert_allclose(got, expected, rtol=2e-9)  # the AME masses typed above
    # Units of the result: GHz = MHz / 1000, cm-1 = Hz / (100 c).
    mhz = rotational_constants(body)
    np.testing.assert_allclose(np.array(expected) * 1e3, mhz, rtol=1e-14)
    np.testing.assert_allclose(
        np.array(mhz) * 1e6 / (100 * sc.c), rotational_constants(body, "cm-1"), rtol=1e-14
    )


def test_linear_molecules_have_no_a_and_a_single_atom_no_constants():
    co2 = ph.Body.from_atoms(["O", "C", "O"], [[0, 0, -1.16], [0, 0, 0], [0, 0, 1.16]])
    a, b, c = rotational_constants(co2)
    assert a is None and b == c
    # I = 2 m_O d^2 about the centre (m_O from the body: the table's 16O).
    m_o = (co2.mass - 12.0) / 2
    expected = sc.h / (8 * np.pi**2 * 2 * m_o * sc.atomic_mass * (1.16 * sc.angstrom) ** 2)
    assert b == pytest.approx(expected / 1e6, rel=1e-12)
    # Atoms off the line by much less than rtol / 2 of the length: still linear, A None.
    bent = ph.Body.from_atoms(["O", "C", "O"], [[0, 0, -1.16], [1e-6, 0, 0], [0, 0, 1.16]])
    assert rotor_type(bent) == "linear" and rotational_constants(bent).A is None
    # With a tolerance that sees the bend, A is the (huge, finite) constant of that geometry.
    a_bent = rotational_constants(bent, rtol=1e-9).A
    assert a_bent is not None and math.isfinite(a_bent) and a_bent > 1e9
    atom = ph.Body.from_atoms(["Ar"], [[1.0, 2.0, 3.0]])
    for function in (rotational_constants, rotor_type, asymmetry):
        with pytest.raises(ph.ArgumentError, match="all three zero") as error:
            function(atom)
        assert error.value.argument == "body"


def test_bad_options_are_named():
    body = ph.Body.from_atoms(["O", "H", "H"], water())
    with pytest.raises(ph.ArgumentError, match="'MHz', 'GHz', 'cm-1'") as error:
        rotational_constants(body, "THz")
    assert error.value.argument == "unit"
    with pytest.raises(ph.ArgumentError) as error:
        rotational_constants(body, length_unit="inch")
    assert error.value.argument == "length_unit"
    with pytest.raises(ph.ArgumentError) as error:
        rotational_constants(body, mass_unit="g")
    assert error.value.argument == "mass_unit"
    with pytest.raises(TypeError, match="unit"):
        rotational_constants(body, 3)
    for rtol in (-1e-3, 1.0, math.nan):
        with pytest.raises(ph.ArgumentError) as error:
            rotor_type(body, rtol=rtol)
        assert error.value.argument == "rtol"
    with pytest.raises(TypeError, match="body"):
        rotational_constants(np.eye(3))


# --- against measured constants -----------------------------------------------------------------
#
# The constants computed here are those of the geometry given. An equilibrium (r_e) structure
# gives equilibrium constants; spectra measure ground-state constants (A_0, B_0, C_0), larger or
# smaller by the vibrational averaging: B_0 = B_e - alpha_e / 2 for a diatomic, up to about 3 per
# cent for the light, floppy hydrides (H2O, NH3). Each tolerance below is the size of that
# effect for the molecule, stated with it; CO, where both B_e and alpha_e are tabulated, is
# checked to the digits of its bond length.


def test_carbon_monoxide_against_huber_and_herzberg():
    # Huber and Herzberg, Constants of Diatomic Molecules (1979), via the NIST Chemistry
    # WebBook, 12C16O X 1Sigma+: r_e = 1.128323 A, B_e = 1.93128087 cm-1, alpha_e =
    # 0.01750441 cm-1. r_e is given to 6 decimals (5e-7 A, 4e-7 relative): B to 1e-6.
    co = ph.Body.from_atoms(["C", "O"], [[0, 0, 0], [0, 0, 1.128323]])
    a, b, c = rotational_constants(co, "cm-1")
    assert a is None and b == c
    assert b == pytest.approx(1.93128087, rel=2e-6)
    # Ground state: B_0 = B_e - alpha_e / 2, against the J = 1-0 line at 115271.2018 MHz
    # (2 B_0 - 4 D_0, D_0 = 0.18350 MHz; CDMS entry 028503).
    b0 = (b - 0.01750441 / 2) * 100 * sc.c / 1e6
    assert b0 == pytest.approx((115271.2018 + 4 * 0.18350) / 2, rel=2e-6)


MEASURED = {
    # NIST CCCBDB, "Listing of experimental geometry data" and experimental rotational
    # constants (cm-1). Water: r_e = 0.9578 A, theta_e = 104.4776 deg (Hoy and Bunker 1979);
    # ground state A_0 = 27.877, B_0 = 14.512, C_0 = 9.285. Equilibrium vs ground state:
    # about 2 per cent for A and C (Ce > C0, Ae < A0).
    "H2O": (["O", "H", "H"], water(), (27.877, 14.512, 9.285), 0.03),
    # Ammonia, r_0 = 1.012 A, H-N-H = 106.67 deg and B_0 = 9.9443, C_0 = 6.196 cm-1 (Herzberg
    # 1966; CCCBDB prints B as 9.44430, a transposed digit: the J = 1-0 line at 572.498 GHz,
    # 2 B_0 less the 23.7 GHz inversion splitting, puts B_0 at 298 GHz = 9.94 cm-1). The
    # inversion makes C_0 differ from the rigid value by about 2.5 per cent.
    "NH3": (["N", "H", "H", "H"], pyramid(1.012, 106.67), (9.9443, 9.9443, 6.196), 0.03),
    # Formaldehyde, r(C=O) = 1.205 A, r(C-H) = 1.111 A, H-C-H = 116.133 deg (Gurvich) and
    # A = 9.4053, B = 1.2953, C = 1.1342 cm-1 (Herzberg 1966): within 0.4 per cent; 1 allowed.
    "H2CO": (["O", "C", "H", "H"], formaldehyde(), (9.4053, 1.2953, 1.1342), 0.01),
}


@pytest.mark.parametrize("name", sorted(MEASURED))
def test_constants_against_measured_values(name):
    symbols, positions, measured, tolerance = MEASURED[name]
    got = rotational_constants(ph.Body.from_atoms(symbols, positions), "cm-1")
    relative = (np.array(got, dtype=float) - measured) / measured
    assert np.abs(relative).max() < tolerance, relative


def test_methyl_chloride_from_ase_against_gordy():
    # ASE's CH3Cl (the G2 set's MP2/6-31G* geometry) through Body.from_molecule, against
    # B_0 = 13292.86 MHz for CH3 35Cl (Gordy et al., "Millimeter wave spectra and centrifugal
    # stretching constants of the methyl halides", J. Chem. Phys. 1954): the computed geometry
    # and the vibrational averaging each account for a few tenths of a per cent.
    body = ph.Body.from_molecule(ase.build.molecule("CH3Cl"))
    assert rotor_type(body) == "prolate"
    a, b, c = rotational_constants(body)
    assert b == pytest.approx(13292.86, rel=0.01)
    # Its B and C agree to 5e-8 (the geometry's own digits): kappa is -1 to that.
    assert asymmetry(body) == pytest.approx(-1.0, abs=1e-6)


def test_a_planar_molecule_has_no_inertial_defect():
    # I_c = I_a + I_b for any planar body (the perpendicular axis theorem); measured
    # ground-state constants of water show a small positive defect, equilibrium ones none.
    body = ph.Body.from_atoms(["O", "C", "H", "H"], formaldehyde())
    i_a, i_b, i_c = body.principal().moments
    assert abs(i_c - i_a - i_b) <= 8 * EPS * i_c


# --- rotor type and asymmetry -------------------------------------------------------------------


def test_rotor_types_of_known_molecules():
    d = 1.09 / math.sqrt(3)
    methane = [[0, 0, 0], [d, d, d], [d, -d, -d], [-d, d, -d], [-d, -d, d]]
    assert rotor_type(ph.Body.from_atoms(["C", "H", "H", "H", "H"], methane)) == "spherical"
    assert rotor_type(ph.Body.from_atoms(["N", "H", "H", "H"], pyramid(1.012, 106.67))) == "oblate"
    assert rotor_type(ph.Body.from_atoms(["O", "H", "H"], water())) == "asymmetric"
    assert rotor_type(ph.Body.from_atoms(["H", "Cl"], [[0, 0, 0], [0, 0, 1.27]])) == "linear"
    # Benzene (a planar hexagon): oblate; ethane-like CH3-CH3 along z: prolate.
    ring = [[1.39 * math.cos(t), 1.39 * math.sin(t), 0] for t in np.radians(np.arange(0, 360, 60))]
    hydrogens = [
        [2.48 * math.cos(t), 2.48 * math.sin(t), 0] for t in np.radians(np.arange(0, 360, 60))
    ]
    benzene = ph.Body.from_atoms(["C"] * 6 + ["H"] * 6, ring + hydrogens)
    assert rotor_type(benzene) == "oblate"
    assert asymmetry(benzene) == pytest.approx(1.0, abs=1e-12)
    ethane = [[0, 0, 0.77], [0, 0, -0.77]]
    for z, phase in ((1.16, 0.0), (-1.16, 60.0)):
        ethane += [
            [1.02 * math.cos(t), 1.02 * math.sin(t), z]
            for t in np.radians(phase + np.array([0, 120, 240]))
        ]
    assert rotor_type(ph.Body.from_atoms(["C", "C"] + ["H"] * 6, ethane)) == "prolate"


def test_the_tolerance_decides_near_symmetric_tops():
    # NH3 with one H moved by 1e-4 A: a symmetric top at the default rtol (1e-3), asymmetric
    # when the tolerance is below the relative split of I_a and I_b (about 1e-4).
    positions = np.array(pyramid(1.012, 106.67))
    positions[1, 0] += 1e-4
    body = ph.Body.from_atoms(["N", "H", "H", "H"], positions)
    i_a, i_b, i_c = body.principal().moments
    split = (i_b - i_a) / i_c
    assert 1e-6 < split < 1e-3
    assert rotor_type(body) == "oblate"
    assert rotor_type(body, rtol=split / 2) == "asymmetric"


def test_asymmetry_matches_rays_formula():
    body = ph.Body.from_atoms(["O", "H", "H"], water())
    a, b, c = rotational_constants(body)
    assert asymmetry(body) == pytest.approx((2 * b - a - c) / (a - c), rel=1e-12)
    assert -1 < asymmetry(body) < 1
    assert asymmetry(
        ph.Body.from_atoms(["N", "H", "H", "H"], pyramid(1.012, 106.67))
    ) == pytest.approx(1.0, abs=1e-12)
    co = ph.Body.from_atoms(["C", "O"], [[0, 0, 0], [0, 0, 1.128]])
    assert asymmetry(co) == -1.0
    d = 1.09 / math.sqrt(3)
    methane = [[0, 0, 0], [d, d, d], [d, -d, -d], [-d, d, -d], [-d, -d, d]]
    with pytest.raises(ph.ArgumentError, match="spherical") as error:
        asymmetry(ph.Body.from_atoms(["C", "H", "H", "H", "H"], methane))
    assert error.value.argument == "body"


# --- other libraries' molecules -----------------------------------------------------------------


def test_from_molecule_reads_ase_atoms_and_files(tmp_path):
    atoms = ase.build.molecule("CH3CH2OH")
    expected = ph.Body.from_atoms(atoms.get_chemical_symbols(), atoms.get_positions())
    body = ph.Body.from_molecule(atoms)
    np.testing.assert_array_equal(body.inertia, expected.inertia)
    for name in ("ethanol.xyz", "ethanol.pdb", "ethanol.cif"):
        path = tmp_path / name
        ase.io.write(path, atoms)
        got = ph.Body.from_molecule(path)
        # PDB keeps 3 decimals, XYZ and CIF more: the inertia to that precision.
        assert got.mass == pytest.approx(expected.mass, rel=1e-12)
        assert np.abs(got.inertia - expected.inertia).max() < 0.05, name
    xyz = tmp_path / "ethanol.xyz"
    assert ph.Body.from_molecule(str(xyz), masses="average").mass == pytest.approx(
        2 * 12.011 + 6 * 1.008 + 15.999, rel=1e-12
    )
    with pytest.raises(FileNotFoundError, match="missing.xyz"):
        ph.Body.from_molecule(tmp_path / "missing.xyz")
    garbage = tmp_path / "garbage.xyz"
    garbage.write_text("this is not\nan xyz file\n")
    with pytest.raises(ph.FileFormatError, match="garbage.xyz") as error:
        ph.Body.from_molecule(garbage)
    assert error.value.argument == "molecule"
    assert error.value.path == str(garbage)
    with pytest.raises(TypeError, match="molecule"):
        ph.Body.from_molecule(42)


def test_from_molecule_reads_an_rdkit_mol():
    mol = Chem.AddHs(Chem.MolFromSmiles("C=O"))
    assert AllChem.EmbedMolecule(mol, randomSeed=7) == 0
    positions = mol.GetConformer().GetPositions()
    symbols = [atom.GetSymbol() for atom in mol.GetAtoms()]
    body = ph.Body.from_molecule(mol)
    np.testing.assert_array_equal(body.inertia, ph.Body.from_atoms(symbols, positions).inertia)
    # Isotopes set on the atoms are used.
    mol.GetAtomWithIdx(0).SetIsotope(13)
    assert ph.Body.from_molecule(mol).mass - body.mass == pytest.approx(
        AME2020["13C"] - 12.0, rel=1e-9
    )
    with pytest.raises(ph.ArgumentError, match="conformer") as error:
        ph.Body.from_molecule(Chem.MolFromSmiles("C=O"))
    assert error.value.argument == "molecule"
    with pytest.raises(ph.ArgumentError) as error:
        ph.Body.from_molecule(mol, conformer=5)
    assert error.value.argument == "conformer"


def numpy_inertia(symbols, positions):
    """The inertia tensor about the centre of mass, written apart: AME 2020 masses of the main
    isotopes (the table above), numpy sums."""
    m = np.array([AME2020[{"O": "16O", "H": "1H", "C": "12C"}[s]] for s in symbols])
    r = np.asarray(positions, dtype=float)
    r = r - m @ r / m.sum()
    return np.einsum("n,nij->ij", m, np.einsum("ni,ni->n", r, r)[:, None, None] * np.eye(3)
                     - r[:, :, None] * r[:, None, :])


@pytest.mark.parametrize("name", ["frames.xyz", "frames.extxyz", "frames.traj", "frames.pdb"])
def test_conformer_picks_a_structure_of_a_multi_frame_file(tmp_path, name):
    # Three frames of a molecule that ASE writes to one file (a trajectory, or an XYZ of several
    # structures): conformer=k gives frame k, as ASE reads it back; before, every conformer gave
    # the first frame without a word.
    base = ase.build.molecule("CH3CH2OH")
    frames = []
    for k in range(3):
        atoms = base.copy()
        atoms.positions = atoms.positions * (1.0 + 0.2 * k) + [0.1 * k, 0.0, 0.0]
        frames.append(atoms)
    path = tmp_path / name
    ase.io.write(path, frames)
    read_back = ase.io.read(path, index=":")
    assert len(read_back) == 3
    symbols = base.get_chemical_symbols()
    for k in range(3):
        expected = numpy_inertia(symbols, read_back[k].get_positions())
        got = ph.Body.from_molecule(path, conformer=k).inertia
        # To the masses' agreement (periodictable's and the table above differ by ~1e-12).
        np.testing.assert_allclose(got, expected, rtol=0, atol=1e-10 * np.abs(expected).max())
    inertias = [numpy_inertia(symbols, f.get_positions()) for f in read_back]
    assert np.abs(inertias[2] - inertias[0]).max() > 0.1 * np.abs(inertias[0]).max()
    # The default (-1) is the first structure, as RDKit's default conformer is the first.
    np.testing.assert_array_equal(
        ph.Body.from_molecule(path).inertia, ph.Body.from_molecule(path, conformer=0).inertia
    )
    for bad, fragment in ((3, r"holds 3 \(0 to 2\)"), (-2, "the first")):
        with pytest.raises(ph.ArgumentError, match=fragment) as error:
            ph.Body.from_molecule(path, conformer=bad)
        assert error.value.argument == "conformer"
    with pytest.raises(TypeError, match="`conformer`"):
        ph.Body.from_molecule(path, conformer="1")


def test_conformer_and_format_are_refused_where_they_mean_nothing(tmp_path):
    atoms = ase.build.molecule("H2O")
    path = tmp_path / "water.xyz"
    ase.io.write(path, atoms)
    with pytest.raises(ph.ArgumentError, match="one structure") as error:
        ph.Body.from_molecule(atoms, conformer=1)
    assert error.value.argument == "conformer"
    ase.io.write(tmp_path / "water.pdb", atoms)
    universe = mda.Universe(str(tmp_path / "water.pdb"))
    with pytest.raises(ph.ArgumentError, match="MDAnalysis") as error:
        ph.Body.from_molecule(universe, conformer=0)
    assert error.value.argument == "conformer"
    with pytest.raises(ph.ArgumentError) as error:
        ph.Body.from_molecule(atoms, format="xyz")
    assert error.value.argument == "format"
    with pytest.raises(ph.ArgumentError) as error:
        ph.Body.from_molecule(path, format="no-such-format")
    assert error.value.argument == "format"
    with pytest.raises(TypeError, match="`format`"):
        ph.Body.from_molecule(path, format=3)
    # A single-structure file has structure 0 only.
    with pytest.raises(ph.ArgumentError, match="holds 1") as error:
        ph.Body.from_molecule(path, conformer=1)
    empty = tmp_path / "empty.xyz"
    empty.write_text("")
    with pytest.raises(ph.FileFormatError) as error:
        ph.Body.from_molecule(empty)
    assert error.value.argument == "molecule"
    mol = Chem.AddHs(Chem.MolFromSmiles("O"))
    assert len(AllChem.EmbedMultipleConfs(mol, 2, randomSeed=3)) == 2
    second = mol.GetConformer(1).GetPositions()
    symbols = [a.GetSymbol() for a in mol.GetAtoms()]
    np.testing.assert_allclose(
        ph.Body.from_molecule(mol, conformer=1).inertia, numpy_inertia(symbols, second),
        rtol=0, atol=1e-10,
    )
    for bad in (2, 2**40):
        with pytest.raises(ph.ArgumentError, match="0 to 1") as error:
            ph.Body.from_molecule(mol, conformer=bad)
        assert error.value.argument == "conformer"


def test_from_molecule_reads_an_mdanalysis_group(tmp_path):
    atoms = ase.build.molecule("CH3Cl")
    path = tmp_path / "ch3cl.pdb"
    ase.io.write(path, atoms)
    universe = mda.Universe(str(path))
    expected = ph.Body.from_atoms(atoms.get_chemical_symbols(), universe.atoms.positions)
    for group in (universe, universe.atoms, universe.select_atoms("all")):
        got = ph.Body.from_molecule(group)
        np.testing.assert_array_equal(got.inertia, expected.inertia)
    bare = mda.Universe.empty(3, trajectory=True)
    with pytest.raises(ph.ArgumentError, match="elements") as error:
        ph.Body.from_molecule(bare.atoms)
    assert error.value.argument == "molecule"


# --- the examples in the docstrings -------------------------------------------------------------


@pytest.mark.parametrize(
    "target",
    [
        molecule,
        ph.Body.from_atoms,
        ph.Body.from_molecule,
        ph.principal,
        ph.point_masses_inertia,
    ],
    ids=lambda t: getattr(t, "__qualname__", getattr(t, "__name__", str(t))),
)
def test_docstring_examples_run(target):
    assert ph.molecule is molecule  # `import polhode` is enough for ph.molecule
    finder = doctest.DocTestFinder(recurse=target is molecule)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    tests = finder.find(target, globs={})
    assert tests and any(t.examples for t in tests)
    for test in tests:
        runner.run(test)
    assert runner.failures == 0

"""Rotational constants of a few molecules against measured values (the table of the README).

    python -m benchmarks.molecule_constants

The geometries and measured constants are those of tests/test_molecule.py, which asserts the
tolerances; this prints the relative differences. CO's equilibrium structure gives B_e, to be
compared with B_e; the other geometries give rigid-molecule constants compared with measured
ground-state constants, which differ from them by the vibrational averaging (up to about 3 per
cent for H2O and NH3).
"""

from __future__ import annotations

import math

import numpy as np

import polhode as ph
from polhode.molecule import rotational_constants


def _bent(r: float, angle: float) -> list[list[float]]:
    a = math.radians(angle) / 2
    return [
        [0, 0, 0],
        [0, r * math.sin(a), -r * math.cos(a)],
        [0, -r * math.sin(a), -r * math.cos(a)],
    ]


def _pyramid(r: float, angle: float) -> list[list[float]]:
    rho = 2 * r * math.sin(math.radians(angle) / 2) / math.sqrt(3)
    h = math.sqrt(r * r - rho * rho)
    return [[0, 0, 0]] + [
        [rho * math.cos(t), rho * math.sin(t), -h] for t in np.radians([90.0, 210.0, 330.0])
    ]


def _formaldehyde() -> list[list[float]]:
    a = math.radians(116.133) / 2
    s, c = 1.111 * math.sin(a), 1.111 * math.cos(a)
    return [[0, 0, 1.205], [0, 0, 0], [0, s, -c], [0, -s, -c]]


# name: (atoms, positions, measured (A, B, C) in cm-1 (A None for a linear molecule), source)
MOLECULES = {
    "CO (B_e)": (
        ["C", "O"],
        [[0, 0, 0], [0, 0, 1.128323]],
        (None, 1.93128087, 1.93128087),
        "r_e and B_e, Huber and Herzberg 1979 (NIST WebBook)",
    ),
    "H2O": (
        ["O", "H", "H"],
        _bent(0.9578, 104.4776),
        (27.877, 14.512, 9.285),
        "r_e (Hoy and Bunker 1979) vs ground state, NIST CCCBDB",
    ),
    "NH3": (
        ["N", "H", "H", "H"],
        _pyramid(1.012, 106.67),
        (9.9443, 9.9443, 6.196),
        "r_0 and B_0, C_0, Herzberg 1966",
    ),
    "H2CO": (
        ["O", "C", "H", "H"],
        _formaldehyde(),
        (9.4053, 1.2953, 1.1342),
        "Gurvich geometry vs Herzberg 1966, NIST CCCBDB",
    ),
}


def main() -> None:
    print(f"{'molecule':10s} {'':3s} {'polhode (cm-1)':>15s} {'measured':>11s} {'rel. diff.':>11s}")
    for name, (symbols, positions, measured, source) in MOLECULES.items():
        got = rotational_constants(ph.Body.from_atoms(symbols, positions), "cm-1")
        for label, value, reference in zip("ABC", got, measured, strict=True):
            if reference is None:
                print(f"{name:10s} {label:3s} {'None':>15s} {'-':>11s} {'-':>11s}")
                continue
            assert value is not None
            diff = (value - reference) / reference
            print(f"{name:10s} {label:3s} {value:15.6f} {reference:11.6f} {diff:+11.2e}")
        print(f"{'':14s}({source})")
    co = ph.Body.from_atoms(["C", "O"], [[0, 0, 0], [0, 0, 1.128323]])
    b0 = (rotational_constants(co, "cm-1").B - 0.01750441 / 2) * 29979.2458
    line = (115271.2018 + 4 * 0.18350) / 2
    print(
        f"CO B_0 = B_e - alpha_e/2 = {b0:.3f} MHz vs (nu(1-0) + 4 D_0)/2 = {line:.3f} MHz: "
        f"{(b0 - line) / line:+.2e}"
    )
    try:
        import ase.build
    except ImportError:  # pragma: no cover
        return
    body = ph.Body.from_molecule(ase.build.molecule("CH3Cl"))
    b = rotational_constants(body).B
    print(
        f"CH3Cl (ASE's G2 geometry) B = {b:.2f} MHz vs B_0 = 13292.86 MHz (Gordy et al. 1954): "
        f"{(b - 13292.86) / 13292.86:+.2e}"
    )


if __name__ == "__main__":
    main()

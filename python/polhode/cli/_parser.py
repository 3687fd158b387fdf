"""The parser of the ``polhode`` command: its commands and options, each command's ``run``."""

from __future__ import annotations

import argparse
from typing import Any

import polhode as ph
from polhode.cli import audit as audit_command
from polhode.cli import bench as bench_command
from polhode.cli import demo as demo_command
from polhode.cli import inertia as inertia_command
from polhode.cli import spin as spin_command
from polhode.cli._common import integer, number, solid_forms
from polhode.cli.inertia import MASS_SOURCES
from polhode.cli.spin import DAMPER_FIELDS, FIXED_STEP, MAX_POINTS, WHEEL_FIELDS


class _Group(argparse.Action):
    """An option taking ``fewest`` to ``len(names)`` numbers, repeatable: one group of numbers
    (one rotor) per use, appended in order."""

    def __init__(self, *args: Any, names: tuple[str, ...], fewest: int, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.names, self.fewest = names, fewest

    def __call__(
        self,
        parser: argparse.ArgumentParser,
        namespace: argparse.Namespace,
        values: Any,
        option_string: str | None = None,
    ) -> None:
        most = len(self.names)
        if not self.fewest <= len(values) <= most:
            optional = self.names[self.fewest :]
            form = " ".join(n.upper() for n in self.names[: self.fewest])
            if optional:
                form += " " + " ".join(f"[{n.upper()}" for n in optional) + "]" * len(optional)
            count = f"{self.fewest}" if self.fewest == most else f"{self.fewest} to {most}"
            raise argparse.ArgumentError(
                self, f"expected {count} numbers ({form}), got {len(values)}."
            )
        setattr(namespace, self.dest, [*(getattr(namespace, self.dest) or []), list(values)])


def build_parser() -> argparse.ArgumentParser:
    """The ``polhode`` command's parser; each command's namespace has its ``run``."""
    parser = argparse.ArgumentParser(
        prog="polhode",
        description="Rigid-body rotation: mass properties and the motion of a body spun free. "
        "Principal axes are numbered 1, 2, 3 in ascending order of moment (I1 <= I2 <= I3). "
        "Start with `polhode demo`.",
    )
    parser.add_argument("--version", action="version", version=f"polhode {ph.__version__}")
    commands = parser.add_subparsers(dest="command")
    demo = commands.add_parser(
        "demo",
        help="principal axes of a few bodies and the tennis-racket flip of a T-handle, "
        "printed, with plots and Poinsot's construction written into ./polhode-demo",
        description="Principal axes of a few bodies, the tennis-racket flip of a T-handle "
        "(predicted, observed, and what is conserved) and the major-axis rule with a damper, "
        "printed; their plots (PNG), the flip animated (tennis_racket.gif) and Poinsot's "
        "construction of the flip (poinsot.html, interactive, opens offline in a browser) "
        "written into --out.",
    )
    demo.add_argument(
        "--out",
        default="polhode-demo",
        help="folder for the PNG plots, tennis_racket.gif and poinsot.html (default "
        "./polhode-demo)",
    )
    demo.add_argument("--no-plots", action="store_true", help="print only, write no file")
    demo.set_defaults(run=demo_command.run)
    spin = commands.add_parser(
        "spin",
        help="simulate one body free of external torques, optionally with internal rotors, "
        "and report its motion and invariant drift",
        description="Simulate one body free of external torques, optionally with internal "
        "rotors: reaction wheels (--wheel, with a constant motor torque on each) and spherical "
        "dampers (--damper). External torques (gravity, torque models, functions) are "
        "polhode.simulate's torque=, not options of this command. Give --moments or --body. "
        "Principal axes are numbered 1, 2, 3 in ascending order of moment (I1 <= I2 <= I3); "
        "numbers are in SI units as the labels say (kg, m, s, rad/s), or any consistent set.",
    )
    source = spin.add_mutually_exclusive_group(required=True)
    source.add_argument(
        "--moments",
        nargs=3,
        type=number("a positive finite number (a principal moment)", positive=True),
        metavar=("IX", "IY", "IZ"),
        help="the principal moments about the body's axes x, y, z (kg m^2): the body's axes "
        "are principal, and given in ascending order they are I1, I2, I3 (any positive "
        "numbers; Euler's equations need no more)",
    )
    source.add_argument(
        "--body",
        nargs="+",
        metavar="KIND NAME=VALUE",
        help="a solid, e.g. 'cylinder mass=1 radius=0.1 length=0.5' or 'cuboid mass=1 "
        "size=0.1,0.2,0.5' (kinds and their keys as polhode.Body names them, each NAME=NUMBER, a "
        "vector's NAME=X,Y,Z: "
        + solid_forms()
        + "), or a mesh file: 'mesh path=part.stl density=2700' (or mass=M; scale=S, "
        "shell=true optional; STL, OBJ, PLY, OFF, glTF/GLB). Its axes are those it is built "
        "in (a solid's: its symmetry axis along z, a cuboid's size along x, y, z)",
    )
    spin.add_argument(
        "--omega",
        nargs=3,
        type=number("a finite number (a component of omega0, in body axes)"),
        required=True,
        metavar=("WX", "WY", "WZ"),
        help="omega0, the angular velocity at t = 0, in body axes x, y, z (rad/s)",
    )
    spin.add_argument(
        "--t",
        type=number("a finite end time >= 0", minimum=0.0),
        required=True,
        help="end time (s)",
    )
    spin.add_argument(
        "--points",
        type=integer(f"an integer from 2 to {MAX_POINTS}", 2, MAX_POINTS),
        default=None,
        help="output times, evenly spaced from 0 to --t (default: those polhode.simulate "
        "takes for the end time --t, 48 per turn of the motion's fastest rate, at least 49 and "
        "at most 100001: with dop853 also the end of every step, with a fixed-step method "
        "every so many steps)",
    )
    spin.add_argument(
        "--method",
        default="auto",
        choices=ph.simulation.METHODS,
        help="the method (default auto: the exact solution, or dop853 with rotors)",
    )
    spin.add_argument(
        "--dt",
        type=number("a positive finite step", positive=True),
        help=f"step (s) of the fixed-step methods ({', '.join(FIXED_STEP)}; required by them)",
    )
    spin.add_argument(
        "--order", type=int, choices=(2, 4, 6), help="order of --method splitting (default 4)"
    )
    spin.add_argument(
        "--rtol",
        type=number("a finite tolerance between 0 and 1", positive=True, below=1.0),
        help="relative tolerance of --method dop853 (default 1e-10)",
    )
    spin.add_argument(
        "--wheel",
        action=_Group,
        nargs="+",
        type=number("a finite number (a wheel's axis, inertia, rate0 or torque)"),
        names=WHEEL_FIELDS,
        fewest=4,
        metavar="NUMBER",
        help="a reaction wheel, AX AY AZ INERTIA [RATE0 [TORQUE]]: its axis in body axes x, "
        "y, z, its axial inertia (kg m^2), its rate relative to the body at t = 0 (rad/s, "
        "default 0) and a constant motor torque on it (N m, default 0); repeatable: wheel 1, "
        "wheel 2, ... in the order given. The body's moments include it, locked",
    )
    spin.add_argument(
        "--damper",
        action=_Group,
        nargs=2,
        type=number("a finite number (a damper's inertia or damping)"),
        names=DAMPER_FIELDS,
        fewest=2,
        metavar=("INERTIA", "DAMPING"),
        help="a spherical (Kane) damper: the sphere's inertia (kg m^2) and the viscous "
        "coefficient (N m s); repeatable: damper 1, damper 2, ... in the order given. The "
        "body's moments include it, locked. With rotors --method is auto (dop853), dop853 or "
        "rk4",
    )
    spin.add_argument(
        "--csv",
        metavar="FILE",
        help="write the trajectory to this CSV file, each column's unit in its header: "
        "'t (s)', omega in body axes ('omega_1 (rad/s)', _2, _3 where the body's axes are its "
        "principal axes 1, 2, 3, else 'omega_x (rad/s)', _y, _z), the orientation as the "
        "quaternion qx, qy, qz, qw (body to space, scalar last) and each rotor's rate "
        "relative to the body ('wheel1_rate (rad/s)' about its axis; a damper's in body axes, "
        "'damper1_rate_x (rad/s)', _y, _z); numbers as the shortest decimals that read back "
        "to the same doubles",
    )
    spin.add_argument(
        "--plot", metavar="FILE", help="write omega and the invariant drift to this image (.png)"
    )
    spin.add_argument(
        "--html",
        metavar="FILE",
        help="write Poinsot's construction of the run to this HTML page: the body turning, its "
        "energy ellipsoid rolling on the invariable plane, the polhode and the herpolhode, "
        "animated (plotly.js embedded: opens offline in a browser; needs plotly, pip install "
        "'polhode[plot]'). Not with --wheel or --damper",
    )
    spin.set_defaults(run=spin_command.run)
    audit_parser = commands.add_parser(
        "audit",
        help="check the declared inertials of a URDF or MJCF file",
        description="Check every link's declared inertial: errors (non-positive mass, not "
        "positive semidefinite, triangle inequality broken), warnings (a near-zero principal "
        "moment, disagreement with the link's own geometry, a centre of mass far from it), "
        "with a corrected inertial where the geometry gives one. Exit status 1 if any error "
        "is found, 2 if the file cannot be read, 0 otherwise.",
    )
    audit_parser.add_argument("file", help="a URDF (.urdf) or MJCF (MuJoCo .xml) file")
    audit_parser.add_argument(
        "--rtol",
        type=number("a positive finite tolerance", positive=True),
        default=0.25,
        help="relative tolerance of the comparison with the geometry (default 0.25)",
    )
    audit_parser.add_argument(
        "--geometry",
        choices=("collision", "visual"),
        default="collision",
        help="URDF geometry to compare with (default collision)",
    )
    audit_parser.add_argument(
        "--density",
        type=number("a positive finite density", positive=True),
        help="density for the corrected inertial of a link whose mass is unusable",
    )
    audit_parser.set_defaults(run=audit_command.run)
    inertia_parser = commands.add_parser(
        "inertia",
        help="mass properties of a file: a mesh, a robot description's links, a molecule",
        description="Mass properties of a file: the mass, the centre of mass, the inertia "
        "tensor about it and the principal moments and axes. A mesh file (STL, OBJ, PLY, OFF, "
        "glTF/GLB: give --density or --mass) as one uniform body; a URDF file as a row per "
        "link from its declared inertial, an MJCF file as a row per body as MuJoCo compiles "
        "it, each in its own frame; any other file as a "
        "molecule read by ASE (XYZ, PDB, CIF, ...; angstrom and u), with its rotational "
        "constants, Ray's asymmetry and rotor type. Exit status 2 if the file cannot be read.",
    )
    inertia_parser.add_argument("file", help="a mesh, URDF, MJCF or molecule file")
    amount = inertia_parser.add_mutually_exclusive_group()
    amount.add_argument(
        "--density",
        type=number("a positive finite density", positive=True),
        help="mesh: mass per volume (per area with --shell); URDF/MJCF: the density of the "
        "links without an inertial (MJCF: then read as written, not as MuJoCo compiles it)",
    )
    amount.add_argument(
        "--mass",
        type=number("a positive finite mass", positive=True),
        help="mesh: the total mass; URDF/MJCF: the total mass of the links without an inertial",
    )
    inertia_parser.add_argument(
        "--scale",
        type=number("a finite non-zero number"),
        help="mesh: length scale of the coordinates (0.001 reads millimetres as metres)",
    )
    inertia_parser.add_argument(
        "--shell", action="store_true", help="mesh: the mass on the surface (a thin shell)"
    )
    inertia_parser.add_argument(
        "--fix-winding", action="store_true", help="mesh: turn an inside-out mesh right way out"
    )
    inertia_parser.add_argument(
        "--merge-fixed",
        action="store_true",
        help="URDF and MJCF: one row per moving part, every link on a fixed joint (MJCF: every "
        "body without joints that MuJoCo fuses) fused into its parent",
    )
    inertia_parser.add_argument(
        "--strict",
        action="store_true",
        help="URDF and MJCF: refuse the file (exit status 2) at the first link a simulator "
        "would refuse, "
        "instead of leaving it out with a warning",
    )
    inertia_parser.add_argument(
        "--masses",
        choices=tuple(MASS_SOURCES),
        help="molecule: the atomic masses, the most abundant isotope's (default) or the "
        "standard atomic weight",
    )
    inertia_parser.add_argument(
        "--unit",
        choices=ph.molecule.UNITS,
        help="molecule: the unit of the rotational constants (default MHz)",
    )
    inertia_parser.add_argument(
        "--format", help="molecule: ASE's name of the file format (default from the extension)"
    )
    inertia_parser.add_argument(
        "--frames",
        metavar="OUT.csv",
        help="molecule: write each frame's principal moments and axes to this CSV, the axes "
        "followed from frame to frame (no sign flips or swaps; the moments follow their axes)",
    )
    inertia_parser.add_argument(
        "--point",
        nargs=3,
        type=number("a finite number (a coordinate of the point)"),
        metavar=("X", "Y", "Z"),
        help="also the inertia tensor about this point (in the file's or the link's frame)",
    )
    inertia_parser.add_argument(
        "--spatial",
        choices=ph.bodies.SPATIAL_CONVENTIONS,
        help="also the 6x6 spatial inertia in this convention (about --point, default the "
        "origin of the file's or the link's frame)",
    )
    inertia_parser.add_argument(
        "--json", action="store_true", help="print JSON (machine-readable) instead of text"
    )
    inertia_parser.set_defaults(run=inertia_command.run)
    bench_parser = commands.add_parser(
        "bench",
        help="speed against error, polhode against scipy, MuJoCo, numpy and trimesh",
        description="Run the benchmark suite and print its tables (benchmarks/ in the source "
        "tree has the full suite and the report).",
    )
    bench_parser.add_argument("--quick", action="store_true", help="under a minute")
    bench_parser.add_argument(
        "--repeats",
        type=integer("an integer >= 1", 1),
        help="repeats per setting (default 3/5; at least 5 with --kernels)",
    )
    bench_parser.add_argument(
        "--kernels",
        action="store_true",
        help="only the kernels against the hardware: each kernel's time per element against "
        "its peer and target, flops and bytes per element, fraction of the machine's limit",
    )
    bench_parser.set_defaults(run=bench_command.run)
    return parser

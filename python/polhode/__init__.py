"""polhode: the rotation of rigid bodies, with a Rust core.

Mass properties and principal axes (:class:`Body`, :func:`principal`), molecules
(:meth:`Body.from_atoms`, :mod:`polhode.molecule`), motion (:func:`simulate`,
:mod:`polhode.torque`, :mod:`polhode.rotors`) and understanding (:func:`analyze`); files in
(:mod:`polhode.io`: meshes, URDF, MJCF, and their audit); see the README.
"""

from polhode import errors, io, molecule, plot, rotors, torque
from polhode._core import cancel_all
from polhode._version import __version__ as __version__
from polhode.analysis import Analysis, analyze
from polhode.bodies import Body
from polhode.errors import (
    ArgumentError,
    CancelledError,
    ConvergenceError,
    FileFormatError,
    InertiaError,
    NonFiniteError,
    NonPositiveError,
    PolhodeError,
    PolhodeWarning,
    RobotFileWarning,
    ShapeError,
)
from polhode.perturbation import perturbation
from polhode.principal_axes import Principal, point_masses_inertia, principal
from polhode.simulation import Trajectory, simulate

__all__ = [
    "Analysis",
    "ArgumentError",
    "Body",
    "CancelledError",
    "ConvergenceError",
    "FileFormatError",
    "InertiaError",
    "NonFiniteError",
    "NonPositiveError",
    "PolhodeError",
    "PolhodeWarning",
    "RobotFileWarning",
    "ShapeError",
    "Principal",
    "Trajectory",
    "analyze",
    "cancel_all",
    "errors",
    "molecule",
    "io",
    "perturbation",
    "plot",
    "point_masses_inertia",
    "principal",
    "rotors",
    "simulate",
    "torque",
]

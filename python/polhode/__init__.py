"""polhode: the rotation of rigid bodies, with a Rust core.

Mass properties and principal axes (:class:`Body`, :func:`principal`), motion
(:func:`simulate`, :mod:`polhode.torque`) and understanding (:func:`analyze`); files in
(:mod:`polhode.io`: meshes, URDF, MJCF, and their audit); see the README.
"""

from polhode import errors, io, plot, torque
from polhode.analysis import Analysis, analyze
from polhode.bodies import Body
from polhode.errors import (
    ArgumentError,
    ConvergenceError,
    FileFormatError,
    InertiaError,
    NonFiniteError,
    NonPositiveError,
    PolhodeError,
    ShapeError,
)
from polhode.perturbation import perturbation
from polhode.principal_axes import Principal, principal
from polhode.simulation import Trajectory, simulate

__all__ = [
    "Analysis",
    "ArgumentError",
    "Body",
    "ConvergenceError",
    "FileFormatError",
    "InertiaError",
    "NonFiniteError",
    "NonPositiveError",
    "PolhodeError",
    "ShapeError",
    "Principal",
    "Trajectory",
    "analyze",
    "errors",
    "io",
    "perturbation",
    "plot",
    "principal",
    "simulate",
    "torque",
]
__version__ = "0.1.0"

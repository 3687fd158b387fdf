"""polhode: the rotation of rigid bodies, with a Rust core.

Mass properties and principal axes (:class:`Body`, :func:`principal`), motion
(:func:`simulate`, :mod:`polhode.torque`, :mod:`polhode.rotors`) and understanding
(:func:`analyze`); see the README.
"""

from polhode import errors, plot, rotors, torque
from polhode.analysis import Analysis, analyze
from polhode.bodies import Body
from polhode.errors import (
    ArgumentError,
    ConvergenceError,
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
    "InertiaError",
    "NonFiniteError",
    "NonPositiveError",
    "PolhodeError",
    "ShapeError",
    "Principal",
    "Trajectory",
    "analyze",
    "errors",
    "perturbation",
    "plot",
    "principal",
    "rotors",
    "simulate",
    "torque",
]
__version__ = "0.1.0"

"""Plots of the motion (matplotlib, the ``plot`` extra).

Every function draws on an ``ax`` if given, otherwise on a new :class:`matplotlib.figure.Figure`
(never pyplot's global state, so it works headless), and returns the Axes. matplotlib is imported
inside the functions: ``import polhode`` never needs it.

Lines are tagged with ``Line2D.get_gid()`` so their data can be found again (the tests do):
``"omega1"``.., ``"drift:energy"``.., ``"polhode:<T>"``, ``"separatrix"``, ``"trajectory"``,
``"herpolhode"``, ``"work_precision:<name>"``, ``"perturbation_error:<order>"``,
``"slope:<order + 1>"``, ``"dissipation:<curve>"``.
"""


# Re-exported: the nine plots of __all__, and the curves, constants and helpers that were
# public names of polhode.plot before it was a package.
from polhode.plot._axes import AXIS_ROLES as AXIS_ROLES
from polhode.plot._axes import FLOOR as FLOOR
from polhode.plot.animation import AXIS_COLORS as AXIS_COLORS
from polhode.plot.animation import PART_COLORS as PART_COLORS
from polhode.plot.animation import animate
from polhode.plot.geometry import herpolhode, polhode
from polhode.plot.geometry import invariable_plane_basis as invariable_plane_basis
from polhode.plot.geometry import omega_space as omega_space
from polhode.plot.geometry import polhode_curves as polhode_curves
from polhode.plot.geometry import separatrix_curves as separatrix_curves
from polhode.plot.motion import DRIFT_CURVES as DRIFT_CURVES
from polhode.plot.motion import PERTURBATION_DIRECTION as PERTURBATION_DIRECTION
from polhode.plot.motion import SLOPE_OFFSET as SLOPE_OFFSET
from polhode.plot.motion import dissipation, drift, omega, perturbation_error, work_precision
from polhode.plot.motion import perturbation_errors as perturbation_errors
from polhode.plot.scene import scene

__all__ = [
    "animate",
    "dissipation",
    "drift",
    "herpolhode",
    "omega",
    "perturbation_error",
    "polhode",
    "scene",
    "work_precision",
]

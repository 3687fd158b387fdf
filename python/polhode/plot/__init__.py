"""Plots of the motion (matplotlib, the ``plot`` extra).

Every function draws on an ``ax`` if given (a 2-D Axes, or a 3-D one for :func:`polhode` and
:func:`animate`; anything else is a TypeError naming ``ax``), otherwise on a new
:class:`matplotlib.figure.Figure` (never pyplot's global state, so it works headless), and
returns the Axes. matplotlib is imported inside the functions: ``import polhode`` never needs
it. Bad input raises the typed errors of :mod:`polhode.errors` naming the argument, as the core
does; a body is taken wherever :func:`polhode.simulate` takes one (a Body, principal moments in
any order, an inertia tensor).

What the labels say:

- **units**: every plot takes ``units``, the base units of the motion,
  ``{"time": "s", "length": "m", "mass": "kg"}`` by default (SI); every axis label says its
  unit, derived from them (``t (s)``, ``omega (rad/s)``, ``L (kg m^2/s)``), or is a ratio;
- **axes**: the principal axes are numbered 1, 2, 3 with the moments ascending
  (I1 <= I2 <= I3) wherever a person reads them (omega_1, L_2, "I3 axis"); an argument that
  picks one (``axis=``, ``mark=``) is a Python index 0, 1, 2 into the ascending moments;
  coordinates in axes that are not principal are x, y, z (omega_x in body axes that are not
  principal).

Lines are tagged with ``Line2D.get_gid()`` so their data can be found again (the tests do):
``"omega[0]"``.. (the column of ``traj.omega``), ``"drift:energy"``.., ``"polhode:<T>"``,
``"separatrix"``, ``"trajectory"`` (with ``"trajectory:time"``, the segments coloured by
time, and ``"start"``, ``"end"``), ``"herpolhode"``, ``"work_precision:<name>"``,
``"perturbation_error:<order>"``, ``"slope:<order + 1>"``, ``"dissipation:<curve>"``;
:func:`animate`'s ``"axis1"``.. ``"axis3"``, ``"omega"``, ``"angular_momentum"``, ``"mark"``.
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

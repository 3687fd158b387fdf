"""polhode.plot's bad input, probed function by function: every public plot and helper with
wrong types, non-finite, negative and zero numbers, wrong shapes, a batch trajectory, a
trajectory without the orientation it needs, one at rest, and matplotlib Axes of the wrong
kind; and the inputs it must take wherever ``simulate`` does (a Body, moments in any order, a
tensor).

Each row is one call and what it must give:

- ``Raises(error, argument)``: exactly that class; a PolhodeError whose ``argument`` is that
  argument, a TypeError whose message names it in backticks;
- ``Draws(check)``: a result, on which ``check`` must hold (a figure's lines, against values
  computed here).

``python tests/test_plot_errors.py`` prints the totals by outcome: **ok** (as the row says),
**minor** (a typed error naming the wrong argument or none, a plain ValueError that is not a
PolhodeError, a typed refusal of what must be taken), **unacceptable** (an untyped error from
inside: AttributeError, IndexError, a numpy error or warning; a crash; silent acceptance of
nonsense). Rows marked ``new`` use arguments the plots did not have before (``units``,
``mark``): they are left out of a count on the old code.
"""

from __future__ import annotations

import collections
import math
import tempfile
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import pytest

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")

from matplotlib.figure import Figure  # noqa: E402

import polhode as ph  # noqa: E402
from polhode import plot  # noqa: E402

NAN, INF = math.nan, math.inf


@dataclass(frozen=True)
class Raises:
    error: type[BaseException]
    argument: str


@dataclass(frozen=True)
class Draws:
    check: Callable[[Any], None]


@dataclass(frozen=True)
class Row:
    id: str
    call: Callable[[], Any]
    expect: Raises | Draws
    new: bool = False


ROWS: list[Row] = []


def err(id_, call, error, argument, new=False):
    ROWS.append(Row(id_, call, Raises(error, argument), new))


def ok(id_, call, check, new=False):
    ROWS.append(Row(id_, call, Draws(check), new))


# ---------------------------------------------------------------------------------------------
# Inputs (built once, lazily: a row's call builds what it needs)
# ---------------------------------------------------------------------------------------------

_cache: dict[str, Any] = {}


def cached(name: str, make: Callable[[], Any]) -> Any:
    if name not in _cache:
        _cache[name] = make()
    return _cache[name]


MOMENTS = [1.0, 2.0, 3.0]
OMEGA0 = [0.1, 1.0, 0.2]
TIMES = np.linspace(0.0, 10.0, 201)


def traj():
    return cached("traj", lambda: ph.simulate(MOMENTS, OMEGA0, TIMES))


def batch():
    return cached("batch", lambda: ph.simulate(MOMENTS, [OMEGA0, OMEGA0], TIMES))


def bare():
    return cached("bare", lambda: ph.simulate(MOMENTS, OMEGA0, TIMES, orientation=False))


def rest():
    return cached("rest", lambda: ph.simulate(MOMENTS, [0.0, 0.0, 0.0], TIMES))


def bar():
    return cached("bar", lambda: ph.Body.cuboid(1.0, [0.3, 0.1, 0.02]))


def bar_traj():
    return cached("bar_traj", lambda: ph.simulate(bar(), [0.05, 5.0, 0.05], TIMES[:41] / 2.5))


def tensor():
    from scipy.spatial.transform import Rotation

    r = Rotation.from_rotvec([0.3, -0.5, 0.2]).as_matrix()
    return r @ np.diag(MOMENTS) @ r.T


def tensor_traj():
    return cached("tensor_traj", lambda: ph.simulate(tensor(), OMEGA0, TIMES))


def damped():
    damper = ph.rotors.SphericalDamper(0.2, 0.1)
    return cached(
        "damped",
        lambda: ph.simulate([1.0, 4.0, 5.0], [2.0, 0.01, 0.01], np.linspace(0, 100, 401),
                            rotors=[damper]),
    )


def ax2d():
    return Figure().add_subplot()


def ax3d():
    import mpl_toolkits.mplot3d  # noqa: F401

    return Figure().add_subplot(projection="3d")


def polar():
    return Figure().add_subplot(projection="polar")


def gif():
    return tempfile.mkdtemp(prefix="polhode-plot-errors-") + "/anim.gif"


def drawn(result):
    """Something was drawn: an Axes with lines, or an animation (rendered)."""
    if hasattr(result, "to_jshtml"):
        assert "data:image/png;base64" in result.to_jshtml()
    if hasattr(result, "get_lines"):
        assert result.get_lines() or result.collections, "nothing drawn"
        for line in result.get_lines():
            data = np.asarray(line.get_xydata() if not hasattr(line, "get_data_3d")
                              else np.column_stack(line.get_data_3d()), dtype=float)
            assert np.all(np.isfinite(data)), line.get_gid()


def lines(ax, prefix):
    return [line for line in ax.get_lines() if str(line.get_gid()).startswith(prefix)]


def same_polhode_as_moments(moments):
    """The curves drawn are those of plot.polhode(sorted moments)."""

    def check(ax):
        reference = plot.polhode(sorted(moments))
        got = [np.column_stack(x.get_data_3d()) for x in lines(ax, "polhode:")]
        want = [np.column_stack(x.get_data_3d()) for x in lines(reference, "polhode:")]
        assert len(got) == len(want) == 16
        for a, b in zip(got, want, strict=True):
            np.testing.assert_allclose(a, b, rtol=1e-9, atol=1e-12)

    return check


def trajectory_in_principal_axes(traj_of, inertia_of):
    """The trajectory drawn on the polhode is L in the principal axes (moments ascending):
    on the sphere |L| and on the energy ellipsoid of the ascending moments."""

    def check(ax):
        (line,) = lines(ax, "trajectory")
        points = np.column_stack(line.get_data_3d())
        moments = np.linalg.eigvalsh(inertia_of())
        t = traj_of()
        ell = np.linalg.norm(t.angular_momentum_body[0])
        np.testing.assert_allclose(np.linalg.norm(points, axis=1), ell, rtol=1e-9)
        np.testing.assert_allclose(
            np.sum(points**2 / moments, axis=1), 2 * t.energy[0], rtol=1e-9
        )

    return check


# ---------------------------------------------------------------------------------------------
# The rows
# ---------------------------------------------------------------------------------------------

# The trajectory argument of every plot that takes one: type, batch, orientation, rest.
TRAJECTORY_PLOTS = {
    "omega": lambda t: plot.omega(t),
    "drift": lambda t: plot.drift(t),
    "dissipation": lambda t: plot.dissipation(t),
    "herpolhode": lambda t: plot.herpolhode(t),
    "omega_space": lambda t: plot.omega_space(t),
    "polhode": lambda t: plot.polhode(traj=t),
    "animate": lambda t: plot.animate(t, bar()),
}
for _name, _call in TRAJECTORY_PLOTS.items():
    _arg = "traj"
    err(f"{_name}/traj='x'", lambda c=_call: c("x"), TypeError, _arg)
    err(f"{_name}/traj=3", lambda c=_call: c(3), TypeError, _arg)
    err(f"{_name}/traj=a batch", lambda c=_call: c(batch()), ph.ShapeError, _arg)
for _name in ("herpolhode", "omega_space", "animate"):
    err(f"{_name}/traj without orientation", lambda c=TRAJECTORY_PLOTS[_name]: c(bare()),
        ph.ArgumentError, "traj")
for _name in ("dissipation", "herpolhode", "polhode"):
    err(f"{_name}/traj at rest", lambda c=TRAJECTORY_PLOTS[_name]: c(rest()),
        ph.ArgumentError, "traj")
err("polhode/traj=None and no body", lambda: plot.polhode(), TypeError, "body")

# ax: not an Axes, or of the wrong kind (3-D for a 2-D plot, 2-D for a 3-D one, polar).
TWO_D = {
    "omega": lambda ax: plot.omega(traj(), ax=ax),
    "drift": lambda ax: plot.drift(traj(), ax=ax),
    "dissipation": lambda ax: plot.dissipation(damped(), ax=ax),
    "herpolhode": lambda ax: plot.herpolhode(traj(), ax=ax),
    "work_precision": lambda ax: plot.work_precision({"rk4": ([1.0, 2.0], [1e-3, 1e-6])}, ax=ax),
    "perturbation_error": lambda ax: plot.perturbation_error(MOMENTS, eps=[1e-3, 1e-2], ax=ax),
}
for _name, _call in TWO_D.items():
    err(f"{_name}/ax='x'", lambda c=_call: c("x"), TypeError, "ax")
    err(f"{_name}/ax=a 3-D Axes", lambda c=_call: c(ax3d()), TypeError, "ax")
    err(f"{_name}/ax=a polar Axes", lambda c=_call: c(polar()), TypeError, "ax")
    ok(f"{_name}/ax=a 2-D Axes", lambda c=_call: c(ax2d()), drawn)
THREE_D = {
    "polhode": lambda ax: plot.polhode(MOMENTS, ax=ax),
    "animate": lambda ax: plot.animate(bar_traj(), bar(), frames=2, ax=ax),
}
for _name, _call in THREE_D.items():
    err(f"{_name}/ax='x'", lambda c=_call: c("x"), TypeError, "ax")
    err(f"{_name}/ax=a 2-D Axes", lambda c=_call: c(ax2d()), TypeError, "ax")
    ok(f"{_name}/ax=a 3-D Axes", lambda c=_call: c(ax3d()), drawn)

# units, the same in every plot (new: only plot.scene had it).
UNIT_PLOTS = {
    "omega": lambda u: plot.omega(traj(), units=u),
    "drift": lambda u: plot.drift(traj(), units=u),
    "dissipation": lambda u: plot.dissipation(damped(), units=u),
    "herpolhode": lambda u: plot.herpolhode(traj(), units=u),
    "work_precision": lambda u: plot.work_precision({"a": ([1.0], [1e-3])}, units=u),
    "perturbation_error": lambda u: plot.perturbation_error(MOMENTS, eps=[1e-3], units=u),
    "polhode": lambda u: plot.polhode(MOMENTS, units=u),
    "animate": lambda u: plot.animate(bar_traj(), bar(), frames=2, units=u),
}
for _name, _call in UNIT_PLOTS.items():
    err(f"{_name}/units='SI'", lambda c=_call: c("SI"), TypeError, "units", new=True)
    err(f"{_name}/units={{'angle': 'deg'}}", lambda c=_call: c({"angle": "deg"}),
        ph.ArgumentError, "units", new=True)
    err(f"{_name}/units={{'time': ''}}", lambda c=_call: c({"time": ""}), ph.ArgumentError,
        "units", new=True)
    err(f"{_name}/units={{'time': 3}}", lambda c=_call: c({"time": 3}), TypeError, "units",
        new=True)
    ok(f"{_name}/units={{'time': 'min'}}", lambda c=_call: c({"time": "min"}), drawn, new=True)

# floor of the log axes.
FLOOR_PLOTS = {
    "drift": lambda f: plot.drift(traj(), floor=f),
    "work_precision": lambda f: plot.work_precision({"a": ([1.0], [0.0])}, floor=f),
    "perturbation_error": lambda f: plot.perturbation_error(MOMENTS, eps=[1e-3], floor=f),
}
for _name, _call in FLOOR_PLOTS.items():
    err(f"{_name}/floor=-1", lambda c=_call: c(-1.0), ph.NonPositiveError, "floor")
    err(f"{_name}/floor=0", lambda c=_call: c(0.0), ph.NonPositiveError, "floor")
    err(f"{_name}/floor=nan", lambda c=_call: c(NAN), ph.NonFiniteError, "floor")
    err(f"{_name}/floor=inf", lambda c=_call: c(INF), ph.NonFiniteError, "floor")
    err(f"{_name}/floor='x'", lambda c=_call: c("x"), TypeError, "floor")

# work_precision's results.
WP = plot.work_precision
err("work_precision/results=[1, 2]", lambda: WP([1, 2]), TypeError, "results")
err("work_precision/results='x'", lambda: WP("x"), TypeError, "results")
err("work_precision/results=None", lambda: WP(None), TypeError, "results")
err("work_precision/results={}", lambda: WP({}), ph.ArgumentError, "results")
err("work_precision/a value not a pair", lambda: WP({"a": 5}), TypeError, "results")
err("work_precision/a triple", lambda: WP({"a": ([1], [1], [1])}), TypeError, "results")
err("work_precision/strings", lambda: WP({"a": (["x"], [1e-3])}), TypeError, "results")
err("work_precision/lengths differ", lambda: WP({"a": ([1.0, 2.0], [1e-3])}), ph.ShapeError,
    "results")
err("work_precision/2-D", lambda: WP({"a": ([[1.0]], [[1e-3]])}), ph.ShapeError, "results")
err("work_precision/no points", lambda: WP({"a": ([], [])}), ph.ShapeError, "results")
err("work_precision/negative time", lambda: WP({"a": ([-1.0, 2.0], [1e-3, 1e-4])}),
    ph.NonPositiveError, "results")
err("work_precision/zero time", lambda: WP({"a": ([0.0, 2.0], [1e-3, 1e-4])}),
    ph.NonPositiveError, "results")
err("work_precision/nan time", lambda: WP({"a": ([NAN, 2.0], [1e-3, 1e-4])}),
    ph.NonFiniteError, "results")
err("work_precision/negative error", lambda: WP({"a": ([1.0, 2.0], [-1e-3, 1e-4])}),
    ph.ArgumentError, "results")
err("work_precision/nan error", lambda: WP({"a": ([1.0, 2.0], [NAN, 1e-4])}),
    ph.NonFiniteError, "results")
ok("work_precision/an exact zero at the floor",
   lambda: WP({"exact": ([1e-4], [0.0])}),
   lambda ax: np.testing.assert_array_equal(ax.get_lines()[0].get_ydata(), [plot.FLOOR]))

# perturbation_error (and perturbation_errors, its numbers).
PE = plot.perturbation_error
PES = plot.perturbation_errors
err("perturbation_error/body='x'", lambda: PE("x"), TypeError, "body")
err("perturbation_error/body=[1, 2]", lambda: PE([1.0, 2.0]), ph.ShapeError, "body")
err("perturbation_error/body=[1, 2, -3]", lambda: PE([1.0, 2.0, -3.0]), ph.NonPositiveError,
    "body")
err("perturbation_error/body=[1, 2, nan]", lambda: PE([1.0, 2.0, NAN]), ph.NonFiniteError,
    "body")
err("perturbation_error/body=(2, 2, 3)", lambda: PE(np.ones((2, 2, 3))), ph.ShapeError, "body")
ok("perturbation_error/body=a Body", lambda: PE(bar(), axis=0, eps=[1e-3, 1e-2]),
   lambda ax: np.testing.assert_allclose(
       lines(ax, "perturbation_error:1")[0].get_ydata(),
       PES(np.linalg.eigvalsh(bar().inertia), 0, [1e-3, 1e-2], (1,))[1], rtol=1e-9))
ok("perturbation_error/body=a tensor", lambda: PE(tensor(), axis=0, eps=[1e-3, 1e-2]),
   lambda ax: np.testing.assert_allclose(
       lines(ax, "perturbation_error:1")[0].get_ydata(),
       PES(MOMENTS, 0, [1e-3, 1e-2], (1,))[1], rtol=1e-6))
err("perturbation_error/axis=3", lambda: PE(MOMENTS, axis=3), ph.ArgumentError, "axis")
err("perturbation_error/axis=-1", lambda: PE(MOMENTS, axis=-1), ph.ArgumentError, "axis")
err("perturbation_error/axis=1.5", lambda: PE(MOMENTS, axis=1.5), TypeError, "axis")
err("perturbation_error/axis=True", lambda: PE(MOMENTS, axis=True), TypeError, "axis")
err("perturbation_error/eps=[0.9]", lambda: PE(MOMENTS, eps=[0.9]), ph.ArgumentError, "eps")
err("perturbation_error/eps=[]", lambda: PE(MOMENTS, eps=[]), ph.ShapeError, "eps")
err("perturbation_error/eps=[[1e-3]]", lambda: PE(MOMENTS, eps=[[1e-3]]), ph.ShapeError, "eps")
err("perturbation_error/eps=1e-3", lambda: PE(MOMENTS, eps=1e-3), ph.ShapeError, "eps")
err("perturbation_error/eps=[0]", lambda: PE(MOMENTS, eps=[0.0]), ph.NonPositiveError, "eps")
err("perturbation_error/eps=[-1e-3]", lambda: PE(MOMENTS, eps=[-1e-3]), ph.NonPositiveError,
    "eps")
err("perturbation_error/eps=[nan]", lambda: PE(MOMENTS, eps=[NAN]), ph.NonFiniteError, "eps")
err("perturbation_error/eps='x'", lambda: PE(MOMENTS, eps="x"), TypeError, "eps")
err("perturbation_error/orders=[3]", lambda: PE(MOMENTS, orders=[3]), ph.ArgumentError,
    "orders")
err("perturbation_error/orders=[]", lambda: PE(MOMENTS, orders=[]), ph.ArgumentError, "orders")
err("perturbation_error/orders=[1.5]", lambda: PE(MOMENTS, orders=[1.5]), TypeError, "orders")
err("perturbation_error/orders=2", lambda: PE(MOMENTS, orders=2), TypeError, "orders")
err("perturbation_error/orders='12'", lambda: PE(MOMENTS, orders="12"), TypeError, "orders")
err("perturbation_error/t=-1", lambda: PE(MOMENTS, t=-1.0), ph.NonPositiveError, "t")
err("perturbation_error/t=0", lambda: PE(MOMENTS, t=0.0), ph.NonPositiveError, "t")
err("perturbation_error/t=nan", lambda: PE(MOMENTS, t=NAN), ph.NonFiniteError, "t")
err("perturbation_error/t=[0, nan]", lambda: PE(MOMENTS, t=[0.0, NAN]), ph.NonFiniteError, "t")
err("perturbation_error/t='x'", lambda: PE(MOMENTS, t="x"), TypeError, "t")
err("perturbation_error/t=[[1]]", lambda: PE(MOMENTS, t=[[1.0]]), ph.ShapeError, "t")
err("perturbation_error/t beyond the growth", lambda: PE(MOMENTS, axis=1, t=100.0),
    ph.ArgumentError, "t")
err("perturbation_error/spin=0", lambda: PE(MOMENTS, spin=0.0), ph.ArgumentError, "spin")
err("perturbation_error/spin=nan", lambda: PE(MOMENTS, spin=NAN), ph.NonFiniteError, "spin")
err("perturbation_error/spin='x'", lambda: PE(MOMENTS, spin="x"), TypeError, "spin")
err("perturbation_error/direction=[0, 0, 0]", lambda: PE(MOMENTS, direction=[0.0, 0.0, 0.0]),
    ph.ArgumentError, "direction")
err("perturbation_error/direction along the axis",
    lambda: PE(MOMENTS, axis=2, direction=[0.0, 0.0, 1.0]), ph.ArgumentError, "direction")
err("perturbation_error/direction=[1, 2]", lambda: PE(MOMENTS, direction=[1.0, 2.0]),
    ph.ShapeError, "direction")
err("perturbation_error/direction=[nan, 0, 1]", lambda: PE(MOMENTS, direction=[NAN, 0.0, 1.0]),
    ph.NonFiniteError, "direction")
err("perturbation_error/direction='x'", lambda: PE(MOMENTS, direction="x"), TypeError,
    "direction")
err("perturbation_errors/axis=3", lambda: PES(MOMENTS, 3, [1e-3]), ph.ArgumentError, "axis")
err("perturbation_errors/eps=[0.9]", lambda: PES(MOMENTS, 0, [0.9]), ph.ArgumentError, "eps")
err("perturbation_errors/orders=[3]", lambda: PES(MOMENTS, 0, [1e-3], [3]), ph.ArgumentError,
    "orders")
ok("perturbation_errors/body=Body.sphere (exact: a steady rotation)",
   lambda: PES(ph.Body.sphere(1.0, 0.1), 0, [1e-3, 1e-2]),
   lambda errors: np.testing.assert_array_less(np.concatenate(list(errors.values())), 1e-15))

# polhode: the body, |L|, the energies, the points, the trajectory.
PO = plot.polhode
err("polhode/body='x'", lambda: PO("x"), TypeError, "body")
err("polhode/body=[1, 2]", lambda: PO([1.0, 2.0]), ph.ShapeError, "body")
err("polhode/body=[1, 2, -3]", lambda: PO([1.0, 2.0, -3.0]), ph.NonPositiveError, "body")
err("polhode/body=[1, 2, nan]", lambda: PO([1.0, 2.0, NAN]), ph.NonFiniteError, "body")
err("polhode/body=[2, 2, 2] (no polhode)", lambda: PO([2.0, 2.0, 2.0]), ph.ArgumentError, "body")
ok("polhode/body=[3, 2, 1] (any order)", lambda: PO([3.0, 2.0, 1.0]),
   same_polhode_as_moments([3.0, 2.0, 1.0]))
ok("polhode/body=a Body", lambda: PO(bar()),
   same_polhode_as_moments(np.linalg.eigvalsh(ph.Body.cuboid(1.0, [0.3, 0.1, 0.02]).inertia)))
ok("polhode/body=a tensor", lambda: PO(tensor()), same_polhode_as_moments(MOMENTS))
ok("polhode/body=a Body, traj=its trajectory", lambda: PO(bar(), traj=bar_traj()),
   trajectory_in_principal_axes(bar_traj, lambda: bar().inertia))
ok("polhode/traj=a tensor's trajectory", lambda: PO(traj=tensor_traj()),
   trajectory_in_principal_axes(tensor_traj, tensor))
ok("polhode/body=a tensor, traj=its trajectory", lambda: PO(tensor(), traj=tensor_traj()),
   trajectory_in_principal_axes(tensor_traj, tensor))
err("polhode/body and traj disagree", lambda: PO([1.0, 2.0, 4.0], traj=traj()),
    ph.ArgumentError, "body")
err("polhode/|L|=-1", lambda: PO(MOMENTS, -1.0), ph.NonPositiveError, "angular_momentum_norm")
err("polhode/|L|=0", lambda: PO(MOMENTS, 0.0), ph.NonPositiveError, "angular_momentum_norm")
err("polhode/|L|=nan", lambda: PO(MOMENTS, NAN), ph.NonFiniteError, "angular_momentum_norm")
err("polhode/|L|='x'", lambda: PO(MOMENTS, "x"), TypeError, "angular_momentum_norm")
err("polhode/energies=[100]", lambda: PO(MOMENTS, 1.0, [100.0]), ph.ArgumentError, "energies")
err("polhode/energies=[-1]", lambda: PO(MOMENTS, 1.0, [-1.0]), ph.ArgumentError, "energies")
err("polhode/energies=[nan]", lambda: PO(MOMENTS, 1.0, [NAN]), ph.NonFiniteError, "energies")
err("polhode/energies='x'", lambda: PO(MOMENTS, 1.0, "x"), TypeError, "energies")
err("polhode/energies=[[0.3]]", lambda: PO(MOMENTS, 1.0, [[0.3]]), ph.ShapeError, "energies")
err("polhode/n=-5", lambda: PO(MOMENTS, n=-5), ph.ArgumentError, "n")
err("polhode/n=1", lambda: PO(MOMENTS, n=1), ph.ArgumentError, "n")
err("polhode/n=2.5", lambda: PO(MOMENTS, n=2.5), TypeError, "n")
err("polhode/n=True", lambda: PO(MOMENTS, n=True), TypeError, "n")
err("polhode/sphere='no'", lambda: PO(MOMENTS, sphere="no"), TypeError, "sphere")

# The curves' helpers (public names of polhode.plot).
PC = plot.polhode_curves
SC = plot.separatrix_curves
err("polhode_curves/moments='x'", lambda: PC("x", 1.0, 0.3), TypeError, "moments")
err("polhode_curves/moments=[1, 2]", lambda: PC([1.0, 2.0], 1.0, 0.3), ph.ShapeError, "moments")
err("polhode_curves/moments=[1, 2, -3]", lambda: PC([1.0, 2.0, -3.0], 1.0, 0.3),
    ph.NonPositiveError, "moments")
err("polhode_curves/moments=[3, 2, 1]", lambda: PC([3.0, 2.0, 1.0], 1.0, 0.3),
    ph.ArgumentError, "moments")
err("polhode_curves/|L|=-1", lambda: PC(MOMENTS, -1.0, 0.3), ph.NonPositiveError,
    "angular_momentum_norm")
err("polhode_curves/energy=100", lambda: PC(MOMENTS, 1.0, 100.0), ph.ArgumentError, "energy")
err("polhode_curves/energy=nan", lambda: PC(MOMENTS, 1.0, NAN), ph.NonFiniteError, "energy")
err("polhode_curves/energy='x'", lambda: PC(MOMENTS, 1.0, "x"), TypeError, "energy")
err("polhode_curves/n=-5", lambda: PC(MOMENTS, 1.0, 0.3, n=-5), ph.ArgumentError, "n")
err("polhode_curves/n=2.5", lambda: PC(MOMENTS, 1.0, 0.3, n=2.5), TypeError, "n")
err("separatrix_curves/moments=[1, 2]", lambda: SC([1.0, 2.0], 1.0), ph.ShapeError, "moments")
err("separatrix_curves/moments=[3, 2, 1]", lambda: SC([3.0, 2.0, 1.0], 1.0), ph.ArgumentError,
    "moments")
err("separatrix_curves/|L|=nan", lambda: SC(MOMENTS, NAN), ph.NonFiniteError,
    "angular_momentum_norm")
err("separatrix_curves/n=0", lambda: SC(MOMENTS, 1.0, n=0), ph.ArgumentError, "n")
IPB = plot.invariable_plane_basis
err("invariable_plane_basis/L=[0, 0, 0]", lambda: IPB([0.0, 0.0, 0.0]), ph.ArgumentError,
    "angular_momentum")
err("invariable_plane_basis/L=[1, 2]", lambda: IPB([1.0, 2.0]), ph.ShapeError,
    "angular_momentum")
err("invariable_plane_basis/L=[nan, 0, 1]", lambda: IPB([NAN, 0.0, 1.0]), ph.NonFiniteError,
    "angular_momentum")
err("invariable_plane_basis/L='x'", lambda: IPB("x"), TypeError, "angular_momentum")
err("invariable_plane_basis/hint=[1, 2]", lambda: IPB([0.0, 0.0, 1.0], [1.0, 2.0]),
    ph.ShapeError, "hint")
err("invariable_plane_basis/hint=[nan, 0, 0]", lambda: IPB([0.0, 0.0, 1.0], [NAN, 0.0, 0.0]),
    ph.NonFiniteError, "hint")
ok("invariable_plane_basis/hint along L (another e1)", lambda: IPB([0.0, 0.0, 2.0], [0, 0, 1]),
   lambda basis: np.testing.assert_allclose(basis @ basis.T, np.eye(3), atol=1e-15))

# animate: every option.
AN = plot.animate


def an(**options):
    options.setdefault("frames", 2)
    return lambda: AN(bar_traj(), bar(), **options)


err("animate/body='x'", lambda: AN(bar_traj(), "x"), TypeError, "body")
err("animate/body=other moments", lambda: AN(bar_traj(), [1.0, 2.0, 3.0]), ph.ArgumentError,
    "body")
err("animate/body=[1, 2]", lambda: AN(bar_traj(), [1.0, 2.0]), ph.ShapeError, "body")
err("animate/origin with moments", lambda: AN(bar_traj(), np.diag(bar().inertia),
                                              origin=[0.0, 0.0, 0.1]), ph.ArgumentError, "origin")
ok("animate/body=its principal moments", lambda: AN(bar_traj(), np.diag(bar().inertia),
                                                     frames=2), drawn)
ok("animate/body=None (the trajectory's)", lambda: AN(bar_traj(), frames=2), drawn)
err("animate/body of other moments", lambda: AN(bar_traj(), ph.Body.cuboid(1.0, [0.3, 0.1, 0.1])),
    ph.ArgumentError, "body")
err("animate/frames=0", an(frames=0), ph.ArgumentError, "frames")
err("animate/frames=-1", an(frames=-1), ph.ArgumentError, "frames")
err("animate/frames=2.5", an(frames=2.5), TypeError, "frames")
err("animate/frames='x'", an(frames="x"), TypeError, "frames")
err("animate/frames=[]", an(frames=[]), ph.ArgumentError, "frames")
err("animate/frames=[0.5]", an(frames=[0.5]), TypeError, "frames")
err("animate/frames=[0, 1000]", an(frames=[0, 1000]), ph.ArgumentError, "frames")
err("animate/origin=[1, 2]", an(origin=[1.0, 2.0]), ph.ShapeError, "origin")
err("animate/origin=[nan, 0, 0]", an(origin=[NAN, 0.0, 0.0]), ph.NonFiniteError, "origin")
err("animate/interval=-1", an(interval=-1.0), ph.NonPositiveError, "interval")
err("animate/interval=0", an(interval=0.0), ph.NonPositiveError, "interval")
err("animate/interval=nan", an(interval=NAN), ph.NonFiniteError, "interval")
err("animate/interval='x'", an(interval="x"), TypeError, "interval")
err("animate/resolution=0", an(resolution=0), ph.ArgumentError, "resolution")
err("animate/resolution=-3", an(resolution=-3), ph.ArgumentError, "resolution")
err("animate/resolution=2.5", an(resolution=2.5), TypeError, "resolution")
err("animate/path=5", an(path=5), TypeError, "path")
err("animate/path=x.txt", lambda: AN(bar_traj(), bar(), frames=2, path=gif()[:-3] + "txt"),
    ph.ArgumentError, "path")
err("animate/dpi=0", lambda: AN(bar_traj(), bar(), frames=2, path=gif(), dpi=0),
    ph.NonPositiveError, "dpi")
err("animate/dpi=-1", lambda: AN(bar_traj(), bar(), frames=2, path=gif(), dpi=-1.0),
    ph.NonPositiveError, "dpi")
err("animate/dpi=nan", lambda: AN(bar_traj(), bar(), frames=2, path=gif(), dpi=NAN),
    ph.NonFiniteError, "dpi")
err("animate/dpi='x'", lambda: AN(bar_traj(), bar(), frames=2, path=gif(), dpi="x"),
    TypeError, "dpi")
err("animate/space_axes='yes'", an(space_axes="yes"), TypeError, "space_axes")
err("animate/mark=3", an(mark=3), ph.ArgumentError, "mark", new=True)
err("animate/mark=1.5", an(mark=1.5), TypeError, "mark", new=True)
ok("animate/a trajectory at rest", lambda: AN(ph.simulate(bar(), [0.0, 0.0, 0.0], TIMES[:5]),
                                                bar(), frames=2), drawn)

# scene: the same discipline (its own tests hold the rest, tests/test_scene.py).
SCENE = plot.scene
err("scene/trajectory='x'", lambda: SCENE("x"), TypeError, "trajectory")
err("scene/trajectory=a batch", lambda: SCENE(batch()), ph.ShapeError, "trajectory")
err("scene/no orientation", lambda: SCENE(bare()), ph.ArgumentError, "trajectory")
err("scene/frames=0", lambda: SCENE(bar_traj(), bar(), frames=0), ph.ArgumentError, "frames")
err("scene/frames=[0.5]", lambda: SCENE(bar_traj(), bar(), frames=[0.5]), TypeError, "frames")
err("scene/resolution=0", lambda: SCENE(bar_traj(), bar(), resolution=0), ph.ArgumentError,
    "resolution")
err("scene/max_vertices=2.5", lambda: SCENE(bar_traj(), bar(), max_vertices=2.5), TypeError,
    "max_vertices")
err("scene/frame_duration=nan", lambda: SCENE(bar_traj(), bar(), frame_duration=NAN),
    ph.NonFiniteError, "frame_duration")
err("scene/units={'time': 3}", lambda: SCENE(bar_traj(), bar(), units={"time": 3}), TypeError,
    "units")
err("scene/body='x'", lambda: SCENE(bar_traj(), "x"), TypeError, "body")
err("scene/body=other moments", lambda: SCENE(bar_traj(), [1.0, 2.0, 3.0]), ph.ArgumentError,
    "body")
ok("scene/body=its principal moments", lambda: SCENE(bar_traj(), np.diag(bar().inertia),
                                                      frames=2), lambda fig: None)
err("scene/path=5", lambda: SCENE(bar_traj(), bar(), frames=2, path=5), TypeError, "path")


# ---------------------------------------------------------------------------------------------
# A second probe: every public function, every argument, with wrong
# types, masked values, numbers beyond double precision and out of range.
# ---------------------------------------------------------------------------------------------

BIG = 2**2000  # beyond double precision: float(BIG) raises OverflowError
def masked(values, mask):
    return np.ma.array(np.asarray(values), mask=mask)


def ball():
    """A body with a round part, whose surface depends on the resolution."""
    return cached("ball", lambda: ph.Body.sphere(1.0, 0.1))


def ball_traj():
    return cached("ball_traj", lambda: ph.simulate(ball(), [0.0, 0.0, 1.0], TIMES[:41]))


def folder():
    return tempfile.mkdtemp(prefix="polhode-plot-errors-")


def frames_drawn(indices):
    """The output times of the frames (an animation's or a scene's), and the frames drawn (an
    animation never rendered warns when it is collected, in whatever test runs then)."""

    def check(result):
        is_animation = hasattr(result, "frame_indices")
        got = result.frame_indices if is_animation else result.layout.meta["frame_indices"]
        np.testing.assert_array_equal(got, indices)
        drawn(result)

    return check


# The trajectory argument: a Body or None where a trajectory is expected.
for _name, _call in TRAJECTORY_PLOTS.items():
    err(f"{_name}/traj=None", lambda c=_call: c(None), TypeError, "traj")
    err(f"{_name}/traj=a Body", lambda c=_call: c(bar()), TypeError, "traj")
# The floor: masked, beyond double precision.
for _name, _call in FLOOR_PLOTS.items():
    err(f"{_name}/floor=np.ma.masked", lambda c=_call: c(np.ma.masked), ph.ArgumentError,
        "floor")
    err(f"{_name}/floor=2**2000", lambda c=_call: c(BIG), ph.NonFiniteError, "floor")

# polhode: a masked body (its masked entries are no data), the number of points, |L| whose
# energies are beyond double precision, trajectories at the ends of double precision.
err("polhode/body masked", lambda: PO(masked(MOMENTS, [0, 1, 0])), ph.ArgumentError, "body")
ok("polhode/body masked, nothing masked", lambda: PO(masked([3.0, 2.0, 1.0], [0, 0, 0])),
   same_polhode_as_moments([3.0, 2.0, 1.0]))
err("polhode/body='abc'", lambda: PO("abc"), TypeError, "body")
err("polhode/n=10**9", lambda: PO(MOMENTS, n=10**9), ph.ArgumentError, "n")
err("polhode/n=2**62", lambda: PO(MOMENTS, n=2**62), ph.ArgumentError, "n")
ok("polhode/n=np.array(400)", lambda: PO(MOMENTS, n=np.array(400)),
   same_polhode_as_moments(MOMENTS))
err("polhode/|L|=2**2000", lambda: PO(MOMENTS, BIG), ph.NonFiniteError,
    "angular_momentum_norm")
err("polhode/|L| masked", lambda: PO(MOMENTS, np.ma.masked), ph.ArgumentError,
    "angular_momentum_norm")
err("polhode/energies masked", lambda: PO(MOMENTS, 1.0, masked([0.3, 0.4], [0, 1])),
    ph.ArgumentError, "energies")
err("polhode/energies=[2**2000]", lambda: PO(MOMENTS, 1.0, [BIG]), ph.NonFiniteError,
    "energies")
err("polhode_curves/n=10**9", lambda: PC(MOMENTS, 1.0, 0.3, n=10**9), ph.ArgumentError, "n")
err("polhode_curves/moments masked", lambda: PC(masked(MOMENTS, [1, 0, 0]), 1.0, 0.3),
    ph.ArgumentError, "moments")
err("separatrix_curves/n=10**9", lambda: SC(MOMENTS, 1.0, n=10**9), ph.ArgumentError, "n")
err("invariable_plane_basis/hint masked",
    lambda: IPB([0.0, 0.0, 1.0], masked([1, 0, 0], [1, 0, 0])), ph.ArgumentError, "hint")

# work_precision: a series' masked or overflowing values name `results`.
err("work_precision/times masked", lambda: WP({"a": (masked([1.0, 2.0], [0, 1]), [1e-3, 1e-6])}),
    ph.ArgumentError, "results")
err("work_precision/errors masked", lambda: WP({"a": ([1.0, 2.0], masked([1e-3, 0.0], [1, 0]))}),
    ph.ArgumentError, "results")
err("work_precision/times 2**2000", lambda: WP({"a": ([1.0, BIG], [1e-3, 1e-6])}),
    ph.NonFiniteError, "results")
err("work_precision/errors 2**2000", lambda: WP({"a": ([1.0, 2.0], [BIG, 1e-6])}),
    ph.NonFiniteError, "results")

# perturbation_error(s): no times, masked and overflowing values, a spin whose motion
# overflows (the spin's fault, not eps'), a direction beyond double precision.
err("perturbation_error/t=[]", lambda: PE(MOMENTS, eps=[1e-3], t=[]), ph.ShapeError, "t")
err("perturbation_errors/t=[]", lambda: PES(MOMENTS, 0, [1e-3], t=[]), ph.ShapeError, "t")
err("perturbation_error/t=2**2000", lambda: PE(MOMENTS, eps=[1e-3], t=BIG), ph.NonFiniteError,
    "t")
err("perturbation_error/t masked", lambda: PE(MOMENTS, eps=[1e-3], t=masked([0.0, 1.0], [0, 1])),
    ph.ArgumentError, "t")
err("perturbation_error/eps masked", lambda: PE(MOMENTS, eps=masked([1e-3, 1e-2], [0, 1])),
    ph.ArgumentError, "eps")
err("perturbation_error/spin masked", lambda: PE(MOMENTS, eps=[1e-3], spin=np.ma.masked),
    ph.ArgumentError, "spin")
err("perturbation_error/spin=1e300", lambda: PE(MOMENTS, eps=[1e-3], spin=1e300),
    ph.ArgumentError, "spin")
err("perturbation_error/spin=1e154", lambda: PE(MOMENTS, eps=[1e-3], spin=1e154),
    ph.ArgumentError, "spin")
err("perturbation_errors/spin=1e300", lambda: PES(MOMENTS, 0, [1e-3], spin=1e300),
    ph.ArgumentError, "spin")
err("perturbation_error/direction 1e300, eps by default",
    lambda: PE(MOMENTS, direction=[1e300, 1e300, 0.0]), ph.ArgumentError, "direction")
err("perturbation_error/direction masked",
    lambda: PE(MOMENTS, eps=[1e-3], direction=masked([1.0, 0.0, 0.0], [0, 1, 0])),
    ph.ArgumentError, "direction")
err("perturbation_error/axis=np.int64(3)", lambda: PE(MOMENTS, axis=np.int64(3)),
    ph.ArgumentError, "axis")

# animate and scene: frames given as a masked array, the resolution, the interval and the
# dpi of a saved file, a path where nothing can be written, trajectories at the ends.
for _name, _call in (("animate", lambda **k: AN(bar_traj(), bar(), **k)),
                     ("scene", lambda **k: SCENE(bar_traj(), bar(), **k))):
    err(f"{_name}/frames masked", lambda c=_call: c(frames=np.ma.array([0, 5], mask=[0, 1])),
        ph.ArgumentError, "frames")
    err(f"{_name}/frames np.ma.masked 0-d", lambda c=_call: c(frames=np.ma.array(2, mask=True)),
        ph.ArgumentError, "frames")
    ok(f"{_name}/frames masked, nothing masked",
       lambda c=_call: c(frames=np.ma.array([0, 5], mask=[0, 0])), frames_drawn([0, 5]))
    ok(f"{_name}/frames=np.array(2)", lambda c=_call: c(frames=np.array(2)),
       frames_drawn([0, 40]))
    err(f"{_name}/path in a missing folder",
        lambda c=_call: c(frames=2, path=folder() + "/missing/x.gif"), FileNotFoundError, "path")
    err(f"{_name}/path=''", lambda c=_call: c(frames=2, path=""), ph.ArgumentError, "path")
    err(f"{_name}/path a folder", lambda c=_call: c(frames=2, path=folder()), ph.ArgumentError,
        "path")
err("animate/resolution=10**6", lambda: AN(ball_traj(), ball(), frames=2, resolution=10**6),
    ph.ArgumentError, "resolution")
err("scene/resolution=10**6", lambda: SCENE(ball_traj(), ball(), frames=2, resolution=10**6),
    ph.ArgumentError, "resolution")
err("scene/resolution=2**62", lambda: SCENE(ball_traj(), ball(), frames=2, resolution=2**62),
    ph.ArgumentError, "resolution")
ok("animate/resolution=360", lambda: AN(ball_traj(), ball(), frames=1, resolution=360), drawn)
err("animate/interval=1e300", lambda: AN(bar_traj(), bar(), frames=2, path=gif(), interval=1e300),
    ph.ArgumentError, "interval")
err("animate/interval=1e6", lambda: AN(bar_traj(), bar(), frames=2, interval=1e6),
    ph.ArgumentError, "interval")
err("animate/dpi=1e300", lambda: AN(bar_traj(), bar(), frames=2, path=gif(), dpi=1e300),
    ph.ArgumentError, "dpi")
err("animate/dpi=5", lambda: AN(bar_traj(), bar(), frames=2, path=gif(), dpi=5.0),
    ph.ArgumentError, "dpi")
err("animate/dpi=1e-300", lambda: AN(bar_traj(), bar(), frames=2, path=gif(), dpi=1e-300),
    ph.ArgumentError, "dpi")
err("animate/dpi masked", lambda: AN(bar_traj(), bar(), frames=2, path=gif(), dpi=np.ma.masked),
    ph.ArgumentError, "dpi")
err("animate/origin masked", lambda: AN(bar_traj(), bar(), frames=2,
                                        origin=masked([0.0, 0.0, 0.1], [0, 0, 1])),
    ph.ArgumentError, "origin")
err("animate/body masked", lambda: AN(bar_traj(), masked(np.diag(bar().inertia), [0, 1, 0]),
                                      frames=2), ph.ArgumentError, "body")


# ---------------------------------------------------------------------------------------------
# At the ends of double precision: trajectories of moments 2^+-1000 [1, 2, 3] (their squares,
# L^2 and |L|'s own, are beyond doubles), huge and tiny |L|, directions, hints and rates. The
# reference of a drawing there is the equation it must satisfy, in units of that power of two
# (exact), or the rationals of the motion (which do not depend on the scale).
# ---------------------------------------------------------------------------------------------

SCALE = 1000  # the trajectories at the ends: moments 2^+-SCALE [1, 2, 3]


def scaled_traj(k):
    """The motion of the moments 2^k [1, 2, 3] from OMEGA0 (omega does not depend on k)."""
    return cached(f"scaled_traj{k}",
                  lambda: ph.simulate(np.ldexp(MOMENTS, k), OMEGA0, TIMES))


def on_the_polhode(points, moments, ell, energy, k):
    """Every point on the sphere |L| = ell and the ellipsoid sum L_i^2 / I_i = 2 T, checked in
    units of 2^k (exact): the equations of the polhode."""
    u = np.ldexp(np.asarray(points, dtype=float), -k)
    m = np.ldexp(np.asarray(moments, dtype=float), -k)
    np.testing.assert_allclose(np.sqrt(np.sum(u * u, axis=-1)), math.ldexp(ell, -k), rtol=1e-12)
    np.testing.assert_allclose(np.sum(u * u / m, axis=-1), 2 * math.ldexp(energy, -k),
                               rtol=1e-12)


def polhode_trajectory_scaled(k):
    """The trajectory drawn on the polhode of the moments 2^k [1, 2, 3] is on its sphere and
    ellipsoid (its own |L| and T at t0, from OMEGA0 in exact rationals)."""

    def check(ax):
        from fractions import Fraction

        (line,) = lines(ax, "trajectory")
        w = [Fraction(x) for x in OMEGA0]
        m = [Fraction(x) for x in MOMENTS]
        l2 = sum((mi * wi) ** 2 for mi, wi in zip(m, w, strict=True))
        energy = sum(mi * wi * wi for mi, wi in zip(m, w, strict=True)) / 2
        on_the_polhode(np.column_stack(line.get_data_3d()), np.ldexp(MOMENTS, k),
                       math.ldexp(math.sqrt(l2), k), math.ldexp(float(energy), k), k)

    return check


def dissipation_levels_exact(ax):
    """Torque-free: T and |L| stay at their first values; the separatrix at L^2 / (2 I2 T) and
    the spin about axis 3 at L^2 / (2 I3 T), from OMEGA0 in exact rationals (they do not
    depend on the moments' scale)."""
    from fractions import Fraction

    w = [Fraction(x) for x in OMEGA0]
    m = [Fraction(x) for x in MOMENTS]
    l2 = sum((mi * wi) ** 2 for mi, wi in zip(m, w, strict=True))
    energy = sum(mi * wi * wi for mi, wi in zip(m, w, strict=True)) / 2
    for gid in ("dissipation:energy", "dissipation:angular_momentum"):
        np.testing.assert_allclose(lines(ax, gid)[0].get_ydata(), 1.0, rtol=1e-12)
    for gid, moment in (("dissipation:separatrix", m[1]), ("dissipation:largest_axis", m[2])):
        level = float(l2 / (2 * moment * energy))
        np.testing.assert_allclose(lines(ax, gid)[0].get_ydata(), level, rtol=4e-16)


def drifts_below(bound):
    def check(ax):
        drawn(ax)
        for line in lines(ax, "drift:"):
            assert np.max(line.get_ydata()) <= bound, line.get_gid()

    return check


def scene_drawn(fig):
    """Every number of the figure finite, and the body not collapsed to a point."""
    for trace in fig.data:
        for axis in "xyz":
            value = getattr(trace, axis, None)
            values = np.asarray([] if value is None else value, dtype=float)
            assert np.all(np.isfinite(values)), (trace.uid, axis)
    body = np.asarray(fig.data[0].x, dtype=float)
    assert np.ptp(body) > 0, "the body drawn as a point"


err("polhode/|L|=1e300 (T = L^2/2I beyond doubles)", lambda: PO(MOMENTS, 1e300),
    ph.ArgumentError, "angular_momentum_norm")
for _k in (SCALE, -SCALE):
    ok(f"polhode/traj of moments 2^{_k} [1, 2, 3]", lambda k=_k: PO(traj=scaled_traj(k)),
       polhode_trajectory_scaled(_k))
err("polhode_curves/moments all equal", lambda: PC([1.0, 1.0, 1.0], 1.0, 0.5), ph.ArgumentError,
    "moments")
err("polhode_curves/|L|=1e300", lambda: PC(MOMENTS, 1e300, 0.3), ph.ArgumentError,
    "angular_momentum_norm")
err("polhode_curves/|L|=1e-300", lambda: PC(MOMENTS, 1e-300, 0.3), ph.ArgumentError,
    "angular_momentum_norm")
ok("polhode_curves/|L| = 2^1000, moments 2^1000 [1, 2, 3] (L^2 beyond doubles, T not)",
   lambda: PC(np.ldexp(MOMENTS, SCALE), math.ldexp(1.0, SCALE), math.ldexp(0.3, SCALE)),
   lambda curves: [on_the_polhode(c, np.ldexp(MOMENTS, SCALE), math.ldexp(1.0, SCALE),
                                  math.ldexp(0.3, SCALE), SCALE) for c in curves])
ok("invariable_plane_basis/hint=1e300 [1, 1, 0]", lambda: IPB([0.0, 0.0, 1.0], [1e300, 1e300, 0]),
   lambda basis: np.testing.assert_allclose(
       basis, [[0.5**0.5, 0.5**0.5, 0.0], [-(0.5**0.5), 0.5**0.5, 0.0], [0.0, 0.0, 1.0]],
       atol=1e-15))
# The time plots at the ends of double precision.
for _k in (SCALE, -SCALE):
    ok(f"drift/traj of moments 2^{_k} [1, 2, 3]", lambda k=_k: plot.drift(scaled_traj(k)),
       drifts_below(64 * np.finfo(float).eps))
    ok(f"dissipation/traj of moments 2^{_k} [1, 2, 3]",
       lambda k=_k: plot.dissipation(scaled_traj(k)), dissipation_levels_exact)

err("perturbation_error/direction=1e308 [1, 1, 0]",
    lambda: PE(MOMENTS, eps=[1e-3], direction=[1e308, 1e308, 0.0]), ph.ArgumentError, "eps")
ok("perturbation_errors/direction 1e300 [1, 1, 0] against eps 1e-303",
   lambda: PES(MOMENTS, 2, [1e-303], t=1.0, direction=[1e300, 1e300, 0.0]),
   lambda errors: np.testing.assert_array_less(errors[2], 1e-6))
for _k in (SCALE, -SCALE):
    ok(f"animate/traj of moments 2^{_k} [1, 2, 3]",
       lambda k=_k: AN(scaled_traj(k), frames=2), drawn)
    ok(f"scene/traj of moments 2^{_k} [1, 2, 3]",
       lambda k=_k: SCENE(scaled_traj(k), frames=2), scene_drawn)
err("scene/omega 1e150 in float32", lambda: SCENE(ph.simulate(
    MOMENTS, [1e150, 1e150, 1e150], np.linspace(0.0, 1e-149, 41)), frames=2), ph.ArgumentError,
    "dtype")
err("scene/omega 1e-160 in float32 (drawn as zeros)", lambda: SCENE(ph.simulate(
    MOMENTS, [1e-160, 1e-160, 1e-160], np.linspace(0.0, 1e161, 41)), frames=2),
    ph.ArgumentError, "dtype")
ok("scene/omega 1e150 in float64", lambda: SCENE(ph.simulate(
    MOMENTS, [1e150, 1e150, 1e150], np.linspace(0.0, 1e-149, 41)), frames=2,
    dtype=np.float64), scene_drawn)


# ---------------------------------------------------------------------------------------------
# Running the rows, and their outcomes
# ---------------------------------------------------------------------------------------------


def _run(row: Row) -> tuple[Any, BaseException | None]:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            return row.call(), None
        except Exception as error:  # noqa: BLE001 - every outcome is classified
            return None, error


def _names(error: BaseException, argument: str) -> bool:
    if isinstance(error, ph.PolhodeError):
        return error.argument == argument
    return f"`{argument}`" in str(error) or f"`{argument}[" in str(error)


def outcome(row: Row) -> tuple[str, str]:
    """("ok" | "minor" | "unacceptable", what happened)."""
    result, error = _run(row)
    expect = row.expect
    if error is None:
        if isinstance(expect, Draws):
            try:
                expect.check(result)
            except AssertionError as failure:
                return "unacceptable", f"drawn wrong: {failure}"
            return "ok", "drawn"
        return "unacceptable", "accepted silently"
    what = f"{type(error).__name__}: {str(error)[:160]}"
    if isinstance(expect, Draws):  # refused: by a check of polhode's, or from inside
        return ("minor" if _is_ours(error) else "unacceptable"), what
    if type(error) is expect.error and _names(error, expect.argument):
        return "ok", what
    if isinstance(error, ph.PolhodeError | TypeError) and _names(error, expect.argument):
        return "ok", what  # typed and naming the argument: another subclass only
    if isinstance(error, ValueError | TypeError) and (
        isinstance(error, ph.PolhodeError) or _is_ours(error)
    ):
        return "minor", what
    return "unacceptable", what


def _is_ours(error: BaseException) -> bool:
    """Raised by a ``raise`` statement of polhode's own (one of its checks), not from inside
    Python, numpy or matplotlib ("could not convert string to float", "too many values to
    unpack", an IndexError in a writer)."""
    import os
    import traceback

    frames = traceback.extract_tb(error.__traceback__)
    if not frames:
        return False
    last = frames[-1]
    package = os.path.dirname(ph.__file__)
    return last.filename.startswith(package) and (last.line or "").lstrip().startswith("raise")


def totals(rows: list[Row], old: bool = False) -> str:
    counts: collections.Counter = collections.Counter()
    lines_out = []
    for row in rows:
        if old and row.new:
            continue
        kind, what = outcome(row)
        counts[kind] += 1
        if kind != "ok":
            lines_out.append(f"  {kind:13s} {row.id}: {what}")
    total = sum(counts.values())
    head = (f"{total} rows: ok {counts['ok']}, minor {counts['minor']}, "
            f"unacceptable {counts['unacceptable']}")
    return "\n".join([head, *lines_out])


@pytest.mark.parametrize("row", ROWS, ids=[row.id for row in ROWS])
def test_row(row: Row):
    expect = row.expect
    if isinstance(expect, Draws):
        expect.check(row.call())
        return
    with pytest.raises(BaseException) as info:  # noqa: PT011, B017 - checked below
        row.call()
    error = info.value
    assert type(error) is expect.error, f"{type(error).__name__}: {error}"
    assert _names(error, expect.argument), (getattr(error, "argument", None), str(error))
    assert "Traceback" not in str(error) and len(str(error)) < 600, str(error)


def test_the_rows():
    """Unique ids, every public plot probed, and each with enough rows."""
    ids = [row.id for row in ROWS]
    assert len(ids) == len(set(ids)), [i for i, n in collections.Counter(ids).items() if n > 1]
    by_function = collections.Counter(i.split("/")[0] for i in ids)
    for name in (*plot.__all__, "perturbation_errors", "polhode_curves", "separatrix_curves",
                 "invariable_plane_basis", "omega_space"):
        assert by_function[name] >= 3, name
    assert len(ROWS) >= 200, len(ROWS)


if __name__ == "__main__":
    import sys

    print(totals(ROWS, old="--old" in sys.argv))

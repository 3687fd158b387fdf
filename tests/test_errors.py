"""Bad input raises at once, with the typed error and the argument's name in the message.

ValueError subclasses (polhode.PolhodeError, polhode.InertiaError) for shapes, non-finite
numbers, non-positive masses and sizes, invalid tensors and rotations; TypeError for wrong types.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import polhode as ph

NAN, INF = math.nan, math.inf
GOOD_POSITIONS = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 2.0, 0.0]]
GOOD_MASSES = [1.0, 2.0, 3.0]


def test_exception_hierarchy():
    assert issubclass(ph.PolhodeError, ValueError)
    assert issubclass(ph.InertiaError, ph.PolhodeError)


def _body():
    return ph.Body.cuboid(2.0, (1.0, 2.0, 3.0))


# (label, callable, argument name that the message must contain)
VALUE_ERRORS = [
    # point masses
    ("masses-nan", lambda: ph.Body.point_masses([1.0, NAN, 3.0], GOOD_POSITIONS), "masses"),
    ("masses-inf", lambda: ph.Body.point_masses([1.0, INF, 3.0], GOOD_POSITIONS), "masses"),
    ("masses-negative", lambda: ph.Body.point_masses([1.0, -2.0, 3.0], GOOD_POSITIONS), "masses"),
    ("masses-all-zero", lambda: ph.Body.point_masses([0.0, 0.0, 0.0], GOOD_POSITIONS), "mass"),
    (
        "positions-nan",
        lambda: ph.Body.point_masses(GOOD_MASSES, [[0, 0, 0], [1, NAN, 0], [0, 2, 0]]),
        "positions",
    ),
    (
        "positions-inf",
        lambda: ph.Body.point_masses(GOOD_MASSES, [[0, 0, 0], [1, 0, 0], [0, 2, -INF]]),
        "positions",
    ),
    (
        "positions-N2",
        lambda: ph.Body.point_masses(GOOD_MASSES, [[0, 0], [1, 0], [0, 2]]),
        "positions",
    ),
    ("positions-flat", lambda: ph.Body.point_masses([1.0], [0.0, 0.0, 0.0]), "positions"),
    ("positions-3d", lambda: ph.Body.point_masses([1.0], [[[0.0, 0.0, 0.0]]]), "positions"),
    ("mismatched-N", lambda: ph.Body.point_masses([1.0, 2.0], GOOD_POSITIONS), "masses|positions"),
    ("masses-2d", lambda: ph.Body.point_masses([[1.0, 2.0, 3.0]], GOOD_POSITIONS), "masses"),
    ("empty", lambda: ph.Body.point_masses([], np.empty((0, 3))), "masses|positions"),
    # solids: zero, negative, non-finite mass and sizes
    ("sphere-mass-0", lambda: ph.Body.sphere(0.0, 1.0), "mass"),
    ("sphere-mass-neg", lambda: ph.Body.sphere(-1.0, 1.0), "mass"),
    ("sphere-mass-nan", lambda: ph.Body.sphere(NAN, 1.0), "mass"),
    ("sphere-mass-inf", lambda: ph.Body.sphere(INF, 1.0), "mass"),
    ("sphere-radius-0", lambda: ph.Body.sphere(1.0, 0.0), "radius"),
    ("sphere-radius-neg", lambda: ph.Body.sphere(1.0, -1.0), "radius"),
    ("sphere-radius-nan", lambda: ph.Body.sphere(1.0, NAN), "radius"),
    ("shell-radius-inf", lambda: ph.Body.spherical_shell(1.0, INF), "radius"),
    ("shell-mass-0", lambda: ph.Body.spherical_shell(0.0, 1.0), "mass"),
    ("box-size-0", lambda: ph.Body.cuboid(1.0, (1.0, 0.0, 1.0)), "size"),
    ("box-size-neg", lambda: ph.Body.cuboid(1.0, (1.0, 1.0, -1.0)), "size"),
    ("box-size-nan", lambda: ph.Body.cuboid(1.0, (NAN, 1.0, 1.0)), "size"),
    ("box-size-shape", lambda: ph.Body.cuboid(1.0, (1.0, 1.0)), "size"),
    ("box-size-scalar", lambda: ph.Body.cuboid(1.0, 1.0), "size"),
    ("box-mass-neg", lambda: ph.Body.cuboid(-1.0, (1.0, 1.0, 1.0)), "mass"),
    ("cylinder-radius-0", lambda: ph.Body.cylinder(1.0, 0.0, 1.0), "radius"),
    ("cylinder-length-neg", lambda: ph.Body.cylinder(1.0, 1.0, -1.0), "length"),
    ("cylinder-length-inf", lambda: ph.Body.cylinder(1.0, 1.0, INF), "length"),
    ("cylinder-mass-nan", lambda: ph.Body.cylinder(NAN, 1.0, 1.0), "mass"),
    (
        "tube-inner-equals-outer",
        lambda: ph.Body.tube(1.0, 1.0, 1.0, 1.0),
        "inner_radius|outer_radius",
    ),
    (
        "tube-inner-above-outer",
        lambda: ph.Body.tube(1.0, 2.0, 1.0, 1.0),
        "inner_radius|outer_radius",
    ),
    ("tube-inner-neg", lambda: ph.Body.tube(1.0, -0.5, 1.0, 1.0), "inner_radius"),
    ("tube-outer-nan", lambda: ph.Body.tube(1.0, 0.5, NAN, 1.0), "outer_radius"),
    ("tube-length-0", lambda: ph.Body.tube(1.0, 0.5, 1.0, 0.0), "length"),
    ("cone-radius-neg", lambda: ph.Body.cone(1.0, -1.0, 1.0), "radius"),
    ("cone-length-0", lambda: ph.Body.cone(1.0, 1.0, 0.0), "length"),
    ("cone-length-nan", lambda: ph.Body.cone(1.0, 1.0, NAN), "length"),
    ("ellipsoid-axis-0", lambda: ph.Body.ellipsoid(1.0, (1.0, 2.0, 0.0)), "semi_axes"),
    ("ellipsoid-axis-inf", lambda: ph.Body.ellipsoid(1.0, (1.0, INF, 1.0)), "semi_axes"),
    ("ellipsoid-shape", lambda: ph.Body.ellipsoid(1.0, (1.0, 2.0, 3.0, 4.0)), "semi_axes"),
    ("rod-length-0", lambda: ph.Body.rod(1.0, 0.0), "length"),
    ("rod-mass-neg", lambda: ph.Body.rod(-1.0, 1.0), "mass"),
    ("disk-radius-neg", lambda: ph.Body.disk(1.0, -2.0), "radius"),
    ("disk-radius-nan", lambda: ph.Body.disk(1.0, NAN), "radius"),
    # a spindle torus (minor > major) overlaps itself: the ring-torus formula does not apply
    ("torus-spindle", lambda: ph.Body.torus(1.0, 1.0, 1.5), "minor_radius|major_radius"),
    ("torus-minor-0", lambda: ph.Body.torus(1.0, 1.0, 0.0), "minor_radius"),
    ("torus-major-neg", lambda: ph.Body.torus(1.0, -1.0, 0.5), "major_radius"),
    ("torus-minor-nan", lambda: ph.Body.torus(1.0, 1.0, NAN), "minor_radius"),
    ("capsule-radius-0", lambda: ph.Body.capsule(1.0, 0.0, 1.0), "radius"),
    ("capsule-length-neg", lambda: ph.Body.capsule(1.0, 1.0, -1.0), "length"),
    ("capsule-mass-inf", lambda: ph.Body.capsule(INF, 1.0, 1.0), "mass"),
    # from_inertia
    ("from-inertia-mass-0", lambda: ph.Body.from_inertia(0.0, np.eye(3)), "mass"),
    ("from-inertia-shape", lambda: ph.Body.from_inertia(1.0, np.eye(2)), "inertia"),
    ("from-inertia-6-vector", lambda: ph.Body.from_inertia(1.0, np.ones(6)), "inertia"),
    ("from-inertia-nan", lambda: ph.Body.from_inertia(1.0, np.diag([1.0, NAN, 1.0])), "inertia"),
    ("from-inertia-inf", lambda: ph.Body.from_inertia(1.0, np.diag([1.0, 1.0, INF])), "inertia"),
    (
        "from-inertia-com-shape",
        lambda: ph.Body.from_inertia(1.0, np.eye(3), (0.0, 0.0)),
        "center_of_mass",
    ),
    (
        "from-inertia-com-nan",
        lambda: ph.Body.from_inertia(1.0, np.eye(3), (0.0, NAN, 0.0)),
        "center_of_mass",
    ),
    # moving and querying
    ("translated-nan", lambda: _body().translated([0.0, NAN, 0.0]), "offset"),
    ("translated-shape", lambda: _body().translated([0.0, 1.0]), "offset"),
    ("rotated-not-orthogonal", lambda: _body().rotated(2.0 * np.eye(3)), "rotation"),
    (
        "rotated-shear",
        lambda: _body().rotated([[1.0, 0.1, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),
        "rotation",
    ),
    ("rotated-reflection", lambda: _body().rotated(np.diag([1.0, 1.0, -1.0])), "rotation"),
    ("rotated-shape-2x2", lambda: _body().rotated(np.eye(2)), "rotation"),
    ("rotated-shape-3", lambda: _body().rotated([0.0, 0.0, 1.0]), "rotation"),
    ("rotated-zero-quaternion", lambda: _body().rotated([0.0, 0.0, 0.0, 0.0]), "rotation"),
    ("rotated-nan-quaternion", lambda: _body().rotated([NAN, 0.0, 0.0, 1.0]), "rotation"),
    ("rotated-nan-matrix", lambda: _body().rotated(np.full((3, 3), NAN)), "rotation"),
    (
        "rotated-stack",
        lambda: _body().rotated(Rotation.from_rotvec([[0.0, 0.0, 1.0]] * 2)),
        "rotation",
    ),
    ("inertia-about-shape", lambda: _body().inertia_about([0.0, 0.0]), "point"),
    ("inertia-about-nan", lambda: _body().inertia_about([0.0, INF, 0.0]), "point"),
    (
        "inertia-about-bad-axes",
        lambda: _body().inertia_about([0.0, 0.0, 0.0], axes=3 * np.eye(3)),
        "axes",
    ),
    (
        "inertia-about-zero-quat",
        lambda: _body().inertia_about([0, 0, 0], axes=[0.0, 0, 0, 0]),
        "axes",
    ),
    ("omega-shape", lambda: _body().angular_momentum_body([1.0, 2.0]), "omega"),
    ("omega-nan", lambda: _body().angular_momentum_body([1.0, NAN, 2.0]), "omega"),
    ("energy-omega-inf", lambda: _body().kinetic_energy([1.0, INF, 2.0]), "omega"),
    ("principal-rtol-neg", lambda: _body().principal(rtol=-1.0), "rtol"),
    ("principal-rtol-nan", lambda: _body().principal(rtol=NAN), "rtol"),
    # principal() on tensors
    ("principal-nan", lambda: ph.principal(np.diag([1.0, NAN, 2.0])), "inertia"),
    ("principal-inf", lambda: ph.principal(np.full((3, 3), INF)), "inertia"),
    (
        "principal-asymmetric",
        lambda: ph.principal([[1.0, 0.1, 0.0], [0.2, 1.0, 0.0], [0.0, 0.0, 1.0]]),
        "inertia",
    ),
    ("principal-shape", lambda: ph.principal(np.ones((3, 2))), "inertia"),
    ("principal-shape-vector", lambda: ph.principal(np.ones(3)), "inertia"),
    (
        "principal-batch-nan",
        lambda: ph.principal(np.stack([np.eye(3), np.diag([1.0, NAN, 1.0])])),
        "inertia",
    ),
    (
        "principal-batch-asymmetric",
        lambda: ph.principal(np.stack([np.eye(3), np.eye(3) + np.triu(np.ones((3, 3)), 1)])),
        "inertia",
    ),
    ("principal-fn-rtol-neg", lambda: ph.principal(np.eye(3), rtol=-1.0), "rtol"),
]


@pytest.mark.parametrize(("label", "call", "name"), VALUE_ERRORS, ids=[v[0] for v in VALUE_ERRORS])
def test_value_errors_name_the_argument(label, call, name):
    with pytest.raises(ph.PolhodeError, match=name) as info:
        call()
    assert isinstance(info.value, ValueError)


INERTIA_ERRORS = [
    ("asymmetric", [[1.0, 0.1, 0.0], [0.2, 1.0, 0.0], [0.0, 0.0, 1.0]]),
    ("not-psd", np.diag([-1e-3, 1.0, 1.0])),
    ("negative-definite", -np.eye(3)),
    ("triangle", np.diag([1.0, 1.0, 3.0])),
    # violated by 1e-10 relative: far beyond the ~16 eps tr/2 tolerance
    ("triangle-slightly", np.diag([1.0, 1.0, 2.0 * (1 + 1e-10)])),
    (
        "triangle-rotated",
        (lambda r: r @ np.diag([0.5, 1.0, 2.0]) @ r.T)(
            Rotation.from_rotvec([0.2, 0.9, -0.4]).as_matrix()
        ),
    ),
]


@pytest.mark.parametrize(("label", "inertia"), INERTIA_ERRORS, ids=[v[0] for v in INERTIA_ERRORS])
def test_invalid_inertia_tensors(label, inertia):
    with pytest.raises(ph.InertiaError, match="inertia"):
        ph.Body.from_inertia(1.0, inertia)


TYPE_ERRORS = [
    ("mass-str", lambda: ph.Body.sphere("heavy", 1.0)),
    ("mass-numeric-str", lambda: ph.Body.sphere("1.0", 1.0)),
    ("mass-none", lambda: ph.Body.sphere(None, 1.0)),
    ("mass-complex", lambda: ph.Body.sphere(1.0 + 2.0j, 1.0)),
    ("radius-str", lambda: ph.Body.cylinder(1.0, "wide", 1.0)),
    ("length-str", lambda: ph.Body.rod(1.0, "1")),
    ("size-str", lambda: ph.Body.cuboid(1.0, "abc")),
    ("size-str-items", lambda: ph.Body.cuboid(1.0, ["a", "b", "c"])),
    ("masses-str", lambda: ph.Body.point_masses(["a", "b", "c"], GOOD_POSITIONS)),
    ("positions-str", lambda: ph.Body.point_masses(GOOD_MASSES, "positions")),
    ("inertia-str", lambda: ph.Body.from_inertia(1.0, "diag(1, 2, 3)")),
    ("rotation-str", lambda: _body().rotated("xyz")),
    ("rotation-none", lambda: _body().rotated(None)),
    ("offset-str", lambda: _body().translated("up")),
    ("principal-str", lambda: ph.principal("inertia")),
    ("add-int", lambda: _body() + 1),
    ("add-str", lambda: _body() + "body"),
    ("add-array", lambda: _body() + np.eye(3)),
]

_NAMES = {
    "mass": "mass",
    "radius": "radius",
    "length": "length",
    "size": "size",
    "masses": "masses",
    "positions": "positions",
    "inertia": "inertia",
    "rotation": "rotation",
    "offset": "offset",
    "principal": "inertia",
}


@pytest.mark.parametrize(("label", "call"), TYPE_ERRORS, ids=[v[0] for v in TYPE_ERRORS])
def test_type_errors(label, call):
    with pytest.raises(TypeError) as info:
        call()
    prefix = label.split("-")[0]
    if prefix in _NAMES:  # our own messages name the argument (b + 1 is Python's message)
        assert _NAMES[prefix] in str(info.value), str(info.value)


def test_errors_are_raised_at_once_not_as_nan():
    # Nothing returns NaN silently: a body built from finite input has finite everything.
    body = ph.Body.point_masses([1e-300, 1e300], [[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]])
    assert np.all(np.isfinite(body.inertia)) and np.all(np.isfinite(body.center_of_mass))

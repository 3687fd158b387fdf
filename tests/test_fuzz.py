"""A hypothesis fuzz of the whole public API: any input gives a finite answer or a typed error.

Each entry point is called with arguments drawn from everything a user could pass (numbers
from the subnormal to the largest float, NaN and infinities, wrong shapes, wrong types). The
call must either return finite numbers (when its input was finite) or raise one of the
documented errors: a ``polhode.PolhodeError`` (a ValueError), a ``TypeError`` or a
``MemoryError``. A ``PanicException`` (a BaseException), any other exception, a NaN or an
infinity in the output of a finite input fails the test.
"""

from __future__ import annotations

import atexit
import contextlib
import io
import math
import shutil
import tempfile
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, note, settings
from hypothesis import strategies as st

import polhode as ph

ALLOWED = (ph.PolhodeError, TypeError, MemoryError)

# Numbers across the whole double range, the special values, and a few exact small ones.
FLOATS = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.floats(-1e3, 1e3),
    st.sampled_from([0.0, -0.0, 1.0, -1.0, 5e-324, 1e-310, 1e-160, 1e160, 1.7e308]),
)
FINITE = st.one_of(
    st.floats(allow_nan=False, allow_infinity=False),
    st.floats(-1e3, 1e3, allow_nan=False),
    st.sampled_from([0.0, 1.0, 5e-324, 1e-300, 1e-160, 1e160, 1e300]),
)
POSITIVE = st.one_of(
    st.floats(min_value=5e-324, max_value=1.7e308, allow_nan=False, allow_infinity=False),
    st.floats(0.01, 100.0),
)


def arrays(elements: st.SearchStrategy[float], shapes: st.SearchStrategy[tuple[int, ...]]):
    return shapes.flatmap(
        lambda shape: st.lists(
            elements, min_size=int(np.prod(shape)), max_size=int(np.prod(shape))
        ).map(lambda v: np.array(v, dtype=float).reshape(shape))
    )


SHAPES = st.sampled_from([(3,), (2,), (4,), (3, 3), (1, 3), (2, 3), (3, 4), (0, 3), (2, 2, 3), ()])
JUNK = st.sampled_from(
    ["abc", None, {"a": 1}, [1, "x", 3], 1 + 2j, np.array([1 + 1j] * 3), b"\x00"]
)


def anything(elements=FLOATS, shapes=SHAPES):
    """A value a user might pass where numbers are expected."""
    return st.one_of(arrays(elements, shapes), elements, JUNK)


def vector3(elements=FLOATS):
    return arrays(elements, st.just((3,)))


def is_finite_input(*values: Any) -> bool:
    """Whether every number in the values is finite (non-numbers count as not finite)."""
    for value in values:
        if np.iscomplexobj(value):
            return False
        try:
            array = np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            return False
        if not np.all(np.isfinite(array)):
            return False
    return True


def check_finite_output(result: Any, what: str) -> None:
    """Every float in the result (arrays, dataclass fields, dicts, tuples) is finite."""
    if result is None or isinstance(result, str | bool | int):
        return
    if isinstance(result, float):
        assert math.isfinite(result), f"{what}: {result}"
        return
    if isinstance(result, np.ndarray):
        if result.dtype.kind == "f":
            assert np.all(np.isfinite(result)), f"{what}: non-finite output"
        return
    if isinstance(result, dict):
        for k, v in result.items():
            check_finite_output(v, f"{what}[{k!r}]")
        return
    if isinstance(result, tuple | list):
        for k, v in enumerate(result):
            check_finite_output(v, f"{what}[{k}]")
        return
    if hasattr(result, "__dataclass_fields__"):
        for name in result.__dataclass_fields__:
            if name != "stats":
                check_finite_output(getattr(result, name), f"{what}.{name}")
        return
    if isinstance(result, ph.Body):
        check_finite_output((result.mass, result.center_of_mass, result.inertia), what)


def call(function, *args, finite_input: bool, what: str, **kwargs):
    """Calls; lets only the documented errors through; checks finite output of finite input."""
    note(f"{what}({args!r}, {kwargs!r})")
    try:
        result = function(*args, **kwargs)
    except ALLOWED:
        return None
    except BaseException as error:  # noqa: BLE001 - the point of the test
        pytest.fail(f"{what} raised {type(error).__name__}: {error}")
    if finite_input:
        check_finite_output(result, what)
    return result


FUZZ = settings(
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much],
)

SOLIDS = {
    "sphere": 1,
    "spherical_shell": 1,
    "cylinder": 2,
    "tube": 3,
    "cone": 2,
    "rod": 1,
    "disk": 1,
    "torus": 2,
    "capsule": 2,
}


@FUZZ
@given(st.sampled_from(sorted(SOLIDS)), FLOATS, st.lists(FLOATS, min_size=3, max_size=3))
def test_solids(name, mass, params):
    args = params[: SOLIDS[name]]
    body = call(getattr(ph.Body, name), mass, *args, finite_input=True, what=name)
    if body is not None:
        check_finite_output(body, name)


@FUZZ
@given(
    st.sampled_from([*sorted(SOLIDS), "cuboid", "ellipsoid", "point", "pyramid"]),
    FLOATS,
    st.dictionaries(
        st.sampled_from(["radius", "length", "size", "semi_axes", "inner_radius",
                         "outer_radius", "major_radius", "minor_radius", "mass", "width"]),
        st.one_of(FLOATS, anything()),
        max_size=4,
    ),
)
def test_solid_by_name(kind, mass, parameters):
    finite = is_finite_input(mass, *parameters.values())
    call(ph.Body.solid, kind, mass, **parameters, finite_input=finite, what=f"solid[{kind}]")


@FUZZ
@given(st.sampled_from(["cuboid", "ellipsoid"]), FLOATS, anything())
def test_vector_solids(name, mass, size):
    call(getattr(ph.Body, name), mass, size, finite_input=is_finite_input(size), what=name)


@FUZZ
@given(anything(shapes=st.sampled_from([(1,), (3,), (2,), (0,)])), anything())
def test_point_masses(masses, positions):
    finite = is_finite_input(masses, positions)
    call(ph.Body.point_masses, masses, positions, finite_input=finite, what="point_masses")


@FUZZ
@given(FLOATS, anything(), anything())
def test_from_inertia(mass, inertia, center):
    finite = is_finite_input(mass, inertia, center)
    call(ph.Body.from_inertia, mass, inertia, center, finite_input=finite, what="from_inertia")


def some_body():
    return st.sampled_from(
        [
            ph.Body.cylinder(1.0, 0.1, 0.5),
            ph.Body.cuboid(2.0, (1.0, 2.0, 3.0)),
            ph.Body.sphere(1.0, 1.0) + ph.Body.rod(0.5, 2.0).translated([0.0, 0.0, 1.0]),
            ph.Body.point_masses([1.0, 2.0], [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]),
        ]
    )


@FUZZ
@given(some_body(), anything(), anything(), FLOATS, FLOATS)
def test_body_methods(body, vector, matrix, a, b):
    finite = is_finite_input(vector)
    call(body.translated, vector, finite_input=finite, what="translated")
    call(body.rotated, matrix, finite_input=is_finite_input(matrix), what="rotated")
    call(body.inertia_about, vector, finite_input=finite, what="inertia_about")
    call(body.angular_momentum_body, vector, finite_input=finite, what="angular_momentum_body")
    call(body.kinetic_energy, vector, finite_input=finite, what="kinetic_energy")
    call(body.scaled, a, b, finite_input=is_finite_input(a, b), what="scaled")
    call(body.principal, a, finite_input=is_finite_input(a), what="principal")


@FUZZ
@given(anything(shapes=st.sampled_from([(3, 3), (2, 3, 3), (3,), (0, 3, 3), (3, 3, 3)])))
def test_principal(tensor):
    if isinstance(tensor, np.ndarray) and tensor.ndim >= 2:
        tensor = 0.5 * tensor + 0.5 * np.swapaxes(tensor, -1, -2)  # symmetric: reach the solver
    call(ph.principal, tensor, finite_input=is_finite_input(tensor), what="principal")


METHODS = st.sampled_from(["exact", "splitting", "midpoint", "rk4", "dop853", "auto", "euler"])


@FUZZ
@given(
    st.one_of(vector3(POSITIVE), vector3(FLOATS), anything()),
    st.one_of(vector3(FINITE), anything()),
    st.one_of(
        st.floats(0.0, 10.0),
        FLOATS,
        arrays(FLOATS, st.sampled_from([(1,), (2,), (3,)])),
        JUNK,
    ),
    METHODS,
    st.one_of(st.none(), st.floats(1e-3, 1.0), FLOATS),
)
def test_simulate(body, omega0, t, method, dt):
    finite = is_finite_input(body, omega0, t) and (dt is None or math.isfinite(dt))
    call(
        ph.simulate,
        body,
        omega0,
        t,
        method=method,
        dt=dt,
        max_steps=20_000,
        finite_input=finite,
        what=f"simulate[{method}]",
    )


@FUZZ
@given(st.one_of(vector3(POSITIVE), anything()), st.one_of(vector3(FINITE), anything()))
def test_analyze(body, omega0):
    call(ph.analyze, body, omega0, finite_input=is_finite_input(body, omega0), what="analyze")


@FUZZ
@given(
    vector3(POSITIVE),
    vector3(FINITE),
    st.one_of(st.floats(0.0, 100.0), FLOATS),
    st.sampled_from([0, 1, 2]),
)
def test_perturbation(moments, omega0, t, order):
    call(
        ph.perturbation,
        moments,
        omega0,
        [0.0, t],
        order=order,
        finite_input=is_finite_input(t),
        what="perturbation",
    )


TORQUES = st.sampled_from(["BodyFixed", "SpaceFixed", "Gravity", "GravityGradient", "Window"])


@FUZZ
@given(TORQUES, anything(), FLOATS, FLOATS)
def test_torque_models(kind, vector, a, b):
    make = {
        "BodyFixed": lambda: ph.torque.BodyFixed(vector),
        "SpaceFixed": lambda: ph.torque.SpaceFixed(vector),
        "Gravity": lambda: ph.torque.Gravity(vector, pivot=None, mass=a, center_of_mass=vector),
        "GravityGradient": lambda: ph.torque.GravityGradient(a, vector, (1.0, 0.0, 0.0)),
        "Window": lambda: ph.torque.Window(ph.torque.BodyFixed((0.0, 0.0, 1.0)), a, b),
    }[kind]
    model = call(make, finite_input=False, what=kind)
    if model is not None and kind != "Gravity":
        call(
            ph.simulate,
            [1.0, 2.0, 3.0],
            [0.1, 0.2, 0.3],
            [0.0, 0.5],
            method="rk4",
            dt=0.01,
            torque=model,
            finite_input=True,
            what=f"simulate[{kind}]",
        )


# ---------------------------------------------------------------------------------------------
# Every method under every torque model, meshes, composites, polhode.dask and the command line
# ---------------------------------------------------------------------------------------------

FIXED_OR_ADAPTIVE = st.sampled_from(["splitting", "midpoint", "rk4", "dop853", "auto"])


def torque_models(vector):
    """A torque model (or plain callable) built from drawn numbers; None if its parameters are
    refused (that refusal is itself checked by ``call``)."""
    return st.one_of(
        vector.map(lambda v: ("BodyFixed", lambda: ph.torque.BodyFixed(v))),
        vector.map(lambda v: ("SpaceFixed", lambda: ph.torque.SpaceFixed(v))),
        st.tuples(vector, FLOATS).map(
            lambda a: ("Gravity", lambda: ph.torque.Gravity(a[0], pivot=(0.0, 0.0, 0.0)))
        ),
        st.tuples(FLOATS, vector).map(
            lambda a: ("GravityGradient", lambda: ph.torque.GravityGradient(a[0], a[1]))
        ),
        st.tuples(vector, FLOATS, FLOATS).map(
            lambda a: ("Window", lambda: ph.torque.Window(ph.torque.BodyFixed(a[0]), a[1], a[2]))
        ),
        st.tuples(vector, vector).map(
            lambda a: ("Sum", lambda: ph.torque.BodyFixed(a[0]) + ph.torque.SpaceFixed(a[1]))
        ),
        st.tuples(vector, st.sampled_from(["constant", "damping", "junk", "nan", "shape"])).map(
            lambda a: ("Function", lambda: ph.torque.Function(_torque_function(*a)))
        ),
    )


def _torque_function(v, kind):
    """A torque function returning something finite, or something a user might wrongly
    return (junk, NaN, a wrong shape): each must end in a typed error, never a panic."""
    if kind == "constant":
        return lambda t, w, q: v
    if kind == "damping":

        def damping(t, w, q):
            # Overflowing to inf is this function's own doing, not a warning to raise: the
            # core must then refuse the non-finite torque with a typed error.
            with np.errstate(over="ignore", invalid="ignore"):
                return -0.1 * np.asarray(w) + v

        return damping
    if kind == "junk":
        return lambda t, w, q: "abc"
    if kind == "nan":
        return lambda t, w, q: (math.nan, 0.0, 0.0)
    return lambda t, w, q: (0.0, 0.0)


@FUZZ
@given(
    torque_models(vector3(FINITE)),
    st.one_of(
        vector3(POSITIVE),
        st.just(ph.Body.cone(1.0, 0.3, 1.0)),
        st.just(ph.Body.cuboid(2.0, (1.0, 2.0, 3.0)).rotated([0.1, 0.2, 0.3, 0.9])),
    ),
    vector3(st.floats(-20.0, 20.0)),
    FIXED_OR_ADAPTIVE,
    st.sampled_from([1, 2]),
)
def test_simulate_with_torques(made, body, omega0, method, steps):
    """Every model under every method that takes a torque, with drawn parameters. A model that
    is refused when made raises a typed error there; one that is made must integrate to finite
    numbers or raise a typed error (a motion that leaves double precision, too many steps)."""
    kind, make = made
    model = call(make, finite_input=False, what=kind)
    if model is None:
        return
    call(
        ph.simulate,
        body,
        omega0,
        np.linspace(0.0, 0.5, steps + 1),
        method=method,
        dt=0.05,
        torque=model,
        max_steps=20_000,
        finite_input=True,
        what=f"simulate[{method}, {kind}]",
    )


TET_V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]])
TET_F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
CUBE_V = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)])
CUBE_F = np.array([
    [0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
    [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3],
])


@st.composite
def meshes(draw):
    """A closed mesh (tetrahedron or cube) moved, scaled and spoilt: vertices anywhere in the
    double range or NaN, faces reversed, dropped, repeated, out of range or of another dtype."""
    vertices, faces = draw(st.sampled_from([(TET_V, TET_F), (CUBE_V, CUBE_F)]))
    scale = draw(st.one_of(st.just(1.0), st.sampled_from([1e-300, 1e-150, 1e150, 1e300]),
                           st.floats(1e-3, 1e3)))
    shift = draw(vector3(st.one_of(st.floats(-1e3, 1e3), st.sampled_from([1e10, -1e200]))))
    vertices = vertices * scale + shift
    if draw(st.booleans()):
        noise = draw(arrays(FLOATS, st.just(vertices.shape)))
        k = draw(st.integers(0, vertices.size - 1))
        vertices = vertices.copy()
        vertices.flat[k] = noise.flat[k]
    faces = faces.copy()
    spoil = draw(st.sampled_from(["none", "reverse", "drop", "repeat", "flip one", "shift",
                                  "dtype", "empty"]))
    if spoil == "reverse":
        faces = faces[:, ::-1]
    elif spoil == "drop":
        faces = faces[:-1]
    elif spoil == "repeat":
        faces = np.vstack([faces, faces[:1]])
    elif spoil == "flip one":
        faces = np.vstack([faces[:-1], faces[-1:, ::-1]])
    elif spoil == "shift":
        faces = faces + draw(st.integers(-2, 2))
    elif spoil == "dtype":
        faces = faces.astype(draw(st.sampled_from([np.int32, np.uint16, np.float64, bool])))
    elif spoil == "empty":
        faces = np.zeros((0, 3), dtype=np.int64)
    return vertices, faces


@FUZZ
@given(
    meshes(),
    st.one_of(st.none(), FLOATS),
    st.one_of(st.none(), FLOATS),
    st.booleans(),
    st.one_of(st.booleans(), JUNK),
)
def test_meshes(mesh, density, mass, shell, fix_winding):
    vertices, faces = mesh
    finite = is_finite_input(vertices) and all(
        x is None or math.isfinite(x) for x in (density, mass)
    )
    body = call(ph.Body.mesh, vertices, faces, density=density, mass=mass, shell=shell,
                fix_winding=fix_winding, finite_input=finite, what="mesh")
    if body is not None:
        call(body.principal, finite_input=True, what="mesh.principal")


def parts():
    """A body part from the constructors, moved by drawn offsets and rotations."""
    return st.tuples(
        st.sampled_from([
            ph.Body.sphere(1.0, 1.0),
            ph.Body.rod(2.0, 3.0),
            ph.Body.point_masses([1e-12], [[0.0, 0.0, 0.0]]),
            ph.Body.cuboid(1e200, (1.0, 2.0, 3.0)),
            ph.Body.disk(1e-200, 1e-100),
        ]),
        st.one_of(vector3(FINITE), vector3(FLOATS)),
        st.one_of(st.just(np.eye(3)), vector3(st.floats(-1.0, 1.0)).map(
            lambda v: np.append(v, 0.5))),
    )


@FUZZ
@given(st.lists(parts(), min_size=1, max_size=4))
def test_composites(pieces):
    """Parts moved anywhere in the double range and added (and summed): the right composite,
    finite, or a typed error naming what overflows."""
    bodies = []
    for body, offset, rotation in pieces:
        moved = call(lambda b=body, o=offset, r=rotation: b.rotated(r).translated(o),
                     finite_input=is_finite_input(offset), what="rotated.translated")
        if moved is None:
            return
        bodies.append(moved)
    total = call(sum, bodies, finite_input=True, what="sum")
    if total is not None:
        call(total.principal, finite_input=True, what="composite.principal")
        call(total.inertia_about, (0.0, 0.0, 0.0), finite_input=True, what="inertia_about")


@FUZZ
@given(
    st.one_of(arrays(POSITIVE, st.sampled_from([(3,), (2, 3), (3, 3)])), anything()),
    st.one_of(arrays(st.floats(-10.0, 10.0), st.sampled_from([(1, 3), (2, 3), (3, 3)])),
              arrays(FLOATS, st.sampled_from([(2, 3), (3,), (0, 3)])), JUNK),
    st.sampled_from([None, 1, 2]),
    st.sampled_from(["exact", "rk4", "dop853"]),
)
def test_dask(body, omega0, chunks, method):
    """polhode.dask.simulate and .analyze on small batches, built and computed in process."""
    phd = pytest.importorskip("polhode.dask")
    finite = is_finite_input(body, omega0)

    def run_simulate():
        return phd.simulate(body, omega0, [0.0, 0.5], chunks=chunks, method=method,
                            dt=0.05 if method == "rk4" else None,
                            max_steps=20_000).compute(scheduler="sync")

    def run_analyze():
        result = phd.analyze(body, omega0, chunks=chunks).compute(scheduler="sync")
        # NaN stands for the None of polhode.analyze (documented): the other numbers must be
        # finite.
        return (result.moments, result.omega, result.energy, result.angular_momentum_norm)

    call(run_simulate, finite_input=finite, what=f"dask.simulate[{method}]")
    call(run_analyze, finite_input=finite, what="dask.analyze")


# The command line: words a user might type, in any order. The numbers stay where a run is
# short (a dop853 run to t = 1e90 would take its 1e8 steps): the fuzz is about parsing and the
# errors, the catalogue and test_cli about the long runs.
NUMBER_WORDS = ["0", "1", "2", "3", "-1", "0.5", "1e-300", "5e-324", "1e300", "nan", "inf",
                "-inf", "1e999", "x", "", "1,5", "0x10", "1e-3"]
SPIN_OPTIONS = {
    "--moments": 3, "--omega": 3, "--t": 1, "--points": 1, "--method": 1, "--dt": 1,
    "--order": 1, "--rtol": 1, "--body": 3, "--csv": 1, "--plot": 1, "--frobnicate": 0,
}
BODY_WORDS = ["sphere", "cylinder", "tube", "torus", "pyramid", "mass=1", "radius=0.1",
              "length=2", "radius=1e300", "radius=-1", "mass=nan", "inner_radius=2",
              "outer_radius=1", "major_radius=1", "minor_radius=2", "a=1", "b=2", "c=x", "="]
METHOD_WORDS = ["auto", "exact", "splitting", "midpoint", "rk4", "dop853", "euler", ""]


@st.composite
def command_lines(draw, folder):
    command = draw(st.sampled_from(["spin"] * 6 + ["demo", "bench", "frobnicate", ""]))
    words = [command] if command else []
    if command == "":  # no command: the help and status 2, or options before one
        return draw(st.lists(st.sampled_from(["--version", "--help", "-h", "--t", "x", "--"]),
                             max_size=3))
    if command == "demo":
        return [*words, "--no-plots", *draw(st.lists(st.sampled_from(["--out", "x", "-q"]),
                                                     max_size=2))]
    if command == "bench":  # only ever with a bad --repeats: a valid one runs the benchmarks
        return [*words, "--repeats", draw(st.sampled_from(["0", "-1", "x", "2.5", ""]))]
    for option in draw(st.lists(st.sampled_from(sorted(SPIN_OPTIONS)), max_size=7)):
        words.append(option)
        count = draw(st.integers(0, SPIN_OPTIONS[option] + 1))
        for _ in range(count):
            if option == "--method":
                words.append(draw(st.sampled_from(METHOD_WORDS)))
            elif option == "--body":
                words.append(draw(st.sampled_from(BODY_WORDS)))
            elif option in ("--csv", "--plot"):
                words.append(draw(st.sampled_from([
                    f"{folder}/run.csv", f"{folder}/run.png", f"{folder}/missing/run.png",
                    folder, "", f"{folder}/run.xyz"])))
            elif option == "--points":
                words.append(draw(st.sampled_from(["2", "3", "1", "0", "x", "1e3", "-5"])))
            elif option == "--t":
                words.append(draw(st.sampled_from(["0", "1", "2.5", "-1", "nan", "inf", "1e999",
                                                   "x", "1e-300", "20"])))
            else:
                words.append(draw(st.sampled_from(NUMBER_WORDS)))
    return words


_CLI_FOLDER = tempfile.mkdtemp(prefix="polhode-fuzz-cli-")
atexit.register(shutil.rmtree, _CLI_FOLDER, ignore_errors=True)


@FUZZ
@given(command_lines(_CLI_FOLDER))
def test_command_line(argv):
    """Any command line exits 0, or 2 with a one-line error (1 only for a failed write, which
    the paths here cannot cause), never with a traceback or another exception."""
    from polhode.cli import main

    note(f"polhode {' '.join(argv)}")
    out, errors = io.StringIO(), io.StringIO()
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(errors):
            code = main(argv)
    except BaseException as error:  # noqa: BLE001 - the point of the test
        pytest.fail(f"polhode {argv} raised {type(error).__name__}: {error}")
    stderr = errors.getvalue()
    assert code in (0, 2), (code, stderr)
    assert "Traceback" not in stderr, stderr
    if code == 2:
        assert "error" in stderr, stderr
    else:
        assert "nan" not in out.getvalue().lower().replace("nan)", ""), out.getvalue()

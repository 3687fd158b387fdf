"""read_mjcf against MuJoCo's compiled model, body by body (tests/mujoco_reference.py says how):
small files for every compiler attribute read_mjcf follows, and every MJCF file of the
installed corpus (mujoco's test data, gymnasium, gymnasium-robotics, dm-control).

The reference is MuJoCo 4.0.0 itself (``MjSpec.compile()``), never polhode; a few values are
also checked against closed forms (volumes of prisms, masses of spheres).
"""

from __future__ import annotations

import os
import struct
import warnings

import numpy as np
import pytest
from mujoco_reference import BOUND, compare, corpus, mujoco_compiles

import polhode as ph
from polhode.errors import FileFormatError

mujoco = pytest.importorskip("mujoco")


def read(path, **options):
    """read_mjcf, with any warning recorded rather than raised (but MuJoCo's own, once per
    process, that settotalmass is deprecated)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        bodies = ph.io.read_mjcf(path, **options)
    return bodies, [w.message for w in caught if "settotalmass" not in str(w.message)]


def check(tmp_path, xml, name="model.xml", fuse=None, **options):
    """Write ``xml``, read it, and hold every body to MuJoCo's compile of it."""
    path = tmp_path / name
    path.write_text(xml)
    if fuse is not None:
        options["merge_fixed"] = fuse
    bodies, caught = read(path, **options)
    result = compare(bodies, str(path), fuse=fuse)
    assert result.within(), result.mismatches
    assert result.bodies > 0
    return bodies, caught


def model(bodies, compiler="", assets="", extra=""):
    return (
        f"<mujoco><compiler {compiler}/><asset>{assets}</asset><worldbody>{bodies}</worldbody>"
        f"{extra}</mujoco>"
    )


def hinge(name, inner, pos="0 0 0"):
    return f'<body name="{name}" pos="{pos}"><joint type="hinge"/>{inner}</body>'


# --- meshes: an L and a U prism (non-convex), an open cube ------------------------------------

L_OUTLINE = [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]
L_CAPS = [(0, 2, 1), (0, 3, 2), (0, 5, 3), (3, 5, 4)]  # wound to -z
U_OUTLINE = [(0, 0), (3, 0), (3, 3), (2, 3), (2, 1), (1, 1), (1, 3), (0, 3)]
U_CAPS = [(1, 0, 4), (4, 0, 5), (2, 1, 4), (3, 2, 4), (5, 0, 7), (6, 5, 7)]


def prism(outline, caps):
    """Vertices and outward triangles of a unit-height prism over a polygon."""
    n = len(outline)
    vertices = [(x, y, 0.0) for x, y in outline] + [(x, y, 1.0) for x, y in outline]
    faces = [list(f) for f in caps] + [[c + n for c in f[::-1]] for f in caps]
    for i in range(n):
        j = (i + 1) % n
        faces += [[i, j, j + n], [i, j + n, i + n]]
    return np.array(vertices, float), np.array(faces)


def inline_mesh(name, vertices, faces, attrs=""):
    v = " ".join(repr(float(x)) for x in np.ravel(vertices))
    f = " ".join(str(int(i)) for i in np.ravel(faces))
    return f'<mesh name="{name}" vertex="{v}" face="{f}" {attrs}/>'


L_PRISM = prism(L_OUTLINE, L_CAPS)
U_PRISM = prism(U_OUTLINE, U_CAPS)


def test_the_prisms_are_closed_and_outward():
    for (vertices, faces), volume in ((L_PRISM, 3.0), (U_PRISM, 7.0)):
        body = ph.Body.mesh(vertices, faces, density=1.0)  # refuses an open or inverted mesh
        assert body.mass == pytest.approx(volume, rel=1e-15)


def write_stl(path, vertices, faces, bump=None):
    """A binary STL; ``bump`` (face, corner, value) rewrites one coordinate x of one corner."""
    out = bytearray(b"prism".ljust(80) + struct.pack("<I", len(faces)))
    for k, face in enumerate(faces):
        corners = [list(map(float, vertices[i])) for i in face]
        if bump is not None and bump[0] == k:
            corners[bump[1]][0] = bump[2]
        out += struct.pack("<3f", 0, 0, 0)
        for c in corners:
            out += struct.pack("<3f", *c)
        out += b"\0\0"
    path.write_bytes(bytes(out))


def write_msh(path, vertices, faces):
    """MuJoCo's MSH: counts, float32 vertices, int32 faces."""
    out = struct.pack("<4i", len(vertices), 0, 0, len(faces))
    out += np.asarray(vertices, "<f4").tobytes() + np.asarray(faces, "<i4").tobytes()
    path.write_bytes(out)


def obj_text(objects, quads=False):
    lines, base = [], 0
    for label, vertices, faces in objects:
        lines.append(label)
        lines += [f"v {float(x)!r} {float(y)!r} {float(z)!r}" for x, y, z in vertices]
        lines += [f"f {a + 1 + base} {b + 1 + base} {c + 1 + base}" for a, b, c in faces]
        base += len(vertices)
    return "\n".join(lines) + "\n"


# --- primitives, fromto, several geoms --------------------------------------------------------

PRIMITIVES = [("sphere", "0.1"), ("capsule", "0.05 0.1"), ("cylinder", "0.05 0.1"),
              ("ellipsoid", "0.1 0.2 0.3"), ("box", "0.1 0.2 0.3")]  # fmt: skip


@pytest.mark.parametrize("shell", ["false", "true"])
def test_primitives_solid_and_shell(tmp_path, shell):
    # One geom per body: MuJoCo keeps its moments unsorted in the geom frame; the shells are
    # MuJoCo's formulas (the ellipsoid's area is Thomsen's approximation).
    inner = "".join(
        hinge(f"{kind}", f'<geom type="{kind}" size="{size}" density="700" '
                         f'shellinertia="{shell}" pos="0.1 0 0" euler="10 20 30"/>')
        for kind, size in PRIMITIVES
    )  # fmt: skip
    bodies, _ = check(tmp_path, model(inner))
    if shell == "false":
        assert bodies["sphere"].mass == pytest.approx(700 * 4 / 3 * np.pi * 1e-3, rel=1e-15)
    else:
        assert bodies["sphere"].mass == pytest.approx(700 * 4 * np.pi * 1e-2, rel=1e-15)


def test_fromto_and_several_rotated_geoms(tmp_path):
    inner = "".join(
        hinge(kind, f'<geom type="{kind}" fromto="0.1 0.2 0.3 0.4 -0.1 0.5" size="0.05"/>'
                    '<geom type="sphere" size="0.01" pos="1 0 0" mass="1e-3"/>')
        for kind in ("capsule", "cylinder", "box", "ellipsoid")
    )  # fmt: skip
    inner += hinge(
        "three",
        '<geom type="box" size=".1 .2 .3" pos=".1 0 0" euler="10 20 30"/>'
        '<geom type="capsule" size=".05 .2" pos="0 .3 0" quat="0.9 0.1 0.3 0.2"/>'
        '<geom type="ellipsoid" size=".1 .05 .02" pos="0 0 -.2" axisangle="1 1 0 45"/>'
        '<geom type="cylinder" size=".05 .1" pos="0 0 .3" xyaxes="0 1 0 -1 0 1"/>'
        '<geom type="box" size=".05 .1 .02" pos="0.2 0 .3" zaxis="1 1 1"/>',
    )
    check(tmp_path, model(inner, 'angle="degree" eulerseq="zyx"'))
    check(tmp_path, model(inner.replace('"1 1 0 45"', '"1 1 0 0.7"'), 'angle="radian"'))


# --- inertiafromgeom, inertiagrouprange, classes, geom mass -----------------------------------


@pytest.mark.parametrize("flag", ["auto", "true", "false"])
def test_inertiafromgeom(tmp_path, flag):
    inner = (
        hinge("both", '<inertial pos="0 0 .5" mass="3" diaginertia="1 2 2.5"/>'
                      '<geom type="sphere" size=".1"/>')
        # true keeps the <inertial> when no geom is selected (group 4 is out of range)
        + hinge("out_of_range", '<inertial pos="0 0 .5" mass="3" diaginertia="1 2 2.5"/>'
                                '<geom type="sphere" size=".1" group="4"/>')
        + hinge("geoms_only", '<geom type="box" size=".1 .2 .3"/>', pos="1 0 0")
        + '<body name="static"><geom type="sphere" size=".2"/></body>'
    )  # fmt: skip
    if flag == "false":
        inner = inner.replace(hinge("geoms_only", '<geom type="box" size=".1 .2 .3"/>',
                                    pos="1 0 0"), "")  # fmt: skip
    bodies, _ = check(tmp_path, model(inner, f'inertiafromgeom="{flag}" inertiagrouprange="0 3"'))
    expected = {"auto": 3.0, "true": 4000 * np.pi / 3 * 1e-3, "false": 3.0}[flag]
    assert bodies["both"].mass == pytest.approx(expected, rel=1e-15)
    assert bodies["out_of_range"].mass == 3.0
    assert ("static" in bodies.frames) == (flag == "false")


@pytest.mark.parametrize("groups", ["0 5", "0 2", "3 5", "6 6"])
def test_inertiagrouprange(tmp_path, groups):
    inner = hinge(
        "b",
        '<geom type="sphere" size=".1" group="3"/><geom type="box" size=".1 .1 .1" pos="1 0 0"/>'
        '<geom type="sphere" size=".2" group="6" pos="0 1 0"/><geom size=".1" group="2"/>',
    )
    inner += '<body name="s" pos="0 0 1"><geom type="box" size=".1 .2 .3" group="5"/></body>'
    bodies, _ = check(tmp_path, model(inner, f'inertiagrouprange="{groups}"'))
    assert ("s" in bodies) == (groups in ("0 5", "3 5"))


def test_defaults_classes_and_geom_mass(tmp_path):
    xml = """<mujoco>
      <default><geom density="500"/>
        <default class="heavy"><geom density="8000"/></default>
        <default class="m2"><geom mass="2"/></default>
        <default class="boxes"><geom type="box" size="0.1 0.05 0.2" euler="0 30 0"/></default>
      </default>
      <worldbody>
        <body name="a" childclass="heavy"><joint/><geom type="sphere" size=".1"/>
          <geom class="main" type="sphere" size=".1" pos="1 0 0"/></body>
        <body name="b"><joint/><geom class="m2" type="box" size=".1 .2 .3"/>
          <geom type="box" size=".1 .2 .3" mass="0" pos="0 0 1"/>
          <geom type="box" size=".1 .1 .1" density="0" pos="0 1 0"/></body>
        <body name="c" childclass="boxes"><joint/><geom/>
          <geom class="m2" type="capsule" size=".1 .1" pos="0 0 .3"/></body>
      </worldbody></mujoco>"""
    bodies, _ = check(tmp_path, xml)
    assert bodies["a"].mass == pytest.approx(8500 * 4 / 3 * np.pi * 1e-3, rel=1e-15)
    assert bodies["b"].mass == 2.0


def test_a_geom_mass_on_no_volume_is_dropped_as_mujoco_does(tmp_path):
    # Two spheres with mass="1": radius 1e-5 has a volume of 4.2e-15 <= 1e-14, and MuJoCo
    # gives it no mass; a plane's mass too. read_mjcf does the same and says so in notes.
    inner = hinge("b", '<geom name="tiny" size="1e-5" mass="1"/><geom size="0.1" mass="1"/>')
    inner += '<body name="floor"><geom type="plane" size="1 1 .1" mass="3"/></body>'
    bodies, _ = check(tmp_path, model(inner))
    assert bodies["b"].mass == 1.0 and list(bodies.frames) == ["floor"]
    assert any("geom 'tiny'" in note and "dropped" in note for note in bodies.notes["b"])
    # radius 2e-5: 3.4e-14, above: both count.
    bodies, _ = check(tmp_path, model(inner.replace("1e-5", "2e-5")))
    assert bodies["b"].mass == 2.0


# --- bounds, balance, settotalmass ------------------------------------------------------------


@pytest.mark.parametrize(
    "compiler",
    ['boundmass="0.5"', 'boundinertia="0.01"', 'boundmass="0.5" boundinertia="0.01"',
     'balanceinertia="true"', 'balanceinertia="true" boundinertia="2"'],
)  # fmt: skip
def test_bounds_and_balance(tmp_path, compiler):
    inner = (
        hinge("moving", '<inertial pos="0 0 0" mass="0.1" diaginertia="1e-3 2e-3 2.5e-3"/>')
        + '<body name="static" pos="1 2 3"><inertial pos=".1 0 0" quat="0.9 0.1 0.2 0.3" '
          'mass="0.1" diaginertia="1e-3 1e-3 1e-3"/></body>'
        + hinge("geoms", '<geom type="box" size=".001 .2 .3"/><geom size=".01" pos="0 0 .4"/>')
        + '<body name="frame" pos="1 2 3" euler="10 20 30"/>'
    )  # fmt: skip
    if "balance" in compiler:
        inner += hinge("flat", '<inertial pos="0 0 0" mass="1" diaginertia="1 1 3"/>')
    bodies, _ = check(tmp_path, model(inner, compiler))
    if "boundmass" in compiler:
        # A body of no mass gets boundmass, and MuJoCo puts it at the body's own position
        # (its inertial frame is a copy of the body frame): so does read_mjcf.
        assert bodies["frame"].mass == 0.5
        np.testing.assert_array_equal(bodies["frame"].center_of_mass, [1, 2, 3])
    if "balance" in compiler:  # (1, 1, 3) averaged; bounded to (2, 2, 3) it needs no balance
        expected = [2, 2, 3] if "boundinertia" in compiler else [5 / 3] * 3
        assert bodies["flat"].principal().moments.tolist() == pytest.approx(expected, 1e-15)


def test_negative_values_become_zero_as_mujoco_bounds_them(tmp_path):
    inner = '<body name="n"><inertial pos="0 0 0" mass="-1" diaginertia="-1 1 1"/></body>'
    inner += hinge("ok", '<geom size=".1"/>')
    bodies, caught = check(tmp_path, model(inner))
    assert list(bodies.frames) == ["n"] and "negative mass" in bodies.notes["n"][0]
    assert len(caught) == 1 and isinstance(caught[0], ph.RobotFileWarning)
    with pytest.raises(FileFormatError) as error:
        ph.io.read_mjcf(tmp_path / "model.xml", strict=True)
    assert (error.value.link, error.value.field) == ("n", "inertial.mass")


def test_fullinertia_bounded_when_only_semidefinite(tmp_path):
    # 4.0.0: with boundinertia > 0 a positive semidefinite fullinertia is bounded.
    inner = hinge("b", '<inertial pos="0 0 0" mass="1" fullinertia="1 .5 .5 0 0 .5"/>')
    check(tmp_path, model(inner, 'boundinertia="1e-6"'))
    path = tmp_path / "refused.xml"
    path.write_text(model(inner + hinge("ok", '<geom size=".1"/>')))
    with pytest.raises(ValueError, match="positive eigenvalues"):
        mujoco.MjModel.from_xml_path(str(path))
    bodies, caught = read(path)
    assert list(bodies) == ["ok"] and "positive" in bodies.left_out["b"]


def test_settotalmass_scales_static_bodies_too(tmp_path):
    inner = '<body name="s"><geom size=".1"/></body>' + hinge("a", '<geom size=".2"/>')
    inner += '<body name="e"><inertial pos="0 0 0" mass="2" diaginertia="1 1 1"/></body>'
    bodies, _ = check(tmp_path, model(inner, 'settotalmass="10"'))
    assert sum(b.mass for b in bodies.values()) == pytest.approx(10.0, rel=1e-15)


# --- meshes -----------------------------------------------------------------------------------


@pytest.mark.parametrize("mode", ["legacy", "exact", "convex", "shell"])
@pytest.mark.parametrize("shape", ["L", "U"])
def test_mesh_inertia_modes(tmp_path, mode, shape):
    vertices, faces = L_PRISM if shape == "L" else U_PRISM
    assets = inline_mesh("m", vertices, faces, f'inertia="{mode}"')
    inner = hinge("b", '<geom type="mesh" mesh="m" pos="0.1 0.2 0.3" euler="10 0 0"/>')
    inner += hinge("two", '<geom type="mesh" mesh="m"/><geom size=".3" pos="0 0 2"/>')
    bodies, _ = check(tmp_path, model(inner, assets=assets))
    volume = {"L": 3.0, "U": 7.0}[shape]
    measure = bodies["b"].mass / 1000
    if mode == "exact":
        assert measure == pytest.approx(volume, rel=1e-15)
    if mode == "legacy":  # the U prism is not seen whole from its faces' centroid
        assert (measure > 1.2 * volume) == (shape == "U")
    if mode == "convex":
        assert measure == pytest.approx({"L": 3.5, "U": 9.0}[shape], rel=1e-15)
    found = ph.io.legacy_mesh_inertia(tmp_path / "model.xml")
    if mode == "legacy":
        assert sorted(found) == ["b", "two"]
        assert found["b"].exact.mass == pytest.approx(1000 * volume, rel=1e-14)
        assert found["b"].legacy.mass == bodies["b"].mass
        assert (found["b"].mass_error > 0.2) == (shape == "U")
    else:
        assert found == {}


@pytest.mark.parametrize(
    "attrs",
    ['scale="0.5 2 -1"', 'refpos="1 1 0"', 'refquat="0.9 0.1 0.2 0.3"',
     'scale="0.1 0.2 0.3" refpos="0.5 0.5 0.5" refquat="0 1 0 1"'],
)  # fmt: skip
@pytest.mark.parametrize("mode", ["legacy", "exact"])
def test_mesh_scale_refpos_refquat(tmp_path, attrs, mode):
    assets = inline_mesh("m", *U_PRISM, f'inertia="{mode}" {attrs}')
    inner = hinge("b", '<geom type="mesh" mesh="m" pos="0.1 0.2 0.3" euler="10 0 0"/>')
    check(tmp_path, model(inner, assets=assets))


def test_open_mesh_and_point_cloud(tmp_path):
    # An open cube (top face missing): MuJoCo integrates it all the same (exact and legacy
    # depend on its faces' centroid); a cloud of points is its convex hull.
    cube = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1],
                     [1, 1, 1], [0, 1, 1]], float)  # fmt: skip
    open_faces = [[0, 2, 1], [0, 3, 2], [0, 1, 5], [0, 5, 4], [1, 2, 6], [1, 6, 5],
                  [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7]]  # fmt: skip
    assets = "".join(
        inline_mesh(mode, cube, open_faces, f'inertia="{mode}"')
        for mode in ("legacy", "exact", "convex", "shell")
    )
    assets += f'<mesh name="cloud" vertex="{" ".join(map(str, np.ravel(cube)))}"/>'
    inner = "".join(
        hinge(m, f'<geom type="mesh" mesh="{m}"/>')
        for m in ("legacy", "exact", "convex", "shell", "cloud")
    )
    bodies, _ = check(tmp_path, model(inner, assets=assets))
    assert bodies["cloud"].mass == pytest.approx(1000.0, rel=1e-14)
    assert bodies["exact"].mass == pytest.approx(804.1666666666, rel=1e-9)
    assert any("not closed" in n or "cannot integrate" in n for n in bodies.notes["exact"])


def test_mesh_files_stl_obj_msh(tmp_path):
    vertices, faces = U_PRISM
    odd = vertices * [0.1234567891234567, 0.2345678912345678, 0.3456789123456789]
    (tmp_path / "meshes").mkdir()
    write_stl(tmp_path / "meshes" / "u.stl", vertices, faces)
    # 0.0 written as -0.0 in one facet: MuJoCo keeps two vertices (its bit pattern), which
    # changes nothing in the integrals.
    write_stl(tmp_path / "meshes" / "signed.stl", vertices, faces, bump=(4, 0, -0.0))
    write_msh(tmp_path / "meshes" / "u.msh", vertices, faces)
    # OBJ text in double precision: MuJoCo keeps float32 vertices (6e-9 apart, here).
    (tmp_path / "meshes" / "odd.obj").write_text(obj_text([("o odd", odd, faces)]))
    # Two objects: MuJoCo takes the faces of the first only (and every vertex for a hull).
    two = obj_text([("o first", vertices, faces), ("o second", vertices + [5, 0, 0], faces)])
    (tmp_path / "meshes" / "two.obj").write_text(two)
    (tmp_path / "meshes" / "groups.obj").write_text(two.replace("o ", "g "))
    # Quads: MuJoCo splits them (0, 1, 2), (0, 2, 3).
    quad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
    quad += "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n"
    (tmp_path / "meshes" / "quads.obj").write_text(quad)
    assets = "".join(
        f'<mesh name="{n}_{mode}" file="{n}" inertia="{mode}"/>'
        for n in ("u.stl", "signed.stl", "u.msh", "odd.obj", "two.obj", "groups.obj",
                  "quads.obj")
        for mode in ("legacy", "exact", "convex")
    )  # fmt: skip
    inner = "".join(
        hinge(f"{n}_{mode}", f'<geom type="mesh" mesh="{n}_{mode}"/>')
        for n in ("u.stl", "signed.stl", "u.msh", "odd.obj", "two.obj", "groups.obj",
                  "quads.obj")
        for mode in ("legacy", "exact", "convex")
    )  # fmt: skip
    bodies, _ = check(tmp_path, model(inner, 'meshdir="meshes"', assets))
    assert bodies["two.obj_exact"].mass == pytest.approx(7000.0, rel=1e-14)  # one U
    assert bodies["quads.obj_exact"].mass == pytest.approx(1000.0, rel=1e-14)
    # float32: the OBJ's double-precision prism differs from MuJoCo's by ~1e-8, not 1e-15.
    exact64 = ph.Body.mesh(odd, faces, density=1000.0).mass
    assert abs(bodies["odd.obj_exact"].mass / exact64 - 1) > 1e-10


def test_convex_hull_with_maxhullvert_and_scaled_shells(tmp_path):
    # A hull of at most 12 vertices (Qhull's "Q9 TA8", as MuJoCo asks it); shells and mesh
    # shells in a scaling frame (a density per area goes as massscale / scale^2); a mirrored
    # mesh with a mass in a scaling frame.
    cloud = np.random.default_rng(1).normal(size=(200, 3)) * [1, 2, 3]
    vertices = " ".join(repr(float(x)) for x in cloud.ravel())
    assets = f'<mesh name="c" vertex="{vertices}" maxhullvert="12" inertia="convex"/>'
    assets += inline_mesh("shell", *U_PRISM, 'inertia="shell"')
    assets += inline_mesh("mirror", *U_PRISM, 'scale="1 -1 1"')
    inner = hinge("hull", '<geom type="mesh" mesh="c"/>') + (
        '<frame scale="2" massscale="5">'
        + hinge("shells", '<geom type="capsule" size=".1 .2" shellinertia="true"/>'
                          '<geom type="box" size=".1 .2 .3" shellinertia="true" pos="1 0 0"/>'
                          '<geom type="mesh" mesh="shell" pos="0 2 0"/>')
        + hinge("mirror", '<geom type="mesh" mesh="mirror" mass="3" pos="1 0 0"/>')
        + "</frame>"
    )  # fmt: skip
    check(tmp_path, model(inner, assets=assets))


def test_ascii_stl_is_left_out_as_mujoco_refuses_it(tmp_path):
    facet = "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
    (tmp_path / "a.stl").write_text(f"solid a\n{facet}endloop\nendfacet\nendsolid a\n")
    path = tmp_path / "m.xml"
    path.write_text(
        model(
            hinge("b", '<geom type="mesh" mesh="a"/>') + hinge("ok", '<geom size=".1"/>'),
            assets='<mesh name="a" file="a.stl"/>',
        )  # fmt: skip
    )
    with pytest.raises(ValueError):
        mujoco.MjModel.from_xml_path(str(path))
    bodies, caught = read(path)
    assert list(bodies) == ["ok"] and "ASCII" in bodies.left_out["b"]


@pytest.mark.parametrize("kind", ["box", "sphere", "capsule", "cylinder", "ellipsoid"])
@pytest.mark.parametrize("compiler", ["", 'fitaabb="true"'])
def test_primitives_fitted_to_a_mesh(tmp_path, kind, compiler):
    # Stretched along z, so that a capsule fitted to its box has a positive half-length.
    assets = inline_mesh("m", *U_PRISM, 'scale="0.3 0.3 2"')
    inner = hinge("b", f'<geom type="{kind}" mesh="m" pos="0 0 1" euler="0 30 0"/>')
    inner += hinge("scaled", f'<geom type="{kind}" mesh="m" fitscale="1.3" mass="2"/>')
    check(tmp_path, model(inner, compiler, assets))


def test_height_field_weighs_as_mujocos_box(tmp_path):
    assets = '<hfield name="h" nrow="3" ncol="3" size="1 2 0.4 0.2"/>'
    inner = hinge("b", '<geom type="hfield" hfield="h" pos="0 0 1"/>')
    bodies, _ = check(tmp_path, model("", assets=assets).replace(
        "<worldbody></worldbody>", f"<worldbody>{inner}</worldbody>"))  # fmt: skip
    assert bodies["b"].mass == pytest.approx(3200.0, rel=1e-14)


# --- frames -----------------------------------------------------------------------------------


def test_frames_inside_and_around_bodies(tmp_path):
    xml = model(
        '<frame pos="1 0 0" euler="0 0 30"><body name="a" pos="0 1 0"><joint/>'
        '<frame pos="0.1 0 0" euler="0 0 0.7"><frame pos="0 0.2 0" quat="0.9 0.3 0.1 -0.2">'
        '<geom type="box" size="0.1 0.05 0.02" pos="0 0 0.1" euler="20 10 0"/></frame>'
        '<geom type="ellipsoid" size="0.05 0.1 0.15" pos="0 0 -0.1"/></frame></body></frame>'
    )
    check(tmp_path, xml)


@pytest.mark.parametrize(
    "attrs", ['scale="2"', 'scale="2" massscale="1"', 'scale="0.5" massscale="3"',
              'massscale="3" scaling="geometry"'],
)  # fmt: skip
def test_frames_that_scale_their_contents(tmp_path, attrs):
    assets = inline_mesh("m", *L_PRISM, 'scale="0.1 0.1 0.1"')
    xml = model(
        f'<frame pos="1 0 0" {attrs}><body name="b" pos="0 1 0" euler="0 0 30"><joint/>'
        '<geom type="box" size=".1 .2 .3" pos=".1 0 0"/>'
        '<geom type="capsule" size=".05" fromto="0 0 0 .3 .2 .1" mass="2"/>'
        '<geom type="mesh" mesh="m" pos="0 0 -.3"/><geom type="cylinder" mesh="m" pos=".3 0 0"/>'
        '<body name="c" pos="0 0 1"><joint/><inertial pos=".1 .2 .3" mass="2" '
        'diaginertia=".1 .2 .25"/></body>'
        '<body name="d" pos="0 0 1"><joint/><frame pos="0.1 0 0" scale="3">'
        '<geom type="sphere" size=".1" pos="0 0 .1"/></frame></body>'
        "</body></frame>",
        assets=assets,
    )
    check(tmp_path, xml)


def test_a_stretching_frame_is_refused_by_name(tmp_path):
    xml = model('<frame scale="1 2 3" scaling="geometry"><body name="b"><joint/>'
                '<geom type="box" size=".1 .2 .3"/></body></frame>')  # fmt: skip
    path = tmp_path / "m.xml"
    path.write_text(xml)
    mujoco.MjModel.from_xml_path(str(path))  # MuJoCo compiles it
    with pytest.raises(FileFormatError, match="stretches") as error:
        ph.io.read_mjcf(path)
    assert (error.value.link, error.value.field) == ("b", "frame.scale")


# --- moving bodies MuJoCo refuses, frames, alignment ------------------------------------------


def test_moving_bodies_without_mass(tmp_path):
    inner = (
        hinge("carried", '<body name="payload"><geom size=".1"/></body>')  # fine: a frame
        + hinge("alone", "")
        + hinge("moving_child_only", hinge("child", '<geom size=".1"/>'))
        + hinge("point", '<inertial pos="0 0 0" mass="1" diaginertia="0 0 0"/>')
        + hinge("thin", '<inertial pos="0 0 0" mass="1" diaginertia="1 1 1e-16"/>')
        + '<body name="static"/>'
    )
    path = tmp_path / "m.xml"
    path.write_text(model(inner))
    with pytest.raises(ValueError, match="mjMINVAL"):
        mujoco.MjModel.from_xml_path(str(path))
    bodies, caught = read(path)
    assert list(bodies) == ["payload", "child"]
    assert bodies.frames == {
        "carried": "mass 0: a moving body whose mass is on the bodies fixed to it",
        "static": "mass 0: a body without joints",
    }
    assert sorted(bodies.left_out) == ["alone", "moving_child_only", "point", "thin"]
    assert all("mjMINVAL" in why for why in bodies.left_out.values())
    [warning] = caught
    assert isinstance(warning, ph.RobotFileWarning) and sorted(warning.links) == sorted(
        bodies.left_out
    )
    with pytest.raises(FileFormatError, match="mjMINVAL") as error:
        ph.io.read_mjcf(path, strict=True)
    assert error.value.link == "alone"


def test_free_bodies_aligned_by_mujoco_compare_in_the_world(tmp_path):
    inner = ('<body name="b" pos="0.5 0 0" euler="0 0 30"><freejoint align="true"/>'
             '<geom type="box" size=".1 .2 .3" pos=".5 .1 0" euler="10 0 0"/></body>')  # fmt: skip
    bodies, _ = check(tmp_path, model(inner, 'alignfree="true"'))
    np.testing.assert_allclose(bodies["b"].center_of_mass, [0.5, 0.1, 0], rtol=0, atol=1e-15)


def test_both_diaginertia_and_fullinertia_name_the_body(tmp_path):
    # The file's fullinertia was once taken without a word; MuJoCo refuses the model.
    path = tmp_path / "m.xml"
    path.write_text(model(hinge("arm", '<inertial pos="0 0 0" mass="1" diaginertia="1 1 1" '
                                       'fullinertia="1 1 1 0 0 0"/>')))  # fmt: skip
    with pytest.raises(ValueError, match="cannot both be specified"):
        mujoco.MjModel.from_xml_path(str(path))
    for as_written in (False, True):
        with pytest.raises(FileFormatError, match="both diaginertia") as error:
            ph.io.read_mjcf(path, as_written=as_written)
        assert (error.value.link, error.value.field) == ("arm", "inertial.diaginertia")


# --- fusestatic and merge_fixed ---------------------------------------------------------------

FUSED = """<mujoco><compiler {compiler}/><worldbody>
  <body name="base" pos="0 0 1"><geom type="box" size=".2 .2 .05"/>
    <body name="arm" pos="0 0 .1"><joint/><geom type="capsule" fromto="0 0 0 0 0 .5" size=".05"/>
      <body name="camera" pos="0 .05 .4" euler="30 0 90"><geom type="box" size=".02 .03 .04"/>
        <body name="lens" pos="0 0 .05"><inertial pos="0 0 .01" mass=".05"
              diaginertia="1e-5 1e-5 2e-5"/></body></body>
      <body name="tool" pos="0 0 .5" quat="0.9 0.1 0.2 0.3"><inertial pos=".01 0 .02"
            quat="0.7 0 0.7 0" mass=".3" diaginertia="1e-3 2e-3 2.5e-3"/>
        <body name="tip" pos="0 0 .1"/>
        <body name="kept" pos="0 0 .1" fuse="false"><geom size=".02"/></body>
        <body name="sensed" pos="0 0 .2"><geom size=".01"/></body></body>
      <body name="forearm" pos="0 0 .5"><joint/><geom type="box" size=".05 .05 .2"/>
        <body name="wrist"><geom size=".04"/></body></body>
    </body></body></worldbody>
  <sensor><framepos objtype="body" objname="sensed"/></sensor></mujoco>"""


@pytest.mark.parametrize("how", ["file", "merge_fixed"])
def test_fusestatic_as_mujoco(tmp_path, how):
    compiler = 'fusestatic="true"' if how == "file" else ""
    bodies, _ = check(
        tmp_path, FUSED.format(compiler=compiler), fuse=True if how == "merge_fixed" else None
    )
    assert list(bodies) == ["arm", "kept", "sensed", "forearm"]
    assert bodies.merged == {"base": "world", "camera": "arm", "lens": "arm", "tool": "arm",
                             "tip": "arm", "wrist": "forearm"}  # fmt: skip
    assert bodies.frames == {}


def _fused(compiler, inner):
    return (
        f'<mujoco><compiler fusestatic="true" {compiler}/><worldbody>{inner}</worldbody></mujoco>'
    )


FUSING = {
    # inertiafromgeom="true": MuJoCo infers the fused body again from all the geoms; the
    # <inertial>s of the bodies fused into it are lost, unless no geom at all counts.
    "ifg-true-child-inertial": _fused('inertiafromgeom="true"', hinge(
        "p", '<geom size=".1"/><body name="c" pos="1 0 0"><inertial pos="0 0 0" mass="2" '
             'diaginertia="1 1 1"/></body>')),
    "ifg-true-child-geom-out-of-range": _fused('inertiafromgeom="true" inertiagrouprange="0 2"',
        hinge("p", '<geom size=".1"/><body name="c" pos="1 0 0"><inertial pos="0 0 0" '
                   'mass="2" diaginertia="1 1 1"/><geom size=".3" group="4"/></body>')),
    "ifg-true-no-geoms": _fused('inertiafromgeom="true"', hinge(
        "p", '<inertial pos="0 0 0" mass="1" diaginertia="1 1 1"/><body name="c" pos="1 0 0">'
             '<inertial pos="0 0 0" mass="2" diaginertia="1 1 1"/></body>')),
    "ifg-true-parent-inertial": _fused('inertiafromgeom="true"', hinge(
        "p", '<inertial pos="0 0 0" mass="1" diaginertia="1 1 1"/><body name="c" pos="1 0 0">'
             '<geom size=".1"/></body>')),
    # MuJoCo does not fuse a body whose bounds changed its inertia with inertiafromgeom="true",
    # nor one with a gravcomp of its own.
    "ifg-true-bounds": _fused('inertiafromgeom="true" boundmass="0.5"', hinge(
        "p", '<geom size=".1"/><body name="c" pos="1 0 0"><geom size=".01"/></body>')),
    "gravcomp": _fused("", hinge(
        "p", '<geom size=".1"/><body name="c" pos="1 0 0" gravcomp="1"><geom size=".1"/></body>')),
}  # fmt: skip


@pytest.mark.parametrize("xml", FUSING.values(), ids=FUSING.keys())
def test_fusing_follows_mujocos_exceptions(tmp_path, xml):
    check(tmp_path, xml)


def test_merge_fixed_false_overrides_the_file(tmp_path):
    bodies, _ = check(tmp_path, FUSED.format(compiler='fusestatic="true"').replace(
        "<compiler", '<compiler inertiafromgeom="auto"'), fuse=False)  # fmt: skip
    assert "camera" in bodies and bodies.merged == {}


def test_as_written_keeps_the_files_values(tmp_path):
    inner = hinge(
        "arm",
        '<inertial pos="0 0 0.1" mass="2" diaginertia="0.02 0.02 0.01"/>'
        '<geom type="box" size="0.05 0.05 0.2" pos="0 0 0.2" density="500"/>',
    )
    path = tmp_path / "m.xml"
    path.write_text(model(inner, 'inertiafromgeom="true" settotalmass="7"'))
    written = ph.io.read_mjcf(path, as_written=True)["arm"]
    assert written.mass == 2.0 and written.center_of_mass.tolist() == [0, 0, 0.1]
    assert read(path)[0]["arm"].mass == pytest.approx(7.0, rel=1e-15)
    with pytest.raises(ph.ArgumentError):
        ph.io.read_mjcf(path, as_written=True, merge_fixed=True)


# --- the installed corpus ---------------------------------------------------------------------

CORPUS = [(label, path) for label, files in corpus().items() for path in files]


def _id(item):
    label, path = item
    return f"{label}:{os.path.relpath(path, os.path.dirname(path) + '/../..')}"


@pytest.mark.parametrize("item", CORPUS, ids=[_id(i) for i in CORPUS])
def test_corpus_files_as_mujoco_compiles_them(item):
    """Every body of every file MuJoCo compiles; the files MuJoCo refuses (include fragments,
    missing assets) are refused by read_mjcf too, or read (it reads a file whose
    meshes need not all load)."""
    _, path = item
    compiled, why = mujoco_compiles(path)
    if compiled is None:
        # Read all the same, with the bodies MuJoCo refuses left out and named, or refused as
        # a file with an error naming it (not a robot description: a fragment, a parse error).
        try:
            bodies, caught = read(path)
        except (FileFormatError, FileNotFoundError) as error:
            assert path in str(error) or os.path.basename(path) in str(error)
            return
        assert all(isinstance(w, ph.RobotFileWarning) for w in caught)
        assert sorted(bodies.left_out) == sorted(w for c in caught for w in c.links)
        return
    bodies, caught = read(path)
    assert not caught, [str(w) for w in caught]
    result = compare(bodies, path)
    assert result.within(), result.mismatches
    assert result.mass <= BOUND and result.center <= BOUND


@pytest.mark.parametrize("item", CORPUS, ids=[_id(i) for i in CORPUS])
def test_corpus_files_merged_as_mujocos_fusestatic(item):
    """merge_fixed=True against MuJoCo's compile with fusestatic="true"."""
    _, path = item
    compiled, why = mujoco_compiles(path)
    if compiled is None:
        pytest.skip(f"MuJoCo refuses it: {why}")
    bodies, caught = read(path, merge_fixed=True)
    assert not caught, [str(w) for w in caught]
    result = compare(bodies, path, fuse=True)
    assert result.within(), result.mismatches


def test_the_corpus_is_there():
    found = corpus()
    assert len(found.get("gymnasium", [])) >= 10 and len(found.get("mujoco testdata", [])) >= 1


def test_command_line_reads_as_mujoco_and_as_written_with_a_density(tmp_path, capsys):
    import json

    from polhode.cli import main

    inner = hinge(
        "arm",
        '<inertial pos="0 0 0.1" mass="2" diaginertia="0.02 0.02 0.01"/>'
        '<geom type="box" size="0.05 0.05 0.2" pos="0 0 0.2" density="500"/>',
    )
    inner += hinge("ball", '<geom type="sphere" size="0.1" density="300"/>', pos="1 0 0")
    path = tmp_path / "m.xml"
    path.write_text(model(inner, 'inertiafromgeom="true"'))

    def links(*options):
        assert main(["inertia", str(path), "--json", *options]) == 0
        return json.loads(capsys.readouterr().out)["links"]

    compiled = links()
    assert compiled["arm"]["mass"] == pytest.approx(2.0, rel=1e-15)  # the box: 500 x 0.004
    assert compiled["arm"]["center_of_mass"] == [0.0, 0.0, 0.2]
    written = links("--density", "1000")  # as written: the <inertial>, the ball at 1000
    assert written["arm"]["center_of_mass"] == [0.0, 0.0, 0.1]
    assert written["ball"]["mass"] == pytest.approx(4000 / 3 * np.pi * 1e-3, rel=1e-15)

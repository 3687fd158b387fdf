"""Every URDF file of the installed corpus (tests/corpus.py: upkie_description,
cookie_description, jvrc_description, airo-models, as the test extra pins them) is read, merged
and audited, with the findings expected of each package.

The expected figures were taken on the pinned versions and checked by hand against the files:
airo-models' camera, mounting-plate and fingertip links give a <mass> and no <inertia> (MuJoCo
and urdfdom refuse those files), its Schunk gripper's finger mounts are moving links without an
inertial; jvrc's meshes are all DAE (which polhode does not read) and its 15 massless links are
on fixed joints or the root; upkie's and cookie's point masses are frames with a nominal 1 g on
fixed joints; their femurs and tibias declare the tensor of a cylinder ten times shorter than
their collision cylinder (test_io_robots.test_audit_of_upkie).
"""

from __future__ import annotations

import collections
import os
import warnings

import pytest

import polhode as ph
from corpus import files

pytest.importorskip("yourdfpy")

URDFS = files("urdf")

#: Per package: files; bodies, frames and links left out by read_urdf; parts with merge_fixed;
#: audit findings by severity.
EXPECTED = {
    "airo_models": dict(files=16, bodies=31, frames=39, left_out=14, parts=25,
                        error=14, warning=36, info=39, ok=5),
    "cookie_description": dict(files=1, bodies=62, frames=0, left_out=0, parts=7,
                               error=0, warning=4, info=4, ok=54),
    "jvrc_description": dict(files=1, bodies=45, frames=15, left_out=0, parts=45,
                             error=0, warning=0, info=50, ok=10),
    "upkie_description": dict(files=2, bodies=84, frames=0, left_out=0, parts=14,
                              error=0, warning=9, info=17, ok=58),
}  # fmt: skip

#: Links every simulator refuses, left out and named (file, link, the start of the reason).
KNOWN_LEFT_OUT = [
    ("cameras/realsense/d435/d435.urdf", "d435_link", "inertial.inertia: the <inertial> has no"),
    ("grippers/schunk_egk40/urdf/schunk_egk40.urdf", "right_finger_mount",
     "inertial: a moving link without mass"),
    ("grippers/schunk_egk40/urdf/schunk_egk40.urdf", "base_link", "inertial.inertia:"),
]  # fmt: skip


def read(path, **kwargs):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        links = ph.io.read_urdf(path, **kwargs)
    ours = [w for w in caught if issubclass(w.category, ph.RobotFileWarning)]
    assert len(ours) == len(caught), [str(w.message) for w in caught]
    return links, ours


@pytest.fixture(scope="module")
def corpus():
    """Per file: the links read, the parts merged, the warnings and the audit."""
    if not URDFS:
        pytest.skip("no URDF corpus installed (pip install 'polhode[test]')")
    out = {}
    for package, path in URDFS:
        links, warned = read(path)
        parts, _ = read(path, merge_fixed=True)
        out[path] = (package, links, parts, warned, ph.io.audit(path))
    return out


def test_every_urdf_reads_whole_and_warns_once_for_what_it_leaves_out(corpus):
    for path, (_, links, parts, warned, _) in corpus.items():
        assert len(warned) == (1 if links.left_out else 0), path
        if links.left_out:
            assert warned[0].message.links == links.left_out
            assert path in str(warned[0].message)
        # Every link is a body, a frame or left out, and nothing is two of them.
        names = set(links) | set(links.frames) | set(links.left_out)
        assert len(names) == len(links) + len(links.frames) + len(links.left_out), path
        # merge_fixed: the same mass, in fewer bodies.
        total = sum(b.mass for b in links.values())
        assert sum(b.mass for b in parts.values()) == pytest.approx(total, rel=1e-14), path
        assert len(parts) <= len(links) + len(links.frames)


def test_the_figures_of_each_package(corpus):
    figures = collections.defaultdict(collections.Counter)
    for package, links, parts, _, findings in corpus.values():
        f = figures[package]
        f.update(files=1, bodies=len(links), frames=len(links.frames))
        f.update(left_out=len(links.left_out), parts=len(parts))
        f.update(x.severity for x in findings)
    for package, expected in EXPECTED.items():
        if package in figures:
            got = {k: figures[package][k] for k in expected}
            assert got == expected, package


def test_known_links_left_out(corpus):
    by_name = {path.replace(os.sep, "/"): entry for path, entry in corpus.items()}
    for suffix, link, reason in KNOWN_LEFT_OUT:
        matches = [entry for path, entry in by_name.items() if path.endswith(suffix)]
        if not matches:
            continue  # that package is not installed
        (_, links, _, _, _), = matches
        assert links.left_out[link].startswith(reason), links.left_out


def test_audit_errors_are_the_links_left_out(corpus):
    """What read_urdf leaves out is what the audit calls an error (the audit may add moving
    point masses, which read_urdf reads as what the file says)."""
    for path, (_, links, _, _, findings) in corpus.items():
        errors = {f.link: f.check for f in findings if f.severity == "error"}
        assert set(links.left_out) <= set(errors), path
        assert all(errors[n] == "moving_part" for n in set(errors) - set(links.left_out)), path


def test_one_finding_per_link_and_check(corpus):
    for path, (*_, findings) in corpus.items():
        keys = [(f.link, f.check) for f in findings]
        assert len(keys) == len(set(keys)), path


def test_drake_prefixes_and_dae_meshes(corpus):
    for path, (package, links, _, warned, findings) in corpus.items():
        if path.endswith(os.path.join("ur5e", "ur5e.urdf")):
            assert not warned and len(links) == 7  # undeclared drake: prefixes, read
        if package == "jvrc_description":
            dae = [f for f in findings if f.check == "geometry_error"]
            assert dae and all(f.severity == "info" and ".dae" in f.message for f in dae)

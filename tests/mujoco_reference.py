"""MuJoCo's compiled model as the reference for polhode.io.read_mjcf, body by body.

MuJoCo compiles the file itself (``mujoco.MjSpec.from_file(...).compile()``); its
``body_mass``, ``body_ipos``, ``body_iquat`` and ``body_inertia`` are compared with what
read_mjcf returns:

- mass and centre of mass to 1e-12 (relative; the centre against the body's radius of
  gyration plus its distance from the origin);
- the inertia tensor as a whole, never the raw ``body_inertia`` vectors (MuJoCo keeps a
  single geom's moments unsorted, in the geom's frame): the full tensor
  ``R(body_iquat) diag(body_inertia) R^T`` to MuJoCo's own eigensolver accuracy, and its
  eigenvalues to 1e-12 of the largest, or to that accuracy where it is larger. mjuu_eig3
  stops once the largest off-diagonal term is below 1e-12 or a rotation would turn by less
  than sqrt(2e-12) = 1.41e-6 rad, so its frame can be off by about that angle: the tensor by
  up to 1.5e-6 (lambda_max - lambda_min), plus 1e-12 of its size. The eigenvalues of a body
  diagonalised once are MuJoCo's to round-off; a body that sums meshes, each placed in the
  frame MuJoCo's solver found for it, has eigenvalues off by up to the tensor's error
  (Weyl's inequality), not more;
- a body of no mass in MuJoCo is a frame for read_mjcf (its body_ipos is MuJoCo's copy of
  the body's own position, not a centre of mass);
- a free body that MuJoCo aligns with its inertial frame (``alignfree``) is compared in the
  world frame at qpos0, its frame as written being taken from a compile without alignment.

Unnamed bodies are named as read_mjcf names them ("body K", K their index in the spec) in
the spec MuJoCo compiles, so that they match after fusing too.
"""

from __future__ import annotations

import contextlib
import glob
import importlib.util
import io
import os
import warnings
from dataclasses import dataclass, field

import numpy as np

#: Relative bound on mass, centre of mass and eigenvalues.
BOUND = 1e-12
#: MuJoCo's eigensolver: frames off by up to ~1.41e-6 rad.
EIG_ANGLE = 1.5e-6


def quat_matrix(wxyz):
    w, x, y, z = np.asarray(wxyz, dtype=float) / np.linalg.norm(wxyz)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def named_spec(path, text=None):
    """MuJoCo's spec of the file, its unnamed bodies named as read_mjcf names them."""
    import mujoco

    with contextlib.redirect_stdout(io.StringIO()), warnings.catch_warnings():
        warnings.simplefilter("ignore")  # settotalmass is deprecated: MuJoCo warns
        spec = (
            mujoco.MjSpec.from_string(text) if text is not None else mujoco.MjSpec.from_file(path)
        )
    taken = {b.name for b in spec.bodies if b.name}
    for index, body in enumerate(spec.bodies):
        if not body.name:
            name = f"body {index}"
            while name in taken:
                name += " (unnamed)"
            body.name = name
    return spec


def compile_quietly(spec):
    import mujoco

    with contextlib.redirect_stdout(io.StringIO()), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = spec.compile()
    return model, mujoco.MjData(model)


@dataclass
class Comparison:
    """The worst differences over the bodies of one file, and what did not match."""

    bodies: int = 0
    mass: float = 0.0
    center: float = 0.0
    eigenvalues: float = 0.0
    tensor: float = 0.0  # relative Frobenius
    tensor_ratio: float = 0.0  # against the eigensolver bound
    mismatches: list[str] = field(default_factory=list)

    def within(self):
        return not self.mismatches

    def worst(self):
        return max(self.mass, self.center, self.eigenvalues, self.tensor)


def _aligned(spec, mujoco):
    """Names of the free bodies MuJoCo moves onto their inertial frame."""
    out = set()
    for body in spec.bodies[1:]:
        joints = body.joints
        if len(joints) != 1 or joints[0].type != mujoco.mjtJoint.mjJNT_FREE or len(body.bodies):
            continue
        align = int(joints[0].align)
        if align == 1 or (align == 2 and spec.compiler.alignfree):
            out.add(body.name)
    return out


def compare(bodies, path, text=None, fuse=None):
    """read_mjcf's ``bodies`` against MuJoCo's compile of the file (fused if ``fuse``, else
    as the file says)."""
    import mujoco

    spec = named_spec(path, text)
    if fuse is not None:
        spec.compiler.fusestatic = bool(fuse)
    model, data = compile_quietly(spec)
    aligned = _aligned(spec, mujoco)
    world = {}
    if aligned:
        mujoco.mj_kinematics(model, data)
        plain = named_spec(path, text)
        plain.compiler.alignfree = False
        if fuse is not None:
            plain.compiler.fusestatic = bool(fuse)
        for body in plain.bodies[1:]:
            for joint in body.joints:
                joint.align = 0
        plain_model, plain_data = compile_quietly(plain)
        mujoco.mj_kinematics(plain_model, plain_data)
        for name in aligned:
            k = plain_model.body(name).id
            world[name] = (plain_data.xpos[k].copy(), plain_data.xmat[k].reshape(3, 3).copy())
    result = Comparison()
    for i in range(1, model.nbody):
        name = model.body(i).name
        mass = model.body_mass[i]
        if mass == 0:
            if name in bodies:
                result.mismatches.append(f"{name}: massless in MuJoCo, read as {bodies[name]}")
            elif name not in bodies.frames:
                result.mismatches.append(f"{name}: massless in MuJoCo, not among the frames")
            continue
        if name not in bodies:
            why = bodies.left_out.get(name, "not read")
            result.mismatches.append(f"{name}: {mass:g} kg in MuJoCo, {why}")
            continue
        body = bodies[name]
        r = quat_matrix(model.body_iquat[i])
        moments = model.body_inertia[i]
        tensor = r @ np.diag(moments) @ r.T
        center = model.body_ipos[i]
        ours_center, ours_tensor = body.center_of_mass, body.inertia
        if name in world:  # both in the world frame
            x, xmat = world[name]
            ours_center = x + xmat @ ours_center
            ours_tensor = xmat @ ours_tensor @ xmat.T
            center = data.xipos[i]
            ximat = data.ximat[i].reshape(3, 3)
            tensor = ximat @ np.diag(moments) @ ximat.T
        result.bodies += 1
        size = np.sqrt(max(np.trace(tensor), 0.0) / mass)
        scale = max(size + np.linalg.norm(center), np.finfo(float).tiny)
        norm = np.linalg.norm(tensor)
        largest = max(np.max(np.abs(moments)), np.finfo(float).tiny)
        e_mass = abs(body.mass - mass) / mass
        e_center = np.linalg.norm(ours_center - center) / scale
        shift = np.max(np.abs(np.sort(np.linalg.eigvalsh(ours_tensor)) - np.sort(moments)))
        difference = np.linalg.norm(ours_tensor - tensor)
        e_tensor = difference / norm if norm > 0 else difference
        bound = EIG_ANGLE * (np.max(moments) - np.min(moments)) + BOUND * norm
        ratio = difference / bound if bound > 0 else (0.0 if difference == 0 else np.inf)
        e_eig = shift / largest
        # Eigenvalues: 1e-12 of the largest, or the solver's bound where it is larger.
        eig_ok = shift <= max(bound, BOUND * largest)
        result.mass = max(result.mass, e_mass)
        result.center = max(result.center, e_center)
        result.eigenvalues = max(result.eigenvalues, e_eig)
        result.tensor = max(result.tensor, e_tensor)
        result.tensor_ratio = max(result.tensor_ratio, ratio)
        if max(e_mass, e_center) > BOUND or not eig_ok or ratio > 1:
            result.mismatches.append(
                f"{name}: mass {e_mass:.1e}, centre {e_center:.1e}, eigenvalues {e_eig:.1e}, "
                f"tensor {e_tensor:.1e} ({ratio:.2g} of the eigensolver bound)"
            )
    in_model = {model.body(i).name for i in range(model.nbody)}
    for name in bodies:
        if name not in in_model:
            result.mismatches.append(f"{name}: read, not in MuJoCo's model")
    return result


def _package_folder(name):
    spec = importlib.util.find_spec(name)  # located without importing the package
    if spec is None or not spec.submodule_search_locations:
        return None
    return spec.submodule_search_locations[0]


def corpus():
    """``{corpus: [MJCF files]}`` of the installed packages: every XML file whose root is
    ``<mujoco>`` (include fragments among them; MuJoCo refuses those)."""
    found = {}
    for label, package, sub in [
        ("mujoco testdata", "mujoco", "testdata"),
        ("gymnasium", "gymnasium", os.path.join("envs", "mujoco", "assets")),
        ("gymnasium_robotics", "gymnasium_robotics", ""),
        ("dm_control", "dm_control", ""),
    ]:
        folder = _package_folder(package)
        if folder is None:
            continue
        files = []
        for path in sorted(glob.glob(os.path.join(folder, sub, "**", "*.xml"), recursive=True)):
            with open(path, "rb") as handle:
                head = handle.read(4096)
            start = head.find(b"<mujoco")
            if start >= 0 and b"<mujocoinclude" not in head[start : start + 15]:
                files.append(path)
        found[label] = files
    return found


def mujoco_compiles(path):
    """MuJoCo's compiled model of the file, or the reason it refuses it."""
    try:
        return compile_quietly(named_spec(path))[0], None
    except Exception as error:  # MuJoCo raises ValueError with its message
        return None, str(error).strip().splitlines()[0]

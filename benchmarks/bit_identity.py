"""A fingerprint of polhode's numbers, to prove that a refactoring changed no bit.

Runs a fixed set of a few hundred calls across every method, torque model, rotors, batches,
bodies given three ways, the exact solution's chunked path, the eigensolve, mesh and point-mass
inertia, and analyze, at 1 and 2 rayon threads, and prints one sha256 per group and one of
everything. Run it before and after a change and compare:

    python -m benchmarks.bit_identity            # prints the hashes
    python -m benchmarks.bit_identity --check FILE   # compares with hashes saved by --save FILE

Each run is in a fresh interpreter per thread count (RAYON_NUM_THREADS is read once).
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import subprocess
import sys

import numpy as np


def _digest(values: list) -> str:
    h = hashlib.sha256()
    for value in values:
        if value is None:
            h.update(b"None")
            continue
        array = np.ascontiguousarray(np.asarray(value, dtype=np.float64))
        h.update(str(array.shape).encode())
        h.update(array.tobytes())
    return h.hexdigest()


def _trajectory(sol) -> list:
    names = [
        "t",
        "omega",
        "quaternion",
        "energy",
        "angular_momentum_body",
        "angular_momentum_space",
        "rotor_rates",
    ]
    return [getattr(sol, name, None) for name in names]


def groups() -> dict[str, list]:
    import polhode as ph

    rng = np.random.default_rng(2024)
    out: dict[str, list] = {}
    t = np.linspace(0.0, 20.0, 41)
    moments = np.sort(rng.uniform(1.0, 4.0, (40, 3)), axis=1)
    omegas = rng.normal(size=(40, 3))

    # Free motion, one body at a time, every method and order.
    values: list = []
    for k in range(12):
        m, w = moments[k], omegas[k]
        values += _trajectory(ph.simulate(m, w, t))
        for order in (2, 4, 6):
            values += _trajectory(ph.simulate(m, w, t, method="splitting", dt=1e-2, order=order))
        values += _trajectory(ph.simulate(m, w, t, method="midpoint", dt=1e-2))
        values += _trajectory(ph.simulate(m, w, t, method="rk4", dt=1e-2))
        values += _trajectory(ph.simulate(m, w, t, method="dop853", rtol=1e-10))
        values += _trajectory(ph.simulate(m, w, t, method="rk4", dt=1e-2, orientation=False))
    out["single"] = values

    # Batches (lanes and the scalar path), with and without orientation.
    values = []
    for method, options in [
        ("exact", {}),
        ("splitting", {"dt": 1e-2}),
        ("midpoint", {"dt": 1e-2}),
        ("rk4", {"dt": 1e-2}),
        ("dop853", {"rtol": 1e-9}),
    ]:
        for orientation in (True, False):
            sol = ph.simulate(moments, omegas, t, method=method, orientation=orientation, **options)
            values += _trajectory(sol)
    # The exact solution at many output times (chunked, on the pool).
    values += _trajectory(ph.simulate(moments[0], omegas[0], np.linspace(0.0, 500.0, 20001)))
    out["batch"] = values

    # Bodies given as a Body and as a tensor in non-principal axes, t0 and orientation0.
    values = []
    body = ph.Body.cuboid(2.0, [0.3, 0.5, 0.9]).rotated(
        [[0.36, 0.48, -0.8], [-0.8, 0.6, 0.0], [0.48, 0.64, 0.6]]
    ) + ph.Body.sphere(0.5, 0.1).translated([0.1, 0.2, 0.3])
    for method in ("exact", "splitting", "midpoint", "rk4", "dop853"):
        opts = {"dt": 1e-2} if method in ("splitting", "midpoint", "rk4") else {}
        values += _trajectory(ph.simulate(body, [0.2, 1.0, 0.3], t, method=method, **opts))
        values += _trajectory(
            ph.simulate(
                body.inertia,
                [0.2, 1.0, 0.3],
                t + 1.0,
                t0=1.0,
                method=method,
                orientation0=[0.1, 0.2, 0.3, 0.927361849549570],
                **opts,
            )
        )
    out["bodies"] = values

    # Torques in Rust and in Python, rk4 and dop853, single and batch.
    values = []
    top = ph.Body.cone(0.1, 0.04, 0.03)
    torques = [
        ph.torque.BodyFixed([0.0, 0.01, 0.02]),
        ph.torque.SpaceFixed([0.01, 0.0, 0.0]),
        ph.torque.Gravity(pivot=[0, 0, 0.03]),
        ph.torque.GravityGradient(mean_motion=0.1),
        ph.torque.Window(ph.torque.BodyFixed([0.0, 0.0, 0.1]), start=0.2, end=0.6),
        ph.torque.BodyFixed([0.0, 0.01, 0.0]) + ph.torque.SpaceFixed([0.0, 0.0, 0.01]),
        ph.torque.Function(lambda time, w, q: -0.01 * np.asarray(w)),
    ]
    for torque in torques:
        for method, opts in [
            ("rk4", {"dt": 1e-3}),
            ("dop853", {"rtol": 1e-10}),
            ("splitting", {"dt": 1e-3}),
            ("midpoint", {"dt": 1e-3}),
        ]:
            values += _trajectory(
                ph.simulate(
                    top,
                    [0.3, 0.1, 150.0],
                    np.linspace(0, 1, 11),
                    method=method,
                    torque=torque,
                    orientation0=[0.99, 0.0, 0.0, 0.141067359796659],
                    **opts,
                )
            )
    values += _trajectory(
        ph.simulate(
            moments[:6],
            omegas[:6],
            np.linspace(0, 2, 5),
            method="dop853",
            torque=ph.torque.SpaceFixed([0.0, 0.1, 0.0]),
        )
    )
    values += _trajectory(
        ph.simulate(
            moments[:6],
            omegas[:6],
            np.linspace(0, 2, 5),
            method="rk4",
            dt=1e-3,
            torque=ph.torque.BodyFixed([0.0, 0.1, 0.0]),
        )
    )
    out["torques"] = values

    # Rotors: wheels (constant, scheduled, Python motor) and dampers, dop853 and rk4, batches.
    values = []
    rotor_sets = [
        [ph.rotors.Wheel([0, 0, 1], inertia=0.1, rate0=3.0)],
        [ph.rotors.Wheel([0, 1, 1], inertia=0.1, torque=[(0.0, 0.05), (1.0, 0.0)])],
        [ph.rotors.SphericalDamper(inertia=0.2, damping=0.1)],
        [
            ph.rotors.Wheel([1, 0, 0], inertia=0.05, torque=lambda time, w, r: 0.01 * np.sin(time)),
            ph.rotors.SphericalDamper(inertia=0.2, damping=0.3),
        ],
    ]
    for rotors in rotor_sets:
        values += _trajectory(
            ph.simulate([1.0, 4.0, 5.0], [2.0, 0.01, 0.01], np.linspace(0, 10, 21), rotors=rotors)
        )
        values += _trajectory(
            ph.simulate(
                [1.0, 4.0, 5.0],
                [2.0, 0.01, 0.01],
                np.linspace(0, 10, 21),
                rotors=rotors,
                method="rk4",
                dt=1e-2,
            )
        )
        values += _trajectory(
            ph.simulate(moments[:4] + 1.0, omegas[:4], np.linspace(0, 5, 6), rotors=rotors)
        )
    out["rotors"] = values

    # Mass properties: eigensolve (batch, continuous), meshes, point masses, frames.
    values = []
    tensors = rng.normal(size=(500, 3, 3))
    tensors = tensors @ tensors.transpose(0, 2, 1)
    tensors[::7] = np.diag([1.0, 1.0, 2.0])
    p = ph.principal(tensors)
    values += [p.moments, p.axes]
    turns = np.cumsum(rng.normal(scale=0.05, size=(300, 3)), axis=0)
    from scipy.spatial.transform import Rotation

    frames = Rotation.from_rotvec(turns).as_matrix()
    series = frames @ np.diag([1.0, 2.0, 3.0]) @ frames.transpose(0, 2, 1)
    p = ph.principal(series, continuous=True)
    values += [p.moments, p.axes]
    points = rng.normal(size=(50, 3)) + 1e3
    masses = rng.uniform(0.5, 2.0, 50)
    b = ph.Body.point_masses(masses, points)
    values += [b.mass, b.center_of_mass, b.inertia]
    positions = points[None] + rng.normal(scale=0.1, size=(20, 50, 3))
    values += [ph.point_masses_inertia(masses, positions)]
    values += [ph.point_masses_inertia(masses, positions.astype(np.float32))]
    import trimesh  # noqa: F401  (the mesh extra; the icosphere is built here, not read)

    sphere = trimesh.creation.icosphere(subdivisions=3)
    m = ph.Body.mesh(sphere.vertices + 7.0, sphere.faces, density=1000.0)
    values += [m.mass, m.center_of_mass, m.inertia]
    for name in ("sphere", "cuboid", "cylinder", "cone", "torus", "capsule", "ellipsoid"):
        solid = {
            "sphere": lambda: ph.Body.sphere(1.0, 0.1),
            "cuboid": lambda: ph.Body.cuboid(1.0, [0.1, 0.2, 0.3]),
            "cylinder": lambda: ph.Body.cylinder(1.0, 0.1, 0.5),
            "cone": lambda: ph.Body.cone(1.0, 0.1, 0.5),
            "torus": lambda: ph.Body.torus(1.0, 0.5, 0.1),
            "capsule": lambda: ph.Body.capsule(1.0, 0.1, 0.5),
            "ellipsoid": lambda: ph.Body.ellipsoid(1.0, [0.1, 0.2, 0.3]),
        }[name]()
        values += [solid.mass, solid.inertia, solid.principal().moments, solid.principal().axes]
    out["mass"] = values

    # analyze, single and batch; the perturbation expansion.
    values = []
    for k in range(20):
        a = ph.analyze(moments[k], omegas[k])
        values += [getattr(a, f) for f in ("period", "energy", "angular_momentum_norm")]
    a = ph.analyze([1.0, 2.0, 3.0], [0.2, 0.3, 1.0])
    values += [a.precession_rate_space, a.nutation_angle]
    d = ph.analyze(
        [1.0, 4.0, 5.0],
        [0.01, 0.01, 2.0],
        rotors=[ph.rotors.SphericalDamper(inertia=0.2, damping=0.1)],
    )
    values += [d.nutation_rate, d.nutation_time_constant]
    values += [ph.perturbation([1.0, 2.0, 3.0], [1.0, 0.01, 0.01], t, order=2)]
    out["analysis"] = values
    return out


def fingerprint() -> dict[str, str]:
    return {name: _digest(values) for name, values in groups().items()}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--save", help="write the hashes to this JSON file")
    parser.add_argument("--check", help="compare with the hashes in this JSON file")
    parser.add_argument("--inner", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.inner:
        print(json.dumps(fingerprint()))
        return 0
    result = {}
    for threads in (1, 2):
        env = dict(os.environ, RAYON_NUM_THREADS=str(threads))
        run = subprocess.run(
            [sys.executable, "-m", "benchmarks.bit_identity", "--inner"],
            env=env,
            capture_output=True,
            text=True,
        )
        if run.returncode:
            sys.stderr.write(run.stderr)
            return run.returncode
        for name, digest in json.loads(run.stdout).items():
            result[f"{name} (threads={threads})"] = digest
    # The thread counts must agree with each other too.
    for name in list(result):
        if "threads=1" in name:
            other = result[name.replace("threads=1", "threads=2")]
            if other != result[name]:
                print(f"{name}: differs between 1 and 2 threads")
    everything = hashlib.sha256(json.dumps(result, sort_keys=True).encode()).hexdigest()
    for name, digest in result.items():
        print(f"{digest[:16]}  {name}")
    print(f"{everything[:16]}  everything")
    if args.save:
        with open(args.save, "w") as file:
            json.dump(result, file, indent=1, sort_keys=True)
    if args.check:
        with open(args.check) as file:
            saved = json.load(file)
        differ = [name for name in saved if saved[name] != result.get(name)]
        if differ:
            print("DIFFERENT:", ", ".join(differ))
            return 1
        print("identical to", args.check)
    return 0


if __name__ == "__main__":
    sys.exit(main())

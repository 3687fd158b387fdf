"""read_mjcf against MuJoCo's compiled model, file by file, over the installed MJCF corpus
(mujoco's test data, gymnasium, gymnasium-robotics, dm-control) and any folders given.

    python -m benchmarks.io_mjcf_vs_mujoco [--fuse] [--files] [NAME=FOLDER ...]

For each corpus: the MJCF files (XML whose root is ``<mujoco>``), those MuJoCo 4.x compiles,
those read_mjcf reads as MuJoCo compiles them (and, as polhode read them before, as written:
``as_written=True``), and the worst difference against MuJoCo's ``body_mass``, ``body_ipos``,
``body_iquat``, ``body_inertia`` of any body: mass and centre of mass (relative), tensor
(relative Frobenius) and the tensor's difference as a fraction of MuJoCo's eigensolver bound
(tests/mujoco_reference.py says how each is taken). ``--files`` lists every file whose worst
difference is above 1e-12, with the reason; ``--fuse`` compares ``merge_fixed=True`` with
MuJoCo's ``fusestatic``. A file MuJoCo refuses is counted, not compared.
"""

from __future__ import annotations

import argparse
import glob
import os
import sys
import time
import warnings

import numpy as np

import polhode as ph

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests"))
from mujoco_reference import BOUND, compare, corpus, mujoco_compiles  # noqa: E402


def mjcf_files(folder: str) -> list[str]:
    files = []
    for path in sorted(glob.glob(os.path.join(folder, "**", "*.xml"), recursive=True)):
        with open(path, "rb") as handle:
            head = handle.read(4096)
        start = head.find(b"<mujoco")
        if start >= 0 and b"<mujocoinclude" not in head[start : start + 15]:
            files.append(path)
    return files


def as_written_worst(path: str, model) -> tuple[str, bool]:
    """The earlier reading (as written) against MuJoCo: its worst mass and tensor
    difference, or why it refuses the file; and whether it agrees (mass to 1e-12, tensor to
    1e-6)."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            bodies = ph.io.read_mjcf(path, as_written=True)
    except (ph.PolhodeError, OSError) as error:
        return f"refused ({type(error).__name__}: {str(error).split(': ')[-1][:60]})", False
    worst_mass = worst_tensor = 0.0
    for i in range(1, model.nbody):
        name = model.body(i).name
        mass = model.body_mass[i]
        if mass == 0:
            continue
        if name not in bodies:
            worst_mass = worst_tensor = 1.0
            continue
        w, x, y, z = model.body_iquat[i]
        r = _matrix(np.array([w, x, y, z]))
        tensor = r @ np.diag(model.body_inertia[i]) @ r.T
        worst_mass = max(worst_mass, abs(bodies[name].mass - mass) / mass)
        norm = np.linalg.norm(tensor)
        if norm > 0:
            worst_tensor = max(worst_tensor, np.linalg.norm(bodies[name].inertia - tensor) / norm)
    agrees = worst_mass <= BOUND and worst_tensor <= 1e-6
    return f"mass {worst_mass:.1e}, tensor {worst_tensor:.1e}", agrees


def _matrix(q):
    w, x, y, z = q / np.linalg.norm(q)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("roots", nargs="*", help="more corpora, as NAME=FOLDER")
    parser.add_argument("--fuse", action="store_true", help="merge_fixed=True vs fusestatic")
    parser.add_argument("--files", action="store_true", help="list files above 1e-12")
    args = parser.parse_args()
    corpora = corpus()
    for root in args.roots:
        name, _, folder = root.partition("=")
        corpora[name] = mjcf_files(folder)
    print(
        f"read_mjcf{'(merge_fixed=True)' if args.fuse else ''} against MuJoCo "
        f"{__import__('mujoco').__version__}'s compiled model (worst body of any file)\n"
    )
    header = (
        f"{'corpus':20s} {'files':>5s} {'MuJoCo':>6s} {'read':>5s} {'before':>6s} {'agreed':>6s}  "
        f"{'mass':>8s} {'centre':>8s} {'tensor':>8s} {'of eig':>7s}  time"
    )
    print(header)
    details = []
    for label, files in corpora.items():
        start = time.perf_counter()
        compiled = read = before = agreed = 0
        worst = np.zeros(4)
        for path in files:
            model, _ = mujoco_compiles(path)
            if model is None:
                continue
            compiled += 1
            written, agrees = as_written_worst(path, model)
            before += not written.startswith("refused")
            agreed += agrees
            try:
                with warnings.catch_warnings(record=True) as caught:
                    warnings.simplefilter("always")
                    bodies = ph.io.read_mjcf(path, merge_fixed=True if args.fuse else None)
                result = compare(bodies, path, fuse=True if args.fuse else None)
            except (ph.PolhodeError, OSError) as error:
                details.append((label, path, f"not read: {error}", written))
                continue
            read += result.within()
            row = np.array([result.mass, result.center, result.tensor, result.tensor_ratio])
            worst = np.maximum(worst, row)
            if not result.within() or caught:
                why = "; ".join(result.mismatches[:2] + [str(w.message)[:120] for w in caught])
                details.append((label, path, why, written))
            elif max(result.mass, result.center, result.tensor) > BOUND:
                why = (
                    f"tensor {result.tensor:.1e}, {result.tensor_ratio:.2g} of MuJoCo's "
                    "eigensolver bound (mass and centre <= 1e-12)"
                )
                details.append((label, path, why, written))
        print(
            f"{label:20s} {len(files):5d} {compiled:6d} {read:5d} {before:6d} {agreed:6d}  "
            f"{worst[0]:8.1e} {worst[1]:8.1e} {worst[2]:8.1e} {worst[3]:7.2g}  "
            f"{time.perf_counter() - start:.1f} s"
        )
    print(
        "\nfiles: XML files with a <mujoco> root; MuJoCo: those it compiles; read: those "
        "read_mjcf reads with every body within the bounds; before: those read as written "
        "(as_written=True, the earlier reading), and agreed: of those, the files within "
        "1e-12 in mass and 1e-6 in tensor. of eig: the largest tensor difference "
        "as a fraction of MuJoCo's eigensolver bound 1.5e-6 (lmax - lmin) + 1e-12 |I|."
    )
    if args.files and details:
        print("\nfiles above 1e-12 (the reason; as written):")
        for label, path, why, written in details:
            print(f"  {label}: {os.path.basename(path)}: {why}  [as written: {written}]")


if __name__ == "__main__":
    main()

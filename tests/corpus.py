"""The real robot descriptions of the test extra (pyproject.toml), found where pip installed
them: robot files no one here wrote, for the tests of polhode.io.

``files("urdf")`` and ``files("mjcf")`` list ``(package, path)`` of every URDF (root
``<robot>``) and MJCF (root ``<mujoco>``) file under the installed packages of :data:`CORPUS`,
sorted; a package that is not installed contributes nothing (the tests then skip it). The
packages are located without being imported (gymnasium-robotics registers environments on
import).
"""

from __future__ import annotations

import importlib.util
import os
import xml.etree.ElementTree as ET

#: The packages of the corpus and the folder of each that holds its robot files.
CORPUS = {
    "gymnasium": "envs/mujoco/assets",
    "gymnasium_robotics": "",
    "upkie_description": "",
    "cookie_description": "",
    "jvrc_description": "",
    "airo_models": "",
}


def root(package: str) -> str | None:
    """The folder of an installed package's robot files, or None if it is not installed."""
    spec = importlib.util.find_spec(package)
    if spec is None or not spec.submodule_search_locations:
        return None
    folder = os.path.join(list(spec.submodule_search_locations)[0], CORPUS[package])
    return folder if os.path.isdir(folder) else None


def kind_of(path: str) -> str | None:
    """'urdf', 'mjcf' or None, by the root element (read up to the first start tag)."""
    try:
        for _, element in ET.iterparse(path, events=("start",)):
            return {"robot": "urdf", "mujoco": "mjcf"}.get(element.tag)
    except ET.ParseError:
        # Undeclared namespace prefixes later in the file (Drake's): the root is what counts.
        with open(path, encoding="utf-8", errors="replace") as handle:
            head = handle.read(4096)
        for tag, kind in (("<robot", "urdf"), ("<mujoco", "mjcf")):
            if tag in head:
                return kind
    return None


def files(kind: str, packages: tuple[str, ...] = tuple(CORPUS)) -> list[tuple[str, str]]:
    """``(package, path)`` of every file of ``kind`` ('urdf' or 'mjcf') in the installed
    corpus, sorted by package and path."""
    out = []
    for package in packages:
        folder = root(package)
        if folder is None:
            continue
        for directory, _, names in os.walk(folder):
            for name in names:
                if name.lower().endswith((".urdf", ".xml")):
                    path = os.path.join(directory, name)
                    if kind_of(path) == kind:
                        out.append((package, path))
    return sorted(out)

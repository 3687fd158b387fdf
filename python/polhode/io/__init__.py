"""Files in: triangle meshes, robot descriptions (URDF, MJCF), and an audit of their inertials.

- :func:`read_mesh` reads STL (ascii and binary), OBJ, PLY, OFF and glTF/GLB with trimesh's
  loaders and returns the meshes of the file as bodies (``Body.from_file`` is their composite).
- :func:`read_urdf` reads a URDF file whole: one :class:`Body` per link, in that link's own
  frame, or with ``merge_fixed=True`` one per moving part; what is not a body is said in the
  result (:class:`Links`: its massless ``frames``, the links ``left_out`` and why) and in one
  :class:`polhode.errors.RobotFileWarning`.
- :func:`read_mjcf` (parsed by MuJoCo's ``MjSpec``) returns each body as MuJoCo's compiler gives
  it (``as_written=True`` for the file's own values), in a :class:`Links` as well;
  :func:`legacy_mesh_inertia` says by how much MuJoCo's default ``legacy`` mesh inertia
  differs from the exact one, body by body.
- :func:`audit` checks every link's declared inertial and its geometry, and returns a
  :class:`Finding` for each link (``polhode audit FILE`` prints them).

The mass properties are polhode's own (exact mesh integrals, the core's solids); the libraries
only read the files. They are optional: ``pip install 'polhode[mesh]'`` (trimesh) and
``'polhode[robots]'`` (yourdfpy, for its rules of mesh file names and its lxml, and MuJoCo).

A broken file raises :class:`polhode.errors.FileFormatError`, whose message and attributes name
the file, the link (or body, or mesh part) and the field at fault; a missing file raises
:class:`FileNotFoundError`.

Examples
--------
>>> import polhode as ph
>>> import polhode.io
>>> import os, tempfile
>>> urdf = '''<robot name="r"><link name="arm"><inertial>
...   <origin xyz="0 0 0.1" rpy="0 0 0"/><mass value="2"/>
...   <inertia ixx="0.02" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.01"/>
... </inertial></link></robot>'''
>>> path = os.path.join(tempfile.mkdtemp(), "r.urdf")
>>> with open(path, "w") as handle:
...     _ = handle.write(urdf)
>>> bodies = ph.io.read_urdf(path)
>>> bodies["arm"].mass, bodies["arm"].center_of_mass.tolist()
(2.0, [0.0, 0.0, 0.1])
>>> [(f.link, f.severity) for f in ph.io.audit(path)]
[('arm', 'ok')]
"""

from polhode import _meshes
from polhode.io._robot import Links
from polhode.io.audit import CHECKS as AUDIT_CHECKS
from polhode.io.audit import Finding, audit
from polhode.io.mesh import read_mesh
from polhode.io.mjcf import LegacyMeshInertia, legacy_mesh_inertia, read_mjcf
from polhode.io.urdf import read_urdf

__all__ = [
    "AUDIT_CHECKS",
    "Finding",
    "LegacyMeshInertia",
    "Links",
    "MESH_FORMATS",
    "audit",
    "legacy_mesh_inertia",
    "read_mesh",
    "read_mjcf",
    "read_urdf",
]

#: The mesh formats :func:`read_mesh` reads (by the file's extension), all through trimesh.
MESH_FORMATS = _meshes.MESH_FORMATS

"""
A robot description, audited
============================

A two-link arm as an exporter might write it (needs ``pip install 'polhode[robots]'``): the
upper arm declared correctly, the forearm with a tensor that no rigid body has.
``polhode.io.read_urdf`` reads every link's declared inertial and refuses one that no body
has; ``polhode.io.audit`` checks each, with a corrected ``<inertial>`` from the link's own
geometry where one can be computed.
"""

import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import polhode as ph

# %%
# The upper arm: a 2 kg cylinder, radius 4 cm, 30 cm long along z, its inertial exact. The
# forearm: a 1 kg box 5 x 5 x 25 cm, whose declared moments break the triangle inequality
# (I_zz > I_xx + I_yy: impossible for a rigid body).
upper = ph.Body.cylinder(2.0, 0.04, 0.3)
ixx, iyy, izz = (float(x) for x in np.diag(upper.inertia))
urdf = f"""<robot name="arm">
  <link name="upper_arm">
    <inertial><mass value="2.0"/><origin xyz="0 0 0"/>
      <inertia ixx="{ixx!r}" iyy="{iyy!r}" izz="{izz!r}" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><geometry><cylinder radius="0.04" length="0.3"/></geometry></collision>
  </link>
  <link name="forearm">
    <inertial><mass value="1.0"/><origin xyz="0 0 0"/>
      <inertia ixx="0.0002" iyy="0.0002" izz="0.0055" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><geometry><box size="0.05 0.05 0.25"/></geometry></collision>
  </link>
  <joint name="elbow" type="revolute">
    <parent link="upper_arm"/><child link="forearm"/><origin xyz="0 0 0.3"/>
    <axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="10" velocity="3"/>
  </joint>
</robot>
"""
path = Path(tempfile.mkdtemp()) / "arm.urdf"
path.write_text(urdf)

# %%
# Reading it for a simulation refuses the forearm, with a typed error that names the file, the
# link and the field:
try:
    ph.io.read_urdf(path)
except ph.FileFormatError as error:
    print(f"{type(error).__name__}: {error}")

# %%
# The audit: every finding with its severity, and the corrected inertial of the forearm.
findings = ph.io.audit(path)
for f in findings:
    print(f"{f.severity:8s} {f.link:10s} {f.check:20s} {f.message}")
    if f.corrected:
        print(f.corrected)

# %%
# Declared against the geometry's principal moments (the box's, with the declared mass).
box = ph.Body.cuboid(1.0, [0.05, 0.05, 0.25])
declared = np.array([0.0002, 0.0002, 0.0055])  # as written in the file (diagonal)
geometry = box.principal().moments
fig, ax = plt.subplots(figsize=(6, 4))
x = np.arange(3)
ax.bar(x - 0.2, declared, 0.4, label="declared in the file")
ax.bar(x + 0.2, geometry, 0.4, label="from the link's box")
ax.set_xticks(x, ["I_1", "I_2", "I_3"])
ax.set_ylabel("principal moment (kg m^2)")
ax.set_title("forearm: I_3 > I_1 + I_2 is no rigid body")
ax.legend()
fig.tight_layout()
plt.show()

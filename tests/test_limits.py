"""Work too large for the machine is refused before it starts, with a way out."""

from __future__ import annotations

import re

import numpy as np
import pytest

import polhode as ph
from polhode import _core


def test_outputs_larger_than_memory_raise_memory_error_before_the_work():
    # 1e6 bodies at 1e6 output times: 1e12 times the numbers of every quantity of the core's
    # table at one output time (without rotors), 8 bytes each (1.1e14 bytes for 14 numbers).
    per_time = sum(
        int(np.prod(row["shape"])) for row in _core.QUANTITIES if "rotors" not in row["requires"]
    )
    size = re.escape(f"{1e12 * per_time * 8:.3g} bytes")
    omega0 = np.zeros((1_000_000, 3))
    t = np.linspace(0.0, 1.0, 1_000_000)
    with pytest.raises(MemoryError, match=rf"{size}.*fewer output times.*polhode\.dask"):
        ph.simulate([1.0, 2.0, 3.0], omega0, t)


def test_the_core_refuses_an_allocation_it_cannot_make():
    """Past the Python check (e.g. memory taken meanwhile), the core's allocation fails as a
    MemoryError, not an abort of the process."""
    omega0 = np.zeros((1_000_000, 3))
    t = np.linspace(0.0, 1.0, 1_000_000)
    with pytest.raises(MemoryError, match="bytes"):
        _core.simulate(np.array([1.0, 2.0, 3.0]), omega0, t, method="exact")


def test_an_orientation_that_blows_up_is_an_error_not_nan_beside_finite_omega():
    # A sphere keeps omega constant (finite), while rk4 with steps 17000 times too long for
    # |omega| = 1732 rad/s makes the quaternion's norm grow like (|omega| dt)^4 per step.
    with pytest.raises(ph.NonFiniteError, match="orientation.*reduce dt"):
        ph.simulate([1.0, 1.0, 1.0], [1e3, 1e3, 1e3], [0.0, 1e4], method="rk4", dt=10.0)
    # Without the orientation, omega alone is fine: the sphere's omega is exact.
    sol = ph.simulate(
        [1.0, 1.0, 1.0], [1e3, 1e3, 1e3], [0.0, 1e4], method="rk4", dt=10.0, orientation=False
    )
    np.testing.assert_array_equal(sol.omega[-1], [1e3, 1e3, 1e3])

"""polhode.plot: each plot rendered to PNG with Agg and checked non-trivial, plus its data."""

from __future__ import annotations

import numpy as np
import pytest

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")

from matplotlib.image import imread  # noqa: E402
from scipy.spatial.transform import Rotation  # noqa: E402

import polhode as ph  # noqa: E402
from polhode import plot  # noqa: E402
from reference import euler_omega  # noqa: E402

MOMENTS = np.array([1.0, 2.0, 3.0])
OMEGA0 = np.array([0.1, 1.0, 0.2])  # near the intermediate axis: a flip


@pytest.fixture(scope="module")
def traj():
    return ph.simulate(MOMENTS, OMEGA0, np.linspace(0.0, 20.0, 801), method="rk4", dt=0.01)


def render(ax, path, min_kb=15, min_colours=30):
    """Save the Axes' figure as a PNG and check it is not blank."""
    ax.figure.savefig(path, dpi=80)
    assert path.stat().st_size > min_kb * 1024
    image = imread(path)
    pixels = image[..., :3].reshape(-1, 3)
    colours = np.unique(np.round(pixels * 255).astype(np.uint8), axis=0)
    assert len(colours) > min_colours
    non_white = np.any(pixels < 0.95, axis=1).mean()
    assert 0.02 < non_white < 0.9


def lines(ax, prefix):
    return [line for line in ax.lines if str(line.get_gid()).startswith(prefix)]


def test_omega(traj, tmp_path):
    ax = plot.omega(traj)
    render(ax, tmp_path / "omega.png")
    assert [line.get_gid() for line in ax.lines] == ["omega[0]", "omega[1]", "omega[2]"]
    for k, line in enumerate(ax.lines):
        np.testing.assert_array_equal(line.get_xdata(), traj.t)
        np.testing.assert_array_equal(line.get_ydata(), traj.omega[:, k])
    # principal moments given in ascending order: the body axes are axes 1, 2, 3
    assert [line.get_label() for line in ax.lines] == [f"$\\omega_{{{k}}}$" for k in (1, 2, 3)]
    assert ax.get_xlabel() == "$t$ (s)" and ax.get_ylabel() == "$\\omega$ (rad/s)"


def test_drift(traj, tmp_path):
    ax = plot.drift(traj)
    render(ax, tmp_path / "drift.png")
    assert ax.get_yscale() == "log"
    E, Lb, Ls = traj.energy, traj.angular_momentum_body, traj.angular_momentum_space
    expected = {
        "drift:energy": np.abs(E - E[0]) / E[0],
        "drift:|L| body": np.abs(np.sqrt((Lb**2).sum(1)) - np.sqrt((Lb[0] ** 2).sum()))
        / np.sqrt((Lb[0] ** 2).sum()),
        "drift:L space": np.sqrt(((Ls - Ls[0]) ** 2).sum(1)) / np.sqrt((Ls[0] ** 2).sum()),
    }
    assert [line.get_gid() for line in lines(ax, "drift:")] == list(expected)
    for line in lines(ax, "drift:"):
        want = np.maximum(expected[line.get_gid()], plot.FLOOR)
        # the norms are summed in a different order here: equal up to a few ulps of |L|
        np.testing.assert_allclose(line.get_ydata(), want, rtol=1e-9, atol=1e-15)
        assert np.all(line.get_ydata() >= plot.FLOOR)
        assert line.get_ydata()[0] == plot.FLOOR  # zero error at t0 is drawn at the floor
    # rk4 at dt = 0.01 over t = 20: the drift is real, not all floor
    assert max(line.get_ydata().max() for line in lines(ax, "drift:")) > 1e-12


def test_polhode_curves_on_sphere_and_ellipsoids(traj, tmp_path):
    ax = plot.polhode(traj=traj)
    render(ax, tmp_path / "polhode.png")
    I1, I2, I3 = traj.moments
    L = np.linalg.norm(traj.angular_momentum_body[0])
    levels = lines(ax, "polhode:")
    assert len(levels) == 16  # 8 default energies, both branches
    sides = set()
    for line in levels:
        x, y, z = (np.asarray(a) for a in line.get_data_3d())
        two_t = 2.0 * float(line.get_gid().split(":")[1])
        np.testing.assert_allclose(np.sqrt(x * x + y * y + z * z), L, rtol=1e-12)
        np.testing.assert_allclose(x * x / I1 + y * y / I2 + z * z / I3, two_t, rtol=1e-12)
        sides.add(two_t > L * L / I2)
        assert np.ptp(x) + np.ptp(y) + np.ptp(z) > 0.05 * L  # a curve, not a point
    assert sides == {True, False}  # levels on both sides of the separatrix
    seps = lines(ax, "separatrix")
    assert len(seps) == 2
    for line in seps:
        x, y, z = (np.asarray(a) for a in line.get_data_3d())
        np.testing.assert_allclose(np.sqrt(x * x + y * y + z * z), L, rtol=1e-12)
        np.testing.assert_allclose(x * x / I1 + y * y / I2 + z * z / I3, L * L / I2, rtol=1e-12)
    (overlay,) = lines(ax, "trajectory")
    np.testing.assert_array_equal(
        np.column_stack(overlay.get_data_3d()), traj.angular_momentum_body
    )


def test_polhode_explicit_energies_and_errors():
    ax = plot.polhode([1.0, 2.0, 3.0], 2.0, energies=[0.8, 1.5], sphere=False)
    assert len(lines(ax, "polhode:")) == 4 and len(lines(ax, "separatrix")) == 2
    # symmetric top: no separatrix, curves still on the sphere
    ax = plot.polhode([1.0, 1.0, 3.0], 1.0, energies=[0.3])
    (a, b) = lines(ax, "polhode:")
    x, y, z = (np.asarray(v) for v in a.get_data_3d())
    np.testing.assert_allclose(x * x + y * y + z * z, 1.0, rtol=1e-12)
    assert lines(ax, "separatrix") == []
    with pytest.raises(ph.ArgumentError, match="energies"):
        plot.polhode([1.0, 2.0, 3.0], 1.0, energies=[5.0])
    with pytest.raises(TypeError, match="sphere"):
        plot.polhode([1.0, 2.0, 3.0], sphere="no")
    # moments in any order, as simulate takes them: the polhode of the ascending moments
    for given in ([3.0, 2.0, 1.0], [2.0, 3.0, 1.0]):
        ax, reference = plot.polhode(given, 2.0, [0.8, 1.5]), plot.polhode([1.0, 2.0, 3.0], 2.0,
                                                                          [0.8, 1.5])
        for a, b in zip(lines(ax, "polhode:"), lines(reference, "polhode:"), strict=True):
            np.testing.assert_array_equal(a.get_data_3d(), b.get_data_3d())
    with pytest.raises(ph.ArgumentError, match="polhode_curves|ascending"):
        plot.polhode_curves([3.0, 2.0, 1.0], 1.0, 0.3)  # the helper: principal axes, ascending


def test_herpolhode_in_invariable_plane(traj, tmp_path):
    ax = plot.herpolhode(traj)
    render(ax, tmp_path / "herpolhode.png")
    (line,) = lines(ax, "herpolhode")
    xy = np.column_stack([line.get_xdata(), line.get_ydata()])
    # independent: omega in space from the quaternions, split along and across L(0)
    w = Rotation.from_quat(traj.quaternion).apply(traj.omega)
    n = traj.angular_momentum_space[0] / np.linalg.norm(traj.angular_momentum_space[0])
    along = w @ n
    across = w - along[:, None] * n
    # the tip of omega stays in a plane perpendicular to L: omega . n = 2T/|L| (rk4 tolerance)
    np.testing.assert_allclose(
        along, 2 * traj.energy[0] / np.linalg.norm(traj.angular_momentum_space[0]), rtol=1e-6
    )
    # the plotted points are the in-plane components (basis-independent: norms and angles)
    np.testing.assert_allclose(
        np.hypot(xy[:, 0], xy[:, 1]), np.linalg.norm(across, axis=1), rtol=1e-10, atol=1e-12
    )
    np.testing.assert_allclose(xy @ xy[0], across @ across[0], rtol=1e-10, atol=1e-12)
    assert xy[0, 1] == pytest.approx(0.0, abs=1e-12)  # e1 along the initial omega
    assert np.ptp(xy[:, 0]) > 0.1 and np.ptp(xy[:, 1]) > 0.1


def test_work_precision(tmp_path):
    results = {
        "rk4": ([0.4, 0.1, 0.02], [1e-12, 1e-8, 1e-4]),
        "exact": ([0.05, 0.06], [0.0, 2e-16]),
    }
    ax = plot.work_precision(results)
    render(ax, tmp_path / "work_precision.png", min_kb=10)
    assert ax.get_xscale() == "log" and ax.get_yscale() == "log"
    rk4, exact = lines(ax, "work_precision:")
    np.testing.assert_array_equal(rk4.get_xdata(), [0.02, 0.1, 0.4])
    np.testing.assert_array_equal(rk4.get_ydata(), [1e-4, 1e-8, 1e-12])
    np.testing.assert_array_equal(exact.get_ydata(), [plot.FLOOR, 2e-16])


def test_batch_and_missing_orientation_rejected():
    batch = ph.simulate([[1.0, 2.0, 3.0]] * 2, [OMEGA0] * 2, [0.0, 1.0])
    with pytest.raises(ValueError, match="batch"):
        plot.omega(batch)
    bare = ph.simulate(MOMENTS, OMEGA0, [0.0, 1.0], orientation=False)
    with pytest.raises(ValueError, match="orientation"):
        plot.herpolhode(bare)


def test_import_polhode_does_not_import_matplotlib():
    import subprocess
    import sys

    code = "import sys, polhode, polhode.plot; print('matplotlib' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_perturbation_error_slopes_and_values(tmp_path):
    from polhode.perturbation import perturbation

    axis, times = 1, np.linspace(0.0, 2.0, 41)  # the intermediate axis: growth, the flip
    ax = plot.perturbation_error(MOMENTS, axis=axis)
    render(ax, tmp_path / "perturbation_error.png", min_kb=10)
    assert ax.get_xscale() == "log" and ax.get_yscale() == "log"
    errors = {int(line.get_gid().split(":")[1]): line for line in lines(ax, "perturbation_error:")}
    slopes = {int(line.get_gid().split(":")[1]): line for line in lines(ax, "slope:")}
    assert sorted(errors) == [1, 2] and sorted(slopes) == [2, 3]
    for n, line in errors.items():
        eps, error = np.asarray(line.get_xdata()), np.asarray(line.get_ydata())
        np.testing.assert_allclose(eps, np.logspace(-4.0, -1.0, 13), rtol=1e-15)
        # the order-n expansion is off by O(eps^(n+1)): so is every plotted point
        fitted = np.polyfit(np.log(eps), np.log(error), 1)[0]
        assert abs(fitted - (n + 1)) < 0.05, (n, fitted)
        # the reference line: exactly eps^(n+1), a little below the smallest-eps point
        np.testing.assert_allclose(
            slopes[n + 1].get_ydata(),
            error[0] / plot.SLOPE_OFFSET * (eps / eps[0]) ** (n + 1),
            rtol=1e-12,
        )
        # the plotted errors against scipy's integration rather than polhode's closed form,
        # where the error is far above that integration's own (about 1e-13)
        for k in (6, 9, 12):
            omega0 = eps[k] * np.array(plot.PERTURBATION_DIRECTION)
            omega0[axis] = 1.0
            approx = perturbation(MOMENTS, omega0, times, axis=axis, order=n)
            expected = np.max(np.abs(approx - euler_omega(MOMENTS, omega0, times)))
            assert error[k] == pytest.approx(expected, rel=1e-4), (n, k)


def test_perturbation_error_options_and_errors():
    from matplotlib.figure import Figure

    ax = Figure().add_subplot()
    out = plot.perturbation_error(
        MOMENTS, axis=2, eps=[1e-2, 1e-3, 3e-3], orders=(0,), t=[0.0, 1.0], ax=ax
    )
    assert out is ax
    (line,) = lines(ax, "perturbation_error:0")
    np.testing.assert_array_equal(line.get_xdata(), [1e-3, 3e-3, 1e-2])  # sorted
    (ref,) = lines(ax, "slope:1")
    np.testing.assert_allclose(ref.get_ydata() / ref.get_xdata(), ref.get_ydata()[0] / 1e-3)
    for bad in ([], [0.0, 1e-3], [[1e-3]]):
        with pytest.raises(ValueError, match="eps"):
            plot.perturbation_error(MOMENTS, eps=bad)
    with pytest.raises(ValueError, match="axis"):
        plot.perturbation_error(MOMENTS, axis=3)
    with pytest.raises(ph.PolhodeError, match="order"):
        plot.perturbation_error(MOMENTS, orders=(3,))

"""polhode.bench.kernels: its table has a row per kernel with finite ratios, and its flop and
byte constants are the counts they claim: the flops counted by running each algorithm on
numbers that count their operations (each run checked to compute the right thing against
numpy, trimesh or a closed form), the bytes from the arrays a call reads and writes. (The
timings themselves are not tested: the machine is shared and noisy.)"""

from __future__ import annotations

import math

import numpy as np
import pytest

import polhode as ph
from polhode.bench import adapters, kernels


class Counted:
    """A real number that counts the arithmetic done on it (+, -, *, / and sqrt: one flop
    each; negation and abs are free, as sign flips)."""

    flops = 0

    def __init__(self, x: float) -> None:
        self.x = float(x)

    @staticmethod
    def _x(other: object) -> float:
        return other.x if isinstance(other, Counted) else float(other)  # type: ignore[arg-type]

    def _op(self, value: float) -> Counted:
        Counted.flops += 1
        return Counted(value)

    def __add__(self, o):
        return self._op(self.x + self._x(o))

    __radd__ = __add__

    def __sub__(self, o):
        return self._op(self.x - self._x(o))

    def __rsub__(self, o):
        return self._op(self._x(o) - self.x)

    def __mul__(self, o):
        return self._op(self.x * self._x(o))

    __rmul__ = __mul__

    def __truediv__(self, o):
        return self._op(self.x / self._x(o))

    def __rtruediv__(self, o):
        return self._op(self._x(o) / self.x)

    def __neg__(self):
        return Counted(-self.x)

    def __abs__(self):
        return Counted(abs(self.x))

    def __lt__(self, o):
        return self.x < self._x(o)

    def __float__(self):
        return self.x


def csqrt(x: Counted) -> Counted:
    return x._op(math.sqrt(x.x))


def count(fn, *args):
    """The flops ``fn`` does on Counted arguments, and its result."""
    Counted.flops = 0
    result = fn(*args)
    return Counted.flops, result


# --------------------------------------------------------------------------------------------
# Eigensolve: a cyclic Jacobi rotation on a symmetric 3x3, counted.


def jacobi_rotation(a, v, p, q):
    """Zero a[p][q] of the symmetric ``a`` (lists of Counted), turning the columns p, q of
    ``v`` the same way (Numerical Recipes' update, as in the comment of FLOPS)."""
    r = 3 - p - q
    if a[p][q].x == 0.0:
        return
    theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q])
    sign = 1.0 if theta.x >= 0 else -1.0
    t = sign / (abs(theta) + csqrt(theta * theta + 1.0))
    c = 1.0 / csqrt(t * t + 1.0)
    s = t * c
    apq = a[p][q]
    a[p][p] = a[p][p] - t * apq
    a[q][q] = a[q][q] + t * apq
    a[p][q] = a[q][p] = Counted(0.0)
    arp, arq = a[r][p], a[r][q]
    a[r][p] = a[p][r] = c * arp - s * arq
    a[r][q] = a[q][r] = s * arp + c * arq
    for k in range(3):
        vp, vq = v[k][p], v[k][q]
        v[k][p] = c * vp - s * vq
        v[k][q] = s * vp + c * vq


def jacobi(tensor, sweeps=4):
    a = [[Counted(x) for x in row] for row in tensor]
    v = [[Counted(float(i == j)) for j in range(3)] for i in range(3)]
    for _ in range(sweeps):
        for p, q in ((0, 1), (0, 2), (1, 2)):
            jacobi_rotation(a, v, p, q)
    return np.array([[x.x for x in row] for row in a]), np.array([[x.x for x in r] for r in v])


def test_eigensolve_flops_are_four_sweeps_of_counted_jacobi_rotations():
    rng = np.random.default_rng(5)
    a = rng.normal(size=(3, 3))
    tensor = a + a.T
    flops, (diag, vectors) = count(jacobi, tensor)
    assert flops == kernels.FLOPS["eigensolve"] == kernels.FLOPS["eigensolve_degenerate"]
    # Four sweeps are what double precision takes: the eigenvalues of numpy's eigh.
    np.testing.assert_allclose(
        np.sort(np.diag(diag)), np.linalg.eigh(tensor)[0], rtol=0, atol=1e-14 * 4
    )
    assert np.max(np.abs(diag - np.diag(np.diag(diag)))) < 1e-14 * np.abs(tensor).max()
    np.testing.assert_allclose(tensor @ vectors, vectors * np.diag(diag), atol=1e-13)


# --------------------------------------------------------------------------------------------
# Mesh: Eberly's per-triangle integrals, counted.


def eberly_triangle(v0, v1, v2, integral):
    """Adds one triangle's terms to the ten integrals (1, x, y, z, x^2, y^2, z^2, xy, yz, zx),
    D. Eberly, Polyhedral Mass Properties (Revisited), 2002."""

    def sub(w0, w1, w2):
        temp0 = w0 + w1
        f1 = temp0 + w2
        temp1 = w0 * w0
        temp2 = temp1 + w1 * temp0
        f2 = temp2 + w2 * f1
        f3 = w0 * temp1 + w1 * temp2 + w2 * f2
        g0 = f2 + w0 * (f1 + w0)
        g1 = f2 + w1 * (f1 + w1)
        g2 = f2 + w2 * (f1 + w2)
        return f1, f2, f3, g0, g1, g2

    e1 = [v1[k] - v0[k] for k in range(3)]
    e2 = [v2[k] - v0[k] for k in range(3)]
    d = [
        e1[1] * e2[2] - e1[2] * e2[1],
        e1[2] * e2[0] - e1[0] * e2[2],
        e1[0] * e2[1] - e1[1] * e2[0],
    ]
    f1x, f2x, f3x, g0x, g1x, g2x = sub(v0[0], v1[0], v2[0])
    _, f2y, f3y, g0y, g1y, g2y = sub(v0[1], v1[1], v2[1])
    _, f2z, f3z, g0z, g1z, g2z = sub(v0[2], v1[2], v2[2])
    integral[0] = integral[0] + d[0] * f1x
    integral[1] = integral[1] + d[0] * f2x
    integral[2] = integral[2] + d[1] * f2y
    integral[3] = integral[3] + d[2] * f2z
    integral[4] = integral[4] + d[0] * f3x
    integral[5] = integral[5] + d[1] * f3y
    integral[6] = integral[6] + d[2] * f3z
    integral[7] = integral[7] + d[0] * (v0[1] * g0x + v1[1] * g1x + v2[1] * g2x)
    integral[8] = integral[8] + d[1] * (v0[2] * g0y + v1[2] * g1y + v2[2] * g2y)
    integral[9] = integral[9] + d[2] * (v0[0] * g0z + v1[0] * g1z + v2[0] * g2z)


def test_mesh_flops_are_one_counted_eberly_triangle():
    pytest.importorskip("trimesh")
    vertices, faces = adapters.icosphere(1)
    integral = [Counted(0.0) for _ in range(10)]
    per_face = []
    for face in faces:
        v = [[Counted(x) for x in vertices[i]] for i in face]
        flops, _ = count(eberly_triangle, *v, integral)
        per_face.append(flops)
    assert set(per_face) == {kernels.FLOPS["mesh"]}
    # What the counted algorithm sums is the mesh's mass properties: volume (integral[0] / 6)
    # and the inertia about the centre, as trimesh and polhode give them.
    values = np.array([x.x for x in integral]) / np.array([6, 24, 24, 24, 60, 60, 60, 120, 120,
                                                          120])
    volume = values[0]
    com = values[1:4] / volume
    xx, yy, zz, xy, yz, zx = values[4:]
    inertia = np.array(
        [[yy + zz, -xy, -zx], [-xy, zz + xx, -yz], [-zx, -yz, xx + yy]]
    ) - volume * (np.dot(com, com) * np.eye(3) - np.outer(com, com))
    body = ph.Body.mesh(vertices, faces, density=1.0)
    assert volume == pytest.approx(body.mass, rel=1e-13)
    np.testing.assert_allclose(inertia, body.inertia, atol=1e-13)


# --------------------------------------------------------------------------------------------
# Point masses and rk4, counted.


def two_pass(m, r):
    """The centre, then the centred second moments (the 6 distinct ones) and the tensor."""
    total = Counted(0.0)
    first = [Counted(0.0)] * 3
    for mi, ri in zip(m, r, strict=True):
        total = total + mi
        for k in range(3):
            first[k] = first[k] + mi * ri[k]
    centre = [f / total for f in first]
    second = {}
    for mi, ri in zip(m, r, strict=True):
        d = [ri[k] - centre[k] for k in range(3)]
        md = [mi * dk for dk in d]
        for i, j in ((0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2)):
            second[i, j] = second.get((i, j), 0.0) + md[i] * d[j]
    return second


def test_point_mass_flops_are_the_counted_two_pass_sum():
    rng = np.random.default_rng(2)
    n = 50
    m_np = rng.uniform(0.5, 2.0, n)
    r_np = rng.normal(size=(n, 3))
    m = [Counted(x) for x in m_np]
    r = [[Counted(x) for x in row] for row in r_np]
    flops, second = count(two_pass, m, r)
    # Per point, less the once-per-call work (3 divisions for the centre); the first
    # accumulation of each sum (0.0 + x) counts like the others.
    assert (flops - 3) / n == kernels.FLOPS["point_masses"]
    c = np.zeros((3, 3))
    for (i, j), value in second.items():
        c[i, j] = c[j, i] = float(value)
    np.testing.assert_allclose(
        np.trace(c) * np.eye(3) - c, adapters.point_mass_inertia(m_np, r_np), rtol=1e-13
    )


def rk4_step(c, w, q, dt):
    """One classic RK4 step of Euler's equations (ratios c precomputed) and q' = q (0, w) / 2,
    as polhode's rk4 does it per body: the quaternion's rate without its factor 1/2, which the
    coefficients carry (h/4 for h/2, h/12 for h/6), and 2 (k2 + k3) as a sum. In the normal
    range these are the numbers of :func:`polhode.bench.adapters.numpy_rk4`, which multiplies
    by 1/2 and by 2 (powers of two)."""

    def rate(w, q):
        a, b, cz = w
        x, y, z, s = q
        dw = [c[0] * b * cz, c[1] * cz * a, c[2] * a * b]
        dq2 = [
            s * a + y * cz - z * b,
            s * b + z * a - x * cz,
            s * cz + x * b - y * a,
            -(x * a + y * b + z * cz),
        ]
        return dw, dq2

    def axpy(y, k, h):
        return [yi + h * ki for yi, ki in zip(y, k, strict=True)]

    def combine(y, k1, k2, k3, k4, h):
        out = []
        for yi, a, b, c_, d in zip(y, k1, k2, k3, k4, strict=True):
            m = b + c_
            out.append(yi + h * (a + (m + m) + d))
        return out

    half, sixth = 0.5 * dt, dt / 6.0
    quarter, twelfth = 0.5 * half, 0.5 * sixth
    a1, b1 = rate(w, q)
    a2, b2 = rate(axpy(w, a1, half), axpy(q, b1, quarter))
    a3, b3 = rate(axpy(w, a2, half), axpy(q, b2, quarter))
    a4, b4 = rate(axpy(w, a3, dt), axpy(q, b3, half))
    return combine(w, a1, a2, a3, a4, sixth), combine(q, b1, b2, b3, b4, twelfth)


def test_rk4_flops_are_one_counted_step():
    moments = np.array([1.0, 2.0, 3.0])
    omega0 = np.array([0.3, 0.5, 0.8])
    i1, i2, i3 = moments
    c = [(i2 - i3) / i1, (i3 - i1) / i2, (i1 - i2) / i3]
    w = [Counted(x) for x in omega0]
    q = [Counted(x) for x in (0.0, 0.0, 0.0, 1.0)]
    flops, (w1, q1) = count(rk4_step, c, w, q, 0.01)
    assert flops == kernels.FLOPS["rk4"]
    # The same step as polhode's rk4 (and the numpy peer's).
    traj = ph.simulate(moments, omega0, [0.0, 0.01], method="rk4", dt=0.01)
    np.testing.assert_allclose([float(x) for x in w1], traj.omega[-1], rtol=1e-14)
    quat = np.array([float(x) for x in q1])
    np.testing.assert_allclose(quat / np.linalg.norm(quat), traj.quaternion[-1], atol=1e-12)


# --------------------------------------------------------------------------------------------
# Bytes: what a call reads and writes.


def test_bytes_are_the_arrays_read_and_written():
    n = 16
    tensors = np.broadcast_to(np.diag([1.0, 2.0, 3.0]), (n, 3, 3)).copy()
    p = ph.principal(tensors)
    assert (tensors.nbytes + p.moments.nbytes + p.axes.nbytes) / n == kernels.BYTES["eigensolve"]

    m, r = np.ones(n), np.zeros((n, 3))
    assert (m.nbytes + r.nbytes) / n == kernels.BYTES["point_masses"]


def test_the_eigensolve_floor_writes_what_principal_returns():
    """The note's floor (outputs alone) allocates and writes the very arrays a call returns."""
    from polhode.bench import mass

    n = 16
    tensors = np.broadcast_to(np.diag([1.0, 2.0, 3.0]), (n, 3, 3)).copy()
    p = ph.principal(tensors)
    floor = mass._fresh_outputs(n)
    returned = (p.moments, p.axes, p.multiplicity)
    assert [(a.shape, a.dtype) for a in floor] == [(a.shape, a.dtype) for a in returned]
    assert all(np.all(a == 1) for a in floor)

    t = np.linspace(0.0, 1.0, n)
    for key, orientation in (("exact_full", True), ("exact_omega", False)):
        traj = ph.simulate([1.0, 2.0, 3.0], [0.3, 0.5, 0.8], t, orientation=orientation)
        out = sum(
            getattr(traj, name).nbytes
            for name in ("omega", "quaternion", "angular_momentum_space",
                         "angular_momentum_body", "energy", "rotor_rates")
            if getattr(traj, name) is not None
        )
        assert out / n == kernels.BYTES[key]

    # A batch of bodies: its inputs and its outputs at 2 times, per body.
    moments, omega0 = np.ones((n, 3)), np.zeros((n, 3))
    traj = ph.simulate(moments, omega0, [0.0, 0.1], method="rk4", dt=0.01)
    out = sum(
        getattr(traj, name).nbytes
        for name in ("omega", "quaternion", "angular_momentum_space", "angular_momentum_body",
                     "energy")
    )
    for key in ("rk4", "splitting", "midpoint"):
        assert (moments.nbytes + omega0.nbytes + out) / n == kernels.BYTES[key]


def test_mesh_bytes_are_indices_and_half_a_vertex_per_face():
    pytest.importorskip("trimesh")
    vertices, faces = adapters.icosphere(3)
    per_face = (vertices.nbytes + faces.nbytes) / len(faces)
    assert per_face == pytest.approx(kernels.BYTES["mesh"], rel=2 * 24 / vertices.nbytes)


# --------------------------------------------------------------------------------------------
# The rest of the harness.


def test_elliptic_parameter_gives_the_period_of_analyze():
    from scipy.special import ellipk

    for moments, omega0 in (kernels.EXACT_BODY, ((1.0, 2.0, 3.0), (1.0, 0.2, 0.1))):
        m, rate = kernels.elliptic_parameter(moments, omega0)
        assert 0.0 < m < 1.0
        assert 4.0 * ellipk(m) / rate == pytest.approx(
            ph.analyze(moments, omega0).period, rel=1e-12
        )


def test_peak_flops_is_cores_clock_lanes_and_two_pipes():
    flops, how = kernels.peak_flops(cores=3, ghz=2.0)
    lanes = flops / (3 * 2.0e9 * 2)
    assert lanes in (2.0, 4.0, 8.0)
    assert "3 cores x 2.00 GHz" in how and "no FMA" in how


def test_row_ratio_fraction_and_target():
    row = kernels.Row("k", "rk4", 100, "body-step", "peer", [1.0, 2.0, 3.0], [10.0, 40.0, 30.0],
                      per=10)
    limits = kernels.Limits(bandwidth=1e9, peak_flops=1e10, how="")
    assert row.ratio == 15.0 and row.ours == 0.02 and row.theirs == 0.3
    assert row.bytes == kernels.BYTES["rk4"] / 10
    assert row.met is (15.0 >= kernels.TARGETS["rk4"])
    expected = max(kernels.FLOPS["rk4"] / 1e10, kernels.BYTES["rk4"] / 10 / 1e9) / 0.02
    assert row.fraction(limits) == pytest.approx(expected, rel=1e-15)
    assert kernels.Row("s", "simulate", 1, "call", "p", [1.0], [1.0]).fraction(limits) is None


def test_run_gives_every_row_with_finite_ratios(monkeypatch):
    monkeypatch.setattr(kernels, "SIZES", {
        "eigensolve": (200, 200), "mesh": (1, 1), "point_masses": (500, 500),
        "exact": (50, 50), "batch": (64, 64),
    })
    monkeypatch.setattr(kernels, "SMALL_CALLS", 3)
    result = kernels.run(quick=True, repeats=1, limits_size=2**20)
    assert result.repeats == 5  # at least five, whatever is asked
    keys = [row.key for row in result.rows]
    expected = ["eigensolve", "eigensolve_degenerate", "mesh", "point_masses", "exact_full",
                "exact_omega", "rk4", "splitting", "midpoint", "simulate", "analyze"]
    if adapters.trimesh_version() is None:
        expected.remove("mesh")
        assert result.skipped
    assert keys == expected
    for row in result.rows:
        assert len(row.ours_seconds) == len(row.peer_seconds) == 5
        assert math.isfinite(row.ratio) and row.ratio > 0
        assert math.isfinite(row.ours) and row.ours > 0
        fraction = row.fraction(result.limits)
        assert fraction is None or (math.isfinite(fraction) and fraction > 0)
        assert (row.flops is None) == (fraction is None)
    assert result.limits.bandwidth > 0 and result.limits.peak_flops > 0
    table = result.table()
    lines = table.splitlines()
    assert lines[0].startswith("| kernel | polhode per element | peer |")
    assert "fraction of the limit" in lines[0]
    rows = [line for line in lines if line.startswith("| ") and not line.startswith("| ---")]
    assert len(rows) == 1 + len(result.rows)
    assert all(line.count("|") == 11 for line in rows)


def test_run_only_some_groups(monkeypatch):
    monkeypatch.setattr(kernels, "SIZES", {**kernels.SIZES, "eigensolve": (200, 200)})
    monkeypatch.setattr(kernels, "SMALL_CALLS", 3)
    result = kernels.run(quick=True, repeats=1, limits_size=2**20,
                         only=["small_calls", "eigensolve"])
    # In the table's order, whatever the order asked.
    assert [row.key for row in result.rows] == [
        "eigensolve", "eigensolve_degenerate", "simulate", "analyze"]
    for only in (["eigen"], []):
        with pytest.raises(ph.errors.ArgumentError, match="only") as error:
            kernels.run(quick=True, only=only)
        assert error.value.argument == "only"


def test_polhode_bench_kernels_prints_the_table(monkeypatch, capsys):
    from polhode.cli import main

    calls = []

    def fake_run(quick=False, repeats=5, limits_size=None):
        calls.append((quick, repeats))
        row = kernels.Row("k", "rk4", 10, "body-step", "numpy", [1.0] * 5, [2.0] * 5)
        return kernels.Kernels([row], kernels.Limits(1e10, 1e11, "limits"), 5)

    monkeypatch.setattr(kernels, "run", fake_run)
    assert main(["bench", "--kernels", "--quick"]) == 0
    out = capsys.readouterr().out
    assert calls == [(True, 5)]
    assert "# polhode bench --kernels --quick" in out
    assert "| k | 100 ms | numpy | 200 ms | 2x | 30x | **no** | 188 |" in out


def test_report_has_a_kernels_section(monkeypatch):
    """benchmarks/report.py writes the table and names the rows that miss their target."""
    import importlib.util
    from pathlib import Path

    path = Path(__file__).resolve().parents[1] / "benchmarks" / "report.py"
    if not path.exists():
        pytest.skip("benchmarks/ is not beside the tests")
    spec = importlib.util.spec_from_file_location("report_under_test", path)
    report = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(report)
    rows = [
        kernels.Row("fast kernel", "rk4", 10, "body-step", "numpy", [1.0] * 5, [40.0] * 5),
        kernels.Row("slow kernel", "mesh", 10, "face", "trimesh", [1.0] * 5, [2.0] * 5),
    ]
    monkeypatch.setattr(
        kernels, "run",
        lambda quick=False, repeats=5: kernels.Kernels(rows, kernels.Limits(1e10, 1e11, "x"), 5),
    )
    lines = report._kernels_section(True, 5)
    assert lines[0] == "## Kernels against the hardware"
    assert "| fast kernel | 100 ms | numpy | 4 s | 40x | 30x | yes | 188 |" in "\n".join(lines)
    assert "- Targets met: 1 of 2; not met: slow kernel." in lines

"""Independent reference for polhode's mass properties and principal axes.

Written apart from the Rust core, from the textbook definitions only (Landau-Lifshitz par. 32,
Goldstein ch. 5): numpy for the everyday cases, exact rational arithmetic (``fractions``) and
mpmath where float64 alone is not accurate enough. Nothing here imports polhode.

Conventions (docs/architecture.md): the inertia tensor is the full symmetric 3x3 with products
of inertia as tensor elements, ``I_ij = sum_p m_p (r_p^2 delta_ij - r_pi r_pj)``; principal moments
ascending; principal axes are the columns of a proper rotation; quaternions are scalar-last
``(x, y, z, w)``; a rotation maps ``x_new = R x``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from fractions import Fraction
from typing import NamedTuple

import mpmath
import numpy as np
from numpy.polynomial.legendre import leggauss
from scipy.spatial.transform import Rotation

EPS = float(np.finfo(np.float64).eps)
IDENTITY = np.eye(3)


class MassProperties(NamedTuple):
    """Mass, centre of mass (3,) and inertia (3,3) about the centre of mass, body axes."""

    mass: float
    center_of_mass: np.ndarray
    inertia: np.ndarray


def inertia_from_second_moment(second_moment: np.ndarray) -> np.ndarray:
    """``I = tr(C) 1 - C`` for the second-moment matrix ``C = sum m r r^T``."""
    c = np.asarray(second_moment, dtype=float)
    return np.trace(c) * IDENTITY - c


def second_moment_from_inertia(inertia: np.ndarray) -> np.ndarray:
    """``C = (tr I / 2) 1 - I``; positive semidefinite iff I obeys the triangle inequality."""
    i = np.asarray(inertia, dtype=float)
    return 0.5 * np.trace(i) * IDENTITY - i


# ---------------------------------------------------------------------------------------------
# Point masses
# ---------------------------------------------------------------------------------------------


def _fractions(values) -> list:
    return [Fraction(float(v)) for v in np.asarray(values, dtype=float).ravel()]


def point_mass_properties_exact(masses, positions, point=None) -> MassProperties:
    """Mass, centre of mass and inertia of point masses, in exact rational arithmetic.

    Every float64 input is an exact rational, so the only error is the final rounding of each
    output element (correctly rounded). The inertia is about the centre of mass, or about
    ``point`` if one is given. No far-origin cancellation can occur: the second moment about
    the centre is ``Q - S S^T / M`` evaluated exactly.
    """
    m = _fractions(masses)
    r = np.asarray(positions, dtype=float).reshape(-1, 3)
    if len(m) != r.shape[0] or not m:
        raise ValueError("masses and positions must have the same non-zero length")
    rf = [_fractions(row) for row in r]
    total = sum(m, Fraction(0))
    pairs = list(zip(m, rf, strict=True))
    first = [sum((mk * rk[i] for mk, rk in pairs), Fraction(0)) for i in range(3)]
    raw = [
        [sum((mk * rk[i] * rk[j] for mk, rk in pairs), Fraction(0)) for j in range(3)]
        for i in range(3)
    ]
    com = [s / total for s in first]
    if point is None:
        # C about the centre of mass: Q - S S^T / M.
        c = [[raw[i][j] - first[i] * first[j] / total for j in range(3)] for i in range(3)]
    else:
        p = _fractions(point)
        # C about p: Q - S p^T - p S^T + M p p^T.
        c = [
            [raw[i][j] - first[i] * p[j] - p[i] * first[j] + total * p[i] * p[j] for j in range(3)]
            for i in range(3)
        ]
    trace = c[0][0] + c[1][1] + c[2][2]
    inertia = np.array(
        [[float((trace if i == j else 0) - c[i][j]) for j in range(3)] for i in range(3)]
    )
    return MassProperties(float(total), np.array([float(x) for x in com]), inertia)


def point_mass_properties(masses, positions) -> MassProperties:
    """The same in float64 numpy, computed carefully: centre first, then second moments.

    The centre of mass gets one refinement pass (the mean of the residuals), so the centred
    coordinates are accurate even for a cloud far from the origin; the second moment is then a
    sum of positive-weighted products of small numbers.
    """
    m = np.asarray(masses, dtype=float)
    r = np.asarray(positions, dtype=float).reshape(-1, 3)
    total = math.fsum(m)
    com = np.array([math.fsum(m * r[:, i]) for i in range(3)]) / total
    com = com + np.array([math.fsum(m * (r[:, i] - com[i])) for i in range(3)]) / total
    d = r - com
    c = np.einsum("k,ki,kj->ij", m, d, d)
    return MassProperties(total, com, inertia_from_second_moment(c))


def point_inertia_about(masses, positions, point) -> np.ndarray:
    """Inertia of point masses about ``point``, exact then rounded."""
    return point_mass_properties_exact(masses, positions, point=point).inertia


def centred_cloud_exact(masses, positions) -> np.ndarray:
    """Rows ``sqrt(m_k) (r_k - r_cm)`` with ``r_k - r_cm`` exact then rounded once."""
    m = _fractions(masses)
    r = np.asarray(positions, dtype=float).reshape(-1, 3)
    rf = [_fractions(row) for row in r]
    total = sum(m, Fraction(0))
    pairs = list(zip(m, rf, strict=True))
    com = [sum((mk * rk[i] for mk, rk in pairs), Fraction(0)) / total for i in range(3)]
    centred = np.array([[float(rk[i] - com[i]) for i in range(3)] for rk in rf])
    return np.sqrt(np.asarray(masses, dtype=float))[:, None] * centred


# ---------------------------------------------------------------------------------------------
# Closed forms of the solids (about the centre of mass, body axes)
# ---------------------------------------------------------------------------------------------


def _diag(mass, com, ixx, iyy, izz) -> MassProperties:
    return MassProperties(float(mass), np.asarray(com, dtype=float), np.diag([ixx, iyy, izz]))


def sphere(mass, radius) -> MassProperties:
    """Solid sphere: 2/5 m r^2."""
    i = 0.4 * mass * radius**2
    return _diag(mass, (0, 0, 0), i, i, i)


def spherical_shell(mass, radius) -> MassProperties:
    """Thin hollow sphere: 2/3 m r^2."""
    i = 2.0 / 3.0 * mass * radius**2
    return _diag(mass, (0, 0, 0), i, i, i)


def cuboid(mass, size) -> MassProperties:
    """Box with full edges (a, b, c): I_x = m (b^2 + c^2) / 12, cyclic."""
    a, b, c = (float(s) for s in size)
    return _diag(
        mass,
        (0, 0, 0),
        mass * (b * b + c * c) / 12,
        mass * (a * a + c * c) / 12,
        mass * (a * a + b * b) / 12,
    )


def cylinder(mass, radius, length) -> MassProperties:
    """Solid cylinder along z: I_z = m r^2 / 2, I_x = m (3 r^2 + L^2) / 12."""
    ix = mass * (3 * radius**2 + length**2) / 12
    return _diag(mass, (0, 0, 0), ix, ix, mass * radius**2 / 2)


def tube(mass, inner_radius, outer_radius, length) -> MassProperties:
    """Thick tube along z: I_z = m (r1^2 + r2^2) / 2, I_x = m (3 (r1^2 + r2^2) + L^2) / 12."""
    s = inner_radius**2 + outer_radius**2
    ix = mass * (3 * s + length**2) / 12
    return _diag(mass, (0, 0, 0), ix, ix, mass * s / 2)


def cone(mass, radius, length) -> MassProperties:
    """Solid cone, base in z = 0, apex at z = L (its length): centre of mass at L/4,
    I_z = 3/10 m r^2, I_x = 3/20 m r^2 + 3/80 m L^2 about the centre of mass."""
    ix = mass * (3 * radius**2 / 20 + 3 * length**2 / 80)
    return _diag(mass, (0, 0, length / 4), ix, ix, 0.3 * mass * radius**2)


def ellipsoid(mass, semi_axes) -> MassProperties:
    """Solid ellipsoid: I_x = m (b^2 + c^2) / 5, cyclic."""
    a, b, c = (float(s) for s in semi_axes)
    return _diag(
        mass,
        (0, 0, 0),
        mass * (b * b + c * c) / 5,
        mass * (a * a + c * c) / 5,
        mass * (a * a + b * b) / 5,
    )


def rod(mass, length) -> MassProperties:
    """Thin rod along z: m L^2 / 12 about x and y, 0 about z."""
    i = mass * length**2 / 12
    return _diag(mass, (0, 0, 0), i, i, 0.0)


def disk(mass, radius) -> MassProperties:
    """Thin disc in the xy plane: I_z = m r^2 / 2, I_x = I_y = m r^2 / 4."""
    return _diag(mass, (0, 0, 0), mass * radius**2 / 4, mass * radius**2 / 4, mass * radius**2 / 2)


def torus(mass, major_radius, minor_radius) -> MassProperties:
    """Solid ring torus about z: I_z = m (R^2 + 3 a^2 / 4), I_x = m (R^2 / 2 + 5 a^2 / 8)."""
    big, a = major_radius, minor_radius
    return _diag(
        mass,
        (0, 0, 0),
        mass * (big**2 / 2 + 5 * a**2 / 8),
        mass * (big**2 / 2 + 5 * a**2 / 8),
        mass * (big**2 + 3 * a**2 / 4),
    )


def capsule(mass, radius, length) -> MassProperties:
    """Cylinder of `length` plus two hemispherical caps, axis z, mass split by volume.

    Derivation (checked against quadrature in the tests): a hemisphere of mass m_h has its
    centre of mass 3r/8 from its flat face and I = 2/5 m_h r^2 about a diameter of that face,
    so 83/320 m_h r^2 about its own centre; shifted by h/2 + 3r/8 this gives per cap
    m_h (2r^2/5 + h^2/4 + 3hr/8).
    """
    r, h = radius, length
    cylinder_volume = math.pi * r * r * h
    caps_volume = 4.0 / 3.0 * math.pi * r**3
    m_c = mass * cylinder_volume / (cylinder_volume + caps_volume)
    m_s = mass * caps_volume / (cylinder_volume + caps_volume)
    iz = m_c * r * r / 2 + 0.4 * m_s * r * r
    ix = m_c * (3 * r * r + h * h) / 12 + m_s * (0.4 * r * r + h * h / 4 + 3 * h * r / 8)
    return _diag(mass, (0, 0, 0), ix, ix, iz)


SOLIDS = {
    "sphere": sphere,
    "spherical_shell": spherical_shell,
    "cuboid": cuboid,
    "cylinder": cylinder,
    "tube": tube,
    "cone": cone,
    "ellipsoid": ellipsoid,
    "rod": rod,
    "disk": disk,
    "torus": torus,
    "capsule": capsule,
}


# ---------------------------------------------------------------------------------------------
# Numerical integration of the solids (to check the closed forms themselves)
# ---------------------------------------------------------------------------------------------


def _ring(n_phi: int, phase: float = 0.3):
    """Equally spaced azimuths: exact for the azimuthal averages of cos^2, sin^2, cos sin
    (trigonometric polynomials of degree < n_phi) once n_phi >= 3."""
    return phase + 2 * np.pi * np.arange(n_phi) / n_phi


def _gauss(a: float, b: float, n: int):
    """Gauss-Legendre nodes and weights on [a, b] (exact for polynomials of degree 2n - 1)."""
    x, w = leggauss(n)
    return 0.5 * (b - a) * x + 0.5 * (b + a), 0.5 * (b - a) * w


def _revolve(rho, z, weight, n_phi=7):
    """Points of a body of revolution: meridian nodes (rho, z, weight incl. rho) times a ring."""
    phi = _ring(n_phi)
    rho, z, weight = (np.asarray(v, dtype=float).ravel() for v in (rho, z, weight))
    pts = np.stack(
        [
            np.outer(rho, np.cos(phi)).ravel(),
            np.outer(rho, np.sin(phi)).ravel(),
            np.repeat(z, phi.size),
        ],
        axis=1,
    )
    return np.repeat(weight, phi.size), pts


def _ball(radius, mu_range=(-1.0, 1.0), n=6):
    t, wt = _gauss(0.0, radius, n)
    mu, wmu = _gauss(mu_range[0], mu_range[1], n)
    tt, mm = np.meshgrid(t, mu, indexing="ij")
    w = np.outer(wt * t * t, wmu)  # r^2 dr dmu (dphi in the ring); rho = r sqrt(1 - mu^2)
    rho = tt * np.sqrt(1 - mm * mm)
    # The ring adds no rho Jacobian here: the weight already is the volume element / dphi.
    return rho, tt * mm, w


def quadrature_cloud(shape: str, mass: float, *params, n: int = 6):
    """Point masses whose inertia equals the solid's up to round-off.

    A product Gauss-Legendre rule (exact for the polynomial integrands involved) in the
    meridian coordinates, times an equally spaced ring in azimuth (exact for the azimuthal
    averages), with the total weight normalised to ``mass``. Independent of the closed forms:
    it only encodes each body's geometry.
    """
    if shape == "cuboid":
        nodes = [_gauss(-s / 2, s / 2, n) for s in params[0]]
        grids = np.meshgrid(*[x for x, _ in nodes], indexing="ij")
        weights = np.einsum("i,j,k->ijk", *[w for _, w in nodes])
        w, pts = weights.ravel(), np.stack([g.ravel() for g in grids], axis=1)
    elif shape in ("sphere", "ellipsoid"):
        rho, z, w = _ball(1.0 if shape == "ellipsoid" else params[0], n=n)
        w, pts = _revolve(rho, z, w)
        if shape == "ellipsoid":
            pts = pts * np.asarray(params[0], dtype=float)
    elif shape == "spherical_shell":
        radius = params[0]
        mu, wmu = _gauss(-1.0, 1.0, n)
        w, pts = _revolve(radius * np.sqrt(1 - mu * mu), radius * mu, wmu)
    elif shape in ("cylinder", "tube"):
        inner, outer, length = (0.0, *params) if shape == "cylinder" else params
        rho, wr = _gauss(inner, outer, n)
        z, wz = _gauss(-length / 2, length / 2, n)
        rr, zz = np.meshgrid(rho, z, indexing="ij")
        w, pts = _revolve(rr, zz, np.outer(wr * rho, wz))
    elif shape == "cone":
        radius, length = params
        z, wz = _gauss(0.0, length, n)
        s, ws = _gauss(0.0, 1.0, n)
        zz, ss = np.meshgrid(z, s, indexing="ij")
        scale = radius * (1 - zz / length)  # rho = scale * s, d rho = scale ds
        w, pts = _revolve(scale * ss, zz, np.outer(wz, ws) * scale * scale * ss)
    elif shape == "torus":
        big, a = params
        t, wt = _gauss(0.0, a, n)
        theta = _ring(9, phase=0.1)
        tt, th = np.meshgrid(t, theta, indexing="ij")
        rho = big + tt * np.cos(th)
        w, pts = _revolve(rho, tt * np.sin(th), np.outer(wt * t, np.full(theta.size, 1.0)) * rho)
    elif shape == "capsule":
        radius, length = params
        rho, wr = _gauss(0.0, radius, n)
        z, wz = _gauss(-length / 2, length / 2, n)
        rr, zz = np.meshgrid(rho, z, indexing="ij")
        parts = [_revolve(rr, zz, np.outer(wr * rho, wz))]
        for sign in (1.0, -1.0):
            r_cap, z_cap, w_cap = _ball(radius, mu_range=(0.0, 1.0), n=n)
            parts.append(_revolve(r_cap, sign * (z_cap + length / 2), w_cap))
        w = np.concatenate([p[0] for p in parts])
        pts = np.concatenate([p[1] for p in parts])
    elif shape == "rod":
        z, w = _gauss(-params[0] / 2, params[0] / 2, n)
        pts = np.stack([np.zeros_like(z), np.zeros_like(z), z], axis=1)
    elif shape == "disk":
        rho, wr = _gauss(0.0, params[0], n)
        w, pts = _revolve(rho, np.zeros_like(rho), wr * rho)
    else:
        raise KeyError(shape)
    return mass * w / math.fsum(w), pts


def revolution_moments_mp(rho_in, rho_out, z_breaks, dps: int = 30):
    """Volume, z of the centre of mass, and I_z / m, I_x / m about the centre of mass, of a
    solid of revolution between radii rho_in(z) <= rho <= rho_out(z), by mpmath tanh-sinh
    quadrature in z (the rho and phi integrals are done in closed form).

    V = int pi (ro^2 - ri^2) dz; int rho^2 dV = int pi (ro^4 - ri^4) / 2 dz;
    int z^k dV = int pi z^k (ro^2 - ri^2) dz; I_x = int (rho^2 / 2 + z^2) dV (azimuthal mean).
    """
    with mpmath.workdps(dps):

        def area(z):
            return mpmath.pi * (rho_out(z) ** 2 - rho_in(z) ** 2)

        volume = mpmath.quad(area, z_breaks)
        z1 = mpmath.quad(lambda z: z * area(z), z_breaks) / volume
        z2 = mpmath.quad(lambda z: z * z * area(z), z_breaks) / volume
        rho2 = (
            mpmath.quad(lambda z: mpmath.pi * (rho_out(z) ** 4 - rho_in(z) ** 4) / 2, z_breaks)
            / volume
        )
        iz = rho2
        ix = rho2 / 2 + z2 - z1 * z1
        return float(volume), float(z1), float(iz), float(ix)


# ---------------------------------------------------------------------------------------------
# Rotations, shifts, composition
# ---------------------------------------------------------------------------------------------


def rotation_matrix(rotation) -> np.ndarray:
    """A scipy Rotation, a (3,3) matrix or an (x, y, z, w) quaternion as a (3,3) matrix."""
    if isinstance(rotation, Rotation):
        return rotation.as_matrix()
    a = np.asarray(rotation, dtype=float)
    if a.shape == (4,):
        return Rotation.from_quat(a).as_matrix()
    if a.shape == (3, 3):
        return a
    raise ValueError(f"not a rotation: shape {a.shape}")


def rotate(props: MassProperties, rotation) -> MassProperties:
    """Rotate a body in its own axes: x_new = R x, so c' = R c and I' = R I R^T."""
    r = rotation_matrix(rotation)
    return MassProperties(props.mass, r @ props.center_of_mass, r @ props.inertia @ r.T)


def translate(props: MassProperties, offset) -> MassProperties:
    return MassProperties(
        props.mass, props.center_of_mass + np.asarray(offset, dtype=float), props.inertia
    )


def parallel_axis(inertia_com, mass, center_of_mass, point) -> np.ndarray:
    """Steiner: I_p = I_cm + M (|d|^2 1 - d d^T) with d = r_cm - p."""
    d = np.asarray(center_of_mass, dtype=float) - np.asarray(point, dtype=float)
    return np.asarray(inertia_com, dtype=float) + mass * (d @ d * IDENTITY - np.outer(d, d))


def shift_origin(inertia_origin, mass, center_of_mass, shift) -> np.ndarray:
    """General origin shift for new coordinates r' = r + R (inertia about the old origin in,
    about the new origin out; r_cm in the old coordinates):

    I'_ij = I_ij + M (R^2 d_ij - R_i R_j) + M (2 r_cm . R d_ij - r_cm_i R_j - R_i r_cm_j).
    """
    big_r = np.asarray(shift, dtype=float)
    c = np.asarray(center_of_mass, dtype=float)
    return (
        np.asarray(inertia_origin, dtype=float)
        + mass * (big_r @ big_r * IDENTITY - np.outer(big_r, big_r))
        + mass * (2 * (c @ big_r) * IDENTITY - np.outer(c, big_r) - np.outer(big_r, c))
    )


def compose(parts: Sequence[MassProperties]) -> MassProperties:
    """Composite body: total mass, mass-weighted centre, parallel-axis sum about it."""
    total = math.fsum(p.mass for p in parts)
    com = np.array([math.fsum(p.mass * p.center_of_mass[i] for p in parts) for i in range(3)])
    com = com / total
    inertia = sum(
        (parallel_axis(p.inertia, p.mass, p.center_of_mass, com) for p in parts), np.zeros((3, 3))
    )
    return MassProperties(total, com, inertia)


# ---------------------------------------------------------------------------------------------
# Principal axes
# ---------------------------------------------------------------------------------------------


def canonical_signs(axes: np.ndarray) -> np.ndarray:
    """The contract's sign convention for non-degenerate axes: the largest-magnitude component
    of the first two columns positive, the third column their cross product (det = +1)."""
    v = np.array(axes, dtype=float)
    for k in range(2):
        if v[np.argmax(np.abs(v[:, k])), k] < 0:
            v[:, k] = -v[:, k]
    v[:, 2] = np.cross(v[:, 0], v[:, 1])
    return v


def principal_eigh(inertia):
    """numpy.linalg.eigh after subtracting trace/3 (the shift is what keeps the axes of
    1e8 1 + 1e-8 E right); moments ascending, axes with canonical signs."""
    a = np.asarray(inertia, dtype=float)
    shift = np.trace(a) / 3
    w, v = np.linalg.eigh(a - shift * IDENTITY)
    return w + shift, canonical_signs(v)


def principal_svd(masses, positions):
    """Principal moments and axes of point masses from the SVD of the centred cloud
    X = sqrt(m) (r - r_cm): C = X^T X has eigenvalues s_k^2, and I_k = sum_j s_j^2 - s_k^2 =
    the sum of the two other s^2, so the smallest moment s_2^2 + s_3^2 carries no cancellation
    (unlike eig(I), which loses it against the largest moment)."""
    x = centred_cloud_exact(masses, positions)
    _, s, vt = np.linalg.svd(x, full_matrices=False)
    s = np.concatenate([s, np.zeros(3 - s.size)])
    c = s * s
    moments = np.array([c[1] + c[2], c[0] + c[2], c[0] + c[1]])
    v = vt.T
    if v.shape[1] < 3:  # fewer than 3 points: complete the frame
        v = np.linalg.qr(np.concatenate([v, np.eye(3)], axis=1))[0][:, :3]
    return moments, canonical_signs(v)


def eigh_mp(matrix, dps: int = 50):
    """Eigenvalues (ascending, mpf) and eigenvectors (float64 columns) of a symmetric float
    matrix taken as exact, in mpmath at `dps` digits."""
    with mpmath.workdps(dps):
        a = mpmath.matrix([[mpmath.mpf(float(x)) for x in row] for row in np.asarray(matrix)])
        e, q = mpmath.eigsy(a)
        order = sorted(range(3), key=lambda k: e[k])
        values = [e[k] for k in order]
        vectors = np.array([[float(q[i, k]) for k in order] for i in range(3)])
    return values, vectors


def principal_cloud_mp(masses, positions, dps: int = 50):
    """Principal moments of point masses to ~dps digits: the exact centred second moment
    C = sum m (r - r_cm)(r - r_cm)^T in mpmath, its eigenvalues c_k, and I_k = the sum of the
    two other c. Returns float64 moments (ascending) and axes."""
    m = _fractions(masses)
    r = np.asarray(positions, dtype=float).reshape(-1, 3)
    rf = [_fractions(row) for row in r]
    total = sum(m, Fraction(0))
    pairs = list(zip(m, rf, strict=True))
    com = [sum((mk * rk[i] for mk, rk in pairs), Fraction(0)) / total for i in range(3)]
    with mpmath.workdps(dps):

        def mpq(q: Fraction):
            return mpmath.mpf(q.numerator) / q.denominator

        d = [[mpq(rk[i] - com[i]) for i in range(3)] for rk in rf]
        mm = [mpq(mk) for mk in m]
        c = mpmath.matrix(3, 3)
        for i in range(3):
            for j in range(3):
                c[i, j] = mpmath.fsum(mk * dk[i] * dk[j] for mk, dk in zip(mm, d, strict=True))
        e, q = mpmath.eigsy(c)
        order = sorted(range(3), key=lambda k: -e[k])  # largest c = smallest moment
        ce = [e[k] for k in order]
        moments = [ce[1] + ce[2], ce[0] + ce[2], ce[0] + ce[1]]
        axes = np.array([[float(q[i, k]) for k in order] for i in range(3)])
        return np.array([float(x) for x in moments]), canonical_signs(axes)


def axis_angle(u, v) -> float:
    """Angle between two lines (sign-agnostic), accurate for tiny angles: atan2(|u x v|, |u.v|)."""
    u = np.asarray(u, dtype=float)
    v = np.asarray(v, dtype=float)
    return math.atan2(float(np.linalg.norm(np.cross(u, v))), abs(float(u @ v)))


def subspace_distance(u, w) -> float:
    """Sine of the largest principal angle between the column spans of u and w (orthonormal)."""
    u = np.asarray(u, dtype=float).reshape(3, -1)
    w = np.asarray(w, dtype=float).reshape(3, -1)
    return float(np.linalg.norm(u @ u.T - w @ w.T, 2))


def random_rotation(rng: np.random.Generator) -> np.ndarray:
    """A uniformly distributed proper rotation matrix."""
    q = rng.normal(size=4)
    return Rotation.from_quat(q / np.linalg.norm(q)).as_matrix()


# ---------------------------------------------------------------------------------------------
# Textbook bodies
# ---------------------------------------------------------------------------------------------


def planar_molecule(m1, m2, m3, bond_length, bond_angle):
    """A rigid triatomic molecule in the xy plane: atom 1 at the origin, atoms 2 and 3 at
    `bond_length` from it, `bond_angle` between the bonds, the bisector along +x.
    Returns (masses (3,), positions (3,3))."""
    h = bond_angle / 2
    positions = np.array(
        [
            [0.0, 0.0, 0.0],
            [bond_length * math.cos(h), bond_length * math.sin(h), 0.0],
            [bond_length * math.cos(h), -bond_length * math.sin(h), 0.0],
        ]
    )
    return np.array([m1, m2, m3], dtype=float), positions


def planar_molecule_inertia_at_atom1(m1, m2, m3, d, alpha) -> np.ndarray:
    """Closed form about atom 1: I_xx = (m2 + m3) d^2 sin^2(a/2), I_yy = (m2 + m3) d^2 cos^2(a/2),
    I_zz = (m2 + m3) d^2, I_xy = -(m2 - m3) d^2 sin(a/2) cos(a/2)."""
    s, c = math.sin(alpha / 2), math.cos(alpha / 2)
    ixy = -(m2 - m3) * d * d * s * c
    return np.array(
        [
            [(m2 + m3) * d * d * s * s, ixy, 0.0],
            [ixy, (m2 + m3) * d * d * c * c, 0.0],
            [0.0, 0.0, (m2 + m3) * d * d],
        ]
    )


def symmetric_molecule_moments(m_center, m_end, d, alpha) -> np.ndarray:
    """Principal moments about the centre of mass of a symmetric triatomic (m2 = m3 = m_end):
    along the bisector (x) I = 2 m_end d^2 sin^2(a/2); across it in plane (y)
    I = 2 m_end m_center d^2 cos^2(a/2) / M; perpendicular (z) their sum (planar body)."""
    big_m = m_center + 2 * m_end
    s, c = math.sin(alpha / 2), math.cos(alpha / 2)
    ix = 2 * m_end * d * d * s * s
    iy = 2 * m_end * m_center * d * d * c * c / big_m
    return np.array(sorted([ix, iy, ix + iy]))


def cube_corners(side: float = 1.0, offset=(0.0, 0.0, 0.0)):
    """Eight unit masses at the corners of a cube, optionally shifted by `offset`."""
    corners = np.array([[i, j, k] for i in (0, 1) for j in (0, 1) for k in (0, 1)], dtype=float)
    return np.ones(8), corners * side + np.asarray(offset, dtype=float)


def qmul(a, b):
    """Hamilton product of scalar-last (x, y, z, w) quaternions, in numpy."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return np.array(
        [
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz,
        ]
    )


def euler_rhs(moments):
    """Euler's torque-free equations in principal axes, w' = f(t, w), for scipy's solve_ivp."""
    i1, i2, i3 = moments

    def rhs(_t, w):
        return [
            (i2 - i3) / i1 * w[1] * w[2],
            (i3 - i1) / i2 * w[2] * w[0],
            (i1 - i2) / i3 * w[0] * w[1],
        ]

    return rhs


def euler_omega(moments, omega0, times):
    """omega at ``times`` (from t = 0) by scipy's DOP853 at rtol 1e-13 (independent of
    polhode), shape (M, 3)."""
    from scipy.integrate import solve_ivp

    sol = solve_ivp(
        euler_rhs(moments),
        (0.0, times[-1]),
        omega0,
        t_eval=times,
        method="DOP853",
        rtol=1e-13,
        atol=1e-16,
    )
    return sol.y.T


def rotate_by_quaternion(q, v):
    """v rotated by the unit quaternion q = (x, y, z, w): R(q) v."""
    x, y, z, w = q
    u = np.array([x, y, z])
    v = np.asarray(v, dtype=float)
    return v + 2.0 * np.cross(u, np.cross(u, v) + w * v)


def rigid_body(inertia, omega0, quaternion0, times, torque, breaks=(), rtol=1e-12):
    """Euler's equations in the body's own axes with the full inertia tensor (not principal
    axes), ``I w' = tau(t, w, q) - w x (I w)`` and ``q' = q (x) (0, w) / 2`` (body to space,
    scalar-last), by scipy's DOP853, restarted at ``breaks`` (the torque's jumps; within a
    piece the torque is asked for times strictly inside it).

    ``torque(t, w, q)`` gives the torque in body axes. Returns omega (M, 3) and the unit
    quaternion (M, 4). Independent of polhode: no principal axes.
    """
    from scipy.integrate import solve_ivp

    inertia = np.asarray(inertia, dtype=float)
    inverse = np.linalg.inv(inertia)
    times = np.asarray(times, dtype=float)
    y = np.concatenate([np.asarray(omega0, float), np.asarray(quaternion0, float)])
    edges = [0.0, *sorted(b for b in breaks if 0.0 < b < times[-1]), float(times[-1])]
    out = np.empty((times.size, 7))
    out[times == 0.0] = y
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        lo, hi = np.nextafter(a, b), np.nextafter(b, a)

        def rhs(t, y, lo=lo, hi=hi):
            w, q = y[:3], y[3:] / np.linalg.norm(y[3:])
            tau = np.asarray(torque(min(max(t, lo), hi), w, q), dtype=float)
            dw = inverse @ (tau - np.cross(w, inertia @ w))
            dq = 0.5 * qmul(y[3:], np.array([w[0], w[1], w[2], 0.0]))
            return np.concatenate([dw, dq])

        sol = solve_ivp(rhs, (a, b), y, method="DOP853", rtol=rtol, atol=rtol * 1e-3,
                        dense_output=True)
        inside = (times > a) & (times <= b)
        out[inside] = sol.sol(times[inside]).T
        y = sol.y[:, -1]
    q = out[:, 3:] / np.linalg.norm(out[:, 3:], axis=1)[:, None]
    return out[:, :3], q


def fixed_axis_rpy_matrix(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """The rotation of URDF's ``rpy``: fixed axes x, y, z in that order, R = Rz(yaw) Ry(pitch)
    Rx(roll), written out from the three elementary rotations."""
    cr, sr = math.cos(roll), math.sin(roll)
    cp, sp = math.cos(pitch), math.sin(pitch)
    cy, sy = math.cos(yaw), math.sin(yaw)
    rx = np.array([[1.0, 0.0, 0.0], [0.0, cr, -sr], [0.0, sr, cr]])
    ry = np.array([[cp, 0.0, sp], [0.0, 1.0, 0.0], [-sp, 0.0, cp]])
    rz = np.array([[cy, -sy, 0.0], [sy, cy, 0.0], [0.0, 0.0, 1.0]])
    return rz @ ry @ rx


def eigvalsh_mp(matrix, dps: int = 60) -> list:
    """Eigenvalues (ascending, mpf) of a symmetric float matrix taken as exact, at ``dps``
    digits: mpmath's exponents are unbounded, so tensors of 1e300 or 1e-310 are no harder than
    tensors of 1."""
    return eigh_mp(matrix, dps)[0]

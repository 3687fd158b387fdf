//! The symmetric 3x3 eigensolve behind principal axes.
//!
//! Inertia tensors are degenerate or nearly so whenever a body has a symmetry, and closed-form
//! (Cardano) solvers lose half the digits there. This module uses cyclic Jacobi rotations on the
//! tensor shifted by `trace/3` (backward stable: residual of a few eps ||A|| on every input) and a
//! one-sided (Hestenes) Jacobi SVD for the square-root factors kept by
//! [`MassProperties`](crate::MassProperties). Both then go through one canonicalisation: moments
//! ascending, axes a proper rotation with deterministic signs, and inside a degenerate subspace
//! the frame closest to the body's own axes.

use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;

use crate::error::{Error, Result};

/// Default relative tolerance under which two principal moments count as equal.
///
/// Relative to the accuracy scale of the representation (`||A||_F` for a plain tensor, the
/// anisotropic part for a [`MassProperties`](crate::MassProperties)); at `8 eps` the moments of
/// a group are replaced by their mean and the canonical axes chosen, which keeps the residual
/// `||A V - V diag(I)||` within `10 eps ||A||`.
pub const DEFAULT_RTOL: f64 = 8.0 * f64::EPSILON;

/// Most Jacobi sweeps; a 3x3 converges quadratically in 4 to 6.
const MAX_SWEEPS: usize = 64;

/// Principal moments and axes.
///
/// ```
/// use nalgebra::Matrix3;
/// // A 1 kg m^2 tensor with a product of inertia in the xy plane.
/// let inertia = Matrix3::new(2.0, -0.5, 0.0, -0.5, 2.0, 0.0, 0.0, 0.0, 3.0);
/// let p = polhode::symmetric_eigen3(&inertia).unwrap();
/// assert!((p.moments[0] - 1.5).abs() < 1e-15 && (p.moments[1] - 2.5).abs() < 1e-15);
/// assert!((p.axes.determinant() - 1.0).abs() < 1e-15);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Principal {
    /// Principal moments, ascending.
    pub moments: Vector3<f64>,
    /// Principal axes as the columns of a proper rotation (det = +1): column k belongs to
    /// `moments[k]`. Maps principal coordinates to the body's coordinates.
    pub axes: Matrix3<f64>,
    /// For each moment, how many moments (itself included) are equal to it within the tolerance:
    /// `[1, 1, 1]` for an asymmetric body, `[2, 2, 1]` or `[1, 2, 2]` for a symmetric one,
    /// `[3, 3, 3]` for a spherical one.
    pub multiplicity: [u8; 3],
}

/// Eigen-decomposition of a symmetric 3x3 tensor with the default tolerance.
///
/// Only the lower triangle's mirror is checked: the tensor must be symmetric to `64 eps` of its
/// largest entry and finite; it is symmetrised before the solve.
pub fn symmetric_eigen3(tensor: &Matrix3<f64>) -> Result<Principal> {
    symmetric_eigen3_with(tensor, DEFAULT_RTOL, "inertia")
}

/// [`symmetric_eigen3`] with an explicit relative tolerance for equal moments; `name` is the
/// argument named in errors.
pub fn symmetric_eigen3_with(tensor: &Matrix3<f64>, rtol: f64, name: &str) -> Result<Principal> {
    let a = checked_symmetric(tensor, name)?;
    Ok(eigen_symmetric_unchecked(&a, rtol))
}

/// Checks finiteness and symmetry and returns the symmetrised tensor.
pub(crate) fn checked_symmetric(tensor: &Matrix3<f64>, name: &str) -> Result<Matrix3<f64>> {
    let mut largest = 0.0_f64;
    for r in 0..3 {
        for c in 0..3 {
            let v = tensor[(r, c)];
            if !v.is_finite() {
                return Err(Error::NonFinite {
                    name: format!("{name}[{r}, {c}]"),
                    value: v,
                });
            }
            largest = largest.max(v.abs());
        }
    }
    for (r, c) in [(0, 1), (0, 2), (1, 2)] {
        let (upper, lower) = (tensor[(r, c)], tensor[(c, r)]);
        if (upper - lower).abs() > 64.0 * f64::EPSILON * largest {
            return Err(Error::InvalidInertia {
                name: name.to_owned(),
                reason: format!(
                    "it must be symmetric, but [{r}, {c}] = {upper:e} and [{c}, {r}] = {lower:e}."
                ),
            });
        }
    }
    Ok((tensor + tensor.transpose()) * 0.5)
}

/// Eigen-decomposition of a symmetric, finite tensor (not checked).
pub(crate) fn eigen_symmetric_unchecked(a: &Matrix3<f64>, rtol: f64) -> Principal {
    let shift = (a[(0, 0)] + a[(1, 1)] + a[(2, 2)]) / 3.0;
    let mut s = [[0.0; 3]; 3];
    for (r, row) in s.iter_mut().enumerate() {
        for (c, v) in row.iter_mut().enumerate() {
            *v = a[(r, c)];
        }
        row[r] -= shift;
    }
    let (values, vectors) = jacobi(s);
    let scale = a.norm();
    canonical(
        [values[0] + shift, values[1] + shift, values[2] + shift],
        vectors,
        rtol * scale,
    )
}

/// Cyclic Jacobi on a symmetric matrix: eigenvalues (unsorted) and eigenvectors as columns.
///
/// Rotations as in Golub & Van Loan, Matrix Computations, 8.5.2 (symmetric Schur
/// decomposition), with `t` the smaller root so the rotation angle is at most pi/4.
fn jacobi(mut a: [[f64; 3]; 3]) -> ([f64; 3], Matrix3<f64>) {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]; // v[row][col]
    let norm2: f64 = a.iter().flatten().map(|x| x * x).sum();
    // Off-diagonal mass below (eps^2 ||A||)^2 changes no eigenvalue or vector in double precision.
    let negligible = norm2 * (f64::EPSILON * f64::EPSILON) * (f64::EPSILON * f64::EPSILON);
    for _ in 0..MAX_SWEEPS {
        let off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        if off <= negligible {
            break;
        }
        for (p, q, r) in [(0, 1, 2), (0, 2, 1), (1, 2, 0)] {
            let apq = a[p][q];
            if apq == 0.0 {
                continue;
            }
            let tau = (a[q][q] - a[p][p]) / (2.0 * apq);
            let t = if tau.abs() > 1e150 {
                0.5 / tau
            } else {
                tau.signum() / (tau.abs() + (1.0 + tau * tau).sqrt())
            };
            let c = 1.0 / (1.0 + t * t).sqrt();
            let s = t * c;
            a[p][p] -= t * apq;
            a[q][q] += t * apq;
            a[p][q] = 0.0;
            a[q][p] = 0.0;
            let (arp, arq) = (a[r][p], a[r][q]);
            a[r][p] = c * arp - s * arq;
            a[p][r] = a[r][p];
            a[r][q] = s * arp + c * arq;
            a[q][r] = a[r][q];
            for row in &mut v {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    let vectors = Matrix3::new(
        v[0][0], v[0][1], v[0][2], v[1][0], v[1][1], v[1][2], v[2][0], v[2][1], v[2][2],
    );
    ([a[0][0], a[1][1], a[2][2]], vectors)
}

/// One-sided (Hestenes) Jacobi SVD of a 3x3 factor `f`: the singular values and the right
/// singular vectors (columns of `V`, `f^T f = V diag(s^2) V^T`).
///
/// Columns of `f V` are orthogonalised pairwise until every pair is orthogonal to `eps` of its
/// norms (Demmel & Veselic 1992), which gives small singular values to high relative accuracy
/// when the columns are well scaled: the needle's smallest moment survives.
pub(crate) fn right_singular(f: &Matrix3<f64>) -> ([f64; 3], Matrix3<f64>) {
    let mut g = [
        [f[(0, 0)], f[(1, 0)], f[(2, 0)]],
        [f[(0, 1)], f[(1, 1)], f[(2, 1)]],
        [f[(0, 2)], f[(1, 2)], f[(2, 2)]],
    ]; // g[col][row]
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]; // v[col][row]
    let dot = |x: &[f64; 3], y: &[f64; 3]| x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
    for _ in 0..MAX_SWEEPS {
        let mut rotated = false;
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            let alpha = dot(&g[p], &g[p]);
            let beta = dot(&g[q], &g[q]);
            let gamma = dot(&g[p], &g[q]);
            if gamma == 0.0 || gamma.abs() <= f64::EPSILON * (alpha.sqrt() * beta.sqrt()) {
                continue;
            }
            rotated = true;
            let zeta = (beta - alpha) / (2.0 * gamma);
            let t = if zeta.abs() > 1e150 {
                0.5 / zeta
            } else {
                zeta.signum() / (zeta.abs() + (1.0 + zeta * zeta).sqrt())
            };
            let c = 1.0 / (1.0 + t * t).sqrt();
            let s = t * c;
            for k in 0..3 {
                let (gp, gq) = (g[p][k], g[q][k]);
                g[p][k] = c * gp - s * gq;
                g[q][k] = s * gp + c * gq;
                let (vp, vq) = (v[p][k], v[q][k]);
                v[p][k] = c * vp - s * vq;
                v[q][k] = s * vp + c * vq;
            }
        }
        if !rotated {
            break;
        }
    }
    let norm = |x: &[f64; 3]| x[0].hypot(x[1]).hypot(x[2]);
    let values = [norm(&g[0]), norm(&g[1]), norm(&g[2])];
    let vectors = Matrix3::new(
        v[0][0], v[1][0], v[2][0], v[0][1], v[1][1], v[2][1], v[0][2], v[1][2], v[2][2],
    );
    (values, vectors)
}

/// Sorts, groups equal moments (gap `<= tolerance`, an absolute number already scaled by the
/// caller), and fixes the frame: deterministic signs, det = +1, and inside a degenerate subspace
/// the axes closest to the body's own.
pub(crate) fn canonical(values: [f64; 3], vectors: Matrix3<f64>, tolerance: f64) -> Principal {
    let mut order = [0usize, 1, 2];
    order.sort_by(|&i, &j| values[i].total_cmp(&values[j]));
    let mut moments = Vector3::new(values[order[0]], values[order[1]], values[order[2]]);
    let column = |k: usize| -> Vector3<f64> { vectors.column(order[k]).into_owned() };

    let low_equal = moments[1] - moments[0] <= tolerance;
    let high_equal = moments[2] - moments[1] <= tolerance;
    let (axes, multiplicity) = if low_equal && high_equal {
        moments.fill(moments.sum() / 3.0);
        (Matrix3::identity(), [3, 3, 3])
    } else if low_equal || high_equal {
        // A symmetric body: one unique axis `u` and a plane of equal moments.
        let (unique, first, second) = if low_equal { (2, 0, 1) } else { (0, 1, 2) };
        let mean = 0.5 * (moments[first] + moments[second]);
        moments[first] = mean;
        moments[second] = mean;
        let u = signed(column(unique));
        // In the plane: the projection of the body axis most perpendicular to `u` (the first
        // such axis on a tie), then the axis that completes a right-handed frame.
        let mut j = 0;
        for k in 1..3 {
            if u[k].abs() < u[j].abs() {
                j = k;
            }
        }
        let mut p1 = -u * u[j];
        p1[j] += 1.0;
        let p1 = p1.normalize();
        let p2 = u.cross(&p1);
        let mut axes = Matrix3::zeros();
        axes.set_column(unique, &u);
        axes.set_column(first, &p1);
        axes.set_column(second, &p2);
        let mut multiplicity = [2, 2, 2];
        multiplicity[unique] = 1;
        (axes, multiplicity)
    } else {
        let a0 = signed(column(0));
        let a1 = signed(column(1));
        let a2 = a0.cross(&a1);
        (Matrix3::from_columns(&[a0, a1, a2]), [1, 1, 1])
    };
    Principal {
        moments,
        axes,
        multiplicity,
    }
}

/// The vector with the sign that makes its largest-magnitude component (the first on a tie)
/// positive.
fn signed(v: Vector3<f64>) -> Vector3<f64> {
    let mut j = 0;
    for k in 1..3 {
        if v[k].abs() > v[j].abs() {
            j = k;
        }
    }
    if v[j] < 0.0 {
        -v
    } else {
        v
    }
}

/// Principal moments and axes of a batch of tensors, in parallel on all cores.
///
/// `tensors` holds row-major 3x3 tensors (`tensors[9 i + 3 r + c]`, numpy's (N, 3, 3) layout);
/// `moments` receives `3 N` values, `axes` `9 N` (row-major, columns are the axes) and
/// `multiplicity` `3 N`. Errors name the first bad tensor as `inertia[i]`.
pub fn principal_batch(
    tensors: &[f64],
    rtol: f64,
    moments: &mut [f64],
    axes: &mut [f64],
    multiplicity: &mut [u8],
) -> Result<()> {
    let n = tensors.len() / 9;
    if tensors.len() != 9 * n
        || moments.len() != 3 * n
        || axes.len() != 9 * n
        || multiplicity.len() != 3 * n
    {
        return Err(Error::Shape {
            name: "inertia".into(),
            expected: "(N, 3, 3)".into(),
            got: format!("{} values", tensors.len()),
        });
    }
    const CHUNK: usize = 4096;
    tensors
        .par_chunks(9 * CHUNK)
        .zip(moments.par_chunks_mut(3 * CHUNK))
        .zip(axes.par_chunks_mut(9 * CHUNK))
        .zip(multiplicity.par_chunks_mut(3 * CHUNK))
        .enumerate()
        .try_for_each(|(chunk, (((t, m), x), u))| {
            for (i, (((ti, mi), xi), ui)) in t
                .chunks_exact(9)
                .zip(m.chunks_exact_mut(3))
                .zip(x.chunks_exact_mut(9))
                .zip(u.chunks_exact_mut(3))
                .enumerate()
            {
                let tensor = Matrix3::from_row_slice(ti);
                let name = || format!("inertia[{}]", chunk * CHUNK + i);
                let a = match checked_symmetric(&tensor, "inertia") {
                    Ok(a) => a,
                    Err(e) => return Err(rename(e, &name())),
                };
                let p = eigen_symmetric_unchecked(&a, rtol);
                mi.copy_from_slice(p.moments.as_slice());
                ui.copy_from_slice(&p.multiplicity);
                for r in 0..3 {
                    for c in 0..3 {
                        xi[3 * r + c] = p.axes[(r, c)];
                    }
                }
            }
            Ok(())
        })
}

/// Replaces the argument name in an error by `name` (keeping any `[r, c]` index suffix).
fn rename(error: Error, name: &str) -> Error {
    let fix = |old: String| old.replacen("inertia", name, 1);
    match error {
        Error::NonFinite { name, value } => Error::NonFinite {
            name: fix(name),
            value,
        },
        Error::InvalidInertia { name, reason } => Error::InvalidInertia {
            name: fix(name),
            reason,
        },
        other => other,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Rotation3;

    fn residual(a: &Matrix3<f64>, p: &Principal) -> f64 {
        (a * p.axes - p.axes * Matrix3::from_diagonal(&p.moments)).norm() / a.norm()
    }

    #[test]
    fn nearly_diagonal_tensors_keep_a_small_residual() {
        // nalgebra issue #1109: a deflated 2x2 block mis-rotated eigenvectors of such tensors.
        for off in [1e-10, 1e-14, 1e-17, 1e-300] {
            let a = Matrix3::new(1.0, off, 0.0, off, 2.0, off, 0.0, off, 3.0);
            let p = symmetric_eigen3(&a).unwrap();
            assert!(residual(&a, &p) <= 10.0 * f64::EPSILON, "off = {off}");
        }
    }

    #[test]
    fn degenerate_rotated_tensor_gives_canonical_frame() {
        let r = Rotation3::from_euler_angles(0.3, -1.1, 2.0);
        let a = r.matrix() * Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, 2.0)) * r.transpose();
        let p = symmetric_eigen3(&a).unwrap();
        assert_eq!(p.multiplicity, [2, 2, 1]);
        assert_eq!(p.moments[0], p.moments[1]);
        let unique = r.matrix().column(2).into_owned();
        assert!(p.axes.column(2).dot(&unique).abs() > 1.0 - 1e-14);
        assert!((p.axes.determinant() - 1.0).abs() < 1e-14);
        assert!(residual(&a, &p) <= 10.0 * f64::EPSILON);
    }

    #[test]
    fn hestenes_svd_resolves_tiny_singular_values() {
        let f = Matrix3::new(3.0, 0.0, 0.0, 0.0, 1e-9, 0.0, 0.0, 0.0, 1e-12);
        let r = Rotation3::from_euler_angles(0.4, 0.2, -0.7);
        let (s, v) = right_singular(&(f * r.transpose()));
        let mut s = s;
        s.sort_by(f64::total_cmp);
        assert!((s[0] - 1e-12).abs() <= 1e-12 * 1e-3);
        assert!((s[1] - 1e-9).abs() <= 1e-9 * 1e-6);
        assert!((v.transpose() * v - Matrix3::identity()).norm() < 1e-15);
    }
}

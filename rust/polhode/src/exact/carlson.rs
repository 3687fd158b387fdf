//! Carlson's symmetric elliptic integrals by the duplication algorithm.
//!
//! B. C. Carlson, "Numerical computation of real or complex elliptic integrals", Numerical
//! Algorithms 10 (1995) 13-26, with the seventh-order series of DLMF 19.36.1-19.36.2 at the
//! end of the duplication. The iteration stops when the normalised deviations are below
//! `DEV` (0.004), where the truncated series is exact to far below one ulp.

/// Stop when every normalised deviation is below this (the first neglected terms are of order
/// `DEV^8 ~ 1e-19` in `R_F` and `DEV^6 ~ 4e-15` times a coefficient below 1e-2 in `R_D`,
/// `R_J`).
const DEV: f64 = 0.004;

/// The series of `R_D` and `R_J` is one order shorter; they iterate to this deviation.
const DEV_3: f64 = 0.0015;

/// The degenerate integral `R_C(x, y) = R_F(x, y, y) = 1/2 int_0^inf (t + x)^(-1/2) (t + y)^(-1) dt`
/// (DLMF 19.2.17), `x >= 0`, `y != 0`; for `y < 0` the Cauchy principal value (DLMF 19.2.20).
///
/// Closed forms (DLMF 19.2.18-19.2.19): `atan(sqrt((y - x)/x)) / sqrt(y - x)` for `x < y`,
/// `atanh(sqrt((x - y)/x)) / sqrt(x - y)` for `y < x`. Returns NaN outside the domain.
pub fn carlson_rc(x: f64, y: f64) -> f64 {
    if x.is_nan() || x < 0.0 || y == 0.0 || y.is_nan() {
        return f64::NAN;
    }
    if y < 0.0 {
        // DLMF 19.2.20: R_C(x, y) = sqrt(x / (x - y)) R_C(x - y, -y).
        let xm = x - y;
        return (x / xm).sqrt() * carlson_rc(xm, -y);
    }
    if x == y {
        return 1.0 / x.sqrt();
    }
    if x == 0.0 {
        return std::f64::consts::FRAC_PI_2 / y.sqrt();
    }
    if x < y {
        let d = y - x;
        (d / x).sqrt().atan() / d.sqrt()
    } else if y > 0.5 * x {
        let d = x - y;
        (d / x).sqrt().atanh() / d.sqrt()
    } else {
        // DLMF 19.2.19: ln((sqrt x + sqrt(x - y)) / sqrt y) / sqrt(x - y).
        let d = (x - y).sqrt();
        ((x.sqrt() + d) / y.sqrt()).ln() / d
    }
}

/// An even power of two near `v > 0` (scaling by it, and by its square root, is exact).
#[inline]
fn pow2_near(v: f64) -> f64 {
    if v.is_finite() && v > 0.0 {
        let e = v.log2().floor().clamp(-1000.0, 1000.0) as i32;
        2f64.powi(e - e.rem_euclid(2))
    } else {
        1.0
    }
}

/// `R_C(1, 1 + e)` for `e > -1`, given also `onepe = 1 + e` computed without cancellation:
/// `atan(sqrt e) / sqrt e` for `e > 0`, `atanh(x) / x` with `x = sqrt(-e)` for `e < 0`, where
/// near `e = -1` `atanh x = ln(1 + x) - ln(1 + e) / 2` (since `1 - x^2 = 1 + e`).
#[inline]
fn rc1(e: f64, onepe: f64) -> f64 {
    if e > 0.0 {
        let s = e.sqrt();
        s.atan() / s
    } else if e < 0.0 {
        let x = (-e).sqrt();
        if x < 0.5 {
            x.atanh() / x
        } else {
            (x.ln_1p() - 0.5 * onepe.ln()) / x
        }
    } else {
        1.0
    }
}

/// Carlson's integral of the first kind
/// `R_F(x, y, z) = 1/2 int_0^inf ((t + x)(t + y)(t + z))^(-1/2) dt` (DLMF 19.16.1),
/// `x, y, z >= 0` with at most one of them zero; NaN otherwise.
pub fn carlson_rf(x: f64, y: f64, z: f64) -> f64 {
    if !(x >= 0.0 && y >= 0.0 && z >= 0.0) || [x, y, z].iter().filter(|v| **v == 0.0).count() > 1 {
        return f64::NAN;
    }
    if x.is_infinite() || y.is_infinite() || z.is_infinite() {
        return 0.0;
    }
    // Scale to avoid overflow in the products of square roots.
    let scale = pow2_near(x.max(y).max(z));
    let (mut x, mut y, mut z) = (x / scale, y / scale, z / scale);
    let a0 = (x + y + z) / 3.0;
    let (dx, dy, dz) = (a0 - x, a0 - y, a0 - z);
    let q = dx.abs().max(dy.abs()).max(dz.abs()) / DEV;
    let mut a = a0;
    let mut f = 1.0;
    for _ in 0..100 {
        if f * q < a.abs() {
            break;
        }
        let (sx, sy, sz) = (x.sqrt(), y.sqrt(), z.sqrt());
        let lambda = sx * sy + sx * sz + sy * sz;
        a = 0.25 * (a + lambda);
        x = 0.25 * (x + lambda);
        y = 0.25 * (y + lambda);
        z = 0.25 * (z + lambda);
        f *= 0.25;
    }
    let xx = dx * f / a;
    let yy = dy * f / a;
    let zz = -(xx + yy);
    let e2 = xx * yy - zz * zz;
    let e3 = xx * yy * zz;
    // DLMF 19.36.1.
    let s = 1.0 - e2 / 10.0 + e3 / 14.0 + e2 * e2 / 24.0
        - 3.0 * e2 * e3 / 44.0
        - 5.0 * e2 * e2 * e2 / 208.0
        + 3.0 * e3 * e3 / 104.0
        + e2 * e2 * e3 / 16.0;
    s / (a.sqrt() * scale.sqrt())
}

/// Carlson's integral of the second kind
/// `R_D(x, y, z) = 3/2 int_0^inf ((t + x)(t + y))^(-1/2) (t + z)^(-3/2) dt` (DLMF 19.16.5),
/// `x, y >= 0` not both zero, `z > 0`; NaN otherwise.
pub fn carlson_rd(x: f64, y: f64, z: f64) -> f64 {
    if !(x >= 0.0 && y >= 0.0 && z > 0.0) || (x == 0.0 && y == 0.0) {
        return f64::NAN;
    }
    let scale = pow2_near(x.max(y).max(z));
    let (mut x, mut y, mut z) = (x / scale, y / scale, z / scale);
    let a0 = (x + y + 3.0 * z) / 5.0;
    let (dx, dy, dz) = (a0 - x, a0 - y, a0 - z);
    let q = dx.abs().max(dy.abs()).max(dz.abs()) / DEV_3;
    let mut a = a0;
    let mut f = 1.0;
    let mut sum = 0.0;
    for _ in 0..100 {
        if f * q < a.abs() {
            break;
        }
        let (sx, sy, sz) = (x.sqrt(), y.sqrt(), z.sqrt());
        let lambda = sx * sy + sx * sz + sy * sz;
        sum += f / (sz * (z + lambda));
        a = 0.25 * (a + lambda);
        x = 0.25 * (x + lambda);
        y = 0.25 * (y + lambda);
        z = 0.25 * (z + lambda);
        f *= 0.25;
    }
    let xx = dx * f / a;
    let yy = dy * f / a;
    let zz = -(xx + yy) / 3.0;
    let xy = xx * yy;
    let z2 = zz * zz;
    let e2 = xy - 6.0 * z2;
    let e3 = (3.0 * xy - 8.0 * z2) * zz;
    let e4 = 3.0 * (xy - z2) * z2;
    let e5 = xy * z2 * zz;
    // DLMF 19.36.2 (Carlson 1995, eq. 2.29).
    let s = 1.0 - 3.0 * e2 / 14.0 + e3 / 6.0 + 9.0 * e2 * e2 / 88.0
        - 3.0 * e4 / 22.0
        - 9.0 * e2 * e3 / 52.0
        + 3.0 * e5 / 26.0;
    (f * s / (a * a.sqrt()) + 3.0 * sum) / scale / scale.sqrt()
}

/// Carlson's integral of the third kind
/// `R_J(x, y, z, p) = 3/2 int_0^inf ((t + x)(t + y)(t + z))^(-1/2) (t + p)^(-1) dt`
/// (DLMF 19.16.2), `x, y, z >= 0` with at most one zero, `p > 0`; NaN otherwise.
///
/// Carlson's 1995 algorithm: the sum of `4^-m R_C(1, 1 + e_m) / d_m` with
/// `d_m = (sqrt p + sqrt x)(sqrt p + sqrt y)(sqrt p + sqrt z)`, `e_m = 4^(-3m) delta / d_m^2`,
/// `delta = (p - x)(p - y)(p - z)`, avoids the cancellation of the older `R_C(alpha^2, beta^2)`.
pub fn carlson_rj(x: f64, y: f64, z: f64, p: f64) -> f64 {
    if !(x >= 0.0 && y >= 0.0 && z >= 0.0 && p > 0.0)
        || [x, y, z].iter().filter(|v| **v == 0.0).count() > 1
    {
        return f64::NAN;
    }
    let scale = pow2_near(x.max(y).max(z).max(p));
    let (mut x, mut y, mut z, mut p) = (x / scale, y / scale, z / scale, p / scale);
    let a0 = (x + y + z + 2.0 * p) / 5.0;
    let delta = (p - x) * (p - y) * (p - z);
    let (dx, dy, dz, dp) = (a0 - x, a0 - y, a0 - z, a0 - p);
    let q = dx.abs().max(dy.abs()).max(dz.abs()).max(dp.abs()) / DEV_3;
    let mut a = a0;
    let mut f = 1.0;
    let mut f3 = 1.0;
    let mut sum = 0.0;
    for _ in 0..100 {
        if f * q < a.abs() {
            break;
        }
        let (sx, sy, sz, sp) = (x.sqrt(), y.sqrt(), z.sqrt(), p.sqrt());
        let lambda = sx * sy + sx * sz + sy * sz;
        let d = (sp + sx) * (sp + sy) * (sp + sz);
        let e = f3 * delta / (d * d);
        // 1 + e = 2 sqrt(p) (p + lambda) / d, since delta_m = d (sp - sx)(sp - sy)(sp - sz).
        let onepe = 2.0 * sp * (p + lambda) / d;
        sum += f * rc1(e, onepe) / d;
        a = 0.25 * (a + lambda);
        x = 0.25 * (x + lambda);
        y = 0.25 * (y + lambda);
        z = 0.25 * (z + lambda);
        p = 0.25 * (p + lambda);
        f *= 0.25;
        f3 *= 1.0 / 64.0;
    }
    let _ = dp;
    let xx = dx * f / a;
    let yy = dy * f / a;
    let zz = dz * f / a;
    let pp = -(xx + yy + zz) / 2.0;
    let p2 = pp * pp;
    let xyz = xx * yy * zz;
    let e2 = xx * yy + xx * zz + yy * zz - 3.0 * p2;
    let e3 = xyz + 2.0 * e2 * pp + 4.0 * p2 * pp;
    let e4 = (2.0 * xyz + e2 * pp + 3.0 * p2 * pp) * pp;
    let e5 = xyz * p2;
    // Carlson 1995, eq. 2.39 (DLMF 19.36.2).
    let s = 1.0 - 3.0 * e2 / 14.0 + e3 / 6.0 + 9.0 * e2 * e2 / 88.0
        - 3.0 * e4 / 22.0
        - 9.0 * e2 * e3 / 52.0
        + 3.0 * e5 / 26.0;
    (f * s / (a * a.sqrt()) + 6.0 * sum) / scale / scale.sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, ulps: f64) -> bool {
        (a - b).abs() <= ulps * f64::EPSILON * b.abs()
    }

    #[test]
    fn degenerate_cases_are_elementary() {
        for x in [1e-300, 1e-8, 0.3, 1.0, 7.0, 1e20, 1e300] {
            assert!(
                close(carlson_rf(x, x, x), 1.0 / x.sqrt(), 2.0),
                "R_F({x},{x},{x})"
            );
            if (1e-200..1e200).contains(&x) {
                assert!(
                    close(carlson_rd(x, x, x), 1.0 / (x * x.sqrt()), 4.0),
                    "R_D({x},{x},{x})"
                );
                assert!(close(carlson_rj(x, x, x, x), 1.0 / (x * x.sqrt()), 4.0));
            }
            assert!(close(carlson_rc(x, x), 1.0 / x.sqrt(), 2.0));
        }
        // R_C(0, 1/4) = pi; R_F(0, 1, 1) = pi/2 (DLMF 19.20.1).
        assert!(close(carlson_rc(0.0, 0.25), std::f64::consts::PI, 2.0));
        assert!(close(
            carlson_rf(0.0, 1.0, 1.0),
            std::f64::consts::FRAC_PI_2,
            2.0
        ));
    }

    #[test]
    fn reductions_between_the_integrals() {
        // R_C(x, y) = R_F(x, y, y); R_J(x, y, z, z) = R_D(x, y, z) (DLMF 19.2.17, 19.20.18).
        for (x, y, z) in [
            (0.1, 2.0, 3.0),
            (1e-9, 1.0, 0.5),
            (4.0, 4.5, 1e-3),
            (0.0, 2.0, 7.0),
        ] {
            assert!(close(carlson_rc(x, y), carlson_rf(x, y, y), 6.0));
            assert!(close(carlson_rj(x, y, z, z), carlson_rd(x, y, z), 12.0));
        }
    }

    #[test]
    fn homogeneity() {
        // R_F is homogeneous of degree -1/2, R_D and R_J of degree -3/2.
        let (x, y, z, p) = (0.3, 1.7, 2.2, 0.9);
        for s in [4.0f64, 1e-100, 1e100] {
            assert!(close(
                carlson_rf(s * x, s * y, s * z),
                carlson_rf(x, y, z) / s.sqrt(),
                4.0
            ));
            let d = carlson_rd(s * x, s * y, s * z) * s * s.sqrt();
            assert!(close(d, carlson_rd(x, y, z), 8.0));
            let j = carlson_rj(s * x, s * y, s * z, s * p) * s * s.sqrt();
            assert!(close(j, carlson_rj(x, y, z, p), 8.0));
        }
    }

    #[test]
    fn out_of_domain_is_nan() {
        assert!(carlson_rf(-1.0, 1.0, 1.0).is_nan());
        assert!(carlson_rf(0.0, 0.0, 1.0).is_nan());
        assert!(carlson_rd(1.0, 1.0, 0.0).is_nan());
        assert!(carlson_rj(1.0, 1.0, 1.0, -1.0).is_nan());
        assert!(carlson_rc(1.0, 0.0).is_nan());
    }
}

//! Jacobi elliptic functions and Legendre's elliptic integrals, parametrised by the
//! complementary parameter `mc = 1 - m = k'^2`.
//!
//! Near the separatrix of a rigid body `m` is within rounding of 1 and `1 - m` cannot be
//! formed; everything here takes `mc` directly and never computes `1 - k^2`.

use super::carlson::{carlson_rf, carlson_rj};
use super::dd::{agm1, cel, Dd};

/// Below this modulus the descending Landen chain stops: the first-order expansion in
/// `m = k^2` (A&S 16.13) is then exact to `O(m^2) < 1e-18`.
const K_STOP: f64 = 3e-5;

/// The most descending Landen steps (`mc = 1e-308` needs 11).
const LEVELS: usize = 20;

/// `K(mc)` in double-double: `K = pi / (2 AGM(1, sqrt(mc)))` (DLMF 19.8.5), for `0 < mc <= 1`.
pub(crate) fn ellipk_dd(mc: Dd) -> Dd {
    Dd::PI / (agm1(mc.sqrt()) * 2.0)
}

/// The complete elliptic integral of the first kind
/// `K(m) = int_0^{pi/2} (1 - m sin^2 t)^(-1/2) dt` as a function of `mc = 1 - m`, by the
/// arithmetic-geometric mean `K = pi / (2 AGM(1, sqrt(mc)))` (DLMF 19.8.5), evaluated in
/// double-double and rounded once.
///
/// `mc` in `(0, 1]` (any `mc > 0` works); `+inf` at `mc = 0`; NaN for `mc < 0` or NaN.
pub fn ellipk(mc: f64) -> f64 {
    if mc == 0.0 {
        f64::INFINITY
    } else if mc > 0.0 && mc.is_finite() {
        ellipk_dd(Dd::new(mc)).to_f64()
    } else {
        f64::NAN
    }
}

/// The descending Landen (Gauss) chain of a parameter, formed once: the moduli `k_n`, the
/// complements `1 - k_n` and the final `m = k_N^2` at which the first-order expansion is exact.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Landen {
    n: usize,
    ks: [f64; LEVELS],
    omks: [f64; LEVELS],
    m: f64,
}

impl Landen {
    /// The chain for `0 < mc <= 1`: `k_{n+1} = k_n^2 / (1 + k'_n)^2`,
    /// `1 - k_{n+1} = 2 k'_n / (1 + k'_n)`, `k'_{n+1} = 2 sqrt(k'_n) / (1 + k'_n)` (cancellation
    /// free), until `k < 3e-5`.
    pub(crate) fn new(mc: f64) -> Landen {
        let mut ks = [0.0; LEVELS];
        let mut omks = [0.0; LEVELS];
        let mut kp = mc.sqrt();
        let mut k = (1.0 - mc).sqrt();
        let mut n = 0;
        while k > K_STOP && n < LEVELS {
            let opk = 1.0 + kp;
            let r = k / opk;
            let k1 = r * r;
            ks[n] = k1;
            omks[n] = 2.0 * kp / opk;
            kp = 2.0 * kp.sqrt() / opk;
            k = k1;
            n += 1;
        }
        Landen {
            n,
            ks,
            omks,
            m: k * k,
        }
    }

    /// `sn, cn, dn (v | m)` for `|v| <= K/2`, by the descending Landen (Gauss)
    /// transformation (DLMF 22.7.1-22.7.3) in the cancellation-free form
    /// `k_{n+1} = k_n^2 / (1 + k'_n)^2`, `1 - k_{n+1} = 2 k'_n / (1 + k'_n)`,
    /// `k'_{n+1} = 2 sqrt(k'_n) / (1 + k'_n)`, ending with the first-order expansion in `m`
    /// (A&S 16.13.1-16.13.3). On `|v| <= K/2` every quantity is positive and every step is a
    /// product, a quotient or a sum of positive numbers, so relative accuracy carries through.
    #[inline]
    pub(crate) fn core(&self, v: f64) -> (f64, f64, f64) {
        let mut zz = v.abs();
        for k in &self.ks[..self.n] {
            zz /= 1.0 + k;
        }
        let m = self.m;
        let (s0, c0) = zz.sin_cos();
        let corr = 0.25 * m * (zz - s0 * c0);
        let mut s = s0 - corr * c0;
        let mut c = c0 + corr * s0;
        let mut d = 1.0 - 0.5 * m * s0 * s0;
        for i in (0..self.n).rev() {
            let k = self.ks[i];
            let s2 = s * s;
            let ks2 = k * s2;
            let den = 1.0 + ks2;
            let num_d = if ks2 <= 0.5 {
                1.0 - ks2
            } else {
                c * c + self.omks[i] * s2
            };
            let s1 = (1.0 + k) * s / den;
            let c1 = c * d / den;
            d = num_d / den;
            s = s1;
            c = c1;
        }
        (s.copysign(v), c, d)
    }

    /// `sn, cn, dn (q K + v | m)` (see [`sncndn_quarter`]): the chain formed once per
    /// parameter, so that each argument costs one `sin_cos` and `N` steps.
    #[inline]
    pub(crate) fn quarter(&self, q: i64, v: f64, kp: f64) -> (f64, f64, f64) {
        let (s, c, d) = self.core(v);
        match q.rem_euclid(4) {
            0 => (s, c, d),
            1 => (c / d, -kp * s / d, kp / d),
            2 => (-s, -c, d),
            _ => (-c / d, kp * s / d, kp / d),
        }
    }
}

/// `sn, cn, dn (q K + v | m)` from the functions of `v` (`|v| <= K/2`) and the quarter-period
/// index `q` (taken mod 4), with the shifts by `K` of DLMF 22.4.3:
/// `sn(v + K) = cn v / dn v`, `cn(v + K) = -k' sn v / dn v`, `dn(v + K) = k' / dn v`.
pub(crate) fn sncndn_quarter(q: i64, v: f64, mc: f64, kp: f64) -> (f64, f64, f64) {
    Landen::new(mc).quarter(q, v, kp)
}

/// Splits `u = q K + v` with `|v| <= K/2` (up to rounding), the reduction done in
/// double-double so that it is exact for `|u|` up to about `2^50 K`.
pub(crate) fn reduce_quarter(u: Dd, k: Dd) -> (i64, f64) {
    let (q, v) = reduce_quarter_dd(u, k);
    (q, v.to_f64())
}

/// [`reduce_quarter`] with the remainder `v` kept in double-double.
pub(crate) fn reduce_quarter_dd(u: Dd, k: Dd) -> (i64, Dd) {
    let q = (u / k).round();
    let v = u - k * q.hi - k * q.lo;
    (q.to_f64() as i64, v)
}

/// The Jacobi elliptic functions `(sn, cn, dn)(u | m)` as functions of the complementary
/// parameter `mc = 1 - m`, `0 <= mc <= 1`.
///
/// The argument is reduced modulo the quarter period `K` in double-double (so a large `u`
/// loses nothing beyond its own rounding), shifted by `K` where needed (DLMF 22.4.3) and
/// evaluated on `|v| <= K/2` by the descending Landen transformation with `k'` carried
/// cancellation-free (DLMF 22.7.1-22.7.3); at `mc = 0` the limits `(tanh u, sech u, sech u)`
/// (DLMF 22.5.4). Returns NaNs for `mc` outside `[0, 1]` or a non-finite `u`.
pub fn sncndn(u: f64, mc: f64) -> (f64, f64, f64) {
    if !(0.0..=1.0).contains(&mc) || !u.is_finite() {
        return (f64::NAN, f64::NAN, f64::NAN);
    }
    if mc == 0.0 {
        let sech = 1.0 / u.cosh();
        return (u.tanh(), sech, sech);
    }
    let k = ellipk_dd(Dd::new(mc));
    let (q, v) = reduce_quarter(Dd::new(u), k);
    sncndn_quarter(q, v, mc, mc.sqrt())
}

/// The Jacobi amplitude `am(u | m)`, the `phi` with `F(phi | m) = u` (DLMF 22.16.1), as a
/// function of `mc = 1 - m`: `am(2 j K + w) = j pi + atan2(sn w, cn w)` with `|w| <= K`;
/// `gd u = atan(sinh u)` at `mc = 0`. NaN for `mc` outside `[0, 1]`.
pub fn am(u: f64, mc: f64) -> f64 {
    if !(0.0..=1.0).contains(&mc) || !u.is_finite() {
        return f64::NAN;
    }
    if mc == 0.0 {
        return u.sinh().atan();
    }
    let k = ellipk_dd(Dd::new(mc));
    let k2 = k * 2.0;
    let j = (Dd::new(u) / k2).round();
    let w = Dd::new(u) - k2 * j.hi - k2 * j.lo;
    let (q, v) = reduce_quarter(w, k);
    let (s, c, _) = sncndn_quarter(q, v, mc, mc.sqrt());
    (Dd::PI * j.hi + Dd::PI * j.lo + s.atan2(c)).to_f64()
}

/// Splits `phi = j pi + r` with `|r| <= pi/2`; returns `(j, sin r, cos r)`.
fn reduce_angle(phi: f64) -> (f64, f64, f64) {
    let j = (phi / std::f64::consts::PI).round();
    let r = (Dd::new(phi) - Dd::PI * j).to_f64();
    let (s, c) = r.sin_cos();
    (j, s, c.abs())
}

/// Legendre's incomplete integral of the first kind
/// `F(phi | m) = int_0^phi (1 - m sin^2 t)^(-1/2) dt` as a function of `mc = 1 - m`:
/// `F = 2 j K + s R_F(c^2, c^2 + mc s^2, 1)` for `phi = j pi + r`, `|r| <= pi/2`,
/// `s = sin r`, `c = cos r` (DLMF 19.25.5, 19.2.10). `0 <= mc <= 1`; NaN otherwise.
pub fn ellipf(phi: f64, mc: f64) -> f64 {
    if !(0.0..=1.0).contains(&mc) || !phi.is_finite() {
        return f64::NAN;
    }
    let (j, s, c) = reduce_angle(phi);
    let d2 = c * c + mc * s * s;
    let part = if c == 0.0 && mc == 0.0 {
        f64::INFINITY.copysign(s)
    } else {
        s * carlson_rf(c * c, d2, 1.0)
    };
    if j == 0.0 {
        part
    } else {
        2.0 * j * ellipk(mc) + part
    }
}

/// Legendre's incomplete integral of the third kind
/// `Pi(phi; n | m) = int_0^phi (1 - n sin^2 t)^(-1) (1 - m sin^2 t)^(-1/2) dt` (DLMF 19.2.7,
/// mpmath's `ellippi(n, phi, m)`), as a function of `mc = 1 - m`:
/// `Pi = 2 j Pi(n | m) + s R_F(c^2, d^2, 1) + (n/3) s^3 R_J(c^2, d^2, 1, 1 - n s^2)` for
/// `phi = j pi + r`, `|r| <= pi/2`, `d^2 = c^2 + mc s^2` (DLMF 19.25.14).
///
/// Domain: `0 <= mc <= 1` and `n sin^2 phi < 1` (and `n < 1` once `|phi| > pi/2`); NaN
/// otherwise (the Cauchy principal value is not provided). For `n << -1` the two terms cancel
/// and the relative accuracy is about `|n|` ulp.
pub fn ellippi(phi: f64, n: f64, mc: f64) -> f64 {
    if !(0.0..=1.0).contains(&mc) || !phi.is_finite() || !n.is_finite() {
        return f64::NAN;
    }
    let (j, s, c) = reduce_angle(phi);
    let s2 = s * s;
    let p = 1.0 - n * s2;
    if p.is_nan() || p <= 0.0 || (j != 0.0 && n >= 1.0) {
        return f64::NAN;
    }
    let c2 = c * c;
    let d2 = c2 + mc * s2;
    let part = if c == 0.0 && mc == 0.0 {
        f64::INFINITY.copysign(s)
    } else {
        s * carlson_rf(c2, d2, 1.0) + n / 3.0 * s * s2 * carlson_rj(c2, d2, 1.0, p)
    };
    if j == 0.0 {
        part
    } else {
        2.0 * j * ellippi_complete(n, mc) + part
    }
}

/// The complete integral of the third kind `Pi(n | m) = Pi(pi/2; n | m)` as a function of
/// `mc = 1 - m`, by Bulirsch's algorithm `Pi(n | m) = cel(sqrt(mc), 1 - n, 1, 1)` (Bulirsch 1969,
/// Numer. Math. 13, 305) in double-double, rounded once. `0 < mc <= 1`, `n < 1`; `+inf` at
/// `mc = 0`; NaN otherwise.
pub fn ellippi_complete(n: f64, mc: f64) -> f64 {
    if n >= 1.0 || !(0.0..=1.0).contains(&mc) || !n.is_finite() {
        return f64::NAN;
    }
    if mc == 0.0 {
        return f64::INFINITY;
    }
    cel(Dd::new(mc).sqrt(), Dd::sum(1.0, -n), Dd::ONE, Dd::ONE).to_f64()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identities_hold_to_rounding() {
        for mc in [1.0, 0.7, 0.2, 1e-4, 1e-12, 1e-40, 1e-200, 1e-308] {
            for u in [0.01, 0.4, 1.1, 3.0, 9.5, -2.2, 60.0, 700.0] {
                let (s, c, d) = sncndn(u, mc);
                assert!(
                    (s * s + c * c - 1.0).abs() <= 16.0 * f64::EPSILON,
                    "mc {mc} u {u}"
                );
                // dn^2 = cn^2 + mc sn^2, relative (both sides positive).
                let r = c * c + mc * s * s;
                assert!(
                    (d * d - r).abs() <= 32.0 * f64::EPSILON * r,
                    "mc {mc} u {u}"
                );
            }
        }
    }

    #[test]
    fn half_period_shifts() {
        for mc in [0.5, 1e-6, 1e-30] {
            let k = ellipk(mc);
            for u in [0.3, 1.0, 5.0] {
                let (s, c, d) = sncndn(u, mc);
                let (s2, c2, d2) = sncndn(u + 2.0 * k, mc);
                let tol = 64.0 * f64::EPSILON * (u + 2.0 * k);
                assert!((s2 + s).abs() <= tol && (c2 + c).abs() <= tol && (d2 - d).abs() <= tol);
            }
            // sn(K) = 1, cn(K) = 0, dn(K) = k'.
            let (s, c, d) = sncndn(k, mc);
            assert!((s - 1.0).abs() <= 2.0 * f64::EPSILON);
            assert!(c.abs() <= 4.0 * f64::EPSILON * k * mc.sqrt());
            assert!((d - mc.sqrt()).abs() <= 4.0 * f64::EPSILON * mc.sqrt() * k);
        }
    }

    #[test]
    fn complete_integrals() {
        assert_eq!(ellipk(1.0), std::f64::consts::FRAC_PI_2);
        // K ~ ln(4 / k') near the separatrix (DLMF 19.12.1).
        let mc: f64 = 1e-300;
        assert!((ellipk(mc) - (4.0 / mc.sqrt()).ln()).abs() < 1e-290);
        assert_eq!(ellippi_complete(0.0, 0.3), ellipk(0.3));
        let f = ellipf(std::f64::consts::FRAC_PI_2, 0.3);
        assert!((f - ellipk(0.3)).abs() <= 2.0 * f64::EPSILON * f);
        let p = ellippi(std::f64::consts::PI, -2.0, 0.3);
        assert!((p - 2.0 * ellippi_complete(-2.0, 0.3)).abs() <= 8.0 * f64::EPSILON * p);
    }
}

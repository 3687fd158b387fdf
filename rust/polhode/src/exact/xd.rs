//! Numbers with an exponent of their own, for the invariants of motions whose components or
//! moments span more than the range of doubles (an angular velocity of 1e-170 next to one of
//! 1, moments from 1e-150 to 1e150, subnormal components).
//!
//! - [`Xd`]: a double-double mantissa and an `i32` binary exponent. Every operation is the
//!   double-double operation on the mantissas, scaled by an exact power of two, so that on
//!   numbers inside the range of doubles it gives bit for bit what double-double gives;
//! - [`Sd`]: a double and an `i32` exponent, for the amplitudes the evaluation multiplies. Its
//!   exponent stays 0 while the value is a comfortable double, so that ordinary inputs take
//!   the plain double operations;
//! - [`exp_dd`], [`ln_dd`]: the exponential and the logarithm in double-double.

use super::dd::Dd;

/// `2^k` as a double, for `-1022 <= k <= 1023`.
#[inline]
fn pow2(k: i32) -> f64 {
    debug_assert!((-1022..=1023).contains(&k));
    f64::from_bits(((k + 1023) as u64) << 52)
}

/// `x = m 2^e` with `1 <= |m| < 2` (`(x, 0)` for zero and non-finite `x`); exact, subnormal `x`
/// included.
pub(crate) fn frexp(x: f64) -> (f64, i32) {
    if x == 0.0 || !x.is_finite() {
        return (x, 0);
    }
    let bits = x.to_bits();
    let be = ((bits >> 52) & 0x7ff) as i32;
    if be == 0 {
        // Subnormal: scale up by 2^64 first (exact).
        let (m, e) = frexp(x * pow2(64));
        return (m, e - 64);
    }
    let m = f64::from_bits((bits & !(0x7ff << 52)) | (1023 << 52));
    (m, be - 1023)
}

/// `x 2^e`, rounded once (only a subnormal result is rounded); `0` or `inf` beyond the range.
pub(crate) fn ldexp(x: f64, e: i32) -> f64 {
    if (-1022..=1023).contains(&e) {
        // A normal product by a power of two is exact: the same bits as below, without
        // splitting `x` (per output, in the scalings of the exact solution).
        let p = x * pow2(e);
        if p.abs() > f64::MIN_POSITIVE && p.abs() <= f64::MAX {
            return p;
        }
    }
    if x == 0.0 || !x.is_finite() || e == 0 {
        return x;
    }
    let (m, k) = frexp(x);
    let t = k.saturating_add(e);
    if t > 1023 {
        return f64::INFINITY.copysign(x);
    }
    if t >= -1022 {
        return m * pow2(t);
    }
    if t < -1080 {
        return 0.0 * x.signum();
    }
    // Subnormal: m 2^(t + 1022) is a normal double (exact), the last product rounds once.
    m * pow2(t + 1022) * pow2(-1022)
}

impl Dd {
    /// `self 2^e` (each part rounded once if it becomes subnormal).
    #[inline]
    pub fn ldexp(self, e: i32) -> Dd {
        if (-900..=900).contains(&e) && (self.hi.abs() < 2.0 && self.hi.abs() >= 0.5) {
            // Both parts stay normal (or zero): one exact product each.
            let p = pow2(e);
            return Dd {
                hi: self.hi * p,
                lo: self.lo * p,
            };
        }
        Dd {
            hi: ldexp(self.hi, e),
            lo: ldexp(self.lo, e),
        }
    }
}

/// A double-double with its own binary exponent: the value `m 2^e`, `1 <= |m.hi| < 2` (or
/// `m = 0`, `e = 0`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Xd {
    pub m: Dd,
    pub e: i32,
}

impl Xd {
    pub const ZERO: Xd = Xd { m: Dd::ZERO, e: 0 };

    /// `m 2^e` normalised.
    #[inline]
    fn norm(m: Dd, e: i32) -> Xd {
        // The usual cases (a product or quotient of mantissas) by exact halving or doubling.
        let a = m.hi.abs();
        if (1.0..2.0).contains(&a) {
            return Xd { m, e };
        }
        if (2.0..4.0).contains(&a) {
            return Xd {
                m: Dd {
                    hi: 0.5 * m.hi,
                    lo: 0.5 * m.lo,
                },
                e: e + 1,
            };
        }
        if (0.5..1.0).contains(&a) {
            return Xd {
                m: Dd {
                    hi: 2.0 * m.hi,
                    lo: 2.0 * m.lo,
                },
                e: e - 1,
            };
        }
        if m.hi == 0.0 {
            return Xd::ZERO;
        }
        let (_, k) = frexp(m.hi);
        Xd {
            m: m.ldexp(-k),
            e: e + k,
        }
    }

    /// The exact value of a double.
    pub fn new(x: f64) -> Xd {
        let (m, e) = frexp(x);
        if m == 0.0 {
            Xd::ZERO
        } else {
            Xd { m: Dd::new(m), e }
        }
    }

    /// The value of a double-double (inside the range of doubles).
    pub fn from_dd(d: Dd) -> Xd {
        Xd::norm(d, 0)
    }

    /// The exact product of two doubles.
    pub fn prod(a: f64, b: f64) -> Xd {
        let (ma, ea) = frexp(a);
        let (mb, eb) = frexp(b);
        Xd::norm(Dd::prod(ma, mb), ea + eb)
    }

    /// The exact sum of two doubles.
    pub fn sum(a: f64, b: f64) -> Xd {
        Xd::new(a) + Xd::new(b)
    }

    pub fn is_zero(self) -> bool {
        self.m.hi == 0.0
    }

    pub fn is_negative(self) -> bool {
        self.m.hi < 0.0
    }

    pub fn abs(self) -> Xd {
        Xd {
            m: self.m.abs(),
            e: self.e,
        }
    }

    /// `self 2^k`.
    pub fn ldexp(self, k: i32) -> Xd {
        if self.is_zero() {
            self
        } else {
            Xd {
                m: self.m,
                e: self.e + k,
            }
        }
    }

    /// The product with a double, as double-double's `Dd * f64`.
    pub fn mul_f64(self, b: f64) -> Xd {
        let (mb, eb) = frexp(b);
        if mb == 0.0 || self.is_zero() {
            return Xd::ZERO;
        }
        Xd::norm(self.m * mb, self.e + eb)
    }

    /// Square root (of a value `>= 0`).
    pub fn sqrt(self) -> Xd {
        if self.m.hi <= 0.0 {
            return Xd::ZERO;
        }
        let (m, e) = if self.e % 2 == 0 {
            (self.m, self.e)
        } else {
            (self.m * 2.0, self.e - 1)
        };
        Xd::norm(m.sqrt(), e / 2)
    }

    /// The value as a double-double, `0` below the range of doubles and `inf` above.
    pub fn to_dd(self) -> Dd {
        self.m.ldexp(self.e)
    }

    /// The value as a double, rounded once.
    pub fn to_f64(self) -> f64 {
        if self.e < -1000 {
            // Round the mantissa to the bits that survive, then scale (exactly).
            ldexp(self.m.hi, self.e) + ldexp(self.m.lo, self.e)
        } else {
            ldexp(self.m.to_f64(), self.e)
        }
    }

    /// `self 2^-unit` as a [`Sd`].
    pub fn to_sd(self, unit: i32) -> Sd {
        Sd::new(self.m.to_f64(), self.e - unit)
    }

    /// `ln self` (for `self > 0`).
    pub fn ln(self) -> Dd {
        ln_dd(self.m) + LN2 * f64::from(self.e)
    }

    /// `|self| < |other|`.
    pub fn abs_lt(self, other: Xd) -> bool {
        if self.is_zero() {
            return !other.is_zero();
        }
        if other.is_zero() {
            return false;
        }
        if self.e != other.e {
            return self.e < other.e;
        }
        self.m.abs().hi < other.m.abs().hi
            || (self.m.abs().hi == other.m.abs().hi && self.m.abs().lo < other.m.abs().lo)
    }
}

impl std::ops::Neg for Xd {
    type Output = Xd;
    fn neg(self) -> Xd {
        Xd {
            m: -self.m,
            e: self.e,
        }
    }
}

impl std::ops::Add for Xd {
    type Output = Xd;
    fn add(self, b: Xd) -> Xd {
        if self.is_zero() {
            return b;
        }
        if b.is_zero() {
            return self;
        }
        let (big, small) = if self.e >= b.e { (self, b) } else { (b, self) };
        let d = big.e - small.e;
        if d > 1100 {
            return big;
        }
        Xd::norm(big.m + small.m.ldexp(-d), big.e)
    }
}

impl std::ops::Sub for Xd {
    type Output = Xd;
    fn sub(self, b: Xd) -> Xd {
        self + (-b)
    }
}

impl std::ops::Mul for Xd {
    type Output = Xd;
    fn mul(self, b: Xd) -> Xd {
        if self.is_zero() || b.is_zero() {
            return Xd::ZERO;
        }
        Xd::norm(self.m * b.m, self.e + b.e)
    }
}

impl std::ops::Div for Xd {
    type Output = Xd;
    fn div(self, b: Xd) -> Xd {
        if self.is_zero() {
            return Xd::ZERO;
        }
        Xd::norm(self.m / b.m, self.e - b.e)
    }
}

/// `Xd / f64`, as double-double's `Dd / f64` (division by the double-double of the double).
impl std::ops::Div<f64> for Xd {
    type Output = Xd;
    fn div(self, b: f64) -> Xd {
        self / Xd::new(b)
    }
}

/// The value `x 2^e`. Arithmetic keeps `e` unchanged while the double stays within
/// `[2^-960, 2^960]` (or is zero), and moves the excess into `e` otherwise.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Sd {
    pub x: f64,
    pub e: i32,
}

const SD_LIMIT: i32 = 960;

impl Sd {
    /// `x 2^e`, with the exponent folded into the double when that is exact and comfortable.
    pub fn new(x: f64, e: i32) -> Sd {
        let (m, k) = frexp(x);
        if m == 0.0 {
            // A signed zero keeps its sign (it decides atan2 on the negative axis).
            return Sd { x, e: 0 };
        }
        let total = k.saturating_add(e);
        if (-SD_LIMIT..=SD_LIMIT).contains(&total) {
            Sd {
                x: ldexp(x, e),
                e: 0,
            }
        } else {
            Sd { x: m, e: total }
        }
    }

    /// Renormalise after an operation on the double.
    fn fix(x: f64, e: i32) -> Sd {
        let (_, k) = frexp(x);
        if x == 0.0 || (-SD_LIMIT..=SD_LIMIT).contains(&k) {
            Sd { x, e }
        } else {
            Sd::new(x, e)
        }
    }

    /// The value as a double (rounded once, `0` or `inf` beyond the range).
    pub fn to_f64(self) -> f64 {
        ldexp(self.x, self.e)
    }

    /// `op(x, y) 2^e`, redone on the mantissas if the double left its comfortable range (the
    /// same bits whenever the direct result was a normal double: the scalings are exact).
    fn apply(x: f64, y: f64, e: i32, op: impl Fn(f64, f64) -> f64, sign: i32) -> Sd {
        let r = op(x, y);
        let (_, k) = frexp(r);
        if (r != 0.0 && (-SD_LIMIT..=SD_LIMIT).contains(&k))
            || x == 0.0
            || !r.is_finite() && !x.is_finite()
        {
            return Sd::fix(r, e);
        }
        let (mx, ex) = frexp(x);
        let (my, ey) = frexp(y);
        Sd::new(op(mx, my), e + ex + sign * ey)
    }

    pub fn mul(self, b: Sd) -> Sd {
        Sd::apply(self.x, b.x, self.e + b.e, |x, y| x * y, 1)
    }

    pub fn mul_f64(self, b: f64) -> Sd {
        Sd::apply(self.x, b, self.e, |x, y| x * y, 1)
    }

    pub fn div(self, b: Sd) -> Sd {
        Sd::apply(self.x, b.x, self.e - b.e, |x, y| x / y, -1)
    }

    /// Square root (of a value `>= 0`).
    pub fn sqrt(self) -> Sd {
        if self.e % 2 == 0 {
            Sd::fix(self.x.sqrt(), self.e / 2)
        } else {
            Sd::fix((2.0 * self.x).sqrt(), (self.e - 1) / 2)
        }
    }

    /// The doubles of `a` and `b` on their common (larger) exponent, and that exponent; the
    /// doubles themselves when the exponents agree.
    pub fn common(a: Sd, b: Sd) -> (f64, f64, i32) {
        if a.e == b.e || b.x == 0.0 {
            return (a.x, ldexp(b.x, b.e - a.e), a.e);
        }
        if a.x == 0.0 {
            return (0.0, b.x, b.e);
        }
        let e = a.e.max(b.e);
        (ldexp(a.x, a.e - e), ldexp(b.x, b.e - e), e)
    }

    pub fn hypot(a: Sd, b: Sd) -> Sd {
        let (x, y, e) = Sd::common(a, b);
        Sd::fix(x.hypot(y), e)
    }

    /// `atan2(a, b)`.
    pub fn atan2(a: Sd, b: Sd) -> f64 {
        let (x, y, _) = Sd::common(a, b);
        x.atan2(y)
    }
}

/// `ln 2` to 106 bits.
pub(crate) const LN2: Dd = Dd {
    hi: std::f64::consts::LN_2,
    lo: 2.319_046_813_846_299_6e-17,
};

/// `1/n!` for `n = 3..=9` to 106 bits.
const INV_FACT: [Dd; 7] = [
    Dd {
        hi: 0.166_666_666_666_666_66,
        lo: 9.251_858_538_542_97e-18,
    },
    Dd {
        hi: 0.041_666_666_666_666_664,
        lo: 2.312_964_634_635_742_7e-18,
    },
    Dd {
        hi: 0.008_333_333_333_333_333,
        lo: 1.156_482_317_317_871_4e-19,
    },
    Dd {
        hi: 0.001_388_888_888_888_889,
        lo: -5.300_543_954_373_577e-20,
    },
    Dd {
        hi: 0.000_198_412_698_412_698_4,
        lo: 1.720_955_829_342_070_5e-22,
    },
    Dd {
        hi: 2.480_158_730_158_73e-5,
        lo: 2.151_194_786_677_588_2e-23,
    },
    Dd {
        hi: 2.755_731_922_398_589_3e-6,
        lo: -1.858_393_274_046_472e-22,
    },
];

/// `e^x = m 2^k` in double-double, `1/sqrt(2) <= m <= sqrt(2)` (about 1e-30 relative); `(0, 0)`
/// far below the range of doubles.
pub(crate) fn exp_dd(x: Dd) -> (Dd, i32) {
    if x.hi < -1e6 {
        return (Dd::ZERO, 0);
    }
    let k = super::dd::round(x.hi / LN2.hi);
    // r = x - k ln 2, |r| <= ln2 / 2 (k ln 2 to 106 bits: k has at most 21 bits).
    let r = x - Dd::prod(LN2.hi, k) - Dd::prod(LN2.lo, k);
    // e^r = (e^s)^256, s = r / 256: e^s - 1 by its series to s^9 (the rest is below 1e-35 of
    // it), then 8 squarings of 1 + p carried as p <- 2 p + p^2, so that nothing cancels.
    let s = r * (1.0 / 256.0);
    let mut q = INV_FACT[6];
    for c in INV_FACT[..6].iter().rev() {
        q = q * s + *c;
    }
    let mut p = s + s * s * (s * q + 0.5);
    for _ in 0..8 {
        p = p * 2.0 + p * p;
    }
    (p + 1.0, k as i32)
}

/// `ln x` in double-double for `x > 0` (one Newton step on the double logarithm).
pub(crate) fn ln_dd(x: Dd) -> Dd {
    let y = x.hi.ln();
    let (m, k) = exp_dd(Dd::new(-y));
    // y + x e^-y - 1
    Dd::new(y) + ((x * m).ldexp(k) - 1.0)
}

/// `asinh y` in double-double for `y >= 0` given as an [`Xd`]: `ln(y + sqrt(1 + y^2))`,
/// `y (1 - y^2/6 + 3 y^4/40)` for `y < 1e-9`.
pub(crate) fn asinh_xd(y: Xd) -> Dd {
    if y.is_zero() {
        return Dd::ZERO;
    }
    if y.e < -30 {
        let d = y.to_dd();
        let d2 = d * d;
        return d * (Dd::ONE - d2 / 6.0 + d2 * d2 * (3.0 / 40.0));
    }
    (y + (Xd::new(1.0) + y * y).sqrt()).ln()
}

/// The exact value of `sum_k a_k b_k^2 (c_k - d_k)` for doubles, rounded to 106 bits, with its
/// exact sign (zero only if the sum is zero): the products of the mantissas form an exact
/// expansion (two-product splits), which repeated error-free passes (two-sum along the list,
/// Ogita, Rump and Oishi 2005) distil until it no longer changes. Exact while the terms are
/// within `2^1000` of each other (a smaller one is negligible, not lost to the sign).
pub(crate) fn exact_sum_a_b2_diff(terms: &[(f64, f64, f64, f64); 2]) -> Xd {
    // At most 2 terms x 2 parts of the difference x 16 components of a four-fold product.
    let mut parts = [(0.0f64, 0i32); 64];
    let mut n = 0;
    for &(a, b, c, d) in terms {
        let diff = Dd::sum(c, -d);
        for x in [diff.hi, diff.lo] {
            if x == 0.0 || a == 0.0 || b == 0.0 {
                continue;
            }
            let (ma, ea) = frexp(a);
            let (mb, eb) = frexp(b);
            let (mx, ex) = frexp(x);
            let mut comps = [0.0f64; 16];
            comps[0] = 1.0;
            let mut len = 1;
            for m in [ma, mb, mb, mx] {
                for i in (0..len).rev() {
                    let p = Dd::prod(comps[i], m);
                    comps[2 * i] = p.hi;
                    comps[2 * i + 1] = p.lo;
                }
                len *= 2;
            }
            let e = ea + 2 * eb + ex;
            for c in &comps[..len] {
                parts[n] = (*c, e);
                n += 1;
            }
        }
    }
    let Some(emax) = parts[..n].iter().map(|p| p.1).max() else {
        return Xd::ZERO;
    };
    let mut v = [0.0f64; 64];
    let mut len = 0;
    for &(c, e) in &parts[..n] {
        let x = ldexp(c, e - emax);
        if x != 0.0 {
            v[len] = x;
            len += 1;
        }
    }
    if len == 0 {
        return Xd::ZERO;
    }
    let v = &mut v[..len];
    for _ in 0..200 {
        let mut changed = false;
        for i in 1..len {
            let s = Dd::sum(v[i], v[i - 1]);
            changed |= s.hi != v[i] || s.lo != v[i - 1];
            v[i] = s.hi;
            v[i - 1] = s.lo;
        }
        if !changed {
            break;
        }
    }
    let lo: f64 = v[..len - 1].iter().sum();
    Xd::from_dd(Dd::sum(v[len - 1], lo)).ldexp(emax)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_sums_see_through_cancellation() {
        // 3 * 3^2 * (1 - 2) + 1 * 1^2 * (27 - 0) = 0 exactly; with the second moment one ulp
        // off, 2^-48 exactly.
        assert!(exact_sum_a_b2_diff(&[(3.0, 3.0, 1.0, 2.0), (1.0, 1.0, 27.0, 0.0)]).is_zero());
        let x =
            exact_sum_a_b2_diff(&[(3.0, 3.0, 1.0, 2.0), (1.0, 1.0, 27.0 + 2f64.powi(-48), 0.0)]);
        assert_eq!(x.to_f64(), 2f64.powi(-48));
        // I (1, 2, 3.125), w = (3, ., 1.6): 1 9 (1 - 2) + 3.125 1.6^2 (3.125 - 2) = 0 in reals,
        // not in doubles (1.6 is not): the sign and size of what the doubles give.
        let x = exact_sum_a_b2_diff(&[(1.0, 3.0, 1.0, 2.0), (3.125, 1.6, 3.125, 2.0)]);
        assert!(!x.is_zero());
        // Below the range of doubles: 1e-170 components.
        let x = exact_sum_a_b2_diff(&[(3.0, 1e-170, 3.0, 5.0), (9.0, 1e-170, 9.0, 5.0)]);
        let want = Xd::new(30.0) * Xd::new(1e-170) * Xd::new(1e-170);
        assert!(((x - want) / want).abs().to_f64() < 1e-30);
    }

    #[test]
    fn frexp_and_ldexp_are_exact() {
        for x in [
            1.0,
            1.5,
            -3.0,
            1e-310,
            5e-324,
            f64::MAX,
            2.2250738585072014e-308,
        ] {
            let (m, e) = frexp(x);
            assert!((1.0..2.0).contains(&m.abs()), "{x}");
            assert_eq!(ldexp(m, e), x);
        }
        assert_eq!(ldexp(1.0, -1074), 5e-324);
        assert_eq!(ldexp(1.5, -1075), 5e-324); // 0.75 of the smallest subnormal rounds up
        assert_eq!(ldexp(1.0, 1024), f64::INFINITY);
        assert_eq!(ldexp(3.0, -2000), 0.0);
    }

    /// `ldexp` is `x 2^e` correctly rounded, against a construction from the bits in integer
    /// arithmetic (the significand shifted with ties to even below the normal range), for
    /// doubles of every magnitude, subnormal ones included, and exponents past both ends.
    #[test]
    fn ldexp_rounds_once_from_the_bits() {
        fn reference(x: f64, e: i32) -> f64 {
            let bits = x.to_bits();
            let sign = bits & (1 << 63);
            let (be, frac) = (((bits >> 52) & 0x7ff) as i64, bits & ((1u64 << 52) - 1));
            if be == 0x7ff || (be == 0 && frac == 0) {
                return x;
            }
            // |x| = sig 2^(k - 52), 2^52 <= sig < 2^53.
            let (mut sig, mut k) = if be == 0 {
                (frac, -1022)
            } else {
                (frac | 1 << 52, be - 1023)
            };
            while sig < 1 << 52 {
                sig <<= 1;
                k -= 1;
            }
            let t = k + i64::from(e);
            let magnitude = if t > 1023 {
                0x7ff0_0000_0000_0000
            } else if t >= -1022 {
                (((t + 1023) as u64) << 52) | (sig & ((1 << 52) - 1))
            } else {
                // Subnormal: sig 2^(t - 52) in units of 2^-1074 is sig >> (-1022 - t).
                let shift = (-1022 - t) as u32;
                if shift > 54 {
                    0
                } else {
                    let (q, r) = (sig >> shift, sig & ((1u64 << shift) - 1));
                    let half = 1u64 << (shift - 1);
                    q + u64::from(r > half || (r == half && q & 1 == 1))
                }
            };
            f64::from_bits(sign | magnitude)
        }
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        for k in 0..300_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let x = f64::from_bits(state);
            let e = (state % 4400) as i32 - 2200;
            let e = if k % 3 == 0 { e % 60 } else { e };
            let want = reference(x, e);
            let got = ldexp(x, e);
            assert!(
                got.to_bits() == want.to_bits() || (got.is_nan() && want.is_nan()),
                "{x:e} 2^{e}: {got:e}, {want:e}"
            );
        }
    }

    #[test]
    fn extended_numbers_keep_tiny_squares() {
        let a = Xd::new(1e-170);
        let sq = a * a;
        assert_eq!(sq.e, -1130);
        let back = sq.sqrt();
        assert_eq!(back.to_f64(), 1e-170);
        let s = Xd::new(3e-200) * Xd::new(3e-200) - Xd::new(1e-200) * Xd::new(1e-200);
        let r = (s / (Xd::new(1e-200) * Xd::new(1e-200))).to_f64();
        assert!((r - 8.0).abs() <= 8.0 * 4.0 * f64::EPSILON);
    }

    #[test]
    fn exp_and_ln_are_double_double() {
        let (m, k) = exp_dd(Dd::ONE);
        let e = m.ldexp(k);
        // e = 2.718281828459045235360287471352662497757
        assert_eq!(e.hi, std::f64::consts::E);
        assert!((e.lo - 1.445_646_891_729_250_2e-16).abs() < 1e-31);
        let l = ln_dd(Dd::new(10.0));
        // ln 10 = 2.302585092994045684017991454684364207601
        assert_eq!(l.hi, std::f64::consts::LN_10);
        assert!((l.lo - (-2.170_756_223_382_249_4e-16)).abs() < 1e-31);
        let (m, k) = exp_dd(Dd::new(-745.0));
        assert!(k < -1070 && m.hi > 0.7);
        // ln(0.75 2^-3000) = -2079.729... to 1e-31 relative.
        let x = Xd::new(0.75).ldexp(-3000);
        let want = ln_dd(Dd::new(0.75)) - LN2 * 3000.0;
        assert!((x.ln() - want).hi.abs() < 1e-28);
        // ln 0.75 = -0.2876820724517809274392190059938274315035
        let l = ln_dd(Dd::new(0.75));
        assert!((l - Dd::new(-0.287_682_072_451_780_9)).hi.abs() < 1e-16);
        assert!((l.hi - -0.287_682_072_451_780_9).abs() < 1e-16);
        let back = exp_dd(l);
        assert!((back.0.ldexp(back.1) - 0.75).hi.abs() < 1e-31);
    }
}

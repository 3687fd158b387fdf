//! Double-double arithmetic (an unevaluated sum `hi + lo` of two doubles, about 106 bits).
//!
//! Error-free transformations after Dekker (1971) and Knuth; the algorithms are those of the QD
//! library (Hida, Li & Bailey 2001). Used only for the constants that set the phase of the exact
//! motion, so that the phase error does not grow with time beyond the rounding of the time itself.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// `hi + lo` with `|lo| <= ulp(hi) / 2`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Dd {
    pub hi: f64,
    pub lo: f64,
}

/// `a + b = s + e` exactly (Knuth's TwoSum).
#[inline]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    let e = (a - (s - bb)) + (b - bb);
    (s, e)
}

/// `a + b = s + e` exactly, given `|a| >= |b|` (Dekker's FastTwoSum).
#[inline]
fn quick_two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    (s, b - (s - a))
}

/// `a * b = p + e` exactly (with a fused multiply-add).
#[inline]
fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

/// `x.round()` (the nearest integer, ties away from zero), the same bits (a NaN is a NaN: Rust
/// does not fix the bits of NaNs), without the call to
/// the C library's `round` that `f64::round` is on the x86-64 baseline (no rounding
/// instruction before SSE4.1): in the reductions of the phase, several times per output.
#[inline(always)]
pub(crate) fn round(x: f64) -> f64 {
    let a = x.abs();
    // Below 2^52 a double may have a fraction; above, it is an integer (or inf, or NaN).
    if a < 4_503_599_627_370_496.0 {
        // The truncation, and the fraction `a - i` (exact: `i <= a < i + 1`).
        let i = a as i64 as f64;
        let r = if a - i >= 0.5 { i + 1.0 } else { i };
        r.copysign(x)
    } else {
        x
    }
}

impl Dd {
    pub const ZERO: Dd = Dd { hi: 0.0, lo: 0.0 };
    pub const ONE: Dd = Dd { hi: 1.0, lo: 0.0 };
    /// pi to 106 bits.
    pub const PI: Dd = Dd {
        hi: std::f64::consts::PI,
        lo: 1.224_646_799_147_353_2e-16,
    };
    /// 2 pi to 106 bits.
    pub const TAU: Dd = Dd {
        hi: std::f64::consts::TAU,
        lo: 2.449_293_598_294_706_4e-16,
    };

    #[inline]
    pub fn new(x: f64) -> Dd {
        Dd { hi: x, lo: 0.0 }
    }

    /// The exact sum of two doubles.
    #[inline]
    pub fn sum(a: f64, b: f64) -> Dd {
        let (hi, lo) = two_sum(a, b);
        Dd { hi, lo }
    }

    /// The exact product of two doubles.
    #[inline]
    pub fn prod(a: f64, b: f64) -> Dd {
        let (hi, lo) = two_prod(a, b);
        Dd { hi, lo }
    }

    #[inline]
    pub fn to_f64(self) -> f64 {
        self.hi + self.lo
    }

    #[inline]
    pub fn mul_f64(self, b: f64) -> Dd {
        let (p, e) = two_prod(self.hi, b);
        let e = self.lo.mul_add(b, e);
        let (hi, lo) = quick_two_sum(p, e);
        Dd { hi, lo }
    }

    /// Square root (one Newton step on the double estimate, Karp & Markstein).
    pub fn sqrt(self) -> Dd {
        if self.hi <= 0.0 {
            return Dd::new(self.hi.sqrt());
        }
        let x = self.hi.sqrt();
        let r = self - Dd::prod(x, x);
        let (hi, lo) = quick_two_sum(x, r.hi / (2.0 * x));
        Dd { hi, lo }
    }

    /// The nearest integer (ties away from zero), as a double-double.
    pub fn round(self) -> Dd {
        let hi = self.hi.round();
        if hi == self.hi {
            // hi is an integer: round the low part.
            let lo = self.lo.round();
            let (hi, lo) = quick_two_sum(hi, lo);
            // A tie on the low part that crossed half an integer is harmless here.
            Dd { hi, lo }
        } else if (hi - self.hi).abs() == 0.5 {
            // Exactly half on hi: the low part decides.
            let hi = if self.lo > 0.0 {
                self.hi.ceil()
            } else if self.lo < 0.0 {
                self.hi.floor()
            } else {
                hi
            };
            Dd::new(hi)
        } else {
            Dd::new(hi)
        }
    }

    pub fn abs(self) -> Dd {
        if self.hi < 0.0 {
            -self
        } else {
            self
        }
    }
}

impl Neg for Dd {
    type Output = Dd;
    #[inline]
    fn neg(self) -> Dd {
        Dd {
            hi: -self.hi,
            lo: -self.lo,
        }
    }
}

impl Add for Dd {
    type Output = Dd;
    #[inline]
    fn add(self, b: Dd) -> Dd {
        // The accurate (IEEE-style) addition of QD.
        let (s1, s2) = two_sum(self.hi, b.hi);
        let (t1, t2) = two_sum(self.lo, b.lo);
        let s2 = s2 + t1;
        let (s1, s2) = quick_two_sum(s1, s2);
        let s2 = s2 + t2;
        let (hi, lo) = quick_two_sum(s1, s2);
        Dd { hi, lo }
    }
}

impl Add<f64> for Dd {
    type Output = Dd;
    #[inline]
    fn add(self, b: f64) -> Dd {
        let (s1, s2) = two_sum(self.hi, b);
        let s2 = s2 + self.lo;
        let (hi, lo) = quick_two_sum(s1, s2);
        Dd { hi, lo }
    }
}

impl Sub for Dd {
    type Output = Dd;
    #[inline]
    fn sub(self, b: Dd) -> Dd {
        self + (-b)
    }
}

impl Sub<f64> for Dd {
    type Output = Dd;
    #[inline]
    fn sub(self, b: f64) -> Dd {
        self + (-b)
    }
}

impl Mul for Dd {
    type Output = Dd;
    #[inline]
    fn mul(self, b: Dd) -> Dd {
        let (p, e) = two_prod(self.hi, b.hi);
        let e = e + (self.hi * b.lo + self.lo * b.hi);
        let (hi, lo) = quick_two_sum(p, e);
        Dd { hi, lo }
    }
}

impl Mul<f64> for Dd {
    type Output = Dd;
    #[inline]
    fn mul(self, b: f64) -> Dd {
        self.mul_f64(b)
    }
}

impl Div for Dd {
    type Output = Dd;
    #[inline]
    fn div(self, b: Dd) -> Dd {
        // Long division with three partial quotients (QD's accurate division).
        let q1 = self.hi / b.hi;
        let r = self - b * q1;
        let q2 = r.hi / b.hi;
        let r = r - b * q2;
        let q3 = r.hi / b.hi;
        let (hi, lo) = quick_two_sum(q1, q2);
        Dd { hi, lo } + q3
    }
}

impl Div<f64> for Dd {
    type Output = Dd;
    #[inline]
    fn div(self, b: f64) -> Dd {
        self / Dd::new(b)
    }
}

/// The arithmetic-geometric mean of 1 and `b` (`0 < b <= 1`), to double-double accuracy.
pub(crate) fn agm1(b: Dd) -> Dd {
    let mut a = Dd::ONE;
    let mut g = b;
    for _ in 0..64 {
        // The AGM converges quadratically: the next a - g is about (a - g)^2 / (8 a), so once
        // |a - g| <= 2^-52 a the mean (a + g) / 2 is the limit to within 2^-107 a, below
        // double-double rounding. (A test for |a - g| <= 1e-33 a never passed: rounding leaves
        // a and g about 1.5e-33 a apart, and every call ran all 64 iterations, not 6 to 8.)
        let diff = (a - g).hi.abs();
        if diff <= f64::EPSILON * a.hi {
            break;
        }
        let a1 = (a + g) * 0.5;
        g = (a * g).sqrt();
        a = a1;
    }
    (a + g) * 0.5
}

/// Bulirsch's general complete elliptic integral
/// `cel(kc, p, a, b) = int_0^{pi/2} (a cos^2 + b sin^2) / ((cos^2 + p sin^2) sqrt(cos^2 + kc^2 sin^2)) dt`
/// for `kc > 0` and `p > 0`, by Bulirsch's quadratically convergent algorithm (Bulirsch 1969,
/// Numer. Math. 13, 305), in double-double.
pub(crate) fn cel(kc: Dd, p: Dd, a: Dd, b: Dd) -> Dd {
    cel_many(kc, p, [(a, b)])[0]
}

/// [`cel`] of several `(a, b)` at one `(kc, p)`, in one loop: `kc`, `p` and the means do not
/// depend on `(a, b)` (cel is linear in them), so they are iterated once for all. Each result
/// has the bits of its own [`cel`] call: the same operations on it, in the same order.
pub(crate) fn cel_many<const N: usize>(kc: Dd, p: Dd, ab: [(Dd, Dd); N]) -> [Dd; N] {
    let mut kc = kc.abs();
    let mut e = kc;
    let mut m = Dd::ONE;
    let mut p = p.sqrt();
    let mut a = ab.map(|(a, _)| a);
    let mut b = ab.map(|(_, b)| b / p);
    for _ in 0..64 {
        let g = e / p;
        for (a, b) in a.iter_mut().zip(b.iter_mut()) {
            let f = *a;
            *a = *a + *b / p;
            *b = (*b + f * g) * 2.0;
        }
        p = g + p;
        let g = m;
        m = m + kc;
        if (g - kc).hi.abs() <= g.hi * 1e-16 {
            break;
        }
        kc = e.sqrt() * 2.0;
        e = kc * m;
    }
    let half_pi = Dd::PI * 0.5;
    let den = m * (m + p);
    let mut out = [Dd::ZERO; N];
    for (o, (a, b)) in out.iter_mut().zip(a.iter().zip(&b)) {
        *o = half_pi * (*b + *a * m) / den;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `round` is `f64::round` bit for bit: ties, signed zeros, the edges of 2^52 and 2^53,
    /// infinities and random doubles of every magnitude (NaN for NaN).
    #[test]
    fn round_is_the_library_round() {
        let mut cases = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.5,
            2.5,
            -2.5,
            0.49999999999999994,
            -0.49999999999999994,
            1.0 - f64::EPSILON / 2.0,
            4_503_599_627_370_495.5,
            4_503_599_627_370_496.0,
            4_503_599_627_370_497.0,
            9_007_199_254_740_993.0,
            f64::MIN_POSITIVE,
            5e-324,
            f64::MAX,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            1e300,
            -7.5,
            3.4999999999999996,
        ];
        // A fixed xorshift: doubles from random bits, and random values near integers.
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        for k in 0..200_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let x = f64::from_bits(state);
            cases.push(x);
            let scale = f64::from(k % 60 - 5).exp2();
            let near = ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * scale;
            cases.extend([near, near.round() + 0.5, near.round() - 0.5]);
        }
        for x in cases {
            if x.is_nan() {
                assert!(round(x).is_nan());
            } else {
                assert_eq!(round(x).to_bits(), x.round().to_bits(), "{x:e}");
            }
        }
    }

    #[test]
    fn arithmetic_is_double_double() {
        let third = Dd::ONE / Dd::new(3.0);
        let back = third * 3.0 - 1.0;
        assert!(back.hi.abs() < 1e-31);
        let two = Dd::new(2.0).sqrt();
        assert!((two * two - 2.0).hi.abs() < 1e-31);
        // 2^(1/2) = 1.4142135623730950488016887242097
        assert_eq!(two.hi, std::f64::consts::SQRT_2);
        assert!((two.lo - (-9.667_293_313_452_913e-17)).abs() < 1e-31);
    }

    #[test]
    fn agm1_is_the_50_digit_mean_in_a_few_steps() {
        // AGM(1, b) of the double b by mpmath at 50 digits, as hi + lo. The stopping test used to ask for
        // |a - g| <= 1e-33 a, below double-double rounding, and every call ran 64 iterations.
        for (b, hi, lo) in [
            (0.5, 0.7283955155234534, 4.945050030370928e-17),
            (1e-3, 0.1893883024099509, -1.1128827200186603e-17),
            (0.999999, 0.9999994999999375, -4.998611844991319e-17),
        ] {
            let got = agm1(Dd::new(b));
            let err = ((got.hi - hi) + (got.lo - lo)).abs();
            assert!(err <= 4e-32 * hi, "b = {b}: {got:?}, error {err:e}");
        }
    }

    #[test]
    fn cel_many_gives_each_cel_its_own_bits() {
        let ab = [
            (Dd::ZERO, Dd::ONE),
            (Dd::ONE, Dd::ZERO),
            (Dd::new(0.3), Dd::new(-2.5)),
        ];
        for (kc, p) in [
            (0.3, 1.7),
            (0.999, 1.0001),
            (1e-3, 40.0),
            (0.7, 0.2),
            (1e-150, 3.0),
        ] {
            let (kc, p) = (Dd::new(kc), Dd::new(p));
            let many = cel_many(kc, p, ab);
            for (got, (a, b)) in many.iter().zip(ab) {
                let one = cel(kc, p, a, b);
                assert_eq!(
                    (got.hi.to_bits(), got.lo.to_bits()),
                    (one.hi.to_bits(), one.lo.to_bits())
                );
            }
            // Linear in (a, b): cel(1, 0) + cel(0, 1) = cel(1, 1), which at p = 1 is K (by the
            // AGM, an independent algorithm).
            let k = if p.hi == 1.0 {
                Dd::PI / (agm1(kc) * 2.0)
            } else {
                cel(kc, p, Dd::ONE, Dd::ONE)
            };
            let sum = many[0] + many[1];
            assert!(((sum - k) / k).hi.abs() <= 1e-30, "{sum:?} {k:?}");
        }
    }

    #[test]
    fn cel_gives_complete_integrals() {
        // cel(kc, 1, 1, 1) = K and pi / (2 AGM); cel(kc, p, 1, 1) at p = 1 - n is Pi(n).
        for kc in [1.0, 0.5, 1e-3, 1e-150] {
            let k1 = cel(Dd::new(kc), Dd::ONE, Dd::ONE, Dd::ONE);
            let k2 = Dd::PI / (agm1(Dd::new(kc)) * 2.0);
            assert!((k1 - k2).hi.abs() <= 1e-30 * k2.hi, "kc = {kc}");
        }
        // K(m = 0) = pi/2 exactly; Pi(n | 0) = pi / (2 sqrt(1 - n)).
        let k = cel(Dd::ONE, Dd::ONE, Dd::ONE, Dd::ONE);
        assert!((k - Dd::PI * 0.5).hi.abs() < 1e-31);
        let p = cel(Dd::ONE, Dd::new(4.0), Dd::ONE, Dd::ONE);
        assert!((p - Dd::PI * 0.25).hi.abs() < 1e-31);
    }

    #[test]
    fn rounding() {
        let x = Dd {
            hi: 4.0,
            lo: -1e-20,
        };
        assert_eq!(x.round().to_f64(), 4.0);
        let y = Dd { hi: 2.5, lo: 1e-20 };
        assert_eq!(y.round().to_f64(), 3.0);
        let z = Dd {
            hi: 2.5,
            lo: -1e-20,
        };
        assert_eq!(z.round().to_f64(), 2.0);
        let w = Dd { hi: -7.3, lo: 0.0 };
        assert_eq!(w.round().to_f64(), -7.0);
    }
}

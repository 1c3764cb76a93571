//! Double-double arithmetic: an unevaluated sum `hi + lo` of two f64 with `|lo| <= ulp(hi)/2`,
//! about 106 significant bits. It is the high-precision reference of the stress campaign:
//! error-free transformations (Knuth's TwoSum, TwoProd through a fused multiply-add) carry
//! the rounding error of every operation in `lo` (Dekker 1971; Hida, Li and Bailey 2001).
//! Only what the references need is here: +, -, *, /, sqrt, comparisons.

use std::cmp::Ordering;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// A double-double number `hi + lo`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Dd {
    pub hi: f64,
    pub lo: f64,
}

/// `a + b = s + e` exactly (Knuth's TwoSum, no precondition on magnitudes).
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    let e = (a - (s - bb)) + (b - bb);
    (s, e)
}

/// `a + b = s + e` exactly when `|a| >= |b|` (Dekker's FastTwoSum).
fn quick_two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    (s, b - (s - a))
}

/// `a * b = p + e` exactly: the fused multiply-add returns the product's rounding error.
fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

impl Dd {
    pub const ZERO: Dd = Dd { hi: 0.0, lo: 0.0 };

    pub fn new(x: f64) -> Dd {
        Dd { hi: x, lo: 0.0 }
    }

    /// Nearest f64.
    pub fn to_f64(self) -> f64 {
        self.hi + self.lo
    }

    pub fn abs(self) -> Dd {
        if self.hi < 0.0 { -self } else { self }
    }

    pub fn is_finite(self) -> bool {
        self.hi.is_finite() && self.lo.is_finite()
    }

    pub fn signum(self) -> f64 {
        if self.hi > 0.0 {
            1.0
        } else if self.hi < 0.0 {
            -1.0
        } else {
            0.0
        }
    }

    /// Square root: one Newton step `x + (a - x^2) / (2 x)` from the f64 root, which doubles
    /// the number of correct bits.
    pub fn sqrt(self) -> Dd {
        if self.hi <= 0.0 {
            return Dd::ZERO;
        }
        let x = self.hi.sqrt();
        let xx = Dd::from(two_prod(x, x));
        let corr = (self - xx).hi / (2.0 * x);
        let (s, e) = quick_two_sum(x, corr);
        Dd { hi: s, lo: e }
    }

    pub fn sqr(self) -> Dd {
        self * self
    }

    pub fn max(self, o: Dd) -> Dd {
        if o > self { o } else { self }
    }

    pub fn min(self, o: Dd) -> Dd {
        if o < self { o } else { self }
    }
}

impl From<(f64, f64)> for Dd {
    fn from((hi, lo): (f64, f64)) -> Dd {
        let (s, e) = two_sum(hi, lo);
        Dd { hi: s, lo: e }
    }
}

impl From<f64> for Dd {
    fn from(x: f64) -> Dd {
        Dd::new(x)
    }
}

impl Add for Dd {
    type Output = Dd;
    /// Accurate addition (Hida-Li-Bailey "ieee add": both TwoSums, two renormalisations).
    fn add(self, o: Dd) -> Dd {
        let (s1, s2) = two_sum(self.hi, o.hi);
        let (t1, t2) = two_sum(self.lo, o.lo);
        let (s1, s2) = quick_two_sum(s1, s2 + t1);
        let (hi, lo) = quick_two_sum(s1, s2 + t2);
        Dd { hi, lo }
    }
}

impl Neg for Dd {
    type Output = Dd;
    fn neg(self) -> Dd {
        Dd {
            hi: -self.hi,
            lo: -self.lo,
        }
    }
}

impl Sub for Dd {
    type Output = Dd;
    fn sub(self, o: Dd) -> Dd {
        self + (-o)
    }
}

impl Mul for Dd {
    type Output = Dd;
    fn mul(self, o: Dd) -> Dd {
        let (p, e) = two_prod(self.hi, o.hi);
        let e = e + (self.hi * o.lo + self.lo * o.hi);
        let (hi, lo) = quick_two_sum(p, e);
        Dd { hi, lo }
    }
}

impl Div for Dd {
    type Output = Dd;
    /// Long division: two quotient digits and a correction.
    fn div(self, o: Dd) -> Dd {
        let q1 = self.hi / o.hi;
        let r = self - o * Dd::new(q1);
        let q2 = r.hi / o.hi;
        let r = r - o * Dd::new(q2);
        let q3 = r.hi / o.hi;
        let (hi, lo) = quick_two_sum(q1, q2);
        Dd { hi, lo } + Dd::new(q3)
    }
}

impl PartialOrd for Dd {
    fn partial_cmp(&self, o: &Dd) -> Option<Ordering> {
        match self.hi.partial_cmp(&o.hi)? {
            Ordering::Equal => self.lo.partial_cmp(&o.lo),
            ord => Some(ord),
        }
    }
}

/// A vector of three double-doubles.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Dd3 {
    pub x: Dd,
    pub y: Dd,
    pub z: Dd,
}

impl Dd3 {
    pub fn new(x: Dd, y: Dd, z: Dd) -> Dd3 {
        Dd3 { x, y, z }
    }

    pub fn from_f64(v: glam::DVec3) -> Dd3 {
        Dd3::new(Dd::new(v.x), Dd::new(v.y), Dd::new(v.z))
    }

    pub fn dot(self, o: Dd3) -> Dd {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    pub fn cross(self, o: Dd3) -> Dd3 {
        Dd3::new(
            self.y * o.z - self.z * o.y,
            self.z * o.x - self.x * o.z,
            self.x * o.y - self.y * o.x,
        )
    }

    pub fn scale(self, s: Dd) -> Dd3 {
        Dd3::new(self.x * s, self.y * s, self.z * s)
    }

    /// The point `self + t dir`.
    pub fn along(self, dir: Dd3, t: Dd) -> Dd3 {
        self + dir.scale(t)
    }

    pub fn to_f64(self) -> glam::DVec3 {
        glam::DVec3::new(self.x.to_f64(), self.y.to_f64(), self.z.to_f64())
    }
}

impl Add for Dd3 {
    type Output = Dd3;
    fn add(self, o: Dd3) -> Dd3 {
        Dd3::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}

impl Sub for Dd3 {
    type Output = Dd3;
    fn sub(self, o: Dd3) -> Dd3 {
        Dd3::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_third_has_twice_the_digits() {
        // 1/3 in double-double: hi = 0.333...33 (f64), lo = 1/3 - hi = 1.850371707708594e-17.
        let third = Dd::new(1.0) / Dd::new(3.0);
        assert_eq!(third.hi, 1.0 / 3.0);
        assert!((third.lo - 1.850_371_707_708_594e-17).abs() < 1e-31, "{}", third.lo);
        // 3 * (1/3) - 1 is below 2^-104 in magnitude.
        assert!((third * Dd::new(3.0) - Dd::new(1.0)).to_f64().abs() < 1e-31);
    }

    #[test]
    fn cancellation_keeps_the_small_part() {
        // (1e8 + 1e-8)^2 - 1e16 = 2 + 1e-16: lost entirely in f64, kept in double-double.
        let x = Dd::new(1e8) + Dd::new(1e-8);
        let y = x.sqr() - Dd::new(1e16);
        assert!((y.to_f64() - 2.0).abs() < 1e-15, "{y:?}");
        assert!((y - Dd::new(2.0)).to_f64() > 0.0);
    }

    #[test]
    fn square_root_of_two() {
        // sqrt(2) = 1.41421356237309504880168872420969807856967...: the low part is
        // sqrt(2) - 1.4142135623730951 = -9.667293313452913e-17.
        let r = Dd::new(2.0).sqrt();
        assert_eq!(r.hi, std::f64::consts::SQRT_2);
        assert!((r.lo + 9.667_293_313_452_913e-17).abs() < 1e-30, "{}", r.lo);
        assert!((r * r - Dd::new(2.0)).to_f64().abs() < 1e-31);
    }
}

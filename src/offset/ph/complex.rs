//! A small complex number type for the planar PH form (seed 004 §2.1.2: the plane as ℂ).
//!
//! Written by hand rather than taken from `num-complex`: the PH code needs only the field
//! operations, conjugate, modulus, argument and the principal square root, and the core crate
//! keeps its dependency list short.

use glam::DVec2;
use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub, SubAssign};

/// z = re + i·im.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Complex {
    pub re: f64,
    pub im: f64,
}

impl Complex {
    /// 0.
    pub const ZERO: Complex = Complex { re: 0.0, im: 0.0 };
    /// 1.
    pub const ONE: Complex = Complex { re: 1.0, im: 0.0 };
    /// The imaginary unit i.
    pub const I: Complex = Complex { re: 0.0, im: 1.0 };

    /// re + i·im.
    pub const fn new(re: f64, im: f64) -> Self {
        Self { re, im }
    }

    /// The point (x, y) as x + i·y.
    pub fn from_vec(v: DVec2) -> Self {
        Self { re: v.x, im: v.y }
    }

    /// The complex number as the point (re, im).
    pub fn to_vec(self) -> DVec2 {
        DVec2::new(self.re, self.im)
    }

    /// Complex conjugate re − i·im.
    pub fn conj(self) -> Self {
        Self::new(self.re, -self.im)
    }

    /// |z|² = re² + im².
    pub fn norm_sqr(self) -> f64 {
        self.re * self.re + self.im * self.im
    }

    /// |z| (computed with `hypot`, no overflow for large parts).
    pub fn abs(self) -> f64 {
        self.re.hypot(self.im)
    }

    /// Principal argument in (−π, π]; 0 for z = 0.
    pub fn arg(self) -> f64 {
        self.im.atan2(self.re)
    }

    /// Principal square root (Re √z ≥ 0, branch cut on the negative real axis), computed
    /// without cancellation: √z = (r, im/(2r)) with r = √((|z| + |re|)/2) for re ≥ 0, and the
    /// mirrored form for re < 0.
    pub fn sqrt(self) -> Self {
        if self.re == 0.0 && self.im == 0.0 {
            return Self::ZERO;
        }
        let m = self.abs();
        let r = ((m + self.re.abs()) * 0.5).sqrt();
        if self.re >= 0.0 {
            Self::new(r, self.im / (2.0 * r))
        } else {
            Self::new(self.im.abs() / (2.0 * r), r.copysign(self.im))
        }
    }

    /// True when both parts are finite.
    pub fn is_finite(self) -> bool {
        self.re.is_finite() && self.im.is_finite()
    }
}

impl From<f64> for Complex {
    fn from(x: f64) -> Self {
        Complex::new(x, 0.0)
    }
}

impl Add for Complex {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self::new(self.re + o.re, self.im + o.im)
    }
}
impl AddAssign for Complex {
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}
impl Sub for Complex {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Self::new(self.re - o.re, self.im - o.im)
    }
}
impl SubAssign for Complex {
    fn sub_assign(&mut self, o: Self) {
        *self = *self - o;
    }
}
impl Neg for Complex {
    type Output = Self;
    fn neg(self) -> Self {
        Self::new(-self.re, -self.im)
    }
}
impl Mul for Complex {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        Self::new(
            self.re * o.re - self.im * o.im,
            self.re * o.im + self.im * o.re,
        )
    }
}
impl Mul<f64> for Complex {
    type Output = Self;
    fn mul(self, s: f64) -> Self {
        Self::new(self.re * s, self.im * s)
    }
}
impl Mul<Complex> for f64 {
    type Output = Complex;
    fn mul(self, z: Complex) -> Complex {
        z * self
    }
}
impl Div for Complex {
    type Output = Self;
    /// a / b = a·conj(b) / |b|².
    fn div(self, o: Self) -> Self {
        let d = o.norm_sqr();
        let n = self * o.conj();
        Self::new(n.re / d, n.im / d)
    }
}
impl Div<f64> for Complex {
    type Output = Self;
    fn div(self, s: f64) -> Self {
        Self::new(self.re / s, self.im / s)
    }
}

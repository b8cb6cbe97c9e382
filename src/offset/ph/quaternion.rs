//! A small quaternion type for the spatial PH form (seed 004 §2.2.2: r′ = A i A*).
//!
//! Written by hand rather than using `glam::DQuat`: `DQuat` is built around unit rotation
//! quaternions (its vector rotation assumes |q| = 1, and glam's optional assertions check
//! normalization), while the PH preimage A(t) is a non-unit quaternion polynomial whose
//! modulus carries the parametric speed |r′| = |A|².

use glam::DVec3;
use std::ops::{Add, Mul, Neg, Sub};

/// q = s + v_x i + v_y j + v_z k (scalar part `s`, vector part `v`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Quaternion {
    pub s: f64,
    pub v: DVec3,
}

impl Quaternion {
    /// 0.
    pub const ZERO: Quaternion = Quaternion {
        s: 0.0,
        v: DVec3::ZERO,
    };

    /// s + x i + y j + z k.
    pub const fn new(s: f64, x: f64, y: f64, z: f64) -> Self {
        Self {
            s,
            v: DVec3::new(x, y, z),
        }
    }

    /// The pure quaternion of a vector.
    pub const fn pure(v: DVec3) -> Self {
        Self { s: 0.0, v }
    }

    /// Conjugate q* = s − v.
    pub fn conj(self) -> Self {
        Self {
            s: self.s,
            v: -self.v,
        }
    }

    /// |q|² = s² + |v|².
    pub fn norm_sqr(self) -> f64 {
        self.s * self.s + self.v.length_squared()
    }

    /// Four-dimensional dot product (the real part of p q*).
    pub fn dot(self, o: Self) -> f64 {
        self.s * o.s + self.v.dot(o.v)
    }

    /// True when all four parts are finite.
    pub fn is_finite(self) -> bool {
        self.s.is_finite() && self.v.is_finite()
    }

    /// The vector part of q u q* for a pure quaternion u (the scalar part is 0).
    pub fn sandwich(self, u: DVec3) -> DVec3 {
        (self * Quaternion::pure(u) * self.conj()).v
    }

    /// A i A* in closed form: (s² + x² − y² − z², 2(xy + sz), 2(xz − sy)).
    pub fn i_sandwich(self) -> DVec3 {
        let Quaternion { s, v } = self;
        DVec3::new(
            s * s + v.x * v.x - v.y * v.y - v.z * v.z,
            2.0 * (v.x * v.y + s * v.z),
            2.0 * (v.x * v.z - s * v.y),
        )
    }

    /// The vector part of p i q*; p i q* + q i p* = 2·vec(p i q*) (the scalar parts cancel).
    pub fn i_product_vec(self, q: Self) -> DVec3 {
        (self * Quaternion::new(0.0, 1.0, 0.0, 0.0) * q.conj()).v
    }
}

impl Add for Quaternion {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self {
            s: self.s + o.s,
            v: self.v + o.v,
        }
    }
}
impl Sub for Quaternion {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Self {
            s: self.s - o.s,
            v: self.v - o.v,
        }
    }
}
impl Neg for Quaternion {
    type Output = Self;
    fn neg(self) -> Self {
        Self {
            s: -self.s,
            v: -self.v,
        }
    }
}
impl Mul<f64> for Quaternion {
    type Output = Self;
    fn mul(self, k: f64) -> Self {
        Self {
            s: self.s * k,
            v: self.v * k,
        }
    }
}
impl Mul for Quaternion {
    type Output = Self;
    /// Hamilton product (a, u)(b, w) = (ab − u·w, a w + b u + u × w).
    fn mul(self, o: Self) -> Self {
        Self {
            s: self.s * o.s - self.v.dot(o.v),
            v: o.v * self.s + self.v * o.s + self.v.cross(o.v),
        }
    }
}

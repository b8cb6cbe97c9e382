//! Bézier foundations (seed 001; seed 000 §2.3).
//!
//! - [`bernstein`]: the Bernstein basis B^n_i(t) (seed 001 §1.4, seed 000 eq. 2.4).
//! - [`curve`]: polynomial Bézier curves of any degree: de Casteljau, derivatives (hodograph),
//!   degree elevation, subdivision, arc length (seed 001 §1.2–1.7, seed 000 eq. 2.3).
//! - [`composite`]: composite (piecewise) Bézier curves and their C^r / G1 joins (seed 001 §1.6).
//! - [`rational`]: rational (weighted) Bézier curves, exact circular arcs (seed 001 §3).
//! - [`surface`]: tensor-product Bézier surfaces, polynomial and rational, exact sphere
//!   (seed 001 §2.2–2.4).
//! - [`join`]: C^r and G1 joins of two tensor-product patches along a common boundary
//!   (seed 001 §2.4).
//!
//! Everything is generic over the control-point type through the small [`Point`] trait
//! (implemented for `f64`, `DVec2`, `DVec3`, `DVec4`); normals and curvatures are for `DVec3`.

pub mod bernstein;
pub mod composite;
pub mod curve;
pub mod join;
pub mod rational;
pub mod reduce;
pub mod surface;

use glam::{DVec2, DVec3, DVec4};
use std::fmt::Debug;
use std::ops::{Add, Mul, Neg, Sub};
use thiserror::Error;

pub use composite::CompositeCurve;
pub use curve::BezierCurve;
pub use rational::RationalCurve;
pub use surface::{BezierSurface, RationalSurface, SurfacePartials};

/// A control point / vector of an affine space over f64: what de Casteljau needs (affine
/// combinations) plus a dot product for lengths and angles.
pub trait Point:
    Copy
    + Debug
    + PartialEq
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<f64, Output = Self>
    + Neg<Output = Self>
{
    /// The zero vector.
    const ZERO: Self;
    /// Euclidean dot product.
    fn dot(self, other: Self) -> f64;
    /// True when every coordinate is finite.
    fn is_finite(self) -> bool;
    /// Euclidean length.
    fn norm(self) -> f64 {
        self.dot(self).sqrt()
    }
    /// Linear interpolation (1 − t)·self + t·other (seed 001 eq. 1.4).
    fn lerp_to(self, other: Self, t: f64) -> Self {
        self * (1.0 - t) + other * t
    }
}

macro_rules! impl_point {
    ($t:ty, $zero:expr) => {
        impl Point for $t {
            const ZERO: Self = $zero;
            fn dot(self, other: Self) -> f64 {
                <$t>::dot(self, other)
            }
            fn is_finite(self) -> bool {
                <$t>::is_finite(self)
            }
        }
    };
}
impl_point!(DVec2, DVec2::ZERO);
impl_point!(DVec3, DVec3::ZERO);
impl_point!(DVec4, DVec4::ZERO);

impl Point for f64 {
    const ZERO: Self = 0.0;
    fn dot(self, other: Self) -> f64 {
        self * other
    }
    fn is_finite(self) -> bool {
        f64::is_finite(self)
    }
}

/// Unsigned angle in [0, π] between two vectors, computed as 2·atan2(|â − b̂|, |â + b̂|), which is
/// accurate also for nearly parallel vectors (unlike acos of the dot product).
/// Returns NaN only when a vector is zero or not finite; callers check that first.
pub fn angle_between<P: Point>(a: P, b: P) -> f64 {
    let a = a * (1.0 / a.norm());
    let b = b * (1.0 / b.norm());
    2.0 * (a - b).norm().atan2((a + b).norm())
}

/// Errors of the Bézier layer; each names the offending element.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum BezierError {
    /// A curve or surface needs at least one control point.
    #[error("no control points given")]
    Empty,
    /// A control point has a NaN or infinite coordinate.
    #[error("control point {index} is not finite")]
    NonFinitePoint { index: usize },
    /// A surface control grid is not rectangular.
    #[error("control-grid row {row} has {len} points, expected {expected}")]
    RaggedRow {
        row: usize,
        len: usize,
        expected: usize,
    },
    /// The number of weights differs from the number of control points.
    #[error("{got} weights given for {expected} control points")]
    WeightCount { got: usize, expected: usize },
    /// A weight is not finite or not positive (seed 001 §3: weights are positive).
    #[error("weight {index} is {value}; weights must be finite and positive")]
    BadWeight { index: usize, value: f64 },
    /// A composite curve needs one more break value than segments.
    #[error("{breaks} break values given for {segments} segments (need segments + 1)")]
    BreakCount { breaks: usize, segments: usize },
    /// Break values must be finite and strictly increasing.
    #[error("break value {index} is not finite or not greater than the previous one")]
    BadBreak { index: usize },
    /// A joint index past the last joint of a composite curve.
    #[error("joint {joint} does not exist (the curve has {joints} joints)")]
    NoSuchJoint { joint: usize, joints: usize },
    /// All control points of a segment coincide, so it has no tangent direction.
    #[error("segment {segment} is a single point and has no tangent")]
    DegenerateTangent { segment: usize },
    /// The surface normal vanishes at a boundary sample of a patch join.
    #[error("normal of patch {patch} vanishes at boundary parameter v = {v}")]
    DegenerateNormal { patch: usize, v: f64 },
    /// A circular-arc sweep angle out of the allowed range.
    #[error("sweep angle {sweep} must lie in (0, π) for one quadratic arc")]
    BadSweep { sweep: f64 },
    /// A radius that is not finite and positive.
    #[error("radius {radius} must be finite and positive")]
    BadRadius { radius: f64 },
}

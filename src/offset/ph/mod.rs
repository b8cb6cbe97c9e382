//! Pythagorean-hodograph (PH) curves (seed 004 §1.5, §2; seed 003 §2): polynomial curves whose
//! parametric speed |r′| is a polynomial, so that arc length is polynomial and offsets are
//! exactly rational. The formulas used are written out in `docs/math/ph.md`.
//!
//! - [`complex`], [`quaternion`]: the small algebra types of the planar and spatial forms.
//! - [`planar`]: planar PH quintics r′ = w² (w a complex quadratic): Hermite interpolation with
//!   all four solutions, exact arc length and its inverse, curvature, rotation index, bending
//!   energy.
//! - [`offset`]: the exact degree-9 rational offset of a planar PH quintic and its cusps.
//! - [`spatial`]: spatial PH quintics r′ = A i A* (A a quaternion quadratic): Hermite
//!   interpolation with free angles, exact arc length, the Euler–Rodrigues frame.
//! - [`spline`]: segment-wise Hermite PH splines (planar, spatial) and C² planar PH quintic
//!   splines, open and closed, by Newton–Raphson.
//! - [`error`] holds [`PhError`].

pub mod complex;
pub mod error;
pub mod offset;
pub mod planar;
pub(crate) mod poly;
pub mod quaternion;
pub mod spatial;
pub mod spline;

pub use complex::Complex;
pub use error::PhError;
pub use offset::RationalOffset;
pub use planar::{CurvatureExtreme, HermiteSolution, HermiteSolutions, PlanarPhQuintic};
pub use quaternion::Quaternion;
pub use spatial::SpatialPhQuintic;
pub use spline::{OpenEnds, PlanarPhSpline, SpatialPhSpline};

//! Pythagorean-normal (PN) surfaces: C¹ interpolation of a grid of points with unit normals in
//! the isotropic model, G¹ in space, with exact rational points, normals and offsets
//! (seed 004 §4). Formulas and the corrections to the seed: `docs/math/pn.md`.
//!
//! Pipeline: points + normals ([`PnGrid`]) → dual (n, h = n·x) → isotropic images y
//! ([`isotropic`], in an [`IsotropicFrame`] that keeps normals off the pole) → derivative
//! vectors (estimated by [`estimate_derivatives`] or supplied by the caller) → one bicubic
//! Coons patch per grid cell ([`coons`]) → pull-back x = h n + N (NᵀN)⁻¹ ∇h
//! ([`PnSurface::eval`]) → offsets x + d·n and exact rational forms of degree (11, 11)
//! ([`PnSurface::rational`], [`PnSurface::rational_offset`]).
//!
//! ```
//! use gbsurf::offset::pn::{PnGrid, PnOptions, PnSurface};
//! use gbsurf::DVec3;
//! // A cap of the unit sphere, normals pointing outwards.
//! let dir = |i: usize, j: usize| DVec3::new(0.3 * i as f64 - 0.45, 0.25 * j as f64 - 0.25, -1.0).normalize();
//! let pts: Vec<Vec<DVec3>> = (0..4).map(|i| (0..3).map(|j| dir(i, j)).collect()).collect();
//! let grid = PnGrid::new(&pts, &pts).unwrap();
//! let s = PnSurface::interpolate(&grid, &PnOptions::default()).unwrap();
//! let p = s.eval(1, 1, 0.5, 0.5).unwrap();
//! assert!((p.offset(0.5) - p.point).length() - 0.5 < 1e-12);
//! ```

pub mod coons;
pub mod error;
pub mod grid;
pub mod isotropic;
pub mod rational;

pub use coons::CoonsPatch;
pub use error::PnError;
pub use grid::{
    estimate_derivatives, DerivativeGrids, FrameChoice, PnGrid, PnOptions, PnSample, PnSurface,
    Projection, TangentEstimate,
};
pub use isotropic::{Dual, IsotropicFrame};
pub use rational::PnRational;

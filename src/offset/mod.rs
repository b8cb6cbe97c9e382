//! Exact offsets (seeds 003/004): Pythagorean-hodograph (PH) curves, whose offsets are rational
//! curves ([`ph`], docs/math/ph.md), and Pythagorean-normal (PN) surfaces interpolating a grid of
//! points with normals, whose offsets are rational surfaces ([`pn`], docs/math/pn.md).

pub mod ph;
pub mod pn;

//! Exact offsets of curves (seeds 003/004): Pythagorean-hodograph (PH) curves.

pub mod ph;

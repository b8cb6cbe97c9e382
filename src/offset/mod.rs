//! Exact offsets: Pythagorean-normal (PN) surfaces (seed 004 §4).
pub mod pn;

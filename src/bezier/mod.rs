//! Bézier foundations (seed 001; seed 000 §2.3).

pub mod bernstein;

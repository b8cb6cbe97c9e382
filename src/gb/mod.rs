//! The n-sided Generalized Bézier patch (seed 000 §2.4–2.7, §3.4–3.6; seed 002).

pub mod patch;

pub mod connected;
pub mod gbp;

pub use patch::{CgbPatch, GbPatch, Ribbon, WeightForm};

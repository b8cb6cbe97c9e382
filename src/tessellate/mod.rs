//! Watertight tessellation of patch collections; output goes through sink builders.

pub mod patch;

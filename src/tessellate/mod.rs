//! Watertight tessellation of patch collections; output goes through sink builders.

pub mod patch;
pub mod surface;

pub use surface::{tessellate_surface_with, PatchEvaluator, SurfaceMesh, SurfacePoint, TessellateError, WeldStats};

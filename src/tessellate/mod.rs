//! Watertight tessellation of patch collections; output goes through sink builders.

pub mod patch;
pub mod surface;

pub use surface::{tessellate_surface, tessellate_surface_with, GbSurfaceEvaluator, PatchEvaluator, SurfaceMesh, SurfacePoint, TessellateError, WeldStats};

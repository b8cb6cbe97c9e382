//! Watertight tessellation of patch collections.
//!
//! - [`patch`]: one patch, its samples emitted through a mesh sink.
//! - [`surface`]: a whole surface, step by step: layouts, the welding map ([`weld`]), parallel
//!   evaluation into per-patch pieces of the output, the joins (module `measure`: welding of
//!   shared samples, boundary gaps, G1) and the normal fallback.
//! - [`fold`]: the fold rule on the samples the tessellation evaluates, and flipped triangles.
//! - [`cage_values`]: attributes of the control mesh carried to the output's face corners.
//! - [`evaluator`]: the patch evaluators and the weight tables they own ([`TableCache`]).

pub mod cage_values;
pub mod edges;
pub mod error;
pub mod evaluator;
pub mod fold;
mod measure;
pub mod patch;
pub mod surface;
pub mod weld;

pub use cage_values::{cage_loop_values, cage_loop_values_into, CageFaces, CageLoops, CageValuesError};
pub use edges::{mesh_edges, MeshEdges};
pub use error::TessellateError;
pub use evaluator::{GbSurfaceEvaluator, PatchEvaluator, SurfacePoint, TableCache};
pub use surface::{tessellate_surface, tessellate_surface_with, PatchLoops, SurfaceMesh, TessellationFolds, WeldStats};

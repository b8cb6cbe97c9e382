//! Quality measures: normals, curvature, G1 deviation, isophotes, slices, reports (seed 000 §5.2,
//! §4.2.2).
//!
//! - [`check`]: topology checks of output triangle meshes (closed, two-manifold, orientation,
//!   duplicate vertices, zero-area triangles), by the project's own code.
//! - [`curvature`]: discrete mean and Gaussian curvature (subdivision methods).
//! - [`display`]: isophotes (a per-vertex scalar for a light direction) and planar slices.
//! - [`report`]: the conversion report (serde JSON).
//! - [`certify`]: certificates of regions free of self-intersections (skipped by the search).
//! - [`validity`]: folds, self-intersections (output and input cage), |H| × diagonal.

pub mod certify;
pub mod check;
pub mod curvature;
pub mod display;
pub mod report;
pub mod validity;

pub use check::{check_mesh, check_mesh_ticked, MeshCheck};
pub use curvature::{discrete_curvature, discrete_curvature_ticked};
pub use display::{isophote, isophote_stripes, slice, slices, Polyline};
pub use report::Report;
pub use certify::Certified;
pub use validity::{cage_self_intersections, cage_self_intersections_ticked, find_folds, mesh_self_intersections, mesh_self_intersections_ticked, self_intersections, self_intersections_certified, FoldSite, Folds};

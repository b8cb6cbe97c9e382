//! # gbsurf
//!
//! Smooth, exact surfaces made of n-sided Generalized Bézier (GB) patches from polygon control
//! meshes, with tangent-plane (G1) continuity between patches, and exact offsets of curves and
//! surfaces (Pythagorean-hodograph curves, Pythagorean-normal surfaces).
//!
//! Layers, each depending only on the ones above it in this list (the order the README's layer
//! table gives; the compiler enforces layering between the workspace's crates):
//! - [`tol`]: the one shared tolerance and the `assert_near!` test helpers; [`limits`]: every
//!   bound on input sizes; [`input`]: bounded reading of input files.
//! - [`bezier`]: Bernstein basis, Bézier curves and tensor-product surfaces, rational forms (seed
//!   001), degree reduction and base + displacement (seed 002).
//! - [`gb`]: the n-sided domain, Wachspress coordinates, the GB patch and its ribbon-only (CGB)
//!   variant, degree elevation, common degree, decomposition, the `.gbp` format, per-(n, d, r)
//!   weight tables (seeds 000, 002).
//! - [`options`]: [`ConvertOptions`] and its enums, the one definition of the conversion options.
//! - [`offset`]: exact offsets: PH curves (planar, spatial, splines) and PN surfaces (seeds 003/004).
//! - [`mesh`]: polygon meshes, half-edge topology, validation and file reading.
//! - [`construct`]: control mesh → curve network → ribbons with twists → patches (seed 000 §2–4).
//! - [`subdiv`]: Doo–Sabin and Catmull–Clark subdivision, for comparison (seed 000 §6.4).
//! - [`tessellate`]: watertight sampling of all patches into one welded triangle mesh (plain
//!   arrays, which the writers and the adapters copy).
//! - [`quality`]: curvature, mesh checks, validity (folds, self-intersections), isophotes, slices,
//!   reports (seed 000 §5.2).
//! - [`export`]: every writer (OBJ, PLY, STL, JSON, `.gbp`) and the one atomic writer.
//! - [`api`]: the pipeline (read, validate, construct or subdivide, tessellate, check).
//!
//! The formulas, their seed sections and the seeds' corrections: `docs/math.md`.
//!
//! This crate has no `unsafe` code, no FFI and no command-line dependencies (the compiler enforces
//! the first: `forbid(unsafe_code)`). The other layers are crates of their own in this workspace:
//! `gbsurf-cli` (`cli/`, the `gbsurf` binary), `gbsurf-capi` (`capi/`, the C ABI `libgbsurf`) and
//! `gbsurf-openmesh` (`openmesh/`, the cxx bridge to OpenMesh).

#![forbid(unsafe_code)]

#[macro_use]
pub mod tol;

pub mod api;
pub mod bezier;
pub mod construct;
pub mod export;
pub mod gb;
pub mod input;
pub mod limits;
pub mod mesh;
pub mod offset;
pub mod options;
pub mod progress;
pub mod quality;
pub mod subdiv;
pub mod tessellate;

pub use api::{convert, convert_file, read_mesh, Conversion, ConvertError};
pub use options::{ConvertOptions, Method, Middle, Twist};
pub use glam::{DVec2, DVec3};

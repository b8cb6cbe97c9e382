//! # gbsurf
//!
//! Smooth, exact surfaces made of n-sided Generalized Bézier (GB) patches from polygon control
//! meshes, with tangent-plane (G1) continuity between patches. (Exact offsets of curves and
//! surfaces, PH curves and PN surfaces of seeds 003/004, are planned as a later module.)
//!
//! Layers, each depending only on the ones above it in this list:
//! - [`tol`]: the one shared tolerance and the `assert_near!` test helpers.
//! - [`bezier`]: Bernstein basis, Bézier curves and tensor-product surfaces, rational forms (seed 001).
//! - [`gb`]: the n-sided domain, Wachspress coordinates, the GB patch and its ribbon-only (CGB)
//!   variant, degree elevation, the `.gbp` format, per-(n, d, r) weight tables (seeds 000, 002).
//! - [`mesh`]: polygon meshes, half-edge topology, validation and file I/O.
//! - [`construct`]: control mesh → curve network → ribbons with twists → patches (seed 000 §2–4).
//! - [`subdiv`]: Doo–Sabin and Catmull–Clark subdivision, for comparison (seed 000 §6.4).
//! - [`tessellate`]: watertight sampling of all patches into triangle meshes through sinks.
//! - [`quality`]: normals, curvature, G1 deviation, isophotes, slices, reports (seed 000 §5.2).
//! - [`ffi`]: the C ABI, the only module with `unsafe`.
//! - `openmesh` (cargo feature `openmesh`, in [`ffi`] because the cxx bridge declares `unsafe extern`):
//!   OpenMesh file I/O and its Catmull–Clark, re-exported here as `gbsurf::openmesh`.

#![deny(unsafe_code)]

#[macro_use]
pub mod tol;

pub mod api;
pub mod bezier;
pub mod construct;
#[allow(unsafe_code)]
pub mod ffi;
pub mod gb;
pub mod mesh;
pub mod offset;
#[cfg(feature = "openmesh")]
pub use ffi::openmesh;
pub mod quality;
pub mod subdiv;
pub mod tessellate;

pub use api::{convert, convert_file, read_mesh, Conversion, ConvertError, ConvertOptions, Method, Twist};
pub use glam::{DVec2, DVec3};

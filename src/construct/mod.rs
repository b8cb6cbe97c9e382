//! Surface construction from a control mesh (seed 000 §2–4): curve network, ribbons, twists, patches.
//!
//! - [`network`]: the structure-agnostic [`CurveNetwork`] and [`assemble`] (corner blocks, twists).
//! - [`blend`]: direction blends for G1 twists (seed 000 §4.3–4.4).
//! - [`centre`]: the central point of a GB patch (every side count but 4) fitted to its boundary.
//! - [`fair`]: the fair middle constraint D_{0.5} ([`crate::options::Middle::Fair`]).
//! - [`check`]: G1 / gap measurements along shared sides.
//! - [`prepare`]: interior valence-2 vertices dissolved, concave faces split (both structures).

pub mod blend;
pub mod centre;
pub mod check;
pub mod derived;
pub mod dual;
pub mod dual_crease;
pub mod fair;
pub mod network;
pub mod prepare;
pub mod surface;
pub mod topology;

pub use blend::{BlendKind, DirectionBlend};
pub use derived::ControlNet;
pub use dual::{build_dual, build_dual_ticked, dual_network};
pub use network::{assemble, assemble_ticked, CurveNetwork, PatchLayout, SideUse};
pub use prepare::{dissolve_valence2, prepare, Prepared};
pub use surface::{CageSector, Diagonals, Patch, PatchSource, SectorMap, SideRef, Surface};
pub use topology::{build_topology, build_topology_ticked, tiles, topology_network, Tiles};

use crate::options::ConvertOptions;

/// The twist construction, defined with the other options in [`crate::options`].
pub use crate::options::Twist as TwistMode;

/// Checks the options the constructions read (fullness, tile depth, mid-scale and the rest of
/// [`ConvertOptions::validate`]).
fn check_options(opts: &ConvertOptions) -> Result<(), ConstructError> {
    opts.validate().map_err(|e| ConstructError::InvalidOption(e.to_string()))
}

/// Errors of the construction; each names the offending element.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum ConstructError {
    #[error("invalid option: {0}")]
    InvalidOption(String),
    #[error("patch {patch} would have {sides} sides (at least 3 needed)")]
    TooFewSides { patch: usize, sides: usize },
    #[error("curve {curve} is used by {uses} patch sides (at most 2)")]
    NonManifoldCurve { curve: usize, uses: usize },
    #[error("curve {curve} is traversed in the same direction by patches {patches:?} (inconsistent orientation)")]
    InconsistentOrientation { curve: usize, patches: [usize; 2] },
    #[error("degenerate corner at end {end} of curve {curve}: cross-derivative parallel to the curve tangent")]
    DegenerateCorner { curve: usize, end: usize },
    #[error("the curve network folds at node {node} (end {end} of curve {curve}): the neighbouring patches' cross-derivatives lie on the same side of the curve, so no G1 join without a flipped normal exists")]
    FoldedCorner { curve: usize, end: usize, node: usize },
    #[error("tile of vertex {vertex} folds: no plane orders its curve tangents around the tile centre")]
    FoldedTile { vertex: usize },
    #[error("face {face} is degenerate (zero area or coincident vertices)")]
    DegenerateFace { face: usize },
    #[error("interior vertex {vertex} of valence 2 cannot be dissolved from face {face}: {reason}")]
    Valence2 { vertex: usize, face: usize, reason: String },
    #[error("tile of vertex {vertex} is degenerate")]
    DegenerateTile { vertex: usize },
    #[error("non-finite control point in patch {patch}, side {side}")]
    NonFinite { patch: usize, side: usize },
    #[error("mesh after splitting concave faces: {0}")]
    Mesh(#[from] crate::mesh::MeshError),
    #[error("internal inconsistency: {0}")]
    Internal(String),
    /// The progress callback asked to stop ([`crate::progress`]).
    #[error("cancelled")]
    Cancelled,
}

impl From<crate::progress::Cancelled> for ConstructError {
    fn from(_: crate::progress::Cancelled) -> Self {
        ConstructError::Cancelled
    }
}

/// The mesh the constructions work on: `mesh` itself when every face is convex in its best-fit
/// plane, otherwise the result of the mesh layer's deterministic
/// [`convexify`](crate::mesh::geometry::convexify) (seed 000 §2.2 splits concave faces by hand).
/// Returns the mesh and, for each of its faces, the index of the input face it came from.
/// Diagonals join existing vertices, so vertex indices are unchanged.
pub fn convex_mesh(
    mesh: &crate::mesh::HalfEdgeMesh,
) -> Result<(std::borrow::Cow<'_, crate::mesh::HalfEdgeMesh>, Vec<usize>), ConstructError> {
    use crate::mesh::geometry::{convexify, is_convex_polygon_with};
    // One corner buffer and one projection buffer for all faces.
    let (mut pts, mut scratch) = (Vec::new(), Vec::new());
    let all_convex = mesh.faces().all(|f| {
        pts.clear();
        pts.extend(mesh.face_vertices(f).map(|v| mesh.position(v)));
        pts.len() == 3 || is_convex_polygon_with(&pts, &mut scratch)
    });
    if all_convex {
        return Ok((std::borrow::Cow::Borrowed(mesh), (0..mesh.n_faces()).collect()));
    }
    let (poly, origin) = convexify(&mesh.to_polymesh());
    let split = crate::mesh::HalfEdgeMesh::from_polymesh(&poly)?;
    if split.n_vertices() != mesh.n_vertices() {
        return Err(ConstructError::Internal("convexify changed the vertex set".into()));
    }
    Ok((std::borrow::Cow::Owned(split), origin.into_iter().map(|f| f as usize).collect()))
}

//! Surface construction from a control mesh (seed 000 §2–4): curve network, ribbons, twists, patches.
//!
//! - [`network`]: the structure-agnostic [`CurveNetwork`] and [`assemble`] (corner blocks, twists).
//! - [`blend`]: direction blends for G1 twists (seed 000 §4.3–4.4).
//! - [`check`]: G1 / gap measurements along shared sides.
//! - [`prepare`]: interior valence-2 vertices dissolved, concave faces split (both structures).

pub mod blend;
pub mod check;
pub mod derived;
pub mod dual;
pub mod network;
pub mod prepare;
pub mod surface;
pub mod topology;

pub use blend::{BlendKind, DirectionBlend};
pub use derived::ControlNet;
pub use dual::{build_dual, dual_network};
pub use network::{assemble, CurveNetwork, PatchLayout, SideUse};
pub use prepare::{dissolve_valence2, prepare, Prepared};
pub use surface::{Patch, PatchSource, SideRef, Surface};
pub use topology::{build_topology, tiles, topology_network, Tiles};

/// How the twist control points (row 1, columns 1 and 2 of each ribbon) are set (seed 000 §4).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TwistMode {
    /// First approximation: convex combination of seed 000 eq. 2.11 (dual) or the tile vertex
    /// (§3.4.1). G1 only where four-sided faces meet four-sided patches; reported, not guaranteed.
    None,
    /// Approximating direction blend (eq. 4.16): G1 along every shared side.
    Approx,
    /// Interpolating direction blend (eq. 4.24): G1 along every shared side.
    #[default]
    Interp,
}

impl TwistMode {
    /// `none`, `approx`, `interp`.
    pub fn name(self) -> &'static str {
        match self {
            TwistMode::None => "none",
            TwistMode::Approx => "approx",
            TwistMode::Interp => "interp",
        }
    }
}

/// Parameters of both constructions.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ConstructOptions {
    /// Fullness κ ∈ [0, 1) of the dual curves: C1 = κ C0 + (1−κ) F (seed 000 eq. 2.2). Default ⅓,
    /// the value of the seed's figures; it gives uniform curves (linear precision) on regular grids.
    pub fullness: f64,
    /// Twist construction.
    pub twist: TwistMode,
    /// Factor on the middle constraint D_{0.5} of the direction blends (seed 000 §4.4.5). Default 1.
    pub mid_scale: f64,
    /// Project onto best-fit planes (seed 000 §3.3.2): dual – the edge midpoints of each face onto
    /// the face's plane; topology – the tile vertices onto the tile's plane. Default true.
    pub best_plane: bool,
    /// Tile split ratio w > 2: tiles cut at |e|/w from each vertex (seed 000 §3.3.1). Default 3
    /// (uniform curves on regular grids). Topology-preserving structure only.
    pub tile_depth: f64,
}

impl Default for ConstructOptions {
    fn default() -> Self {
        Self { fullness: 1.0 / 3.0, twist: TwistMode::Interp, mid_scale: 1.0, best_plane: true, tile_depth: 3.0 }
    }
}

impl ConstructOptions {
    /// Checks the ranges: 0 ≤ κ < 1, w > 2 finite, mid_scale finite.
    pub fn validate(&self) -> Result<(), ConstructError> {
        if !(self.fullness >= 0.0 && self.fullness < 1.0) {
            return Err(ConstructError::InvalidOption(format!("fullness κ = {} not in [0, 1)", self.fullness)));
        }
        if !(self.tile_depth > 2.0 && self.tile_depth.is_finite()) {
            return Err(ConstructError::InvalidOption(format!("tile depth w = {} must be > 2", self.tile_depth)));
        }
        if !self.mid_scale.is_finite() {
            return Err(ConstructError::InvalidOption(format!("mid_scale = {} not finite", self.mid_scale)));
        }
        Ok(())
    }
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
}

/// The mesh the constructions work on: `mesh` itself when every face is convex in its best-fit
/// plane, otherwise the result of the mesh layer's deterministic
/// [`convexify`](crate::mesh::geometry::convexify) (seed 000 §2.2 splits concave faces by hand).
/// Returns the mesh and, for each of its faces, the index of the input face it came from.
/// Diagonals join existing vertices, so vertex indices are unchanged.
pub fn convex_mesh(
    mesh: &crate::mesh::HalfEdgeMesh,
) -> Result<(std::borrow::Cow<'_, crate::mesh::HalfEdgeMesh>, Vec<usize>), ConstructError> {
    use crate::mesh::geometry::{convexify, is_convex_polygon};
    let all_convex = mesh.faces().all(|f| {
        let pts: Vec<glam::DVec3> = mesh.face_vertices(f).map(|v| mesh.position(v)).collect();
        pts.len() == 3 || is_convex_polygon(&pts)
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

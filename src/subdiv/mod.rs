//! Doo–Sabin and Catmull–Clark subdivision, the comparison methods of seed 000 §6.4
//! (described in seed 000 §1.2.1.1–1.2.1.2), on the mesh layer's [`HalfEdgeMesh`].
//!
//! [`subdivide`] is the entry point: it takes a [`PolyMesh`] (validated with
//! [`HalfEdgeMesh::from_polymesh`], the one mesh validator) or an already built [`HalfEdgeMesh`],
//! and returns the subdivided mesh with the face ancestry (for every output face, the input face
//! it descends from). Both schemes take any face sizes (triangles, quads, n-gons, mixed) and open
//! meshes; the boundary rules are documented on [`catmull_clark`] and [`doo_sabin`]. Nothing
//! panics on bad input.
//!
//! Note on seed 000 eq. 1.1 (`v' = 1/n² Σf + 2/n² Σe + (n−3)/n v`): it is the textbook
//! Catmull–Clark vertex rule only when `e` are the edge *midpoints*. With the new edge points
//! (which the seed's text suggests) the cube corner would move to ±4/9 instead of ±5/9; we use
//! midpoints, as Catmull and Clark (1978) and OpenMesh do.

mod catmull_clark;
mod doo_sabin;

pub use doo_sabin::doo_sabin_weights;

use crate::mesh::{EdgeId, FaceId, HalfEdgeMesh, HalfedgeId, MeshError, PolyMesh, VertexId};
use crate::progress::Ticker;
use glam::DVec3;
use std::borrow::Cow;

/// The subdivision schemes available for comparison with GB surfaces.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SubdivisionScheme {
    /// Catmull–Clark (primal, quads after one level; seed 000 §1.2.1.2).
    CatmullClark,
    /// Doo–Sabin (dual, corner cutting; seed 000 §1.2.1.1).
    DooSabin,
}

/// The control mesh given to [`subdivide`].
#[derive(Clone, Copy, Debug)]
pub enum ControlMesh<'a> {
    /// A face list, validated first. Its vertex numbering is kept: Catmull–Clark keeps unused
    /// vertices unchanged at their indices, Doo–Sabin drops them.
    Poly(&'a PolyMesh),
    /// A half-edge mesh (valid by construction), in its own vertex numbering.
    HalfEdge(&'a HalfEdgeMesh),
}

impl<'a> From<&'a PolyMesh> for ControlMesh<'a> {
    fn from(mesh: &'a PolyMesh) -> Self {
        ControlMesh::Poly(mesh)
    }
}

impl<'a> From<&'a HalfEdgeMesh> for ControlMesh<'a> {
    fn from(mesh: &'a HalfEdgeMesh) -> Self {
        ControlMesh::HalfEdge(mesh)
    }
}

/// A subdivided mesh with its face ancestry.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Subdivided {
    /// The mesh after the requested levels (vertex and face order documented on each scheme).
    pub mesh: PolyMesh,
    /// For every face of `mesh`, the input face it descends from (as the user wrote it: the
    /// pieces of a face with holes descend from that face). Catmull–Clark: the children
    /// of a face are consecutive, one per corner. Doo–Sabin: every new point belongs to one
    /// corner of an old face, and a new face descends from the face of its first such point.
    pub face_ancestor: Vec<u32>,
}

/// Why a mesh cannot be subdivided. Every variant names the offending element.
///
/// Besides the mesh validator's errors only two cases remain, both specific to subdivision
/// (the mesh layer accepts such meshes for every other method): a vertex that Doo–Sabin cannot
/// cut, and an output too large for u32 indices.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SubdivError {
    /// The input mesh was rejected by the mesh validator.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// Doo–Sabin would make a two-sided face around an interior vertex of valence 2.
    #[error(
        "vertex {vertex} is an interior vertex of valence 2; Doo–Sabin would make a two-sided face"
    )]
    InteriorValenceTwo { vertex: usize },
    /// The output would need more indices than u32 can address.
    #[error("the subdivided mesh would need {count} indices, more than u32 can address")]
    TooLarge { count: u64 },
    /// The progress callback asked to stop ([`crate::progress`]).
    #[error("cancelled")]
    Cancelled,
}

impl From<crate::progress::Cancelled> for SubdivError {
    fn from(_: crate::progress::Cancelled) -> Self {
        SubdivError::Cancelled
    }
}

/// Subdivides `mesh` `levels` times with `scheme` and tracks the face ancestry.
/// `levels == 0` validates and returns a copy (for a [`HalfEdgeMesh`], its face lists) with the
/// identity ancestry.
pub fn subdivide<'a>(
    mesh: impl Into<ControlMesh<'a>>,
    scheme: SubdivisionScheme,
    levels: u32,
) -> Result<Subdivided, SubdivError> {
    subdivide_ticked(mesh, scheme, levels, &mut Ticker::none())
}

/// [`subdivide`] reporting progress to `ticker` (its current range split over the levels by
/// their sizes, each level ticking per face, edge and vertex; see [`crate::progress`]).
pub fn subdivide_ticked<'a>(
    mesh: impl Into<ControlMesh<'a>>,
    scheme: SubdivisionScheme,
    levels: u32,
    ticker: &mut Ticker<'_>,
) -> Result<Subdivided, SubdivError> {
    let level = match mesh.into() {
        ControlMesh::Poly(m) => {
            let he = HalfEdgeMesh::from_polymesh(m)?;
            if levels == 0 {
                return Ok(Subdivided::unchanged(m.clone()));
            }
            Level::of_polymesh(m, Cow::Owned(he))
        }
        ControlMesh::HalfEdge(he) => {
            if levels == 0 {
                return Ok(Subdivided::unchanged(he.to_polymesh()));
            }
            Level {
                positions: he.positions(),
                index: (0..he.n_vertices() as u32).collect(),
                he: Cow::Borrowed(he),
            }
        }
    };
    subdivide_levels(level, scheme, levels, ticker)
}

impl Subdivided {
    /// `mesh` itself, each face its own ancestor.
    fn unchanged(mesh: PolyMesh) -> Self {
        let face_ancestor = (0..mesh.faces.len() as u32).collect();
        Subdivided {
            mesh,
            face_ancestor,
        }
    }
}

/// Catmull–Clark subdivision, `levels` times: [`subdivide`] without the ancestry. The rules:
///
/// One level, with `n` the valence of vertex `V`:
/// - face point `F` = centroid of the face's vertices;
/// - interior edge point = `(a + b + F₀ + F₁)/4`; boundary edge point = midpoint `(a + b)/2`;
/// - interior vertex: `V' = (Q + 2R + (n−3)V)/n`, `Q` = mean of the adjacent face points,
///   `R` = mean of the adjacent edge *midpoints* (seed 000 eq. 1.1 read with midpoints);
/// - boundary vertex with boundary neighbours `a`, `b`: `V' = (a + 6V + b)/8` (cubic B-spline);
/// - corner (boundary vertex in a single face, valence 2): `V' = V`;
/// - unused vertices are kept unchanged.
///
/// Each face of size k becomes k quads `[V', E'(i), F, E'(i−1)]` (eq. 1.2), with the original
/// orientation. Output vertex order: vertex points (same indices as the input), then edge points
/// (edges by first appearance in the face list), then face points (face order).
/// Counts: `V' = V + E + F`, `F' = Σ|f|`, `E' = 2E + Σ|f|`.
pub fn catmull_clark<'a>(
    mesh: impl Into<ControlMesh<'a>>,
    levels: u32,
) -> Result<PolyMesh, SubdivError> {
    subdivide(mesh, SubdivisionScheme::CatmullClark, levels).map(|s| s.mesh)
}

/// Doo–Sabin subdivision, `levels` times: [`subdivide`] without the ancestry. Original Doo–Sabin
/// weights, Chaikin boundary rule for open meshes.
///
/// One level: every corner `i` of an n-sided face gets the new point `Σ_j α_{(j−i) mod n} v_j`
/// ([`doo_sabin_weights`]). New faces, all oriented like the input:
/// - F-face: per face, its n new corner points;
/// - E-face: per interior edge, the quad of the four new points at its ends;
/// - V-face: per interior vertex of valence k, the k new points around it.
///
/// Open meshes (our choice; the seeds leave it open): the new boundary is Chaikin's corner
/// cutting of the old boundary polygon, so the limit boundary is the quadratic B-spline of the
/// boundary polygon. Each boundary edge `a → b` gets two new points `3/4·a + 1/4·b` and
/// `1/4·a + 3/4·b` and a quad joining them to the two new points of its face at `a` and `b`;
/// each boundary vertex with k faces gets a (k+2)-gon: the Chaikin point on its outgoing
/// boundary edge, its k new face points in counter-clockwise order, and the Chaikin point on its
/// incoming boundary edge (a triangle at a corner of a single face, which is cut off like every
/// other boundary vertex). Unused vertices disappear. An interior vertex of valence 2 is an
/// error ([`SubdivError::InteriorValenceTwo`]).
///
/// Output vertex order: new corner points (faces in order, corners in order), then the two
/// Chaikin points of each boundary edge. Face order: F-faces, E-faces, boundary-edge quads,
/// V-faces (vertex order, interior and boundary).
/// Counts on a closed mesh: `V' = Σ|f| = 2E`, `E' = 4E`, `F' = F + E + V`.
pub fn doo_sabin<'a>(
    mesh: impl Into<ControlMesh<'a>>,
    levels: u32,
) -> Result<PolyMesh, SubdivError> {
    subdivide(mesh, SubdivisionScheme::DooSabin, levels).map(|s| s.mesh)
}

/// One subdivision level's input: the half-edge mesh, the positions in the level's own vertex
/// numbering (which may hold unused vertices) and, per half-edge-mesh vertex, its index there.
struct Level<'a> {
    he: Cow<'a, HalfEdgeMesh>,
    positions: &'a [DVec3],
    index: Vec<u32>,
}

impl<'a> Level<'a> {
    fn of_polymesh(mesh: &'a PolyMesh, he: Cow<'a, HalfEdgeMesh>) -> Self {
        Level {
            positions: &mesh.positions,
            index: he.original_vertices().to_vec(),
            he,
        }
    }
}

/// The output of one level: the mesh and, per output face, its parent face in the level's input.
type LevelOutput = (PolyMesh, Vec<u32>);

/// `levels ≥ 1` levels from `first`; every level after the first is built from the previous
/// output, whose topology is valid by construction.
fn subdivide_levels(
    first: Level<'_>,
    scheme: SubdivisionScheme,
    levels: u32,
    ticker: &mut Ticker<'_>,
) -> Result<Subdivided, SubdivError> {
    let one = |level: &Level<'_>, t: &mut Ticker<'_>| match scheme {
        SubdivisionScheme::CatmullClark => catmull_clark::level(level, t),
        SubdivisionScheme::DooSabin => doo_sabin::level(level, t),
    };
    // Level k costs about 4^k times the first (faces and corners grow fourfold per level): its
    // share of the range is 4^k / Σ 4^j. Within a level the half-edge mesh of its input takes
    // HALF_EDGE of the share (measured), the level itself the rest.
    let total: f32 = (0..levels).map(|k| 4f32.powi(k as i32)).sum();
    let share = |k: u32| (4f32.powi(k as i32) - 1.0) / 3.0 / total;
    let (mut mesh, parent) = ticker.within(0.0, share(1), |t| one(&first, t))?;
    // The input face as the user wrote it (a face with holes is split into pieces first).
    let mut ancestor: Vec<u32> = parent.iter().map(|&f| first.he.input_face(FaceId(f)) as u32).collect();
    for k in 1..levels {
        let (next, parent) = ticker.within(share(k), share(k + 1), |t| {
            let he = t.within(0.0, HALF_EDGE, |t| {
                HalfEdgeMesh::from_checked_polymesh_ticked::<SubdivError>(&mesh, &mut |done, total| Ok(t.at(done, total)?))
            })?;
            t.within(HALF_EDGE, 1.0, |t| one(&Level::of_polymesh(&mesh, Cow::Owned(he)), t))
        })?;
        ancestor = parent.iter().map(|&f| ancestor[f as usize]).collect();
        mesh = next;
    }
    Ok(Subdivided {
        mesh,
        face_ancestor: ancestor,
    })
}

/// The half-edge mesh's share of a level after the first in [`subdivide_levels`].
const HALF_EDGE: f32 = 0.3;

/// Errors with [`SubdivError::TooLarge`] when `count` does not fit a u32 index.
fn check_size(count: u64) -> Result<(), SubdivError> {
    if count >= u32::MAX as u64 {
        Err(SubdivError::TooLarge { count })
    } else {
        Ok(())
    }
}

/// Corner numbering of a face list: corner `c` is the `i`-th corner of face `f` when
/// `c = Σ_{g<f} |g| + i`, corners in order from the face's first corner.
struct Corners {
    /// Corner of each half-edge's origin in its face (`u32::MAX` on a boundary half-edge).
    of_halfedge: Vec<u32>,
    /// Per vertex, its outgoing half-edge at its first corner (the smallest corner index).
    first: Vec<HalfedgeId>,
    /// Number of corners.
    count: usize,
}

impl Corners {
    fn new(he: &HalfEdgeMesh) -> Self {
        let mut of_halfedge = vec![u32::MAX; he.n_halfedges()];
        let mut first = vec![HalfedgeId(u32::MAX); he.n_vertices()];
        let mut count = 0u32;
        for f in he.faces() {
            for h in he.face_halfedges(f) {
                of_halfedge[h.idx()] = count;
                count += 1;
                let slot = &mut first[he.origin(h).idx()];
                if slot.0 == u32::MAX {
                    *slot = h;
                }
            }
        }
        Corners {
            of_halfedge,
            first,
            count: count as usize,
        }
    }

    fn of(&self, h: HalfedgeId) -> u32 {
        self.of_halfedge[h.idx()]
    }

    /// The outgoing half-edges of `v` that have a face, counter-clockwise: for a boundary
    /// vertex from the one after its incoming boundary edge to the one before its outgoing
    /// boundary edge; for an interior vertex from its first corner.
    fn fan(&self, he: &HalfEdgeMesh, v: VertexId) -> Vec<HalfedgeId> {
        if he.is_boundary_vertex(v) {
            return he
                .vertex_outgoing(v)
                .filter(|&h| !he.is_boundary_halfedge(h))
                .collect();
        }
        let start = self.first[v.idx()];
        let mut fan = vec![start];
        let mut h = he.ccw_rotated(start);
        while h != start {
            fan.push(h);
            h = he.ccw_rotated(h);
        }
        fan
    }
}

/// The half-edge of `e` in the face that comes first in face order (the edge's direction at its
/// first appearance); the face's half-edge on a boundary edge.
fn first_halfedge(he: &HalfEdgeMesh, e: EdgeId) -> HalfedgeId {
    let (h0, h1) = (he.edge_halfedge(e, 0), he.edge_halfedge(e, 1));
    match (he.face(h0), he.face(h1)) {
        (Some(f0), Some(f1)) => {
            if f0 < f1 {
                h0
            } else {
                h1
            }
        }
        (Some(_), None) => h0,
        _ => h1,
    }
}

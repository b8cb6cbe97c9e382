//! The output size guard: an upper bound of a conversion's output vertex count and peak memory,
//! computed from the control mesh alone, before any work.
//!
//! Peak memory per output vertex, measured (peak RSS of `gbsurf convert` by `/usr/bin/time -v`,
//! torus.obj of 96 quads, OBJ output; every figure includes the output mesh arrays (positions,
//! normals, curvatures, G1, patch indices, triangles), the evaluation buffers, the welding maps,
//! the validity checks' BVH and the writer):
//!
//! | method | output vertices | peak RSS | bytes per vertex (marginal) |
//! |---|---|---|---|
//! | dual, r = 16 / 48 | 49 152 / 442 368 | 53.3 / 404.7 MiB | 937 |
//! | topology, r = 16 / 48 | 49 152 / 442 368 | 53.4 / 404.6 MiB | 937 |
//! | catmull-clark, levels 4 / 5 / 6 | 24 576 / 98 304 / 393 216 | 31.4 / 100.1 / 374.5 MiB | 978 |
//! | doo-sabin, levels 4 / 5 / 6 | 24 576 / 98 304 / 393 216 | 32.2 / 102.5 / 383.6 MiB | 1000 |
//!
//! (Output triangles are twice the vertices in all of them, so a figure per vertex includes two
//! triangles: of the ~950 bytes, 76 are the vertex's output arrays and 2 × 16 its triangles'.)
//! The estimate is [`BASE_BYTES`] plus [`GB_BYTES_PER_SAMPLE`] per tessellation sample (before
//! welding: an n-sided patch at resolution r has 1 + n·r(r+1)/2, or 1 + n·r(r+1) in the quad
//! layout, whose per-sample arrays are the same plus one quad (16 bytes) and one face corner) or [`SUBDIV_BYTES_PER_VERTEX`]
//! per subdivided vertex, 10–25 % above every measurement (largest total: 1023 bytes per vertex
//! for doo-sabin levels 6, estimated 1196).

use crate::mesh::HalfEdgeMesh;
use crate::options::{ConvertOptions, Method};

/// Memory of a conversion besides its output (program, input, construction), bytes.
pub const BASE_BYTES: u64 = 16 << 20;
/// Peak bytes per tessellation sample of the GB methods (measured ≤ 940, see the module doc).
pub const GB_BYTES_PER_SAMPLE: u64 = 1024;
/// Peak bytes per output vertex of the subdivision methods (measured ≤ 1000).
pub const SUBDIV_BYTES_PER_VERTEX: u64 = 1152;

/// An upper bound of a conversion's output, from [`estimate_output`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OutputEstimate {
    /// Output vertices (GB methods: tessellation samples before welding; subdivision: exact for
    /// closed meshes, an upper bound with boundary).
    pub vertices: u64,
    /// Peak memory of the conversion, bytes.
    pub bytes: u64,
}

/// The output size and peak memory of converting `mesh` with `options` (see the module doc for
/// the figures). Saturates instead of overflowing.
///
/// Patch sides: dual – one patch per vertex with one side per edge, plus one at a boundary
/// vertex; topology – one patch per face with one side per face side (concave faces, split into
/// convex pieces by the construction, get two more sides per cut: rare, and within the margin).
pub fn estimate_output(mesh: &HalfEdgeMesh, options: &ConvertOptions) -> OutputEstimate {
    let sat = |x: u128| u64::try_from(x).unwrap_or(u64::MAX);
    let sampling = options.sampling();
    // A patch of more than MAX_UNSPLIT_SIDES sides becomes n three-sided patches.
    let samples = |n: usize| {
        if n > crate::limits::MAX_UNSPLIT_SIDES {
            n as u128 * sampling.sample_count(3) as u128
        } else {
            sampling.sample_count(n) as u128
        }
    };
    let vertices: u128 = match options.method {
        Method::Dual => (0..mesh.n_vertices())
            .map(|v| {
                let v = crate::mesh::halfedge::VertexId::from(v);
                samples(mesh.valence(v) + mesh.is_boundary_vertex(v) as usize)
            })
            .sum(),
        Method::Topology => (0..mesh.n_faces()).map(|f| samples(mesh.face_size(crate::mesh::halfedge::FaceId::from(f)))).sum(),
        Method::CatmullClark | Method::DooSabin => subdivided_vertices(mesh, options.method, options.levels),
    };
    let per = if options.method.is_patch_method() { GB_BYTES_PER_SAMPLE } else { SUBDIV_BYTES_PER_VERTEX };
    OutputEstimate { vertices: sat(vertices), bytes: sat((BASE_BYTES as u128).saturating_add(vertices.saturating_mul(per as u128))) }
}

/// Vertices after `levels` steps of Catmull–Clark (exact: V' = V + E + F, E' = 2E + H, F' = H,
/// H' = 4H with H the face corners) or Doo–Sabin (V' = H + 2B with B the boundary edges,
/// H' ≤ 4V' since every new vertex is in at most four faces, B' = 2B; exact when closed).
fn subdivided_vertices(mesh: &HalfEdgeMesh, method: Method, levels: u32) -> u128 {
    let corners: u128 = (0..mesh.n_faces()).map(|f| mesh.face_size(crate::mesh::halfedge::FaceId::from(f)) as u128).sum();
    let (mut v, mut e, mut f, mut h) = (mesh.n_vertices() as u128, mesh.n_edges() as u128, mesh.n_faces() as u128, corners);
    let mut b = (0..mesh.n_edges()).filter(|&e| mesh.is_boundary_edge(crate::mesh::halfedge::EdgeId::from(e))).count() as u128;
    for _ in 0..levels {
        if method == Method::CatmullClark {
            (v, e, f, h) = (v + e + f, 2 * e + h, h, 4 * h);
        } else {
            v = h + 2 * b;
            h = 4 * v;
        }
        b *= 2;
    }
    let _ = (e, f);
    v
}

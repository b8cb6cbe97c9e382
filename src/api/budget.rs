//! The output size guard: an upper bound of a conversion's output vertex count and peak memory,
//! computed from the control mesh alone, before any work.
//!
//! Peak memory, measured (peak RSS of `gbsurf convert` by `/usr/bin/time`, release build; every
//! figure includes the output mesh arrays, the evaluation buffers, the welding maps, the validity
//! checks (with the self-intersection BVH: tori are not star-shaped, so no shell certificate
//! skips it) and the writer). Marginal bytes between two resolutions of torus.obj (96 quads, OBJ
//! output), and the whole run of a 120k-triangle binary STL torus (PLY output):
//!
//! | method | case | bytes per sample | bytes per output vertex |
//! |---|---|---|---|
//! | dual, quads | torus.obj r = 32 → 64 | 293 | 296 |
//! | dual, triangles | torus.obj r = 32 → 64 | 225 | 450 |
//! | dual, triangles, with per-loop cage coordinates and corners | torus.obj r = 32 → 64 | 373 | 746 |
//! | topology, quads | torus.obj r = 32 → 64 | 293 | 296 |
//! | dual, quads r = 2 | STL torus, 1.44 M vertices, 681 MiB | 314 | 484 |
//! | topology, quads r = 2 | STL torus, 1.44 M vertices, 716 MiB | 336 | 521 |
//! | catmull-clark | torus.obj levels 5 → 6 | — | 563 |
//! | doo-sabin | torus.obj levels 5 → 6 | — | 570 |
//!
//! (Samples are counted before welding: an n-sided patch at resolution r has 1 + n·r(r+1)/2 in
//! the triangle layout, 1 + n·r(r+1) in the quad layout; a patch of more than
//! [`crate::limits::MAX_UNSPLIT_SIDES`] sides counts as n three-sided parts.)
//! The triangle layout's per-loop cage coordinates and corners (`SurfaceMesh::cage_coords`,
//! `cage_loop_corner`: 3 · (16 + 8) = 72 bytes per triangle, two triangles per sample) add 148
//! bytes per sample, measured on the debug build (202 → 350 bytes per sample, the same run
//! before and after; allocation sizes do not depend on the build), so 225 + 148 = 373.
//! The estimate is [`BASE_BYTES`] plus [`GB_BYTES_PER_SAMPLE`] (quad layout) or
//! [`GB_TRIANGLE_BYTES_PER_SAMPLE`] (triangle layout) per sample or
//! [`SUBDIV_BYTES_PER_VERTEX`] per subdivided vertex, about 25 % above the largest measurement.
//! (Until the validity checks and writers were reworked the figures were about 950 bytes per
//! vertex for every method, and the estimate 1024 bytes per sample refused runs of a third of the
//! limit.)

use crate::mesh::HalfEdgeMesh;
use crate::options::{ConvertOptions, Method};

/// Memory of a conversion besides its output (program, input, construction), bytes.
pub const BASE_BYTES: u64 = 16 << 20;
/// Peak bytes per tessellation sample of the GB methods in the quad layout (measured ≤ 336, see
/// the module doc).
pub const GB_BYTES_PER_SAMPLE: u64 = 420;
/// Peak bytes per tessellation sample of the GB methods in the triangle layout (measured ≤ 373
/// with its per-loop cage data, see the module doc).
pub const GB_TRIANGLE_BYTES_PER_SAMPLE: u64 = 470;
/// Peak bytes per output vertex of the subdivision methods (measured ≤ 570).
pub const SUBDIV_BYTES_PER_VERTEX: u64 = 712;

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
                // A crease splits the patch into sectors with 3 more corners each (at most one
                // sector per sharp edge): sum over sectors of (1 + m·q) ≤ 1 + (n + 4k)·q.
                let sharp = mesh.vertex_outgoing(v).filter(|&h| mesh.edge_crease(mesh.edge(h)) > 0.0).count();
                samples(mesh.valence(v) + mesh.is_boundary_vertex(v) as usize + 4 * sharp)
            })
            .sum(),
        Method::Topology => (0..mesh.n_faces()).map(|f| samples(mesh.face_size(crate::mesh::halfedge::FaceId::from(f)))).sum(),
        Method::CatmullClark | Method::DooSabin => subdivided_vertices(mesh, options.method, options.levels),
    };
    let per = match (options.method.is_patch_method(), options.layout) {
        (false, _) => SUBDIV_BYTES_PER_VERTEX,
        (true, crate::gb::Layout::Quads) => GB_BYTES_PER_SAMPLE,
        (true, crate::gb::Layout::Triangles) => GB_TRIANGLE_BYTES_PER_SAMPLE,
    };
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

//! Polygon meshes: plain face lists ([`PolyMesh`]), triangle output ([`TriMesh`]) and the
//! [`MeshSink`] trait through which single-patch tessellation emits triangles; half-edge topology,
//! validation and file I/O live in submodules.

use glam::DVec3;

/// A polygon mesh as plain face lists: the exchange type between layers.
/// Faces are counter-clockwise seen from outside; indices are 0-based into `positions`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PolyMesh {
    /// Vertex positions.
    pub positions: Vec<DVec3>,
    /// Faces as vertex-index loops (3 or more entries each).
    pub faces: Vec<Vec<u32>>,
}

impl PolyMesh {
    /// A mesh from positions and faces (no validation here; see the validation module).
    pub fn new(positions: Vec<DVec3>, faces: Vec<Vec<u32>>) -> Self {
        Self { positions, faces }
    }
}

/// Receives a triangle mesh piece by piece (vertices with normals, then triangles). Single-patch
/// tessellation emits through it; the whole-surface output is a plain-array mesh that the
/// writers, the C ABI, the OpenMesh bridge and the Blender add-on copy (none of them implements
/// this trait).
pub trait MeshSink {
    /// Adds a vertex with its unit normal and returns its index.
    fn add_vertex(&mut self, position: DVec3, normal: DVec3) -> u32;
    /// Adds a counter-clockwise triangle of earlier vertex indices.
    fn add_triangle(&mut self, tri: [u32; 3]);
}

/// A triangle mesh with per-vertex normals: the simplest [`MeshSink`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriMesh {
    pub positions: Vec<DVec3>,
    pub normals: Vec<DVec3>,
    pub triangles: Vec<[u32; 3]>,
}

impl MeshSink for TriMesh {
    fn add_vertex(&mut self, position: DVec3, normal: DVec3) -> u32 {
        self.positions.push(position);
        self.normals.push(normal);
        (self.positions.len() - 1) as u32
    }
    fn add_triangle(&mut self, tri: [u32; 3]) {
        self.triangles.push(tri);
    }
}

pub mod error;
pub mod geometry;
pub mod halfedge;
pub mod validate;

pub use error::{MeshError, MeshWarning, SourceMap, COORDINATE_LIMIT};
pub use halfedge::{EdgeId, FaceId, HalfEdgeMesh, HalfedgeId, VertexId};
pub use validate::{validate, ValidMesh};
pub mod io;
pub use io::{read_mesh, read_polymesh};
pub mod generate;

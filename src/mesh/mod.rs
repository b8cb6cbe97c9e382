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
    /// Edge and vertex sharpness (empty for a smooth mesh).
    pub creases: Creases,
    /// Inner loops of faces with holes (empty for a mesh of simple faces; see [`Hole`]).
    pub holes: Vec<Hole>,
}

impl PolyMesh {
    /// A mesh from positions and faces, without creases (no validation here; see the validation
    /// module).
    pub fn new(positions: Vec<DVec3>, faces: Vec<Vec<u32>>) -> Self {
        Self { positions, faces, creases: Creases::default(), holes: Vec::new() }
    }
}

/// An inner loop (hole) of a face (the one definition; see docs/math.md, "Faces with holes").
///
/// The face `faces[face]` is then the outer loop (counter-clockwise seen from outside) and
/// `vertices` an inner loop in the opposite orientation (clockwise seen from outside), strictly
/// inside the outer loop, sharing no vertex with it or with the face's other holes, crossing no
/// other loop of the face. A face may have several holes (entries in order). Read from OBJ as
/// molihua writes it (`#h N` after a face line, then N `f` lines holding the inner loops).
/// Validated and split into simple convex faces by the one validator
/// ([`HalfEdgeMesh::from_polymesh`], [`holes::split_holes`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Hole {
    /// Index of the face (outer loop) into [`PolyMesh::faces`].
    pub face: u32,
    /// The inner loop's vertex indices.
    pub vertices: Vec<u32>,
}

/// Sharpness of edges and vertices of a control mesh (the one definition; see docs/math.md#creases).
///
/// Sharpness c ∈ [0, 1]: 0 = smooth (the surface is exactly that of a mesh without the entry),
/// 1 = infinitely sharp (edge: the surface is G0 across it; vertex: a corner), in between a
/// semi-sharp crease. Readers map their own scales onto c (OBJ/OpenSubdiv `t crease` sharpness
/// s: c = sqrt(min(s, 10)/10), inverting Blender's s = 10·c²; Blender's `crease_edge` and
/// `crease_vert` attributes are c already). Indices are the mesh's vertex indices (0-based, input
/// numbering). Validated by the one validator ([`HalfEdgeMesh::from_polymesh`]): c finite in
/// [0, 1], vertices in range, the edge must be an edge of some face; an edge or vertex listed
/// twice keeps the larger value.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Creases {
    /// `([a, b], c)`: the edge between vertices a and b (either order) has sharpness c.
    pub edges: Vec<([u32; 2], f64)>,
    /// `(v, c)`: vertex v has corner sharpness c.
    pub vertices: Vec<(u32, f64)>,
}

impl Creases {
    /// True when no entry has a sharpness above 0 (the mesh is smooth).
    pub fn is_smooth(&self) -> bool {
        self.edges.iter().all(|e| e.1 == 0.0) && self.vertices.iter().all(|v| v.1 == 0.0)
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

pub(crate) mod edges;
pub mod error;
pub mod geometry;
pub mod halfedge;
pub mod holes;
pub mod validate;

pub use error::{HoleDefect, MeshError, MeshWarning, SourceMap, COORDINATE_LIMIT};
pub use halfedge::{EdgeId, FaceId, HalfEdgeMesh, HalfedgeId, VertexId};
pub use validate::{validate, ValidMesh};
pub mod io;
pub use io::{read_mesh, read_polymesh};
pub mod generate;

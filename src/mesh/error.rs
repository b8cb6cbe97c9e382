//! Typed mesh errors and warnings. Every variant names the offending element.
//!
//! Conventions: vertex and face indices are 0-based indices into the *input* [`PolyMesh`]
//! (before isolated vertices are dropped); `line` is the 1-based line of the element in the
//! source file when the mesh was read from a file (see [`SourceMap`]), `None` otherwise. An
//! error annotated from a file ([`MeshError::with_source`]) names vertices as the file numbers
//! them: 1-based for OBJ (its `v` lines count from 1, as its `f` lines name them), 0-based for OFF
//! and PLY; OpenSubdiv's `t crease` / `t corner` tags are 0-based in OBJ too and keep their
//! numbers. Faces are 0-based in every format (no format numbers them) with their line.
//!
//! [`PolyMesh`]: super::PolyMesh

use thiserror::Error;

/// Largest accepted absolute coordinate. Squares and products of two coordinates (areas,
/// normals, squared lengths) then stay below 1e300 < `f64::MAX` ≈ 1.8e308, so no geometric
/// computation of the crate can overflow silently. Larger values give
/// [`MeshError::CoordinateRange`].
pub const COORDINATE_LIMIT: f64 = 1e150;

/// Relative tolerance of the zero-area test: a face is degenerate when its (Newell) area is at
/// most `ZERO_AREA_REL * d²`, `d` the largest extent of the face's bounding box.
pub const ZERO_AREA_REL: f64 = 1e-12;

/// Why a mesh was rejected.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum MeshError {
    /// The file could not be read or parsed (syntax errors, unknown format).
    #[error("parse error{}: {message}", fmt_line(*line))]
    Parse { line: Option<usize>, message: String },
    /// An I/O failure (open, read, write, rename).
    #[error("i/o error on {path}: {message}")]
    Io { path: String, message: String },
    /// The mesh has no faces.
    #[error("empty mesh: no faces")]
    Empty,
    /// A coordinate is NaN or infinite.
    #[error("vertex {vertex}{}: coordinate {axis} is {value} (not finite)", fmt_line(*line))]
    NonFiniteCoordinate { vertex: usize, axis: usize, value: f64, line: Option<usize> },
    /// A coordinate exceeds [`COORDINATE_LIMIT`] in absolute value.
    #[error("vertex {vertex}{}: coordinate {axis} = {value:e} exceeds the limit {limit:e}", fmt_line(*line))]
    CoordinateRange { vertex: usize, axis: usize, value: f64, limit: f64, line: Option<usize> },
    /// A face has fewer than 3 corners.
    #[error("face {face}{} has {len} corners (at least 3 needed)", fmt_line(*line))]
    FaceTooSmall { face: usize, len: usize, line: Option<usize> },
    /// A face names a vertex that does not exist. `index` is 0-based (may be negative for a
    /// relative OBJ index that points before the first vertex).
    #[error("face {face}{} corner {corner}: vertex index {index} out of range (0..{n_vertices})", fmt_line(*line))]
    IndexOutOfRange { face: usize, corner: usize, index: i64, n_vertices: usize, line: Option<usize> },
    /// An OBJ face names a vertex that does not exist. `index` is as written in the file (1-based,
    /// or negative relative to the vertices above the face); `available` is the number of
    /// vertices it may name (all of them for a positive index, those above the face otherwise).
    #[error("face {face}{} corner {corner}: vertex index {index} out of range ({})", fmt_line(*line), obj_range(*index, *available))]
    ObjIndexOutOfRange { face: usize, corner: usize, index: i64, available: usize, line: Option<usize> },
    /// The path is not a regular file (a directory, device or FIFO).
    #[error("{path} is not a regular file")]
    NotAFile { path: String },
    /// The file is larger than [`crate::limits::MAX_INPUT_BYTES`].
    #[error("{path} is larger than the limit of {limit} bytes")]
    InputTooLarge { path: String, limit: u64 },
    /// The bounding box is too small relative to the coordinates' magnitude for f64 to resolve
    /// the shape (see [`crate::limits::MIN_RELATIVE_EXTENT`]).
    #[error("mesh extent {extent:e} is below {min_ratio:e} times the coordinate magnitude {magnitude:e} of vertex {vertex}{}: f64 cannot resolve the shape; move the mesh nearer the origin", fmt_line(*line))]
    UnresolvableExtent { extent: f64, magnitude: f64, min_ratio: f64, vertex: usize, line: Option<usize> },
    /// A face names the same vertex more than once.
    #[error("face {face}{} names vertex {vertex} more than once", fmt_line(*line))]
    RepeatedIndex { face: usize, vertex: usize, line: Option<usize> },
    /// A face has (relatively) zero area: its corners are collinear or coincident.
    #[error("face {face}{} has zero area (area {area:e})", fmt_line(*line))]
    ZeroAreaFace { face: usize, area: f64, line: Option<usize> },
    /// The same vertex cycle appears twice (same or opposite orientation).
    #[error("face {face}{} duplicates face {first}", fmt_line(*line))]
    DuplicateFace { face: usize, first: usize, line: Option<usize> },
    /// An edge (as its vertex pair) is shared by more than two faces (all of them listed).
    #[error("edge ({}, {}) is shared by {} faces {faces:?}{}", edge.0, edge.1, faces.len(), fmt_line(*line))]
    NonManifoldEdge { edge: (usize, usize), faces: Vec<usize>, line: Option<usize> },
    /// Two faces traverse the directed edge `edge.0 → edge.1` in the same direction.
    #[error("faces {} and {} both use edge {} -> {} in the same direction (inconsistent orientation){}", faces.0, faces.1, edge.0, edge.1, fmt_line(*line))]
    InconsistentOrientation { edge: (usize, usize), faces: (usize, usize), line: Option<usize> },
    /// The faces around a vertex form more than one fan (a "bowtie" vertex).
    #[error("vertex {vertex}{} is non-manifold: its faces form {fans} separate fans", fmt_line(*line))]
    NonManifoldVertex { vertex: usize, fans: usize, line: Option<usize> },
    /// A geometric operation could not be carried out (e.g. degenerate input to a generator).
    #[error("degenerate geometry: {0}")]
    Degenerate(String),
    /// An edge crease ([`super::Creases::edges`] entry `entry`) has a sharpness that is not a
    /// finite number in [0, 1].
    #[error("edge crease {entry} on edge ({}, {}){}: sharpness {value} is not a finite number in [0, 1]", edge.0, edge.1, fmt_line(*line))]
    EdgeCreaseValue { entry: usize, edge: (usize, usize), value: f64, line: Option<usize> },
    /// An edge crease names a vertex pair that is no edge of any face (or a vertex that does not
    /// exist).
    #[error("edge crease {entry}{}: ({}, {}) is not an edge of any face", fmt_line(*line), edge.0, edge.1)]
    CreaseEdgeMissing { entry: usize, edge: (usize, usize), line: Option<usize> },
    /// A vertex crease (corner, [`super::Creases::vertices`] entry `entry`) has a sharpness that is
    /// not a finite number in [0, 1].
    #[error("vertex crease {entry} on vertex {vertex}{}: sharpness {value} is not a finite number in [0, 1]", fmt_line(*line))]
    VertexCreaseValue { entry: usize, vertex: usize, value: f64, line: Option<usize> },
    /// A vertex crease names a vertex that does not exist.
    #[error("vertex crease {entry}{}: vertex {vertex} out of range (0..{n_vertices})", fmt_line(*line))]
    CreaseVertexOutOfRange { entry: usize, vertex: usize, n_vertices: usize, line: Option<usize> },
    /// A hole ([`super::PolyMesh::holes`] entry `hole`) of face `face` is not a proper inner loop;
    /// `line` is the line of the hole's own `f` line in an OBJ file.
    #[error("hole {hole} of face {face}{}: {defect}", fmt_line(*line))]
    Hole { face: usize, hole: usize, defect: HoleDefect, line: Option<usize> },
    /// A hole names a face that does not exist.
    #[error("hole {hole}{}: face {face} out of range (0..{n_faces})", fmt_line(*line))]
    HoleFaceOutOfRange { hole: usize, face: usize, n_faces: usize, line: Option<usize> },
    /// An OBJ `#h N` line announces more inner loops than `f` lines follow it.
    #[error("line {line}: `#h {declared}` announces {declared} hole loop(s) of face {face} but only {found} `f` line(s) follow")]
    MissingHoleLoops { face: usize, declared: usize, found: usize, line: usize },
}

/// What is wrong with an inner loop ([`MeshError::Hole`]). Vertex indices are 0-based input
/// indices; `other` is another hole (index into [`super::PolyMesh::holes`]).
#[derive(Clone, Debug, Error, PartialEq)]
pub enum HoleDefect {
    #[error("has {len} corners (at least 3 needed)")]
    TooSmall { len: usize },
    #[error("corner {corner}: vertex index {index} out of range (0..{n_vertices})")]
    IndexOutOfRange { corner: usize, index: i64, n_vertices: usize },
    #[error("names vertex {vertex} more than once")]
    RepeatedVertex { vertex: usize },
    /// The vertex is also on the outer loop (`other` = None) or on hole `other` of the same face.
    #[error("vertex {vertex} is also on {}", match other { None => "the outer loop".to_string(), Some(h) => format!("hole {h} of the same face") })]
    SharedVertex { vertex: usize, other: Option<usize> },
    #[error("has zero area (area {area:e})")]
    ZeroArea { area: f64 },
    #[error("has the orientation of the outer loop (an inner loop must run the opposite way)")]
    SameOrientation,
    #[error("edge from corner {corner} crosses or touches the outer loop")]
    CrossesOuter { corner: usize },
    #[error("vertex {vertex} is not strictly inside the outer loop")]
    Outside { vertex: usize },
    #[error("crosses or touches hole {other}")]
    CrossesHole { other: usize },
    #[error("lies inside hole {other} or contains it")]
    Nested { other: usize },
    /// The face and its holes up to this one have more corners than the checks and the split
    /// handle ([`crate::limits::MAX_HOLED_FACE_CORNERS`]; their cost grows with its square).
    #[error("brings the face's loops to {corners} corners; a face with holes may have at most {max} (split it into several faces)")]
    TooManyCorners { corners: usize, max: usize },
}

impl HoleDefect {
    /// The defect with its vertex indices shifted by `base` (see [`SourceMap::vertex_base`]).
    fn renumbered(self, base: usize) -> Self {
        use HoleDefect::*;
        match self {
            RepeatedVertex { vertex } => RepeatedVertex { vertex: vertex + base },
            SharedVertex { vertex, other } => SharedVertex { vertex: vertex + base, other },
            Outside { vertex } => Outside { vertex: vertex + base },
            d => d,
        }
    }
}

fn obj_range(index: i64, n: usize) -> String {
    match (index < 0, n) {
        (false, 0) | (true, 0) => "no vertices to name".to_string(),
        (false, n) => format!("1..={n}"),
        (true, n) => format!("-{n}..=-1 relative to the {n} vertices above"),
    }
}

fn fmt_line(line: Option<usize>) -> String {
    match line {
        Some(l) => format!(" (line {l})"),
        None => String::new(),
    }
}

/// Something accepted but changed on the way in.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum MeshWarning {
    /// A vertex used by no face was dropped (vertices renumbered).
    #[error("vertex {vertex}{} is used by no face and was dropped", fmt_line(*line))]
    IsolatedVertex { vertex: usize, line: Option<usize> },
    /// A file statement the reader does not support was skipped (OBJ free-form geometry,
    /// render attributes, OpenSubdiv tags as `t <tag>`): the first line and how many there were.
    #[error("skipped {count} unsupported statement(s) {statement:?} (first on line {line})")]
    SkippedStatement { statement: String, line: usize, count: usize },
}

/// Source lines of the elements of a mesh read from a file (1-based), to annotate errors.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SourceMap {
    /// Line of each vertex.
    pub vertex_lines: Vec<usize>,
    /// Line of each face.
    pub face_lines: Vec<usize>,
    /// Line of each edge crease ([`super::Creases::edges`], OBJ `t crease`).
    pub edge_crease_lines: Vec<usize>,
    /// Line of each vertex crease ([`super::Creases::vertices`], OBJ `t corner`).
    pub vertex_crease_lines: Vec<usize>,
    /// Line of each hole loop ([`super::PolyMesh::holes`], the `f` lines after OBJ `#h N`).
    pub hole_lines: Vec<usize>,
    /// Added to the vertex indices an error or warning names so that they read as the file
    /// numbers its vertices: 1 for OBJ, 0 for OFF, PLY and STL (see the module doc).
    pub vertex_base: usize,
    /// What the reader skipped (added to the mesh's warnings by
    /// [`super::HalfEdgeMesh::annotate_warnings`]).
    pub warnings: Vec<MeshWarning>,
}

impl SourceMap {
    fn vl(&self, v: usize) -> Option<usize> {
        self.vertex_lines.get(v).copied()
    }
    fn fl(&self, f: usize) -> Option<usize> {
        self.face_lines.get(f).copied()
    }
}

impl MeshError {
    /// Fills in the `line` of the named element from `map` (vertex errors: the vertex's line;
    /// face and edge errors: the line of the (last) face named).
    pub fn with_source(self, map: &SourceMap) -> Self {
        use MeshError::*;
        // Vertex indices as the file numbers them.
        let b = map.vertex_base;
        match self {
            NonFiniteCoordinate { vertex, axis, value, .. } => {
                NonFiniteCoordinate { vertex: vertex + b, axis, value, line: map.vl(vertex) }
            }
            CoordinateRange { vertex, axis, value, limit, .. } => {
                CoordinateRange { vertex: vertex + b, axis, value, limit, line: map.vl(vertex) }
            }
            FaceTooSmall { face, len, .. } => FaceTooSmall { face, len, line: map.fl(face) },
            IndexOutOfRange { face, corner, index, n_vertices, .. } => {
                IndexOutOfRange { face, corner, index, n_vertices, line: map.fl(face) }
            }
            RepeatedIndex { face, vertex, .. } => RepeatedIndex { face, vertex: vertex + b, line: map.fl(face) },
            ZeroAreaFace { face, area, .. } => ZeroAreaFace { face, area, line: map.fl(face) },
            DuplicateFace { face, first, .. } => DuplicateFace { face, first, line: map.fl(face) },
            NonManifoldEdge { edge, faces, .. } => {
                let line = faces.last().and_then(|&f| map.fl(f));
                NonManifoldEdge { edge: (edge.0 + b, edge.1 + b), faces, line }
            }
            InconsistentOrientation { edge, faces, .. } => {
                InconsistentOrientation { edge: (edge.0 + b, edge.1 + b), faces, line: map.fl(faces.1) }
            }
            NonManifoldVertex { vertex, fans, .. } => {
                NonManifoldVertex { vertex: vertex + b, fans, line: map.vl(vertex) }
            }
            UnresolvableExtent { extent, magnitude, min_ratio, vertex, .. } => {
                UnresolvableExtent { extent, magnitude, min_ratio, vertex: vertex + b, line: map.vl(vertex) }
            }
            EdgeCreaseValue { entry, edge, value, .. } => {
                EdgeCreaseValue { entry, edge, value, line: map.edge_crease_lines.get(entry).copied() }
            }
            CreaseEdgeMissing { entry, edge, .. } => {
                CreaseEdgeMissing { entry, edge, line: map.edge_crease_lines.get(entry).copied() }
            }
            VertexCreaseValue { entry, vertex, value, .. } => {
                VertexCreaseValue { entry, vertex, value, line: map.vertex_crease_lines.get(entry).copied() }
            }
            CreaseVertexOutOfRange { entry, vertex, n_vertices, .. } => {
                CreaseVertexOutOfRange { entry, vertex, n_vertices, line: map.vertex_crease_lines.get(entry).copied() }
            }
            Hole { face, hole, defect, .. } => Hole { face, hole, defect: defect.renumbered(b), line: map.hole_lines.get(hole).copied() },
            HoleFaceOutOfRange { hole, face, n_faces, .. } => {
                HoleFaceOutOfRange { hole, face, n_faces, line: map.hole_lines.get(hole).copied() }
            }
            e => e,
        }
    }
}

impl MeshError {
    /// Renames the faces an error names through `f` (e.g. faces of a split mesh back to the input
    /// faces they come from).
    pub fn map_faces(self, f: impl Fn(usize) -> usize) -> Self {
        use MeshError::*;
        match self {
            FaceTooSmall { face, len, line } => FaceTooSmall { face: f(face), len, line },
            IndexOutOfRange { face, corner, index, n_vertices, line } => IndexOutOfRange { face: f(face), corner, index, n_vertices, line },
            RepeatedIndex { face, vertex, line } => RepeatedIndex { face: f(face), vertex, line },
            ZeroAreaFace { face, area, line } => ZeroAreaFace { face: f(face), area, line },
            DuplicateFace { face, first, line } => DuplicateFace { face: f(face), first: f(first), line },
            NonManifoldEdge { edge, faces, line } => NonManifoldEdge { edge, faces: faces.into_iter().map(&f).collect(), line },
            InconsistentOrientation { edge, faces, line } => InconsistentOrientation { edge, faces: (f(faces.0), f(faces.1)), line },
            e => e,
        }
    }
}

impl MeshWarning {
    /// Fills in the `line` of the named element from `map`.
    pub fn with_source(self, map: &SourceMap) -> Self {
        match self {
            MeshWarning::IsolatedVertex { vertex, .. } => {
                MeshWarning::IsolatedVertex { vertex: vertex + map.vertex_base, line: map.vl(vertex) }
            }
            w @ MeshWarning::SkippedStatement { .. } => w,
        }
    }
}

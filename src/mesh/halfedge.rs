//! OpenMesh-style half-edge topology of a validated polygon mesh.
//!
//! Index types are small `u32` newtypes ([`VertexId`], [`FaceId`], [`HalfedgeId`], [`EdgeId`]);
//! `.idx()` gives the `usize` index, `.0` the raw `u32`. Every edge `e` has the two half-edges
//! `2e` and `2e + 1`, so `twin(h) = h ^ 1` and `edge(h) = h / 2`. A boundary half-edge has no
//! face; boundary half-edges are linked by `next`/`prev` into the boundary loops (traversed with
//! the hole on their left, i.e. clockwise seen from outside the surface).
//!
//! Orientation: faces are counter-clockwise seen from outside. Around a vertex `v` the
//! counter-clockwise successor of an outgoing half-edge `h` is `twin(prev(h))` (OpenMesh's
//! `ccw_rotated_halfedge`). For a boundary vertex, [`HalfEdgeMesh::vertex_halfedge`] is its outgoing
//! boundary half-edge, so [`HalfEdgeMesh::vertex_outgoing`] starts there and visits the faces of
//! the (single) fan in counter-clockwise order without a gap.
//!
//! Built in linear time from a [`PolyMesh`] with a hash map of undirected edges, after the checks of
//! [`super::validate`]; isolated vertices are dropped (see [`HalfEdgeMesh::warnings`]).

use super::error::{MeshError, MeshWarning};
use super::edges::{first_corners, Corners};
use super::validate::{check_polymesh, drop_isolated};
use super::PolyMesh;
use glam::DVec3;
use std::collections::HashMap;

macro_rules! id_type {
    ($(#[$m:meta])* $name:ident) => {
        $(#[$m])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub struct $name(pub u32);
        impl $name {
            /// The index as `usize`.
            #[inline]
            pub fn idx(self) -> usize {
                self.0 as usize
            }
        }
        impl From<usize> for $name {
            #[inline]
            fn from(i: usize) -> Self {
                Self(i as u32)
            }
        }
        impl From<u32> for $name {
            #[inline]
            fn from(i: u32) -> Self {
                Self(i)
            }
        }
    };
}

id_type!(
    /// Index of a vertex of a [`HalfEdgeMesh`].
    VertexId
);
id_type!(
    /// Index of a face of a [`HalfEdgeMesh`] (same order as the faces of the input mesh).
    FaceId
);
id_type!(
    /// Index of a half-edge; `twin = h ^ 1`.
    HalfedgeId
);
id_type!(
    /// Index of an (undirected) edge; its half-edges are `2e`, `2e + 1`.
    EdgeId
);

const NONE: u32 = u32::MAX;

/// Half-edge mesh (see the module doc for conventions).
#[derive(Clone, Debug, PartialEq)]
pub struct HalfEdgeMesh {
    positions: Vec<DVec3>,
    he_origin: Vec<u32>,
    he_next: Vec<u32>,
    he_prev: Vec<u32>,
    he_face: Vec<u32>,
    vertex_he: Vec<u32>,
    face_he: Vec<u32>,
    warnings: Vec<MeshWarning>,
    original_vertex: Vec<u32>,
    /// Sharpness per edge (empty: all 0), see [`super::Creases`].
    edge_crease: Vec<f64>,
    /// Corner sharpness per vertex (empty: all 0).
    vertex_crease: Vec<f64>,
    /// Per face: the input face it is a piece of (empty: every face is its own input face; set
    /// for faces with holes, [`super::holes::HoleSplit::origin`]).
    face_input: Vec<u32>,
    /// Per half-edge with a face: the user's corner index of its origin in that input face
    /// ([`super::holes::HoleSplit::corner`]); empty: the position in its face.
    he_input_corner: Vec<u32>,
}

/// Faces (and vertices) between two progress ticks of [`HalfEdgeMesh::from_checked_polymesh_ticked`].
const TICK_FACES: usize = 4096;

impl HalfEdgeMesh {
    /// Validates `mesh` (see [`super::validate`]), drops isolated vertices and builds the
    /// half-edge structure. Errors name elements in the input numbering.
    ///
    /// Faces with holes ([`PolyMesh::holes`]) are checked and split into simple convex faces
    /// first ([`super::holes::split_holes`]): face `f` then holds its first piece and the other
    /// pieces follow the input faces; errors name the input face.
    pub fn from_polymesh(mesh: &PolyMesh) -> Result<Self, MeshError> {
        check_polymesh(mesh)?;
        if mesh.holes.is_empty() {
            return Self::from_checked_polymesh(mesh);
        }
        let split = super::holes::split_holes(mesh)?;
        let origin = &split.origin;
        let mut m = check_polymesh(&split.mesh)
            .and_then(|()| Self::from_checked_polymesh(&split.mesh))
            .map_err(|e| e.map_faces(|f| origin.get(f).map_or(f, |&o| o as usize)))?;
        let mut corner = vec![NONE; m.n_halfedges()];
        for f in m.faces() {
            let user = &split.corner[f.idx()];
            for (i, h) in m.face_halfedges(f).enumerate() {
                corner[h.idx()] = if user.is_empty() { i as u32 } else { user[i] };
            }
        }
        m.face_input = split.origin;
        m.he_input_corner = corner;
        Ok(m)
    }

    /// The input face (as the user wrote it) that face `f` is, or is a piece of (a face with
    /// holes is split into pieces, [`super::holes::split_holes`]).
    pub fn input_face(&self, f: FaceId) -> usize {
        self.face_input.get(f.idx()).map_or(f.idx(), |&o| o as usize)
    }

    /// The user's corner index of the origin of half-edge `h` in its face's input face
    /// ([`Self::input_face`]): its position in the face as written, or for a face with holes
    /// "outer loop 0..m−1, then the holes' loops in order" ([`super::holes::HoleSplit::corner`]).
    /// `None` for a boundary half-edge.
    pub fn input_corner(&self, h: HalfedgeId) -> Option<usize> {
        let f = self.face(h)?;
        match self.he_input_corner.get(h.idx()) {
            Some(&c) => Some(c as usize),
            None => self.face_halfedges(f).position(|g| g == h),
        }
    }

    /// Builds the half-edge structure of a mesh whose faces are valid by construction (indices in
    /// range, each directed edge used once, no face repeated), skipping the checks of
    /// [`check_polymesh`] but not the single-fan check. Used for subdivision levels, whose
    /// topology follows from a validated input.
    pub(crate) fn from_checked_polymesh(mesh: &PolyMesh) -> Result<Self, MeshError> {
        Self::from_checked_polymesh_ticked(mesh, &mut |_, _| Ok(()))
    }

    /// [`Self::from_checked_polymesh`] calling `tick(done, total)` every [`TICK_FACES`] faces
    /// and vertices (total = faces + vertices) so a caller can report progress and cancel; its
    /// error ends the build.
    pub(crate) fn from_checked_polymesh_ticked<E: From<MeshError>>(
        mesh: &PolyMesh,
        tick: &mut dyn FnMut(usize, usize) -> Result<(), E>,
    ) -> Result<Self, E> {
        let (clean, original_vertex, warnings) = drop_isolated(mesh);
        let nv = clean.positions.len();
        let total = clean.faces.len() + nv;
        // Edges numbered in order of first use (super::edges), no hash map.
        let corners = Corners::new(&clean.faces).ok_or_else(|| MeshError::Degenerate(format!("more than {} face corners", u32::MAX)))?;
        let first = first_corners(&corners, nv);
        let n_corners = corners.len();
        // Per corner its half-edge; a later use of an edge takes the edge of its first use.
        let mut corner_he = vec![NONE; n_corners];
        let mut he_origin = Vec::with_capacity(n_corners + 8);
        let mut he_face = Vec::with_capacity(n_corners + 8);
        let mut he_next = Vec::with_capacity(n_corners + 8);
        let mut he_prev = Vec::with_capacity(n_corners + 8);
        let mut face_he = Vec::with_capacity(clean.faces.len());
        for f in 0..clean.faces.len() {
            if f % TICK_FACES == 0 {
                tick(f, total)?;
            }
            let (c0, c1) = (corners.start[f] as usize, corners.start[f + 1] as usize);
            for c in c0..c1 {
                let (a, b) = corners.edge(f, c);
                let (lo, hi) = (a.min(b), a.max(b));
                let e = if first[c] as usize == c {
                    let e = (he_origin.len() / 2) as u32;
                    he_origin.extend([lo, hi]);
                    he_face.extend([NONE, NONE]);
                    he_next.extend([NONE, NONE]);
                    he_prev.extend([NONE, NONE]);
                    e
                } else {
                    corner_he[first[c] as usize] / 2
                };
                let h = 2 * e + u32::from(a != lo);
                corner_he[c] = h;
                // check_polymesh guarantees each directed edge is used once.
                he_face[h as usize] = f as u32;
            }
            for c in c0..c1 {
                let next = if c + 1 == c1 { c0 } else { c + 1 };
                let (h, g) = (corner_he[c], corner_he[next]);
                he_next[h as usize] = g;
                he_prev[g as usize] = h;
            }
            face_he.push(corner_he[c0]);
        }
        // Outgoing half-edge per vertex (boundary preferred); count boundary outgoing.
        let nh = he_origin.len();
        let mut vertex_he = vec![NONE; nv];
        let mut boundary_out = vec![NONE; nv];
        let mut n_out = vec![0u32; nv];
        for h in 0..nh {
            let v = he_origin[h] as usize;
            n_out[v] += 1;
            if vertex_he[v] == NONE {
                vertex_he[v] = h as u32;
            }
            if he_face[h] == NONE {
                if boundary_out[v] != NONE {
                    return Err(MeshError::NonManifoldVertex {
                        vertex: original_vertex[v] as usize,
                        fans: count_boundary_out(&he_origin, &he_face, v as u32),
                        line: None,
                    }
                    .into());
                }
                boundary_out[v] = h as u32;
                vertex_he[v] = h as u32;
            }
        }
        // Link boundary loops: next of a→b (boundary) is the boundary half-edge leaving b.
        for h in 0..nh {
            if he_face[h] == NONE {
                let b = he_origin[h ^ 1] as usize;
                let n = boundary_out[b];
                if n == NONE {
                    return Err(MeshError::NonManifoldVertex {
                        vertex: original_vertex[b] as usize,
                        fans: 2,
                        line: None,
                    }
                    .into());
                }
                he_next[h] = n;
                he_prev[n as usize] = h as u32;
            }
        }
        tick(clean.faces.len(), total)?;
        let positions = match clean {
            std::borrow::Cow::Borrowed(m) => m.positions.clone(),
            std::borrow::Cow::Owned(m) => m.positions,
        };
        let mut m = HalfEdgeMesh {
            positions,
            he_origin,
            he_next,
            he_prev,
            he_face,
            vertex_he,
            face_he,
            warnings,
            original_vertex,
            edge_crease: Vec::new(),
            vertex_crease: Vec::new(),
            face_input: Vec::new(),
            he_input_corner: Vec::new(),
        };
        // Single fan per vertex: the CCW walk from vertex_he must visit every outgoing half-edge.
        for v in 0..nv {
            if v % TICK_FACES == 0 {
                tick(total - nv + v, total)?;
            }
            let walked = m.vertex_outgoing(VertexId(v as u32)).count() as u32;
            if walked != n_out[v] {
                let fans = m.count_fans(v, n_out[v]);
                return Err(MeshError::NonManifoldVertex {
                    vertex: m.original_vertex[v] as usize,
                    fans,
                    line: None,
                }
                .into());
            }
        }
        m.warnings.shrink_to_fit();
        m.apply_creases(&mesh.creases)?;
        Ok(m)
    }

    /// Stores `creases` (input numbering) per edge and vertex; values were checked by
    /// [`check_polymesh`] (re-checked here for meshes built without it). An edge crease must name
    /// an edge of the mesh; a vertex crease on a dropped isolated vertex is ignored; a repeated
    /// entry keeps the larger value. Nothing is stored when every value is 0.
    fn apply_creases(&mut self, creases: &super::Creases) -> Result<(), MeshError> {
        if creases.is_smooth() {
            return Ok(());
        }
        super::validate::check_creases(creases, usize::MAX)?;
        let n_input = self.original_vertex.last().map_or(0, |&o| o as usize + 1);
        let mut index = vec![NONE; n_input];
        for (v, &o) in self.original_vertex.iter().enumerate() {
            index[o as usize] = v as u32;
        }
        let new_index = |v: u32| index.get(v as usize).copied().filter(|&x| x != NONE);
        self.edge_crease = vec![0.0; self.n_edges()];
        self.vertex_crease = vec![0.0; self.n_vertices()];
        for (entry, &([a, b], c)) in creases.edges.iter().enumerate() {
            let e = match (new_index(a), new_index(b)) {
                (Some(x), Some(y)) => {
                    self.vertex_outgoing(VertexId(x)).find(|&h| self.target(h) == VertexId(y)).map(|h| self.edge(h).0)
                }
                _ => None,
            };
            let e = e.ok_or(MeshError::CreaseEdgeMissing { entry, edge: (a as usize, b as usize), line: None })?;
            let slot = &mut self.edge_crease[e as usize];
            *slot = slot.max(c);
        }
        for &(v, c) in &creases.vertices {
            if let Some(x) = new_index(v) {
                let slot = &mut self.vertex_crease[x as usize];
                *slot = slot.max(c);
            }
        }
        Ok(())
    }

    /// Sharpness of edge `e` in [0, 1] (0 = smooth), see [`super::Creases`].
    pub fn edge_crease(&self, e: EdgeId) -> f64 {
        self.edge_crease.get(e.idx()).copied().unwrap_or(0.0)
    }

    /// Corner sharpness of vertex `v` in [0, 1] (0 = smooth), see [`super::Creases`].
    pub fn vertex_crease(&self, v: VertexId) -> f64 {
        self.vertex_crease.get(v.idx()).copied().unwrap_or(0.0)
    }

    /// True when some edge or vertex has a sharpness above 0.
    pub fn has_creases(&self) -> bool {
        self.edge_crease.iter().chain(&self.vertex_crease).any(|&c| c > 0.0)
    }

    /// Number of separate fans of vertex `v` (only called for non-manifold vertices).
    fn count_fans(&self, v: usize, n_out: u32) -> usize {
        let mut seen: HashMap<u32, ()> = HashMap::new();
        let mut fans = 0;
        for h in 0..self.he_origin.len() {
            if self.he_origin[h] as usize == v && !seen.contains_key(&(h as u32)) {
                fans += 1;
                let mut g = h as u32;
                loop {
                    seen.insert(g, ());
                    g = self.he_prev[g as usize] ^ 1;
                    if seen.contains_key(&g) {
                        break;
                    }
                }
                if seen.len() as u32 >= n_out {
                    break;
                }
            }
        }
        fans
    }

    // ---- sizes ----
    /// Number of vertices.
    pub fn n_vertices(&self) -> usize {
        self.positions.len()
    }
    /// Number of faces.
    pub fn n_faces(&self) -> usize {
        self.face_he.len()
    }
    /// Number of half-edges (`2 · n_edges`).
    pub fn n_halfedges(&self) -> usize {
        self.he_origin.len()
    }
    /// Number of edges.
    pub fn n_edges(&self) -> usize {
        self.he_origin.len() / 2
    }
    /// Euler characteristic `V − E + F`.
    pub fn euler_characteristic(&self) -> i64 {
        self.n_vertices() as i64 - self.n_edges() as i64 + self.n_faces() as i64
    }

    // ---- geometry ----
    /// Position of vertex `v`.
    pub fn position(&self, v: VertexId) -> DVec3 {
        self.positions[v.idx()]
    }
    /// All vertex positions.
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }
    /// Moves vertex `v` (topology unchanged; no validation).
    pub fn set_position(&mut self, v: VertexId, p: DVec3) {
        self.positions[v.idx()] = p;
    }

    // ---- provenance ----
    /// Warnings collected while building (dropped isolated vertices).
    pub fn warnings(&self) -> &[MeshWarning] {
        &self.warnings
    }
    /// Index in the input mesh of vertex `v`.
    pub fn original_vertex(&self, v: VertexId) -> usize {
        self.original_vertex[v.idx()] as usize
    }
    /// Fills in source lines of the warnings and puts the reader's warnings
    /// ([`super::SourceMap::warnings`]) first (used by the file readers).
    pub fn annotate_warnings(&mut self, map: &super::SourceMap) {
        for w in &mut self.warnings {
            *w = w.clone().with_source(map);
        }
        self.warnings.splice(0..0, map.warnings.iter().cloned());
    }
    /// `new → input` vertex index map.
    pub fn original_vertices(&self) -> &[u32] {
        &self.original_vertex
    }

    // ---- connectivity ----
    /// One half-edge of face `f` (the one leaving the face's first corner).
    pub fn face_halfedge(&self, f: FaceId) -> HalfedgeId {
        HalfedgeId(self.face_he[f.idx()])
    }
    /// An outgoing half-edge of `v`; for a boundary vertex its outgoing boundary half-edge.
    pub fn vertex_halfedge(&self, v: VertexId) -> HalfedgeId {
        HalfedgeId(self.vertex_he[v.idx()])
    }
    /// Next half-edge in the same face (or boundary loop).
    pub fn next(&self, h: HalfedgeId) -> HalfedgeId {
        HalfedgeId(self.he_next[h.idx()])
    }
    /// Previous half-edge in the same face (or boundary loop).
    pub fn prev(&self, h: HalfedgeId) -> HalfedgeId {
        HalfedgeId(self.he_prev[h.idx()])
    }
    /// The opposite half-edge of the same edge.
    pub fn twin(&self, h: HalfedgeId) -> HalfedgeId {
        HalfedgeId(h.0 ^ 1)
    }
    /// Start vertex of `h`.
    pub fn origin(&self, h: HalfedgeId) -> VertexId {
        VertexId(self.he_origin[h.idx()])
    }
    /// End vertex of `h`.
    pub fn target(&self, h: HalfedgeId) -> VertexId {
        VertexId(self.he_origin[h.idx() ^ 1])
    }
    /// Face on the left of `h`; `None` for a boundary half-edge.
    pub fn face(&self, h: HalfedgeId) -> Option<FaceId> {
        let f = self.he_face[h.idx()];
        (f != NONE).then_some(FaceId(f))
    }
    /// Edge of `h`.
    pub fn edge(&self, h: HalfedgeId) -> EdgeId {
        EdgeId(h.0 / 2)
    }
    /// Half-edge `0` or `1` of edge `e` (`2e + i`).
    pub fn edge_halfedge(&self, e: EdgeId, i: u32) -> HalfedgeId {
        HalfedgeId(2 * e.0 + (i & 1))
    }
    /// End vertices of edge `e` (origin and target of its half-edge `2e`).
    pub fn edge_vertices(&self, e: EdgeId) -> (VertexId, VertexId) {
        let h = HalfedgeId(2 * e.0);
        (self.origin(h), self.target(h))
    }
    /// Counter-clockwise successor of the outgoing half-edge `h` around its origin:
    /// `twin(prev(h))`.
    pub fn ccw_rotated(&self, h: HalfedgeId) -> HalfedgeId {
        self.twin(self.prev(h))
    }
    /// Clockwise successor of the outgoing half-edge `h` around its origin: `next(twin(h))`.
    pub fn cw_rotated(&self, h: HalfedgeId) -> HalfedgeId {
        self.next(self.twin(h))
    }
    /// Whether `h` has no face.
    pub fn is_boundary_halfedge(&self, h: HalfedgeId) -> bool {
        self.he_face[h.idx()] == NONE
    }
    /// Whether one side of `e` has no face.
    pub fn is_boundary_edge(&self, e: EdgeId) -> bool {
        self.he_face[2 * e.idx()] == NONE || self.he_face[2 * e.idx() + 1] == NONE
    }
    /// Whether `v` lies on the boundary.
    pub fn is_boundary_vertex(&self, v: VertexId) -> bool {
        self.is_boundary_halfedge(self.vertex_halfedge(v))
    }
    /// Whether the mesh has no boundary.
    pub fn is_closed(&self) -> bool {
        self.he_face.iter().all(|&f| f != NONE)
    }

    // ---- iterators ----
    /// Half-edges of face `f` in order, starting at [`Self::face_halfedge`].
    pub fn face_halfedges(&self, f: FaceId) -> impl Iterator<Item = HalfedgeId> + '_ {
        let start = self.face_halfedge(f);
        self.loop_from(start)
    }
    /// Half-edges of the loop (face or boundary) through `start`, following `next`.
    pub fn loop_from(&self, start: HalfedgeId) -> impl Iterator<Item = HalfedgeId> + '_ {
        let mut cur = Some(start);
        std::iter::from_fn(move || {
            let h = cur?;
            let n = self.next(h);
            cur = (n != start).then_some(n);
            Some(h)
        })
    }
    /// Vertices of face `f` in order (counter-clockwise), starting with the input's first corner.
    pub fn face_vertices(&self, f: FaceId) -> impl Iterator<Item = VertexId> + '_ {
        self.face_halfedges(f).map(|h| self.origin(h))
    }
    /// Number of corners of face `f`.
    pub fn face_size(&self, f: FaceId) -> usize {
        self.face_halfedges(f).count()
    }
    /// Outgoing half-edges of `v`, counter-clockwise, starting at [`Self::vertex_halfedge`].
    pub fn vertex_outgoing(&self, v: VertexId) -> impl Iterator<Item = HalfedgeId> + '_ {
        let start = self.vertex_halfedge(v);
        let mut cur = Some(start);
        std::iter::from_fn(move || {
            let h = cur?;
            let n = self.ccw_rotated(h);
            cur = (n != start).then_some(n);
            Some(h)
        })
    }
    /// Faces around `v`, counter-clockwise (for a boundary vertex from the face next to the
    /// incoming boundary edge to the face next to the outgoing one).
    pub fn vertex_faces(&self, v: VertexId) -> impl Iterator<Item = FaceId> + '_ {
        self.vertex_outgoing(v).filter_map(|h| self.face(h))
    }
    /// Neighbouring vertices of `v`, counter-clockwise.
    pub fn vertex_vertices(&self, v: VertexId) -> impl Iterator<Item = VertexId> + '_ {
        self.vertex_outgoing(v).map(|h| self.target(h))
    }
    /// Number of edges at `v`.
    pub fn valence(&self, v: VertexId) -> usize {
        self.vertex_outgoing(v).count()
    }
    /// Boundary loops, each as its half-edges in `next` order (hole on the left); loops sorted by
    /// their smallest half-edge index, each starting at that half-edge.
    pub fn boundary_loops(&self) -> Vec<Vec<HalfedgeId>> {
        let mut seen = vec![false; self.n_halfedges()];
        let mut loops = Vec::new();
        for h in 0..self.n_halfedges() {
            if self.he_face[h] == NONE && !seen[h] {
                let lp: Vec<HalfedgeId> = self.loop_from(HalfedgeId(h as u32)).collect();
                for g in &lp {
                    seen[g.idx()] = true;
                }
                loops.push(lp);
            }
        }
        loops
    }
    /// Iterators over all ids.
    pub fn vertices(&self) -> impl Iterator<Item = VertexId> {
        (0..self.n_vertices() as u32).map(VertexId)
    }
    /// All face ids.
    pub fn faces(&self) -> impl Iterator<Item = FaceId> {
        (0..self.n_faces() as u32).map(FaceId)
    }
    /// All half-edge ids.
    pub fn halfedges(&self) -> impl Iterator<Item = HalfedgeId> {
        (0..self.n_halfedges() as u32).map(HalfedgeId)
    }
    /// All edge ids.
    pub fn edges(&self) -> impl Iterator<Item = EdgeId> {
        (0..self.n_edges() as u32).map(EdgeId)
    }
    /// The face loops as a plain [`PolyMesh`] (cleaned vertex numbering, input face order and
    /// corner order).
    pub fn to_polymesh(&self) -> PolyMesh {
        let creases = super::Creases {
            edges: self
                .edges()
                .filter(|&e| self.edge_crease(e) > 0.0)
                .map(|e| {
                    let (a, b) = self.edge_vertices(e);
                    ([a.0, b.0], self.edge_crease(e))
                })
                .collect(),
            vertices: self.vertices().filter(|&v| self.vertex_crease(v) > 0.0).map(|v| (v.0, self.vertex_crease(v))).collect(),
        };
        PolyMesh {
            positions: self.positions.clone(),
            faces: self.faces().map(|f| self.face_vertices(f).map(|v| v.0).collect()).collect(),
            creases,
            holes: Vec::new(),
        }
    }
}

fn count_boundary_out(origin: &[u32], face: &[u32], v: u32) -> usize {
    (0..origin.len()).filter(|&h| origin[h] == v && face[h] == NONE).count()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The ticked build reports increasing progress up to faces + vertices, stops at the first
    /// tick error, and builds the same mesh as the unticked one.
    #[test]
    fn ticked_build_reports_and_stops() {
        let mesh = crate::mesh::generate::torus(100, 100, 3.0, 1.0).unwrap();
        let total = mesh.faces.len() + mesh.positions.len();
        let mut seen = Vec::new();
        let he = HalfEdgeMesh::from_checked_polymesh_ticked::<MeshError>(&mesh, &mut |d, t| {
            assert_eq!(t, total);
            seen.push(d);
            Ok(())
        })
        .unwrap();
        assert!(seen.len() >= 4 && seen.windows(2).all(|w| w[0] <= w[1]), "{seen:?}");
        let plain = HalfEdgeMesh::from_checked_polymesh(&mesh).unwrap();
        assert_eq!((he.n_faces(), he.he_next.clone(), he.positions.clone()), (plain.n_faces(), plain.he_next, plain.positions));
        #[derive(Debug, PartialEq)]
        enum Stop {
            Mesh,
            Cancelled,
        }
        impl From<MeshError> for Stop {
            fn from(_: MeshError) -> Self {
                Stop::Mesh
            }
        }
        let mut calls = 0;
        let stopped = HalfEdgeMesh::from_checked_polymesh_ticked::<Stop>(&mesh, &mut |_, _| {
            calls += 1;
            if calls == 2 {
                Err(Stop::Cancelled)
            } else {
                Ok(())
            }
        });
        assert_eq!(stopped.err(), Some(Stop::Cancelled));
        assert_eq!(calls, 2);
    }
}

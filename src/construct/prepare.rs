//! Mesh preparation shared by both structures: dissolving interior valence-2 vertices, then
//! splitting concave faces ([`super::convex_mesh`]).
//!
//! Interior vertices of valence 2 (not in the seed; defined here). A manifold mesh may have an
//! interior vertex V with exactly two edges A–V and V–B; its two faces f and g then share both
//! edges (artist meshes have them, e.g. Blender's Suzanne). Neither structure can use V as it is:
//! its dual patch would have 2 sides and its tile degenerates to a segment (two tile vertices).
//! Rule: V is *dissolved* (like Blender's "Dissolve Vertices"): it is removed from the loops of f
//! and g, which then share the single edge A–B; V contributes no patch and its position no
//! longer influences the surface. A warning names every dissolved vertex. This never lowers the
//! valence of A or B (their edge to V becomes their edge to the other), so one pass removes all
//! of them (the pass is still repeated until none remain, bounded by the vertex count). A face
//! left with fewer than 3 corners, or an edge A–B that already exists elsewhere (the result would
//! not be manifold), is a [`ConstructError::Valence2`] naming the vertex and the face.
//! Splitting concave faces afterwards only adds edges, so it creates no new valence-2 vertices.
//! Boundary vertices of valence 2 (the corner of an open grid: one face) need nothing: their dual
//! patch has 3 sides and their tile 3 points (see [`super::dual`], [`super::topology`]).

use super::surface::PatchSource;
use super::ConstructError;
use super::surface::{CageSector, Diagonals, SectorMap};
use crate::mesh::{FaceId, HalfEdgeMesh, HalfedgeId};
use std::borrow::Cow;
use std::collections::HashMap;

/// The mesh the constructions work on and how it maps back to the input.
#[derive(Clone, Debug)]
pub struct Prepared<'a> {
    /// Interior valence-2 vertices dissolved, concave faces split.
    pub mesh: Cow<'a, HalfEdgeMesh>,
    /// `vertex_origin[v]`: the input vertex that vertex v of `mesh` is.
    pub vertex_origin: Vec<usize>,
    /// `face_origin[f]`: the input face that face f of `mesh` is (a part of).
    pub face_origin: Vec<usize>,
    /// `face_input[f]`: the face as the user wrote it that face f of `mesh` is (a part of): the
    /// concave split ([`Self::face_origin`]) composed with the hole split
    /// ([`HalfEdgeMesh::input_face`]); the one map for messages and cage corners.
    pub face_input: Vec<usize>,
    /// One warning per dissolved vertex (input numbering).
    pub warnings: Vec<String>,
}

impl Prepared<'_> {
    /// A patch source of the prepared mesh in the user's numbering: a vertex of the input mesh
    /// (splits add no vertices), a face as the user wrote it ([`Self::face_input`]: the pieces of
    /// a concave face or a face with holes share its source).
    pub fn source(&self, s: PatchSource) -> PatchSource {
        match s {
            PatchSource::Vertex(v) => PatchSource::Vertex(self.vertex_origin[v]),
            PatchSource::Face(f) => PatchSource::Face(self.input_face(FaceId(f as u32))),
        }
    }

    /// The input face (as the user wrote it) of face `f` of the prepared mesh: the concave split
    /// ([`Self::face_origin`]) composed with the hole split ([`HalfEdgeMesh::input_face`]).
    fn input_face(&self, f: FaceId) -> usize {
        self.face_input.get(f.idx()).copied().unwrap_or(f.idx())
    }

    /// The cage corner (the user's numbering) of half-edge `h` of the prepared mesh (its origin in
    /// its face), with `map`; `input` is the mesh the preparation started from. A face split
    /// into convex pieces (concave or with holes) maps to its input face, the corner to the
    /// user's corner index of the vertex ([`HalfEdgeMesh::input_corner`]). When the face's edge
    /// at h or at its previous half-edge is a split diagonal (the face across it comes from the
    /// same input face), the map sends that edge's midpoint to the face centre
    /// ([`SectorMap::across_diagonals`], docs/math.md#cage-corners).
    fn cage_corner(&self, input: &HalfEdgeMesh, h: HalfedgeId, map: SectorMap) -> CageSector {
        let m = &*self.mesh;
        let unknown = CageSector { face: u32::MAX, corner: u32::MAX, map };
        let Some(f) = m.face(h) else { return unknown };
        let g = self.face_origin.get(f.idx()).copied().unwrap_or(f.idx());
        let face = self.input_face(f);
        let vertex = self.vertex_origin.get(m.origin(h).idx()).copied().unwrap_or(m.origin(h).idx());
        let corner = if g < input.n_faces() {
            let mut around = input.face_halfedges(FaceId(g as u32));
            around.find(|&k| input.origin(k).idx() == vertex).and_then(|k| input.input_corner(k))
        } else {
            None
        };
        let map = map.across_diagonals(self.diagonals(h));
        CageSector { face: face as u32, corner: corner.map_or(u32::MAX, |c| c as u32), map }
    }

    /// Which edges of the cage corner at half-edge `h` of the prepared mesh (its origin in its
    /// face) are split diagonals: the edge of h (`next`) or of its previous half-edge (`prev`)
    /// has the same input face on both sides (docs/math.md#cage-corners).
    pub fn diagonals(&self, h: HalfedgeId) -> Diagonals {
        let m = &*self.mesh;
        let Some(f) = m.face(h) else { return Diagonals::default() };
        let face = self.input_face(f);
        let diagonal = |e: HalfedgeId| m.face(m.twin(e)).is_some_and(|o| self.input_face(o) == face);
        Diagonals { next: diagonal(h), prev: diagonal(m.prev(h)) }
    }

    /// Topology structure: per patch (face of the prepared mesh) and corner i (the origin of the
    /// face's i-th half-edge), its cage corner.
    pub fn cage_topology(&self, input: &HalfEdgeMesh) -> Vec<Vec<CageSector>> {
        let m = &*self.mesh;
        m.faces()
            .map(|f| m.face_halfedges(f).map(|h| self.cage_corner(input, h, SectorMap::Face)).collect())
            .collect()
    }

    /// Dual structure: per patch (vertex of the prepared mesh) and corner i (the i-th face around
    /// it in `vertex_outgoing` order), its cage corner. A boundary vertex with n outgoing
    /// half-edges has n + 1 corners: corner 0 (on the first boundary edge) maps to the first
    /// face, flattened ([`SectorMap::OpenStart`]); corners 1..n−1 to the faces; corner n (on the
    /// last boundary edge) to the last face ([`SectorMap::OpenEnd`]).
    pub fn cage_dual(&self, input: &HalfEdgeMesh) -> Vec<Vec<CageSector>> {
        let m = &*self.mesh;
        // The outgoing half-edges of each vertex in one reused buffer.
        let mut out: Vec<HalfedgeId> = Vec::new();
        m.vertices()
            .map(|v| {
                out.clear();
                out.extend(m.vertex_outgoing(v));
                let n = out.len();
                let at = |h: HalfedgeId, map| m.face(h).map(|_| self.cage_corner(input, h, map));
                let unknown = CageSector { face: u32::MAX, corner: u32::MAX, map: SectorMap::Vertex };
                if !m.is_boundary_vertex(v) || n < 2 {
                    return out.iter().map(|&h| at(h, SectorMap::Vertex).unwrap_or(unknown)).collect();
                }
                // g_k = out[k + 1]: g_0 .. g_{n−2} have faces, g_{n−1} is the boundary half-edge.
                let g = |k: usize| out[(k + 1) % n];
                let mut c = Vec::with_capacity(n + 1);
                c.push(at(g(0), SectorMap::OpenStart).unwrap_or(unknown));
                c.extend((1..n).map(|j| at(g(j - 1), SectorMap::Vertex).unwrap_or(unknown)));
                c.push(at(g(n - 2), SectorMap::OpenEnd).unwrap_or(unknown));
                c
            })
            .collect()
    }

    /// An error of the construction on the prepared mesh in the input numbering (vertex and face
    /// indices; patch indices when `patch_is_vertex`, as in the dual structure).
    pub fn error(&self, e: ConstructError, patch_is_vertex: bool) -> ConstructError {
        let v = |i: usize| self.vertex_origin.get(i).copied().unwrap_or(i);
        let f = |i: usize| self.input_face(FaceId(i as u32));
        match e {
            ConstructError::FoldedTile { vertex } => ConstructError::FoldedTile { vertex: v(vertex) },
            ConstructError::DegenerateTile { vertex } => ConstructError::DegenerateTile { vertex: v(vertex) },
            ConstructError::DegenerateFace { face } => ConstructError::DegenerateFace { face: f(face) },
            ConstructError::TooFewSides { patch, sides } if patch_is_vertex => {
                ConstructError::TooFewSides { patch: v(patch), sides }
            }
            e => e,
        }
    }
}

/// A mesh with its interior valence-2 vertices dissolved, the map new vertex → old vertex, and one
/// warning per dissolved vertex.
pub type Dissolved<'a> = (Cow<'a, HalfEdgeMesh>, Vec<usize>, Vec<String>);

/// Interior vertices of valence 2 of `mesh`, ascending.
pub fn interior_valence2(mesh: &HalfEdgeMesh) -> Vec<usize> {
    mesh.vertices().filter(|&v| !mesh.is_boundary_vertex(v) && mesh.valence(v) == 2).map(|v| v.idx()).collect()
}

/// Dissolves every interior valence-2 vertex (see the module doc). Returns the new mesh (borrowed
/// when there is none), the map new vertex → vertex of `mesh`, and one warning per dissolved
/// vertex. Face indices are unchanged.
pub fn dissolve_valence2(
    mesh: &HalfEdgeMesh,
) -> Result<Dissolved<'_>, ConstructError> {
    let mut cur: Cow<'_, HalfEdgeMesh> = Cow::Borrowed(mesh);
    let mut origin: Vec<usize> = (0..mesh.n_vertices()).collect();
    let mut warnings = Vec::new();
    for _ in 0..=mesh.n_vertices() {
        let doomed = interior_valence2(&cur);
        if doomed.is_empty() {
            return Ok((cur, origin, warnings));
        }
        let mut gone = vec![false; cur.n_vertices()];
        for &v in &doomed {
            gone[v] = true;
        }
        let mut pm = cur.to_polymesh();
        // Creases on the edges of a dissolved vertex go with it (its edges disappear).
        pm.creases.edges.retain(|&([a, b], _)| !gone[a as usize] && !gone[b as usize]);
        pm.creases.vertices.retain(|&(v, _)| !gone[v as usize]);
        let mut by_face: HashMap<usize, usize> = HashMap::new(); // face → a dissolved vertex of it
        for (fi, face) in pm.faces.iter_mut().enumerate() {
            if let Some(&v) = face.iter().find(|&&v| gone[v as usize]) {
                by_face.insert(fi, v as usize);
                face.retain(|&v| !gone[v as usize]);
                if face.len() < 3 {
                    return Err(ConstructError::Valence2 {
                        vertex: origin[v as usize],
                        face: fi,
                        reason: format!("the face would keep {} corners", face.len()),
                    });
                }
            }
        }
        // An edge A–B created by the dissolution must not exist elsewhere (the result would have
        // an edge with more than two faces or a face used twice in one direction).
        let mut uses: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
        for (fi, face) in pm.faces.iter().enumerate() {
            for i in 0..face.len() {
                let (a, b) = (face[i], face[(i + 1) % face.len()]);
                uses.entry((a.min(b), a.max(b))).or_default().push(fi);
            }
        }
        let mut bad: Option<(usize, usize)> = None;
        for fs in uses.values() {
            if fs.len() > 2 || (fs.len() == 2 && fs[0] == fs[1]) {
                if let Some(&fi) = fs.iter().find(|f| by_face.contains_key(f)) {
                    let cand = (fi, by_face[&fi]);
                    bad = Some(bad.map_or(cand, |b: (usize, usize)| b.min(cand)));
                }
            }
        }
        if let Some((fi, v)) = bad {
            return Err(ConstructError::Valence2 {
                vertex: origin[v],
                face: fi,
                reason: "the edge joining the vertex's two neighbours already exists".into(),
            });
        }
        let next = HalfEdgeMesh::from_polymesh(&pm).map_err(|e| ConstructError::Valence2 {
            vertex: origin[doomed[0]],
            face: by_face.keys().copied().min().unwrap_or(0),
            reason: e.to_string(),
        })?;
        for &v in &doomed {
            warnings.push(format!(
                "interior vertex {} has valence 2: dissolved (its two faces share the edge between its neighbours)",
                origin[v]
            ));
        }
        origin = next.original_vertices().iter().map(|&o| origin[o as usize]).collect();
        cur = Cow::Owned(next);
    }
    Err(ConstructError::Internal("dissolving valence-2 vertices did not terminate".into()))
}

/// Dissolves interior valence-2 vertices ([`dissolve_valence2`]), then splits concave faces
/// ([`super::convex_mesh`]).
pub fn prepare(mesh: &HalfEdgeMesh) -> Result<Prepared<'_>, ConstructError> {
    let input = mesh;
    // Faces named by an error here are faces of `input` (pieces of a face with holes included):
    // named as the user wrote them.
    // (`input_face` keeps an index it does not know.)
    let input_face = |f: usize| input.input_face(FaceId(f as u32));
    let user = |e: ConstructError| match e {
        ConstructError::DegenerateFace { face } => ConstructError::DegenerateFace { face: input_face(face) },
        ConstructError::Valence2 { vertex, face, reason } => ConstructError::Valence2 { vertex, face: input_face(face), reason },
        e => e,
    };
    let (dissolved, vertex_origin, warnings) = dissolve_valence2(mesh).map_err(user)?;
    let (mesh, face_origin) = match dissolved {
        Cow::Borrowed(m) => super::convex_mesh(m).map_err(user)?,
        Cow::Owned(m) => {
            let (c, o) = super::convex_mesh(&m).map_err(user)?;
            (Cow::Owned(c.into_owned()), o)
        }
    };
    let face_input = face_origin.iter().map(|&g| input_face(g)).collect();
    Ok(Prepared { mesh, vertex_origin, face_origin, face_input, warnings })
}

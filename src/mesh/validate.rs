//! Validation of a [`PolyMesh`] before any work is done on it.
//!
//! Checks, in this order (the first failure is returned, naming the element):
//! 1. no faces → [`MeshError::Empty`];
//! 2. every coordinate finite ([`MeshError::NonFiniteCoordinate`]) and of absolute value at most
//!    [`COORDINATE_LIMIT`] ([`MeshError::CoordinateRange`]);
//! 3. per face, in face order: at least 3 corners, indices in range, no repeated index, area
//!    not (relatively) zero (computed in a frame scaled by the face's size, so it cannot overflow);
//!    then the bounding box of the face vertices not too small relative to the coordinates'
//!    magnitude: extent ≥ [`MIN_RELATIVE_EXTENT`] · max |coordinate|
//!    ([`MeshError::UnresolvableExtent`], naming the first vertex of largest magnitude);
//! 4. no face repeated with the same orientation ([`MeshError::DuplicateFace`]);
//! 5. no edge shared by more than two faces ([`MeshError::NonManifoldEdge`]);
//! 6. no directed edge used twice ([`MeshError::InconsistentOrientation`]);
//! 7. no face repeated with the opposite orientation ([`MeshError::DuplicateFace`]);
//! 8. (in [`HalfEdgeMesh::from_polymesh`]) every vertex has a single fan of faces
//!    ([`MeshError::NonManifoldVertex`]).
//!
//! Isolated vertices (used by no face) are not errors: they are dropped, the remaining vertices
//! renumbered in order, and a [`MeshWarning::IsolatedVertex`] recorded.
//!
//! Steps 4–7 group corners by edge and faces by cycle without hash maps ([`super::edges`]):
//! linear in the mesh size but for one sort of the faces on a 64-bit key.
//!
//! [`HalfEdgeMesh::from_polymesh`]: super::halfedge::HalfEdgeMesh::from_polymesh

use super::error::{MeshError, MeshWarning, COORDINATE_LIMIT, ZERO_AREA_REL};
use super::geometry::newell_normal;
use super::halfedge::HalfEdgeMesh;
use super::PolyMesh;
use crate::limits::MIN_RELATIVE_EXTENT;
use glam::DVec3;
use rayon::prelude::*;
use super::edges::{cycle_groups, first_corners, Corners};
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// A small multiplicative (Fx-style) hasher for integer keys: the maps here are only looked up,
/// never iterated, so the hash function cannot change any result, only the speed.
#[derive(Default, Clone, Copy)]
pub(crate) struct FxHasher(u64);

impl FxHasher {
    #[inline]
    fn add(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(0x517c_c1b7_2722_0a95);
    }
}

impl Hasher for FxHasher {
    #[inline]
    fn finish(&self) -> u64 {
        self.0
    }
    #[inline]
    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut b = [0u8; 8];
            b[..chunk.len()].copy_from_slice(chunk);
            self.add(u64::from_le_bytes(b));
        }
    }
    #[inline]
    fn write_u32(&mut self, i: u32) {
        self.add(u64::from(i));
    }
    #[inline]
    fn write_u64(&mut self, i: u64) {
        self.add(i);
    }
    #[inline]
    fn write_usize(&mut self, i: usize) {
        self.add(i as u64);
    }
}

/// `HashMap` with [`FxHasher`].
pub(crate) type FxHashMap<K, V> = HashMap<K, V, BuildHasherDefault<FxHasher>>;

/// An empty [`FxHashMap`] with room for `n` entries.
pub(crate) fn fx_map<K, V>(n: usize) -> FxHashMap<K, V> {
    FxHashMap::with_capacity_and_hasher(n, Default::default())
}

/// A mesh that passed validation: cleaned (isolated vertices dropped), with warnings and the map
/// back to the input's vertex numbering.
#[derive(Clone, Debug, PartialEq)]
pub struct ValidMesh {
    /// The cleaned mesh (vertices renumbered).
    pub mesh: PolyMesh,
    /// What was changed on the way in.
    pub warnings: Vec<MeshWarning>,
    /// `original_vertex[v]` = index of the cleaned vertex `v` in the input mesh.
    pub original_vertex: Vec<u32>,
}

/// Validates `mesh` completely (all checks of this module, including the vertex-fan check of the
/// half-edge build) and returns the cleaned mesh.
pub fn validate(mesh: &PolyMesh) -> Result<ValidMesh, MeshError> {
    let he = HalfEdgeMesh::from_polymesh(mesh)?;
    Ok(ValidMesh {
        mesh: he.to_polymesh(),
        warnings: he.warnings().to_vec(),
        original_vertex: he.original_vertices().to_vec(),
    })
}

/// The extent check of step 3 of the module doc (faces already checked: indices in range).
fn check_extent(mesh: &PolyMesh) -> Result<(), MeshError> {
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    let (mut magnitude, mut vertex) = (0.0_f64, 0);
    for &i in mesh.faces.iter().flatten() {
        let p = mesh.positions[i as usize];
        lo = lo.min(p);
        hi = hi.max(p);
        let m = p.abs().max_element();
        if m > magnitude {
            (magnitude, vertex) = (m, i as usize);
        }
    }
    let extent = (hi - lo).max_element();
    if extent < MIN_RELATIVE_EXTENT * magnitude {
        return Err(MeshError::UnresolvableExtent { extent, magnitude, min_ratio: MIN_RELATIVE_EXTENT, vertex, line: None });
    }
    Ok(())
}

/// The crease checks of [`check_polymesh`]: every sharpness finite in [0, 1], every vertex of a
/// vertex crease below `n_vertices` (edge existence is checked when the half-edge structure is
/// built).
pub fn check_creases(creases: &super::Creases, n_vertices: usize) -> Result<(), MeshError> {
    let ok = |c: f64| (0.0..=1.0).contains(&c);
    for (entry, &([a, b], c)) in creases.edges.iter().enumerate() {
        if !ok(c) {
            return Err(MeshError::EdgeCreaseValue { entry, edge: (a as usize, b as usize), value: c, line: None });
        }
    }
    for (entry, &(v, c)) in creases.vertices.iter().enumerate() {
        if v as usize >= n_vertices {
            return Err(MeshError::CreaseVertexOutOfRange { entry, vertex: v as usize, n_vertices, line: None });
        }
        if !ok(c) {
            return Err(MeshError::VertexCreaseValue { entry, vertex: v as usize, value: c, line: None });
        }
    }
    Ok(())
}

/// Checks 1–7 of the module doc (everything that needs no half-edge structure) and the crease
/// values ([`check_creases`]).
pub fn check_polymesh(mesh: &PolyMesh) -> Result<(), MeshError> {
    if mesh.faces.is_empty() {
        return Err(MeshError::Empty);
    }
    check_creases(&mesh.creases, mesh.positions.len())?;
    // Per vertex and per face in parallel; the error of the first offending element (as the
    // sequential loops found it).
    let coordinate_error = |(v, p): (usize, &DVec3)| -> Option<MeshError> {
        for axis in 0..3 {
            let x = p[axis];
            if !x.is_finite() {
                return Some(MeshError::NonFiniteCoordinate { vertex: v, axis, value: x, line: None });
            }
            if x.abs() > COORDINATE_LIMIT {
                return Some(MeshError::CoordinateRange { vertex: v, axis, value: x, limit: COORDINATE_LIMIT, line: None });
            }
        }
        None
    };
    if let Some(e) = mesh.positions.par_iter().enumerate().with_min_len(PAR_MIN).find_map_first(coordinate_error) {
        return Err(e);
    }
    // Corner buffers per worker, reused over its faces.
    let face_errors = mesh.faces.par_iter().enumerate().with_min_len(PAR_MIN);
    let face_errors =
        face_errors.map_init(<[Vec<DVec3>; 2]>::default, |buf, (f, face)| face_error(mesh, f, face, buf).err());
    if let Some(e) = face_errors.find_map_first(|e| e) {
        return Err(e);
    }
    check_extent(mesh)?;
    // 4.–7. from one grouping of equal cycles and one of corners by edge (super::edges).
    let groups = cycle_groups(&mesh.faces);
    // 4. the first face (in face order) repeating an earlier face's oriented cycle.
    let same = groups.iter().flat_map(|g| {
        [true, false].into_iter().filter_map(move |o| {
            let mut it = g.iter().filter(move |x| x.1 == o).map(|x| x.0);
            let first = it.next()?;
            Some((it.next()?, first))
        })
    });
    if let Some((face, first)) = same.min() {
        return Err(MeshError::DuplicateFace { face, first, line: None });
    }
    let corners = Corners::new(&mesh.faces).ok_or_else(|| MeshError::Degenerate(format!("more than {} face corners", u32::MAX)))?;
    let first = first_corners(&corners, mesh.positions.len());
    // 5. the first corner (in face order) of an edge used more than twice; its faces in order.
    let mut uses = vec![0u8; corners.len()];
    for &c in &first {
        uses[c as usize] = uses[c as usize].saturating_add(1);
    }
    if let Some(c) = (0..corners.len()).find(|&c| uses[c] > 2) {
        let (a, b) = corners.edge(corners.face_of(c), c);
        let faces = (0..corners.len()).filter(|&d| first[d] as usize == c).map(|d| corners.face_of(d)).collect();
        return Err(MeshError::NonManifoldEdge { edge: (a.min(b) as usize, a.max(b) as usize), faces, line: None });
    }
    // 6. the first corner whose directed edge an earlier corner has (edges have ≤ 2 uses now).
    let again = corners.iter().find(|&(_, c)| {
        let e = first[c] as usize;
        e != c && corners.verts[e] == corners.verts[c]
    });
    if let Some((f, c)) = again {
        let (a, b) = corners.edge(f, c);
        return Err(MeshError::InconsistentOrientation { edge: (a as usize, b as usize), faces: (corners.face_of(first[c] as usize), f), line: None });
    }
    // 7. a face repeating an earlier face's cycle reversed (each orientation once per group now):
    // the later face of the pair, the first such in face order.
    let opposite = groups.iter().filter_map(|g| {
        let a = g.iter().find(|x| x.1)?.0;
        let b = g.iter().find(|x| !x.1)?.0;
        Some((a.max(b), a.min(b)))
    });
    match opposite.min() {
        Some((face, first)) => Err(MeshError::DuplicateFace { face, first, line: None }),
        None => Ok(()),
    }
}

/// Least items per parallel task of [`check_polymesh`]'s per-element passes.
const PAR_MIN: usize = 1024;

/// The checks of one face `f` of [`check_polymesh`] that need nothing else: at least three
/// corners, indices in range, no repeated index (named at its second use), area above zero.
/// `buf`: two scratch buffers for the corners (reused over faces).
fn face_error(mesh: &PolyMesh, f: usize, face: &[u32], buf: &mut [Vec<DVec3>; 2]) -> Result<(), MeshError> {
    let nv = mesh.positions.len();
    if face.len() < 3 {
        return Err(MeshError::FaceTooSmall { face: f, len: face.len(), line: None });
    }
    for (c, &i) in face.iter().enumerate() {
        if i as usize >= nv {
            return Err(MeshError::IndexOutOfRange { face: f, corner: c, index: i as i64, n_vertices: nv, line: None });
        }
    }
    // Small faces by a quadratic scan, large ones through a hash set: the same first repeat.
    let repeated = if face.len() <= 16 {
        (1..face.len()).find(|&c| face[..c].contains(&face[c]))
    } else {
        let mut seen: FxHashMap<u32, ()> = fx_map(face.len());
        face.iter().position(|&i| seen.insert(i, ()).is_some())
    };
    if let Some(c) = repeated {
        return Err(MeshError::RepeatedIndex { face: f, vertex: face[c] as usize, line: None });
    }
    let [pts, local] = buf;
    pts.clear();
    pts.extend(face.iter().map(|&i| mesh.positions[i as usize]));
    let (area, h) = scaled_area(pts, local);
    // relative to d² with d = 2h the largest extent: area/4 ≤ ZERO_AREA_REL
    if area * 0.25 <= ZERO_AREA_REL {
        return Err(MeshError::ZeroAreaFace { face: f, area: area * h * h, line: None });
    }
    Ok(())
}

/// Area of the polygon scaled to unit size, and the scale `h` (half the largest bounding-box
/// extent; the scaled polygon fits in `[-1, 1]³`): the true area is `area · h²`. Scaling first
/// keeps every product finite for any finite input.
/// `local` is a scratch buffer for the scaled corners (reused over polygons).
pub(crate) fn scaled_area(pts: &[DVec3], local: &mut Vec<DVec3>) -> (f64, f64) {
    let (lo, hi) = pts
        .iter()
        .fold((DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)), |(lo, hi), p| {
            (lo.min(*p), hi.max(*p))
        });
    let h = (hi * 0.5 - lo * 0.5).max_element();
    if !(h > 0.0) || !h.is_finite() {
        return (0.0, h);
    }
    let c_half = lo * 0.25 + hi * 0.25;
    local.clear();
    local.extend(pts.iter().map(|p| (*p * 0.5 - c_half) / (h * 0.5)));
    (0.5 * newell_normal(local).length(), h)
}

/// Drops vertices used by no face; returns the renumbered mesh, `new → old` vertex map and one
/// warning per dropped vertex. Assumes indices are in range.
pub(crate) fn drop_isolated(mesh: &PolyMesh) -> (std::borrow::Cow<'_, PolyMesh>, Vec<u32>, Vec<MeshWarning>) {
    let mut used = vec![false; mesh.positions.len()];
    for face in &mesh.faces {
        for &i in face {
            used[i as usize] = true;
        }
    }
    // Nothing to drop (every subdivision level): the mesh itself, numbered as it is.
    if used.iter().all(|&u| u) {
        return (std::borrow::Cow::Borrowed(mesh), (0..mesh.positions.len() as u32).collect(), Vec::new());
    }
    let mut new_index = vec![u32::MAX; mesh.positions.len()];
    let mut old = Vec::new();
    let mut positions = Vec::new();
    let mut warnings = Vec::new();
    for (v, &u) in used.iter().enumerate() {
        if u {
            new_index[v] = positions.len() as u32;
            positions.push(mesh.positions[v]);
            old.push(v as u32);
        } else {
            warnings.push(MeshWarning::IsolatedVertex { vertex: v, line: None });
        }
    }
    let faces = mesh
        .faces
        .iter()
        .map(|f| f.iter().map(|&i| new_index[i as usize]).collect())
        .collect();
    (std::borrow::Cow::Owned(PolyMesh::new(positions, faces)), old, warnings)
}

//! Attributes of the control mesh carried to the output's face corners (docs/math.md#cage-corners):
//! the "keep corners" rule of Subdivision Surface, for UV maps and any other per-face-corner data.
//!
//! For an output face corner (loop) in cage corner (f, k) at cage coordinates (σ, τ):
//!
//! a(σ, τ) = (1−τ)·[(1−σ)·a_k + σ·½(a_k + a_{k+1})] + τ·[(1−σ)·½(a_k + a_{k−1}) + σ·ā],
//!
//! a_k the value at corner k of face f, a_{k±1} its neighbours in the face (for a face with holes:
//! in k's own loop), ā the mean over the face's corners (all its loops). The four values are
//! tabulated once per cage corner; each loop then costs four reads and three lerps. One
//! definition for every adapter: the Blender add-on, C and C++ call it through
//! `gbsurf_cage_loop_values` (`gbsurf_cage_loop_values_holed` for faces with holes).

use crate::limits::MAX_CAGE_VALUE_DIM;
use rayon::prelude::*;

/// Where the output's face corners lie in the cage (the arrays of [`super::SurfaceMesh`]).
#[derive(Clone, Copy, Debug)]
pub struct CageLoops<'a> {
    /// Per output face: its cage corner `[face, corner]` ([`super::SurfaceMesh::cage_corner`]).
    pub face_corner: &'a [[u32; 2]],
    /// Per loop: its own cage corner (the triangle layout's
    /// [`super::SurfaceMesh::cage_loop_corner`]), or empty: then every loop takes its face's, the
    /// loops of face i being `m·i .. m·i + m` with m = loops / faces.
    pub loop_corner: &'a [[u32; 2]],
    /// Per loop: (σ, τ) in its cage corner ([`super::SurfaceMesh::cage_coords`]).
    pub coords: &'a [[f64; 2]],
}

/// Why cage values could not be interpolated; indices as the caller gave them.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CageValuesError {
    #[error("the value dimension is 0 (give at least one value per face corner)")]
    ZeroDimension,
    #[error("{dim} values per face corner: at most {max} are carried")]
    DimensionTooLarge { dim: usize, max: usize },
    #[error("cage face {face} has {size} corners: a face needs at least 3")]
    FaceTooSmall { face: usize, size: u32 },
    #[error("hole {hole} has {size} corners: a hole needs at least 3")]
    HoleTooSmall { hole: usize, size: u32 },
    #[error("hole {hole} belongs to cage face {face}, but the cage has {faces} faces")]
    HoleFaceOutOfRange { hole: usize, face: u32, faces: usize },
    #[error("{what}: {got} where {expected} are needed")]
    WrongLength { what: &'static str, expected: usize, got: usize },
    #[error("face_corner: {faces} output faces (pairs) cannot share the {loops} face corners of coords evenly")]
    UnevenFaces { loops: usize, faces: usize },
    #[error("output face corner {index} lies in cage face {face}, but the cage has {faces} faces (the face sizes are not those of the cage the result was built from)")]
    FaceOutOfRange { index: usize, face: u32, faces: usize },
    #[error("output face corner {index} lies in corner {corner} of cage face {face}, which has {size} corners (the face sizes are not those of the cage the result was built from)")]
    CornerOutOfRange { index: usize, face: u32, corner: u32, size: u32 },
    #[error("cage coordinates of output face corner {index} are not finite")]
    NotFinite { index: usize },
    #[error("the result has no cage maps: convert with ConvertOptions::cage_maps on to carry cage values over")]
    NoCageMaps,
}

/// The faces of the cage the values are given for (the mesh the result was built from).
/// Values are given per face corner in the user's numbering (docs/math.md#cage-corners): face by
/// face, the corners of its outer loop, then those of each of its holes in hole order. A slice
/// of face sizes converts into faces without holes.
#[derive(Clone, Copy, Debug, Default)]
pub struct CageFaces<'a> {
    /// Per face: the corner count of its (outer) loop, in input order.
    pub sizes: &'a [u32],
    /// Per hole (inner loop, in the order of [`crate::mesh::PolyMesh::holes`]): its face.
    pub hole_faces: &'a [u32],
    /// Per hole: its corner count (one per entry of `hole_faces`).
    pub hole_sizes: &'a [u32],
}

impl<'a, T: AsRef<[u32]> + ?Sized> From<&'a T> for CageFaces<'a> {
    fn from(sizes: &'a T) -> Self {
        CageFaces { sizes: sizes.as_ref(), hole_faces: &[], hole_sizes: &[] }
    }
}

/// The loops of [`CageFaces`] in value order: `start[l]` the first value corner of loop l
/// (face by face: outer loop, then its holes in order; a last entry = the corner total) and
/// `face[f]` the index of face f's outer loop (a last entry = the loop count).
struct LoopStarts {
    start: Vec<usize>,
    face: Vec<usize>,
}

impl LoopStarts {
    fn new(faces: CageFaces<'_>) -> Result<Self, CageValuesError> {
        let (nf, nh) = (faces.sizes.len(), faces.hole_faces.len());
        if faces.hole_sizes.len() != nh {
            let got = faces.hole_sizes.len();
            return Err(CageValuesError::WrongLength { what: "hole sizes (one per hole face)", expected: nh, got });
        }
        // Holes grouped by face, in order (a counting sort).
        let mut first = vec![0usize; nf + 1];
        for (hole, (&face, &size)) in faces.hole_faces.iter().zip(faces.hole_sizes).enumerate() {
            if face as usize >= nf {
                return Err(CageValuesError::HoleFaceOutOfRange { hole, face, faces: nf });
            }
            if size < 3 {
                return Err(CageValuesError::HoleTooSmall { hole, size });
            }
            first[face as usize + 1] += 1;
        }
        for f in 0..nf {
            first[f + 1] += first[f];
        }
        let mut order = vec![0usize; nh];
        let mut next = first.clone();
        for (hole, &face) in faces.hole_faces.iter().enumerate() {
            order[next[face as usize]] = hole;
            next[face as usize] += 1;
        }
        let mut start = Vec::with_capacity(nf + nh + 1);
        let mut face = Vec::with_capacity(nf + 1);
        let mut total = 0usize;
        // A corner count that does not fit in usize (sizes made up on a 32-bit target) is a wrong
        // length, never a wrapped sum.
        let overflow = || CageValuesError::WrongLength { what: "corner count (sum of the face and hole sizes)", expected: usize::MAX, got: usize::MAX };
        for (f, &size) in faces.sizes.iter().enumerate() {
            if size < 3 {
                return Err(CageValuesError::FaceTooSmall { face: f, size });
            }
            face.push(start.len());
            start.push(total);
            total = total.checked_add(size as usize).ok_or_else(overflow)?;
            for &h in &order[first[f]..first[f + 1]] {
                start.push(total);
                total = total.checked_add(faces.hole_sizes[h] as usize).ok_or_else(overflow)?;
            }
        }
        face.push(start.len());
        start.push(total);
        Ok(LoopStarts { start, face })
    }

    fn total(&self) -> usize {
        self.start[self.start.len() - 1]
    }

    /// The first value corner of face f and its corner count (all its loops).
    fn face_range(&self, f: usize) -> (usize, usize) {
        let (a, b) = (self.start[self.face[f]], self.start[self.face[f + 1]]);
        (a, b - a)
    }
}

/// Loops per parallel task.
const CHUNK: usize = 1 << 14;

/// The keep-corners values (module doc) of `values` (`dim` values per cage face corner, in the
/// face-corner order of `faces`: face sizes, or [`CageFaces`] with holes) at every loop of
/// `loops`: `dim` values per loop, in loop order. Loops in an unknown cage corner (`u32::MAX`,
/// e.g. a hand-built surface) get 0. Values are f32 (like Blender's UVs and weights); the face
/// means are summed in f64. A corner of a face with holes takes its neighbours a_{k±1} in its
/// own loop and ā over all the face's corners.
pub fn cage_loop_values<'a>(
    faces: impl Into<CageFaces<'a>>,
    values: &[f32],
    dim: usize,
    loops: CageLoops<'_>,
) -> Result<Vec<f32>, CageValuesError> {
    check_dim(dim)?;
    let mut out = vec![0f32; loops.coords.len() * dim];
    cage_loop_values_into(faces, values, dim, loops, &mut out)?;
    Ok(out)
}

/// 0 < dim ≤ [`MAX_CAGE_VALUE_DIM`].
fn check_dim(dim: usize) -> Result<(), CageValuesError> {
    match dim {
        0 => Err(CageValuesError::ZeroDimension),
        d if d > MAX_CAGE_VALUE_DIM => Err(CageValuesError::DimensionTooLarge { dim, max: MAX_CAGE_VALUE_DIM }),
        _ => Ok(()),
    }
}

/// [`cage_loop_values`] written into `out` (`dim` × loops values; the C ABI's buffer). `out` is
/// written only when every input is valid.
pub fn cage_loop_values_into<'a>(
    faces: impl Into<CageFaces<'a>>,
    values: &[f32],
    dim: usize,
    loops: CageLoops<'_>,
    out: &mut [f32],
) -> Result<(), CageValuesError> {
    check_dim(dim)?;
    let layout = LoopStarts::new(faces.into())?;
    let n_faces = layout.face.len() - 1;
    let total = layout.total();
    // dim ≤ MAX_CAGE_VALUE_DIM and every length below isize::MAX bytes: no product overflows,
    // but a wrong count must never wrap, so the products saturate (and then cannot match).
    let expected = total.saturating_mul(dim);
    if values.len() != expected {
        return Err(CageValuesError::WrongLength { what: "values (dim per cage face corner)", expected, got: values.len() });
    }
    let n = loops.coords.len();
    let expected = n.saturating_mul(dim);
    if out.len() != expected {
        return Err(CageValuesError::WrongLength { what: "out (dim per coords pair)", expected, got: out.len() });
    }
    // Loops per output face, or None when every loop has its own corner.
    let per_face = if !loops.loop_corner.is_empty() {
        if loops.loop_corner.len() != n {
            return Err(CageValuesError::WrongLength { what: "loop_corner pairs (one per coords pair)", expected: n, got: loops.loop_corner.len() });
        }
        None
    } else if n == 0 {
        Some(1)
    } else if loops.face_corner.is_empty() || !n.is_multiple_of(loops.face_corner.len()) {
        return Err(CageValuesError::UnevenFaces { loops: n, faces: loops.face_corner.len() });
    } else {
        Some(n / loops.face_corner.len())
    };
    let corner_of = |i: usize| match per_face {
        None => loops.loop_corner[i],
        Some(m) => loops.face_corner[i / m],
    };
    // Every loop's corner is checked before anything is written; the first bad loop is named.
    let bad = |i: usize| -> Option<CageValuesError> {
        let [f, k] = corner_of(i);
        if f == u32::MAX || k == u32::MAX {
            return None;
        }
        if f as usize >= n_faces {
            return Some(CageValuesError::FaceOutOfRange { index: i, face: f, faces: n_faces });
        }
        let size = layout.face_range(f as usize).1 as u32;
        if k >= size {
            Some(CageValuesError::CornerOutOfRange { index: i, face: f, corner: k, size })
        } else if !loops.coords[i].iter().all(|x| x.is_finite()) {
            Some(CageValuesError::NotFinite { index: i })
        } else {
            None
        }
    };
    if let Some(i) = (0..n).into_par_iter().with_min_len(CHUNK).find_first(|&i| bad(i).is_some()) {
        return Err(bad(i).expect("found above"));
    }
    // Per face its mean (summed in f64), then per cage corner g: [a_k, ½(a_k + a_{k+1}), ā,
    // ½(a_k + a_{k−1})], dim values each (k±1 within g's loop).
    let mut means = vec![0f32; n_faces * dim];
    means.par_chunks_mut(dim).enumerate().for_each(|(f, m)| {
        let (s, size) = layout.face_range(f);
        for (d, x) in m.iter_mut().enumerate() {
            *x = ((s..s + size).map(|j| values[j * dim + d] as f64).sum::<f64>() / size as f64) as f32;
        }
    });
    let mut table = vec![0f32; 4 * total * dim];
    table.par_chunks_mut(4 * dim * 64).enumerate().for_each(|(chunk, rows)| {
        for (r, row) in rows.chunks_mut(4 * dim).enumerate() {
            let g = chunk * 64 + r;
            let l = layout.start.partition_point(|&s| s <= g) - 1;
            let f = layout.face.partition_point(|&i| i <= l) - 1;
            let (s, size) = (layout.start[l], layout.start[l + 1] - layout.start[l]);
            let k = g - s;
            let at = |j: usize| &values[(s + j) * dim..(s + j + 1) * dim];
            let (a, next, prev) = (at(k), at((k + 1) % size), at((k + size - 1) % size));
            for d in 0..dim {
                row[d] = a[d];
                row[dim + d] = 0.5 * (a[d] + next[d]);
                row[2 * dim + d] = means[f * dim + d];
                row[3 * dim + d] = 0.5 * (a[d] + prev[d]);
            }
        }
    });
    out.par_chunks_mut(CHUNK * dim).enumerate().for_each(|(chunk, part)| {
        for (j, o) in part.chunks_mut(dim).enumerate() {
            let i = chunk * CHUNK + j;
            let [f, k] = corner_of(i);
            if f == u32::MAX || k == u32::MAX {
                o.fill(0.0);
                continue;
            }
            let g = layout.face_range(f as usize).0 + k as usize;
            let row = &table[4 * g * dim..4 * (g + 1) * dim];
            let [s, t] = loops.coords[i].map(|x| x as f32);
            for d in 0..dim {
                let low = row[d] + s * (row[dim + d] - row[d]);
                let high = row[3 * dim + d] + s * (row[2 * dim + d] - row[3 * dim + d]);
                o[d] = low + t * (high - low);
            }
        }
    });
    Ok(())
}

impl super::SurfaceMesh {
    /// [`cage_loop_values`] at this mesh's face corners (quads, or triangles in the triangle
    /// layout; empty for the subdivision methods), for the cage `faces` it was built from (face
    /// sizes, or [`CageFaces`] with holes). [`CageValuesError::NoCageMaps`] when the mesh has
    /// faces but was converted with [`crate::options::ConvertOptions::cage_maps`] off (no cage
    /// corners at all).
    pub fn cage_loop_values<'a>(
        &self,
        faces: impl Into<CageFaces<'a>>,
        values: &[f32],
        dim: usize,
    ) -> Result<Vec<f32>, CageValuesError> {
        if self.cage_corner.is_empty() && !(self.quads.is_empty() && self.triangles.is_empty()) {
            return Err(CageValuesError::NoCageMaps);
        }
        let loops = CageLoops { face_corner: &self.cage_corner, loop_corner: &self.cage_loop_corner, coords: &self.cage_coords };
        cage_loop_values(faces, values, dim, loops)
    }
}

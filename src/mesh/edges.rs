//! Corners grouped by undirected edge, and faces grouped by cycle, without hash maps: the
//! bookkeeping behind checks 4–7 of [`super::validate`] and the edges of
//! [`super::halfedge::HalfEdgeMesh`].
//!
//! Corners are numbered in face order: corner c of the mesh is corner i of face f, and stands for
//! the directed edge (face[i], face[i+1]). Two corners share an undirected edge when their
//! edges have the same two vertices. [`first_corners`] gives every corner the least-numbered
//! corner with its edge (the edge's first use when the faces are read in order), by a counting
//! sort of the corners on the smaller vertex of their edge: each vertex's bucket is scanned in
//! corner order (sorted by the other vertex first when it has more than
//! [`SCAN_LIMIT`] entries, so a vertex of valence k costs O(k log k), never O(k²)). Linear in the
//! number of corners otherwise, with two passes over flat arrays. The per-edge hash maps it
//! replaces took about as many instructions but missed the cache: reading the 40k-quad torus
//! into the half-edge structure took 3–5× as long (`examples/mesh_build`).
//!
//! Faces with the same cycle up to rotation and reversal are found by [`cycle_groups`]: a sort
//! of the faces on (least vertex, its smaller neighbour), refined by the whole cycle read from
//! the least vertex towards that neighbour.

use rayon::prelude::*;
use std::cmp::Ordering;

/// Buckets of at most this many corners are scanned pairwise; larger ones are sorted.
const SCAN_LIMIT: usize = 16;

/// The faces' corners in one flat array: corner c is `verts[c]`, face f has corners
/// `start[f]..start[f + 1]`.
pub(crate) struct Corners {
    pub start: Vec<u32>,
    pub verts: Vec<u32>,
}

impl Corners {
    /// The corners of `faces`; `None` when there are more than `u32::MAX` of them (no corner
    /// number fits then; no cage of that size fits in memory either).
    pub fn new(faces: &[Vec<u32>]) -> Option<Corners> {
        let mut start = Vec::with_capacity(faces.len() + 1);
        let mut verts = Vec::with_capacity(faces.iter().map(Vec::len).sum());
        start.push(0);
        for face in faces {
            verts.extend_from_slice(face);
            start.push(u32::try_from(verts.len()).ok()?);
        }
        Some(Corners { start, verts })
    }

    /// The number of corners.
    pub fn len(&self) -> usize {
        self.verts.len()
    }

    /// The directed edge of corner `c` of face `f`: (its vertex, the next corner's vertex).
    #[inline]
    pub fn edge(&self, f: usize, c: usize) -> (u32, u32) {
        let next = if c + 1 == self.start[f + 1] as usize { self.start[f] as usize } else { c + 1 };
        (self.verts[c], self.verts[next])
    }

    /// The face of corner `c`.
    pub fn face_of(&self, c: usize) -> usize {
        self.start.partition_point(|&s| s as usize <= c) - 1
    }

    /// Calls `visit(c, a, b)` for every corner c in order with its directed edge (a, b).
    #[inline]
    pub fn for_each_edge(&self, mut visit: impl FnMut(usize, u32, u32)) {
        for f in 0..self.start.len() - 1 {
            let (c0, c1) = (self.start[f] as usize, self.start[f + 1] as usize);
            let face = &self.verts[c0..c1];
            let Some(&last) = face.last() else { continue };
            for (i, w) in face.windows(2).enumerate() {
                visit(c0 + i, w[0], w[1]);
            }
            visit(c1 - 1, last, face[0]);
        }
    }

    /// Every corner with its face: (f, c) in corner order.
    pub fn iter(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        (0..self.start.len() - 1).flat_map(move |f| (self.start[f] as usize..self.start[f + 1] as usize).map(move |c| (f, c)))
    }
}

/// Per corner, the least-numbered corner whose edge has the same two vertices (module doc).
/// `n_vertices` bounds the corners' vertices.
pub(crate) fn first_corners(corners: &Corners, n_vertices: usize) -> Vec<u32> {
    // Counting sort on the smaller vertex: bucket v holds (other vertex, corner) in corner order.
    let mut start = vec![0u32; n_vertices + 1];
    corners.for_each_edge(|_, a, b| start[a.min(b) as usize + 1] += 1);
    for v in 0..n_vertices {
        start[v + 1] += start[v];
    }
    let mut fill = start.clone();
    let mut bucket = vec![(0u32, 0u32); corners.len()];
    corners.for_each_edge(|c, a, b| {
        let slot = &mut fill[a.min(b) as usize];
        bucket[*slot as usize] = (a.max(b), c as u32);
        *slot += 1;
    });
    let mut first = vec![0u32; corners.len()];
    for v in 0..n_vertices {
        let entries = &mut bucket[start[v] as usize..start[v + 1] as usize];
        if entries.len() <= SCAN_LIMIT {
            for j in 0..entries.len() {
                let (w, c) = entries[j];
                first[c as usize] = entries[..j].iter().find(|e| e.0 == w).map_or(c, |e| e.1);
            }
        } else {
            // Sorted on (other vertex, corner): each run's first entry is its least corner.
            entries.sort_unstable();
            let mut run = 0;
            for j in 0..entries.len() {
                if entries[j].0 != entries[run].0 {
                    run = j;
                }
                first[entries[j].1 as usize] = entries[run].1;
            }
        }
    }
    first
}

/// Face f's cycle read from its least vertex towards the smaller of that vertex's two
/// neighbours: (the corner to start at, +1 or −1). Same for a rotated or reversed cycle.
fn canonical_start(face: &[u32]) -> (usize, bool) {
    let n = face.len();
    let k = (0..n).min_by_key(|&i| face[i]).unwrap_or(0);
    (k, face[(k + 1) % n] <= face[(k + n - 1) % n])
}

/// The cycle of `face` from [`canonical_start`].
fn canonical(face: &[u32]) -> impl Iterator<Item = u32> + '_ {
    let n = face.len();
    let (k, forward) = canonical_start(face);
    (0..n).map(move |i| face[if forward { (k + i) % n } else { (k + n - i) % n }])
}

/// Two faces ordered by length, then by their cycles from [`canonical_start`].
fn cmp_cycles(a: &[u32], b: &[u32]) -> Ordering {
    a.len().cmp(&b.len()).then_with(|| canonical(a).cmp(canonical(b)))
}

/// Faces with equal cycles up to rotation and reversal, in groups of two or more: each group
/// as (face, reads forward) in face order, `reads forward` telling the orientation (two faces of
/// a group are the same oriented cycle iff their flags agree). Faces with fewer than three
/// corners are left out.
pub(crate) fn cycle_groups(faces: &[Vec<u32>]) -> Vec<Vec<(usize, bool)>> {
    // A cheap key first: (least vertex, its smaller neighbour); equal cycles have equal keys.
    let key = |face: &[u32]| -> u64 {
        let n = face.len();
        let (k, _) = canonical_start(face);
        (u64::from(face[k]) << 32) | u64::from(face[(k + 1) % n].min(face[(k + n - 1) % n]))
    };
    let mut order: Vec<(u64, u32)> =
        faces.par_iter().enumerate().filter(|(_, f)| f.len() >= 3).map(|(i, f)| (key(f), i as u32)).collect();
    order.par_sort_unstable();
    let mut groups = Vec::new();
    let mut i = 0;
    while i < order.len() {
        let mut j = i + 1;
        while j < order.len() && order[j].0 == order[i].0 {
            j += 1;
        }
        if j - i >= 2 {
            let mut run: Vec<u32> = order[i..j].iter().map(|e| e.1).collect();
            run.sort_by(|&x, &y| cmp_cycles(&faces[x as usize], &faces[y as usize]).then(x.cmp(&y)));
            let mut s = 0;
            for t in 1..=run.len() {
                if t == run.len() || cmp_cycles(&faces[run[s] as usize], &faces[run[t] as usize]) != Ordering::Equal {
                    if t - s >= 2 {
                        groups.push(run[s..t].iter().map(|&f| (f as usize, canonical_start(&faces[f as usize]).1)).collect());
                    }
                    s = t;
                }
            }
        }
        i = j;
    }
    groups
}

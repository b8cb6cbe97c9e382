//! Shared test helper for the cage-corner tests: the keep-corners rule (docs/math.md#cage-corners)
//! evaluated independently in f64, with the cage's own positions as the attribute.
#![allow(dead_code)]

use gbsurf::mesh::PolyMesh;
use gbsurf::tessellate::SurfaceMesh;
use glam::DVec3;
use std::collections::HashMap;

/// The loops of face f as the user wrote them: its outer loop, then its holes' loops in hole order
/// (the user's corner numbering, docs/math.md#cage-corners).
pub fn user_loops(cage: &PolyMesh, f: usize) -> Vec<&[u32]> {
    let holes = cage.holes.iter().filter(|h| h.face as usize == f).map(|h| &h.vertices[..]);
    std::iter::once(&cage.faces[f][..]).chain(holes).collect()
}

/// The face sizes, hole faces and hole sizes of `cage` (for `CageFaces`).
pub fn cage_faces(cage: &PolyMesh) -> (Vec<u32>, Vec<u32>, Vec<u32>) {
    (
        cage.faces.iter().map(|f| f.len() as u32).collect(),
        cage.holes.iter().map(|h| h.face).collect(),
        cage.holes.iter().map(|h| h.vertices.len() as u32).collect(),
    )
}

/// `value(vertex)` per face corner in the user's numbering (face by face, outer loop then holes).
pub fn per_corner<const D: usize>(cage: &PolyMesh, value: impl Fn(usize, u32) -> [f32; D]) -> Vec<f32> {
    let value = &value;
    let corners = |f: usize| user_loops(cage, f).concat().into_iter().flat_map(move |v| value(f, v));
    (0..cage.faces.len()).flat_map(corners).collect()
}

/// The cage point of (σ, τ) in corner k of face f (the keep-corners rule with the cage's
/// positions as the attribute; k in the user's numbering: its neighbours are in its own loop,
/// the centre is over all the face's loops).
pub fn cage_point(cage: &PolyMesh, [f, k]: [u32; 2], [s, t]: [f64; 2]) -> DVec3 {
    let loops = user_loops(cage, f as usize);
    let all: Vec<u32> = loops.concat();
    let centre = all.iter().map(|&v| cage.positions[v as usize]).sum::<DVec3>() / all.len() as f64;
    let mut k = k as usize;
    let face = loops.iter().find(|l| if k < l.len() { true } else { k -= l.len(); false }).expect("corner in the face");
    let n = face.len();
    let p = |i: usize| cage.positions[face[i % n] as usize];
    let (v, next, prev) = (p(k), 0.5 * (p(k) + p(k + 1)), 0.5 * (p(k) + p(k + n - 1)));
    v * ((1.0 - s) * (1.0 - t)) + next * (s * (1.0 - t)) + centre * (s * t) + prev * ((1.0 - s) * t)
}

/// Largest difference (any component) between the values (`dim` per loop, quad layout) of the
/// loops meeting at one output vertex; with `same_face`, only between loops in the same cage
/// face (values given per face corner may jump across cage edges, never inside a face).
pub fn loop_jump(m: &SurfaceMesh, values: &[f32], dim: usize, same_face: bool) -> f64 {
    let mut first: HashMap<(u32, u32), usize> = HashMap::new();
    let mut worst = 0f64;
    for (i, &x) in m.quads.iter().flatten().enumerate() {
        let face = if same_face { m.cage_corner[i / 4][0] } else { 0 };
        let j = *first.entry((x, face)).or_insert(i);
        for d in 0..dim {
            worst = worst.max((values[i * dim + d] - values[j * dim + d]).abs() as f64);
        }
    }
    worst
}

/// Largest difference (any component) between the values of neighbouring output vertices (the
/// two ends of an output quad's edge; quad layout), a vertex's value being that of its first
/// loop (with `same_face`: its first loop in the quad's cage face), so the jumps of
/// [`loop_jump`] show here too.
pub fn neighbour_difference(m: &SurfaceMesh, values: &[f32], dim: usize, same_face: bool) -> f64 {
    let face = |i: usize| if same_face { m.cage_corner[i / 4][0] } else { 0 };
    let mut first: HashMap<(u32, u32), usize> = HashMap::new();
    for (i, &x) in m.quads.iter().flatten().enumerate() {
        first.entry((x, face(i))).or_insert(i);
    }
    let mut worst = 0f64;
    for (k, q) in m.quads.iter().enumerate() {
        let f = face(4 * k);
        for c in 0..4 {
            let (i, j) = (first[&(q[c], f)], first[&(q[(c + 1) % 4], f)]);
            for d in 0..dim {
                worst = worst.max((values[i * dim + d] - values[j * dim + d]).abs() as f64);
            }
        }
    }
    worst
}

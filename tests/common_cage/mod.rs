//! Shared test helper for the cage-corner tests: the keep-corners rule (docs/math.md#cage-corners)
//! evaluated independently in f64, with the cage's own positions as the attribute.
#![allow(dead_code)]

use gbsurf::mesh::PolyMesh;
use glam::DVec3;

/// The cage point of (σ, τ) in corner k of face f (the keep-corners rule with the cage's
/// positions as the attribute).
pub fn cage_point(cage: &PolyMesh, [f, k]: [u32; 2], [s, t]: [f64; 2]) -> DVec3 {
    let face = &cage.faces[f as usize];
    let n = face.len();
    let p = |i: usize| cage.positions[face[i % n] as usize];
    let centre = (0..n).map(p).sum::<DVec3>() / n as f64;
    let k = k as usize;
    let (v, next, prev) = (p(k), 0.5 * (p(k) + p(k + 1)), 0.5 * (p(k) + p(k + n - 1)));
    v * ((1.0 - s) * (1.0 - t)) + next * (s * (1.0 - t)) + centre * (s * t) + prev * ((1.0 - s) * t)
}

//! Polygon geometry used by the construction: centroid, Newell normal, best-fit plane,
//! projection, planarity, and splitting concave faces into convex pieces.

use glam::DVec3;

/// Area-weighted normal of a polygon by Newell's method: `N = Σ_i p_i × p_{i+1}` (twice the
/// vector area; its length is `2 · area` for a planar polygon, and for a non-planar one it is the
/// sum of the area-weighted normals of any fan triangulation, seed 000 §3.3.2).
/// Computed relative to the first corner, which removes the translation part of the round-off.
pub fn newell_normal(pts: &[DVec3]) -> DVec3 {
    let Some(&o) = pts.first() else { return DVec3::ZERO };
    let n = pts.len();
    let mut s = DVec3::ZERO;
    for i in 0..n {
        let a = pts[i] - o;
        let b = pts[(i + 1) % n] - o;
        s += a.cross(b);
    }
    s
}

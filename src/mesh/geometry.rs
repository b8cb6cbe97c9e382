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

use super::PolyMesh;
use crate::progress::{par_map, Cancelled, Ticker};
use glam::DVec2;
use std::f64::consts::TAU;

/// Vertex average `c = (1/n) Σ p_i` of a polygon (seed 000 §3.3.2 uses it as the plane point).
pub fn centroid(pts: &[DVec3]) -> DVec3 {
    if pts.is_empty() {
        return DVec3::ZERO;
    }
    pts.iter().sum::<DVec3>() / pts.len() as f64
}

/// Area of a polygon, `|newell_normal| / 2` (for a non-planar polygon: the area of its
/// projection to the best-fit plane).
pub fn polygon_area(pts: &[DVec3]) -> f64 {
    0.5 * newell_normal(pts).length()
}

/// A plane through `point` with unit `normal`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    pub point: DVec3,
    pub normal: DVec3,
}

impl Plane {
    /// Signed distance `(p − point) · normal`.
    pub fn signed_distance(&self, p: DVec3) -> f64 {
        (p - self.point).dot(self.normal)
    }
    /// Orthogonal projection of `p` onto the plane: `p − ((p − point)·n) n`.
    pub fn project(&self, p: DVec3) -> DVec3 {
        p - self.normal * self.signed_distance(p)
    }
    /// Orthonormal in-plane axes `(u, v)` with `u × v = normal` (`u` from
    /// `normal.any_orthonormal_pair()`, deterministic).
    pub fn basis(&self) -> (DVec3, DVec3) {
        let (u, _) = self.normal.any_orthonormal_pair();
        (u, self.normal.cross(u))
    }
    /// Coordinates of the projection of `p` in the frame `(point; u, v)` of [`Self::basis`].
    pub fn to_2d(&self, p: DVec3) -> DVec2 {
        let (u, v) = self.basis();
        let d = p - self.point;
        DVec2::new(d.dot(u), d.dot(v))
    }
}

/// Best-fit plane of a polygon (seed 000 §3.3.2): normal = normalized area-weighted normal
/// (Newell), point = [`centroid`]. `None` if the polygon has (numerically) zero area.
pub fn best_fit_plane(pts: &[DVec3]) -> Option<Plane> {
    let n = newell_normal(pts);
    let len = n.length();
    (len > 0.0 && len.is_finite()).then(|| Plane { point: centroid(pts), normal: n / len })
}

/// Largest distance of a corner from the [`best_fit_plane`] (0 for a planar polygon; `inf` if
/// there is no plane).
pub fn max_plane_distance(pts: &[DVec3]) -> f64 {
    match best_fit_plane(pts) {
        Some(pl) => pts.iter().map(|p| pl.signed_distance(*p).abs()).fold(0.0, f64::max),
        None => f64::INFINITY,
    }
}

/// Scale-free planarity measure: [`max_plane_distance`] divided by the polygon's diameter
/// (largest corner-to-corner distance); 0 = planar.
pub fn planarity(pts: &[DVec3]) -> f64 {
    let mut diam: f64 = 0.0;
    for i in 0..pts.len() {
        for j in i + 1..pts.len() {
            diam = diam.max(pts[i].distance(pts[j]));
        }
    }
    if diam == 0.0 {
        return f64::INFINITY;
    }
    max_plane_distance(pts) / diam
}

/// The polygon projected into its best-fit plane frame (counter-clockwise, since `u × v` is the
/// Newell normal), or `None` when it has zero area.
pub fn project_polygon(pts: &[DVec3]) -> Option<Vec<DVec2>> {
    let mut out = Vec::with_capacity(pts.len());
    project_polygon_into(pts, &mut out).then_some(out)
}

/// [`project_polygon`] into `out` (cleared first; a buffer reused over many polygons); false
/// when the polygon has zero area.
pub fn project_polygon_into(pts: &[DVec3], out: &mut Vec<DVec2>) -> bool {
    out.clear();
    let Some(pl) = best_fit_plane(pts) else { return false };
    out.extend(pts.iter().map(|p| pl.to_2d(*p)));
    true
}

fn cross2(a: DVec2, b: DVec2) -> f64 {
    a.x * b.y - a.y * b.x
}

/// Tolerance for "turns right" at a corner: `1e-12 · d²`, `d` the largest bounding-box extent.
fn turn_tol(p: &[DVec2]) -> f64 {
    let (lo, hi) = p.iter().fold((DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)), |(l, h), q| {
        (l.min(*q), h.max(*q))
    });
    let d = (hi - lo).max_element();
    1e-12 * d * d
}

/// Whether the counter-clockwise 2D polygon is convex: no corner turns right by more than the
/// tolerance (straight 180° corners are allowed).
pub fn is_convex_2d(p: &[DVec2]) -> bool {
    let tol = turn_tol(p);
    let n = p.len();
    (0..n).all(|i| cross2(p[i] - p[(i + n - 1) % n], p[(i + 1) % n] - p[i]) >= -tol)
}

/// Whether a 3D polygon is convex in its best-fit plane (false if it has zero area).
pub fn is_convex_polygon(pts: &[DVec3]) -> bool {
    is_convex_polygon_with(pts, &mut Vec::new())
}

/// [`is_convex_polygon`] with `scratch` for the projected polygon (reused over many polygons).
pub fn is_convex_polygon_with(pts: &[DVec3], scratch: &mut Vec<DVec2>) -> bool {
    project_polygon_into(pts, scratch) && is_convex_2d(scratch)
}

/// Splits a simple polygon into convex pieces (see [`convexify`] for the rule). `pts` are the
/// corners; `keys` give the tie-breaking order of corners (e.g. mesh vertex indices). Returns
/// pieces as lists of positions into `pts`, each in the polygon's orientation. A polygon that is
/// already convex, has zero area, or for which no valid diagonal is found is returned whole.
pub fn convex_split(pts: &[DVec3], keys: &[u32]) -> Vec<Vec<usize>> {
    let all: Vec<usize> = (0..pts.len()).collect();
    let Some(p2) = project_polygon(pts) else { return vec![all] };
    let tol = turn_tol(&p2);
    let mut out = Vec::new();
    split_rec(&p2, keys, all, tol, &mut out);
    out
}

fn interior_angle(p: &[DVec2], poly: &[usize], k: usize) -> (f64, f64) {
    // returns (angle of e_next, interior sweep from e_next CCW to e_prev)
    let n = poly.len();
    let c = p[poly[k]];
    let e_next = p[poly[(k + 1) % n]] - c;
    let e_prev = p[poly[(k + n - 1) % n]] - c;
    let a0 = e_next.y.atan2(e_next.x);
    let a1 = e_prev.y.atan2(e_prev.x);
    let mut sweep = (a1 - a0).rem_euclid(TAU);
    if sweep == 0.0 {
        sweep = TAU;
    }
    (a0, sweep)
}

/// Offset of direction `d` from `a0` CCW in `[0, 2π)`.
fn offset(d: DVec2, a0: f64) -> f64 {
    (d.y.atan2(d.x) - a0).rem_euclid(TAU)
}

fn segments_touch(a: DVec2, b: DVec2, c: DVec2, d: DVec2, tol: f64) -> bool {
    // closed-segment intersection test with tolerance on orientations
    let o1 = cross2(b - a, c - a);
    let o2 = cross2(b - a, d - a);
    let o3 = cross2(d - c, a - c);
    let o4 = cross2(d - c, b - c);
    if ((o1 > tol && o2 < -tol) || (o1 < -tol && o2 > tol)) && ((o3 > tol && o4 < -tol) || (o3 < -tol && o4 > tol)) {
        return true;
    }
    let on = |p: DVec2, q: DVec2, r: DVec2, o: f64| {
        o.abs() <= tol && r.x >= p.x.min(q.x) - 1e-15 && r.x <= p.x.max(q.x) + 1e-15 && r.y >= p.y.min(q.y) - 1e-15 && r.y <= p.y.max(q.y) + 1e-15
    };
    on(a, b, c, o1) || on(a, b, d, o2) || on(c, d, a, o3) || on(c, d, b, o4)
}

fn split_rec(p: &[DVec2], keys: &[u32], poly: Vec<usize>, tol: f64, out: &mut Vec<Vec<usize>>) {
    let n = poly.len();
    let key = |i: usize| keys.get(i).copied().unwrap_or(i as u32);
    // reflex corner with the smallest key
    let reflex = (0..n)
        .filter(|&k| {
            let (a, b, c) = (p[poly[(k + n - 1) % n]], p[poly[k]], p[poly[(k + 1) % n]]);
            cross2(b - a, c - b) < -tol
        })
        .min_by_key(|&k| key(poly[k]));
    let Some(r) = reflex else {
        out.push(poly);
        return;
    };
    let (a0, sweep) = interior_angle(p, &poly, r);
    let pr = p[poly[r]];
    let mut best: Option<(bool, bool, f64, u32, usize)> = None;
    for j in 0..n {
        if j == r || j == (r + 1) % n || j == (r + n - 1) % n {
            continue;
        }
        let pj = p[poly[j]];
        let d = pj - pr;
        let t = offset(d, a0);
        if !(t > 1e-12 && t < sweep - 1e-12) {
            continue;
        }
        let (b0, sweep_j) = interior_angle(p, &poly, j);
        let tj = offset(-d, b0);
        if !(tj > 1e-12 && tj < sweep_j - 1e-12) {
            continue;
        }
        let blocked = (0..n).any(|k| {
            let k1 = (k + 1) % n;
            if k == r || k1 == r || k == j || k1 == j {
                return false;
            }
            segments_touch(pr, pj, p[poly[k]], p[poly[k1]], tol)
        });
        if blocked {
            continue;
        }
        use std::f64::consts::PI;
        let eps = 1e-12;
        let resolves_r = t <= PI + eps && sweep - t <= PI + eps;
        let resolves_j = sweep_j > PI + eps && tj <= PI + eps && sweep_j - tj <= PI + eps;
        let cand = (!resolves_r, !resolves_j, (t - sweep * 0.5).abs(), key(poly[j]), j);
        let better = match best {
            None => true,
            Some(b) => {
                (cand.0, cand.1) < (b.0, b.1)
                    || ((cand.0, cand.1) == (b.0, b.1)
                        && (cand.2 < b.2 - eps || (cand.2 <= b.2 + eps && cand.3 < b.3)))
            }
        };
        if better {
            best = Some(cand);
        }
    }
    let Some((_, _, _, _, j)) = best else {
        out.push(poly);
        return;
    };
    let mut a = Vec::new();
    let mut k = r;
    loop {
        a.push(poly[k]);
        if k == j {
            break;
        }
        k = (k + 1) % n;
    }
    let mut b = Vec::new();
    let mut k = j;
    loop {
        b.push(poly[k]);
        if k == r {
            break;
        }
        k = (k + 1) % n;
    }
    split_rec(p, keys, a, tol, out);
    split_rec(p, keys, b, tol, out);
}

/// Splits every concave face of `mesh` into convex pieces; returns the new mesh (same vertices)
/// and, for each new face, the index of the face it came from.
///
/// Rule (deterministic): each face is projected into its [`best_fit_plane`]. While a piece has a
/// reflex corner (turning right by more than `1e-12·d²`), take the reflex corner `r` whose mesh
/// vertex index is smallest and cut the piece along a diagonal from `r`. Candidates are the
/// diagonals that lie inside the interior angles at both ends and touch no other edge or corner;
/// among them prefer, in this order: (1) diagonals leaving `r` convex in both pieces, (2) ones
/// ending at a reflex corner that they leave convex in both pieces too, (3) the direction
/// closest to the bisector of `r`'s interior angle, (4) the smaller end vertex index. With (1)
/// available at every step the result has at most (number of reflex corners + 1) pieces. Pieces are emitted depth first: first the part from the reflex corner forward to the
/// diagonal's end, then the rest; each keeps the face's orientation and starts at the cut corner.
/// Faces that are already convex are kept unchanged (same corner order). Diagonals join existing
/// vertices only, so a closed mesh stays closed and `V − E + F` is unchanged.
pub fn convexify(mesh: &PolyMesh) -> (PolyMesh, Vec<u32>) {
    match convexify_ticked(mesh, &mut Ticker::none()) {
        Ok(r) => r,
        // A ticker without callback never cancels.
        Err(Cancelled) => (mesh.clone(), (0..mesh.faces.len() as u32).collect()),
    }
}

/// Most faces per chunk of [`convexify_ticked`].
const CONVEXIFY_CHUNK: usize = 1 << 14;

/// [`convexify`] in parallel over the faces (rayon, chunks of faces; the same result), ticking
/// `ticker` between chunks (see [`crate::progress`]).
pub fn convexify_ticked(mesh: &PolyMesh, ticker: &mut Ticker<'_>) -> Result<(PolyMesh, Vec<u32>), Cancelled> {
    // Per face: None when it is kept unchanged, else its pieces (corner indices into the face).
    let split = par_map(ticker, mesh.faces.len(), CONVEXIFY_CHUNK, |f| {
        let face = &mesh.faces[f];
        let pts: Vec<DVec3> = face.iter().map(|&i| mesh.positions.get(i as usize).copied().unwrap_or(DVec3::NAN)).collect();
        if face.len() <= 3 || pts.iter().any(|p| !p.is_finite()) {
            return None;
        }
        Some(convex_split(&pts, face))
    })?;
    let n: usize = split.iter().map(|s| s.as_ref().map_or(1, Vec::len)).sum();
    let mut faces = Vec::with_capacity(n);
    let mut origin = Vec::with_capacity(n);
    for (f, (face, pieces)) in mesh.faces.iter().zip(split).enumerate() {
        match pieces {
            None => {
                faces.push(face.clone());
                origin.push(f as u32);
            }
            Some(pieces) => {
                for piece in pieces {
                    faces.push(piece.iter().map(|&k| face[k]).collect());
                    origin.push(f as u32);
                }
            }
        }
    }
    Ok((PolyMesh { positions: mesh.positions.clone(), faces, creases: mesh.creases.clone(), holes: Vec::new() }, origin))
}

/// Area-weighted vertex normals of a triangle mesh (unit, zero for unused vertices).
pub fn vertex_normals(positions: &[DVec3], triangles: &[[u32; 3]]) -> Vec<DVec3> {
    let mut n = vec![DVec3::ZERO; positions.len()];
    for t in triangles {
        if t.iter().any(|&i| i as usize >= positions.len()) {
            continue;
        }
        let [a, b, c] = t.map(|i| positions[i as usize]);
        let f = (b - a).cross(c - a);
        for &i in t {
            n[i as usize] += f;
        }
    }
    n.iter().map(|v| v.normalize_or_zero()).collect()
}


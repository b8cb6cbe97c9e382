//! Certificates that regions of the output are free of self-intersections, so that
//! [`super::validity::self_intersections_certified`] can skip their triangle pairs and still
//! count exactly.
//!
//! # The certificate
//!
//! Let R be a set of output triangles, a a unit vector and f the orthogonal projection onto the
//! plane ⊥ a. Suppose
//! 1. every triangle of R has a geometric normal n with n·a > 0 (output triangles are
//!    counter-clockwise), and
//! 2. the boundary of R — the directed edges of R's triangles whose reverse is not an edge of R
//!    (as a chain: an edge and its reverse cancel) — is ONE closed loop b_0 → b_1 → … → b_0
//!    without a repeated vertex which, projected by f, is strictly star-shaped around the
//!    projection of a vertex q of R not on the loop: every edge turns positively around f(q),
//!    cross(f(b_i) − f(q), f(b_{i+1}) − f(q)) > 0, and the turning angles sum to 2π (winding
//!    number exactly 1).
//!
//! Then f is injective on R, so no two triangles of R that share no vertex meet.
//!
//! Proof. By (1) f is orientation-preserving on every triangle. For a point y off the images of
//! all edges, the number of triangles of R whose image contains y equals the winding number of
//! f(∂R) around y (each triangle contributes the winding number of its own boundary, +1 inside
//! its image and 0 outside, and the sum of the triangles' boundaries is the chain ∂R); as f(∂R)
//! is a simple loop star-shaped around f(q), that number is 1 inside the loop and 0 outside. So
//! every point of R has local degree ≥ 1 where R surrounds it (1 inside triangles and across
//! edges of R, a positive integer at vertices): a point x of R off the boundary loop with
//! f(x) on or outside the loop would cover points just outside it, where the count is 0, so
//! every such x maps strictly inside the loop, and the count 1 there allows at most one
//! preimage; points on the boundary loop map one to one onto the simple loop f(∂R). Hence every
//! y has at most one preimage. Two triangles sharing no vertex index are disjoint pieces of R,
//! so their images are disjoint, and so are they. ∎
//!
//! Floating point: anything uncertain means "not certified", and those pairs go through the
//! exact test as before. Condition (1) is checked per patch on a normal cone (the axis and the
//! largest angle between it and a triangle's unit normal) with a margin of [`CONE_MARGIN`]
//! radians, far above the rounding of unit normals of triangles that are not slivers (a
//! triangle with |e1 × e2| ≤ [`SLIVER`]·|e1||e2| makes its patch uncertifiable); condition (2)
//! asks cross > [`TURN_MARGIN`]·|f(b_i) − f(q)||f(b_{i+1}) − f(q)|, far above the rounding of
//! the projection (so every turning angle is in (0, π), also for the exact points), and the
//! winding number 1: with positive turns the angles sum to 2πk, k the number of upward
//! crossings of the line through f(q) (half-open, so a vertex on the line counts once).
//! A degenerate triangle, a repeated vertex on the loop, several loops or an edge left twice
//! are refusals.
//!
//! # Regions
//!
//! Stars of nodes: for every node (a corner vertex of a patch, where patches meet), R is all
//! triangles of the patches having that node as a corner, q the node, a the normalised sum of
//! the patches' cone axes. (1) holds when angle(a, axis_p) + half-angle_p < 90° − margin for
//! every patch p of the star; the boundary comes from the patches' boundary loops
//! ([`PatchLoops`], made by the tessellation): their directed edges, those appearing reversed in
//! another patch of the star cancelled. Every pair of patches sharing a vertex or a side lies in
//! one star, so on smooth closed surfaces all neighbouring pairs are certified.

use crate::progress::{Cancelled, Ticker};
use crate::tessellate::{PatchLoops, SurfaceMesh};
use glam::{DVec2, DVec3};
use rayon::prelude::*;

/// Margin (radians) of the normal-cone test of condition (1).
pub const CONE_MARGIN: f64 = 1e-3;
/// Relative margin of the star-shaped test of condition (2).
pub const TURN_MARGIN: f64 = 1e-9;
/// Triangles with |e1 × e2| at most this times |e1||e2| are slivers: their unit normal is not
/// trusted.
pub const SLIVER: f64 = 1e-6;

/// Regions of an output mesh proven free of self-intersections: per patch the certified stars
/// containing it. Pass [`Certified::none`] (or call [`super::self_intersections`]) to test every
/// pair.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Certified {
    /// The triangles of patch p are `tri_start[p]..tri_start[p + 1]`.
    tri_start: Vec<usize>,
    /// The certified stars containing patch p are `stars[star_start[p]..star_start[p + 1]]`,
    /// ascending.
    star_start: Vec<usize>,
    stars: Vec<u32>,
}

/// Normal cone of a patch: unit axis and the cosine of the largest angle between the axis and a
/// triangle's unit normal; `None` when a triangle is degenerate, a sliver or not finite.
fn normal_cone(positions: &[DVec3], triangles: &[[u32; 3]]) -> Option<(DVec3, f64)> {
    // The unit normal of a triangle, None for a sliver. Any axis gives a valid cone (cos is the
    // smallest dot product over all triangles): it is the mean of about 16 spread triangles'
    // normals, then one pass over all of them, without allocating.
    let unit = |t: &[u32; 3]| -> Option<DVec3> {
        let [a, b, c] = t.map(|i| positions.get(i as usize).copied().unwrap_or(DVec3::NAN));
        let (e1, e2) = (b - a, c - a);
        let n = e1.cross(e2);
        let len2 = n.length_squared();
        (len2.is_finite() && len2 > SLIVER * SLIVER * e1.length_squared() * e2.length_squared()).then(|| n / len2.sqrt())
    };
    let mut sum = DVec3::ZERO;
    for t in triangles.iter().step_by((triangles.len() / 16).max(1)) {
        sum += unit(t)?;
    }
    let axis = sum.normalize_or_zero();
    if axis == DVec3::ZERO {
        return None;
    }
    let mut cos = 1.0f64;
    for t in triangles {
        cos = cos.min(unit(t)?.dot(axis));
    }
    Some((axis, cos))
}

/// The chain of directed `edges` with every edge cancelled against a reverse, chained into one
/// loop of distinct vertices; `None` if that is not one simple loop.
fn single_loop(mut edges: Vec<(u32, u32)>) -> Option<Vec<u32>> {
    edges.sort_unstable_by_key(|&(a, b)| (a.min(b), a.max(b)));
    let mut rest: Vec<(u32, u32)> = Vec::new();
    let mut k = 0;
    while k < edges.len() {
        let key = (edges[k].0.min(edges[k].1), edges[k].0.max(edges[k].1));
        if key.0 == key.1 {
            return None;
        }
        let mut net = 0i64;
        while k < edges.len() && (edges[k].0.min(edges[k].1), edges[k].0.max(edges[k].1)) == key {
            net += if edges[k].0 < edges[k].1 { 1 } else { -1 };
            k += 1;
        }
        match net {
            0 => {}
            1 => rest.push(key),
            -1 => rest.push((key.1, key.0)),
            _ => return None,
        }
    }
    if rest.len() < 3 {
        return None;
    }
    rest.sort_unstable();
    if rest.windows(2).any(|w| w[0].0 == w[1].0) {
        return None;
    }
    let mut out = Vec::with_capacity(rest.len());
    let first = rest[0].0;
    let mut at = first;
    for _ in 0..rest.len() {
        let i = rest.binary_search_by_key(&at, |e| e.0).ok()?;
        out.push(at);
        at = rest[i].1;
        if at == first {
            break;
        }
    }
    (at == first && out.len() == rest.len()).then_some(out)
}

/// Condition (2): `lp` projected along `a` is strictly star-shaped around q with winding number 1.
fn star_shaped(positions: &[DVec3], lp: &[u32], q: u32, a: DVec3) -> bool {
    if lp.contains(&q) {
        return false;
    }
    let Some(&pq) = positions.get(q as usize) else { return false };
    let (e1, e2) = a.any_orthonormal_pair();
    let proj = |v: u32| positions.get(v as usize).map(|&p| {
        let d = p - pq;
        DVec2::new(d.dot(e1), d.dot(e2))
    });
    // With every turn in (0, π) the loop winds k ≥ 1 times, k = its upward crossings of the
    // line through f(q) (all on the positive side, half-open so a vertex on it counts once).
    let mut crossings = 0usize;
    for k in 0..lp.len() {
        let (Some(u), Some(v)) = (proj(lp[k]), proj(lp[(k + 1) % lp.len()])) else { return false };
        let cross = u.perp_dot(v);
        if !(cross > TURN_MARGIN * u.length() * v.length()) {
            return false;
        }
        crossings += (u.y < 0.0 && v.y >= 0.0) as usize;
    }
    crossings == 1
}

/// Checks the certificate (see the module doc) for the region made of `triangles` (indices into
/// `positions`) around vertex `q`, with a the normalised sum of the triangles' unit normals:
/// true when proven free of self-intersections. For tests and for regions other than stars.
pub fn certify_region(positions: &[DVec3], triangles: &[[u32; 3]], q: u32) -> bool {
    let Some((axis, cos)) = normal_cone(positions, triangles) else { return false };
    if !(cos.clamp(-1.0, 1.0).acos() < std::f64::consts::FRAC_PI_2 - CONE_MARGIN) {
        return false;
    }
    let edges = triangles.iter().flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])]).collect();
    single_loop(edges).is_some_and(|lp| star_shaped(positions, &lp, q, axis))
}

/// The star of node q made of `patches` (with their cones): conditions (1) and (2).
fn certify_star(positions: &[DVec3], loops: &PatchLoops, cones: &[Option<(DVec3, f64)>], q: u32, patches: &[u32]) -> bool {
    let mut cs = Vec::with_capacity(patches.len());
    for &p in patches {
        match cones[p as usize] {
            Some(c) => cs.push(c),
            None => return false,
        }
    }
    let a = cs.iter().map(|c| c.0).sum::<DVec3>().normalize_or_zero();
    if a == DVec3::ZERO {
        return false;
    }
    let limit = std::f64::consts::FRAC_PI_2 - CONE_MARGIN;
    if !cs.iter().all(|&(axis, cos)| a.dot(axis).clamp(-1.0, 1.0).acos() + cos.clamp(-1.0, 1.0).acos() < limit) {
        return false;
    }
    let mut edges = Vec::new();
    for &p in patches {
        let lp = loops.of(p as usize);
        edges.extend((0..lp.len()).map(|k| (lp[k], lp[(k + 1) % lp.len()])));
    }
    single_loop(edges).is_some_and(|lp| star_shaped(positions, &lp, q, a))
}

/// Stars certified per progress tick.
const STARS_PER_TICK: usize = 2048;

impl Certified {
    /// No certified region: every pair is tested.
    pub fn none() -> Certified {
        Certified::default()
    }

    /// The certified stars of the nodes of a tessellation (see the module doc); none for a mesh
    /// without patch loops (subdivision methods) or whose loops do not match its triangles.
    pub fn of_mesh(mesh: &SurfaceMesh) -> Certified {
        Certified::of_patches(&mesh.positions, &mesh.triangles, &mesh.patch_loops)
    }

    /// The certified stars of the nodes of `loops` over the mesh (`positions`, `triangles`).
    pub fn of_patches(positions: &[DVec3], triangles: &[[u32; 3]], loops: &PatchLoops) -> Certified {
        Certified::of_patches_ticked(positions, triangles, loops, &mut Ticker::none()).unwrap_or_else(|_| Certified::none())
    }

    /// [`Certified::of_mesh`] reporting progress to `ticker` (see [`crate::progress`]).
    pub fn of_mesh_ticked(mesh: &SurfaceMesh, ticker: &mut Ticker<'_>) -> Result<Certified, Cancelled> {
        Certified::of_patches_ticked(&mesh.positions, &mesh.triangles, &mesh.patch_loops, ticker)
    }

    /// [`Certified::of_patches`] reporting progress to `ticker` (per chunk of stars).
    pub fn of_patches_ticked(
        positions: &[DVec3],
        triangles: &[[u32; 3]],
        loops: &PatchLoops,
        ticker: &mut Ticker<'_>,
    ) -> Result<Certified, Cancelled> {
        let np = loops.len();
        let consistent = np > 0
            && loops.triangles.len() == np + 1
            && loops.triangles[np] == triangles.len()
            && loops.triangles.windows(2).all(|w| w[0] <= w[1])
            && loops.ids.iter().all(|&v| (v as usize) < positions.len());
        if !consistent {
            return Ok(Certified::none());
        }
        let cones: Vec<Option<(DVec3, f64)>> = (0..np)
            .into_par_iter()
            .map(|p| normal_cone(positions, &triangles[loops.triangles[p]..loops.triangles[p + 1]]))
            .collect();
        // Nodes: (corner vertex, patch), grouped by vertex.
        let mut corners: Vec<(u32, u32)> = (0..np).flat_map(|p| loops.corners(p).map(move |v| (v, p as u32))).collect();
        corners.par_sort_unstable();
        corners.dedup();
        let mut groups: Vec<(usize, usize)> = Vec::new();
        let mut k = 0;
        while k < corners.len() {
            let s = k;
            while k < corners.len() && corners[k].0 == corners[s].0 {
                k += 1;
            }
            groups.push((s, k));
        }
        ticker.at(1, 10)?;
        let mut certified: Vec<bool> = Vec::with_capacity(groups.len());
        let per_tick = crate::progress::chunk_size(groups.len(), STARS_PER_TICK);
        for part in groups.chunks(per_tick) {
            certified.par_extend(part.par_iter().map_init(Vec::new, |ps, &(s, e)| {
                ps.clear();
                ps.extend(corners[s..e].iter().map(|c| c.1));
                certify_star(positions, loops, &cones, corners[s].0, ps)
            }));
            ticker.at_part(0.1, 1.0, certified.len(), groups.len())?;
        }
        let mut member: Vec<(u32, u32)> = Vec::new();
        for (g, &(s, e)) in groups.iter().enumerate() {
            if certified[g] {
                member.extend(corners[s..e].iter().map(|c| (c.1, g as u32)));
            }
        }
        member.par_sort_unstable();
        let mut star_start = Vec::with_capacity(np + 1);
        let mut k = 0;
        for p in 0..np as u32 {
            star_start.push(k);
            while k < member.len() && member[k].0 == p {
                k += 1;
            }
        }
        star_start.push(member.len());
        Ok(Certified { tri_start: loops.triangles.clone(), star_start, stars: member.into_iter().map(|m| m.1).collect() })
    }

    /// Number of patches lying in at least one certified star.
    pub fn certified_patches(&self) -> usize {
        self.star_start.windows(2).filter(|w| w[1] > w[0]).count()
    }

    /// Number of patches.
    pub fn patches(&self) -> usize {
        self.star_start.len().saturating_sub(1)
    }

    /// The certified stars containing patch p (ascending).
    fn stars_of(&self, p: usize) -> &[u32] {
        self.star_start.get(p..p + 2).map_or(&[], |w| &self.stars[w[0]..w[1]])
    }

    /// The patch of triangle t, if the certificate covers it.
    pub(crate) fn patch_of(&self, t: usize) -> Option<usize> {
        if t >= *self.tri_start.last()? {
            return None;
        }
        Some(self.tri_start.partition_point(|&s| s <= t) - 1)
    }

    /// The certified stars containing every triangle of `first..=last` (triangle indices of the
    /// mesh, ascending range; the patches' triangles are consecutive): the common stars of the
    /// patches spanned, ascending; empty when none.
    pub(crate) fn stars_of_range(&self, first: usize, last: usize) -> Vec<u32> {
        let (Some(p0), Some(p1)) = (self.patch_of(first), self.patch_of(last)) else { return Vec::new() };
        let mut common = self.stars_of(p0).to_vec();
        for p in p0 + 1..=p1 {
            if common.is_empty() {
                break;
            }
            let s = self.stars_of(p);
            common.retain(|x| s.binary_search(x).is_ok());
        }
        common
    }
}

/// Two ascending lists share an element.
pub(crate) fn share(a: &[u32], b: &[u32]) -> bool {
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        match a[i].cmp(&b[j]) {
            std::cmp::Ordering::Less => i += 1,
            std::cmp::Ordering::Greater => j += 1,
            std::cmp::Ordering::Equal => return true,
        }
    }
    false
}

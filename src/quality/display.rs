//! Quality displays of seed 000 §5.2 / §4.2.2: isophotes and planar slices.
//!
//! Isophotes join points of equal reflected light for a light direction L: the scalar n·L of the
//! unit normal. Stripes of equal width in the angle acos(n·L) make the classic zebra display; a
//! G1 joint shows as stripes that meet with a kink (G0 isophotes ⇔ G1 surface).

use glam::DVec3;
use std::collections::HashMap;

/// The isophote scalar n·L ∈ [−1, 1] per vertex (L normalized; zero normals give 0).
pub fn isophote(normals: &[DVec3], light: DVec3) -> Vec<f64> {
    let l = light.normalize_or_zero();
    normals.iter().map(|n| n.normalize_or_zero().dot(l).clamp(-1.0, 1.0)).collect()
}

/// Isophote stripes: the angle acos(n·L) ∈ [0, π] split into `stripes` equal bands; per vertex the
/// band coordinate `stripes · acos(n·L) / π` (its integer part is the band, the parity gives the
/// zebra colour, the fractional part interpolates linearly over triangles).
pub fn isophote_stripes(normals: &[DVec3], light: DVec3, stripes: u32) -> Vec<f64> {
    let k = stripes.max(1) as f64;
    isophote(normals, light).into_iter().map(|c| k * c.acos() / std::f64::consts::PI).collect()
}

/// A polyline (closed when its first and last points coincide exactly, i.e. are the same sample).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Polyline {
    pub points: Vec<DVec3>,
    pub closed: bool,
}

/// Intersects a triangle mesh with the plane {x : n·x = d} and chains the segments into
/// polylines (closed loops where the mesh is closed). Vertices exactly on the plane are nudged to
/// the positive side (symbolic perturbation), so every crossing is a proper edge crossing and the
/// loops are simple; each crossing point is computed once per edge, so loops close exactly.
pub fn slice(positions: &[DVec3], triangles: &[[u32; 3]], normal: DVec3, d: f64) -> Vec<Polyline> {
    let n = normal;
    let side: Vec<bool> = positions.iter().map(|p| n.dot(*p) - d >= 0.0).collect();
    let point = |a: u32, b: u32| -> DVec3 {
        let (pa, pb) = (positions[a as usize], positions[b as usize]);
        let (fa, fb) = (n.dot(pa) - d, n.dot(pb) - d);
        let t = if fa == fb { 0.5 } else { fa / (fa - fb) };
        pa + (pb - pa) * t.clamp(0.0, 1.0)
    };
    // Each triangle crossing the plane gives one segment from edge e1 to edge e2 (edges as
    // sorted vertex pairs), oriented so that the positive side is on the left seen from n.
    let key = |a: u32, b: u32| (a.min(b), a.max(b));
    let mut next: HashMap<(u32, u32), (u32, u32)> = HashMap::new();
    let mut has_prev: HashMap<(u32, u32), bool> = HashMap::new();
    for t in triangles {
        if t.iter().any(|&i| i as usize >= positions.len()) {
            continue;
        }
        let s = t.map(|i| side[i as usize]);
        // Find the edge going from positive to negative (exit) and from negative to positive.
        let mut out_edge = None;
        let mut in_edge = None;
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            match (s[k], s[(k + 1) % 3]) {
                (true, false) => out_edge = Some(key(a, b)),
                (false, true) => in_edge = Some(key(a, b)),
                _ => {}
            }
        }
        if let (Some(e1), Some(e2)) = (in_edge, out_edge) {
            next.insert(e1, e2);
            has_prev.insert(e2, true);
        }
    }
    let mut visited: HashMap<(u32, u32), bool> = HashMap::new();
    let mut lines = Vec::new();
    // Open chains first (start where nothing leads in), then the remaining closed loops.
    let mut starts: Vec<(u32, u32)> = next.keys().filter(|e| !has_prev.contains_key(e)).copied().collect();
    starts.sort_unstable();
    let mut rest: Vec<(u32, u32)> = next.keys().copied().collect();
    rest.sort_unstable();
    for (open, list) in [(true, starts), (false, rest)] {
        for s in list {
            if visited.contains_key(&s) {
                continue;
            }
            let mut pts = vec![point(s.0, s.1)];
            visited.insert(s, true);
            let mut cur = s;
            let mut closed = false;
            while let Some(&nx) = next.get(&cur) {
                pts.push(point(nx.0, nx.1));
                if nx == s {
                    closed = true;
                    break;
                }
                if visited.contains_key(&nx) {
                    break;
                }
                visited.insert(nx, true);
                cur = nx;
            }
            let _ = open;
            lines.push(Polyline { points: pts, closed });
        }
    }
    lines
}

/// `count` parallel slices with normal `normal` evenly spaced across the mesh's extent along it
/// (strictly inside, so no slice touches the extreme points).
///
/// `count` must be in 1..=[`crate::limits::MAX_SLICES`] ([`crate::options::check_slice_count`]).
pub fn slices(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    normal: DVec3,
    count: usize,
) -> Result<Vec<(f64, Vec<Polyline>)>, crate::options::OptionError> {
    let count = crate::options::check_slice_count(count)?;
    let n = normal.normalize_or_zero();
    if positions.is_empty() || n == DVec3::ZERO {
        return Ok(Vec::new());
    }
    let (lo, hi) = positions.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
        let x = n.dot(*p);
        (lo.min(x), hi.max(x))
    });
    Ok((1..=count)
        .map(|k| {
            let d = lo + (hi - lo) * k as f64 / (count + 1) as f64;
            (d, slice(positions, triangles, n, d))
        })
        .collect())
}

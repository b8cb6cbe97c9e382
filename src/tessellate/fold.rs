//! The fold rule on the samples of a tessellation (the rule is documented in
//! [`crate::quality::validity`]): a sample of domain triangle i (centre, v_{i−1}, v_i) with
//! barycentric weights (a, b, c) is folded where its unit normal turns against the reference
//! normal T × X of ribbon i at the foot s = c/(b + c) of the sample on side i.
//!
//! Per layout, [`Sectors`] holds every sample's (i, s) once (it depends on the domain only); per
//! patch, [`patch_folds`] evaluates the reference normals with [`ribbon_normal`] (the normal of
//! [`crate::construct::check::ribbon_frame`], without allocating) and compares. The tessellation
//! runs it on the samples it has just evaluated, so the check costs no second evaluation.

use super::evaluator::SurfacePoint;
use crate::construct::Patch;
use crate::gb::Ribbon;
use glam::{DVec2, DVec3};

/// Per sample of a layout: its domain triangle i and its foot s ∈ [0, 1] on side i.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Sectors {
    pub at: Vec<(u32, f64)>,
}

impl Sectors {
    /// The sectors of the samples `uv` in the domain polygon `domain` (counter-clockwise,
    /// vertex i ends side i): each sample goes to the domain triangle whose smaller weight on
    /// (v_{i−1}, v_i) is largest (the one containing it), s = c/(b + c) (½ at the centre).
    pub fn new(domain: &[DVec2], uv: &[DVec2]) -> Sectors {
        let n = domain.len();
        let centre = domain.iter().copied().sum::<DVec2>() / n.max(1) as f64;
        let at = uv
            .iter()
            .map(|&x| {
                let q = x - centre;
                let mut best = (0u32, 0.5, f64::NEG_INFINITY);
                for i in 0..n {
                    let (e0, e1) = (domain[(i + n - 1) % n] - centre, domain[i] - centre);
                    let det = e0.perp_dot(e1);
                    if det == 0.0 {
                        continue;
                    }
                    let (b, c) = (q.perp_dot(e1) / det, e0.perp_dot(q) / det);
                    if b.min(c) > best.2 {
                        let s = if b + c > 1e-12 { (c / (b + c)).clamp(0.0, 1.0) } else { 0.5 };
                        best = (i as u32, s, b.min(c));
                    }
                }
                (best.0, best.1)
            })
            .collect();
        Sectors { at }
    }
}

/// Unit boundary-frame normal T × X of `ribbon` at s (zero where undefined): the same vectors as
/// [`crate::construct::check::ribbon_frame`], T = d Σ B^{d−1}_j(s)(P_{0,j+1} − P_{0,j}),
/// X = d Σ B^d_j(s)(P_{1,j} − P_{0,j}), summed without allocating.
pub fn ribbon_normal(ribbon: &Ribbon, s: f64) -> DVec3 {
    let d = ribbon.degree;
    let (r0, r1) = (&ribbon.rows[0], &ribbon.rows[1]);
    let u = 1.0 - s;
    let bern = |n: usize, j: usize, binom: f64| binom * s.powi(j as i32) * u.powi((n - j) as i32);
    let (mut t, mut x) = (DVec3::ZERO, DVec3::ZERO);
    let mut binom = 1.0;
    for j in 0..=d {
        x += bern(d, j, binom) * (r1[j] - r0[j]);
        binom = binom * (d - j) as f64 / (j + 1) as f64;
    }
    let mut binom = 1.0;
    for j in 0..d {
        t += bern(d - 1, j, binom) * (r0[j + 1] - r0[j]);
        binom = binom * (d - 1 - j) as f64 / (j + 1) as f64;
    }
    reference_normal(t, x)
}

/// Smallest sin of the angle between T and X for which T × X counts as a normal: below it (T and
/// X parallel up to rounding, as at a corner where the ribbon frame degenerates, e.g. at the end
/// of a sharp crease) the direction of the computed cross product is rounding noise.
pub const MIN_FRAME_SIN: f64 = 1e-8;

/// Unit T × X, or zero (undefined) when |T × X| ≤ [`MIN_FRAME_SIN`]·|T|·|X| or not finite.
pub fn reference_normal(t: DVec3, x: DVec3) -> DVec3 {
    let n = t.cross(x);
    if !(n.length() > MIN_FRAME_SIN * t.length() * x.length()) {
        return DVec3::ZERO;
    }
    n.normalize_or_zero()
}

/// Folds of one patch: folded samples (indices into the layout), and the worst one.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PatchFolds {
    /// Layout indices of the folded samples.
    pub samples: Vec<u32>,
    /// Domain point of the sample whose normal turns furthest against its reference.
    pub worst: Option<DVec2>,
}

/// Applies the fold rule to the evaluated `points` of `patch` at the layout samples `uv` with
/// their `sectors`. Samples with an undefined normal (zero or non-finite, e.g. at a collapsed
/// corner) and samples whose reference normal is undefined are skipped: the sign means nothing
/// there.
pub fn patch_folds(patch: &Patch, sectors: &Sectors, uv: &[DVec2], points: &[SurfacePoint]) -> PatchFolds {
    let ribbons = patch.ribbons();
    let mut out = PatchFolds::default();
    let mut worst = 0.0f64;
    for (k, ((&x, sp), &(i, s))) in uv.iter().zip(points).zip(&sectors.at).enumerate() {
        if sp.normal == DVec3::ZERO || !sp.normal.is_finite() {
            continue;
        }
        let Some(ribbon) = ribbons.get(i as usize) else { continue };
        let rel = sp.normal.dot(ribbon_normal(ribbon, s));
        if rel < 0.0 {
            out.samples.push(k as u32);
            if rel < worst {
                worst = rel;
                out.worst = Some(x);
            }
        }
    }
    out
}

/// Output triangles whose geometric normal (b − a) × (c − a) opposes the normals of all three of
/// its vertices (a strictly negative dot product with each nonzero vertex normal): the triangle
/// is turned over against the surface it samples. Returns their indices.
pub fn flipped_triangles(positions: &[DVec3], normals: &[DVec3], triangles: &[[u32; 3]]) -> Vec<u32> {
    use rayon::prelude::*;
    triangles
        .par_iter()
        .enumerate()
        .with_min_len(1 << 14)
        .filter(|(_, t)| {
            if t.iter().any(|&i| i as usize >= positions.len() || i as usize >= normals.len()) {
                return false;
            }
            let [a, b, c] = t.map(|i| positions[i as usize]);
            let g = (b - a).cross(c - a);
            g != DVec3::ZERO && t.iter().all(|&i| {
                let n = normals[i as usize];
                n != DVec3::ZERO && g.dot(n) < 0.0
            })
        })
        .map(|(k, _)| k as u32)
        .collect()
}

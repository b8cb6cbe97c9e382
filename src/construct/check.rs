//! Continuity measurements along shared sides of a [`Surface`].
//!
//! Ribbon level (no evaluator needed): along side i of patch A with parameter s, the ribbon gives
//! the tangent T(s) = Σ_j B³_j'(s) P_{j,0} and the inward cross-derivative
//! X(s) = 3 Σ_j B³_j(s)(P_{j,1} − P_{j,0}); the outward normal is T × X. Across a shared side the
//! neighbour is sampled at 1 − s with its own T, X. The GB / CGB patch with squared correction
//! weights reproduces each ribbon's cross-derivative along its side, so these angles are the
//! patches' normal angles along the side.

use super::surface::{Patch, Surface};
use crate::bezier::bernstein::bernstein_all_d2;
use crate::gb::{angle_deg, Evaluate, Ribbon};
use glam::DVec3;

/// Worst value found and where: (patch, side, s).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Worst {
    pub value: f64,
    pub patch: usize,
    pub side: usize,
    pub s: f64,
}

impl Worst {
    fn update(&mut self, value: f64, patch: usize, side: usize, s: f64) {
        if value > self.value || value.is_nan() {
            *self = Worst { value, patch, side, s };
        }
    }
}

/// (point, tangent d/ds, inward cross-derivative d/dh) of a ribbon at (s, h = 0).
pub fn ribbon_frame(r: &Ribbon, s: f64) -> (DVec3, DVec3, DVec3) {
    let d = r.degree;
    let (b, db, _) = bernstein_all_d2(d, s);
    let mut p = DVec3::ZERO;
    let mut t = DVec3::ZERO;
    let mut x = DVec3::ZERO;
    let (r0, r1) = (r.row(0), r.row(1));
    for j in 0..=d {
        p += b[j] * r0[j];
        t += db[j] * r0[j];
        x += b[j] * (r1[j] - r0[j]);
    }
    (p, t, d as f64 * x)
}

/// The worst value of `measure(frame of A at s, frame of B at 1 − s)` over every shared side
/// (once per side, [`Surface::shared_sides`]) at `samples` ≥ 2 equally spaced parameters (ends
/// included); frames are (point, tangent, cross-derivative) of [`ribbon_frame`].
fn worst_along_shared_sides(
    surface: &Surface,
    samples: usize,
    measure: impl Fn((DVec3, DVec3, DVec3), (DVec3, DVec3, DVec3)) -> f64,
) -> Worst {
    let mut w = Worst::default();
    let samples = samples.max(2);
    for (p, i, n) in surface.shared_sides() {
        let ra = &surface.patches[p].ribbons()[i];
        let rb = &surface.patches[n.patch].ribbons()[n.side];
        for k in 0..samples {
            let s = k as f64 / (samples - 1) as f64;
            w.update(measure(ribbon_frame(ra, s), ribbon_frame(rb, 1.0 - s)), p, i, s);
        }
    }
    w
}

/// Max angle (degrees) between the ribbon normals T × X of the two patches along every shared side,
/// at `samples` ≥ 2 equally spaced parameters (ends included).
pub fn ribbon_g1_angle(surface: &Surface, samples: usize) -> Worst {
    worst_along_shared_sides(surface, samples, |(_, ta, xa), (_, tb, xb)| angle_deg(ta.cross(xa), tb.cross(xb)))
}

/// Max distance between the two ribbons' boundary points along every shared side (the curve as
/// seen from both patches, B at 1 − s).
pub fn ribbon_gap(surface: &Surface, samples: usize) -> Worst {
    worst_along_shared_sides(surface, samples, |(pa, _, _), (pb, _, _)| pa.distance(pb))
}

/// Max distance between corner-block points that must coincide: ribbon i's row 1 column 0 and the
/// boundary point of side i−1 at column d−1, row 1 column d and side i+1's boundary column 1, and
/// the ends of consecutive boundaries.
pub fn corner_block_defect(surface: &Surface) -> Worst {
    let mut w = Worst::default();
    for (p, patch) in surface.patches.iter().enumerate() {
        let rs = patch.ribbons();
        let n = rs.len();
        for i in 0..n {
            let prev = &rs[(i + n - 1) % n];
            let next = &rs[(i + 1) % n];
            let r = &rs[i];
            let d = r.degree;
            w.update(r.row(1)[0].distance(prev.row(0)[prev.degree - 1]), p, i, 0.0);
            w.update(r.row(1)[d].distance(next.row(0)[1]), p, i, 1.0);
            w.update(r.row(0)[d].distance(next.row(0)[0]), p, i, 1.0);
        }
    }
    w
}

/// Evaluator-level measurements of the joins of a surface (see [`join_report`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct JoinReport {
    /// Max angle (degrees) between the two patches' unit normals at the same curve point.
    pub angle_deg: Worst,
    /// Max distance between the two patches' evaluations of the shared side.
    pub gap: Worst,
    /// Number of shared sides measured (each pair once).
    pub sides: usize,
    /// Samples where a patch normal was undefined (degenerate parameterization).
    pub degenerate: usize,
}

/// Point, first and second derivatives of any patch at a domain point.
impl Evaluate for Patch {
    fn eval_derivs(&self, uv: glam::DVec2, form: crate::gb::WeightForm) -> crate::gb::SurfaceDerivs {
        match self {
            Patch::Gb(g) => g.eval_derivs(uv, form),
            Patch::Cgb(c) => c.eval_derivs(uv, form),
        }
    }
}

/// Sample parameters along a side: `samples` equally spaced interior points t_k = (k+1)/(samples+1)
/// plus two points 1e-6 away from the corners (the corners themselves are the nodes, where the
/// evaluator returns the corner point).
pub fn side_params(samples: usize) -> Vec<f64> {
    let mut t: Vec<f64> = (0..samples).map(|k| (k + 1) as f64 / (samples + 1) as f64).collect();
    t.push(1e-6);
    t.push(1.0 - 1e-6);
    t
}

/// Evaluates both patches along every shared side: side i of patch A at t is side j of patch B at
/// 1 − t (domain convention of [`crate::gb::Domain`]: side i runs from vertex i−1 to vertex i).
/// Reports the max normal angle and the max positional gap.
pub fn join_report(surface: &Surface, samples: usize, form: crate::gb::WeightForm) -> JoinReport {
    use crate::gb::Domain;
    let mut r = JoinReport::default();
    let domains: Vec<Option<Domain>> =
        surface.patches.iter().map(|p| Domain::regular(p.sides()).ok()).collect();
    let ts = side_params(samples);
    for (p, i, n) in surface.shared_sides() {
        let (Some(da), Some(db)) = (&domains[p], &domains[n.patch]) else {
            r.degenerate += 1;
            continue;
        };
        r.sides += 1;
        for &t in &ts {
            let a = surface.patches[p].eval_derivs(da.side_point(i, t), form);
            let b = surface.patches[n.patch].eval_derivs(db.side_point(n.side, 1.0 - t), form);
            r.gap.update(a.p.distance(b.p), p, i, t);
            match (a.normal(), b.normal()) {
                (Some(na), Some(nb)) => r.angle_deg.update(angle_deg(na, nb), p, i, t),
                _ => r.degenerate += 1,
            }
        }
    }
    r
}

/// Max angle (degrees) between each patch's normal at its corners and the prescribed node normal
/// (up to sign) — e.g. the face plane at the dual nodes (seed 000 §4.4.4). `corner_node(p, i)`
/// gives the node at domain vertex i of patch p (or `None` to skip). The normal is taken at the
/// domain point 1e-9 inside the corner.
pub fn corner_plane_angle(
    surface: &Surface,
    node_normals: &[DVec3],
    corner_node: impl Fn(usize, usize) -> Option<usize>,
    form: crate::gb::WeightForm,
) -> Worst {
    use crate::gb::Domain;
    let mut w = Worst::default();
    for (p, patch) in surface.patches.iter().enumerate() {
        let n = patch.sides();
        let Ok(d) = Domain::regular(n) else { continue };
        for i in 0..n {
            let Some(node) = corner_node(p, i) else { continue };
            let uv = d.vertex(i) * (1.0 - 1e-9);
            match patch.eval_derivs(uv, form).normal() {
                Some(nn) => {
                    let a = angle_deg(nn, node_normals[node]);
                    w.update(a.min(180.0 - a), p, i, 1.0);
                }
                None => w.update(f64::INFINITY, p, i, 1.0),
            }
        }
    }
    w
}

/// Fold measurements inside the patches of a surface (see [`fold_report`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FoldReport {
    /// Max angle (degrees) between a sampled unit normal of a patch and the patch's average normal
    /// (`side` = domain triangle, `s` = sample index in it). Above 90° the patch turns over
    /// (e.g. a rim curling round a sharp convex edge); not by itself a fold.
    pub normal_deviation_deg: Worst,
    /// Max angle (degrees) between the normals of neighbouring samples: a fold (the Jacobian
    /// changing sign) shows as a jump near 180°, a smooth patch as a few degrees.
    pub max_neighbor_turn_deg: Worst,
    /// Min over samples of |S_u × S_v| divided by the mean of |S_u × S_v| over the patch's samples
    /// (stored as a [`Worst`] whose `value` is that minimum): 0 where the Jacobian vanishes.
    pub min_rel_jacobian: Worst,
    /// Samples taken.
    pub samples: usize,
    /// Samples with an undefined normal or non-finite derivatives.
    pub degenerate: usize,
}

/// Domain points of triangle i (centre, v_{i−1}, v_i) of the regular n-gon for [`fold_report`]:
/// the barycentric grid (a, b, c)/`level`, a + b + c = `level`, in the order a = 0..level,
/// b = 0..=level−a; the a = 0 row (side i) is pulled 10⁻³ towards the centre, so the side and its
/// corners are probed just inside.
pub fn fold_sample_points(d: &crate::gb::Domain, i: usize, level: usize) -> Vec<glam::DVec2> {
    let level = level.max(1);
    let (v0, v1) = (d.vertex(i + d.n() - 1), d.vertex(i));
    let mut pts = Vec::new();
    for a in 0..=level {
        for b in 0..=(level - a) {
            let c = level - a - b;
            let uv = (b as f64 * v0 + c as f64 * v1) / level as f64;
            pts.push(if a == 0 { uv * (1.0 - 1e-3) } else { uv });
        }
    }
    pts
}

/// Samples every patch on the grids of [`fold_sample_points`] and reports how far its normal
/// strays from its average normal, how much it turns between neighbouring samples, and how small
/// its Jacobian |S_u × S_v| gets relative to the patch's mean.
pub fn fold_report(surface: &Surface, level: usize, form: crate::gb::WeightForm) -> FoldReport {
    use crate::gb::Domain;
    let level = level.max(1);
    let mut r = FoldReport { min_rel_jacobian: Worst { value: f64::INFINITY, ..Worst::default() }, ..Default::default() };
    // Index of (a, b) in a triangle's grid.
    let idx = |a: usize, b: usize| (0..a).map(|q| level - q + 1).sum::<usize>() + b;
    for (p, patch) in surface.patches.iter().enumerate() {
        let Ok(d) = Domain::regular(patch.sides()) else {
            r.degenerate += 1;
            continue;
        };
        let tri: Vec<Vec<crate::gb::SurfaceDerivs>> = (0..d.n())
            .map(|i| fold_sample_points(&d, i, level).iter().map(|&uv| patch.eval_derivs(uv, form)).collect())
            .collect();
        let mut avg = DVec3::ZERO;
        let mut mean_jac = 0.0;
        let mut count = 0usize;
        for s in tri.iter().flatten() {
            r.samples += 1;
            match s.normal() {
                Some(n) if s.is_finite() => {
                    avg += n;
                    mean_jac += s.su.cross(s.sv).length();
                    count += 1;
                }
                _ => r.degenerate += 1,
            }
        }
        mean_jac /= count.max(1) as f64;
        let avg = avg.normalize_or_zero();
        for (i, ders) in tri.iter().enumerate() {
            for a in 0..=level {
                for b in 0..=(level - a) {
                    let k = idx(a, b);
                    let Some(n) = ders[k].normal() else { continue };
                    r.normal_deviation_deg.update(angle_deg(n, avg), p, i, k as f64);
                    let j = ders[k].su.cross(ders[k].sv).length() / mean_jac;
                    if j < r.min_rel_jacobian.value {
                        r.min_rel_jacobian = Worst { value: j, patch: p, side: i, s: k as f64 };
                    }
                    let mut nbs = Vec::with_capacity(2);
                    if b < level - a {
                        nbs.push(idx(a, b + 1));
                    }
                    if a < level && b < level - a {
                        nbs.push(idx(a + 1, b));
                    }
                    for q in nbs {
                        if let Some(m) = ders[q].normal() {
                            r.max_neighbor_turn_deg.update(angle_deg(n, m), p, i, k as f64);
                        }
                    }
                }
            }
        }
    }
    r
}

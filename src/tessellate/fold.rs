//! The fold rule on the samples of a tessellation (the rule is documented in
//! [`crate::quality::validity`]): a sample of domain triangle i (centre, v_{i−1}, v_i) with
//! barycentric weights (a, b, c) is folded where its unit normal turns against the reference
//! normal T × X of ribbon i at the foot s = c/(b + c) of the sample on side i.
//!
//! Per layout, [`Sectors`] holds every sample's (i, s) once (it depends on the domain only); per
//! patch, [`patch_folds`] evaluates the reference normals with [`ribbon_normal_with`] (the normal of
//! [`crate::construct::check::ribbon_frame`], with the binomial coefficients made once per degree) and compares. The tessellation
//! runs it on the samples it has just evaluated, so the check costs no second evaluation.

use super::evaluator::SurfacePoint;
use crate::construct::Patch;
use crate::gb::Ribbon;
use glam::{DVec2, DVec3};

/// Per sample of a layout: its domain triangle i and its foot s ∈ [0, 1] on side i.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Sectors {
    /// Per sample: (i, s). Private with `feet` and `foot`, which are derived from it.
    at: Vec<(u32, f64)>,
    /// The distinct values of `at` (samples on one ray from the centre share their foot), so a
    /// patch evaluates each reference normal once ([`patch_folds`]).
    feet: Vec<(u32, f64)>,
    /// Per sample: the index of its (i, s) in `feet`.
    foot: Vec<u32>,
}

impl Sectors {
    /// Per sample: its domain triangle i and its foot s on side i.
    pub fn at(&self) -> &[(u32, f64)] {
        &self.at
    }

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
        Sectors::of_feet(at)
    }

    /// The sectors with their distinct feet (equal where the bits of s are).
    fn of_feet(at: Vec<(u32, f64)>) -> Sectors {
        let mut index: std::collections::HashMap<(u32, u64), u32> = std::collections::HashMap::new();
        let mut feet = Vec::new();
        let foot = at
            .iter()
            .map(|&(i, s)| {
                *index.entry((i, s.to_bits())).or_insert_with(|| {
                    feet.push((i, s));
                    feet.len() as u32 - 1
                })
            })
            .collect();
        Sectors { at, feet, foot }
    }
}

/// Unit boundary-frame normal T × X of `ribbon` at s (zero where undefined): the same vectors as
/// [`crate::construct::check::ribbon_frame`], T = d Σ B^{d−1}_j(s)(P_{0,j+1} − P_{0,j}),
/// X = d Σ B^d_j(s)(P_{1,j} − P_{0,j}) (the binomial coefficients made for this call; a patch
/// reuses them across its ribbons and feet with [`ribbon_normal_with`]).
pub fn ribbon_normal(ribbon: &Ribbon, s: f64) -> DVec3 {
    ribbon_normal_with(ribbon, s, &mut Binomials::default())
}

/// The binomial coefficients C(d, j), j ≤ d, and C(d − 1, j), j < d, of one degree d, made by
/// the recurrence C(n, j + 1) = C(n, j)·(n − j)/(j + 1) (the values [`ribbon_normal`] sums with),
/// kept for the next ribbon of the same degree (the ribbons of a patch share it).
#[derive(Default)]
pub struct Binomials {
    degree: Option<usize>,
    d: Vec<f64>,
    d1: Vec<f64>,
}

impl Binomials {
    fn of(&mut self, d: usize) -> (&[f64], &[f64]) {
        if self.degree != Some(d) {
            let row = |n: usize, out: &mut Vec<f64>| {
                out.clear();
                let mut binom = 1.0;
                for j in 0..=n {
                    out.push(binom);
                    binom = binom * (n - j) as f64 / (j + 1) as f64;
                }
            };
            row(d, &mut self.d);
            self.d1.clear();
            if d > 0 {
                row(d - 1, &mut self.d1);
            }
            self.degree = Some(d);
        }
        (&self.d, &self.d1)
    }
}

/// [`ribbon_normal`] with the binomial coefficients of the ribbon's degree from `binomials`
/// (made once per degree): the same value.
pub fn ribbon_normal_with(ribbon: &Ribbon, s: f64, binomials: &mut Binomials) -> DVec3 {
    let d = ribbon.degree;
    let (r0, r1) = (ribbon.row(0), ribbon.row(1));
    let u = 1.0 - s;
    // The powers s^j and u^j, j ≤ d, once (each B^d_j and B^{d−1}_j is binom · s^j · u^(n−j)
    // with these very values); on the stack up to degree [`POWERS`] − 1.
    let (mut sp, mut up) = ([0.0; POWERS], [0.0; POWERS]);
    let (sv, uv);
    let (sp, up): (&[f64], &[f64]) = if d < POWERS {
        for j in 0..=d {
            (sp[j], up[j]) = (s.powi(j as i32), u.powi(j as i32));
        }
        (&sp, &up)
    } else {
        sv = (0..=d).map(|j| s.powi(j as i32)).collect::<Vec<f64>>();
        uv = (0..=d).map(|j| u.powi(j as i32)).collect::<Vec<f64>>();
        (&sv, &uv)
    };
    let (bd, bd1) = binomials.of(d);
    let (mut t, mut x) = (DVec3::ZERO, DVec3::ZERO);
    for j in 0..=d {
        x += bd[j] * sp[j] * up[d - j] * (r1[j] - r0[j]);
    }
    for j in 0..d {
        t += bd1[j] * sp[j] * up[d - 1 - j] * (r0[j + 1] - r0[j]);
    }
    reference_normal(t, x)
}

/// Powers kept on the stack by [`ribbon_normal`] (degrees below it; the construction's are far
/// below, higher ones take a heap buffer).
const POWERS: usize = 33;

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
///
/// Each distinct foot's reference normal is evaluated once per patch (the same values as per
/// sample: [`ribbon_normal`] is a function of the ribbon and s).
pub fn patch_folds(patch: &Patch, sectors: &Sectors, uv: &[DVec2], points: &[SurfacePoint]) -> PatchFolds {
    let ribbons = patch.ribbons();
    let mut out = PatchFolds::default();
    let mut worst = 0.0f64;
    // None: the sector names a missing ribbon.
    let mut binomials = Binomials::default();
    let reference: Vec<Option<DVec3>> = sectors.feet.iter().map(|&(i, s)| ribbons.get(i as usize).map(|r| ribbon_normal_with(r, s, &mut binomials))).collect();
    for (k, ((&x, sp), &f)) in uv.iter().zip(points).zip(&sectors.foot).enumerate() {
        if sp.normal == DVec3::ZERO || !sp.normal.is_finite() {
            continue;
        }
        let Some(Some(normal)) = reference.get(f as usize) else { continue };
        let rel = sp.normal.dot(*normal);
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::api::{convert_unchecked, ConvertOptions, Method};
    use crate::tessellate::evaluator::PatchEvaluator;

    #[test]
    fn one_reference_normal_per_foot_gives_the_per_sample_verdicts() {
        // The dual cube with every central point moved 40 along x folds (as the sideways pulls
        // of tests/quality_validity.rs do); the verdicts per sample, with the reference normal
        // evaluated for every sample, are those of patch_folds, folded or not.
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/models/cube.obj");
        let mesh = crate::mesh::read_polymesh(path).unwrap().0;
        let mut folded = 0;
        for (method, pull) in [(Method::Dual, false), (Method::Dual, true), (Method::Topology, false)] {
            for r in [1, 2, 3] {
                let opts = ConvertOptions { method, resolution: r, ..Default::default() };
                let mut surface = convert_unchecked(&mesh, &opts).unwrap().surface.unwrap();
                for p in surface.patches.iter_mut().filter(|_| pull) {
                    let crate::construct::Patch::Gb(g) = p else { panic!("dual cube patches are GB") };
                    g.center += DVec3::new(40.0, 0.0, 0.0);
                }
                let eval = crate::tessellate::evaluator::GbSurfaceEvaluator::new(&surface, opts.sampling(), opts.weights).unwrap();
                for (p, patch) in surface.patches.iter().enumerate() {
                    let n = patch.sides();
                    let layout = crate::gb::SampleLayout::new(&eval.domain(n), opts.sampling()).unwrap();
                    let sectors = Sectors::new(&eval.domain(n), &layout.uv);
                    assert!(sectors.feet.len() < sectors.at.len());
                    let mut buf = Vec::new();
                    eval.evaluate(&surface, p, &layout, &mut buf);
                    let got = patch_folds(patch, &sectors, &layout.uv, &buf);
                    let ribbons = patch.ribbons();
                    let expected: Vec<u32> = (0..buf.len() as u32)
                        .filter(|&k| {
                            let (sp, (i, s)) = (&buf[k as usize], sectors.at[k as usize]);
                            sp.normal != DVec3::ZERO && sp.normal.is_finite() && sp.normal.dot(ribbon_normal(&ribbons[i as usize], s)) < 0.0
                        })
                        .collect();
                    assert_eq!(got.samples, expected, "{method:?} r = {r}, patch {p}");
                    folded += expected.len();
                }
            }
        }
        assert!(folded > 0, "the pulled central points fold");
    }
}

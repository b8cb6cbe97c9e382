//! The fold rule on the samples of a tessellation (the rule is documented in
//! [`crate::quality::validity`] and docs/math.md#folds): a sample of domain triangle i (centre,
//! v_{i−1}, v_i) with barycentric weights (a, b, c) is folded where its unit normal turns against
//! the reference normal unit((1 − a)·N_i(s) + a·N̄) ([`blended_reference`]): N_i(s) the unit
//! normal T × X of ribbon i at the foot s = c/(b + c) of the sample on side i, N̄ the patch's
//! centre reference ([`centre_reference`]: the unit mean of its ribbons' normals at their
//! midpoints, or the unit vector area of its boundary where that is more than 60° from the mean
//! and nearer to the patch's normal at its centre), and one of its neighbours in the layout's
//! triangles has a normal pointing the other way (n·n′ < 0, [`reversed_samples`]: a turnover
//! reverses the normal across its fold line; a strong regular bend does not, docs/math.md#fold-neighbours).
//!
//! The tessellation's samples are too sparse to see a small fold (a Jacobian that turns over near
//! a corner, inside one output face), so the pass runs in two steps (docs/math.md#fold-clearing):
//! [`patch_folds`] applies the rule to the samples just evaluated and, from the same samples,
//! decides whether the patch is *cleared* ([`ClearTest`]); the patches that are not go, after the
//! tessellation's evaluation, to [`dense_folds_of`]: the rule on the samples of a dense triangle
//! layout through weight tables (or [`dense_folds`], the direct evaluator), whose folded samples
//! are the patch's count and whose worst point becomes the patch's site.
//!
//! Per layout, [`Sectors`] holds every sample's (i, s) once (it depends on the domain only); per
//! patch, [`patch_folds`] evaluates the reference normals (the normal of
//! [`crate::construct::check::ribbon_frame`]) once per foot and compares: a cubic ribbon's from
//! the foot's Bernstein weights, which [`Sectors`] makes once per layout ([`cubic_frame_weights`]),
//! other degrees by [`ribbon_normal_with`] (binomial coefficients made once per degree). The tessellation
//! runs it on the samples it has just evaluated, so the check costs no second evaluation.

use super::evaluator::{GbSurfaceEvaluator, PatchEvaluator, SurfacePoint};
use crate::construct::check::fold_sample_points;
use crate::construct::{Patch, Surface};
use std::collections::HashMap;
use crate::gb::{Domain, Ribbon, SampleLayout, Sampling, WeightForm};
use glam::{DVec2, DVec3};

/// Per sample of a layout: its domain triangle i, its foot s ∈ [0, 1] on side i and its centre
/// weight a.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Sectors {
    /// Per sample: (i, s). Private with `feet` and `foot`, which are derived from it.
    at: Vec<(u32, f64)>,
    /// Per sample: its barycentric weight a ∈ [0, 1] on the domain centre (1 at the centre, 0 on
    /// the boundary).
    centre: Vec<f64>,
    /// The distinct values of `at` (samples on one ray from the centre share their foot), so a
    /// patch evaluates each reference normal once ([`patch_folds`]).
    feet: Vec<(u32, f64)>,
    /// Per sample: the index of its (i, s) in `feet`.
    foot: Vec<u32>,
    /// Per foot: its [`cubic_frame_weights`] (made once per layout, not once per patch).
    foot_weights: Vec<[f64; 7]>,
}

impl Sectors {
    /// Per sample: its domain triangle i and its foot s on side i.
    pub fn at(&self) -> &[(u32, f64)] {
        &self.at
    }

    /// Per sample: its centre weight a.
    pub fn centre_weights(&self) -> &[f64] {
        &self.centre
    }

    /// The sample nearest to the domain centre (largest centre weight; the first of equals), or
    /// `None` for an empty layout.
    pub fn centre_sample(&self) -> Option<usize> {
        self.centre.iter().enumerate().fold(None, |best: Option<(usize, f64)>, (k, &a)| match best {
            Some((_, b)) if b >= a => best,
            _ => Some((k, a)),
        }).map(|(k, _)| k)
    }

    /// The sectors of the samples `uv` in the domain polygon `domain` (counter-clockwise,
    /// vertex i ends side i): each sample goes to the domain triangle whose smaller weight on
    /// (v_{i−1}, v_i) is largest (the one containing it), s = c/(b + c) (½ at the centre), and
    /// its centre weight is a = 1 − b − c in that triangle (clamped to [0, 1]).
    pub fn new(domain: &[DVec2], uv: &[DVec2]) -> Sectors {
        let n = domain.len();
        let centre = domain.iter().copied().sum::<DVec2>() / n.max(1) as f64;
        let mut weights = Vec::with_capacity(uv.len());
        let at = uv
            .iter()
            .map(|&x| {
                let q = x - centre;
                let mut best = (0u32, 0.5, f64::NEG_INFINITY);
                let mut a = 1.0;
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
                        a = (1.0 - b - c).clamp(0.0, 1.0);
                    }
                }
                weights.push(a);
                (best.0, best.1)
            })
            .collect();
        Sectors::of_feet(at, weights)
    }

    /// The sectors with their distinct feet (equal where the bits of s are), and each foot's
    /// cubic frame weights ([`cubic_frame_weights`]).
    fn of_feet(at: Vec<(u32, f64)>, centre: Vec<f64>) -> Sectors {
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
        let mut binomials = Binomials::default();
        let foot_weights = feet.iter().map(|&(_, s)| cubic_frame_weights(s, &mut binomials)).collect();
        Sectors { at, centre, feet, foot, foot_weights }
    }
}

/// The centre reference N̄ of a patch (docs/math.md#folds): the unit mean of its ribbons' normals
/// at their midpoints (s = ½; undefined ones left out), or zero when that mean vanishes. It does
/// not depend on which side is numbered first, unlike any one ribbon's normal.
///
/// Around a rim that turns by more than a right angle (a cone's base, whose ribbons all lean
/// outwards and up while the cap faces down) that mean points the wrong way. So it is checked
/// against a second candidate, the unit vector area A = ½ Σ_k p_k × p_{k+1} of the boundary's
/// control polygon (the row 0 points of the ribbons in order, a closed loop; by Stokes' theorem
/// the vector area of a closed curve is ∫ n dA over any surface it bounds, so A of the control
/// polygon approximates the patch's mean normal; not used where |A| is below [`MIN_AREA_RATIO`]
/// of the area of a circle of the same perimeter). Where the two are more than 60° apart
/// ([`CANDIDATES_AGREE`]), N̄ is the one nearer to the patch's own normal at its centre,
/// `centre_normal()` (called only then; zero when undefined, which keeps the mean).
pub fn centre_reference(ribbons: &[Ribbon], binomials: &mut Binomials, centre_normal: impl FnOnce() -> DVec3) -> DVec3 {
    let mean = ribbons.iter().map(|r| ribbon_normal_with(r, 0.5, binomials)).sum::<DVec3>().normalize_or_zero();
    let (area, perimeter) = vector_area(ribbons);
    // A loop whose vector area nearly cancels (a long thin saddle) gives no direction.
    let disc = perimeter * perimeter / (4.0 * std::f64::consts::PI);
    if mean == DVec3::ZERO || !(area.length() > MIN_AREA_RATIO * disc) {
        return mean;
    }
    let area = area.normalize();
    if mean.dot(area) >= CANDIDATES_AGREE {
        return mean;
    }
    let n = centre_normal();
    if n.is_finite() && n.dot(area) > n.dot(mean) {
        area
    } else {
        mean
    }
}

/// Below this ratio of its vector area's length to the area of the circle of the same perimeter,
/// a boundary loop gives no candidate for N̄ ([`centre_reference`] keeps the ribbons' mean): a
/// planar convex loop is above 0.1 while its width is a tenth of its length or more, a loop that
/// folds back over itself is near 0.
pub const MIN_AREA_RATIO: f64 = 0.01;

/// Dot product of the two candidates for N̄ ([`centre_reference`]) above which the ribbons' mean
/// is taken without looking at the patch (cos 60°).
pub const CANDIDATES_AGREE: f64 = 0.5;

/// ½ Σ_k p_k × p_{k+1} over the closed control polygon of the ribbons' row 0 (each ribbon's last
/// point is the next one's first), relative to its first point, and the polygon's length.
fn vector_area(ribbons: &[Ribbon]) -> (DVec3, f64) {
    let mut points = ribbons.iter().flat_map(|r| {
        let row = r.row(0);
        row[..row.len().saturating_sub(1)].iter().copied()
    });
    let Some(first) = points.next() else { return (DVec3::ZERO, 0.0) };
    let (mut area, mut length) = (DVec3::ZERO, 0.0);
    let mut prev = first;
    for p in points.chain(std::iter::once(first)) {
        area += 0.5 * (prev - first).cross(p - first);
        length += prev.distance(p);
        prev = p;
    }
    (area, length)
}

/// The reference normal of a sample with centre weight a whose foot has the ribbon normal `foot`:
/// unit((1 − a)·foot + a·centre), the ribbon's normal on the boundary (a = 0) turning linearly to
/// the patch's centre reference at the centre (a = 1). A patch bends continuously from its
/// boundary normals to its centre, so a surface that turns by up to 180° between a side and the
/// centre without turning over is not flagged, while a sample turned against this interpolated
/// frame is (docs/math.md#folds). Falls back to `foot` where `centre` is zero, a = 0 or the blend
/// vanishes, and to `centre` where `foot` is zero (undefined, as on the ray to a degenerate
/// corner) and a > 0, so the samples on that ray are still judged.
pub fn blended_reference(foot: DVec3, centre: DVec3, a: f64) -> DVec3 {
    if centre == DVec3::ZERO || a <= 0.0 {
        return foot;
    }
    if foot == DVec3::ZERO {
        return centre;
    }
    let r = (1.0 - a) * foot + a * centre;
    let len = r.length();
    if len > MIN_FRAME_SIN {
        // r.normalize() without computing the length again (the same value: r · (1/|r|)).
        r * len.recip()
    } else {
        foot
    }
}

/// How far the unit normal `n` of a sample (centre weight a, foot normal `foot`) agrees with its
/// frame: n·R with R = [`blended_reference`]; `None` where R is undefined. The sample is folded
/// where this is negative and a neighbour's normal is reversed ([`reversed_samples`]).
pub fn reference_dot(n: DVec3, foot: DVec3, centre: DVec3, a: f64) -> Option<f64> {
    let r = blended_reference(foot, centre, a);
    if r == DVec3::ZERO {
        return None;
    }
    Some(n.dot(r))
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
    if ribbon.degree == 3 {
        return cubic_ribbon_normal(ribbon, &cubic_frame_weights(s, binomials));
    }
    general_ribbon_normal(ribbon, s, binomials)
}

/// The reference normal of `ribbon` at the foot s whose cubic weights are `w` (a foot of
/// [`Sectors`]): from the weights for a cubic ribbon, else by [`ribbon_normal_with`].
fn foot_normal(ribbon: &Ribbon, s: f64, w: &[f64; 7], binomials: &mut Binomials) -> DVec3 {
    if ribbon.degree == 3 {
        cubic_ribbon_normal(ribbon, w)
    } else {
        general_ribbon_normal(ribbon, s, binomials)
    }
}

/// [`ribbon_normal_with`] for any degree d (the sums with the powers of s and 1 − s made once).
fn general_ribbon_normal(ribbon: &Ribbon, s: f64, binomials: &mut Binomials) -> DVec3 {
    let d = ribbon.degree;
    let (r0, r1) = (ribbon.row(0), ribbon.row(1));
    let u = 1.0 - s;
    // The powers s^j and u^j, j ≤ d, once (each B^d_j and B^{d−1}_j is binom · s^j · u^(n−j)
    // with these very values), by repeated products; on the stack up to degree [`POWERS`] − 1.
    let (mut sp, mut up) = ([1.0; POWERS], [1.0; POWERS]);
    let (mut sv, mut uv);
    let (sp, up): (&mut [f64], &mut [f64]) = if d < POWERS {
        (&mut sp[..=d], &mut up[..=d])
    } else {
        (sv, uv) = (vec![1.0; d + 1], vec![1.0; d + 1]);
        (&mut sv, &mut uv)
    };
    for j in 1..=d {
        (sp[j], up[j]) = (sp[j - 1] * s, up[j - 1] * u);
    }
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

/// The weights of [`ribbon_normal_with`] for a cubic ribbon at s: B³_j(s), j = 0..3, then
/// B²_j(s), j = 0..2, each binom · s^j · u^(n−j) with the same products in the same order as the
/// general loop, so a patch can make them once per foot ([`Sectors`]) and get the same normals.
pub(crate) fn cubic_frame_weights(s: f64, binomials: &mut Binomials) -> [f64; 7] {
    let u = 1.0 - s;
    let (sp, up) = ([1.0, s, s * s, s * s * s], [1.0, u, u * u, u * u * u]);
    let (bd, bd1) = binomials.of(3);
    let mut w = [0.0; 7];
    for j in 0..=3 {
        w[j] = bd[j] * sp[j] * up[3 - j];
    }
    for j in 0..3 {
        w[4 + j] = bd1[j] * sp[j] * up[2 - j];
    }
    w
}

/// [`ribbon_normal_with`] of a cubic ribbon from its [`cubic_frame_weights`]:
/// X = Σ w_j (P_{1,j} − P_{0,j}), T = Σ w_{4+j} (P_{0,j+1} − P_{0,j}) (the factors d = 3 and 2
/// of T and X left out: they do not change the direction), the unit T × X by
/// [`reference_normal`] (zero where undefined).
pub(crate) fn cubic_ribbon_normal(ribbon: &Ribbon, w: &[f64; 7]) -> DVec3 {
    let (r0, r1) = (ribbon.row(0), ribbon.row(1));
    let (mut t, mut x) = (DVec3::ZERO, DVec3::ZERO);
    for j in 0..=3 {
        x += w[j] * (r1[j] - r0[j]);
    }
    for j in 0..3 {
        t += w[4 + j] * (r0[j + 1] - r0[j]);
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
    // Squared, so one square root (the normalisation's) per call: |T × X|² > s²·|T|²·|X|² is
    // the test above (false for NaN, as is the unsquared one; the same verdict except at
    // rounding-level ties).
    let len2 = n.length_squared();
    if !(len2 > MIN_FRAME_SIN * MIN_FRAME_SIN * t.length_squared() * x.length_squared()) {
        return DVec3::ZERO;
    }
    n.normalize_or_zero()
}

/// Folds of one patch on the tessellation's samples: folded samples (indices into the layout),
/// the worst one, and whether the samples clear the patch ([`ClearTest`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PatchFolds {
    /// Layout indices of the folded samples.
    pub samples: Vec<u32>,
    /// Domain point of the sample whose normal turns furthest against its reference.
    pub worst: Option<DVec2>,
    /// The samples pass [`ClearTest`]: the patch has no fold the dense pass would find, so the
    /// verdict of these samples (no folded sample, as the test demands it) stands.
    pub cleared: bool,
}

/// The test that clears a patch from its tessellation samples alone (docs/math.md#fold-clearing):
/// every sample has a defined normal within 45° of its reference R (dot ≥ [`Self::REFERENCE`]),
/// the normals of every two samples joined by a layout edge are within 45° of each other (dot ≥
/// [`Self::NEIGHBOUR`]), and the smallest Jacobian |S_u × S_v| of a sample is at least
/// [`Self::JACOBIAN`] of the samples' mean. A Jacobian that turns over between the samples (a
/// small fold near a corner, which the samples miss) shows in the data they do have as a normal
/// that turns fast between neighbours, a small Jacobian, or a reference that turns with it.
pub struct ClearTest;

impl ClearTest {
    /// Smallest dot of a sample's normal with its reference (cos 45°, rounded).
    pub const REFERENCE: f64 = 0.7;
    /// Smallest dot of the normals of two samples joined by a layout edge (cos 45°, rounded).
    pub const NEIGHBOUR: f64 = 0.7;
    /// Smallest ratio of a sample's Jacobian to the samples' mean.
    pub const JACOBIAN: f64 = 0.05;
}

/// Dense fold level (steps per side of the triangle layout) for a patch the tessellation's
/// samples do not clear, and of [`crate::quality::find_folds`]: twice the tessellation's own
/// steps per side (`per_side`: r for triangles, 2r for quads), at least [`DENSE_STEPS`]
/// (docs/math.md#fold-clearing). Twice `per_side` rather than 2r, so the dense pass is denser
/// than the tessellation in both layouts (2r would only equal the quad layout's density at r ≥ 8).
/// At the defaults (quads, r = 2) it is 16.
pub fn dense_level(sampling: Sampling) -> usize {
    (2 * sampling.per_side()).max(DENSE_STEPS)
}

/// Least steps per side of the dense pass's layout (docs/math.md#fold-clearing: from 16 steps on
/// the report names every patch the reference sampler of `examples/fold_truth.rs` sees turn over on
/// the public cages except bishop dual patch 1115, where the sampler's own verdict changes between
/// 60 and 120 steps).
pub const DENSE_STEPS: usize = 16;

/// Per sample (of `n`): whether one of its neighbours (the `edges` of the layout) has a normal
/// pointing the other way, n·n′ < 0 (docs/math.md#folds: the second condition of a folded
/// sample). Undefined (zero) normals reverse nothing.
fn reversed_samples(n: usize, edges: impl Iterator<Item = (u32, u32)>, normal: impl Fn(u32) -> DVec3) -> Vec<bool> {
    let mut reversed = vec![false; n];
    for (i, j) in edges {
        if normal(i).dot(normal(j)) < 0.0 {
            for q in [i, j] {
                if let Some(r) = reversed.get_mut(q as usize) {
                    *r = true;
                }
            }
        }
    }
    reversed
}

/// Applies the fold rule to the evaluated `points` of `patch` at the samples of `layout` with
/// their `sectors`, and the [`ClearTest`]. Samples with an undefined normal (zero or non-finite,
/// e.g. at a collapsed corner) and samples whose reference normal is undefined are skipped: the
/// sign means nothing there (and the patch is not cleared).
///
/// Each distinct foot's reference normal is evaluated once per patch (the same values as per
/// sample: [`ribbon_normal`] is a function of the ribbon and s).
pub fn patch_folds(patch: &Patch, sectors: &Sectors, layout: &SampleLayout, points: &[SurfacePoint]) -> PatchFolds {
    let ribbons = patch.ribbons();
    let mut out = PatchFolds::default();
    let mut worst = 0.0f64;
    let mut cleared = points.len() == layout.uv.len();
    // None: the sector names a missing ribbon.
    let mut binomials = Binomials::default();
    let reference: Vec<Option<DVec3>> = sectors
        .feet
        .iter()
        .zip(&sectors.foot_weights)
        .map(|(&(i, s), w)| {
            ribbons.get(i as usize).map(|r| foot_normal(r, s, w, &mut binomials))
        })
        .collect();
    let centre = centre_reference(ribbons, &mut binomials, || {
        sectors.centre_sample().and_then(|k| points.get(k)).map_or(DVec3::ZERO, |p| p.normal)
    });
    let normal = |i: u32| points.get(i as usize).map_or(DVec3::ZERO, |p| p.normal);
    // Samples opposing their reference (k, n·R, domain point), in layout order: rare, so the
    // neighbour condition is computed only when there are some.
    let mut opposing: Vec<(usize, f64, DVec2)> = Vec::new();
    for (k, (((&x, sp), &f), &a)) in layout.uv.iter().zip(points).zip(&sectors.foot).zip(&sectors.centre).enumerate() {
        if sp.normal == DVec3::ZERO || !sp.normal.is_finite() {
            cleared = false;
            continue;
        }
        let Some(Some(normal)) = reference.get(f as usize) else {
            cleared = false;
            continue;
        };
        let Some(rel) = reference_dot(sp.normal, *normal, centre, a) else {
            cleared = false;
            continue;
        };
        cleared &= rel >= ClearTest::REFERENCE;
        if rel < 0.0 {
            opposing.push((k, rel, x));
        }
    }
    if !opposing.is_empty() {
        let reversed = reversed_samples(points.len(), layout.triangles.iter().flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])]), normal);
        for (k, rel, x) in opposing.into_iter().filter(|&(k, _, _)| reversed[k]) {
            out.samples.push(k as u32);
            if rel < worst {
                worst = rel;
                out.worst = Some(x);
            }
        }
    }
    if cleared {
        let mean = points.iter().map(|p| p.jacobian).sum::<f64>() / points.len().max(1) as f64;
        cleared = points.iter().all(|p| p.jacobian >= ClearTest::JACOBIAN * mean) && mean > 0.0;
    }
    if cleared {
        let close = |a: u32, b: u32| normal(a).dot(normal(b)) >= ClearTest::NEIGHBOUR;
        cleared = layout.triangles.iter().all(|t| close(t[0], t[1]) && close(t[1], t[2]) && close(t[2], t[0]));
    }
    out.cleared = cleared;
    out
}

/// (S_u × S_v) at a domain point of a GB or CGB patch with a prepared evaluator.
enum PatchEval<'a> {
    Gb(&'a crate::gb::GbPatch, crate::gb::GbBasisEvaluator),
    Cgb(&'a crate::gb::CgbPatch, crate::gb::CgbBasisEvaluator),
}

impl PatchEval<'_> {
    fn new(patch: &Patch) -> Option<PatchEval<'_>> {
        match patch {
            Patch::Gb(g) => g.evaluator().ok().map(|e| PatchEval::Gb(g, e)),
            Patch::Cgb(c) => c.evaluator().ok().map(|e| PatchEval::Cgb(c, e)),
        }
    }
    fn derivs(&mut self, uv: DVec2, form: WeightForm) -> crate::gb::SurfaceDerivs {
        match self {
            PatchEval::Gb(g, e) => g.eval_derivs_with_form(e, uv, form),
            PatchEval::Cgb(c, e) => c.eval_derivs_with(e, uv, form),
        }
    }

    fn jacobian_normal(&mut self, uv: DVec2, form: WeightForm) -> DVec3 {
        let d = self.derivs(uv, form);
        d.su.cross(d.sv)
    }

    /// The unit normal at `uv` ([`crate::gb::SurfaceDerivs::normal`]), zero where the
    /// parameterisation degenerates.
    fn unit_normal(&mut self, uv: DVec2, form: WeightForm) -> DVec3 {
        self.derivs(uv, form).normal().unwrap_or(DVec3::ZERO)
    }
}

/// The fold rule on a dense grid of `patch`, evaluated directly with weight form `form`: in each
/// domain triangle i of the regular n-gon the barycentric grid (a, b, c)/`level`
/// ([`fold_sample_points`], the boundary row pulled 10⁻³ inside), a sample folded where
/// (S_u × S_v)·R < 0 with R = [`blended_reference`] of its foot and a grid neighbour's normal is
/// reversed ([`reversed_samples`]; the neighbours across the spokes and at the centre included,
/// as the table layout has them; the boundary row, pulled inside differently from the table
/// layout's, can differ by a sample). Each sample is taken once: the
/// spoke c → v_i shared by triangles i and i + 1 in triangle i + 1 (its c = 0 row), the centre in
/// triangle 0, so the samples are those of the table path's layout of the same level,
/// 1 + n·level(level + 1)/2. Returns (folded samples, domain point of the worst). Samples whose
/// Jacobian or reference is undefined are skipped.
pub fn dense_folds(patch: &Patch, level: usize, form: WeightForm) -> (usize, Option<DVec2>) {
    let n = patch.sides();
    let level = level.max(1);
    let (Ok(domain), Some(mut ev)) = (Domain::regular(n), PatchEval::new(patch)) else {
        return (0, None);
    };
    let ribbons = patch.ribbons();
    let mut binomials = Binomials::default();
    let centre = centre_reference(ribbons, &mut binomials, || ev.unit_normal(domain.center(), form));
    let (mut count, mut worst, mut at) = (0usize, 0.0f64, None);
    // Grid point (a, b) of a domain triangle (c = level − a − b), in fold_sample_points' order.
    let index = |a: usize, b: usize| a * (level + 1) - a * a.saturating_sub(1) / 2 + b;
    let n_pts = (level + 1) * (level + 2) / 2;
    // The grid of every domain triangle and the unit normals at its points (zero where undefined).
    let grids: Vec<Vec<DVec2>> = (0..n).map(|i| fold_sample_points(&domain, i, level)).collect();
    let normals: Vec<Vec<DVec3>> = grids
        .iter()
        .map(|pts| {
            pts.iter()
                .map(|&uv| {
                    let jn = ev.jacobian_normal(uv, form);
                    let scale = jn.length();
                    if scale > 0.0 { jn / scale } else { DVec3::ZERO }
                })
                .collect()
        })
        .collect();
    // The reversed ones among the grid's edges (directions (0, 1, −1), (1, 0, −1), (1, −1, 0) in
    // (a, b, c)), then shared along the spokes (triangle i's b = 0 row is triangle i + 1's c = 0
    // row) and at the centre, so each point has every neighbour the table layout gives it.
    let mut reversed: Vec<Vec<bool>> = normals
        .iter()
        .map(|nm| {
            let edges = (0..=level).flat_map(|a| (0..=(level - a)).map(move |b| (a, b))).flat_map(|(a, b)| {
                let c = level - a - b;
                let at = index(a, b) as u32;
                [(c >= 1).then(|| (at, index(a, b + 1) as u32)), (c >= 1).then(|| (at, index(a + 1, b) as u32)), (b >= 1).then(|| (at, index(a + 1, b - 1) as u32))]
                    .into_iter()
                    .flatten()
            });
            reversed_samples(n_pts, edges, |k| nm[k as usize])
        })
        .collect();
    for i in 0..n {
        let j = (i + 1) % n;
        for a in 0..=level {
            let (ki, kj) = (index(a, 0), index(a, level - a));
            let r = reversed[i][ki] || reversed[j][kj];
            reversed[i][ki] = r;
            reversed[j][kj] = r;
        }
    }
    let centre_reversed = reversed.iter().any(|r| r[index(level, 0)]);
    for r in &mut reversed {
        r[index(level, 0)] = centre_reversed;
    }
    for ((i, ribbon), pts) in ribbons.iter().enumerate().zip(&grids) {
        let mut k = 0;
        for a in 0..=level {
            for b in 0..=(level - a) {
                let c = level - a - b;
                let uv = pts[k];
                let (unit, rev) = (normals[i][k], reversed[i][k]);
                k += 1;
                // The b = 0 row (the spoke to v_i) is the next triangle's c = 0 row, and the
                // centre is in every triangle: each is counted once (in triangle i + 1, and in
                // triangle 0), as the table path's layout holds it once.
                if b == 0 && !(a == level && i == 0) {
                    continue;
                }
                if unit == DVec3::ZERO {
                    continue;
                }
                let s = if b + c == 0 { 0.5 } else { c as f64 / (b + c) as f64 };
                let foot = ribbon_normal_with(ribbon, s, &mut binomials);
                let Some(rel) = reference_dot(unit, foot, centre, a as f64 / level as f64) else {
                    continue;
                };
                if rel < 0.0 && rev {
                    count += 1;
                    if rel < worst {
                        worst = rel;
                        at = Some(uv);
                    }
                }
            }
        }
    }
    (count, at)
}

/// [`dense_folds`] of the patches `which` of `surface` (per listed patch: folded samples, worst
/// domain point), through weight tables of the triangle layout of resolution `level`
/// ([`GbSurfaceEvaluator`] on a surface of those patches alone, each sample with its sector
/// ([`Sectors`]) and the rule of [`patch_folds`]): the same rule on the level's own samples, the
/// boundary included, at a fraction of the direct evaluator's cost. A patch the tables do not
/// evaluate (or a layout that cannot be built) falls back to [`dense_folds`].
pub fn dense_folds_of(
    surface: &Surface,
    which: &[usize],
    level: usize,
    form: WeightForm,
) -> Vec<(usize, Option<DVec2>)> {
    let mut never = |_: usize| Ok::<(), std::convert::Infallible>(());
    match dense_folds_of_ticked(surface, which, level, form, which.len(), &mut never) {
        Ok(v) => v,
        Err(never) => match never {},
    }
}

/// [`dense_folds_of`] in chunks of `chunk` patches (the tables made once), calling `on_chunk`
/// with the number of patches done after each chunk on the calling thread; its error stops the
/// pass (a cancel takes effect after the running chunk).
pub fn dense_folds_of_ticked<E>(
    surface: &Surface,
    which: &[usize],
    level: usize,
    form: WeightForm,
    chunk: usize,
    on_chunk: &mut dyn FnMut(usize) -> Result<(), E>,
) -> Result<Vec<(usize, Option<DVec2>)>, E> {
    use rayon::prelude::*;
    let level = level.max(1);
    let chunk = chunk.max(1);
    let mut out = Vec::with_capacity(which.len());
    // Runs `one` on the patches in chunks (indices into `which`), ticking after each.
    type One<'a> = dyn Fn(&mut Vec<SurfacePoint>, usize) -> (usize, Option<DVec2>) + Sync + 'a;
    let mut chunked = |one: &One<'_>| -> Result<(), E> {
        let mut done = 0;
        while done < which.len() {
            let end = (done + chunk).min(which.len());
            out.par_extend((done..end).into_par_iter().map_init(Vec::new, |buf, k| one(buf, k)));
            done = end;
            on_chunk(done)?;
        }
        Ok(())
    };
    let direct = |_: &mut Vec<SurfacePoint>, k: usize| {
        surface.patches.get(which[k]).map_or((0, None), |x| dense_folds(x, level, form))
    };
    if which.is_empty() {
        return Ok(out);
    }
    let patches: Vec<Patch> = which.iter().filter_map(|&p| surface.patches.get(p).cloned()).collect();
    if patches.len() != which.len() {
        chunked(&direct)?;
        return Ok(out);
    }
    let sub = Surface::of_patches(patches);
    let Ok(eval) = GbSurfaceEvaluator::new(&sub, level, form) else {
        chunked(&direct)?;
        return Ok(out);
    };
    let mut layouts: HashMap<usize, Option<(Sectors, SampleLayout)>> = HashMap::new();
    for p in &sub.patches {
        layouts.entry(p.sides()).or_insert_with(|| {
            let domain = eval.domain(p.sides());
            let layout = SampleLayout::new(&domain, level).ok()?;
            Some((Sectors::new(&domain, &layout.uv), layout))
        });
    }
    let tabled = |buf: &mut Vec<SurfacePoint>, i: usize| {
        let p = &sub.patches[i];
        let Some((sectors, layout)) = &layouts[&p.sides()] else { return dense_folds(p, level, form) };
        eval.evaluate(&sub, i, layout, buf);
        if buf.len() != layout.uv.len() {
            return dense_folds(p, level, form);
        }
        let f = patch_folds(p, sectors, layout, buf);
        (f.samples.len(), f.worst)
    };
    chunked(&tabled)?;
    Ok(out)
}

/// The samples of `layout` around the domain point `at`: the nearest sample and the other corners
/// of the layout triangles that hold it (where [`dense_folds`] found a fold between the samples,
/// the output vertices that mark it).
pub fn samples_around(layout: &SampleLayout, at: DVec2) -> Vec<u32> {
    let d = |k: usize| layout.uv[k].distance_squared(at);
    let Some(near) = (0..layout.uv.len()).min_by(|&a, &b| d(a).total_cmp(&d(b))) else {
        return Vec::new();
    };
    let near = near as u32;
    let mut out = vec![near];
    for t in layout.triangles.iter().filter(|t| t.contains(&near)) {
        out.extend(t.iter().copied().filter(|&x| x != near));
    }
    out.sort_unstable();
    out.dedup();
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
    fn cubic_frame_weights_give_the_general_ribbon_normal() {
        // A cubic ribbon's normal through the per-foot weights equals (a) T × X summed with
        // Bernstein values of crate::bezier, and (b) the general path's normal of the same
        // ribbon elevated to degree 4 (row 0 elevated, row 1 − row 0 elevated: the same curve
        // and the same cross direction up to a positive factor), at s = 0, 1 and in between.
        let mut seed = 12345u64;
        let mut next = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let elevate = |p: &[DVec3]| -> Vec<DVec3> {
            let d = p.len() - 1;
            (0..=d + 1)
                .map(|j| {
                    let a = j as f64 / (d + 1) as f64;
                    let lo = if j > 0 { p[j - 1] } else { DVec3::ZERO };
                    let hi = if j <= d { p[j] } else { DVec3::ZERO };
                    a * lo + (1.0 - a) * hi
                })
                .collect()
        };
        let mut binomials = Binomials::default();
        for _ in 0..200 {
            let pts: Vec<DVec3> = (0..8).map(|_| DVec3::new(next(), next(), next())).collect();
            let cubic = Ribbon::from_fn(3, 2, 4, |k, j| pts[4 * k + j]);
            let (r0, r1) = (cubic.row(0).to_vec(), cubic.row(1).to_vec());
            let diff: Vec<DVec3> = r1.iter().zip(&r0).map(|(a, b)| *a - *b).collect();
            let (e0, ed) = (elevate(&r0), elevate(&diff));
            let quartic = Ribbon::from_fn(4, 2, 5, |k, j| if k == 0 { e0[j] } else { e0[j] + ed[j] });
            for s in [0.0, 1.0, 0.5, (next() + 1.0) / 2.0] {
                let w = cubic_frame_weights(s, &mut binomials);
                let fast = cubic_ribbon_normal(&cubic, &w);
                // Bit for bit the general loop's value at degree 3 (the weights are its products).
                assert_eq!(fast, general_ribbon_normal(&cubic, s, &mut binomials));
                let b = |n: usize, j: usize| crate::bezier::bernstein::bernstein(n, j, s);
                let x: DVec3 = (0..4).map(|j| b(3, j) * diff[j]).sum();
                let t: DVec3 = (0..3).map(|j| b(2, j) * (r0[j + 1] - r0[j])).sum();
                let direct = reference_normal(t, x);
                let general = ribbon_normal_with(&quartic, s, &mut binomials);
                if t.cross(x).length() < 1e-3 * t.length() * x.length() {
                    continue; // a nearly degenerate frame amplifies rounding: not a test of the formula
                }
                crate::assert_near!(fast, direct, 1e-9);
                crate::assert_near!(general, direct, 1e-9);
            }
        }
    }

    #[test]
    fn one_reference_normal_per_foot_gives_the_per_sample_verdicts() {
        // The dual cube with every central point moved 40 along x folds (as the sideways pulls
        // of tests/quality_validity.rs do); the verdicts per sample, with the reference normal
        // evaluated for every sample and the neighbour condition checked on the layout's
        // triangles, are those of patch_folds, folded or not.
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
                    let got = patch_folds(patch, &sectors, &layout, &buf);
                    let ribbons = patch.ribbons();
                    let centre = centre_reference(ribbons, &mut Binomials::default(), || {
                        sectors.centre_sample().map_or(DVec3::ZERO, |k| buf[k].normal)
                    });
                    // Samples with a layout neighbour whose normal points the other way.
                    let mut rev = vec![false; buf.len()];
                    for t in &layout.triangles {
                        for (x, y) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                            if buf[x as usize].normal.dot(buf[y as usize].normal) < 0.0 {
                                rev[x as usize] = true;
                                rev[y as usize] = true;
                            }
                        }
                    }
                    let expected: Vec<u32> = (0..buf.len() as u32)
                        .filter(|&k| rev[k as usize])
                        .filter(|&k| {
                            let (sp, (i, s)) = (&buf[k as usize], sectors.at[k as usize]);
                            let foot = ribbon_normal(&ribbons[i as usize], s);
                            let rel = reference_dot(sp.normal, foot, centre, sectors.centre[k as usize]);
                            sp.normal != DVec3::ZERO && sp.normal.is_finite() && rel.is_some_and(|r| r < 0.0)
                        })
                        .collect();
                    assert_eq!(got.samples, expected, "{method:?} r = {r}, patch {p}");
                    folded += expected.len();
                }
            }
        }
        assert!(folded > 0, "the pulled central points fold");
    }

    #[test]
    fn the_direct_dense_pass_counts_each_sample_once_as_the_tables_do() {
        // The dual cube with every central point moved 40 along x: its patches fold over a large
        // region, the spokes and the centre included, so a sample counted twice (or n times, the
        // centre) by the direct grids would show in the count.
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/models/cube.obj");
        let mesh = crate::mesh::read_polymesh(path).unwrap().0;
        let opts = ConvertOptions { method: Method::Dual, ..Default::default() };
        let mut surface = convert_unchecked(&mesh, &opts).unwrap().surface.unwrap();
        for p in surface.patches.iter_mut() {
            let crate::construct::Patch::Gb(g) = p else { panic!("dual cube patches are GB") };
            g.center += DVec3::new(40.0, 0.0, 0.0);
        }
        let level = DENSE_STEPS;
        let all: Vec<usize> = (0..surface.patches.len()).collect();
        let tables = dense_folds_of(&surface, &all, level, opts.weights);
        let mut folded = 0;
        for (p, patch) in surface.patches.iter().enumerate() {
            let direct = dense_folds(patch, level, opts.weights);
            assert_eq!(direct.0, tables[p].0, "patch {p}");
            folded += direct.0;
        }
        assert!(folded > 0, "the pulled central points fold");
    }
}

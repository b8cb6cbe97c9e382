//! The central control point of a GB patch fitted to its boundary (docs/math.md#centre-fit; not
//! in the seeds, defined here), for every side count but 4 ([`fits`]).
//!
//! The seed puts a dual patch's central point C at its cage vertex (seed 000 §2.4). On a patch of
//! many sides the central weight B₀ is large over most of the domain (at the centre of a cubic
//! patch B₀ = (n − 2)(n − 4)/n², 0.82 for n = 32), so C alone shapes the middle of the patch, and
//! the cage vertex is rarely where the ribbons would have the surface go: the valence-32 pole of
//! Blender's UV sphere became a point whose mean curvature was −10.7/R instead of −1/R.
//!
//! Here C moves along the patch's normal N at its domain centre to the point where the centre's
//! mean curvature H equals that of the isotropic paraboloid z = ½κr² (in the frame of the centre
//! point and N) fitted by least squares to points of the boundary curves. Moving C by t·N changes
//! neither S_u nor S_v at the centre (∇B₀ = 0 there: B₀ is invariant under the rotations of the
//! regular domain), so N, E, F, G stay and H is affine in t, H(t) = H₀ + h·t; the centre point
//! moves by t·B₀(0)·N, so the fit κ(t) = 2 Σ z_k r_k² / Σ r_k⁴ with z_k = (p_k − S(0))·N is affine
//! in t too. One linear equation gives t. The ribbons, hence the boundary and G1, are unchanged.

use crate::gb::{Domain, Evaluate, GbPatch, WeightForm};
use glam::DVec3;

/// Whether a GB patch of `n` sides gets its central point fitted: every n but 4. At the centre
/// of a cubic patch B₀(0) = (n − 2)(n − 4)/n² (−1/9 for n = 3, 0.22 for n = 6, 0.82 for n = 32):
/// for n = 4 it vanishes, so C does not move the centre point and reaches the centre's curvature
/// only through B₀'s second derivatives; quads keep the seed's C (the tensor-product-like case the
/// seed's rule was made for). Measured (docs/math.md#centre-fit): fitting every n ≥ 3 but 4 rather
/// than n ≥ 9 makes the rook's dual fold-free and lowers the ico and quad spheres' |H·R + 1|.
pub fn fits(n: usize) -> bool {
    n >= 3 && n != 4
}

/// Smallest |h − dκ/dt| relative to |h| for which the fit is solved (module doc): below it the
/// centre's curvature and the fit change alike with C and no move matches them.
pub const MIN_SLOPE_GAP: f64 = 0.1;

/// Largest move of C, relative to the RMS distance of the boundary points from the centre point:
/// a move of the size of the patch itself is no correction of its middle any more. (Measured on
/// the apexes of cones of 9 to 32 sides and height 0.2 to 3: moves of 0.08 to 0.76 of it. On
/// fewer sides the clamp acts: 1.03 on the corners of a cube, 1.25 on a 3-sided cone of height
/// 0.5, 1.33 on the apex of a 5-sided one of height 3; there H stays short of κ.)
pub const MAX_MOVE: f64 = 1.0;

/// Points per side of the boundary (s = k/4, k = 0..3) the paraboloid is fitted to.
const SAMPLES_PER_SIDE: usize = 4;

/// Moves `patch`'s central point along its centre normal so that the centre's mean curvature
/// matches the paraboloid fitted to its boundary (module doc). Leaves the patch as it is where the
/// centre's normal or curvature is undefined, or where the equation is ill-conditioned (the two
/// slopes h and dκ/dt within a tenth of h of each other, [`MIN_SLOPE_GAP`]); the move is at most
/// the boundary's RMS distance from the centre point ([`MAX_MOVE`]). Only for patches whose
/// sides are all shared: the caller leaves the patches of open boundary vertices alone (a
/// one-sided boundary says nothing of the curvature across it).
pub fn fit_centre(patch: &mut GbPatch, form: WeightForm) {
    let n = patch.ribbons.len();
    let Ok(domain) = Domain::regular(n) else { return };
    let at = domain.center();
    let d0 = patch.eval_derivs(at, form);
    let Some(normal) = d0.normal() else { return };
    let Some((h0, _)) = d0.mean_and_gaussian(normal) else { return };
    let boundary: Vec<DVec3> = patch
        .ribbons
        .iter()
        .flat_map(|r| (0..SAMPLES_PER_SIDE).map(move |k| r.boundary_point(k as f64 / SAMPLES_PER_SIDE as f64)))
        .collect();
    let (mut szr, mut sr2, mut sr4, mut sd2) = (0.0, 0.0, 0.0, 0.0);
    for p in &boundary {
        let d = *p - d0.p;
        let z = d.dot(normal);
        let r2 = (d.length_squared() - z * z).max(0.0);
        (szr, sr2, sr4, sd2) = (szr + z * r2, sr2 + r2, sr4 + r2 * r2, sd2 + d.length_squared());
    }
    if !(sr4 > 0.0) {
        return;
    }
    // One step of length ℓ along N gives h and B₀(0) (both exact: the dependence is affine).
    let step = (sr2 / boundary.len() as f64).sqrt();
    let seed = patch.center;
    patch.center = seed + step * normal;
    let d1 = patch.eval_derivs(at, form);
    patch.center = seed;
    let Some((h1, _)) = d1.mean_and_gaussian(normal) else { return };
    let h = (h1 - h0) / step;
    let b0 = (d1.p - d0.p).dot(normal) / step;
    let kappa0 = 2.0 * szr / sr4;
    let dkappa = -2.0 * b0 * sr2 / sr4;
    if !((h - dkappa).abs() >= MIN_SLOPE_GAP * h.abs()) {
        return;
    }
    let bound = MAX_MOVE * (sd2 / boundary.len() as f64).sqrt();
    let t = (kappa0 - h0) / (h - dkappa);
    if t.is_finite() {
        patch.center += t.clamp(-bound, bound) * normal;
    }
}

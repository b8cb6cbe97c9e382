//! Joins of two tensor-product patches along a common boundary (seed 001 §2.4).
//!
//! Convention: patch `a` meets patch `b` with a's side u = 1 on b's side u = 0, both boundary
//! curves running in the same v direction. Other configurations are brought to this one with
//! `transposed`, `reversed_u` and `reversed_v`. `delta_a`, `delta_b` are the lengths Δ_{I−1},
//! Δ_I of the two patches' u intervals in the composite surface (seed 001 eq. 2.17).

use super::curve::BezierCurve;
use super::surface::{BezierSurface, RationalSurface, SurfacePartials};
use super::{angle_between, BezierError, Point};
use glam::DVec3;

/// A surface over DVec3 with position and partial derivatives (polynomial or rational).
pub trait PartialsSurface {
    /// Position and first and second partials at (u, v).
    fn partials_at(&self, u: f64, v: f64) -> SurfacePartials<DVec3>;
}

impl PartialsSurface for BezierSurface<DVec3> {
    fn partials_at(&self, u: f64, v: f64) -> SurfacePartials<DVec3> {
        self.partials(u, v)
    }
}

impl PartialsSurface for RationalSurface<DVec3> {
    fn partials_at(&self, u: f64, v: f64) -> SurfacePartials<DVec3> {
        self.partials(u, v)
    }
}

/// Max control-point distance of two curves after elevating both to the higher degree; zero
/// exactly when they are the same polynomial curve, and a bound of their pointwise distance.
fn curve_deviation<P: Point>(x: &BezierCurve<P>, y: &BezierCurve<P>) -> f64 {
    let d = x.degree().max(y.degree());
    let (x, y) = (x.elevate_by(d - x.degree()), y.elevate_by(d - y.degree()));
    x.points()
        .iter()
        .zip(y.points())
        .map(|(&p, &q)| (p - q).norm())
        .fold(0.0, f64::max)
}

/// The scaled cross-boundary derivative curves for k = 0..=r:
/// a: Δ_a^{−k} ∂^k a/∂u^k (1, v), b: Δ_b^{−k} ∂^k b/∂u^k (0, v) (seed 001 eq. 2.17).
fn cross_derivatives<P: Point>(
    a: &BezierSurface<P>,
    b: &BezierSurface<P>,
    r: usize,
    delta_a: f64,
    delta_b: f64,
) -> Vec<(BezierCurve<P>, BezierCurve<P>)> {
    let (mut da, mut db) = (a.clone(), b.clone());
    let mut out = Vec::with_capacity(r + 1);
    for k in 0..=r {
        let sa = delta_a.powi(-(k as i32));
        let sb = delta_b.powi(-(k as i32));
        let row_a = da
            .points()
            .last()
            .expect("non-empty grid")
            .iter()
            .map(|&p| p * sa)
            .collect();
        let row_b = db.points()[0].iter().map(|&p| p * sb).collect();
        out.push((BezierCurve::from_vec(row_a), BezierCurve::from_vec(row_b)));
        da = da.derivative_u();
        db = db.derivative_u();
    }
    out
}

/// For k = 0..=r, the max control-point deviation between the scaled k-th cross-boundary
/// derivative curves of a (at u = 1) and b (at u = 0): entry 0 is the C0 gap of the boundary
/// curves, entry 1 the C1 condition (1/Δ_a) m_a (p_{m,j} − p_{m−1,j}) = (1/Δ_b) m_b (q_{1,j} − q_{0,j})
/// (seed 001 eq. 2.18), and so on. Curves of different v degree are compared after elevation.
pub fn cross_derivative_deviations<P: Point>(
    a: &BezierSurface<P>,
    b: &BezierSurface<P>,
    r: usize,
    delta_a: f64,
    delta_b: f64,
) -> Vec<f64> {
    cross_derivatives(a, b, r, delta_a, delta_b)
        .iter()
        .map(|(x, y)| curve_deviation(x, y))
        .collect()
}

/// C0 gap: max control-point distance of the boundary curves a(1, v) and b(0, v).
pub fn c0_deviation<P: Point>(a: &BezierSurface<P>, b: &BezierSurface<P>) -> f64 {
    cross_derivative_deviations(a, b, 0, 1.0, 1.0)[0]
}

/// C1 gap across the boundary: the k = 1 entry of [`cross_derivative_deviations`].
pub fn c1_deviation<P: Point>(
    a: &BezierSurface<P>,
    b: &BezierSurface<P>,
    delta_a: f64,
    delta_b: f64,
) -> f64 {
    cross_derivative_deviations(a, b, 1, delta_a, delta_b)[1]
}

/// The continuity order across the boundary, checked up to `max_order` (seed 001 thm. 2.3):
/// the largest r with every k ≤ r deviation within `tol` relative to max(1, the largest control
/// point of the compared curves). `None` when the patches do not share the boundary (not C0).
pub fn continuity_order<P: Point>(
    a: &BezierSurface<P>,
    b: &BezierSurface<P>,
    max_order: usize,
    delta_a: f64,
    delta_b: f64,
    tol: f64,
) -> Option<usize> {
    let ok = |(x, y): &(BezierCurve<P>, BezierCurve<P>)| {
        let scale = x
            .points()
            .iter()
            .chain(y.points())
            .map(|p| p.norm())
            .fold(1.0, f64::max);
        curve_deviation(x, y) <= tol * scale
    };
    cross_derivatives(a, b, max_order, delta_a, delta_b)
        .iter()
        .take_while(|c| ok(c))
        .count()
        .checked_sub(1)
}

/// G1 check: the largest angle in [0, π] between the unit normals of a at (1, v) and b at (0, v)
/// over `samples` (at least 2) equally spaced v ∈ [0, 1]. 0 means the tangent planes agree with
/// the same orientation (seed 001 §2.4, eq. 2.19); π means flipped normals. Errors where a
/// normal vanishes (patch 0 is a, 1 is b).
pub fn g1_max_angle<S: PartialsSurface>(a: &S, b: &S, samples: usize) -> Result<f64, BezierError> {
    let samples = samples.max(2);
    let mut worst: f64 = 0.0;
    for s in 0..samples {
        let v = s as f64 / (samples - 1) as f64;
        let na = a
            .partials_at(1.0, v)
            .normal()
            .ok_or(BezierError::DegenerateNormal { patch: 0, v })?;
        let nb = b
            .partials_at(0.0, v)
            .normal()
            .ok_or(BezierError::DegenerateNormal { patch: 1, v })?;
        worst = worst.max(angle_between(na, nb));
    }
    Ok(worst)
}

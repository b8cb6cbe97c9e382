//! Polynomial and composite Bézier curves (seed 001 §1; seed 000 eq. 2.3, 2.10).

use gbsurf::assert_near;
use gbsurf::bezier::curve::gauss_legendre;
use gbsurf::bezier::{BezierCurve, BezierError, CompositeCurve, Point};
use gbsurf::{DVec2, DVec3};
use proptest::prelude::*;

fn v(x: f64, y: f64) -> DVec3 {
    DVec3::new(x, y, 0.0)
}

fn cubic() -> BezierCurve<DVec3> {
    BezierCurve::new(vec![v(0.0, 0.0), v(1.0, 2.0), v(3.0, 3.0), v(4.0, 0.0)]).unwrap()
}

#[test]
fn cubic_known_points_and_seed000_eq_2_10() {
    let c = cubic();
    assert_eq!(c.degree(), 3);
    assert_near!(c.eval(0.5), v(2.0, 15.0 / 8.0));
    assert_near!(c.eval_bernstein(0.5), v(2.0, 15.0 / 8.0));
    assert_eq!(c.eval(0.0), c.points()[0]);
    assert_eq!(c.eval(1.0), c.points()[3]);
    for &t in &[0.0f64, 0.13, 0.5, 0.71, 1.0] {
        let s = 1.0 - t;
        let p = c.points();
        let explicit = p[0] * s.powi(3)
            + p[1] * (3.0 * s * s * t)
            + p[2] * (3.0 * s * t * t)
            + p[3] * t.powi(3);
        assert_near!(c.eval(t), explicit);
        assert_near!(c.eval_bernstein(t), explicit);
    }
}

#[test]
fn cubic_derivatives_by_hand() {
    // Δp = (1,2), (2,1), (1,−3); Δ²p = (1,−1), (−1,−4); Δ³p = (−2,−3).
    let c = cubic();
    assert_near!(c.derivative(0.5, 1), v(4.5, 0.75));
    assert_near!(c.derivative(0.5, 2), v(0.0, -15.0));
    assert_near!(c.derivative(0.5, 3), v(-12.0, -18.0));
    assert_near!(c.derivative(0.5, 4), v(0.0, 0.0));
    assert_eq!(c.derivative_curve(7).degree(), 0);
    // Seed 001 eq. 1.17: end derivatives depend on the end control points only.
    assert_near!(c.derivative(0.0, 1), v(3.0, 6.0));
    assert_near!(c.derivative(1.0, 1), v(3.0, -9.0));
    assert_near!(c.derivative(0.0, 2), v(6.0, -6.0));
    assert_near!(c.derivative(1.0, 2), v(-6.0, -24.0));
    let d = c.derivatives(0.5, 3);
    assert_near!(
        d,
        vec![c.eval(0.5), v(4.5, 0.75), v(0.0, -15.0), v(-12.0, -18.0)]
    );
    assert_eq!(c.forward_differences(3), vec![v(-2.0, -3.0)]);
    assert!(c.forward_differences(4).is_empty());
}

#[test]
fn elevation_subdivision_reversal_exact() {
    let q = BezierCurve::new(vec![0.0, 3.0, 6.0 + 3.0]).unwrap();
    // Seed 001 eq. 1.22: p̄ = (p0, p0/3 + 2p1/3, 2p1/3 + p2/3, p2).
    assert_near!(q.elevate().points().to_vec(), vec![0.0, 2.0, 5.0, 9.0]);
    assert_near!(
        q.elevate_by(2).points().to_vec(),
        q.elevate().elevate().points().to_vec()
    );
    let (l, r) = cubic().subdivide(0.5);
    assert_near!(
        l.points().to_vec(),
        vec![v(0.0, 0.0), v(0.5, 1.0), v(1.25, 1.75), v(2.0, 15.0 / 8.0)]
    );
    assert_near!(
        r.points().to_vec(),
        vec![v(2.0, 15.0 / 8.0), v(2.75, 2.0), v(3.5, 1.5), v(4.0, 0.0)]
    );
    assert_near!(cubic().reversed().eval(0.3), cubic().eval(0.7));
}

#[test]
fn power_basis() {
    // B(t) = 1 − 2t + 3t² + 4t³ in power form.
    let a = vec![1.0, -2.0, 3.0, 4.0];
    let c = BezierCurve::from_power_basis(a.clone()).unwrap();
    for &t in &[-0.5f64, 0.0, 0.3, 1.0, 1.7] {
        assert_near!(
            c.eval(t),
            1.0 - 2.0 * t + 3.0 * t * t + 4.0 * t.powi(3),
            1e-12
        );
    }
    assert_near!(c.to_power_basis(), a);
    assert_near!(
        cubic().to_power_basis(),
        vec![v(0.0, 0.0), v(3.0, 6.0), v(3.0, -3.0), v(-2.0, -3.0)]
    );
}

#[test]
fn arc_length_and_quadrature() {
    let line = BezierCurve::new(vec![v(0.0, 0.0), v(0.1, 0.0), v(2.5, 0.0), v(3.0, 0.0)]).unwrap();
    assert_near!(line.arc_length(), 3.0);
    // x = t, y = t²: length of y = x² on [0, 1] is (2√5 + asinh 2)/4.
    let parabola = BezierCurve::new(vec![
        DVec2::new(0.0, 0.0),
        DVec2::new(0.5, 0.0),
        DVec2::new(1.0, 1.0),
    ])
    .unwrap();
    assert_near!(
        parabola.arc_length(),
        (2.0 * 5f64.sqrt() + 2f64.asinh()) / 4.0
    );
    assert!(parabola.arc_length() <= parabola.control_polygon_length());
    let (x, w) = gauss_legendre(5);
    assert_near!(w.iter().sum::<f64>(), 2.0);
    // ∫_{−1}^{1} x^8 dx = 2/9, exact for 5 nodes (degree ≤ 9).
    assert_near!(
        x.iter().zip(&w).map(|(x, w)| w * x.powi(8)).sum::<f64>(),
        2.0 / 9.0
    );
}

#[test]
fn bad_input_is_an_error() {
    assert_eq!(BezierCurve::<DVec3>::new(vec![]), Err(BezierError::Empty));
    assert_eq!(
        BezierCurve::new(vec![v(0.0, 0.0), v(f64::NAN, 1.0)]),
        Err(BezierError::NonFinitePoint { index: 1 })
    );
    let c = cubic();
    assert_eq!(
        CompositeCurve::new(vec![c.clone(), c.clone()], vec![0.0, 1.0]),
        Err(BezierError::BreakCount {
            breaks: 2,
            segments: 2
        })
    );
    assert_eq!(
        CompositeCurve::new(vec![c.clone(), c.clone()], vec![0.0, 1.0, 1.0]),
        Err(BezierError::BadBreak { index: 2 })
    );
    let s = CompositeCurve::uniform(vec![c.clone(), c.clone()]).unwrap();
    assert_eq!(
        s.g1_angle(1),
        Err(BezierError::NoSuchJoint {
            joint: 1,
            joints: 1
        })
    );
    let dot = BezierCurve::new(vec![v(4.0, 0.0); 3]).unwrap();
    let s = CompositeCurve::uniform(vec![c, dot]).unwrap();
    assert_eq!(
        s.g1_angle(0),
        Err(BezierError::DegenerateTangent { segment: 1 })
    );
}

/// Two cubics over [a, b] and [b, c] with p4 from the collinearity rule of seed 001 eq. 1.18:
/// p4 = p3 + (c − b)/(b − a) (p3 − p2).
fn c1_pair(perturb: DVec3) -> CompositeCurve<DVec3> {
    let (a, b, c) = (0.0, 2.0, 2.5);
    let left = cubic();
    let p = left.points();
    let p4 = p[3] + (p[3] - p[2]) * ((c - b) / (b - a)) + perturb;
    let right = BezierCurve::new(vec![p[3], p4, v(5.0, -1.0), v(6.0, 1.0)]).unwrap();
    CompositeCurve::new(vec![left, right], vec![a, b, c]).unwrap()
}

#[test]
fn c1_join_by_collinearity_rule() {
    let s = c1_pair(DVec3::ZERO);
    assert_eq!(s.continuity_order(0, 3, 1e-12).unwrap(), Some(1));
    assert!(s.joint_gaps(0, 1).unwrap()[1] <= 1e-12);
    assert_near!(s.g1_angle(0).unwrap(), 0.0);
    assert_near!(
        s.derivative(2.0 - 1e-9, 1),
        s.derivative(2.0 + 1e-9, 1),
        1e-6
    );
    // Perturbed along the tangent: still G1, no longer C1.
    let g1 = c1_pair(v(0.5, -1.5) * 0.1);
    assert_eq!(g1.continuity_order(0, 3, 1e-12).unwrap(), Some(0));
    assert_near!(g1.g1_angle(0).unwrap(), 0.0);
    // Perturbed off the tangent: neither C1 nor G1.
    let bent = c1_pair(v(0.0, 0.01));
    assert_eq!(bent.continuity_order(0, 3, 1e-12).unwrap(), Some(0));
    assert!(bent.g1_angle(0).unwrap() > 1e-3);
    // Cusp: tangent reversed.
    let p = cubic().points().to_vec();
    let back = BezierCurve::new(vec![p[3], p[2], v(0.0, 5.0)]).unwrap();
    let cusp = CompositeCurve::uniform(vec![cubic(), back]).unwrap();
    assert_near!(cusp.g1_angle(0).unwrap(), std::f64::consts::PI);
    // Not even C0.
    let gap = CompositeCurve::uniform(vec![
        cubic(),
        BezierCurve::new(vec![v(9.0, 9.0), v(10.0, 9.0)]).unwrap(),
    ])
    .unwrap();
    assert_eq!(gap.continuity_order(0, 2, 1e-12).unwrap(), None);
}

#[test]
fn subdivided_curve_is_c_infinity() {
    let (l, r) = cubic().subdivide(0.3);
    let s = CompositeCurve::new(vec![l, r], vec![0.0, 0.3, 1.0]).unwrap();
    assert_eq!(s.continuity_order(0, 6, 1e-12).unwrap(), Some(6));
    for &u in &[0.0, 0.1, 0.3, 0.55, 1.0] {
        assert_near!(s.eval(u), cubic().eval(u));
        assert_near!(s.derivative(u, 2), cubic().derivative(u, 2), 1e-11);
    }
    assert_eq!(s.segment_index(0.3), 0);
    assert_eq!(s.segment_index(0.31), 1);
}

fn points3(max_deg: usize) -> impl Strategy<Value = Vec<DVec3>> {
    prop::collection::vec(
        (-10.0..10.0f64, -10.0..10.0f64, -10.0..10.0f64),
        1..=max_deg + 1,
    )
    .prop_map(|v| v.into_iter().map(|(x, y, z)| DVec3::new(x, y, z)).collect())
}

fn scale(c: &BezierCurve<DVec3>) -> f64 {
    c.points().iter().map(|p| p.norm()).fold(1.0, f64::max)
}

proptest! {
    #[test]
    fn elevation_keeps_the_curve(p in points3(9), k in 1usize..5, t in 0.0..=1.0f64) {
        let c = BezierCurve::new(p).unwrap();
        let tol = 1e-12 * scale(&c);
        assert_near!(c.elevate().eval(t), c.eval(t), tol);
        assert_near!(c.elevate_by(k).eval(t), c.eval(t), tol);
        prop_assert_eq!(c.elevate_by(k).degree(), c.degree() + k);
    }

    #[test]
    fn subdivision_keeps_the_curve(p in points3(9), t in 0.01..0.99f64, s in 0.0..=1.0f64) {
        let c = BezierCurve::new(p).unwrap();
        let tol = 1e-12 * scale(&c);
        let (l, r) = c.subdivide(t);
        assert_near!(l.eval(s), c.eval(s * t), tol);
        assert_near!(r.eval(s), c.eval(t + s * (1.0 - t)), tol);
        let seg = c.segment(0.2, 0.9);
        assert_near!(seg.eval(s), c.eval(0.2 + 0.7 * s), tol);
        assert_near!(c.reversed().eval(s), c.eval(1.0 - s), tol);
    }

    #[test]
    fn de_casteljau_bernstein_and_power_forms_agree(p in points3(12), t in 0.0..=1.0f64) {
        let c = BezierCurve::new(p).unwrap();
        let tol = 1e-12 * scale(&c) * (1u64 << c.degree().min(12)) as f64;
        assert_near!(c.eval_bernstein(t), c.eval(t), 1e-12 * scale(&c));
        let a = c.to_power_basis();
        let horner = a.iter().rev().fold(DVec3::ZERO, |acc, &ak| acc * t + ak);
        assert_near!(horner, c.eval(t), tol);
    }

    #[test]
    fn derivatives_match_finite_differences(p in points3(8), t in 0.05..0.95f64) {
        let c = BezierCurve::new(p).unwrap();
        let h = 1e-5;
        let n = c.degree() as f64;
        let d1 = (c.eval(t + h) - c.eval(t - h)) / (2.0 * h);
        assert_near!(c.derivative(t, 1), d1, 1e-7 * scale(&c) * n * n);
        let d2 = (c.derivative(t + h, 1) - c.derivative(t - h, 1)) / (2.0 * h);
        assert_near!(c.derivative(t, 2), d2, 1e-6 * scale(&c) * n.powi(4));
    }

    #[test]
    fn affine_invariance(p in points3(8), t in 0.0..=1.0f64,
                         m in prop::array::uniform9(-2.0..2.0f64), off in prop::array::uniform3(-5.0..5.0f64)) {
        let a = glam::DMat3::from_cols_array(&m);
        let o = DVec3::from_array(off);
        let f = |q: DVec3| a * q + o;
        let c = BezierCurve::new(p).unwrap();
        let image = c.map(f);
        assert_near!(image.eval(t), f(c.eval(t)), 1e-11 * scale(&c) * 10.0);
    }
}

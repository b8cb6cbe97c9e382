//! Rational Bézier curves and the exact circle (seed 001 §2.4, §3).

use gbsurf::assert_near;
use gbsurf::bezier::{BezierCurve, BezierError, RationalCurve};
use gbsurf::DVec3;
use proptest::prelude::*;
use std::f64::consts::{FRAC_1_SQRT_2, FRAC_PI_2, PI};

fn curvature(d: &[DVec3]) -> f64 {
    d[1].cross(d[2]).length() / d[1].length().powi(3)
}

#[test]
fn full_circle_is_exact() {
    let arcs = RationalCurve::full_circle(DVec3::ZERO, 1.0).unwrap();
    // Control polygon = circumscribed square, weights 1, √2/2, 1 (seed 001 fig. 3.3).
    assert_near!(
        arcs[0].points().to_vec(),
        vec![DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y]
    );
    assert_near!(arcs[0].weights().to_vec(), vec![1.0, FRAC_1_SQRT_2, 1.0]);
    let mut worst: f64 = 0.0;
    for (k, arc) in arcs.iter().enumerate() {
        assert_near!(
            arc.eval(0.0),
            DVec3::new(
                (k as f64 * FRAC_PI_2).cos(),
                (k as f64 * FRAC_PI_2).sin(),
                0.0
            ),
            1e-15
        );
        for s in 0..=1000 {
            let t = s as f64 / 1000.0;
            let d = arc.derivatives(t, 2);
            worst = worst.max((d[0].length() - 1.0).abs());
            assert!(
                d[0].dot(d[1]).abs() <= 1e-14 * d[1].length(),
                "tangent not ⟂ radius at t = {t}"
            );
            assert_near!(curvature(&d), 1.0, 1e-13);
            // Counter-clockwise orientation.
            assert!(d[0].cross(d[1]).z > 0.0);
        }
    }
    assert!(worst <= 1e-14, "max ||p| − 1| = {worst:e}");
    // Consecutive arcs meet with the same tangent direction.
    for k in 0..4 {
        let (a, b) = (&arcs[k], &arcs[(k + 1) % 4]);
        assert_near!(a.eval(1.0), b.eval(0.0), 1e-15);
        assert_near!(
            a.derivative(1.0, 1).normalize(),
            b.derivative(0.0, 1).normalize(),
            1e-15
        );
    }
}

#[test]
fn seed_weights_quarter_and_sqrt2_over_2_do_not_give_a_circle() {
    // Seed 001 §3 prints the alternating weights 0.25 and √2/2: not a circle (see rational.rs).
    let pts = vec![DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
    let seed = RationalCurve::new(pts.clone(), vec![0.25, FRAC_1_SQRT_2, 0.25]).unwrap();
    assert!((seed.eval(0.5).length() - 1.0).abs() > 0.1);
    let fixed = RationalCurve::new(pts, vec![0.25, 0.25 * FRAC_1_SQRT_2, 0.25]).unwrap();
    assert_near!(fixed.eval(0.5).length(), 1.0, 1e-15);
}

#[test]
fn derivatives_by_quotient_rule_by_hand() {
    // Quadratic with weights (1, 2, 1) in 1D: R = (2·2t(1−t)·p1 + t²p2)/(1 + 2t(1−t)) with p0 = 0.
    let c = RationalCurve::new(vec![0.0, 1.0, 3.0], vec![1.0, 2.0, 1.0]).unwrap();
    let t = 0.25;
    let n = |t: f64| 4.0 * t * (1.0 - t) + 3.0 * t * t;
    let w = |t: f64| 1.0 + 2.0 * t * (1.0 - t);
    let (n1, w1) = (4.0 - 2.0 * t, 2.0 - 4.0 * t);
    let (n2, w2) = (-2.0, -4.0);
    let r = n(t) / w(t);
    let r1 = (n1 - w1 * r) / w(t);
    let r2 = (n2 - 2.0 * w1 * r1 - w2 * r) / w(t);
    assert_near!(c.derivatives(t, 2), vec![r, r1, r2]);
    // At the ends: R′(0) = n w1/w0 (p1 − p0).
    assert_near!(c.derivative(0.0, 1), 2.0 * 2.0 * 1.0);
}

#[test]
fn unit_weights_and_common_factors() {
    let p = BezierCurve::new(vec![
        DVec3::ZERO,
        DVec3::new(1.0, 2.0, 3.0),
        DVec3::new(4.0, 0.0, -1.0),
    ])
    .unwrap();
    let r = RationalCurve::from_polynomial(&p);
    let scaled = RationalCurve::new(p.points().to_vec(), vec![3.0; 3]).unwrap();
    for &t in &[0.0, 0.3, 0.8, 1.0] {
        assert_near!(r.eval(t), p.eval(t));
        assert_near!(scaled.eval(t), p.eval(t));
        assert_near!(r.derivatives(t, 2), p.derivatives(t, 2), 1e-12);
    }
}

#[test]
fn bad_input_is_an_error() {
    let p = vec![DVec3::X, DVec3::Y];
    assert_eq!(
        RationalCurve::new(p.clone(), vec![1.0]),
        Err(BezierError::WeightCount {
            got: 1,
            expected: 2
        })
    );
    assert_eq!(
        RationalCurve::new(p.clone(), vec![1.0, 0.0]),
        Err(BezierError::BadWeight {
            index: 1,
            value: 0.0
        })
    );
    assert!(matches!(
        RationalCurve::new(p, vec![f64::NAN, 1.0]),
        Err(BezierError::BadWeight { index: 0, .. })
    ));
    assert_eq!(
        RationalCurve::circular_arc(DVec3::ZERO, 1.0, 0.0, PI),
        Err(BezierError::BadSweep { sweep: PI })
    );
    assert_eq!(
        RationalCurve::circular_arc(DVec3::ZERO, -1.0, 0.0, 1.0),
        Err(BezierError::BadRadius { radius: -1.0 })
    );
}

fn rational3(max_deg: usize) -> impl Strategy<Value = (Vec<DVec3>, Vec<f64>)> {
    (1..=max_deg).prop_flat_map(|n| {
        (
            prop::collection::vec(prop::array::uniform3(-10.0..10.0f64), n + 1),
            prop::collection::vec(0.2..5.0f64, n + 1),
        )
            .prop_map(|(p, w)| (p.into_iter().map(DVec3::from_array).collect(), w))
    })
}

proptest! {
    #[test]
    fn arcs_lie_on_their_circle(c in prop::array::uniform3(-5.0..5.0f64), r in 0.1..10.0f64,
                                theta0 in -PI..PI, sweep in 0.05..2.5f64, t in 0.0..=1.0f64, k in 0usize..4) {
        let c = DVec3::from_array(c);
        let arc = RationalCurve::circular_arc(c, r, theta0, sweep).unwrap();
        let tol = 1e-14 * (1.0 + c.length() / r);
        prop_assert!(((arc.eval(t) - c).length() / r - 1.0).abs() <= tol);
        prop_assert!(((arc.elevate_by(k).eval(t) - c).length() / r - 1.0).abs() <= 4.0 * tol);
        assert_near!(curvature(&arc.derivatives(t, 2)), 1.0 / r, 1e-11 / r);
        assert_near!(arc.eval(1.0) - c, DVec3::new((theta0 + sweep).cos(), (theta0 + sweep).sin(), 0.0) * r, 1e-13 * r);
    }

    #[test]
    fn elevation_and_subdivision_keep_the_curve((p, w) in rational3(7), k in 1usize..4, t in 0.01..0.99f64, s in 0.0..=1.0f64) {
        let c = RationalCurve::new(p, w).unwrap();
        let scale = c.points().iter().map(|p| p.length()).fold(1.0, f64::max);
        let tol = 1e-12 * scale;
        assert_near!(c.elevate().eval(s), c.eval(s), tol);
        assert_near!(c.elevate_by(k).eval(s), c.eval(s), tol);
        let (l, r) = c.subdivide(t);
        assert_near!(l.eval(s), c.eval(s * t), tol);
        assert_near!(r.eval(s), c.eval(t + s * (1.0 - t)), tol);
        assert_near!(c.reversed().eval(s), c.eval(1.0 - s), tol);
    }

    #[test]
    fn derivatives_match_finite_differences((p, w) in rational3(6), t in 0.05..0.95f64) {
        let c = RationalCurve::new(p, w).unwrap();
        let scale = c.points().iter().map(|p| p.length()).fold(1.0, f64::max);
        let h = 1e-5;
        let d = c.derivatives(t, 3);
        let fd1 = (c.eval(t + h) - c.eval(t - h)) / (2.0 * h);
        let fd2 = (c.derivative(t + h, 1) - c.derivative(t - h, 1)) / (2.0 * h);
        let fd3 = (c.derivative(t + h, 2) - c.derivative(t - h, 2)) / (2.0 * h);
        // Weight ratios up to 25 make derivatives large; compare relative to their size.
        let rel = |a: DVec3, b: DVec3| (a - b).length() / (1.0 + a.length().max(b.length()));
        prop_assert!(rel(d[1], fd1) <= 1e-6 * scale, "R' {:?} vs {:?}", d[1], fd1);
        prop_assert!(rel(d[2], fd2) <= 1e-5 * scale, "R'' {:?} vs {:?}", d[2], fd2);
        prop_assert!(rel(d[3], fd3) <= 1e-4 * scale, "R''' {:?} vs {:?}", d[3], fd3);
    }

    #[test]
    fn affine_invariance((p, w) in rational3(6), t in 0.0..=1.0f64,
                         m in prop::array::uniform9(-2.0..2.0f64), off in prop::array::uniform3(-5.0..5.0f64)) {
        let a = glam::DMat3::from_cols_array(&m);
        let o = DVec3::from_array(off);
        let f = |q: DVec3| a * q + o;
        let c = RationalCurve::new(p, w).unwrap();
        let scale = c.points().iter().map(|p| p.length()).fold(1.0, f64::max);
        assert_near!(c.map(f).eval(t), f(c.eval(t)), 1e-11 * scale * 10.0);
    }
}

//! Degree reduction of Bézier curves and the base + displacement form (seed 002 "Fokszám emelés
//! és csökkentés", "alap + eltolás"; formulas in docs/math/editing.md).

use gbsurf::assert_near;
use gbsurf::bezier::curve::gauss_legendre;
use gbsurf::bezier::reduce::{
    error_bound, hermite_cubic, reduce_degree, BaseDisplacement, ReduceError,
};
use gbsurf::bezier::{bernstein::bernstein, BezierCurve};
use gbsurf::DVec3;
use proptest::prelude::*;

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// Seed 002's quartic example with concrete points.
fn quartic() -> BezierCurve<DVec3> {
    BezierCurve::new(vec![
        v(0.0, 0.0, 0.0),
        v(1.0, 2.0, 0.0),
        v(2.0, 3.0, 1.0),
        v(4.0, 2.0, 0.0),
        v(5.0, 0.0, 0.0),
    ])
    .unwrap()
}

/// max over 201 samples of |a(t) − b(t)|.
fn sampled_distance(a: &BezierCurve<DVec3>, b: &BezierCurve<DVec3>) -> f64 {
    (0..=200)
        .map(|k| {
            let t = k as f64 / 200.0;
            (a.eval(t) - b.eval(t)).length()
        })
        .fold(0.0, f64::max)
}

#[test]
fn seed002_quartic_example() {
    let c = quartic();
    let q = c.points();
    let h = hermite_cubic(&c);
    // C0 = Q0, C1 = Q0 + 4/3 (Q1 − Q0), C2 = Q4 + 4/3 (Q3 − Q4), C3 = Q4
    assert_near!(h.points()[0], q[0]);
    assert_near!(h.points()[1], q[0] + (q[1] - q[0]) * (4.0 / 3.0));
    assert_near!(h.points()[2], q[4] + (q[3] - q[4]) * (4.0 / 3.0));
    assert_near!(h.points()[3], q[4]);
    assert_near!(h.points()[1], v(4.0 / 3.0, 8.0 / 3.0, 0.0));
    assert_near!(h.points()[2], v(11.0 / 3.0, 8.0 / 3.0, 0.0));

    // elevated back to degree 4: C*_i = Q_i for i = 0, 1, 3, 4 and C*_2 = (C1 + C2)/2
    let bd = BaseDisplacement::new(&c).unwrap();
    let e = bd.base_elevated();
    for i in [0, 1, 3, 4] {
        assert_near!(e.points()[i], q[i]);
    }
    let c2 = (h.points()[1] + h.points()[2]) * 0.5;
    assert_near!(e.points()[2], c2);
    assert_near!(e.points()[2], v(2.5, 8.0 / 3.0, 0.0));
    // displacement vectors: only D2 = Q2 − C*_2 is non-zero
    let dvec = bd.displacement();
    assert_eq!(dvec.len(), 5);
    for i in [0, 1, 3, 4] {
        assert_eq!(dvec[i], DVec3::ZERO);
    }
    assert_near!(dvec[2], v(-0.5, 1.0 / 3.0, 1.0));
    // r_D(u) = D2 · B^4_2(u)
    for &u in &[0.0, 0.2, 0.5, 0.9, 1.0] {
        assert_near!(
            bd.displacement_curve().eval(u),
            dvec[2] * bernstein(4, 2, u)
        );
        assert_near!(bd.eval(u), c.eval(u));
    }
}

#[test]
fn t4_hermite_error_is_t2_1mt_2_and_bound_is_one_sixth() {
    // f(t) = t^4: Bézier coefficients 0,0,0,0,1. Its cubic Hermite interpolant H differs by the
    // quartic with double roots at 0 and 1 and leading coefficient 1: t²(1−t)², max 1/16 at ½.
    let f = BezierCurve::new(vec![0.0, 0.0, 0.0, 0.0, 1.0]).unwrap();
    let h = hermite_cubic(&f);
    assert_near!(h.points().to_vec(), vec![0.0, 0.0, -1.0 / 3.0, 1.0]);
    for k in 0..=20 {
        let t = k as f64 / 20.0;
        assert_near!(f.eval(t) - h.eval(t), t * t * (1.0 - t) * (1.0 - t));
    }
    // elevated H = 0, 0, −1/6, 0, 1, so the control-point bound is 1/6 (≥ 1/16)
    assert_near!(error_bound(&f, &h), 1.0 / 6.0);
    let r = reduce_degree(&f, 3, 1).unwrap();
    assert_near!(r.curve.points().to_vec(), h.points().to_vec());
    assert_near!(r.error_bound, 1.0 / 6.0);
    // displacement: D2 = 1/6, r_D = (1/6)·6t²(1−t)²
    let bd = BaseDisplacement::new(&f).unwrap();
    assert_near!(
        bd.displacement().to_vec(),
        vec![0.0, 0.0, 1.0 / 6.0, 0.0, 0.0]
    );
}

#[test]
fn end_point_only_reduction_to_a_line_is_the_chord() {
    let c = quartic();
    let r = reduce_degree(&c, 1, 0).unwrap();
    assert_near!(
        r.curve.points().to_vec(),
        vec![c.points()[0], c.points()[4]]
    );
    assert!(r.error_bound >= sampled_distance(&c, &r.curve));
}

#[test]
fn errors_name_the_argument() {
    let c = quartic();
    assert_eq!(
        reduce_degree(&c, 4, 1),
        Err(ReduceError::TargetNotLower {
            target: 4,
            degree: 4
        })
    );
    assert_eq!(
        reduce_degree(&c, 7, 0),
        Err(ReduceError::TargetNotLower {
            target: 7,
            degree: 4
        })
    );
    assert_eq!(
        reduce_degree(&c, 2, 1),
        Err(ReduceError::TargetTooLow {
            target: 2,
            order: 1,
            min: 3
        })
    );
    assert_eq!(
        reduce_degree(&c.elevate_by(4), 4, 2),
        Err(ReduceError::TargetTooLow {
            target: 4,
            order: 2,
            min: 5
        })
    );
    let quad =
        BezierCurve::new(vec![v(0.0, 0.0, 0.0), v(1.0, 1.0, 0.0), v(2.0, 0.0, 0.0)]).unwrap();
    assert_eq!(
        BaseDisplacement::new(&quad),
        Err(ReduceError::BelowCubic { degree: 2 })
    );

    let mut bd = BaseDisplacement::new(&c.elevate_by(2)).unwrap(); // degree 6: editable 2..=4
    for index in [0, 1, 5, 6, 7, usize::MAX] {
        assert_eq!(
            bd.set_displacement(index, DVec3::X),
            Err(ReduceError::FixedDisplacement { index, degree: 6 })
        );
    }
    assert_eq!(
        bd.set_displacement(3, v(f64::NAN, 0.0, 0.0)),
        Err(ReduceError::NonFiniteDisplacement { index: 3 })
    );
    assert!(bd.set_displacement(4, DVec3::X).is_ok());
    assert_eq!(
        bd.set_base(quad),
        Err(ReduceError::BaseNotCubic { degree: 2 })
    );
    let msg = ReduceError::FixedDisplacement {
        index: 1,
        degree: 6,
    }
    .to_string();
    assert!(msg.contains("2..=4"), "{msg}");
}

#[test]
fn hermite_cubic_of_low_degree_curves_is_their_elevation() {
    for d in 0..=3usize {
        let c = BezierCurve::new(
            (0..=d)
                .map(|i| v(i as f64, (i * i) as f64, 1.0 - i as f64))
                .collect(),
        )
        .unwrap();
        let h = hermite_cubic(&c);
        assert_near!(h.points().to_vec(), c.elevate_by(3 - d).points().to_vec());
    }
}

#[test]
fn set_base_moves_only_the_end_constraints() {
    let c = quartic().elevate_by(3); // degree 7
    let mut bd = BaseDisplacement::new(&c).unwrap();
    let d0 = bd.displacement().to_vec();
    let new_base = BezierCurve::new(vec![
        v(0.0, 0.0, 1.0),
        v(1.0, 0.0, 1.0),
        v(2.0, 1.0, 1.0),
        v(3.0, 0.0, 1.0),
    ])
    .unwrap();
    bd.set_base(new_base.clone()).unwrap();
    let r = bd.curve();
    assert_near!(r.eval(0.0), new_base.eval(0.0));
    assert_near!(r.eval(1.0), new_base.eval(1.0));
    assert_near!(r.derivative(0.0, 1), new_base.derivative(0.0, 1), 1e-12);
    assert_near!(r.derivative(1.0, 1), new_base.derivative(1.0, 1), 1e-12);
    // and splitting the new curve gives back the same displacement
    let again = BaseDisplacement::new(&r).unwrap();
    assert_near!(again.displacement().to_vec(), d0, 1e-12);
    assert_near!(
        again.base().points().to_vec(),
        new_base.points().to_vec(),
        1e-12
    );
}

/// ∫_0^1 (r − q)(t) · B^m_i(t) dt by 16-point Gauss–Legendre (exact for these degrees ≤ 31).
fn residual_moment(r: &BezierCurve<DVec3>, q: &BezierCurve<DVec3>, i: usize) -> DVec3 {
    let (x, w) = gauss_legendre(16);
    let m = q.degree();
    x.iter()
        .zip(&w)
        .map(|(&xi, &wi)| {
            let t = 0.5 * (xi + 1.0);
            (r.eval(t) - q.eval(t)) * (0.5 * wi * bernstein(m, i, t))
        })
        .sum()
}

fn l2_error(r: &BezierCurve<DVec3>, q: &BezierCurve<DVec3>) -> f64 {
    let (x, w) = gauss_legendre(16);
    x.iter()
        .zip(&w)
        .map(|(&xi, &wi)| {
            0.5 * wi * (r.eval(0.5 * (xi + 1.0)) - q.eval(0.5 * (xi + 1.0))).length_squared()
        })
        .sum::<f64>()
}

fn points3(max_degree: usize) -> impl Strategy<Value = Vec<DVec3>> {
    prop::collection::vec(
        (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64),
        5..=max_degree + 1,
    )
    .prop_map(|v| v.into_iter().map(|(x, y, z)| DVec3::new(x, y, z)).collect())
}

proptest! {
    #[test]
    fn reduction_keeps_end_derivatives(p in points3(11), m_off in 0usize..8, order in 0usize..3) {
        let c = BezierCurve::new(p).unwrap();
        let d = c.degree();
        let min = 2 * order + 1;
        prop_assume!(min < d);
        let m = min + m_off % (d - min);
        let r = reduce_degree(&c, m, order).unwrap();
        prop_assert_eq!(r.curve.degree(), m);
        for k in 0..=order {
            assert_near!(r.curve.derivative(0.0, k), c.derivative(0.0, k), 1e-10);
            assert_near!(r.curve.derivative(1.0, k), c.derivative(1.0, k), 1e-10);
        }
        // the bound is an upper bound of the sampled error
        prop_assert!(sampled_distance(&c, &r.curve) <= r.error_bound + 1e-12);
    }

    #[test]
    fn reduction_is_the_constrained_l2_optimum(p in points3(10), m_off in 0usize..8, order in 0usize..3) {
        let c = BezierCurve::new(p).unwrap();
        let d = c.degree();
        let min = 2 * order + 1;
        prop_assume!(min + 1 < d);
        let m = min + 1 + m_off % (d - min - 1); // at least one free control point
        let r = reduce_degree(&c, m, order).unwrap();
        // normal equations: the residual is L2-orthogonal to every free basis function
        for i in order + 1..m - order {
            assert_near!(residual_moment(&c, &r.curve, i), DVec3::ZERO, 1e-10, "m={} i={}", m, i);
        }
        // and moving a free point makes the L2 error larger
        let e0 = l2_error(&c, &r.curve);
        let mut q = r.curve.points().to_vec();
        q[order + 1] += DVec3::new(1e-3, -2e-3, 1e-3);
        prop_assert!(l2_error(&c, &BezierCurve::new(q).unwrap()) > e0);
    }

    #[test]
    fn reduction_recovers_an_elevated_curve(p in points3(8), k in 1usize..4, order in 0usize..3) {
        let q = BezierCurve::new(p).unwrap();
        prop_assume!(q.degree() > 2 * order);
        let c = q.elevate_by(k);
        let r = reduce_degree(&c, q.degree(), order).unwrap();
        assert_near!(r.curve.points().to_vec(), q.points().to_vec(), 1e-9);
        prop_assert!(r.error_bound <= 1e-9);
    }

    #[test]
    fn hermite_cubic_is_the_order_one_reduction(p in points3(11)) {
        let c = BezierCurve::new(p).unwrap();
        prop_assume!(c.degree() > 3);
        let h = hermite_cubic(&c);
        let r = reduce_degree(&c, 3, 1).unwrap();
        assert_near!(r.curve.points().to_vec(), h.points().to_vec(), 1e-12);
        for t in [0.0, 1.0] {
            assert_near!(h.eval(t), c.eval(t), 1e-14);
            assert_near!(h.derivative(t, 1), c.derivative(t, 1), 1e-12);
        }
    }

    #[test]
    fn base_plus_displacement_round_trip(p in points3(12)) {
        let c = BezierCurve::new(p).unwrap();
        let bd = BaseDisplacement::new(&c).unwrap();
        prop_assert_eq!(bd.degree(), c.degree());
        prop_assert_eq!(bd.base().degree(), 3);
        assert_near!(bd.curve().points().to_vec(), c.points().to_vec(), 1e-14);
        let d = bd.degree();
        for i in [0, 1, d - 1, d] {
            prop_assert_eq!(bd.displacement()[i], DVec3::ZERO);
        }
        for k in 0..=10 {
            let t = k as f64 / 10.0;
            assert_near!(bd.eval(t), c.eval(t), 1e-14);
        }
    }

    #[test]
    fn editing_the_displacement_keeps_end_positions_and_tangents(
        p in points3(12),
        edits in prop::collection::vec((0usize..100, -2.0..2.0f64, -2.0..2.0f64, -2.0..2.0f64), 1..6),
    ) {
        let c = BezierCurve::new(p).unwrap();
        let d = c.degree();
        let mut bd = BaseDisplacement::new(&c).unwrap();
        let mut moved = false;
        for (i, x, y, z) in edits {
            let index = 2 + i % (d - 3); // 2..=d−2
            let e = DVec3::new(x, y, z);
            bd.set_displacement(index, bd.displacement()[index] + e).unwrap();
            moved |= e.length() > 1e-3;
        }
        let r = bd.curve();
        for t in [0.0, 1.0] {
            assert_near!(r.eval(t), c.eval(t), 1e-14);
            assert_near!(r.derivative(t, 1), c.derivative(t, 1), 1e-12);
            assert_near!(bd.eval(t), c.eval(t), 1e-14);
        }
        // the edit does change the inside of the curve (so the test can fail)
        if moved {
            prop_assert!(sampled_distance(&r, &c) > 1e-6);
        }
    }
}

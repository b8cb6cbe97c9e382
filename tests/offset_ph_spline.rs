//! PH quintic splines: segment-wise Hermite (planar, spatial) and C² planar splines, open and
//! closed, on the sample data of ACM TOMS Algorithm 952 and on random point sets.

use gbsurf::assert_near;
use gbsurf::bezier::curve::gauss_legendre;
use gbsurf::offset::ph::{OpenEnds, PhError, PlanarPhSpline, SpatialPhSpline};
use gbsurf::{DVec2, DVec3};
use proptest::prelude::*;

fn pts(v: &[(f64, f64)]) -> Vec<DVec2> {
    v.iter().map(|&(x, y)| DVec2::new(x, y)).collect()
}

/// Algorithm 952's open sample (7 points).
fn open_952() -> Vec<DVec2> {
    pts(&[
        (-2.1, 1.8),
        (-3.1, 0.0),
        (-0.3, -0.8),
        (0.7, 2.2),
        (3.4, 0.5),
        (1.1, -0.6),
        (2.3, -2.4),
    ])
}

/// Algorithm 952's closed sample (the repeated first point dropped: 9 distinct points).
fn closed_952() -> Vec<DVec2> {
    pts(&[
        (-4.1, -0.8),
        (-1.5, -1.5),
        (-0.6, -3.6),
        (1.2, -1.5),
        (4.1, 0.4),
        (1.2, 3.3),
        (0.9, 0.4),
        (-1.4, -0.2),
        (-2.3, 1.7),
    ])
}

/// Interpolation, C² at every joint (relative 1e-10), and per-segment arc length equal to
/// quadrature of that segment's own hodograph.
fn check_spline(s: &PlanarPhSpline, points: &[DVec2]) {
    let n = s.segments.len();
    let size = points
        .iter()
        .map(|p| p.abs().max_element())
        .fold(1.0, f64::max);
    for (i, seg) in s.segments.iter().enumerate() {
        assert_near!(seg.eval(0.0), points[i], 1e-12 * size);
        assert_near!(
            seg.end_point(),
            points[(i + 1) % points.len()],
            1e-10 * size
        );
    }
    let joints = if s.closed { n } else { n - 1 };
    for i in 0..joints {
        let (a, b) = (s.segments[i].bezier(), s.segments[(i + 1) % n].bezier());
        for r in 0..=2 {
            let (x, y) = (a.derivative(1.0, r), b.derivative(0.0, r));
            let scale = x.length().max(y.length()).max(1.0);
            assert_near!(x, y, 1e-10 * scale, "joint {i}, derivative {r}");
        }
    }
    let (gx, gw) = gauss_legendre(24);
    for seg in &s.segments {
        let h = seg.bezier().hodograph();
        let l: f64 = (0..16)
            .map(|k| {
                let a = k as f64 / 16.0;
                gx.iter()
                    .zip(&gw)
                    .map(|(&x, &w)| w * h.eval(a + (x + 1.0) / 32.0).length())
                    .sum::<f64>()
                    / 32.0
            })
            .sum();
        assert_near!(seg.arc_length(), l, 1e-12 * l);
    }
}

#[test]
fn open_952_sample_is_c2() {
    let p = open_952();
    let s = PlanarPhSpline::c2_open(&p, OpenEnds::CubicEndSpans).unwrap();
    assert_eq!(s.segments.len(), 6);
    assert!(s.iterations <= 20, "{}", s.iterations);
    check_spline(&s, &p);
    // Cubic end spans: w is linear on the first and last segment (w0 − 2w1 + w2 = 0).
    for seg in [&s.segments[0], &s.segments[5]] {
        let [w0, w1, w2] = seg.w;
        assert_near!((w0 - w1 * 2.0 + w2).abs(), 0.0, 1e-12);
    }
}

#[test]
fn open_spline_with_end_derivatives() {
    let p = open_952();
    let (start, end) = (DVec2::new(-1.0, -4.0), DVec2::new(2.0, -3.0));
    let s = PlanarPhSpline::c2_open(&p, OpenEnds::Derivatives { start, end }).unwrap();
    check_spline(&s, &p);
    assert_near!(s.segments[0].derivative(0.0), start, 1e-12);
    assert_near!(s.segments[5].derivative(1.0), end, 1e-12);
    // Two points and end derivatives: the Hermite problem (one of its four solutions).
    let two = PlanarPhSpline::c2_open(&p[..2], OpenEnds::Derivatives { start, end }).unwrap();
    check_spline(&two, &p[..2]);
    assert_near!(two.segments[0].derivative(1.0), end, 1e-12);
}

#[test]
fn closed_952_sample_closes_and_is_c2() {
    let p = closed_952();
    let s = PlanarPhSpline::c2_closed(&p).unwrap();
    assert_eq!(s.segments.len(), 9);
    assert!(s.closed);
    check_spline(&s, &p);
    assert_near!(s.segments[8].end_point(), p[0], 1e-10);
}

#[test]
fn each_segment_uses_its_own_speed() {
    // The published code assigns σ_1 of every segment to segment 1. Here each segment's speed
    // polynomial must equal |w|² of its own preimage.
    let s = PlanarPhSpline::c2_open(&open_952(), OpenEnds::CubicEndSpans).unwrap();
    for seg in &s.segments {
        let sigma = seg.speed_coeffs();
        for k in 0..=10 {
            let t = k as f64 / 10.0;
            let b = gbsurf::bezier::bernstein::bernstein_all(4, t);
            let val: f64 = sigma.iter().zip(&b).map(|(a, b)| a * b).sum();
            assert_near!(val, seg.speed(t), 1e-12);
        }
    }
}

#[test]
fn hermite_splines_are_c1() {
    let p = open_952();
    let tangents: Vec<DVec2> = (0..p.len())
        .map(|i| {
            let (a, b) = (p[i.saturating_sub(1)], p[(i + 1).min(p.len() - 1)]);
            (b - a) * 0.5 * if i == 0 || i + 1 == p.len() { 2.0 } else { 1.0 }
        })
        .collect();
    let s = PlanarPhSpline::hermite(&p, &tangents).unwrap();
    for (i, seg) in s.segments.iter().enumerate() {
        assert_near!(seg.eval(0.0), p[i], 1e-13);
        assert_near!(seg.end_point(), p[i + 1], 1e-13);
        assert_near!(seg.derivative(0.0), tangents[i], 1e-13);
        assert_near!(seg.derivative(1.0), tangents[i + 1], 1e-13);
    }
    let p3: Vec<DVec3> = p
        .iter()
        .enumerate()
        .map(|(i, v)| v.extend(0.3 * i as f64))
        .collect();
    let t3: Vec<DVec3> = tangents.iter().map(|v| v.extend(0.3)).collect();
    for angles in [None, Some((0.2, -0.4))] {
        let s3 = SpatialPhSpline::hermite(&p3, &t3, angles).unwrap();
        for (i, seg) in s3.segments.iter().enumerate() {
            assert_near!(seg.eval(0.0), p3[i], 1e-13);
            assert_near!(seg.end_point(), p3[i + 1], 1e-12);
            assert_near!(seg.derivative(0.0), t3[i], 1e-12);
            assert_near!(seg.derivative(1.0), t3[i + 1], 1e-12);
        }
        assert_near!(s3.eval(6.0), p3[6], 1e-12);
    }
}

#[test]
fn bad_input_names_the_index() {
    let mut p = open_952();
    assert_eq!(
        PlanarPhSpline::c2_open(&p[..2], OpenEnds::CubicEndSpans),
        Err(PhError::TooFewPoints {
            arg: "points",
            got: 2,
            need: 3
        })
    );
    p[3] = p[2];
    assert_eq!(
        PlanarPhSpline::c2_open(&p, OpenEnds::CubicEndSpans),
        Err(PhError::CoincidentPoints {
            arg: "points",
            index: 2
        })
    );
    let mut q = closed_952();
    q.push(q[0]); // the first point repeated: last segment has zero length
    assert_eq!(
        PlanarPhSpline::c2_closed(&q),
        Err(PhError::CoincidentPoints {
            arg: "points",
            index: 9
        })
    );
    let mut r = open_952();
    r[4].y = f64::NAN;
    assert_eq!(
        PlanarPhSpline::c2_closed(&r),
        Err(PhError::NonFinite {
            arg: "points",
            index: Some(4)
        })
    );
    let t = vec![DVec2::X; 3];
    assert_eq!(
        PlanarPhSpline::hermite(&open_952(), &t),
        Err(PhError::LengthMismatch {
            arg: "tangents",
            got: 3,
            expected: 7
        })
    );
    let mut t = vec![DVec2::X; 7];
    t[5] = DVec2::ZERO;
    assert_eq!(
        PlanarPhSpline::hermite(&open_952(), &t),
        Err(PhError::ZeroDerivative {
            arg: "tangents",
            index: Some(5)
        })
    );
}

/// Random "reasonably even" point sets (the C² construction's domain, Algorithm 952): a walk
/// with steps of length 0.6..1.6 turning by at most ±80° per step.
fn walk(closed: bool) -> impl Strategy<Value = Vec<DVec2>> {
    (
        3usize..12,
        prop::collection::vec((0.6..1.6f64, -1.4..1.4f64), 12),
        0.0..6.3f64,
    )
        .prop_map(move |(n, steps, h0)| {
            if closed {
                // Points on a perturbed circle.
                (0..n + 1)
                    .map(|i| {
                        let a = i as f64 / (n + 1) as f64 * std::f64::consts::TAU + h0;
                        let r = 3.0 + 0.4 * steps[i].1;
                        DVec2::new(r * a.cos(), r * a.sin())
                    })
                    .collect()
            } else {
                let mut p = vec![DVec2::ZERO];
                let mut h = h0;
                for &(len, turn) in steps.iter().take(n) {
                    h += turn;
                    let last = *p.last().unwrap();
                    p.push(last + DVec2::new(h.cos(), h.sin()) * len);
                }
                p
            }
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn random_open_splines_are_c2(p in walk(false)) {
        let s = PlanarPhSpline::c2_open(&p, OpenEnds::CubicEndSpans).unwrap();
        check_spline(&s, &p);
    }

    #[test]
    fn random_closed_splines_close_and_are_c2(p in walk(true)) {
        let s = PlanarPhSpline::c2_closed(&p).unwrap();
        check_spline(&s, &p);
    }
}

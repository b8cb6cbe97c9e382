//! Planar PH quintics: Hermite interpolation (all four solutions), exact arc length and its
//! inverse, curvature, rotation index, bending energy, exact rational offsets and cusps.
//! Reference data: the sample input of ACM TOMS Algorithm 952 (PHquintic, Dong & Farouki), whose
//! published program prints no values we could compare against, so the checks are derived:
//! its selection rule and offset formula are transcribed independently below.

use gbsurf::assert_near;
use gbsurf::bezier::curve::gauss_legendre;
use gbsurf::offset::ph::{Complex, PhError, PlanarPhQuintic};
use gbsurf::DVec2;
use proptest::prelude::*;

fn c(re: f64, im: f64) -> Complex {
    Complex::new(re, im)
}

/// Algorithm 952's sample: control points p0, p1, p4, p5, so d0 = 5(p1 − p0), d1 = 5(p5 − p4).
fn sample_952() -> (DVec2, DVec2, DVec2, DVec2) {
    let p0 = DVec2::new(0.8, 1.4);
    let p1 = DVec2::new(2.4, 0.8);
    let p4 = DVec2::new(2.6, 4.2);
    let p5 = DVec2::new(4.2, 3.6);
    (p0, (p1 - p0) * 5.0, p5, (p5 - p4) * 5.0)
}

/// ∫_0^1 f by composite Gauss–Legendre on 256 pieces (independent of the library's routine).
fn quad(f: impl Fn(f64) -> f64) -> f64 {
    let (x, w) = gauss_legendre(20);
    let m = 256;
    let h = 1.0 / m as f64;
    (0..m)
        .map(|k| {
            let a = k as f64 * h;
            x.iter()
                .zip(&w)
                .map(|(&xi, &wi)| wi * f(a + 0.5 * h * (xi + 1.0)))
                .sum::<f64>()
                * 0.5
                * h
        })
        .sum()
}

fn check_interpolates(p0: DVec2, d0: DVec2, p1: DVec2, d1: DVec2) {
    let sols = PlanarPhQuintic::hermite(p0, d0, p1, d1).unwrap();
    let size = p0
        .abs()
        .max(p1.abs())
        .max(d0.abs())
        .max(d1.abs())
        .max_element()
        .max(1.0);
    for s in &sols.solutions {
        let b = s.curve.bezier();
        assert_near!(b.eval(0.0), p0, 1e-14 * size);
        assert_near!(b.eval(1.0), p1, 1e-14 * size);
        assert_near!(b.derivative(0.0, 1), d0, 1e-14 * size);
        assert_near!(b.derivative(1.0, 1), d1, 1e-14 * size);
        assert_near!(s.curve.derivative(0.5), b.derivative(0.5, 1), 1e-13 * size);
    }
}

#[test]
fn sample_952_all_four_solutions_interpolate() {
    let (p0, d0, p1, d1) = sample_952();
    check_interpolates(p0, d0, p1, d1);
}

/// Algorithm 952's rotation-index computation (`construct_PHquintic`), transcribed with its
/// triangle-angle (law of cosines) formulas: an independent check of our arg-based one.
fn rindex_952(w0: Complex, w1: Complex, w2: Complex) -> f64 {
    let angle = |a: Complex, t0: f64, t1: f64| {
        let s1 = (a - c(t0, 0.0)).abs();
        let s2 = (c(t1, 0.0) - a).abs();
        let s3 = t1 - t0;
        ((s1 * s1 + s2 * s2 - s3 * s3) / (2.0 * s1 * s2)).acos()
    };
    let k = w2 - w1 * 2.0 + w0;
    let disc = (w1 * w1 - w0 * w2).sqrt();
    let a = (w0 - w1 + disc) / k;
    let b = (w0 - w1 - disc) / k;
    if a.im * b.im > 0.0 {
        angle(a, 0.0, 1.0) + angle(b, 0.0, 1.0)
    } else {
        let c2 = (a + b).im;
        let c1 = -2.0 * (a * b).im;
        let c0 = a.norm_sqr() * b.im + b.norm_sqr() * a.im;
        let small = 1e-12;
        let mut t = vec![0.0];
        if c2.abs() > small {
            let dd = (c1 * c1 - 4.0 * c2 * c0).sqrt();
            let (mut t1, mut t2) = ((-c1 - dd) / (2.0 * c2), (-c1 + dd) / (2.0 * c2));
            if t2 < t1 {
                std::mem::swap(&mut t1, &mut t2);
            }
            for r in [t1, t2] {
                if r > 0.0 && r < 1.0 {
                    t.push(r);
                }
            }
        } else if c1.abs() > small {
            let r = -c0 / c1;
            if r > 0.0 && r < 1.0 {
                t.push(r);
            }
        }
        t.push(1.0);
        t.windows(2)
            .map(|s| (angle(a, s[0], s[1]) - angle(b, s[0], s[1])).abs())
            .sum()
    }
}

#[test]
fn sample_952_selection_matches_the_published_rule() {
    let (p0, d0, p1, d1) = sample_952();
    let sols = PlanarPhQuintic::hermite(p0, d0, p1, d1).unwrap();
    // 952 picks the minimum of its rindex (= π·R); compare values and the choice.
    let r952: Vec<f64> = sols
        .solutions
        .iter()
        .map(|s| {
            let [w0, w1, w2] = s.curve.w;
            rindex_952(w0, w1, w2)
        })
        .collect();
    for (s, r) in sols.solutions.iter().zip(&r952) {
        assert_near!(s.rotation_index * std::f64::consts::PI, *r, 1e-9);
    }
    let best952 = (0..4).min_by(|&i, &j| r952[i].total_cmp(&r952[j])).unwrap();
    assert_eq!(sols.best, best952);
    // The good interpolant (an S-shape: equal end tangents across a slanted chord) turns by
    // less than a full turn in total; the other three turn more.
    let best = sols.best();
    assert!(best.rotation_index < 1.0, "{}", best.rotation_index);
    for (i, s) in sols.solutions.iter().enumerate() {
        if i != sols.best {
            assert!(s.rotation_index > best.rotation_index);
        }
    }
}

#[test]
fn rotation_index_and_energy_match_quadrature() {
    let (p0, d0, p1, d1) = sample_952();
    let sols = PlanarPhQuintic::hermite(p0, d0, p1, d1).unwrap();
    for s in &sols.solutions {
        let b = s.curve.bezier();
        let h1 = b.hodograph();
        let h2 = h1.hodograph();
        // κ = (x′y″ − y′x″)/|r′|³ from the generic Bézier derivatives, ds = |r′| dt.
        let kappa = |t: f64| {
            let (a, bb) = (h1.eval(t), h2.eval(t));
            a.perp_dot(bb) / a.length().powi(3)
        };
        let e = quad(|t| kappa(t).powi(2) * h1.eval(t).length());
        assert_near!(s.bending_energy, e, 1e-10 * e.max(1.0));
        let r = quad(|t| kappa(t).abs() * h1.eval(t).length()) / std::f64::consts::TAU;
        assert_near!(s.rotation_index, r, 1e-8);
        for k in 0..=10 {
            let t = k as f64 / 10.0;
            assert_near!(
                s.curve.curvature(t),
                kappa(t),
                1e-12 * kappa(t).abs().max(1.0)
            );
        }
    }
}

#[test]
fn arc_length_depends_only_on_the_sign_product() {
    let (p0, d0, p1, d1) = sample_952();
    let sols = PlanarPhQuintic::hermite(p0, d0, p1, d1).unwrap();
    let by = |e0: i8, e2: i8| {
        sols.solutions
            .iter()
            .find(|s| s.eta0 == e0 && s.eta2 == e2)
            .unwrap()
            .arc_length
    };
    assert_near!(by(1, 1), by(-1, -1), 1e-13);
    assert_near!(by(1, -1), by(-1, 1), 1e-13);
    assert!((by(1, 1) - by(1, -1)).abs() > 1e-6, "the two pairs differ");
}

#[test]
fn arc_length_equals_quadrature_and_inverts() {
    let (p0, d0, p1, d1) = sample_952();
    let sols = PlanarPhQuintic::hermite(p0, d0, p1, d1).unwrap();
    for s in &sols.solutions {
        let h = s.curve.bezier().hodograph();
        let l = quad(|t| h.eval(t).length());
        assert_near!(s.curve.arc_length(), l, 1e-12 * l);
        assert_near!(s.arc_length, l, 1e-12 * l);
        for k in 0..=8 {
            let t = k as f64 / 8.0;
            let part = quad(|u| h.eval(u * t).length()) * t;
            assert_near!(s.curve.arc_length_at(t), part, 1e-12 * l);
            let back = s
                .curve
                .param_at_arc_length(s.curve.arc_length_at(t))
                .unwrap();
            assert_near!(back, t, 1e-13);
        }
    }
    let curve = sols.best().curve;
    assert!(matches!(
        curve.param_at_arc_length(-1.0),
        Err(PhError::ArcLengthOutOfRange { .. })
    ));
    assert!(matches!(
        curve.param_at_arc_length(f64::NAN),
        Err(PhError::NonFinite { .. })
    ));
}

#[test]
fn a_sampled_ph_quintic_is_recovered() {
    let curve = PlanarPhQuintic::new(
        DVec2::new(0.3, -0.2),
        [c(1.2, 0.4), c(0.9, -0.5), c(1.1, 0.3)],
    )
    .unwrap();
    let sols = PlanarPhQuintic::hermite(
        curve.eval(0.0),
        curve.derivative(0.0),
        curve.eval(1.0),
        curve.derivative(1.0),
    )
    .unwrap();
    let target = curve.control_points();
    let hit = sols
        .solutions
        .iter()
        .filter(|s| {
            let p = s.curve.control_points();
            p.iter()
                .zip(&target)
                .all(|(a, b)| (*a - *b).length() < 1e-13)
        })
        .count();
    assert_eq!(
        hit, 1,
        "exactly one of the four solutions is the sampled curve"
    );
}

#[test]
fn curvature_extreme_is_the_maximum() {
    let (p0, d0, p1, d1) = sample_952();
    let sols = PlanarPhQuintic::hermite(p0, d0, p1, d1).unwrap();
    for s in &sols.solutions {
        let ext = s.curve.max_curvature().unwrap();
        let sampled = (0..=2000)
            .map(|k| s.curve.curvature(k as f64 / 2000.0).abs())
            .fold(0.0, f64::max);
        assert!(ext.curvature.abs() >= sampled * (1.0 - 1e-12));
        assert!(
            ext.curvature.abs() <= sampled * (1.0 + 1e-3),
            "{} vs {}",
            ext.curvature,
            sampled
        );
        assert_near!(ext.radius, 1.0 / ext.curvature.abs(), 1e-12 * ext.radius);
    }
}

/// Algorithm 952's `PHquintic_offset`, transcribed: homogeneous (W, X, Y) with
/// f = C(k,j) C(9−k,4−j)/126, X_k += f(σ_j x_{k−j} + 5d Δy_j), Y_k += f(σ_j y_{k−j} − 5d Δx_j).
fn offset_952(curve: &PlanarPhQuintic, d: f64) -> Vec<(f64, f64, f64)> {
    let binom = |n: usize, k: usize| gbsurf::bezier::bernstein::binomial(n, k);
    let p = curve.control_points();
    let sigma = curve.speed_coeffs();
    (0..=9usize)
        .map(|k| {
            let (mut w, mut x, mut y) = (0.0, 0.0, 0.0);
            for j in k.saturating_sub(5)..=k.min(4) {
                let f = binom(k, j) * binom(9 - k, 4 - j) / 126.0;
                let dp = p[j + 1] - p[j];
                w += f * sigma[j];
                x += f * (sigma[j] * p[k - j].x + 5.0 * d * dp.y);
                y += f * (sigma[j] * p[k - j].y - 5.0 * d * dp.x);
            }
            (w, x, y)
        })
        .collect()
}

#[test]
fn offset_matches_algorithm_952_and_the_definition() {
    let (p0, d0, p1, d1) = sample_952();
    let curve = PlanarPhQuintic::hermite(p0, d0, p1, d1)
        .unwrap()
        .best()
        .curve;
    let d = 1.25; // the sample's distance
    let off = curve.offset(d).unwrap();
    assert_eq!(off.points.len(), 10);
    for ((w, x, y), (pt, wt)) in offset_952(&curve, d)
        .into_iter()
        .zip(off.points.iter().zip(&off.weights))
    {
        assert_near!(*wt, w, 1e-13 * w.abs().max(1.0));
        assert_near!(*pt, DVec2::new(x / w, y / w), 1e-12);
    }
    for k in 0..=50 {
        let t = k as f64 / 50.0;
        assert_near!(off.eval(t), curve.offset_point(t, d), 1e-12);
        assert_near!(off.eval(t), curve.eval(t) + curve.normal(t) * d, 1e-12);
    }
}

#[test]
fn offset_is_exactly_at_distance_below_min_radius() {
    let (p0, d0, p1, d1) = sample_952();
    let curve = PlanarPhQuintic::hermite(p0, d0, p1, d1)
        .unwrap()
        .best()
        .curve;
    let rmin = curve.min_radius_of_curvature().unwrap();
    for d in [0.5 * rmin, -0.9 * rmin, 0.99 * rmin] {
        let off = curve.offset(d).unwrap();
        assert!(off.cusps.is_empty(), "d = {d}: {:?}", off.cusps);
        for k in 0..=40 {
            let t = k as f64 / 40.0;
            let q = off.eval(t);
            let r = curve.eval(t);
            assert_near!((q - r).length(), d.abs(), 1e-12);
            // q − r is normal to the curve and on the side of d's sign (right for d > 0).
            assert_near!(
                (q - r).dot(curve.derivative(t)),
                0.0,
                1e-12 * curve.speed(t)
            );
            assert!((q - r).perp_dot(curve.derivative(t)) * d > 0.0);
        }
        // The offset's own tangent is parallel to the curve's (1 + dκ > 0): r_d′ = σT(1 + dκ).
        let rc = off.to_rational_curve();
        if let Ok(rc) = rc {
            for k in 1..10 {
                let t = k as f64 / 10.0;
                let dt = rc.derivative(t, 1);
                let want = curve.derivative(t) * (1.0 + d * curve.curvature(t));
                assert_near!(dt, want, 1e-10 * want.length().max(1.0));
            }
        }
    }
}

#[test]
fn cusps_are_reported_beyond_min_radius_on_the_concave_side() {
    let (p0, d0, p1, d1) = sample_952();
    let curve = PlanarPhQuintic::hermite(p0, d0, p1, d1)
        .unwrap()
        .best()
        .curve;
    let ext = curve.max_curvature().unwrap();
    // Concave side: d > 0 (right) where κ < 0, d < 0 where κ > 0; so d = −1.2/κ_max.
    let d = -1.2 / ext.curvature;
    let off = curve.offset(d).unwrap();
    assert!(
        off.cusps.len() >= 2,
        "expected a pair of cusps around t = {}: {:?}",
        ext.t,
        off.cusps
    );
    for &t in &off.cusps {
        assert_near!(1.0 + d * curve.curvature(t), 0.0, 1e-9);
    }
    assert!(off.cusps[0] < ext.t && ext.t < off.cusps[off.cusps.len() - 1]);
    // The convex side at the same distance has no cusps when |d| < radius there.
    let other = curve.offset(-d).unwrap();
    let kmin_same_side = (0..=1000)
        .map(|k| curve.curvature(k as f64 / 1000.0))
        .filter(|k| k * ext.curvature < 0.0)
        .map(f64::abs)
        .fold(0.0, f64::max);
    if kmin_same_side * d.abs() < 0.99 {
        assert!(other.cusps.is_empty(), "{:?}", other.cusps);
    }
}

#[test]
fn bad_input_is_rejected_with_the_argument_named() {
    let (p0, d0, p1, d1) = sample_952();
    assert_eq!(
        PlanarPhQuintic::hermite(p0, DVec2::ZERO, p1, d1),
        Err(PhError::ZeroDerivative {
            arg: "d0",
            index: None
        })
    );
    assert_eq!(
        PlanarPhQuintic::hermite(p0, d0, p1, DVec2::ZERO),
        Err(PhError::ZeroDerivative {
            arg: "d1",
            index: None
        })
    );
    assert_eq!(
        PlanarPhQuintic::hermite(p0, d0, p0, d1),
        Err(PhError::CoincidentPoints {
            arg: "p0, p1",
            index: 0
        })
    );
    assert_eq!(
        PlanarPhQuintic::hermite(p0, d0, DVec2::new(f64::NAN, 0.0), d1),
        Err(PhError::NonFinite {
            arg: "p1",
            index: None
        })
    );
    let curve = PlanarPhQuintic::hermite(p0, d0, p1, d1)
        .unwrap()
        .best()
        .curve;
    assert_eq!(curve.offset(0.0), Err(PhError::ZeroOffsetDistance));
    assert_eq!(
        curve.offset(f64::INFINITY),
        Err(PhError::NonFinite {
            arg: "d",
            index: None
        })
    );
    assert!(matches!(
        PlanarPhQuintic::new(p0, [c(1.0, 0.0), c(f64::NAN, 0.0), c(1.0, 0.0)]),
        Err(PhError::NonFinite {
            arg: "w",
            index: Some(1)
        })
    ));
    // w(t) = (1 − 2t)·(1 + 0i) vanishes at t = ½: the offset has a pole there.
    let singular = PlanarPhQuintic::new(p0, [c(1.0, 0.0), c(0.0, 0.0), c(-1.0, 0.0)]).unwrap();
    assert!(
        matches!(singular.offset(0.1), Err(PhError::SingularHodograph { t }) if (t - 0.5).abs() < 1e-12)
    );
    assert_eq!(singular.bending_energy(), f64::INFINITY);
    let msg = PhError::ZeroDerivative {
        arg: "tangents",
        index: Some(3),
    }
    .to_string();
    assert!(msg.contains("tangents") && msg.contains('3'), "{msg}");
}

#[test]
fn straight_line_has_infinite_radius_and_no_cusps() {
    let line = PlanarPhQuintic::hermite(DVec2::ZERO, DVec2::X, DVec2::X * 2.0, DVec2::X).unwrap();
    let best = line.best();
    assert_near!(best.rotation_index, 0.0, 1e-14);
    assert_near!(best.bending_energy, 0.0, 1e-20);
    assert_eq!(best.curve.min_radius_of_curvature().unwrap(), f64::INFINITY);
    assert!(best.curve.offset(5.0).unwrap().cusps.is_empty());
    assert_near!(best.curve.arc_length(), 2.0, 1e-14);
}

fn vec2() -> impl Strategy<Value = DVec2> {
    (-3.0..3.0f64, -3.0..3.0f64).prop_map(|(x, y)| DVec2::new(x, y))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn random_hermite_data_are_interpolated(p0 in vec2(), p1 in vec2(), d0 in vec2(), d1 in vec2()) {
        prop_assume!((p1 - p0).length() > 0.1 && d0.length() > 0.1 && d1.length() > 0.1);
        check_interpolates(p0, d0, p1, d1);
        let sols = PlanarPhQuintic::hermite(p0, d0, p1, d1).unwrap();
        let b = sols.best();
        for s in &sols.solutions {
            prop_assert!(b.rotation_index <= s.rotation_index + 1e-9);
            prop_assert!(s.rotation_index.is_finite() && s.bending_energy.is_finite());
        }
        // Equal sign products, equal lengths.
        let l = |e0: i8, e2: i8| sols.solutions.iter().find(|s| s.eta0 == e0 && s.eta2 == e2).unwrap().arc_length;
        prop_assert!((l(1, 1) - l(-1, -1)).abs() <= 1e-12 * l(1, 1));
        prop_assert!((l(1, -1) - l(-1, 1)).abs() <= 1e-12 * l(1, -1));
    }

    #[test]
    fn random_offsets_keep_their_distance(p0 in vec2(), p1 in vec2(), d0 in vec2(), d1 in vec2(), f in 0.05..0.95f64, side in prop::bool::ANY) {
        prop_assume!((p1 - p0).length() > 0.1 && d0.length() > 0.1 && d1.length() > 0.1);
        let curve = PlanarPhQuintic::hermite(p0, d0, p1, d1).unwrap().best().curve;
        let r = curve.min_radius_of_curvature().unwrap();
        prop_assume!(r.is_finite() && r > 1e-3);
        let d = if side { f * r } else { -f * r };
        let off = curve.offset(d).unwrap();
        prop_assert!(off.cusps.is_empty(), "{:?}", off.cusps);
        for k in 0..=16 {
            let t = k as f64 / 16.0;
            let q = off.eval(t);
            prop_assert!(((q - curve.eval(t)).length() - d.abs()).abs() <= 1e-12 * (1.0 + q.length()));
        }
    }
}

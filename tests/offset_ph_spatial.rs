//! Spatial PH quintics (quaternion form): Hermite interpolation with free angles, exact speed
//! and arc length, the Euler–Rodrigues frame, and the reduction to the planar case.

use gbsurf::assert_near;
use gbsurf::bezier::curve::gauss_legendre;
use gbsurf::offset::ph::spatial::{i_sandwich_root, SpatialPhQuintic};
use gbsurf::offset::ph::{PhError, PlanarPhQuintic, Quaternion};
use gbsurf::{DVec2, DVec3};
use proptest::prelude::*;
use std::f64::consts::FRAC_PI_2;

fn data() -> (DVec3, DVec3, DVec3, DVec3) {
    (
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 1.5, -0.5),
        DVec3::new(2.0, 1.0, 1.5),
        DVec3::new(1.5, -1.0, 1.0),
    )
}

fn quad(f: impl Fn(f64) -> f64) -> f64 {
    let (x, w) = gauss_legendre(20);
    let m = 128;
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

fn check_curve(c: &SpatialPhQuintic, p0: DVec3, d0: DVec3, p1: DVec3, d1: DVec3) {
    let size = p0
        .abs()
        .max(p1.abs())
        .max(d0.abs())
        .max(d1.abs())
        .max_element()
        .max(1.0);
    let b = c.bezier();
    assert_near!(b.eval(0.0), p0, 1e-14 * size);
    assert_near!(b.eval(1.0), p1, 1e-13 * size);
    assert_near!(b.derivative(0.0, 1), d0, 1e-13 * size);
    assert_near!(b.derivative(1.0, 1), d1, 1e-13 * size);
    let h = b.hodograph();
    let h2 = h.hodograph();
    for k in 0..=20 {
        let t = k as f64 / 20.0;
        // |r′| of the generic Bézier hodograph equals the polynomial speed |A|².
        assert_near!(h.eval(t).length(), c.speed(t), 1e-12 * size);
        assert_near!(c.derivative(t), h.eval(t), 1e-12 * size);
        assert_near!(c.second_derivative(t), h2.eval(t), 1e-11 * size);
        let [e1, e2, e3] = c.frame(t).unwrap();
        for (u, v) in [(e1, e2), (e2, e3), (e1, e3)] {
            assert_near!(u.dot(v), 0.0, 1e-13);
        }
        for u in [e1, e2, e3] {
            assert_near!(u.length(), 1.0, 1e-13);
        }
        assert_near!(e1.cross(e2), e3, 1e-13);
        assert_near!(e1, h.eval(t).normalize(), 1e-13);
    }
    let l = quad(|t| h.eval(t).length());
    assert_near!(c.arc_length(), l, 1e-12 * l);
    for k in 0..=4 {
        let t = k as f64 / 4.0;
        assert_near!(c.param_at_arc_length(c.arc_length_at(t)).unwrap(), t, 1e-13);
    }
}

#[test]
fn quaternion_roots_solve_a_i_astar() {
    for v in [
        DVec3::new(1.0, 2.0, 3.0),
        DVec3::new(-1.0, 0.0, 0.0),
        DVec3::new(-1.0, 1e-9, -1e-9),
        DVec3::new(-2.0, 0.3, 0.0),
        DVec3::new(0.0, 0.0, -4.0),
    ] {
        for phi in [0.0, 0.7, -FRAC_PI_2, 3.0] {
            let a = i_sandwich_root(v, phi);
            assert_near!(a.i_sandwich(), v, 1e-14 * v.length());
            assert_near!(a.sandwich(DVec3::X), v, 1e-14 * v.length());
            assert_near!(a.norm_sqr(), v.length(), 1e-14 * v.length());
        }
    }
    let q = Quaternion::new(0.3, -1.0, 2.0, 0.5);
    let p = Quaternion::new(-0.7, 0.2, 0.1, 1.5);
    assert_near!((q * p).norm_sqr(), q.norm_sqr() * p.norm_sqr(), 1e-13);
}

#[test]
fn hermite_with_angles_interpolates_and_frame_is_orthonormal() {
    let (p0, d0, p1, d1) = data();
    for (phi0, phi2) in [
        (0.0, 0.0),
        (-FRAC_PI_2, -FRAC_PI_2),
        (1.0, -2.0),
        (3.0, 0.5),
    ] {
        let c = SpatialPhQuintic::hermite(p0, d0, p1, d1, phi0, phi2).unwrap();
        check_curve(&c, p0, d0, p1, d1);
    }
    let c = SpatialPhQuintic::hermite_default(p0, d0, p1, d1).unwrap();
    check_curve(&c, p0, d0, p1, d1);
    // The default has the least bending energy of its four candidates.
    for phi0 in [-FRAC_PI_2, FRAC_PI_2] {
        for phi2 in [-FRAC_PI_2, FRAC_PI_2] {
            let o = SpatialPhQuintic::hermite(p0, d0, p1, d1, phi0, phi2).unwrap();
            assert!(c.bending_energy() <= o.bending_energy() + 1e-12);
        }
    }
}

#[test]
fn the_shape_depends_on_the_angles() {
    let (p0, d0, p1, d1) = data();
    let a = SpatialPhQuintic::hermite(p0, d0, p1, d1, 0.0, 0.0).unwrap();
    let b = SpatialPhQuintic::hermite(p0, d0, p1, d1, 0.0, 1.0).unwrap();
    assert!((a.eval(0.5) - b.eval(0.5)).length() > 1e-3);
    // Shifting both angles by π (A0 → −A0, A2 → −A2 with the middle root fixed) is another
    // interpolant, while right-multiplying all of A by exp(iθ) leaves the curve unchanged.
    let rot = Quaternion::new(0.4f64.cos(), 0.4f64.sin(), 0.0, 0.0);
    let turned = SpatialPhQuintic::new(a.p0, a.a.map(|q| q * rot)).unwrap();
    for k in 0..=10 {
        let t = k as f64 / 10.0;
        assert_near!(turned.eval(t), a.eval(t), 1e-13);
    }
}

#[test]
fn planar_data_reproduce_the_planar_interpolants() {
    let p0 = DVec2::new(0.8, 1.4);
    let p1 = DVec2::new(4.2, 3.6);
    let d0 = DVec2::new(8.0, -3.0);
    let d1 = DVec2::new(8.0, -3.0);
    let e = |v: DVec2| v.extend(0.0);
    let planar = PlanarPhQuintic::hermite(p0, d0, p1, d1).unwrap();
    let mut matched = 0;
    for phi0 in [-FRAC_PI_2, FRAC_PI_2] {
        for phi2 in [-FRAC_PI_2, FRAC_PI_2] {
            let c = SpatialPhQuintic::hermite(e(p0), e(d0), e(p1), e(d1), phi0, phi2).unwrap();
            let pts = c.control_points();
            assert!(
                pts.iter().all(|p| p.z.abs() < 1e-14),
                "planar data give a planar curve"
            );
            let hit = planar.solutions.iter().any(|s| {
                s.curve
                    .control_points()
                    .iter()
                    .zip(&pts)
                    .all(|(a, b)| (e(*a) - *b).length() < 1e-12)
            });
            matched += hit as usize;
        }
    }
    assert_eq!(
        matched, 4,
        "the four angle choices are the four planar solutions"
    );
    let def = SpatialPhQuintic::hermite_default(e(p0), e(d0), e(p1), e(d1)).unwrap();
    let least = planar
        .solutions
        .iter()
        .min_by(|a, b| a.bending_energy.total_cmp(&b.bending_energy))
        .unwrap();
    assert_near!(def.eval(0.37), e(least.curve.eval(0.37)), 1e-12);
}

#[test]
fn bad_input_is_rejected() {
    let (p0, d0, p1, d1) = data();
    assert_eq!(
        SpatialPhQuintic::hermite_default(p0, DVec3::ZERO, p1, d1),
        Err(PhError::ZeroDerivative {
            arg: "d0",
            index: None
        })
    );
    assert_eq!(
        SpatialPhQuintic::hermite_default(p0, d0, p0, d1),
        Err(PhError::CoincidentPoints {
            arg: "p0, p1",
            index: 0
        })
    );
    assert_eq!(
        SpatialPhQuintic::hermite(p0, d0, p1, d1, f64::NAN, 0.0),
        Err(PhError::NonFinite {
            arg: "phi0",
            index: None
        })
    );
    assert_eq!(
        SpatialPhQuintic::hermite_default(p0, d0, p1, DVec3::new(0.0, f64::INFINITY, 0.0)),
        Err(PhError::NonFinite {
            arg: "d1",
            index: None
        })
    );
}

fn vec3() -> impl Strategy<Value = DVec3> {
    (-3.0..3.0f64, -3.0..3.0f64, -3.0..3.0f64).prop_map(|(x, y, z)| DVec3::new(x, y, z))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn random_spatial_hermite(p0 in vec3(), p1 in vec3(), d0 in vec3(), d1 in vec3(), phi0 in -3.2..3.2f64, phi2 in -3.2..3.2f64) {
        prop_assume!((p1 - p0).length() > 0.1 && d0.length() > 0.1 && d1.length() > 0.1);
        let c = SpatialPhQuintic::hermite(p0, d0, p1, d1, phi0, phi2).unwrap();
        check_curve(&c, p0, d0, p1, d1);
    }
}

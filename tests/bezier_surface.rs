//! Tensor-product Bézier surfaces, the exact sphere, and patch joins (seed 001 §2).

use gbsurf::assert_near;
use gbsurf::bezier::join::{
    c0_deviation, c1_deviation, continuity_order, cross_derivative_deviations, g1_max_angle,
};
use gbsurf::bezier::{BezierCurve, BezierError, BezierSurface, RationalSurface, SurfacePartials};
use gbsurf::DVec3;
use proptest::prelude::*;

fn d3(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

#[test]
fn bilinear_hyperbolic_paraboloid() {
    // Seed 001 eq. 2.1: x(u, v) = (u, v, uv).
    let s = BezierSurface::new(vec![
        vec![d3(0.0, 0.0, 0.0), d3(0.0, 1.0, 0.0)],
        vec![d3(1.0, 0.0, 0.0), d3(1.0, 1.0, 1.0)],
    ])
    .unwrap();
    let (u, v) = (0.3, 0.8);
    assert_near!(s.eval(u, v), d3(u, v, u * v));
    let p = s.partials(u, v);
    assert_near!(p.u, d3(1.0, 0.0, v));
    assert_near!(p.v, d3(0.0, 1.0, u));
    assert_near!(p.uv, d3(0.0, 0.0, 1.0));
    assert_near!(p.uu, DVec3::ZERO);
    assert_near!(p.vv, DVec3::ZERO);
    // z = xy at the origin: K = −1, H = 0.
    let (h, k) = s.curvature(0.0, 0.0).unwrap();
    assert_near!(k, -1.0);
    assert_near!(h, 0.0);
    assert_near!(s.normal(0.0, 0.0).unwrap(), DVec3::Z);
}

/// z = (x² + y²)/2 over x, y ∈ [−1, 1] as a biquadratic patch: x = 2u − 1 has coefficients
/// (−1, 0, 1) and (2u − 1)² has (1, −1, 1).
fn paraboloid() -> BezierSurface<DVec3> {
    let x = [-1.0, 0.0, 1.0];
    let a = [1.0, -1.0, 1.0];
    BezierSurface::new(
        (0..3)
            .map(|i| {
                (0..3)
                    .map(|j| d3(x[i], x[j], 0.5 * (a[i] + a[j])))
                    .collect()
            })
            .collect(),
    )
    .unwrap()
}

#[test]
fn paraboloid_curvature_and_derivatives() {
    let s = paraboloid();
    for &(u, v) in &[(0.5, 0.5), (0.2, 0.9), (1.0, 0.0)] {
        let (x, y) = (2.0 * u - 1.0, 2.0 * v - 1.0);
        assert_near!(s.eval(u, v), d3(x, y, 0.5 * (x * x + y * y)));
        let p = s.partials(u, v);
        assert_near!(p.u, d3(2.0, 0.0, 2.0 * x));
        assert_near!(p.vv, d3(0.0, 0.0, 4.0));
        assert_near!(p.uv, DVec3::ZERO);
        // Graph z = f(x, y): K = (f_xx f_yy − f_xy²)/(1 + |∇f|²)², H = ((1+f_y²) f_xx + (1+f_x²) f_yy)/(2 (1+|∇f|²)^{3/2}).
        let g = 1.0 + x * x + y * y;
        let (h, k) = s.curvature(u, v).unwrap();
        assert_near!(k, 1.0 / (g * g));
        assert_near!(h, ((1.0 + y * y) + (1.0 + x * x)) / (2.0 * g.powf(1.5)));
    }
    // Seed 001 eq. 2.6: the derivative surface has degree (m − 1, n).
    let du = s.derivative_u();
    assert_eq!((du.degree_u(), du.degree_v()), (1, 2));
    assert_near!(du.eval(0.2, 0.7), s.partials(0.2, 0.7).u);
    assert_near!(s.derivative_v().eval(0.2, 0.7), s.partials(0.2, 0.7).v);
}

#[test]
fn translational_surface_has_zero_twist() {
    // Seed 001 eq. 2.13: p_ij = a_i + b_j makes every net quadrilateral a parallelogram.
    let a = [
        d3(0.0, 0.0, 0.0),
        d3(1.0, 0.0, 1.0),
        d3(2.0, 0.5, -1.0),
        d3(3.0, 0.0, 0.0),
    ];
    let b = [d3(0.0, 0.0, 0.0), d3(0.0, 1.0, 2.0), d3(0.3, 2.0, 0.0)];
    let s = BezierSurface::new(
        a.iter()
            .map(|&ai| b.iter().map(|&bj| ai + bj).collect())
            .collect(),
    )
    .unwrap();
    for &(u, v) in &[(0.1, 0.2), (0.5, 0.5), (0.9, 0.4)] {
        assert_near!(s.partials(u, v).uv, DVec3::ZERO);
    }
}

#[test]
fn iso_curves_and_boundaries() {
    let s = paraboloid().elevate_v(1);
    assert_eq!(s.iso_u(0.3).degree(), 3);
    assert_eq!(s.iso_v(0.3).degree(), 2);
    assert_near!(s.iso_u(0.3).eval(0.6), s.eval(0.3, 0.6));
    assert_near!(s.iso_v(0.6).eval(0.3), s.eval(0.3, 0.6));
    // u = 0 boundary is the first row (seed 001 §2.2).
    assert_near!(s.iso_u(0.0).points().to_vec(), s.points()[0].clone());
    assert_near!(s.transposed().eval(0.6, 0.3), s.eval(0.3, 0.6));
    assert_near!(s.reversed_u().eval(0.25, 0.3), s.eval(0.75, 0.3));
    assert_near!(s.reversed_v().eval(0.25, 0.3), s.eval(0.25, 0.7));
}

#[test]
fn bad_input_is_an_error() {
    assert_eq!(BezierSurface::<DVec3>::new(vec![]), Err(BezierError::Empty));
    assert_eq!(
        BezierSurface::<DVec3>::new(vec![vec![]]),
        Err(BezierError::Empty)
    );
    assert_eq!(
        BezierSurface::new(vec![vec![DVec3::X, DVec3::Y], vec![DVec3::Z]]),
        Err(BezierError::RaggedRow {
            row: 1,
            len: 1,
            expected: 2
        })
    );
    assert_eq!(
        BezierSurface::new(vec![vec![DVec3::X, DVec3::Y], vec![DVec3::Z, DVec3::NAN]]),
        Err(BezierError::NonFinitePoint { index: 3 })
    );
    let g = vec![vec![DVec3::X, DVec3::Y], vec![DVec3::Z, DVec3::ONE]];
    assert_eq!(
        RationalSurface::new(g.clone(), vec![vec![1.0, 1.0]]),
        Err(BezierError::WeightCount {
            got: 2,
            expected: 4
        })
    );
    assert_eq!(
        RationalSurface::new(g, vec![vec![1.0, 1.0], vec![-2.0, 1.0]]),
        Err(BezierError::BadWeight {
            index: 2,
            value: -2.0
        })
    );
}

#[test]
fn sphere_is_exact() {
    let c = d3(1.0, -2.0, 0.5);
    let r = 2.5;
    let patches = RationalSurface::sphere(c, r).unwrap();
    assert_eq!(patches.len(), 8);
    let mut worst: f64 = 0.0;
    for s in &patches {
        assert_eq!((s.degree_u(), s.degree_v()), (2, 2));
        for a in 0..=40 {
            for b in 0..=40 {
                let (u, v) = (a as f64 / 40.0, b as f64 / 40.0);
                let p = s.eval(u, v);
                worst = worst.max(((p - c).length() / r - 1.0).abs());
                if b < 40 {
                    // Outward normal, K = 1/r², H = −1/r with the x_u × x_v convention.
                    assert_near!(s.normal(u, v).unwrap(), (p - c) / r, 1e-13);
                    let (h, k) = s.curvature(u, v).unwrap();
                    assert_near!(k, 1.0 / (r * r), 1e-12);
                    assert_near!(h, -1.0 / r, 1e-12);
                }
            }
        }
        // The pole edge v = 1 is degenerate: no normal there.
        assert!(s.normal(0.5, 1.0).is_none());
    }
    assert!(worst <= 1e-14, "max ||p − c|/r − 1| = {worst:e}");
    // Weights of the northern octant: products of (1, √2/2, 1).
    let h = std::f64::consts::FRAC_1_SQRT_2;
    assert_near!(patches[0].weights()[1].clone(), vec![h, 0.5, h]);
    // Degree elevation keeps the sphere.
    let e = patches[0].elevate_u(2).elevate_v(1);
    for &(u, v) in &[(0.1, 0.3), (0.77, 0.5), (0.5, 0.99)] {
        assert_near!(e.eval(u, v), patches[0].eval(u, v), 1e-14 * r);
    }
    // Iso-curves of the octant are circular arcs: the equator and a meridian.
    let eq = patches[0].iso_v(0.0);
    let mer = patches[0].iso_u(0.37);
    for t in [0.0, 0.25, 0.6, 1.0] {
        assert_near!((eq.eval(t) - c).length(), r, 1e-14 * r);
        assert_near!(eq.eval(t).z, c.z, 1e-14 * r);
        assert_near!((mer.eval(t) - c).length(), r, 1e-14 * r);
    }
}

#[test]
fn sphere_octants_join_g1() {
    let (c, r) = (DVec3::ZERO, 1.0);
    // Equator: a = southern octant with u running to the equator, b = northern one from it.
    let north = RationalSurface::sphere_octant(c, r, 0.0, true).unwrap();
    let south = RationalSurface::sphere_octant(c, r, 0.0, false).unwrap();
    let a = south.transposed().reversed_u();
    let b = north.transposed();
    assert_near!(a.eval(1.0, 0.3), b.eval(0.0, 0.3), 1e-15);
    assert!(g1_max_angle(&a, &b, 50).unwrap() <= 1e-14);
    // Along a meridian the samples reach the pole, where the normal vanishes.
    let next = RationalSurface::sphere_octant(c, r, std::f64::consts::FRAC_PI_2, true).unwrap();
    assert_eq!(
        g1_max_angle(&north, &next, 5),
        Err(BezierError::DegenerateNormal { patch: 0, v: 1.0 })
    );
}

/// A bicubic patch over [0, 1]² lifted by a wavy height.
fn bicubic_a() -> BezierSurface<DVec3> {
    BezierSurface::new(
        (0..4)
            .map(|i| {
                (0..4)
                    .map(|j| {
                        d3(
                            i as f64,
                            j as f64 + 0.2 * i as f64,
                            ((i * 7 + j * 3) % 5) as f64 * 0.3,
                        )
                    })
                    .collect()
            })
            .collect(),
    )
    .unwrap()
}

/// A patch b with b's u = 0 side on a's u = 1 side and first cross differences
/// q_1j − q_0j = λ (p_3j − p_2j) + μ h_j, where h_j/3 are the control points of the boundary
/// tangent a_v(1, v) elevated to degree 3 (so b_u = 3λ(...) + μ a_v along the boundary).
fn bicubic_b(
    a: &BezierSurface<DVec3>,
    lambda: f64,
    mu: f64,
    perturb: DVec3,
) -> BezierSurface<DVec3> {
    let p = a.points();
    let boundary = BezierCurve::new(p[3].clone()).unwrap();
    let h = boundary.hodograph().elevate().into_points();
    let q: Vec<Vec<DVec3>> = (0..4)
        .map(|i| {
            (0..4)
                .map(|j| match i {
                    0 => p[3][j],
                    1 => {
                        p[3][j]
                            + (p[3][j] - p[2][j]) * lambda
                            + h[j] * (mu / 3.0)
                            + if j == 1 { perturb } else { DVec3::ZERO }
                    }
                    _ => d3(3.0 + i as f64, j as f64 + 0.6, (i + j) as f64 * 0.1),
                })
                .collect()
        })
        .collect();
    BezierSurface::new(q).unwrap()
}

#[test]
fn c1_join_of_bicubic_patches() {
    let a = bicubic_a();
    // Seed 001 eq. 2.18 with Δ_a = 2, Δ_b = 1: q_1j − q_0j = (Δ_b/Δ_a)(p_3j − p_2j).
    let b = bicubic_b(&a, 0.5, 0.0, DVec3::ZERO);
    assert_near!(c0_deviation(&a, &b), 0.0);
    assert!(c1_deviation(&a, &b, 2.0, 1.0) <= 1e-14);
    assert_eq!(continuity_order(&a, &b, 3, 2.0, 1.0, 1e-12), Some(1));
    // With equal intervals the same patches are only C0 (but still G1).
    assert_eq!(continuity_order(&a, &b, 3, 1.0, 1.0, 1e-12), Some(0));
    assert!(g1_max_angle(&a, &b, 33).unwrap() <= 1e-13);
    // Degree elevation of b in v changes nothing (curves are compared after elevation).
    assert!(cross_derivative_deviations(&a, &b.elevate_v(2), 1, 2.0, 1.0)[1] <= 1e-13);
    // Perturbing one cross-boundary point breaks C1 and G1.
    let bad = bicubic_b(&a, 0.5, 0.0, d3(0.0, 0.0, 0.05));
    assert_eq!(continuity_order(&a, &bad, 3, 2.0, 1.0, 1e-12), Some(0));
    assert!(c1_deviation(&a, &bad, 2.0, 1.0) > 0.01);
    assert!(g1_max_angle(&a, &bad, 33).unwrap() > 1e-3);
    // A gap at the boundary: not C0.
    let moved = b.map(|p| p + d3(0.0, 0.0, 1e-3));
    assert_eq!(continuity_order(&a, &moved, 2, 2.0, 1.0, 1e-12), None);
    assert_near!(c0_deviation(&a, &moved), 1e-3, 1e-15);
}

#[test]
fn g1_but_not_c1_join() {
    let a = bicubic_a();
    // b_u = λ-scaled a_u plus a multiple of the boundary tangent: same tangent planes.
    let b = bicubic_b(&a, 0.8, 0.4, DVec3::ZERO);
    assert!(g1_max_angle(&a, &b, 65).unwrap() <= 1e-13);
    for delta_b in [0.5, 0.8, 1.0, 2.0] {
        assert_eq!(continuity_order(&a, &b, 2, 1.0, delta_b, 1e-9), Some(0));
    }
    // A negative factor flips the cross-boundary direction: the surface folds back (angle π).
    let fold = bicubic_b(&a, -0.8, 0.0, DVec3::ZERO);
    assert_near!(
        g1_max_angle(&a, &fold, 9).unwrap(),
        std::f64::consts::PI,
        1e-12
    );
}

#[test]
fn subdivided_patch_is_c_infinity_across_the_cut() {
    let s = bicubic_a();
    let (a, b) = s.subdivide_u(0.4);
    assert_eq!(continuity_order(&a, &b, 5, 0.4, 0.6, 1e-12), Some(5));
    let (l, r) = s.subdivide_v(0.7);
    assert_eq!(
        continuity_order(&l.transposed(), &r.transposed(), 5, 0.7, 0.3, 1e-12),
        Some(5)
    );
}

fn grid(max_deg: usize) -> impl Strategy<Value = Vec<Vec<DVec3>>> {
    (1..=max_deg, 1..=max_deg).prop_flat_map(|(m, n)| {
        prop::collection::vec(
            prop::collection::vec(prop::array::uniform3(-10.0..10.0f64), n + 1),
            m + 1,
        )
        .prop_map(|g| {
            g.into_iter()
                .map(|r| r.into_iter().map(DVec3::from_array).collect())
                .collect()
        })
    })
}

fn scale(g: &[Vec<DVec3>]) -> f64 {
    g.iter().flatten().map(|p| p.length()).fold(1.0, f64::max)
}

fn fd_check(f: impl Fn(f64, f64) -> SurfacePartials<DVec3>, u: f64, v: f64, tol1: f64, tol2: f64) {
    let h = 1e-5;
    let p = f(u, v);
    let (pu, mu, pv, mv) = (f(u + h, v), f(u - h, v), f(u, v + h), f(u, v - h));
    assert_near!(p.u, (pu.p - mu.p) / (2.0 * h), tol1);
    assert_near!(p.v, (pv.p - mv.p) / (2.0 * h), tol1);
    assert_near!(p.uu, (pu.u - mu.u) / (2.0 * h), tol2);
    assert_near!(p.vv, (pv.v - mv.v) / (2.0 * h), tol2);
    assert_near!(p.uv, (pv.u - mv.u) / (2.0 * h), tol2);
    assert_near!(p.uv, (pu.v - mu.v) / (2.0 * h), tol2);
}

proptest! {
    #[test]
    fn elevation_and_subdivision_keep_the_surface(g in grid(5), ku in 0usize..3, kv in 0usize..3,
                                                  t in 0.05..0.95f64, u in 0.0..=1.0f64, v in 0.0..=1.0f64) {
        let tol = 1e-12 * scale(&g);
        let s = BezierSurface::new(g).unwrap();
        assert_near!(s.elevate_u(ku).elevate_v(kv).eval(u, v), s.eval(u, v), tol);
        let (a, b) = s.subdivide_u(t);
        assert_near!(a.eval(u, v), s.eval(u * t, v), tol);
        assert_near!(b.eval(u, v), s.eval(t + u * (1.0 - t), v), tol);
        let (c, d) = s.subdivide_v(t);
        assert_near!(c.eval(u, v), s.eval(u, v * t), tol);
        assert_near!(d.eval(u, v), s.eval(u, t + v * (1.0 - t)), tol);
        assert_near!(s.iso_u(u).eval(v), s.eval(u, v), tol);
        assert_near!(s.partials(u, v).p, s.eval(u, v), tol);
    }

    #[test]
    fn partials_match_finite_differences(g in grid(5), u in 0.05..0.95f64, v in 0.05..0.95f64) {
        let sc = scale(&g);
        let s = BezierSurface::new(g).unwrap();
        fd_check(|u, v| s.partials(u, v), u, v, 1e-6 * sc, 1e-4 * sc);
    }

    #[test]
    fn rational_surface_derivatives_and_elevation(g in grid(4), w in prop::collection::vec(0.3..3.0f64, 25),
                                                  u in 0.05..0.95f64, v in 0.05..0.95f64) {
        let sc = scale(&g);
        let weights: Vec<Vec<f64>> = g.iter().enumerate().map(|(i, r)| (0..r.len()).map(|j| w[i * 5 + j]).collect()).collect();
        let s = RationalSurface::new(g, weights).unwrap();
        fd_check(|u, v| s.partials(u, v), u, v, 1e-5 * sc, 1e-3 * sc);
        assert_near!(s.elevate_u(1).elevate_v(2).eval(u, v), s.eval(u, v), 1e-12 * sc);
        assert_near!(s.iso_u(u).eval(v), s.eval(u, v), 1e-12 * sc);
        assert_near!(s.iso_v(v).eval(u), s.eval(u, v), 1e-12 * sc);
    }

    #[test]
    fn affine_invariance(g in grid(4), u in 0.0..=1.0f64, v in 0.0..=1.0f64,
                         m in prop::array::uniform9(-2.0..2.0f64), off in prop::array::uniform3(-5.0..5.0f64)) {
        let a = glam::DMat3::from_cols_array(&m);
        let o = DVec3::from_array(off);
        let f = |q: DVec3| a * q + o;
        let sc = scale(&g);
        let s = BezierSurface::new(g).unwrap();
        assert_near!(s.map(f).eval(u, v), f(s.eval(u, v)), 1e-11 * sc * 10.0);
    }
}

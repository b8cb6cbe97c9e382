//! The ribbon-only CGB patch (seed 000 §3.6, eq. 3.7–3.8).

mod common_gb;

use common_gb::{fd_derivs, random_ribbons, Rng};
use gbsurf::gb::Evaluate;
use gbsurf::assert_near;
use gbsurf::gb::{CgbPatch, Domain, WeightForm};
use gbsurf::{DVec2, DVec3};
use proptest::prelude::*;

fn mixed(n: usize, seed: u64) -> CgbPatch {
    let mut r = Rng::new(seed + 5);
    let degrees: Vec<usize> = (0..n).map(|_| 2 + (r.f() * 5.0) as usize).collect();
    let layers: Vec<usize> = degrees
        .iter()
        .map(|&d| 1 + (r.f() * d.div_ceil(2) as f64) as usize)
        .collect();
    CgbPatch {
        ribbons: random_ribbons(&degrees, &layers, seed),
    }
}

fn samples(dom: &Domain) -> Vec<DVec2> {
    let mut v = vec![DVec2::ZERO];
    for i in 0..dom.n() {
        for m in 0..=10 {
            let q = dom.side_point(i, m as f64 / 10.0);
            v.extend([q, q * 0.999_999, q * 0.6, q * 0.2]);
        }
        v.push(dom.side_point(i, 1e-9));
    }
    v
}

#[test]
fn boundary_interpolation_mixed_degrees() {
    for n in 3..=8 {
        for seed in 0..4 {
            let p = mixed(n, seed * 31 + n as u64);
            p.validate().unwrap();
            let dom = Domain::regular(n).unwrap();
            let mut ev = p.evaluator().unwrap();
            for form in [WeightForm::Squared, WeightForm::Linear] {
                for i in 0..n {
                    for m in 0..=12 {
                        let t = m as f64 / 12.0;
                        let s = p.eval_derivs_with(&mut ev, dom.side_point(i, t), form);
                        assert_near!(
                            s.p,
                            p.ribbons[i].boundary_point(t),
                            1e-12,
                            "n={n} side {i} t={t}"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn constant_net_gives_constant_surface_and_no_nan() {
    for n in 3..=8 {
        let mut p = mixed(n, 3);
        let c = DVec3::new(0.3, -2.0, 7.0);
        for r in &mut p.ribbons {
            r.points_mut().iter_mut().for_each(|q| *q = c);
        }
        let dom = Domain::regular(n).unwrap();
        let q = mixed(n, 11);
        for x in samples(&dom) {
            let s = p.eval_derivs(x, WeightForm::Squared);
            assert_near!(s.p, c, 1e-12);
            // derivative round-off grows near the corners (0/0 corner weights)
            let r = dom
                .vertices()
                .iter()
                .map(|v| (*v - x).length())
                .fold(1.0, f64::min);
            let (t1, t2) = if r > 1e-4 { (1e-9, 1e-4) } else { (1e-6, 1e-2) };
            assert_near!(s.su, DVec3::ZERO, t1, "x={x}");
            assert_near!(s.sv, DVec3::ZERO, t1, "x={x}");
            assert_near!(s.svv, DVec3::ZERO, t2, "x={x}");
            for form in [WeightForm::Squared, WeightForm::Linear] {
                let s = q.eval_derivs(x, form);
                assert!(s.is_finite(), "n={n} x={x}");
                if let Some(c) = s.curvature() {
                    assert!(c.mean.is_finite() && c.gaussian.is_finite());
                }
            }
        }
    }
}

#[test]
fn squared_weights_keep_ribbon_normals() {
    for n in 3..=7 {
        let dom = Domain::regular(n).unwrap();
        let mut r = Rng::new(n as u64);
        // a gentle graph surface, then independent row-1 perturbations
        let degrees: Vec<usize> = (0..n).map(|i| 3 + (i % 3)).collect();
        let ribbons = (0..n)
            .map(|i| {
                let d = degrees[i];
                let l = d.div_ceil(2);
                let rows = (0..l)
                    .map(|k| {
                        (0..=d)
                            .map(|j| {
                                let a = dom.vertex(i + n - 1);
                                let b = dom.vertex(i);
                                let q = (a + (b - a) * (j as f64 / d as f64))
                                    * (1.0 - k as f64 / d as f64);
                                let mut p = DVec3::new(q.x, q.y, 0.3 * q.x * q.y + 0.2 * q.x * q.x);
                                if k == 1 {
                                    p += r.v() * 0.05;
                                }
                                p
                            })
                            .collect()
                    })
                    .collect();
                gbsurf::gb::Ribbon::from_rows(d, rows).unwrap()
            })
            .collect();
        let p = CgbPatch { ribbons };
        p.validate().unwrap();
        let mut worst: f64 = 0.0;
        let mut worst_lin: f64 = 0.0;
        for i in 0..n {
            for m in 1..30 {
                let t = m as f64 / 30.0;
                let x = dom.side_point(i, t);
                let b = p.ribbons[i].boundary_normal(t).unwrap();
                let a = p.normal(x, WeightForm::Squared).unwrap();
                worst = worst.max(a.cross(b).length() + (a.dot(b) < 0.0) as u8 as f64);
                let a = p.normal(x, WeightForm::Linear).unwrap();
                worst_lin = worst_lin.max(a.cross(b).length());
            }
        }
        assert!(worst < 1e-7, "n={n}: {worst}");
        assert!(worst_lin > 1e-3, "n={n}: linear {worst_lin}");
    }
}

#[test]
fn validate_and_errors() {
    use gbsurf::gb::GbError;
    let mut p = mixed(5, 1);
    p.ribbons[2] = gbsurf::gb::Ribbon::from_rows(p.ribbons[2].degree, vec![]).unwrap();
    assert!(matches!(
        p.validate(),
        Err(GbError::LayerCount { side: 2, .. })
    ));
    let mut p = mixed(5, 1);
    p.ribbons[4].degree = 1;
    assert!(matches!(
        p.validate(),
        Err(GbError::DegreeTooLow { side: 4, .. })
    ));
    let p = CgbPatch {
        ribbons: mixed(5, 1).ribbons[..2].to_vec(),
    };
    assert_eq!(p.validate(), Err(GbError::TooFewSides(2)));
    assert_eq!(p.eval(DVec2::ZERO, WeightForm::Squared), DVec3::ZERO);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn derivatives_match_finite_differences(n in 3usize..8, seed in 0u64..500, i in 0usize..8,
                                             t in 0.05f64..0.95, r in 0.05f64..0.95, lin in proptest::bool::ANY) {
        let form = if lin { WeightForm::Linear } else { WeightForm::Squared };
        let p = mixed(n, seed);
        let x = Domain::regular(n).unwrap().side_point(i % n, t) * r;
        let a = p.eval_derivs(x, form);
        let b = fd_derivs(&|y| p.eval(y, form), x);
        assert_near!(a.p, b[0]);
        assert_near!(a.su, b[1], 1e-6);
        assert_near!(a.sv, b[2], 1e-6);
        assert_near!(a.suu, b[3], 3e-3);
        assert_near!(a.suv, b[4], 3e-3);
        assert_near!(a.svv, b[5], 3e-3);
    }

    #[test]
    fn affine_invariance(n in 3usize..8, seed in 0u64..500, t in 0.0f64..1.0, r in 0.0f64..1.0,
                         m in proptest::array::uniform9(-2.0f64..2.0), off in proptest::array::uniform3(-5.0f64..5.0)) {
        let p = mixed(n, seed);
        let mat = glam::DMat3::from_cols_array(&m);
        let o = DVec3::from_array(off);
        let mut q = p.clone();
        for rb in &mut q.ribbons { for x in rb.points_mut() { *x = mat * *x + o; } }
        let x = Domain::regular(n).unwrap().side_point(1, t) * r;
        assert_near!(q.eval(x, WeightForm::Squared), mat * p.eval(x, WeightForm::Squared) + o, 1e-11);
    }

    #[test]
    fn normalized_basis_matches_eval(n in 3usize..8, seed in 0u64..500, x in -0.5f64..0.5, y in -0.5f64..0.5) {
        let p = mixed(n, seed);
        let mut ev = p.evaluator().unwrap();
        let mut w = vec![gbsurf::gb::Jet2::ZERO; ev.len()];
        let uv = DVec2::new(x, y);
        ev.eval_into(uv, WeightForm::Squared, &mut w).unwrap();
        let pts = p.control_points_flat();
        let s: DVec3 = pts.iter().zip(&w).map(|(q, w)| *q * w.val).sum();
        let su: DVec3 = pts.iter().zip(&w).map(|(q, w)| *q * w.du).sum();
        let d = p.eval_derivs(uv, WeightForm::Squared);
        assert_near!(s, d.p, 1e-12);
        assert_near!(su, d.su, 1e-10);
        let total: f64 = w.iter().map(|w| w.val).sum();
        assert_near!(total, 1.0);
    }
}

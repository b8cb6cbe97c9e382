//! Degree elevation of GB patches (seed 002): exact boundaries and cross-derivatives.

mod common_gb;

use common_gb::random_patch;
use gbsurf::gb::Evaluate;
use gbsurf::assert_near;
use gbsurf::gb::{layers_for_degree, Domain, GbPatch, Ribbon, WeightForm};
use gbsurf::{DVec2, DVec3};

#[test]
fn boundaries_and_cross_derivatives_are_exact() {
    for n in 3..=8 {
        let dom = Domain::regular(n).unwrap();
        for d in 2..=7 {
            let p = random_patch(n, d, (n * 100 + d) as u64);
            let q = p.elevate().unwrap();
            q.validate().unwrap();
            assert_eq!(q.degree(), d + 1);
            assert_eq!(q.layers(), layers_for_degree(d + 1));
            let mut ea = p.evaluator().unwrap();
            let mut eb = q.evaluator().unwrap();
            for i in 0..n {
                for m in 0..=16 {
                    let t = m as f64 / 16.0;
                    // ribbon level: boundary curve and cross-derivative curve
                    assert_near!(
                        q.ribbons[i].boundary_point(t),
                        p.ribbons[i].boundary_point(t),
                        1e-12
                    );
                    if d >= 3 {
                        assert_near!(
                            q.ribbons[i].cross_derivative(t),
                            p.ribbons[i].cross_derivative(t),
                            1e-12
                        );
                    }
                    // patch level: point and both partial derivatives on the side
                    let x = dom.side_point(i, t);
                    let a = p.eval_derivs_with(&mut ea, x);
                    let b = q.eval_derivs_with(&mut eb, x);
                    assert_near!(a.p, b.p, 1e-12, "n={n} d={d} side {i} t={t}");
                    if d >= 3 && m > 0 && m < 16 {
                        assert_near!(a.su, b.su, 1e-11, "n={n} d={d} side {i} t={t}");
                        assert_near!(a.sv, b.sv, 1e-11, "n={n} d={d} side {i} t={t}");
                    }
                }
            }
            // the central surface point is kept (unless the new central weight vanishes there:
            // n = 4 and odd d+1, where B0 ≡ 0)
            if !(n == 4 && (d + 1) % 2 == 1) {
                assert_near!(
                    q.eval(DVec2::ZERO, WeightForm::Squared),
                    p.eval(DVec2::ZERO, WeightForm::Squared),
                    1e-12,
                    "n={n} d={d}"
                );
            }
        }
    }
}

#[test]
fn four_sided_elevation_is_exact_everywhere() {
    // a shared n = 4 net (tensor-product grid) stays the same surface
    for d in 2..=6 {
        let mut r = common_gb::Rng::new(d as u64);
        let grid: Vec<Vec<DVec3>> = (0..=d).map(|_| (0..=d).map(|_| r.v()).collect()).collect();
        let l = layers_for_degree(d);
        let side = |f: &dyn Fn(usize, usize) -> DVec3| Ribbon::from_fn(d, l, d + 1, |k, j| f(j, k));
        let p = GbPatch {
            ribbons: vec![
                side(&|j, k| grid[d - k][j]),
                side(&|j, k| grid[d - j][d - k]),
                side(&|j, k| grid[k][d - j]),
                side(&|j, k| grid[j][k]),
            ],
            center: grid[d / 2][d / 2],
        };
        let q = p.elevate_to(d + 2).unwrap();
        assert_eq!(q.degree(), d + 2);
        for a in 0..=8 {
            for b in 0..=8 {
                let x = DVec2::new(a as f64 / 4.0 - 1.0, b as f64 / 4.0 - 1.0);
                for form in [WeightForm::Squared, WeightForm::Linear] {
                    assert_near!(q.eval(x, form), p.eval(x, form), 1e-12, "d={d} x={x}");
                }
            }
        }
    }
}

#[test]
fn elevation_rejects_invalid_patches_and_is_a_noop_at_target() {
    let mut p = random_patch(5, 3, 1);
    assert_eq!(p.elevate_to(3).unwrap(), p);
    p.ribbons[1] = Ribbon::from_fn(3, 2, 3, |k, j| p.ribbons[1].row(k)[j]);
    assert!(p.elevate().is_err());
}

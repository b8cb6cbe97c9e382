//! GB patch basis and evaluation (seed 000 §2.7, eq. 2.22–2.25; docs/math.md#gb).

use gbsurf::gb::Evaluate;
use gbsurf::assert_near;
use gbsurf::bezier::bernstein::bernstein_all_d2;
use gbsurf::gb::{
    gb_basis, layers_for_degree, Domain, GbBasis, GbPatch, Ribbon, SurfaceDerivs, WeightForm,
};
use gbsurf::{DVec2, DVec3};
use proptest::prelude::*;

const FORMS: [WeightForm; 2] = [WeightForm::Squared, WeightForm::Linear];

/// Small deterministic generator (xorshift64*).
struct Rng(u64);
impl Rng {
    fn f(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545F4914F6CDD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn v(&mut self) -> DVec3 {
        DVec3::new(
            self.f() * 2.0 - 1.0,
            self.f() * 2.0 - 1.0,
            self.f() * 2.0 - 1.0,
        )
    }
}

/// Random ribbons whose row-0 end points agree at the corners (independent everything else).
fn random_patch(n: usize, d: usize, seed: u64) -> GbPatch {
    let mut r = Rng(seed.wrapping_mul(2654435761).wrapping_add(12345) | 1);
    let l = layers_for_degree(d);
    let mut ribbons: Vec<Ribbon> = (0..n)
        .map(|_| Ribbon::from_rows(d, (0..l).map(|_| (0..=d).map(|_| r.v()).collect()).collect()).unwrap())
        .collect();
    for i in 0..n {
        let p = ribbons[(i + n - 1) % n].row(0)[d];
        ribbons[i].row_mut(0)[0] = p;
    }
    GbPatch {
        ribbons,
        center: r.v(),
    }
}

/// Random patch with the connected-structure sharing of docs/math.md#sharing: (i, j, k) with j < l is
/// (i−1, d−k, j).
fn shared_patch(n: usize, d: usize, seed: u64) -> GbPatch {
    let mut p = random_patch(n, d, seed);
    let l = layers_for_degree(d);
    for i in 0..n {
        for k in 0..l {
            for j in 0..l {
                let q = p.ribbons[(i + n - 1) % n].row(j)[d - k];
                p.ribbons[i].row_mut(k)[j] = q;
            }
        }
    }
    p
}

/// Tensor-product Bézier grid P[a][b], T(u,v) = Σ P[a][b] B_a(u) B_b(v), as an n = 4 GB patch
/// on the square (1,1), (−1,1), (−1,−1), (1,−1): u = (1+x)/2, v = (1+y)/2;
/// side 3: s = u, h = v; side 0: s = v, h = 1−u; side 1: s = 1−u, h = 1−v; side 2: s = 1−v, h = u.
fn tensor_to_gb(grid: &[Vec<DVec3>]) -> GbPatch {
    let d = grid.len() - 1;
    let l = layers_for_degree(d);
    let side = |f: &dyn Fn(usize, usize) -> DVec3| Ribbon::from_fn(d, l, d + 1, |k, j| f(j, k));
    GbPatch {
        ribbons: vec![
            side(&|j, k| grid[d - k][j]),
            side(&|j, k| grid[d - j][d - k]),
            side(&|j, k| grid[k][d - j]),
            side(&|j, k| grid[j][k]),
        ],
        center: grid[d / 2][d / 2],
    }
}

/// Tensor-product surface derivatives in the square's (x, y): ∂/∂x = ½ ∂/∂u.
fn tensor_eval(grid: &[Vec<DVec3>], x: DVec2) -> SurfaceDerivs {
    let d = grid.len() - 1;
    let (bu, du, ddu) = bernstein_all_d2(d, (1.0 + x.x) / 2.0);
    let (bv, dv, ddv) = bernstein_all_d2(d, (1.0 + x.y) / 2.0);
    let mut s = SurfaceDerivs::default();
    for a in 0..=d {
        for b in 0..=d {
            let p = grid[a][b];
            s.p += p * bu[a] * bv[b];
            s.su += p * du[a] * bv[b] * 0.5;
            s.sv += p * bu[a] * dv[b] * 0.5;
            s.suu += p * ddu[a] * bv[b] * 0.25;
            s.suv += p * du[a] * dv[b] * 0.25;
            s.svv += p * bu[a] * ddv[b] * 0.25;
        }
    }
    s
}

fn random_grid(d: usize, seed: u64) -> Vec<Vec<DVec3>> {
    let mut r = Rng(seed * 7919 + 3);
    (0..=d).map(|_| (0..=d).map(|_| r.v()).collect()).collect()
}

/// Sample points of the closed domain: vertices, side points, interior rings.
fn closed_domain_samples(dom: &Domain) -> Vec<DVec2> {
    let n = dom.n();
    let mut pts = vec![DVec2::ZERO];
    for i in 0..n {
        for m in 0..=10 {
            pts.push(dom.side_point(i, m as f64 / 10.0));
        }
        for &t in &[1e-14, 1e-9, 1e-6, 1.0 - 1e-9] {
            pts.push(dom.side_point(i, t));
        }
        for &r in &[0.999_999_999, 0.99, 0.7, 0.3] {
            for m in 0..=5 {
                pts.push(dom.side_point(i, m as f64 / 5.0) * r);
            }
        }
    }
    pts
}

fn fd_derivs(f: &dyn Fn(DVec2) -> DVec3, x: DVec2) -> SurfaceDerivs {
    let e = 1e-5;
    let g = |a: f64, b: f64| f(x + DVec2::new(a, b));
    let p = g(0.0, 0.0);
    SurfaceDerivs {
        p,
        su: (g(e, 0.0) - g(-e, 0.0)) / (2.0 * e),
        sv: (g(0.0, e) - g(0.0, -e)) / (2.0 * e),
        suu: (g(e, 0.0) - 2.0 * p + g(-e, 0.0)) / (e * e),
        suv: (g(e, e) - g(e, -e) - g(-e, e) + g(-e, -e)) / (4.0 * e * e),
        svv: (g(0.0, e) - 2.0 * p + g(0.0, -e)) / (e * e),
    }
}

#[test]
fn mu_rule_and_basis_layout() {
    let b = gb_basis(5, 4, DVec2::new(0.1, 0.2), WeightForm::Squared).unwrap();
    assert_eq!(b.len(), 1 + 5 * 2 * 5);
    assert_eq!(GbBasis::len_for(5, 4), b.len());
    assert_eq!(b.index(2, 1, 3), 1 + (2 * 2 + 1) * 5 + 3);
    assert_eq!(GbBasis::index_for(4, 2, 1, 3), b.index(2, 1, 3));
    use gbsurf::gb::weights::{mu_kind, MuKind::*};
    assert_eq!(
        [mu_kind(2, 0, 0), mu_kind(2, 0, 1), mu_kind(2, 0, 2)],
        [Alpha, One, Beta]
    );
    // cubic: all 2x2 corner blocks
    assert_eq!(
        [
            mu_kind(3, 0, 0),
            mu_kind(3, 1, 1),
            mu_kind(3, 0, 2),
            mu_kind(3, 1, 3)
        ],
        [Alpha, Alpha, Beta, Beta]
    );
    // degree 6, row 2: j = 2 and j = 4 halves, j = 3 one, j < 2 or j > 4 zero
    assert_eq!(
        (0..=6).map(|j| mu_kind(6, 2, j)).collect::<Vec<_>>(),
        vec![Zero, Zero, Half, One, Half, Zero, Zero]
    );
    assert_eq!(mu_kind(5, 0, 2), One);
    assert!(gb_basis(2, 3, DVec2::ZERO, WeightForm::Squared).is_err());
    assert!(gb_basis(5, 1, DVec2::ZERO, WeightForm::Squared).is_err());
}

#[test]
fn central_weight_of_cubic_patch_at_centre() {
    for n in 3..=10 {
        for form in FORMS {
            let b = gb_basis(n, 3, DVec2::ZERO, form).unwrap();
            let nf = n as f64;
            assert_near!(b.center().val, (nf - 2.0) * (nf - 4.0) / (nf * nf));
        }
    }
    assert_near!(
        gb_basis(3, 3, DVec2::ZERO, WeightForm::Squared)
            .unwrap()
            .center()
            .val,
        -1.0 / 9.0
    );
}

#[test]
fn basis_is_a_partition_of_unity_everywhere() {
    for n in 3..=8 {
        let dom = Domain::regular(n).unwrap();
        for d in 2..=6 {
            for form in FORMS {
                let mut ev = gbsurf::gb::GbBasisEvaluator::new(n, d).unwrap();
                for x in closed_domain_samples(&dom) {
                    let b = ev.eval(x, form);
                    assert!(b.weights.iter().all(|w| w.is_finite()), "n={n} d={d} x={x}");
                    let s = b.weights.iter().fold(gbsurf::gb::Jet2::ZERO, |a, w| a + *w);
                    assert_near!(s.val, 1.0, 1e-12);
                    // the sum's derivatives vanish up to the round-off of the (large) corner
                    // weight derivatives, which grow like 1/r and 1/r² near a corner
                    let r = dom
                        .vertices()
                        .iter()
                        .map(|v| (*v - x).length())
                        .fold(1.0, f64::min);
                    let (t1, t2) = if r > 1e-3 {
                        (1e-12, 1e-11)
                    } else {
                        (1e-9, 1e-5)
                    };
                    assert_near!(s.du, 0.0, t1, "n={n} d={d} x={x}");
                    assert_near!(s.dv, 0.0, t1);
                    assert_near!(s.duu, 0.0, t2, "n={n} d={d} x={x} {form:?}");
                    assert_near!(s.duv, 0.0, t2);
                    assert_near!(s.dvv, 0.0, t2, "n={n} d={d} x={x} {form:?}");
                }
            }
        }
    }
}

#[test]
fn boundary_interpolation_and_exact_corners() {
    for n in 3..=8 {
        let dom = Domain::regular(n).unwrap();
        for d in 3..=8 {
            let p = random_patch(n, d, (n * 10 + d) as u64);
            p.validate().unwrap();
            let mut ev = p.evaluator().unwrap();
            for form in FORMS {
                for i in 0..n {
                    for m in 0..=12 {
                        let t = m as f64 / 12.0;
                        let s = p.ribbons[i].boundary_point(t);
                        let g = p.eval_derivs_with_form(&mut ev, dom.side_point(i, t), form);
                        assert_near!(g.p, s, 1e-12, "n={n} d={d} side {i} t={t} {form:?}");
                    }
                    // corners exactly
                    let c = p.eval_derivs_with_form(&mut ev, dom.vertex(i), form).p;
                    assert_eq!(c, p.ribbons[i].row(0)[d], "corner {i} n={n} d={d}");
                }
            }
        }
    }
}

#[test]
fn no_nan_on_the_closed_domain() {
    for n in 3..=8 {
        let dom = Domain::regular(n).unwrap();
        for d in 2..=8 {
            for (pi, p) in [
                random_patch(n, d, 99 + d as u64),
                shared_patch(n, d, 7 + n as u64),
            ]
            .iter()
            .enumerate()
            {
                let mut ev = p.evaluator().unwrap();
                for form in FORMS {
                    for x in closed_domain_samples(&dom) {
                        let s = p.eval_derivs_with_form(&mut ev, x, form);
                        assert!(
                            s.is_finite(),
                            "n={n} d={d} patch {pi} x={x} {form:?}: {s:?}"
                        );
                        if let Some(nv) = s.normal() {
                            assert!(nv.is_finite());
                        }
                        if let Some(c) = s.curvature() {
                            assert!(
                                c.mean.is_finite() && c.gaussian.is_finite() && c.k1.is_finite()
                            );
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn four_sided_patch_is_the_tensor_product_patch() {
    let dom = Domain::regular(4).unwrap();
    for d in 2..=7 {
        let grid = random_grid(d, d as u64);
        let p = tensor_to_gb(&grid);
        p.validate().unwrap();
        let mut ev = p.evaluator().unwrap();
        for form in FORMS {
            for x in closed_domain_samples(&dom) {
                let g = p.eval_derivs_with_form(&mut ev, x, form);
                let t = tensor_eval(&grid, x);
                assert_near!(g.p, t.p, 1e-12, "d={d} x={x} {form:?}");
                // derivatives: exact up to round-off, which grows like ε/r and ε/r² at the
                // distance r from a corner (0/0 weights there)
                let r = dom
                    .vertices()
                    .iter()
                    .map(|v| (*v - x).length())
                    .fold(f64::MAX, f64::min);
                if r > 0.0 {
                    let (t1, t2) = (1e-10 + 1e-15 / r, 1e-9 + 1e-14 / (r * r));
                    assert_near!(g.su, t.su, t1, "d={d} x={x}");
                    assert_near!(g.sv, t.sv, t1, "d={d} x={x}");
                    assert_near!(g.suu, t.suu, t2, "d={d} x={x}");
                    assert_near!(g.suv, t.suv, t2, "d={d} x={x}");
                    assert_near!(g.svv, t.svv, t2, "d={d} x={x}");
                }
            }
        }
    }
}

#[test]
fn curvature_of_four_sided_patch_matches_tensor_product() {
    // a saddle-like and a dome-like grid
    for d in 3..=6 {
        let grid: Vec<Vec<DVec3>> = (0..=d)
            .map(|a| {
                (0..=d)
                    .map(|b| {
                        let (u, v) = (a as f64 / d as f64, b as f64 / d as f64);
                        DVec3::new(
                            u,
                            v,
                            0.5 * (u - 0.5).powi(2) - 0.8 * (v - 0.4).powi(2) + 0.1 * u * v,
                        )
                    })
                    .collect()
            })
            .collect();
        let p = tensor_to_gb(&grid);
        for &(x, y) in &[(0.0, 0.0), (0.3, -0.7), (-0.9, 0.95), (1.0, 0.2)] {
            let x = DVec2::new(x, y);
            let a = p.eval_derivs(x, WeightForm::Squared).curvature().unwrap();
            let b = tensor_eval(&grid, x).curvature().unwrap();
            assert_near!(a.mean, b.mean, 1e-9);
            assert_near!(a.gaussian, b.gaussian, 1e-9);
            assert!(b.gaussian.abs() > 1e-3);
        }
    }
}

/// A net on the unit sphere's upper part: points of the polar-angle grid over the domain.
fn sphere_patch(n: usize, d: usize) -> GbPatch {
    let dom = Domain::regular(n).unwrap();
    let l = layers_for_degree(d);
    // map a domain point to the sphere by lifting (x, y) ↦ normalize(0.6 x, 0.6 y, 1)
    let lift = |q: DVec2| DVec3::new(0.6 * q.x, 0.6 * q.y, 1.0).normalize();
    let mut ribbons = Vec::new();
    for i in 0..n {
        let a = dom.vertex(i + n - 1);
        let b = dom.vertex(i);
        let rows = (0..l)
            .map(|k| {
                (0..=d)
                    .map(|j| {
                        let on = a + (b - a) * (j as f64 / d as f64);
                        let t = k as f64 / d as f64;
                        lift(on * (1.0 - t))
                    })
                    .collect()
            })
            .collect();
        ribbons.push(Ribbon::from_rows(d, rows).unwrap());
    }
    GbPatch {
        ribbons,
        center: DVec3::Z,
    }
}

#[test]
fn curvature_matches_finite_differences_of_the_normal() {
    for n in [3, 5, 6] {
        for d in [3, 4, 5] {
            let p = sphere_patch(n, d);
            let dom = Domain::regular(n).unwrap();
            let mut ev = p.evaluator().unwrap();
            for &(i, t, r) in &[
                (0usize, 0.3, 0.5),
                (1, 0.6, 0.9),
                (2, 0.5, 0.1),
                (0, 0.8, 0.97),
            ] {
                let x = dom.side_point(i, t) * r;
                let s = p.eval_derivs_with(&mut ev, x);
                let c = s.curvature().unwrap();
                let e = 1e-6;
                let nrm = |y: DVec2| p.eval_derivs(y, WeightForm::Squared).normal().unwrap();
                let nu = (nrm(x + DVec2::X * e) - nrm(x - DVec2::X * e)) / (2.0 * e);
                let nv = (nrm(x + DVec2::Y * e) - nrm(x - DVec2::Y * e)) / (2.0 * e);
                // Weingarten: −[n_u n_v] = [S_u S_v] W; solve in the least-squares sense
                let (e1, f1, g1) = s.first_fundamental_form();
                let det = e1 * g1 - f1 * f1;
                let solve = |w: DVec3| {
                    let (a, b) = (s.su.dot(w), s.sv.dot(w));
                    ((g1 * a - f1 * b) / det, (e1 * b - f1 * a) / det)
                };
                let (w11, w21) = solve(-nu);
                let (w12, w22) = solve(-nv);
                assert_near!(c.gaussian, w11 * w22 - w12 * w21, 1e-6, "n={n} d={d}");
                assert_near!(c.mean, 0.5 * (w11 + w22), 1e-6);
                // a convex dome (S_u × S_v points up, away from the centre of curvature: H < 0)
                assert!(c.mean < -0.1 && c.gaussian > 0.01, "n={n} d={d} {c:?}");
            }
        }
    }
}

/// Angle between the patch normal and the ribbon normal along side i (max over samples).
fn max_side_normal_angle(p: &GbPatch, form: WeightForm) -> f64 {
    let n = p.n();
    let dom = Domain::regular(n).unwrap();
    let mut ev = p.evaluator().unwrap();
    let mut worst: f64 = 0.0;
    for i in 0..n {
        for m in 1..40 {
            let t = m as f64 / 40.0;
            let s = p.eval_derivs_with_form(&mut ev, dom.side_point(i, t), form);
            let a = s.normal().unwrap();
            let b = p.ribbons[i].boundary_normal(t).unwrap();
            worst = worst.max(a.cross(b).length().asin().abs().max(if a.dot(b) < 0.0 {
                3.0
            } else {
                0.0
            }));
        }
    }
    worst
}

#[test]
fn squared_weights_keep_ribbon_normals_with_independent_corner_blocks() {
    for n in 3..=7 {
        for d in 3..=6 {
            // a smooth shared net, then every side's corner blocks moved independently
            let mut p = shared_patch(n, d, 1000 + (n * d) as u64);
            // make it a gentle surface so the normals are well defined and consistently oriented
            let dom = Domain::regular(n).unwrap();
            let l = layers_for_degree(d);
            let mut r = Rng(77 + n as u64);
            for i in 0..n {
                for k in 0..l {
                    for j in 0..=d {
                        let a = dom.vertex(i + n - 1);
                        let b = dom.vertex(i);
                        let q = (a + (b - a) * (j as f64 / d as f64)) * (1.0 - k as f64 / d as f64);
                        p.ribbons[i].row_mut(k)[j] =
                            DVec3::new(q.x, q.y, 0.3 * q.x * q.y + 0.2 * q.x * q.x);
                    }
                }
                // independent blocks: the row-1 end points and twists of each side
                for &j in &[0usize, 1, d - 1, d] {
                    p.ribbons[i].row_mut(1)[j] += r.v() * 0.05;
                }
            }
            p.validate().unwrap();
            let sq = max_side_normal_angle(&p, WeightForm::Squared);
            let lin = max_side_normal_angle(&p, WeightForm::Linear);
            assert!(sq < 1e-7, "n={n} d={d}: squared angle {sq}");
            assert!(
                lin > 1e-3,
                "n={n} d={d}: linear angle {lin} (expected a visible deviation)"
            );
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn analytic_derivatives_match_finite_differences(n in 3usize..8, d in 2usize..7, seed in 0u64..1000,
                                                     i in 0usize..8, t in 0.05f64..0.95, r in 0.05f64..0.95,
                                                     lin in proptest::bool::ANY) {
        let form = if lin { WeightForm::Linear } else { WeightForm::Squared };
        let p = random_patch(n, d, seed);
        let dom = Domain::regular(n).unwrap();
        let x = dom.side_point(i % n, t) * r;
        let a = p.eval_derivs(x, form);
        let f = |y: DVec2| p.eval(y, form);
        let b = fd_derivs(&f, x);
        assert_near!(a.p, b.p);
        assert_near!(a.su, b.su, 1e-6);
        assert_near!(a.sv, b.sv, 1e-6);
        assert_near!(a.suu, b.suu, 2e-3);
        assert_near!(a.suv, b.suv, 2e-3);
        assert_near!(a.svv, b.svv, 2e-3);
    }

    #[test]
    fn affine_invariance(n in 3usize..8, d in 2usize..7, seed in 0u64..1000, i in 0usize..8,
                         t in 0.0f64..1.0, r in 0.0f64..1.0,
                         m in proptest::array::uniform9(-2.0f64..2.0), off in proptest::array::uniform3(-5.0f64..5.0)) {
        let p = random_patch(n, d, seed);
        let mat = glam::DMat3::from_cols_array(&m);
        let o = DVec3::from_array(off);
        let map = |q: DVec3| mat * q + o;
        let q = GbPatch {
            ribbons: p
                .ribbons
                .iter()
                .map(|rb| Ribbon::from_fn(rb.degree, rb.layers(), rb.width(), |k, j| map(rb.row(k)[j])))
                .collect(),
            center: map(p.center),
        };
        let x = Domain::regular(n).unwrap().side_point(i % n, t) * r;
        for form in FORMS {
            assert_near!(q.eval(x, form), map(p.eval(x, form)), 1e-11);
        }
    }

    #[test]
    fn flat_order_matches_basis(n in 3usize..8, d in 2usize..7, seed in 0u64..1000, x in -0.5f64..0.5, y in -0.5f64..0.5) {
        let p = random_patch(n, d, seed);
        let uv = DVec2::new(x, y);
        let b = gb_basis(n, d, uv, WeightForm::Squared).unwrap();
        let pts = p.control_points_flat();
        assert_eq!(pts.len(), b.len());
        let s: DVec3 = pts.iter().zip(&b.weights).map(|(q, w)| *q * w.val).sum();
        assert_near!(s, p.eval(uv, WeightForm::Squared), 1e-12);
        let su: DVec3 = pts.iter().zip(&b.weights).map(|(q, w)| *q * w.du).sum();
        assert_near!(su, p.eval_derivs(uv, WeightForm::Squared).su, 1e-11);
    }
}

#[test]
fn validate_names_the_offending_element() {
    use gbsurf::gb::GbError;
    let mut p = random_patch(5, 4, 1);
    // Ragged rows cannot make a ribbon; rows all one point short make one that does not validate.
    let mut rows = p.ribbons[3].to_rows();
    rows[1].pop();
    assert_eq!(
        Ribbon::from_rows(4, rows),
        Err(GbError::RaggedRows {
            row: 1,
            expected: 5,
            found: 4
        })
    );
    p.ribbons[3] = Ribbon::from_fn(4, 2, 4, |k, j| p.ribbons[3].row(k)[j]);
    assert_eq!(
        p.validate(),
        Err(GbError::RowLength {
            side: 3,
            row: 0,
            expected: 5,
            found: 4
        })
    );
    let mut p = random_patch(5, 4, 1);
    p.ribbons[2].degree = 3;
    assert!(matches!(
        p.validate(),
        Err(GbError::DegreeMismatch { side: 2, .. })
    ));
    let mut p = random_patch(5, 4, 1);
    p.ribbons[4] = Ribbon::from_fn(4, 1, 5, |k, j| p.ribbons[4].row(k)[j]);
    assert!(matches!(
        p.validate(),
        Err(GbError::LayerCount { side: 4, .. })
    ));
    let mut p = random_patch(5, 4, 1);
    p.ribbons[1].row_mut(0)[2].x = f64::NAN;
    assert_eq!(
        p.validate(),
        Err(GbError::NonFinite {
            side: Some(1),
            row: 0,
            col: 2
        })
    );
    let mut p = random_patch(5, 4, 1);
    p.center.y = f64::INFINITY;
    assert_eq!(
        p.validate(),
        Err(GbError::NonFinite {
            side: None,
            row: 0,
            col: 0
        })
    );
    let p = GbPatch {
        ribbons: random_patch(5, 4, 1).ribbons[..2].to_vec(),
        center: DVec3::ZERO,
    };
    assert_eq!(p.validate(), Err(GbError::TooFewSides(2)));
    // malformed patches evaluate without panicking
    let mut q = random_patch(5, 4, 1);
    q.ribbons[3] = Ribbon::from_fn(4, 2, 2, |k, j| q.ribbons[3].row(k)[j]);
    assert!(q
        .eval(DVec2::new(0.1, 0.1), WeightForm::Squared)
        .is_finite());
}

/// Patches as they could arrive from a file or the C ABI: every public entry point returns an
/// error or a value, never panics (absurd degrees used to overflow `d + 1` in the evaluators).
#[test]
fn malformed_patches_never_panic() {
    use gbsurf::gb::{CgbPatch, GbError};
    let x = DVec2::new(0.1, -0.2);
    let huge = |d: usize, rows: Vec<Vec<DVec3>>| GbPatch {
        ribbons: vec![Ribbon::from_rows(d, rows).unwrap(); 4],
        center: DVec3::ONE,
    };
    let mut cases = vec![
        huge(usize::MAX, vec![]),
        huge(usize::MAX - 1, vec![vec![DVec3::ZERO; 3]]),
        huge(1 << 40, vec![]),
        huge(0, vec![vec![]]),
        huge(1, vec![vec![DVec3::ZERO; 2]]),
        GbPatch {
            ribbons: vec![],
            center: DVec3::ONE,
        },
    ];
    let mut ragged = random_patch(5, 5, 3);
    ragged.ribbons[1] = Ribbon::from_rows(5, vec![]).unwrap();
    ragged.ribbons[2] = Ribbon::from_fn(5, 3, 9, |_, _| DVec3::ONE);
    ragged.ribbons[4].degree = 7;
    cases.push(ragged);
    for (c, p) in cases.iter().enumerate() {
        assert!(p.validate().is_err(), "case {c}");
        let _ = p.eval(x, WeightForm::Squared);
        let _ = p.normal(x, WeightForm::Linear);
        let _ = p.curvature(x, WeightForm::Squared);
        assert!(p.elevate().is_err(), "case {c}");
        let cgb = CgbPatch {
            ribbons: p.ribbons.clone(),
        };
        assert!(cgb.validate().is_err(), "case {c}");
        let _ = cgb.eval(x, WeightForm::Squared);
    }
    assert!(matches!(
        cases[0].validate(),
        Err(GbError::DegreeTooHigh { side: 0, .. })
    ));
    // The evaluator itself refuses such degrees with a typed error.
    assert!(matches!(
        gbsurf::gb::GbBasisEvaluator::new(3, usize::MAX),
        Err(GbError::DegreeTooHigh { .. })
    ));
    // Elevation stops with an error at the cap instead of looping or allocating without bound.
    assert!(random_patch(3, 3, 1).elevate_to(usize::MAX).is_err());
}

/// A ribbon serializes as before its rows were one buffer, `{"degree": d, "rows": [[[x, y, z], …], …]}`,
/// reads back equal, and ragged rows in a file are refused with a message naming the row.
#[test]
fn ribbon_serde_form_is_rows_of_points() {
    let p = random_patch(5, 4, 7);
    let r = &p.ribbons[2];
    let text = serde_json::to_string(r).unwrap();
    let rows: Vec<Vec<[f64; 3]>> = r.rows().map(|row| row.iter().map(|q| q.to_array()).collect()).collect();
    let expected = serde_json::json!({"degree": 4, "rows": rows});
    assert_eq!(text, serde_json::to_string(&expected).unwrap());
    // Read back: the rows the same text gives as `Vec<Vec<DVec3>>` (serde_json's float parsing,
    // not exact to the last bit without its `float_roundtrip` feature, is the same for both).
    #[derive(serde::Deserialize)]
    struct Rows {
        degree: usize,
        rows: Vec<Vec<DVec3>>,
    }
    let (back, old) = (serde_json::from_str::<Ribbon>(&text).unwrap(), serde_json::from_str::<Rows>(&text).unwrap());
    assert_eq!((back.degree, back.to_rows()), (old.degree, old.rows));
    assert_near!(back.points().to_vec(), r.points().to_vec(), 1e-15);
    let ragged = r#"{"degree": 2, "rows": [[[0,0,0],[1,0,0],[2,0,0]], [[0,1,0],[1,1,0]]]}"#;
    let err = serde_json::from_str::<Ribbon>(ragged).unwrap_err().to_string();
    assert!(err.contains("ribbon row 1 has 2 points where row 0 has 3"), "{err}");
}

//! GB patch editing (seed 002): S = S_B + Σ S_Di + S_I, and elevation to a common degree.
//! The rule is in docs/math/editing.md.

mod common_gb;

use common_gb::{random_patch, Rng};
use gbsurf::gb::Evaluate;
use gbsurf::assert_near;
use gbsurf::bezier::reduce::BaseDisplacement;
use gbsurf::bezier::BezierCurve;
use gbsurf::construct::check::join_report;
use gbsurf::construct::{build_dual, Patch, Surface};
use gbsurf::ConvertOptions;
use gbsurf::gb::decompose::{
    base_patch, common_degree, decompose, max_degree, CommonDegreeError, DecomposeError,
};
use gbsurf::gb::{layers_for_degree, Domain, GbError, GbPatch, Ribbon, WeightForm};
use gbsurf::mesh::generate::torus;
use gbsurf::mesh::{HalfEdgeMesh, PolyMesh};
use gbsurf::{DVec2, DVec3};

const FORMS: [WeightForm; 2] = [WeightForm::Squared, WeightForm::Linear];

/// Random points inside the domain: convex combinations of the vertices.
fn domain_points(dom: &Domain, count: usize, seed: u64) -> Vec<DVec2> {
    let mut r = Rng::new(seed);
    (0..count)
        .map(|_| {
            let w: Vec<f64> = dom.vertices().iter().map(|_| r.f() + 1e-3).collect();
            let sum: f64 = w.iter().sum();
            dom.vertices()
                .iter()
                .zip(&w)
                .map(|(v, w)| *v * (*w / sum))
                .sum()
        })
        .collect()
}

/// Sample parameters along a side, corners included, with the tolerance for first derivatives
/// there: 1e-12, except 1e-6 from a corner. There the gradients of the correction weights grow
/// like 1/r and the central weight's gradient −Σ(weight gradients) carries round-off of about
/// 1e-15/r (measured: 1.6e-10 squared, 1.6e-9 linear at r = 1e-6, growing tenfold per decade).
fn side_ts() -> Vec<(f64, f64)> {
    let mut t: Vec<(f64, f64)> = (0..=16).map(|k| (k as f64 / 16.0, 1e-12)).collect();
    t.extend([(1e-6, 1e-8), (1.0 - 1e-6, 1e-8)]);
    t
}

#[test]
fn the_terms_add_up_to_the_patch() {
    for n in 3..=8 {
        let dom = Domain::regular(n).unwrap();
        for d in 3..=6 {
            let p = random_patch(n, d, (100 * n + d) as u64);
            let dec = decompose(&p).unwrap();
            assert_eq!(dec.degree(), d);
            assert_eq!(dec.base_cubic.degree(), 3);
            assert_eq!(dec.displacements.len(), n);
            for t in dec.displacements.iter().chain([&dec.base, &dec.interior]) {
                t.validate().unwrap();
                assert_eq!(t.degree(), d);
            }
            // control point by control point
            let q = dec.recompose();
            assert_near!(q.control_points_flat(), p.control_points_flat(), 1e-14);
            // and as surfaces, at random domain points and on the boundary
            let mut pts = domain_points(&dom, 40, (n * d) as u64);
            for i in 0..n {
                pts.extend(side_ts().into_iter().map(|(t, _)| dom.side_point(i, t)));
            }
            for form in FORMS {
                for &x in &pts {
                    let sum = dec.base.eval(x, form)
                        + dec
                            .displacements
                            .iter()
                            .map(|t| t.eval(x, form))
                            .sum::<DVec3>()
                        + dec.interior.eval(x, form);
                    assert_near!(sum, p.eval(x, form), 1e-12, "n={n} d={d} x={x} {form:?}");
                }
            }
        }
    }
}

#[test]
fn each_displacement_changes_only_its_own_side_and_the_interior_none() {
    for n in 3..=8 {
        let dom = Domain::regular(n).unwrap();
        for d in 3..=6 {
            let p = random_patch(n, d, (7 * n + d) as u64);
            let dec = decompose(&p).unwrap();
            let mut ev = p.evaluator().unwrap();
            for form in FORMS {
                for i in 0..n {
                    // the term itself: zero with zero gradient on every other side
                    let mut own_side = 0.0f64;
                    for m in 0..n {
                        for (t, tol) in side_ts() {
                            let x = dom.side_point(m, t);
                            let v = dec.displacements[i].eval_derivs_with_form(&mut ev, x, form);
                            if m == i {
                                own_side = own_side
                                    .max(v.p.length())
                                    .max(v.su.length())
                                    .max(v.sv.length());
                                continue;
                            }
                            let ctx = format!("n={n} d={d} S_D{i} on side {m} t={t} {form:?}");
                            assert_near!(v.p, DVec3::ZERO, 1e-12, "{ctx}");
                            assert_near!(v.su, DVec3::ZERO, tol, "{ctx}");
                            assert_near!(v.sv, DVec3::ZERO, tol, "{ctx}");
                        }
                    }
                    // it does act on its own side (columns 2..=d−2 exist from d = 4 on)
                    if d >= 4 {
                        assert!(
                            own_side > 1e-3,
                            "n={n} d={d} side {i}: S_D{i} is ~0 on its own side"
                        );
                    } else {
                        assert_eq!(own_side, 0.0);
                    }
                }
                for m in 0..n {
                    for (t, tol) in side_ts() {
                        let x = dom.side_point(m, t);
                        let v = dec.interior.eval_derivs_with_form(&mut ev, x, form);
                        let ctx = format!("n={n} d={d} S_I on side {m} t={t} {form:?}");
                        assert_near!(v.p, DVec3::ZERO, 1e-12, "{ctx}");
                        assert_near!(v.su, DVec3::ZERO, tol, "{ctx}");
                        assert_near!(v.sv, DVec3::ZERO, tol, "{ctx}");
                    }
                }
            }
        }
    }
}

#[test]
fn editing_a_displacement_keeps_the_other_sides() {
    // S' = S + 2·S_Di (an edit of side i's displacement): the other sides keep their boundary
    // points and first derivatives (hence cross-derivatives and normals); side i moves.
    for n in 3..=8 {
        let dom = Domain::regular(n).unwrap();
        for d in 4..=6 {
            let p = random_patch(n, d, (31 * n + d) as u64);
            let mut dec = decompose(&p).unwrap();
            let i = (n + d) % n;
            for r in &mut dec.displacements[i].ribbons {
                for v in r.points_mut() {
                    *v *= 3.0;
                }
            }
            let q = dec.recompose();
            let mut moved = 0.0f64;
            for m in 0..n {
                for (t, tol) in side_ts() {
                    let x = dom.side_point(m, t);
                    let a = p.eval_derivs(x, WeightForm::Squared);
                    let b = q.eval_derivs(x, WeightForm::Squared);
                    if m == i {
                        moved = moved.max(a.p.distance(b.p));
                        continue;
                    }
                    let ctx = format!("n={n} d={d} edit side {i}, side {m} t={t}");
                    assert_near!(b.p, a.p, 1e-12, "{ctx}");
                    assert_near!(b.su, a.su, tol, "{ctx}");
                    assert_near!(b.sv, a.sv, tol, "{ctx}");
                }
            }
            assert!(moved > 1e-3, "n={n} d={d}: the edited side did not move");
        }
    }
}

#[test]
fn the_base_carries_the_corner_data() {
    for n in 3..=8 {
        for d in 3..=6 {
            let p = random_patch(n, d, (13 * n + d) as u64);
            let cubic = base_patch(&p).unwrap();
            let elevated = cubic.elevate_to(d).unwrap();
            let dec = decompose(&p).unwrap();
            assert_eq!(dec.base_cubic, cubic);
            for i in 0..n {
                let (r, e) = (&p.ribbons[i], &elevated.ribbons[i]);
                // corner blocks: rows 0–1, columns 0, 1, d−1, d (before the round-off copy)
                for k in 0..2 {
                    for j in [0, 1, d - 1, d] {
                        assert_near!(
                            e.row(k)[j],
                            r.row(k)[j],
                            1e-13,
                            "n={n} d={d} side {i} ({k},{j})"
                        );
                        assert_eq!(dec.base.ribbons[i].row(k)[j], r.row(k)[j]);
                    }
                }
                // end positions and first derivatives of the boundary and the cross-derivative
                let c = &cubic.ribbons[i];
                for s in [0.0, 1.0] {
                    assert_near!(c.boundary_point(s), r.boundary_point(s), 1e-13);
                    assert_near!(c.boundary_tangent(s), r.boundary_tangent(s), 1e-12);
                    assert_near!(c.cross_derivative(s), r.cross_derivative(s), 1e-12);
                }
                let xd = |rb: &Ribbon| {
                    BezierCurve::new(
                        (0..=rb.degree)
                            .map(|j| (rb.row(1)[j] - rb.row(0)[j]) * rb.degree as f64)
                            .collect(),
                    )
                    .unwrap()
                };
                for s in [0.0, 1.0] {
                    assert_near!(xd(c).derivative(s, 1), xd(r).derivative(s, 1), 1e-11);
                }
                // boundary row of S_B and of S_Di is the curve form r = r_B + r_D of row 0
                let bd =
                    BaseDisplacement::new(&BezierCurve::new(r.row(0).to_vec()).unwrap()).unwrap();
                assert_near!(
                    dec.base.ribbons[i].row(0).to_vec(),
                    bd.base_elevated().into_points(),
                    1e-13
                );
                assert_near!(
                    dec.displacements[i].ribbons[i].row(0).to_vec(),
                    bd.displacement().to_vec(),
                    1e-13
                );
            }
        }
    }
}

#[test]
fn cubic_patches_are_their_own_base() {
    for n in 3..=6 {
        let p = random_patch(n, 3, n as u64);
        let dec = decompose(&p).unwrap();
        assert_eq!(dec.base, p);
        for t in dec.displacements.iter().chain([&dec.interior]) {
            assert!(t.control_points_flat().iter().all(|v| *v == DVec3::ZERO));
        }
    }
}

#[test]
fn decomposition_errors() {
    let p = random_patch(5, 2, 1);
    assert_eq!(decompose(&p), Err(DecomposeError::BelowCubic { degree: 2 }));
    let mut bad = random_patch(5, 4, 1);
    // Rows one point short (a ribbon's rows all have one length).
    bad.ribbons[3] = Ribbon::from_fn(4, 2, 4, |k, j| bad.ribbons[3].row(k)[j]);
    assert_eq!(
        decompose(&bad),
        Err(DecomposeError::Invalid(GbError::RowLength {
            side: 3,
            row: 0,
            expected: 5,
            found: 4
        }))
    );
}

#[test]
fn common_degree_errors_name_the_patch() {
    let ps = vec![
        random_patch(3, 3, 1),
        random_patch(4, 6, 2),
        random_patch(5, 4, 3),
    ];
    assert_eq!(
        common_degree(&ps, 5),
        Err(CommonDegreeError::AboveTarget {
            patch: 1,
            degree: 6,
            target: 5
        })
    );
    assert_eq!(
        common_degree(&ps, 1000),
        Err(CommonDegreeError::TargetTooHigh {
            target: 1000,
            max: 128
        })
    );
    let mut bad = ps.clone();
    bad[2].center.x = f64::NAN;
    assert_eq!(
        common_degree(&bad, 6),
        Err(CommonDegreeError::Patch {
            patch: 2,
            source: GbError::NonFinite {
                side: None,
                row: 0,
                col: 0
            }
        })
    );
    assert_eq!(max_degree(&ps), 6);
    assert_eq!(max_degree(&[]), 0);
    assert_eq!(common_degree(&[], 4), Ok(vec![]));
}

#[test]
fn common_degree_keeps_boundaries_and_cross_derivatives() {
    let ps: Vec<GbPatch> = (3..=6).map(|d| random_patch(3 + d, d, d as u64)).collect();
    for target in [6, 7] {
        let qs = common_degree(&ps, target).unwrap();
        for (p, q) in ps.iter().zip(&qs) {
            assert_eq!(q.degree(), target);
            assert_eq!(q.layers(), layers_for_degree(target));
            let dom = Domain::regular(p.n()).unwrap();
            for i in 0..p.n() {
                for (t, tol) in side_ts() {
                    let x = dom.side_point(i, t);
                    let a = p.eval_derivs(x, WeightForm::Squared);
                    let b = q.eval_derivs(x, WeightForm::Squared);
                    assert_near!(b.p, a.p, 1e-12);
                    // gradients of size ~10: relative round-off, and at the corners of unshared
                    // corner blocks the gradient has no limit (the evaluator's choice there differs)
                    if t > 0.0 && t < 1.0 {
                        assert_near!(b.su, a.su, 100.0 * tol, "t={t}");
                        assert_near!(b.sv, a.sv, 100.0 * tol, "t={t}");
                    }
                }
            }
        }
    }
}

/// A four-sided patch (the tensor-product net `grid[row][col]`, rows along side 0's cross
/// direction) in GB form, as in the elevation tests: side 0 is the grid row `d` read left to right.
fn four_sided(grid: &[Vec<DVec3>]) -> GbPatch {
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

#[test]
fn a_g1_pair_of_degrees_3_and_5_stays_g1_at_a_common_degree() {
    // patch A: random bicubic net; patch B: degree 5, sharing A's side 0 reversed, with the
    // opposite cross-derivative (a C1, hence G1, join), the rest random.
    let mut r = Rng::new(77);
    let a_grid: Vec<Vec<DVec3>> = (0..=3).map(|_| (0..=3).map(|_| r.v()).collect()).collect();
    let boundary = BezierCurve::new(a_grid[3].clone()).unwrap();
    let cross = BezierCurve::new(
        (0..=3)
            .map(|j| (a_grid[2][j] - a_grid[3][j]) * 3.0)
            .collect(),
    )
    .unwrap();
    let b_bound = boundary.reversed().elevate_by(2).into_points();
    let b_cross = cross.reversed().elevate_by(2).into_points();
    let mut b_grid: Vec<Vec<DVec3>> = (0..=5)
        .map(|_| (0..=5).map(|_| r.v() + DVec3::Z).collect())
        .collect();
    b_grid[5] = b_bound.clone();
    b_grid[4] = (0..=5)
        .map(|j| b_bound[j] - b_cross[j] * (1.0 / 5.0))
        .collect();
    let a = four_sided(&a_grid);
    let b = four_sided(&b_grid);
    let dom = Domain::regular(4).unwrap();
    let check = |a: &GbPatch, b: &GbPatch| -> (f64, f64) {
        let (mut gap, mut angle) = (0.0f64, 0.0f64);
        for t in side_ts()
            .into_iter()
            .map(|(t, _)| t)
            .filter(|t| *t > 0.0 && *t < 1.0)
        {
            let pa = a.eval_derivs(dom.side_point(0, t), WeightForm::Squared);
            let pb = b.eval_derivs(dom.side_point(0, 1.0 - t), WeightForm::Squared);
            gap = gap.max(pa.p.distance(pb.p));
            let (na, nb) = (pa.normal().unwrap(), pb.normal().unwrap());
            angle = angle.max(na.cross(nb).length()).max((na - nb).length());
        }
        (gap, angle)
    };
    let (g0, n0) = check(&a, &b);
    assert!(
        g0 < 1e-12 && n0 < 1e-9,
        "the hand-built pair is G1: gap {g0:e}, normals {n0:e}"
    );
    for target in [5, 6, 8] {
        let out = common_degree(&[a.clone(), b.clone()], target).unwrap();
        assert!(out.iter().all(|p| p.degree() == target));
        let (g, n) = check(&out[0], &out[1]);
        assert!(
            g < 1e-9 && n < 1e-9,
            "degree {target}: gap {g:e}, normals {n:e}"
        );
    }
}

/// Small control meshes built in place: a cube with a pulled, non-planar corner (valence-3
/// vertices: triangular patches), a square pyramid (one valence-4 vertex) and a coarse torus
/// (valence 4 everywhere: four-sided patches).
fn meshes() -> Vec<(&'static str, HalfEdgeMesh)> {
    let v = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
    let cube = PolyMesh::new(
        vec![
            v(0.0, 0.0, 0.0),
            v(1.0, 0.0, 0.0),
            v(1.0, 1.0, 0.0),
            v(0.0, 1.0, 0.0),
            v(0.0, 0.0, 1.0),
            v(1.0, 0.0, 1.0),
            v(1.3, 1.2, 1.4),
            v(0.0, 1.0, 1.0),
        ],
        vec![
            vec![0, 3, 2, 1],
            vec![4, 5, 6, 7],
            vec![0, 1, 5, 4],
            vec![1, 2, 6, 5],
            vec![2, 3, 7, 6],
            vec![3, 0, 4, 7],
        ],
    );
    let pyramid = PolyMesh::new(
        vec![
            v(-1.0, -1.0, 0.0),
            v(1.0, -1.0, 0.0),
            v(1.0, 1.0, 0.0),
            v(-1.0, 1.0, 0.0),
            v(0.1, 0.2, 1.5),
        ],
        vec![
            vec![0, 3, 2, 1],
            vec![0, 1, 4],
            vec![1, 2, 4],
            vec![2, 3, 4],
            vec![3, 0, 4],
        ],
    );
    let torus = torus(6, 4, 2.0, 0.7).unwrap();
    [("cube", cube), ("pyramid", pyramid), ("torus", torus)]
        .into_iter()
        .map(|(name, m)| (name, HalfEdgeMesh::from_polymesh(&m).unwrap()))
        .collect()
}

#[test]
fn constructed_surface_with_mixed_degrees_keeps_its_joins() {
    // dual (GB) surfaces: give the patches degrees 3, 4, 5, 6 in turn, then one common degree;
    // every patch keeps its boundary points and normals (1e-9), so the joins are as before.
    for (name, mesh) in meshes() {
        let s = build_dual(&mesh, &ConvertOptions::triangles_r8()).unwrap();
        let gb: Vec<GbPatch> = s
            .patches
            .iter()
            .map(|p| match p {
                Patch::Gb(g) => g.clone(),
                Patch::Cgb(_) => panic!("{name}: dual surfaces are GB"),
            })
            .collect();
        let mixed: Vec<GbPatch> = gb
            .iter()
            .enumerate()
            .map(|(k, p)| p.elevate_to(3 + k % 4).unwrap())
            .collect();
        let d = max_degree(&mixed);
        assert_eq!(d, 6);
        let common = common_degree(&mixed, d).unwrap();
        let mut worst = (0.0f64, 0.0f64);
        for (p, q) in gb.iter().zip(&common) {
            assert_eq!(q.degree(), 6);
            let dom = Domain::regular(p.n()).unwrap();
            for i in 0..p.n() {
                for t in side_ts()
                    .into_iter()
                    .map(|(t, _)| t)
                    .filter(|t| *t > 0.0 && *t < 1.0)
                {
                    let x = dom.side_point(i, t);
                    let a = p.eval_derivs(x, WeightForm::Squared);
                    let b = q.eval_derivs(x, WeightForm::Squared);
                    worst.0 = worst.0.max(a.p.distance(b.p));
                    worst.1 = worst
                        .1
                        .max((a.normal().unwrap() - b.normal().unwrap()).length());
                }
            }
        }
        assert!(
            worst.0 < 1e-9 && worst.1 < 1e-9,
            "{name}: position {:e}, normal {:e}",
            worst.0,
            worst.1
        );
        let before = join_report(&s, 17, WeightForm::Squared);
        let after_s = Surface {
            patches: common.into_iter().map(Patch::Gb).collect(),
            ..s.clone()
        };
        let after = join_report(&after_s, 17, WeightForm::Squared);
        println!(
            "{name}: joins before angle {:.3e}° gap {:.3e}; after angle {:.3e}° gap {:.3e}",
            before.angle_deg.value, before.gap.value, after.angle_deg.value, after.gap.value
        );
        assert_eq!(after.sides, before.sides);
        assert_eq!(after.degenerate, 0);
        assert!(after.gap.value <= 1e-9, "{name}: gap {:e}", after.gap.value);
        assert!(
            after.angle_deg.value.to_radians() <= 1e-9,
            "{name}: angle {:e}°",
            after.angle_deg.value
        );
    }
}

/// `Surface::with_common_degree` on a whole dual surface: every patch at the target degree, the
/// curve network elevated with it, and the ribbons still meet with the same gap and G1 angle.
#[test]
fn surface_common_degree_keeps_the_joins() {
    use gbsurf::construct::check::{ribbon_g1_angle, ribbon_gap};
    let mesh = gbsurf::mesh::read_mesh(concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/models/cube_corner_pulled.obj")).unwrap();
    let surface = gbsurf::construct::build_dual(&mesh, &gbsurf::ConvertOptions::triangles_r8()).unwrap();
    let elevated = surface.with_common_degree(6).unwrap();
    assert!(elevated.patches.iter().all(|p| p.ribbons().iter().all(|r| r.degree == 6)));
    assert!(elevated.curves.iter().all(|c| c.len() == 7));
    let (g0, a0) = (ribbon_gap(&surface, 17).value, ribbon_g1_angle(&surface, 17).value);
    let (g1, a1) = (ribbon_gap(&elevated, 17).value, ribbon_g1_angle(&elevated, 17).value);
    assert!(g1 <= g0 + 1e-12 && a1 <= a0 + 1e-9, "gap {g0:e} -> {g1:e}, angle {a0:e}° -> {a1:e}°");
    let topo = gbsurf::construct::build_topology(&mesh, &gbsurf::ConvertOptions::triangles_r8()).unwrap();
    assert_eq!(topo.with_common_degree(6).unwrap_err(), gbsurf::gb::decompose::CommonDegreeError::NotGb { patch: 0 });
    assert!(matches!(surface.with_common_degree(2), Err(gbsurf::gb::decompose::CommonDegreeError::AboveTarget { patch: 0, .. })));
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(24))]

    /// Random patches (any seed, n = 3..8, d = 3..7): the terms recompose the patch exactly, and
    /// every displacement term is zero to first order on every other side.
    #[test]
    fn decomposition_properties(seed in 0u64..1_000_000, n in 3usize..=8, d in 3usize..=7, t in 0.0f64..=1.0) {
        let p = random_patch(n, d, seed);
        let dec = decompose(&p).unwrap();
        let q = dec.recompose();
        assert_near!(q.control_points_flat(), p.control_points_flat(), 1e-13);
        let dom = Domain::regular(n).unwrap();
        for (i, term) in dec.displacements.iter().enumerate() {
            for side in (0..n).filter(|&s| s != i) {
                let x = dom.side_point(side, t);
                let dv = term.eval_derivs(x, WeightForm::Squared);
                proptest::prop_assert!(dv.p.length() < 1e-12, "side {side} of term {i}: {}", dv.p);
                proptest::prop_assert!(dv.su.length() + dv.sv.length() < 1e-8, "side {side} of term {i}: gradient");
            }
        }
    }
}

//! Validity checks of the report: folds (a patch made to fold on purpose is found, with its
//! index), self-intersections (within one shell only, exact triangle–triangle tests checked
//! against brute force), the input cage's own intersections, and every shared model converting to
//! a valid surface with both structures; certified intersection-free regions skipped without
//! changing the count, crafted regions violating each condition of the certificate refused.

use gbsurf::api::{convert, convert_file, ConvertOptions, Method};
use gbsurf::construct::{build_dual, Patch};
use gbsurf::gb::{Domain, Evaluate, WeightForm};
use gbsurf::mesh::{HalfEdgeMesh, PolyMesh};
use gbsurf::quality::validity::{max_abs_mean_curvature_times_diagonal, triangles_intersect, MAX_FOLD_SITES};
use gbsurf::quality::certify::certify_region;
use gbsurf::quality::{cage_self_intersections, find_folds, mesh_self_intersections, self_intersections, self_intersections_certified, Certified};
use gbsurf::DVec3;
use gbsurf::tessellate::fold::dense_level;
use proptest::prelude::*;

const MODELS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/models");

fn cube(pulled: Option<DVec3>) -> PolyMesh {
    let mut positions: Vec<DVec3> = (0..8).map(|i| DVec3::new([-1.0, 1.0][i & 1], [-1.0, 1.0][(i >> 1) & 1], [-1.0, 1.0][i >> 2])).collect();
    if let Some(p) = pulled {
        positions[7] = p;
    }
    let faces = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    PolyMesh::new(positions, faces.iter().map(|f| f.to_vec()).collect())
}

/// A closed triangulated box [lo, hi] with its vertices from index `base`.
fn box_tris(lo: DVec3, hi: DVec3, base: u32) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let c = cube(None);
    let pos = c.positions.iter().map(|p| lo + (*p + DVec3::ONE) * 0.5 * (hi - lo)).collect();
    let tris = c.faces.iter().flat_map(|f| [[f[0], f[1], f[2]], [f[0], f[2], f[3]]]).map(|t| t.map(|i| i + base)).collect();
    (pos, tris)
}

#[test]
fn a_pulled_central_point_folds_its_patch() {
    let he = HalfEdgeMesh::from_polymesh(&cube(None)).unwrap();
    let mut surface = build_dual(&he, &ConvertOptions::triangles_r8()).unwrap();
    let form = WeightForm::Squared;
    assert_eq!(find_folds(&surface, dense_level(8.into()), form).patches, 0);
    let k = 3;
    let Patch::Gb(g) = &mut surface.patches[k] else { panic!("dual cube patches are GB") };
    // Moving the central point along the normal cannot fold (the normal component of S_u × S_v
    // does not change); pulled far sideways, its weight's slope turns the Jacobian over.
    let d = Domain::regular(g.ribbons.len()).unwrap();
    let n = g.normal(d.center(), form).unwrap();
    let t = g.eval_derivs(d.center(), form).su.normalize();
    g.center += 40.0 * t;
    let folds = find_folds(&surface, dense_level(8.into()), form);
    assert_eq!(folds.patches, 1, "{folds:?}");
    assert!(folds.samples > 0);
    assert_eq!(folds.sites.len(), 1);
    assert_eq!(folds.sites[0].patch, k);
    // The worst sample lies in the domain and the patch's Jacobian there points inward.
    let site = &folds.sites[0];
    let uv = gbsurf::DVec2::new(site.u, site.v);
    assert!(uv.length() < 1.0 + 1e-9);
    assert!(surface.patches[k].normal(uv, form).unwrap().dot(n) < 0.0);
    // Pulled along the normal, far through the surface: a deep dimple, no fold.
    let mut dimple = build_dual(&he, &ConvertOptions::triangles_r8()).unwrap();
    let Patch::Gb(g) = &mut dimple.patches[k] else { panic!("GB") };
    g.center -= 40.0 * n;
    assert_eq!(find_folds(&dimple, dense_level(8.into()), form).patches, 0);
}

#[test]
fn fold_sites_are_listed_in_patch_order() {
    let mesh = cube(None);
    let he = HalfEdgeMesh::from_polymesh(&mesh).unwrap();
    let mut surface = build_dual(&he, &ConvertOptions::triangles_r8()).unwrap();
    let form = WeightForm::Squared;
    for p in surface.patches.iter_mut() {
        let Patch::Gb(g) = p else { panic!("GB patch expected") };
        let d = Domain::regular(g.ribbons.len()).unwrap();
        let t = g.eval_derivs(d.center(), form).su.normalize();
        g.center += 40.0 * t;
    }
    let folds = find_folds(&surface, dense_level(8.into()), form);
    assert_eq!(folds.patches, surface.patches.len());
    assert_eq!(folds.sites.len(), surface.patches.len().min(MAX_FOLD_SITES));
    assert!(folds.sites.iter().enumerate().all(|(i, s)| s.patch == i));
}

#[test]
fn crossing_shells_do_not_count_one_shell_does() {
    let (mut pos, mut tris) = box_tris(DVec3::splat(-1.0), DVec3::splat(1.0), 0);
    let (p2, t2) = box_tris(DVec3::new(0.0, -0.5, -0.5), DVec3::new(2.0, 0.5, 0.5), 8);
    pos.extend(p2);
    tris.extend(t2);
    // Two separate shells crossing each other.
    assert_eq!(self_intersections(&pos, &tris), 0);
    // Tied into one shell by a sliver triangle sharing a vertex with each box, far from the
    // crossing: now the crossing pairs count.
    tris.push([0, 8, 1]);
    let n = self_intersections(&pos, &tris);
    assert!(n >= 8, "{n}");
    // Each box alone is free of self-intersections.
    let (pos, tris) = box_tris(DVec3::splat(-1.0), DVec3::splat(1.0), 0);
    assert_eq!(self_intersections(&pos, &tris), 0);
}

#[test]
fn exact_triangle_tests() {
    let t = [DVec3::ZERO, DVec3::X, DVec3::Y];
    // Crossing through the interior.
    assert!(triangles_intersect(t, [DVec3::new(0.2, 0.2, -1.0), DVec3::new(0.2, 0.2, 1.0), DVec3::new(5.0, 5.0, 0.0)]));
    // Touching at one point (a vertex on the other's interior).
    assert!(triangles_intersect(t, [DVec3::new(0.25, 0.25, 0.0), DVec3::new(0.2, 0.2, 1.0), DVec3::new(1.0, 1.0, 1.0)]));
    // Just above the plane: disjoint.
    let eps = f64::EPSILON;
    assert!(!triangles_intersect(t, [DVec3::new(0.25, 0.25, eps), DVec3::new(0.2, 0.2, 1.0), DVec3::new(1.0, 1.0, 1.0)]));
    // Coplanar: overlapping, contained, disjoint.
    assert!(triangles_intersect(t, [DVec3::new(0.5, 0.0, 0.0), DVec3::new(1.5, 0.0, 0.0), DVec3::new(0.5, 1.0, 0.0)]));
    assert!(triangles_intersect(t, [DVec3::new(0.1, 0.1, 0.0), DVec3::new(0.2, 0.1, 0.0), DVec3::new(0.1, 0.2, 0.0)]));
    assert!(!triangles_intersect(t, [DVec3::new(1.0, 1.0, 0.0), DVec3::new(2.0, 1.0, 0.0), DVec3::new(1.0, 2.0, 0.0)]));
}

#[test]
fn a_cage_with_a_corner_pulled_through_intersects_itself() {
    assert_eq!(cage_self_intersections(&cube(None)), 0);
    // Corner (1, 1, 1) pulled through the opposite face z = −1.
    let bad = cube(Some(DVec3::new(-0.5, -0.5, -3.0)));
    let n = cage_self_intersections(&bad);
    assert!(n > 0, "{n}");
    // The conversion reports the input's intersections whenever its output has some (the only
    // case in which validity depends on them), whatever it makes of the cage.
    if let Ok(c) = convert(&bad, &ConvertOptions { method: Method::Dual, resolution: 4, ..ConvertOptions::triangles_r8() }, None) {
        let r = &c.report;
        let expected = (r.self_intersections > 0).then_some(n);
        assert_eq!(r.input_self_intersections, expected, "{} output pairs", r.self_intersections);
    }
}

/// The cage is counted exactly when the output self-intersects, and `valid` follows the rule:
/// a torus cage with one vertex pushed through the tube crosses itself, so does its dual
/// surface; the cage's count is then reported and excuses the output's (valid), while the same
/// report with a cage free of intersections is not valid. The plain torus has no
/// self-intersections: its cage is not counted (JSON `null`) and it is valid.
#[test]
fn the_cage_is_counted_exactly_when_the_output_self_intersects() {
    let options = ConvertOptions { method: Method::Dual, resolution: 3, ..Default::default() };
    let plain = gbsurf::mesh::generate::torus(10, 6, 10.0, 3.0).unwrap();
    let mut pushed = plain.clone();
    let c = pushed.positions[0];
    pushed.positions[0] = c - 10.0 * DVec3::new(c.x, c.y, 0.0).normalize();
    let n = cage_self_intersections(&pushed);
    assert!(n > 0, "{n}");
    let r = convert(&pushed, &options, None).unwrap().report;
    assert!(r.self_intersections > 0, "{r:?}");
    assert_eq!(r.input_self_intersections, Some(n));
    assert!(r.valid && r.folds == 0 && r.closed, "{:?}", r.validity_problems());
    let mut clean_cage = r.clone();
    clean_cage.input_self_intersections = Some(0);
    clean_cage.set_valid();
    assert!(!clean_cage.valid);
    let problems = clean_cage.validity_problems();
    assert!(problems.iter().any(|p| p.contains("self-intersecting triangle pairs")), "{problems:?}");
    let mut unchecked = r.clone();
    unchecked.input_self_intersections = None;
    unchecked.set_valid();
    assert!(!unchecked.valid, "an unchecked cage excuses nothing");

    assert_eq!(cage_self_intersections(&plain), 0);
    let r = convert(&plain, &options, None).unwrap().report;
    assert_eq!((r.self_intersections, r.input_self_intersections), (0, None));
    assert!(r.valid, "{:?}", r.validity_problems());
    let json: serde_json::Value = serde_json::from_str(&r.to_json()).unwrap();
    assert_eq!(json.get("input_self_intersections"), Some(&serde_json::Value::Null));
    // The conversion's search (after its mesh check: no degenerate triangle, so no filter pass)
    // counts as the plain search over all pairs, with and without intersections.
    for mesh in [&pushed, &plain] {
        let out = convert(mesh, &options, None).unwrap().mesh;
        let check = gbsurf::quality::check_mesh(&out.positions, &out.triangles);
        assert_eq!((check.bad_indices, check.zero_area_triangles), (0, 0));
        let mut ticker = gbsurf::progress::Ticker::none();
        let fast = gbsurf::quality::validity::mesh_self_intersections_checked(&out, &check, &mut ticker).unwrap();
        assert_eq!(fast, self_intersections(&out.positions, &out.triangles));
    }
    let back: gbsurf::quality::Report = serde_json::from_str(&r.to_json()).unwrap();
    assert_eq!(back.input_self_intersections, None);
}

#[test]
fn folds_where_the_cage_folds_are_attributed_to_the_cage() {
    use gbsurf::quality::validity::cage_fold_vertices;
    // The plain cube has no cage fold. With its corner 7 = (1, 1, 1) pulled inside to
    // (−0.5, −0.5, −0.5), the three faces at 7 turn back at their corners opposite 7 (vertices
    // 1, 2 and 4), and vertex 0, away from the pulled faces, stays unflagged.
    assert!(!cage_fold_vertices(&HalfEdgeMesh::from_polymesh(&cube(None)).unwrap()).iter().any(|&b| b));
    let bad = cube(Some(DVec3::new(-0.5, -0.5, -0.5)));
    let flags = cage_fold_vertices(&HalfEdgeMesh::from_polymesh(&bad).unwrap());
    let at: Vec<usize> = (0..8).filter(|&v| flags[v]).collect();
    assert!(!at.is_empty() && !at.contains(&0), "{at:?}");
    for method in [Method::Dual, Method::Topology] {
        let Ok(c) = convert(&bad, &ConvertOptions { method, ..Default::default() }, None) else { continue };
        if c.report.folds == 0 {
            continue;
        }
        let w = c.warnings.iter().find(|w| w.contains("where the cage itself turns back")).unwrap_or_else(|| panic!("{method}: {:?}", c.warnings));
        assert!(w.contains(&format!("of the {} folded patches", c.report.folds)), "{w}");
        println!("{method}: {w}");
    }
    // A surface without folds says nothing of the kind.
    let c = convert(&cube(None), &ConvertOptions::default(), None).unwrap();
    assert!(!c.warnings.iter().any(|w| w.contains("cage itself turns back")), "{:?}", c.warnings);
}

#[test]
fn every_shared_model_is_valid_with_both_structures() {
    let mut models: Vec<_> = std::fs::read_dir(MODELS)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "obj"))
        .collect();
    models.sort();
    assert!(models.len() >= 10);
    for path in &models {
        for method in [Method::Dual, Method::Topology] {
            let c = convert_file(path, &ConvertOptions { method, ..ConvertOptions::triangles_r8() }, None).unwrap();
            let r = &c.report;
            assert!(r.valid, "{} {method}: {:?}", path.display(), r.validity_problems());
            assert_eq!((r.folds, r.self_intersections, r.input_self_intersections), (0, 0, None), "{}", path.display());
            assert!(r.max_abs_mean_curvature_times_diagonal.is_finite() && r.max_abs_mean_curvature_times_diagonal > 0.0);
            let json: serde_json::Value = serde_json::from_str(&r.to_json()).unwrap();
            for key in ["folds", "fold_sites", "self_intersections", "input_self_intersections", "max_abs_mean_curvature_times_diagonal", "valid", "closed", "max_g1_deg"] {
                assert!(json.get(key).is_some(), "{key}");
            }
        }
    }
}

/// Blender's default cone (32 vertices, radius 1, depth 2): the topology structure's base cap
/// turns by about 116° from its rim, where its ribbons lean outwards and up, to its flat centre
/// facing down. The mean of the ribbons' normals points up there, and every sample near the
/// centre used to be counted as folded against it; the cap's vector area points down
/// (docs/math.md#fold-centre). The 8-sided cone of height 1 is the same case. Both structures stay
/// valid, at the default layout and at triangles r = 8.
#[test]
fn a_cone_whose_base_cap_turns_more_than_a_right_angle_is_valid() {
    for (n, height) in [(32, 2.0), (8, 1.0)] {
        let base = gbsurf::mesh::generate::cone(n).unwrap();
        let positions: Vec<DVec3> = base.positions.iter().map(|p| DVec3::new(p.x, p.y, p.z * height)).collect();
        let cone = PolyMesh::new(positions, base.faces.clone());
        for method in [Method::Dual, Method::Topology] {
            for opts in [ConvertOptions::default(), ConvertOptions::triangles_r8()] {
                let c = convert(&cone, &ConvertOptions { method, ..opts }, None).unwrap();
                let r = &c.report;
                assert!(r.valid, "cone {n} {method}: {:?}", r.validity_problems());
                assert_eq!(r.folds, 0, "cone {n} {method}");
                let dense = find_folds(c.surface.as_ref().unwrap(), 40, WeightForm::default());
                assert_eq!(dense.patches, 0, "cone {n} {method} at level 40");
            }
        }
    }
}

#[test]
fn curvature_times_diagonal_of_a_sphere_sample() {
    // Unit sphere points with H = −1 everywhere: |H| × diagonal = 2√3.
    let pos = [DVec3::splat(-1.0), DVec3::splat(1.0)];
    let v = max_abs_mean_curvature_times_diagonal(&pos, &[-1.0, -1.0]);
    assert!((v - 2.0 * 3f64.sqrt()).abs() < 1e-12);
    assert_eq!(max_abs_mean_curvature_times_diagonal(&[], &[]), 0.0);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    /// The BVH-pruned count equals a brute-force count over all pairs of one shell.
    #[test]
    fn bvh_count_matches_brute_force(coords in proptest::collection::vec(-4i32..4, 3 * 24), tris in proptest::collection::vec(proptest::array::uniform3(0u32..24), 1..30)) {
        let pos: Vec<DVec3> = coords.chunks(3).map(|c| DVec3::new(c[0] as f64, c[1] as f64, c[2] as f64) * 0.5).collect();
        // One shell: chain every triangle to the next through a shared vertex.
        let mut all = tris.clone();
        for w in tris.windows(2) {
            all.push([w[0][0], w[1][0], w[0][1]]);
        }
        let good = |t: &[u32; 3]| {
            let [a, b, c] = t.map(|i| pos[i as usize]);
            (b - a).cross(c - a) != DVec3::ZERO
        };
        // Brute force over good triangles; shells by union–find over all triangles used.
        let kept: Vec<[u32; 3]> = all.iter().copied().filter(good).collect();
        let mut parent: Vec<usize> = (0..24).collect();
        fn find(p: &mut Vec<usize>, x: usize) -> usize { if p[x] == x { x } else { let r = find(p, p[x]); p[x] = r; r } }
        for t in &kept {
            for &v in &t[1..] {
                let (a, b) = (find(&mut parent, t[0] as usize), find(&mut parent, v as usize));
                parent[a] = b;
            }
        }
        let mut brute = 0;
        for i in 0..all.len() {
            for j in i + 1..all.len() {
                let (a, b) = (all[i], all[j]);
                if !good(&a) || !good(&b) || a.iter().any(|v| b.contains(v)) {
                    continue;
                }
                if find(&mut parent, a[0] as usize) != find(&mut parent, b[0] as usize) {
                    continue;
                }
                if triangles_intersect(a.map(|v| pos[v as usize]), b.map(|v| pos[v as usize])) {
                    brute += 1;
                }
            }
        }
        prop_assert_eq!(self_intersections(&pos, &all), brute);
    }

    /// The exact test is symmetric and invariant under cyclic vertex order and reflection.
    #[test]
    fn triangle_test_is_symmetric(c in proptest::collection::vec(-3i32..3, 18)) {
        let p: Vec<DVec3> = c.chunks(3).map(|c| DVec3::new(c[0] as f64, c[1] as f64, c[2] as f64)).collect();
        let (a, b) = ([p[0], p[1], p[2]], [p[3], p[4], p[5]]);
        prop_assume!((a[1] - a[0]).cross(a[2] - a[0]) != DVec3::ZERO && (b[1] - b[0]).cross(b[2] - b[0]) != DVec3::ZERO);
        let x = triangles_intersect(a, b);
        prop_assert_eq!(x, triangles_intersect(b, a));
        prop_assert_eq!(x, triangles_intersect([a[1], a[2], a[0]], [b[2], b[1], b[0]]));
        let m = |t: [DVec3; 3]| t.map(|v| DVec3::new(-v.x, v.y, v.z));
        prop_assert_eq!(x, triangles_intersect(m(a), m(b)));
    }
}

/// Dual construction of `mesh` with its patches edited by `edit`.
fn edited_dual(mesh: &PolyMesh, edit: impl Fn(&mut gbsurf::gb::GbPatch)) -> gbsurf::construct::Surface {
    let he = HalfEdgeMesh::from_polymesh(mesh).unwrap();
    let mut surface = build_dual(&he, &ConvertOptions::triangles_r8()).unwrap();
    for p in surface.patches.iter_mut() {
        let Patch::Gb(g) = p else { panic!("dual patches are GB") };
        edit(g);
    }
    surface
}

/// The patches the tessellation pass finds folded, and those the dense check finds.
fn in_pass_and_dense(surface: &gbsurf::construct::Surface) -> (Vec<usize>, Vec<usize>, gbsurf::tessellate::SurfaceMesh) {
    let form = WeightForm::Squared;
    let (m, _) = gbsurf::tessellate::tessellate_surface(surface, 8, form, None).unwrap();
    let in_pass: Vec<usize> = m.patch_folds.iter().enumerate().filter(|(_, f)| f.samples > 0).map(|(p, _)| p).collect();
    let dense = find_folds(surface, dense_level(8.into()), form);
    let dense_patches: Vec<usize> = (0..surface.patches.len())
        .filter(|&p| {
            let mut one = surface.clone();
            one.patches = vec![surface.patches[p].clone()];
            one.neighbors = vec![vec![None; surface.patches[p].sides()]];
            find_folds(&one, dense_level(8.into()), form).patches > 0
        })
        .collect();
    assert_eq!(dense.patches, dense_patches.len());
    (in_pass, dense_patches, m)
}

#[test]
fn the_tessellation_pass_finds_the_folds_of_the_dense_check() {
    let form = WeightForm::Squared;
    // Every patch of the cube pulled sideways (as above), and one patch only.
    let pulled = |g: &mut gbsurf::gb::GbPatch| {
        let d = Domain::regular(g.ribbons.len()).unwrap();
        let t = g.eval_derivs(d.center(), form).su.normalize();
        g.center += 40.0 * t;
    };
    let all = edited_dual(&cube(None), pulled);
    let (in_pass, dense, m) = in_pass_and_dense(&all);
    assert_eq!(in_pass, dense);
    assert_eq!(in_pass.len(), all.patches.len());
    assert!(m.fold.iter().any(|&f| f == 1));
    assert_eq!(m.fold.len(), m.positions.len());
    // The report of a conversion counts what the pass found, with sites in patch order.
    let folds = gbsurf::quality::Folds::of_tessellation(&m);
    assert_eq!(folds.patches, all.patches.len());
    assert!(folds.sites.iter().enumerate().all(|(i, s)| s.patch == i));
    // An unedited surface: nothing folded, no vertex flagged.
    let plain = edited_dual(&cube(None), |_| {});
    let (in_pass, dense, m) = in_pass_and_dense(&plain);
    assert!(in_pass.is_empty() && dense.is_empty());
    assert!(m.fold.iter().all(|&f| f == 0));
    // Its samples clear every patch (docs/math.md#fold-clearing): no dense pass ran.
    assert!(m.patch_folds.iter().all(|f| !f.dense));
    assert!(m.flipped_triangles.is_empty());
}

#[test]
fn a_quad_torus_ignores_its_central_points_but_folds_with_its_ribbons() {
    // The finding behind the "dual 8×6 torus with pulled central points has no folds" report:
    // on four-sided GB patches of odd degree the ribbons' layers cover the whole control net, so
    // the central control point has weight 0 everywhere. Pulling it changes nothing, and 0 folds
    // is right.
    let form = WeightForm::Squared;
    let torus = gbsurf::mesh::generate::torus(8, 6, 10.0, 3.0).unwrap();
    let plain = edited_dual(&torus, |_| {});
    let pulled = edited_dual(&torus, |g| {
        let d = Domain::regular(g.ribbons.len()).unwrap();
        g.center += 16.0 * g.eval_derivs(d.center(), form).su;
    });
    let (a, _) = gbsurf::tessellate::tessellate_surface(&plain, 8, form, None).unwrap();
    let (b, _) = gbsurf::tessellate::tessellate_surface(&pulled, 8, form, None).unwrap();
    // (Up to rounding: the weight is 1 − Σ ribbon weights, 0 up to a few ulps.)
    let moved = a.positions.iter().zip(&b.positions).map(|(p, q)| p.distance(*q)).fold(0.0, f64::max);
    assert!(moved < 1e-9, "the central point has no weight on these patches: moved {moved}");
    assert!(b.fold.iter().all(|&f| f == 0));
    // Pulling the inner row of one ribbon per patch sideways does fold them, and both checks
    // see it on the same patches.
    let ribbon_pulled = edited_dual(&torus, |g| {
        let d = Domain::regular(g.ribbons.len()).unwrap();
        let su = g.eval_derivs(d.center(), form).su;
        let row = g.ribbons[0].row_mut(1);
        let last = row.len() - 1;
        for p in &mut row[1..last] {
            *p += 2.0 * su;
        }
    });
    let (in_pass, dense, m) = in_pass_and_dense(&ribbon_pulled);
    assert_eq!(in_pass, dense);
    // 4 of the 48 with the neighbour condition (docs/math.md#fold-neighbours; 34 with the blended
    // reference alone, whose second clause counted patches turned more than 90° against the frame
    // their ribbons give them without turning over; the side's own reference flagged all 48). The
    // reference sampler (neighbouring normals on 60 steps) sees the Jacobian change sign in patch
    // 1 only; the other 3 have neighbouring normals reversed at the dense pass's 16 steps. No
    // patch that turns over is missed.
    let flips: Vec<usize> =
        (0..ribbon_pulled.patches.len()).filter(|&p| fine::neighbour_normals(&ribbon_pulled.patches[p], form, 60).0 < 0.0).collect();
    assert_eq!(flips, vec![1]);
    assert!(flips.iter().all(|p| in_pass.contains(p)), "{flips:?} {in_pass:?}");
    assert_eq!(in_pass.len(), 4, "{in_pass:?}");
    assert!(m.fold.iter().filter(|&&f| f == 1).count() > 4);
}

#[test]
fn flipped_triangles_are_found() {
    use gbsurf::tessellate::fold::flipped_triangles;
    let pos = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(1.0, 1.0, 0.0)];
    let up = [DVec3::Z; 4];
    // Counter-clockwise seen from +z agrees with the normals; the reversed one opposes them.
    let tris = [[0, 1, 2], [1, 3, 2], [0, 2, 1]];
    assert_eq!(flipped_triangles(&pos, &up, &tris), vec![2]);
    // A vertex without a normal, or one normal agreeing: not flipped.
    let mut some = up;
    some[0] = DVec3::ZERO;
    assert!(flipped_triangles(&pos, &some, &[[0, 2, 1]]).is_empty());
    some[0] = -DVec3::Z;
    assert!(flipped_triangles(&pos, &some, &[[0, 2, 1]]).is_empty());
}

#[test]
fn ribbon_normal_is_the_ribbon_frame_normal() {
    use gbsurf::construct::check::ribbon_frame;
    use gbsurf::tessellate::fold::ribbon_normal;
    for method in [Method::Dual, Method::Topology] {
        let he = HalfEdgeMesh::from_polymesh(&cube(Some(DVec3::new(1.5, 1.2, 0.9)))).unwrap();
        let opts = ConvertOptions { method, ..ConvertOptions::triangles_r8() };
        let surface = if method == Method::Dual { build_dual(&he, &opts) } else { gbsurf::construct::build_topology(&he, &opts) }.unwrap();
        for p in &surface.patches {
            for r in p.ribbons() {
                for k in 0..=16 {
                    let s = k as f64 / 16.0;
                    let (_, t, x) = ribbon_frame(r, s);
                    let want = t.cross(x).normalize();
                    let got = ribbon_normal(r, s);
                    assert!((got - want).length() < 1e-12, "{method} s = {s}: {got} vs {want}");
                }
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]
    /// Where the floating-point filter decides an orientation, it is the exact one.
    #[test]
    fn the_orientation_filter_agrees_with_the_exact_predicate(
        c in proptest::collection::vec(-1.0e3f64..1.0e3, 9),
        t in proptest::collection::vec(-1.0f64..2.0, 2),
        h in prop_oneof![Just(0.0), -1e-12f64..1e-12, -1.0f64..1.0],
        scale in prop_oneof![Just(1.0), Just(1e-150), Just(1e150)],
    ) {
        use gbsurf::quality::validity::orient_filtered;
        let p = |i: usize| DVec3::new(c[3 * i], c[3 * i + 1], c[3 * i + 2]) * scale;
        let (a, b, cc) = (p(0), p(1), p(2));
        // A point near the plane (in it for h = 0, up to rounding), often on the exact boundary.
        let n = (b - a).cross(cc - a);
        let d = a + t[0] * (b - a) + t[1] * (cc - a) + h * scale * n.normalize_or_zero();
        let exact = robust::orient3d(
            robust::Coord3D { x: a.x, y: a.y, z: a.z },
            robust::Coord3D { x: b.x, y: b.y, z: b.z },
            robust::Coord3D { x: cc.x, y: cc.y, z: cc.z },
            robust::Coord3D { x: d.x, y: d.y, z: d.z },
        );
        // robust::orient3d is positive when d lies below the plane: the opposite sign.
        let sign = (exact < 0.0) as i8 - (exact > 0.0) as i8;
        if let Some(s) = orient_filtered(a, b, cc, d) {
            prop_assert_eq!(s, sign);
        }
    }

    /// The filtered triangle test equals the exact one.
    #[test]
    fn filtered_triangle_test_equals_exact(c in proptest::collection::vec(-3i32..3, 18), e in -1e-9f64..1e-9) {
        use gbsurf::quality::validity::triangles_intersect_exact;
        let mut p: Vec<DVec3> = c.chunks(3).map(|c| DVec3::new(c[0] as f64, c[1] as f64, c[2] as f64)).collect();
        // One vertex nudged off the lattice: near-coplanar and near-touching cases.
        p[3].z += e;
        let (a, b) = ([p[0], p[1], p[2]], [p[3], p[4], p[5]]);
        prop_assume!((a[1] - a[0]).cross(a[2] - a[0]) != DVec3::ZERO && (b[1] - b[0]).cross(b[2] - b[0]) != DVec3::ZERO);
        prop_assert_eq!(triangles_intersect(a, b), triangles_intersect_exact(a, b));
    }
}

/// Many triangles (several chunks of the coarse search): the count still equals brute force.
#[test]
fn chunked_search_matches_brute_force_on_a_crumpled_grid() {
    // A 20 × 20 grid of quads, z crumpled so that far-apart triangles cross.
    let n = 20usize;
    let pos: Vec<DVec3> = (0..=n)
        .flat_map(|i| (0..=n).map(move |j| DVec3::new(i as f64 * 0.1, j as f64 * 0.1, ((i * 7 + j * 13) % 5) as f64 * 0.4 - 0.8)))
        .map(|p| DVec3::new(p.x + 0.6 * (p.z * 3.0).sin(), p.y, p.z))
        .collect();
    let id = |i: usize, j: usize| (i * (n + 1) + j) as u32;
    let mut tris = Vec::new();
    for i in 0..n {
        for j in 0..n {
            tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let mut brute = 0;
    for a in 0..tris.len() {
        for b in a + 1..tris.len() {
            let (x, y) = (tris[a], tris[b]);
            if x.iter().any(|v| y.contains(v)) {
                continue;
            }
            if triangles_intersect(x.map(|v| pos[v as usize]), y.map(|v| pos[v as usize])) {
                brute += 1;
            }
        }
    }
    assert!(brute > 0);
    assert_eq!(self_intersections(&pos, &tris), brute);
}

/// The reference normal of the fold test is undefined (zero) where the ribbon frame degenerates
/// (T ∥ X up to rounding, as at the end of a sharp crease), so rounding noise cannot report a
/// fold; a proper frame gives the unit normal.
#[test]
fn reference_normal_is_undefined_for_a_degenerate_frame() {
    use gbsurf::tessellate::fold::reference_normal;
    let t = DVec3::new(1.0, -1.0, 0.0);
    assert_eq!(reference_normal(t, -t), DVec3::ZERO);
    assert_eq!(reference_normal(t, t * 3.0 + DVec3::new(0.0, 0.0, 1e-15)), DVec3::ZERO);
    assert_eq!(reference_normal(DVec3::ZERO, t), DVec3::ZERO);
    let n = reference_normal(DVec3::X * 2.0, DVec3::Y * 0.5);
    assert!((n - DVec3::Z).length() < 1e-15);
}

/// Pairs of triangles sharing no vertex that meet, by trying every pair (one shell assumed).
fn brute_force(pos: &[DVec3], tris: &[[u32; 3]]) -> usize {
    let mut n = 0;
    for a in 0..tris.len() {
        for b in a + 1..tris.len() {
            let (x, y) = (tris[a], tris[b]);
            if !x.iter().any(|v| y.contains(v)) && triangles_intersect(x.map(|v| pos[v as usize]), y.map(|v| pos[v as usize])) {
                n += 1;
            }
        }
    }
    n
}

/// The count with the certificates of a tessellation equals the count without them.
fn same_with_certificates(m: &gbsurf::tessellate::SurfaceMesh) -> (usize, Certified) {
    let cert = Certified::of_mesh(m);
    let with = self_intersections_certified(&m.positions, &m.triangles, &cert);
    assert_eq!(with, self_intersections(&m.positions, &m.triangles));
    assert_eq!(with, mesh_self_intersections(m));
    (with, cert)
}

#[test]
fn certificates_keep_the_count_on_folded_surfaces() {
    let form = WeightForm::Squared;
    // Every patch of the cube pulled sideways (folded, crossing), and one patch only.
    let pull = |g: &mut gbsurf::gb::GbPatch| {
        let d = Domain::regular(g.ribbons.len()).unwrap();
        let t = g.eval_derivs(d.center(), form).su.normalize();
        g.center += 40.0 * t;
    };
    let all = edited_dual(&cube(None), pull);
    let (m, _) = gbsurf::tessellate::tessellate_surface(&all, 4, form, None).unwrap();
    let (n, _) = same_with_certificates(&m);
    assert!(n > 0, "the pulled cube crosses itself");
    assert_eq!(n, brute_force(&m.positions, &m.triangles));
    // A torus with the inner rows of one ribbon per patch pulled sideways (folds everywhere).
    let torus = gbsurf::mesh::generate::torus(8, 6, 10.0, 3.0).unwrap();
    let crumpled = edited_dual(&torus, |g| {
        let d = Domain::regular(g.ribbons.len()).unwrap();
        let su = g.eval_derivs(d.center(), form).su;
        let row = g.ribbons[0].row_mut(1);
        let last = row.len() - 1;
        for p in &mut row[1..last] {
            *p += 6.0 * su;
        }
    });
    let (m, _) = gbsurf::tessellate::tessellate_surface(&crumpled, 4, form, None).unwrap();
    let (n, _) = same_with_certificates(&m);
    assert!(n > 0, "the crumpled torus crosses itself");
}

#[test]
fn certificates_keep_the_count_on_a_jittered_torus_against_brute_force() {
    // One cage vertex pushed through the tube: intersections near it, certified stars elsewhere.
    let mut torus = gbsurf::mesh::generate::torus(10, 6, 10.0, 3.0).unwrap();
    let c = torus.positions[0];
    torus.positions[0] = c - 10.0 * DVec3::new(c.x, c.y, 0.0).normalize();
    let c = convert(&torus, &ConvertOptions { method: Method::Dual, resolution: 3, ..ConvertOptions::triangles_r8() }, None).unwrap();
    let m = &c.mesh;
    let (n, cert) = same_with_certificates(m);
    assert_eq!(c.report.self_intersections, n);
    assert_eq!(n, brute_force(&m.positions, &m.triangles));
    assert!(n > 0, "the pushed vertex makes the surface cross itself");
    assert!(cert.certified_patches() > 0 && cert.certified_patches() < cert.patches(), "{} of {}", cert.certified_patches(), cert.patches());
}

#[test]
fn the_count_does_not_depend_on_the_order_of_the_cage_faces() {
    // The search groups triangles into chunks by patch (with certificates) or by Morton order
    // (without): faces listed in no spatial order (as in many cage files) give the same counts.
    let mut torus = gbsurf::mesh::generate::torus(10, 6, 10.0, 3.0).unwrap();
    let c = torus.positions[0];
    torus.positions[0] = c - 10.0 * DVec3::new(c.x, c.y, 0.0).normalize();
    let mut shuffled = torus.clone();
    let nf = torus.faces.len();
    // A fixed permutation that scatters neighbours: k -> 37 k mod nf (37 is prime to nf = 60).
    shuffled.faces = (0..nf).map(|k| torus.faces[37 * k % nf].clone()).collect();
    assert_eq!(cage_self_intersections(&shuffled), cage_self_intersections(&torus));
    for method in [Method::Dual, Method::Topology] {
        let options = ConvertOptions { method, resolution: 3, ..Default::default() };
        let (a, b) = (convert(&torus, &options, None).unwrap(), convert(&shuffled, &options, None).unwrap());
        if method == Method::Dual {
            assert!(a.report.self_intersections > 0, "the pushed vertex makes the dual surface cross itself");
        }
        assert_eq!(a.report.self_intersections, b.report.self_intersections, "{method}");
        assert_eq!(b.report.self_intersections, brute_force(&b.mesh.positions, &b.mesh.triangles), "{method}");
        let (n, _) = same_with_certificates(&b.mesh);
        assert_eq!(n, b.report.self_intersections, "{method}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]
    /// Jittered cages, both structures: the report's count (with certificates) is the count of
    /// every pair.
    #[test]
    fn certificates_keep_the_count_on_jittered_cages(
        jitter in proptest::collection::vec(-1.0f64..1.0, 72),
        amp in prop_oneof![Just(0.3), Just(2.5)],
        topology in any::<bool>(),
    ) {
        let mut torus = gbsurf::mesh::generate::torus(6, 4, 4.0, 1.5).unwrap();
        for (k, p) in torus.positions.iter_mut().enumerate() {
            *p += amp * DVec3::new(jitter[3 * k], jitter[3 * k + 1], jitter[3 * k + 2]);
        }
        let method = if topology { Method::Topology } else { Method::Dual };
        if let Ok(c) = convert(&torus, &ConvertOptions { method, resolution: 3, ..ConvertOptions::triangles_r8() }, None) {
            prop_assert_eq!(c.report.self_intersections, self_intersections(&c.mesh.positions, &c.mesh.triangles));
        }
    }
}

#[test]
fn most_patches_of_smooth_surfaces_lie_in_a_certified_star() {
    for method in [Method::Dual, Method::Topology] {
        let torus = gbsurf::mesh::generate::torus(16, 8, 10.0, 3.0).unwrap();
        let c = convert(&torus, &ConvertOptions { method, resolution: 8, ..ConvertOptions::triangles_r8() }, None).unwrap();
        let (n, cert) = same_with_certificates(&c.mesh);
        assert_eq!(n, 0);
        assert_eq!(cert.patches(), c.report.patches);
        assert!(cert.certified_patches() * 10 >= cert.patches() * 9, "{method}: {} of {}", cert.certified_patches(), cert.patches());
    }
    // The smooth shared models: every patch. (Cube-like cages have stars whose normals spread
    // beyond a half space: the star of a cube corner is not certified.)
    for name in ["torus.obj", "dodecahedron.obj"] {
        let c = convert_file(format!("{MODELS}/{name}"), &ConvertOptions::triangles_r8(), None).unwrap();
        let cert = Certified::of_mesh(&c.mesh);
        assert_eq!(cert.certified_patches(), cert.patches(), "{name}");
    }
}

/// A fan of triangles (q = vertex 0, rim vertices 1..=k at `rim`), triangle i = (0, i, i + 1),
/// closed when `closed`.
fn fan(rim: &[DVec3], closed: bool) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let mut pos = vec![DVec3::ZERO];
    pos.extend_from_slice(rim);
    let k = rim.len() as u32;
    let tris = (1..=k).filter(|&i| closed || i < k).map(|i| [0, i, if i == k { 1 } else { i + 1 }]).collect();
    (pos, tris)
}

fn circle(k: usize, turns: f64, radius: impl Fn(usize) -> f64, z: impl Fn(usize) -> f64) -> Vec<DVec3> {
    (0..k)
        .map(|i| {
            let t = std::f64::consts::TAU * turns * i as f64 / k as f64;
            DVec3::new(radius(i) * t.cos(), radius(i) * t.sin(), z(i))
        })
        .collect()
}

#[test]
fn crafted_regions_violating_a_condition_are_not_certified() {
    // A bumpy closed fan around q: certified.
    let (pos, tris) = fan(&circle(7, 1.0, |i| 1.0 + 0.1 * i as f64, |i| 0.2 * (i % 2) as f64), true);
    assert!(certify_region(&pos, &tris, 0));
    // The same with q not a vertex inside: not certified around a rim vertex.
    assert!(!certify_region(&pos, &tris, 1));
    // Normal flip: one triangle turned over.
    let mut flipped = tris.clone();
    flipped[2].swap(1, 2);
    assert!(!certify_region(&pos, &flipped, 0));
    // A rim vertex pulled across its neighbour's spoke: that triangle's normal points down.
    let mut folded = pos.clone();
    folded[3] = DVec3::new(folded[2].x * 1.5, folded[2].y * 1.5 - 0.3, 0.0);
    if (folded[3] - folded[0]).cross(folded[4] - folded[0]).z < 0.0 || (folded[2] - folded[0]).cross(folded[3] - folded[0]).z < 0.0 {
        assert!(!certify_region(&folded, &tris, 0));
    }
    // Double winding: the rim goes twice around q (distinct vertices, every triangle
    // counter-clockwise and facing up), so the region overlaps itself (its triangles all share
    // q, but a region built the same way from larger pieces would cross).
    let (pos, tris) = fan(&circle(14, 2.0, |i| if i < 7 { 1.0 } else { 2.0 }, |_| 0.0), true);
    assert!(tris.iter().all(|t| (pos[t[1] as usize] - pos[t[0] as usize]).cross(pos[t[2] as usize] - pos[t[0] as usize]).z > 0.0));
    assert!(!certify_region(&pos, &tris, 0));
    // A loop through q: an open fan (a half disc) whose boundary passes through q.
    let (pos, tris) = fan(&circle(5, 0.5, |_| 1.0, |_| 0.0), false);
    assert!(!certify_region(&pos, &tris, 0));
    // A degenerate triangle (a rim vertex on q's spoke line at q): not certified.
    let (mut pos, tris) = fan(&circle(6, 1.0, |_| 1.0, |_| 0.0), true);
    pos[1] = DVec3::ZERO;
    assert!(!certify_region(&pos, &tris, 0));
    // Two loops: two disjoint fans around two centres.
    let (p1, t1) = fan(&circle(6, 1.0, |_| 1.0, |_| 0.0), true);
    let (p2, t2) = fan(&circle(6, 1.0, |_| 1.0, |_| 1.0), true);
    let mut pos = p1;
    pos.extend(p2.iter().map(|p| *p + DVec3::new(5.0, 0.0, 0.0)));
    let mut tris = t1;
    tris.extend(t2.iter().map(|t| t.map(|v| v + 7)));
    assert!(!certify_region(&pos, &tris, 0));
}

/// Every folded patch of a report has a site, also a patch folded only through flipped triangles
/// (the thin three-sided vertex patches of a cone over a 300-gon, dual structure; the 200-gon's
/// stopped folding when their central points were fitted, docs/math.md#centre-fit).
#[test]
fn every_folded_patch_gets_a_site() {
    let cone = gbsurf::mesh::generate::cone(300).unwrap();
    let opts = gbsurf::api::ConvertOptions { method: gbsurf::api::Method::Dual, resolution: 4, ..ConvertOptions::triangles_r8() };
    let c = gbsurf::api::convert(&cone, &opts, None).unwrap();
    assert!(c.report.folds > 0 && !c.report.valid, "{} folds", c.report.folds);
    assert_eq!(c.report.fold_sites.len(), c.report.folds.min(gbsurf::quality::validity::MAX_FOLD_SITES));
    for s in &c.report.fold_sites {
        assert!(s.u.is_finite() && s.v.is_finite() && s.u.hypot(s.v) <= 1.0 + 1e-12, "{s:?}");
    }
}

/// Closed star-shaped outputs (cube, cone, prism, both structures) are certified by central
/// projection, and their count (0) is the brute-force count; a torus and an open surface are not.
#[test]
fn closed_star_shaped_shells_are_certified_others_are_not() {
    use gbsurf::mesh::generate::{cone, prism, torus};
    use gbsurf::quality::certify::star_shaped_shells;
    let one_shell = |m: &gbsurf::tessellate::SurfaceMesh| star_shaped_shells(&m.positions, &m.triangles, &vec![0; m.triangles.len()]);
    for method in [Method::Dual, Method::Topology] {
        let opts = ConvertOptions { method, ..ConvertOptions::default() };
        for (name, mesh) in [("cube", cube(None)), ("cone", cone(12).unwrap()), ("prism", prism(9).unwrap())] {
            let m = convert(&mesh, &opts, None).unwrap().mesh;
            assert!(one_shell(&m).iter().all(|&x| x), "{method} {name}");
            assert_eq!(brute_force(&m.positions, &m.triangles), 0, "{method} {name}");
            assert_eq!(mesh_self_intersections(&m), 0);
        }
        let t = convert(&torus(8, 6, 3.0, 1.0).unwrap(), &opts, None).unwrap().mesh;
        assert!(one_shell(&t).iter().all(|&x| !x), "{method} torus");
        // The cube without its top face: open.
        let mut open = cube(None);
        open.faces.pop();
        let o = convert(&open, &opts, None).unwrap().mesh;
        assert!(one_shell(&o).iter().all(|&x| !x), "{method} open cube");
    }
}

/// A closed surface winding twice around its centre (degree 2: total solid angle 8π, every
/// triangle positively oriented) is not certified, and the count equals brute force.
#[test]
fn a_closed_surface_winding_twice_around_its_centre_is_not_certified() {
    use gbsurf::quality::certify::star_shaped_shells;
    let m = 7u32; // equator points; angle step 4π/7 < π, one loop around twice
    let mut pos: Vec<DVec3> = (0..m)
        .map(|k| {
            let a = 4.0 * std::f64::consts::PI * k as f64 / m as f64;
            let r = if k % 2 == 0 { 1.0 } else { 1.6 };
            DVec3::new(r * a.cos(), r * a.sin(), 0.1 * k as f64 - 0.3)
        })
        .collect();
    pos.push(DVec3::new(0.0, 0.0, 2.0));
    pos.push(DVec3::new(0.0, 0.0, -2.0));
    let (north, south) = (m, m + 1);
    let mut tris = Vec::new();
    for k in 0..m {
        let j = (k + 1) % m;
        tris.push([k, j, north]);
        tris.push([j, k, south]);
    }
    let cert = star_shaped_shells(&pos, &tris, &vec![0; tris.len()]);
    assert!(cert.iter().all(|&x| !x));
    let brute = brute_force(&pos, &tris);
    assert!(brute > 0);
    assert_eq!(self_intersections(&pos, &tris), brute);
}

/// Around a node of valence 100 whose patches turn by more than 90° (the cap of an open prism of
/// 100 sides in the dual structure) the star is not certified but its core is; the count is the
/// same as without any certificate.
#[test]
fn high_valence_stars_get_certified_cores() {
    use gbsurf::mesh::generate::prism;
    let mut p = prism(100).unwrap();
    p.faces.remove(100); // the bottom cap: open, so no shell certificate applies
    for method in [Method::Dual, Method::Topology] {
        let m = convert(&p, &ConvertOptions { method, ..ConvertOptions::default() }, None).unwrap().mesh;
        let cert = Certified::of_mesh(&m);
        assert!(cert.certified_core_sectors() >= 100 || method == Method::Topology, "{method}: {}", cert.certified_core_sectors());
        let with = self_intersections_certified(&m.positions, &m.triangles, &cert);
        assert_eq!(with, self_intersections(&m.positions, &m.triangles), "{method}");
        assert_eq!(with, mesh_self_intersections(&m));
    }
}

#[path = "../examples/common/fine.rs"]
mod fine;

const OPENSUBDIV: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/opensubdiv");

/// The patches the conversion's report finds folded (folded samples of the tessellation pass or
/// of its dense pass).
fn reported(c: &gbsurf::api::Conversion) -> Vec<usize> {
    c.mesh.patch_folds.iter().enumerate().filter(|(_, f)| f.samples > 0).map(|(p, _)| p).collect()
}

/// Regression (issue 10, docs/math.md#fold-clearing): the report names exactly the patches the
/// reference sampler (neighbouring normals on 60 steps per sector radius, `examples/fold_truth.rs`)
/// sees turn over: the list is that sampler's, measured on all 1088 patches, and each listed patch
/// is checked again here. With the side's own reference and only the tessellation's samples the
/// report named 18 patches, 17 of them bent but not turned over, and missed 24 of the 25 that
/// turned over then. Those 24 (the base ring, [`ROOK_DUAL_BASE_RING`]) no longer turn over since
/// the direction blend is kept on its side of the curve (docs/math.md#blend-side); the one left,
/// 950 (a 6-sided CGB sector of a split crease vertex, docs/math.md#dual-creases), no longer
/// turns over since the smooth surface the sectors start from has its central points fitted
/// (docs/math.md#centre-fit): none is named, and 950's neighbouring normals agree.
#[test]
fn the_rook_dual_report_names_the_patches_that_turn_over() {
    let path = format!("{OPENSUBDIV}/catmark_rook.obj");
    let opts = ConvertOptions { method: Method::Dual, ..Default::default() };
    let c = convert_file(&path, &opts, None).unwrap();
    let got = reported(&c);
    let flipped: Vec<usize> = ROOK_DUAL_FLIPS.to_vec();
    assert_eq!(got, flipped, "reported folded patches");
    assert_eq!(c.report.folds, flipped.len());
    let surface = c.surface.as_ref().unwrap();
    for &p in &flipped {
        let (dot, at, _) = fine::neighbour_normals(&surface.patches[p], opts.weights, 60);
        assert!(dot < 0.0, "patch {p}: neighbouring normals {dot} at {at:?}");
        // The fold flags mark output vertices of the patch.
        let hit = c.mesh.triangles.iter().zip(&c.mesh.triangle_patch).any(|(t, &q)| q as usize == p && t.iter().any(|&v| c.mesh.fold[v as usize] == 1));
        assert!(hit, "patch {p}: no flagged vertex");
    }
    for p in ROOK_DUAL_FORMER_FLIPS {
        let (dot, at, _) = fine::neighbour_normals(&surface.patches[p], opts.weights, 60);
        assert!(dot > 0.0, "patch {p}: neighbouring normals {dot} at {at:?}");
    }
}

/// The rook dual's patches that turn over (`examples/fold_truth.rs`, default options).
const ROOK_DUAL_FLIPS: [usize; 0] = [];

/// The rook dual's patches that turned over before the central points were fitted.
const ROOK_DUAL_FORMER_FLIPS: [usize; 1] = [950];

/// The rook dual's 4-sided base-ring patches that turned over before the direction blend was kept
/// on its side of the curve (docs/math.md#blend-side).
const ROOK_DUAL_BASE_RING: [usize; 24] =
    [0, 22, 45, 68, 90, 113, 136, 158, 181, 204, 226, 249, 272, 294, 317, 340, 362, 385, 408, 430, 453, 476, 498, 521];

/// Regression (issue 10, docs/math.md#blend-side): each base-ring patch's side 1 crosses a cage
/// edge 0.0013 long between two long thin faces; the direction blend's across components were
/// 0.00131 at the start and the middle and 0.0242 at the end, so the interpolating quadratic
/// swung through the curve's tangent for s in about (0.05, 0.45): the cross-derivatives of both
/// patches pointed across the curve the wrong way (−90° instead of +90° from T) and the patches
/// turned over next to the corner (|S_u × S_v| down to 10⁻⁷ of its maximum). Kept on its side,
/// X(s) stays on one side of T along the whole side and no patch of the ring turns over.
#[test]
fn the_rook_dual_base_ring_does_not_turn_over() {
    let path = format!("{OPENSUBDIV}/catmark_rook.obj");
    let opts = ConvertOptions { method: Method::Dual, ..Default::default() };
    let c = convert_file(&path, &opts, None).unwrap();
    let surface = c.surface.as_ref().unwrap();
    let bez = |p: &[DVec3], s: f64| -> DVec3 {
        let mut q = p.to_vec();
        for k in 1..q.len() {
            for j in 0..q.len() - k {
                q[j] = q[j] * (1.0 - s) + q[j + 1] * s;
            }
        }
        q[0]
    };
    for &p in &ROOK_DUAL_BASE_RING {
        assert_eq!(surface.patches[p].sides(), 4, "patch {p}");
        let r = &surface.patches[p].ribbons()[1];
        let (r0, r1) = (r.row(0), r.row(1));
        let tangent = |s: f64| bez(&[r0[1] - r0[0], r0[2] - r0[1], r0[3] - r0[2]], s);
        let cross = |s: f64| bez(r1, s) - bez(r0, s);
        let n_mid = tangent(0.5).cross(cross(0.5)).normalize();
        for k in 0..=40 {
            let s = k as f64 / 40.0;
            let side = tangent(s).cross(cross(s)).normalize().dot(n_mid);
            assert!(side > 0.5, "patch {p} side 1 at s = {s}: cross-derivative turned across the curve ({side})");
        }
        let (dot, at, ratio) = fine::neighbour_normals(&surface.patches[p], opts.weights, 60);
        assert!(dot > 0.0, "patch {p}: neighbouring normals {dot} at {at:?}, |Su x Sv| ratio {ratio:e}");
    }
}

/// The rook's topology structure has no patch that turns over (reference sampler, all 777
/// patches), and its report names none. It used to count 23 folded patches, all bent regularly
/// against the one side's normal; with the blended reference it named one, patch 736, whose normal
/// turned more than 90° away from the blended reference over a region without a Jacobian sign
/// change: a fold by the rule's second clause (docs/math.md#folds). Since the direction blends
/// are kept on their side of the curve (docs/math.md#blend-side; 6 of the rook topology's curves
/// change) no patch bends that far.
#[test]
fn the_rook_topology_report_names_no_patch() {
    let path = format!("{OPENSUBDIV}/catmark_rook.obj");
    let opts = ConvertOptions { method: Method::Topology, ..Default::default() };
    let c = convert_file(&path, &opts, None).unwrap();
    assert_eq!(reported(&c), Vec::<usize>::new());
    assert_eq!(c.report.folds, 0);
    let surface = c.surface.as_ref().unwrap();
    let (dot, at, _) = fine::neighbour_normals(&surface.patches[736], opts.weights, 60);
    assert!(dot > 0.0, "patch 736 does not turn over: {dot} at {at:?}");
}

/// At the default options (quad layout, r = 2) the samples of a smooth surface clear every patch,
/// so the dense fold pass takes none (docs/math.md#fold-clearing: it costs nothing there).
#[test]
fn a_smooth_torus_takes_no_dense_pass_at_the_defaults() {
    let torus = gbsurf::mesh::generate::torus(24, 16, 10.0, 3.0).unwrap();
    for method in [Method::Dual, Method::Topology] {
        let c = convert(&torus, &ConvertOptions { method, ..Default::default() }, None).unwrap();
        let patches = c.surface.as_ref().unwrap().patches.len();
        assert_eq!(c.mesh.patch_folds.len(), patches, "{method}: one fold result per patch");
        let dense = c.mesh.patch_folds.iter().filter(|f| f.dense).count();
        assert_eq!(dense, 0, "{method}: {dense} of {patches} patches uncleared");
        assert_eq!(c.report.folds, 0, "{method}");
    }
}

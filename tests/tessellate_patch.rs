//! Single-patch sampling layout and tessellation (tessellate::patch).

use gbsurf::gb::Evaluate;
use gbsurf::mesh::TriMesh;
use gbsurf::gb::{LayoutError, SampleLayout};
use gbsurf::tessellate::patch::{emit_patch, tessellate_with};
use gbsurf::{DVec2, DVec3};
use proptest::prelude::*;
use std::collections::HashMap;

fn area(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    0.5 * (b - a).perp_dot(c - a)
}

/// Checks that the triangulation is a CCW topological disk whose boundary is `boundary_loop`.
fn check_disk(l: &SampleLayout) {
    let (n, r) = (l.sides, l.resolution);
    assert_eq!(l.uv.len(), SampleLayout::sample_count(n, r));
    assert_eq!(l.triangles.len(), SampleLayout::triangle_count(n, r));
    // Directed edges: each at most once; undirected edges used once (boundary) or twice.
    let mut directed: HashMap<(u32, u32), usize> = HashMap::new();
    let mut used = vec![false; l.uv.len()];
    let poly_area = area_of(&SampleLayout::regular_polygon(n));
    let mut total = 0.0;
    let min_area = poly_area / (n * r * r) as f64 * 1e-3;
    for (f, t) in l.triangles.iter().enumerate() {
        let a = area(
            l.uv[t[0] as usize],
            l.uv[t[1] as usize],
            l.uv[t[2] as usize],
        );
        assert!(a > min_area, "triangle {f} {t:?} has area {a}");
        total += a;
        for e in 0..3 {
            let (p, q) = (t[e], t[(e + 1) % 3]);
            used[p as usize] = true;
            assert!(
                directed.insert((p, q), f).is_none(),
                "directed edge {p}->{q} twice"
            );
        }
    }
    assert!(used.iter().all(|&u| u), "unused sample");
    gbsurf::assert_near!(
        total,
        poly_area,
        1e-12 * poly_area.max(1.0) * (r * r) as f64
    );
    let mut undirected = 0;
    let mut boundary_next: HashMap<u32, u32> = HashMap::new();
    for &(p, q) in directed.keys() {
        if !directed.contains_key(&(q, p)) {
            assert!(
                boundary_next.insert(p, q).is_none(),
                "boundary branches at {p}"
            );
            undirected += 1;
        } else if p < q {
            undirected += 1;
        }
    }
    let (v, e, f) = (
        l.uv.len() as i64,
        undirected as i64,
        l.triangles.len() as i64,
    );
    assert_eq!(v - e + f, 1, "Euler characteristic of a disk");
    // The boundary is one loop of n·r edges, in the order of boundary_loop (CCW).
    let lp = l.boundary_loop();
    assert_eq!(lp.len(), n * r);
    assert_eq!(boundary_next.len(), n * r);
    for k in 0..lp.len() {
        assert_eq!(boundary_next[&lp[k]], lp[(k + 1) % lp.len()]);
    }
}

fn area_of(poly: &[DVec2]) -> f64 {
    (0..poly.len())
        .map(|i| 0.5 * poly[i].perp_dot(poly[(i + 1) % poly.len()]))
        .sum()
}

#[test]
fn layouts_are_ccw_disks() {
    for n in 3..=8 {
        for r in 1..=9 {
            check_disk(&SampleLayout::regular(n, r).unwrap());
        }
    }
    check_disk(&SampleLayout::regular(5, 64).unwrap());
}

#[test]
fn small_layout_exact() {
    let l = SampleLayout::regular(3, 1).unwrap();
    assert_eq!(l.uv.len(), 4);
    assert_eq!(l.triangles, vec![[1, 2, 0], [2, 3, 0], [3, 1, 0]]);
    let l = SampleLayout::regular(4, 2).unwrap();
    assert_eq!(l.uv.len(), 13);
    assert_eq!(l.triangles.len(), 16);
    // Ring 1: the half-size domain square's corners v_{i-1}/2 for side i.
    assert_eq!(l.uv[1], DVec2::new(0.5, -0.5));
    assert_eq!(l.uv[2], DVec2::new(0.5, 0.5));
    assert_eq!(l.ring_index(1, 3, 1), 1);
}

use gbsurf::assert_near;

#[test]
fn boundary_samples_are_uniform_in_side_parameter() {
    for n in 3..=7 {
        let r = 6;
        let l = SampleLayout::regular(n, r).unwrap();
        let v = SampleLayout::regular_polygon(n);
        for i in 0..n {
            let (a, b) = (v[(i + n - 1) % n], v[i]);
            for t in 0..=r {
                let s = t as f64 / r as f64;
                let idx = l.boundary_index(i, t);
                assert!(l.is_boundary(idx));
                assert_near!(l.uv[idx], a + (b - a) * s);
            }
            // Step r of side i is step 0 of side i + 1; the corners are exact.
            assert_eq!(l.boundary_index(i, r), l.boundary_index(i + 1, 0));
            assert_eq!(l.uv[l.boundary_index(i, 0)], a);
        }
        assert!(!l.is_boundary(0));
        assert!(!l.is_boundary(l.ring_index(r - 1, n - 1, r - 2)));
    }
}

#[test]
fn inner_rings_are_scaled_copies() {
    let n = 5;
    let r = 7;
    let l = SampleLayout::regular(n, r).unwrap();
    for m in 1..r {
        for i in 0..n {
            for t in 0..=m {
                // Same side parameter t/m on ring m as on the boundary, scaled by m/r.
                let on_boundary = {
                    let v = SampleLayout::regular_polygon(n);
                    let (a, b) = (v[(i + n - 1) % n], v[i]);
                    a + (b - a) * (t as f64 / m as f64)
                };
                assert_near!(
                    l.uv[l.ring_index(m, i, t)],
                    on_boundary * (m as f64 / r as f64)
                );
            }
        }
    }
    assert_eq!(l.uv[0], DVec2::ZERO);
}

#[test]
fn layout_errors() {
    assert_eq!(
        SampleLayout::regular(2, 4),
        Err(LayoutError::TooFewSides { n: 2 })
    );
    assert_eq!(
        SampleLayout::regular(5, 0),
        Err(LayoutError::ZeroResolution { r: 0 })
    );
    assert!(matches!(
        SampleLayout::regular(6, 1 << 20),
        Err(LayoutError::TooLarge { .. })
    ));
    assert!(matches!(
        SampleLayout::regular(6, usize::MAX / 2),
        Err(LayoutError::TooLarge { .. })
    ));
    let mut cw = SampleLayout::regular_polygon(4);
    cw.reverse();
    assert!(matches!(
        SampleLayout::new(&cw, 3),
        Err(LayoutError::NotConvex { .. })
    ));
    let dart = [
        DVec2::new(0.0, 0.0),
        DVec2::new(1.0, -1.0),
        DVec2::new(0.2, 0.0),
        DVec2::new(1.0, 1.0),
    ];
    assert!(matches!(
        SampleLayout::new(&dart, 3),
        Err(LayoutError::NotConvex { .. })
    ));
    let bad = [DVec2::ZERO, DVec2::X, DVec2::new(f64::NAN, 1.0)];
    assert_eq!(
        SampleLayout::new(&bad, 3),
        Err(LayoutError::NonFiniteVertex { index: 2 })
    );
}

#[test]
fn square_domain_of_transfinite_works() {
    // transfinite's n = 4 domain: (1,1), (−1,1), (−1,−1), (1,−1).
    let sq = [
        DVec2::new(1.0, 1.0),
        DVec2::new(-1.0, 1.0),
        DVec2::new(-1.0, -1.0),
        DVec2::new(1.0, -1.0),
    ];
    let l = SampleLayout::new(&sq, 4).unwrap();
    assert_eq!(l.uv[l.boundary_index(1, 2)], DVec2::new(0.0, 1.0));
    // The GB domain for n = 4 is that square.
    assert_eq!(SampleLayout::regular(4, 4).unwrap(), l);
    let total: f64 = l
        .triangles
        .iter()
        .map(|t| {
            area(
                l.uv[t[0] as usize],
                l.uv[t[1] as usize],
                l.uv[t[2] as usize],
            )
        })
        .sum();
    assert_near!(total, 4.0);
}

#[test]
fn tessellate_with_uses_the_evaluator_per_sample() {
    let l = SampleLayout::regular(6, 5).unwrap();
    let mut calls = 0;
    let mesh = tessellate_with(&l, |s, uv| {
        calls += 1;
        assert_eq!(l.uv[s], uv);
        (DVec3::new(uv.x, uv.y, uv.x * uv.y), DVec3::Z)
    });
    assert_eq!(calls, l.uv.len());
    assert_eq!(mesh.positions.len(), l.uv.len());
    assert_eq!(mesh.triangles, l.triangles);
    assert_eq!(
        mesh.positions[7],
        DVec3::new(l.uv[7].x, l.uv[7].y, l.uv[7].x * l.uv[7].y)
    );
    // The OBJ has one `v`, `vn` per sample and one `f` per triangle.
    let mut obj = Vec::new();
    mesh.write_obj(&mut obj).unwrap();
    let obj = String::from_utf8(obj).unwrap();
    assert_eq!(obj.lines().filter(|x| x.starts_with("f ")).count(), 6 * 25);
}

#[test]
fn emit_patch_reuses_existing_boundary_vertices() {
    // Two copies of a patch glued along side 0 of the first and side 2 of the second: the
    // second traverses the shared side backwards (its step r − t is the first's step t).
    let r = 4;
    let l = SampleLayout::regular(3, r).unwrap();
    let mut sink = TriMesh::default();
    let ids_a = emit_patch(&l, |_, uv| (uv.extend(0.0), DVec3::Z), |_| None, &mut sink);
    let mut shared = HashMap::new();
    for t in 0..=r {
        shared.insert(l.boundary_index(2, r - t), ids_a[l.boundary_index(0, t)]);
    }
    let ids_b = emit_patch(
        &l,
        |_, uv| (uv.extend(1.0), DVec3::Z),
        |s| shared.get(&s).copied(),
        &mut sink,
    );
    assert_eq!(sink.positions.len(), 2 * l.uv.len() - (r + 1));
    assert_eq!(sink.triangles.len(), 2 * l.triangles.len());
    assert_eq!(ids_b[l.boundary_index(2, r)], ids_a[l.boundary_index(0, 0)]);
    assert!(ids_b[0] as usize >= l.uv.len());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    /// Any strictly convex domain (a regular polygon with jittered radii and angles) gives a disk.
    #[test]
    fn convex_domains_give_disks(n in 3usize..9, r in 1usize..7, jitter in proptest::collection::vec((0.8..1.2f64, -0.2..0.2f64), 8)) {
        let v: Vec<DVec2> = (0..n).map(|i| {
            let (rad, da) = jitter[i];
            let a = (i as f64 + da) * std::f64::consts::TAU / n as f64;
            DVec2::new(a.cos(), a.sin()) * rad
        }).collect();
        let l = match SampleLayout::new(&v, r) { Ok(l) => l, Err(LayoutError::NotConvex { .. }) => return Ok(()), Err(e) => panic!("{e}") };
        prop_assert_eq!(l.boundary_loop().len(), n * r);
        let total: f64 = l.triangles.iter().map(|t| area(l.uv[t[0] as usize], l.uv[t[1] as usize], l.uv[t[2] as usize])).sum();
        prop_assert!((total - area_of(&v)).abs() < 1e-12 * (r * r) as f64);
        prop_assert!(l.triangles.iter().all(|t| area(l.uv[t[0] as usize], l.uv[t[1] as usize], l.uv[t[2] as usize]) > 0.0));
    }
}

// ---- GB patches: weight tables and direct tessellation ----

use gbsurf::gb::table::{GbTable, TableError};
use gbsurf::gb::{GbPatch, Ribbon, WeightForm};
use gbsurf::limits::MAX_RESOLUTION;
use gbsurf::tessellate::patch::{tessellate_gb, tessellate_table};
use gbsurf::tessellate::TessellateError;

/// A GB patch with independent (not shared) ribbon points on a wavy dome.
fn wavy_patch(n: usize, d: usize, seed: f64) -> GbPatch {
    let l = d.div_ceil(2);
    let ribbons = (0..n)
        .map(|i| {
            Ribbon::from_fn(d, l, d + 1, |k, j| {
                let a =
                    (i as f64 + j as f64 / d as f64) * std::f64::consts::TAU / n as f64;
                let rad = 1.0 - 0.6 * k as f64 / d as f64;
                DVec3::new(
                    rad * a.cos() + 0.05 * (seed + j as f64).sin(),
                    rad * a.sin() + 0.04 * (seed * 1.3 + k as f64 + i as f64).cos(),
                    0.4 * k as f64 + 0.1 * (seed + 3.0 * i as f64 + j as f64).sin(),
                )
            })
        })
        .collect();
    GbPatch {
        ribbons,
        center: DVec3::new(0.02 * seed.sin(), -0.01, 0.9),
    }
}

#[test]
fn table_evaluation_equals_direct_eval() {
    for form in [WeightForm::Squared, WeightForm::Linear] {
        for n in 3..=8 {
            for d in 2..=6 {
                let patch = wavy_patch(n, d, n as f64 + 0.1 * d as f64);
                let table = GbTable::new(n, d, 6, form).unwrap();
                let ctrl = table.controls_of(&patch).unwrap();
                let mut ev = patch.evaluator().unwrap();
                for (s, &uv) in table.layout.uv.iter().enumerate() {
                    let f = table.eval_sample(s, &ctrl);
                    let direct = patch.eval_derivs_with_form(&mut ev, uv, form);
                    assert_near!(f.position, direct.p, 1e-12, "n={n} d={d} s={s}");
                    assert_near!(f.du, direct.su, 1e-12, "n={n} d={d} s={s}");
                    assert_near!(f.dv, direct.sv, 1e-12, "n={n} d={d} s={s}");
                    match (f.normal(), direct.normal()) {
                        (Some(a), Some(b)) => assert_near!(a, b, 1e-10),
                        (a, b) => assert_eq!(a.is_some(), b.is_some(), "n={n} d={d} s={s}"),
                    }
                }
                let mut pos = Vec::new();
                let mut nrm = Vec::new();
                table.eval_all(&ctrl, &mut pos, &mut nrm);
                assert_eq!(pos.len(), table.sample_count());
                // The tiled kernel agrees with direct evaluation at every sample.
                for (s, &uv) in table.layout.uv.iter().enumerate() {
                    let direct = patch.eval_derivs_with_form(&mut ev, uv, form);
                    assert_near!(pos[s], direct.p, 1e-12, "n={n} d={d} s={s}");
                    assert_near!(nrm[s], direct.normal().unwrap_or(DVec3::ZERO), 1e-10);
                }
                // Batch evaluation gives the same values as one-by-one evaluation.
                let other = wavy_patch(n, d, 7.7);
                let ctrls = [ctrl.clone(), table.controls_of(&other).unwrap()];
                let mut bp = vec![Vec::new(), Vec::new()];
                let mut bn = vec![Vec::new(), Vec::new()];
                table.eval_batch(&ctrls, &mut bp, &mut bn);
                assert_eq!(bp[0], pos);
                assert_eq!(bn[0], nrm);
                assert_near!(bp[1][3], other.eval(table.layout.uv[3], form), 1e-12);
            }
        }
    }
}

#[test]
fn table_rejects_mismatched_patches() {
    let table = GbTable::new(5, 3, 2, WeightForm::Squared).unwrap();
    assert!(matches!(
        table.controls_of(&wavy_patch(6, 3, 0.0)),
        Err(TableError::Mismatch {
            n: 6,
            d: 3,
            table_n: 5,
            table_d: 3
        })
    ));
    assert!(matches!(
        table.controls_of(&wavy_patch(5, 4, 0.0)),
        Err(TableError::Mismatch { .. })
    ));
    let mut bad = wavy_patch(5, 3, 0.0);
    bad.ribbons[2].row_mut(0)[1].x = f64::NAN;
    assert!(matches!(table.controls_of(&bad), Err(TableError::Patch(_))));
}

#[test]
fn gb_tessellation_interpolates_boundary_and_matches_table() {
    let n = 5;
    let r = 8;
    let patch = gbsurf::gb::gbp::load_gbp(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/cubic5.gbp"
    ))
    .unwrap();
    let mesh = tessellate_gb(&patch, r, WeightForm::Squared).unwrap();
    let table = GbTable::new(n, 3, r, WeightForm::Squared).unwrap();
    let via_table = tessellate_table(&table, &patch).unwrap();
    assert_eq!(mesh.triangles, via_table.triangles);
    assert_near!(mesh.positions, via_table.positions, 1e-12);
    assert_near!(mesh.normals, via_table.normals, 1e-10);
    // Boundary samples lie on the boundary Bézier curves (row 0 of each ribbon) at s = t/r.
    for i in 0..n {
        for t in 0..=r {
            let s = t as f64 / r as f64;
            let idx = table.layout.boundary_index(i, t);
            assert_near!(
                mesh.positions[idx],
                patch.ribbons[i].boundary_point(s),
                1e-12
            );
        }
    }
    // Unit normals, oriented like the patch (dome opening to −z: normals have z > 0 inside).
    for nrm in &mesh.normals {
        assert_near!(nrm.length(), 1.0, 1e-12);
    }
    assert!(
        mesh.normals[0].z > 0.9,
        "centre normal {:?}",
        mesh.normals[0]
    );
    assert_eq!(
        tessellate_gb(&patch, 0, WeightForm::Squared),
        Err(TessellateError::Layout {
            patch: 0,
            source: LayoutError::ZeroResolution { r: 0 }
        })
    );
    assert_eq!(
        tessellate_gb(&patch, MAX_RESOLUTION + 1, WeightForm::Squared),
        Err(TessellateError::ResolutionTooHigh {
            r: MAX_RESOLUTION + 1
        })
    );
}

/// A connected cubic GB patch of n sides over the unit circle with a wavy inner row and a raised
/// centre, as `.gbp` text.
fn wavy_gbp(n: usize) -> String {
    let mut text = format!("{n} 3\n0.1 -0.05 0.6\n");
    for k in 0..2 {
        for i in 0..n {
            for j in k..3 - k {
                let a = std::f64::consts::TAU * ((i as f64 - 1.0) + j as f64 / 3.0) / n as f64;
                let (r, z) = if k == 0 { (1.0 + 0.05 * (3.0 * a).sin(), 0.1 * (2.0 * a).cos()) } else { (0.8, 0.3 + 0.05 * (5.0 * a).sin()) };
                text += &format!("{} {} {}\n", r * a.cos(), r * a.sin(), z);
            }
        }
    }
    text
}

/// Patches of more than 64 sides are tessellated through the rotational symmetry of the regular
/// domain (one basis evaluation per sample of side 0, applied to every rotation): the same points
/// and normals as evaluating every sample directly.
#[test]
fn symmetric_tessellation_of_many_sides_equals_direct_evaluation() {
    use gbsurf::gb::{gbp::parse_gbp, WeightForm};
    use gbsurf::tessellate::patch::tessellate_gb;
    for (n, r) in [(65usize, 3usize), (97, 4)] {
        let patch = parse_gbp(&wavy_gbp(n)).unwrap();
        for form in [WeightForm::Squared, WeightForm::Linear] {
            let mesh = tessellate_gb(&patch, r, form).unwrap();
            let layout = SampleLayout::regular(n, r).unwrap();
            assert_eq!(mesh.positions.len(), layout.uv.len());
            for (s, &uv) in layout.uv.iter().enumerate() {
                let d = patch.eval_derivs(uv, form);
                assert!((mesh.positions[s] - d.p).length() < 1e-12, "n {n} sample {s}: {} vs {}", mesh.positions[s], d.p);
                let nrm = d.normal().unwrap();
                assert!((mesh.normals[s] - nrm).length() < 1e-9, "n {n} sample {s}: {} vs {nrm}", mesh.normals[s]);
            }
        }
    }
}

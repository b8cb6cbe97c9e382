//! Cage coordinates in the triangle layout (SurfaceMesh::cage_coords, cage_loop_corner;
//! docs/math.md#cage-corners): every loop names a valid cage corner with (σ, τ) ∈ [0,1]², each
//! output vertex is one cage point whatever loop and patch it is seen from, and at the samples the
//! triangle layout at resolution 2r shares with the quad layout at r (the boundary samples and
//! the domain centre) every loop carries exactly the quad layout's (corner, σ, τ) — on the side
//! midpoints, which lie on two sectors, the same cage point. The inverse of the bilinear sector
//! map reproduces domain points (proptest over n and r).

use gbsurf::api::{convert, ConvertOptions, Method};
use gbsurf::assert_near;
use gbsurf::gb::{bilinear, bilinear_inverse, Domain, Layout, SampleLayout, Sampling};
use gbsurf::mesh::PolyMesh;
use gbsurf::tessellate::SurfaceMesh;
use glam::{DVec2, DVec3};
use proptest::prelude::*;
use std::collections::{BTreeSet, HashMap};

mod common_cage;
use common_cage::cage_point;

const MODELS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/models");

fn model(name: &str) -> PolyMesh {
    gbsurf::api::read_mesh(format!("{MODELS}/{name}")).unwrap()
}

fn mesh(cage: &PolyMesh, method: Method, layout: Layout, r: usize) -> SurfaceMesh {
    let opts = ConvertOptions { method, layout, resolution: r, ..Default::default() };
    convert(cage, &opts, None).unwrap_or_else(|e| panic!("{method} {layout:?} r={r}: {e}")).mesh
}

/// (cage corner, σ, τ bits) of a loop, for exact comparison.
type Loop = ([u32; 2], [u64; 2]);

/// Per patch: output vertex → the (corner, σ, τ) of its loops in that patch's faces.
fn loops_by_patch(m: &SurfaceMesh) -> Vec<HashMap<u32, BTreeSet<Loop>>> {
    let quads = !m.quads.is_empty();
    let np = m.patch_loops.len();
    let mut out = vec![HashMap::<u32, BTreeSet<Loop>>::new(); np];
    for (f, p) in (0..m.face_count()).map(|f| (f, m.face_patch(f) as usize)) {
        let face = m.face(f);
        for (j, &x) in face.iter().enumerate() {
            let l = face.len() * f + j;
            let corner = if quads { m.cage_corner[f] } else { m.cage_loop_corner[l] };
            out[p].entry(x).or_default().insert((corner, m.cage_coords[l].map(f64::to_bits)));
        }
    }
    out
}

/// The checks of the module doc for one cage, structure and quad resolution r.
fn check(name: &str, cage: &PolyMesh, method: Method, r: usize) {
    let tri = mesh(cage, method, Layout::Triangles, 2 * r);
    let quad = mesh(cage, method, Layout::Quads, r);
    let what = format!("{name} {method} r={r}");
    let nt = tri.triangles.len();
    assert_eq!((tri.cage_coords.len(), tri.cage_loop_corner.len()), (3 * nt, 3 * nt), "{what}");
    let scale = cage.positions.iter().map(|p| p.length()).fold(1.0, f64::max);
    // Valid corners, coordinates in [0,1]², one cage point per output vertex.
    let mut point: HashMap<u32, DVec3> = HashMap::new();
    for (l, (&c, &st)) in tri.cage_loop_corner.iter().zip(&tri.cage_coords).enumerate() {
        let (f, k) = (c[0] as usize, c[1] as usize);
        assert!(f < cage.faces.len() && k < cage.faces[f].len(), "{what}: loop {l} → {c:?}");
        assert!(st.iter().all(|x| (0.0..=1.0).contains(x)), "{what}: loop {l} {st:?}");
        let x = tri.triangles[l / 3][l % 3];
        let p = cage_point(cage, c, st);
        let prev = *point.entry(x).or_insert(p);
        assert!(prev.distance(p) <= 1e-12 * scale, "{what}: vertex {x}: {prev} vs {p}");
    }
    assert_eq!(point.len(), tri.positions.len(), "{what}: a vertex without loops");
    // The shared samples: every boundary step (the same count per side: 2r) and the centre.
    let (lt, lq) = (loops_by_patch(&tri), loops_by_patch(&quad));
    assert_eq!(tri.patch_loops.per_side, quad.patch_loops.per_side, "{what}");
    assert_eq!(tri.patch_loops.len(), quad.patch_loops.len(), "{what}");
    let mut midpoints = 0;
    for p in 0..tri.patch_loops.len() {
        let (bt, bq) = (tri.patch_loops.of(p), quad.patch_loops.of(p));
        assert_eq!(bt.len(), bq.len(), "{what} patch {p}");
        // Centre: the third vertex of the patch's first triangle; the first of its first quad.
        let ct = tri.triangles[tri.patch_loops.triangles[p]][2];
        let cq = quad.quads[quad.patch_loops.triangles[p] / 2][0];
        let shared = bt.iter().zip(bq).map(|(&a, &b)| (a, b, false)).enumerate();
        for (j, (a, b, centre)) in shared.chain(std::iter::once((usize::MAX, (ct, cq, true)))) {
            let (sa, sb) = (&lt[p][&a], &lq[p][&b]);
            let midpoint = !centre && j % tri.patch_loops.per_side == r;
            if midpoint {
                // On a spoke: sector i − 1 or i, either way the same cage point.
                midpoints += 1;
                let pt = |s: &BTreeSet<Loop>| s.iter().map(|(c, st)| cage_point(cage, *c, st.map(f64::from_bits))).collect::<Vec<_>>();
                let want = pt(sb)[0];
                for q in pt(sa).into_iter().chain(pt(sb)) {
                    assert!(q.distance(want) <= 1e-12 * scale, "{what} patch {p} step {j}: {q} vs {want}");
                }
            } else {
                assert!(sa.is_subset(sb) && !sa.is_empty(), "{what} patch {p} step {j} (centre {centre}): {sa:?} vs {sb:?}");
                if !centre {
                    assert_eq!(sa, sb, "{what} patch {p} step {j}");
                }
            }
        }
    }
    assert!(midpoints > 0, "{what}");
}

#[test]
fn cube_both_structures() {
    let cube = model("cube.obj");
    for r in 1..=3 {
        check("cube", &cube, Method::Topology, r);
        check("cube", &cube, Method::Dual, r);
    }
}

#[test]
fn closed_and_open_cages() {
    for r in [1, 2] {
        for name in ["torus.obj", "grid_open.obj"] {
            check(name, &model(name), Method::Topology, r);
            check(name, &model(name), Method::Dual, r);
        }
    }
}

/// The inverse on the quad layout's own sectors: an n-gon's sector 0 is a kite (the square's a
/// square: the quadratic is linear), the grid points come back exactly up to rounding.
#[test]
fn inverse_of_the_quad_grid() {
    for n in [3, 4, 5, 6, 9] {
        let r = 4;
        let l = SampleLayout::for_domain(&Domain::regular(n).unwrap(), Sampling::new(Layout::Quads, r)).unwrap();
        for i in 0..n {
            let q = l.quad_sector(i);
            for a in 0..=r {
                for b in 0..=r {
                    let st = bilinear_inverse(q, l.uv[l.sector_index(i, a, b)]);
                    assert_near!(st, DVec2::new(a as f64 / r as f64, b as f64 / r as f64), 1e-12, "n={n} sector {i} ({a},{b})");
                }
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// Every triangle-layout sample lies at its coordinates in each of its sectors, and a point
    /// of a sector at (s, t) inverts to (s, t).
    #[test]
    fn inverse_reproduces_the_domain_point(n in 3usize..13, r in 1usize..12, s in 0.0f64..=1.0, t in 0.0f64..=1.0, i in 0usize..12) {
        let l = SampleLayout::for_domain(&Domain::regular(n).unwrap(), Sampling::new(Layout::Triangles, r)).unwrap();
        let points = l.sector_points();
        prop_assert_eq!(points.len(), l.uv.len());
        for (x, (sp, &uv)) in points.iter().zip(&l.uv).enumerate() {
            prop_assert!(sp.count >= 1 && (sp.count <= 2 || x == 0));
            for j in 0..sp.count {
                let sector = (sp.first + j) as usize % n;
                let st = sp.in_sector(sector as u32, n as u32).unwrap();
                prop_assert!((0.0..=1.0).contains(&st.x) && (0.0..=1.0).contains(&st.y), "{:?}", st);
                let back = bilinear(l.quad_sector(sector), st.x, st.y);
                prop_assert!(back.distance(uv) <= 1e-12, "n={} r={} sample {} sector {}: {} vs {}", n, r, x, sector, back, uv);
            }
            // Not in the other sectors.
            let inside = (0..n).filter(|&k| sp.in_sector(k as u32, n as u32).is_some()).count();
            prop_assert_eq!(inside, sp.count as usize);
        }
        // Every triangle lies in its face corner's sector (its closure), but the middle one of
        // each ring's side, which straddles the spoke with two of its vertices in it.
        let corners = l.face_corners();
        let mut straddling = 0;
        for (tri, &c) in l.triangles.iter().zip(&corners) {
            let inside = tri.iter().filter(|&&x| points[x as usize].in_sector(c, n as u32).is_some()).count();
            prop_assert!(inside >= 2, "n={} r={} {:?} corner {}", n, r, tri, c);
            straddling += usize::from(inside == 2);
        }
        prop_assert_eq!(straddling, n * r);
        // Ring 1: one triangle per corner.
        let ring1: std::collections::BTreeSet<u32> = corners[..n].iter().copied().collect();
        prop_assert_eq!(ring1.len(), n);
        let q = l.quad_sector(i % n);
        let st = bilinear_inverse(q, bilinear(q, s, t));
        prop_assert!(st.distance(DVec2::new(s, t)) <= 1e-12, "n={} ({}, {}) → {}", n, s, t, st);
    }
}

//! Whole-surface tessellation and welding (tessellate::surface) on hand-built GB surfaces:
//! a closed "pillow" of two n-sided patches glued along all their sides, single open patches,
//! and malformed adjacency.

use gbsurf::gb::Evaluate;
use gbsurf::construct::{Patch, PatchSource, SideRef, Surface};
use gbsurf::gb::{GbPatch, Ribbon, WeightForm};
use gbsurf::quality::check_mesh;
use gbsurf::gb::SampleLayout;
use gbsurf::tessellate::{tessellate_surface, TessellateError};
use gbsurf::DVec3;

/// Corner c of the boundary polygon (unit regular n-gon in z = 0, wobbled in z so the curve is
/// not planar).
fn corner(n: usize, c: usize) -> DVec3 {
    let a = std::f64::consts::TAU * (c % n) as f64 / n as f64;
    DVec3::new(a.cos(), a.sin(), 0.1 * (3.0 * a).sin())
}

/// A cubic GB patch whose side i runs along the boundary polygon from `corners[i−1]` to
/// `corners[i]`, bulging by `bulge` in z.
fn patch(corners: &[DVec3], bulge: f64) -> GbPatch {
    let n = corners.len();
    let centroid = corners.iter().copied().sum::<DVec3>() / n as f64;
    let ribbons = (0..n)
        .map(|i| {
            let (a, b) = (corners[(i + n - 1) % n], corners[i]);
            let row0: Vec<DVec3> = (0..=3).map(|j| a + (b - a) * (j as f64 / 3.0)).collect();
            let row1: Vec<DVec3> = row0.iter().map(|p| *p + (centroid - *p) / 3.0 + DVec3::Z * bulge).collect();
            Ribbon::from_rows(3, vec![row0, row1]).unwrap()
        })
        .collect();
    GbPatch { ribbons, center: centroid + DVec3::Z * 1.4 * bulge }
}

/// Two patches: A (up, sides CCW from above) and B (down, sides CCW from below); side i of A is
/// side (n − i) mod n of B, traversed the other way.
fn pillow(n: usize) -> Surface {
    let ca: Vec<DVec3> = (0..n).map(|c| corner(n, c)).collect();
    // B corner j = A corner −j−1, so B side j runs from A corner −j to A corner −j−1.
    let cb: Vec<DVec3> = (0..n).map(|j| corner(n, (2 * n - j - 1) % n)).collect();
    let a = patch(&ca, 0.5);
    let b = patch(&cb, -0.5);
    let na = (0..n).map(|i| Some(SideRef { patch: 1, side: (n - i) % n })).collect();
    let nb = (0..n).map(|j| Some(SideRef { patch: 0, side: (n - j) % n })).collect();
    Surface {
        patches: vec![Patch::Gb(a), Patch::Gb(b)],
        neighbors: vec![na, nb],
        sources: vec![PatchSource::Vertex(0), PatchSource::Vertex(1)],
        curves: Vec::new(),
        warnings: Vec::new(),
        creases: Vec::new(),
        cage: Vec::new(),
    }
}

#[test]
fn pillow_is_closed_clean_two_manifold() {
    for n in 3..=7 {
        for r in [1, 2, 5] {
            let s = pillow(n);
            let (m, stats) = tessellate_surface(&s, r, WeightForm::Squared, None).unwrap();
            let c = check_mesh(&m.positions, &m.triangles);
            assert!(c.is_clean_closed(), "n = {n}, r = {r}: {c:?}");
            assert_eq!(c.euler_characteristic, 2, "n = {n}, r = {r}");
            let per_patch = SampleLayout::sample_count(n, r);
            assert_eq!(m.positions.len(), 2 * per_patch - n * r, "n = {n}, r = {r}");
            assert_eq!(m.triangles.len(), 2 * n * r * r);
            assert!(stats.max_boundary_gap <= 1e-12, "gap {}", stats.max_boundary_gap);
            // The two halves meet at a crease: a large, measured G1 deviation on the seam only.
            assert!(stats.max_g1_deg > 10.0, "n = {n}: {}", stats.max_g1_deg);
            assert_eq!(stats.shared_vertices, n * r);
            let seam = m.g1_deviation_deg.iter().filter(|&&g| g > 0.0).count();
            assert_eq!(seam, n * r);
            // Per-vertex arrays complete, normals unit and outward (away from the centre).
            for v in 0..m.positions.len() {
                assert!((m.normals[v].length() - 1.0).abs() < 1e-12);
                assert!(m.patch[v] <= 1);
            }
            assert_eq!(m.triangle_patch.len(), m.triangles.len());
            let top = m.positions.iter().enumerate().max_by(|a, b| a.1.z.total_cmp(&b.1.z)).unwrap().0;
            assert!(m.normals[top].z > 0.9, "n = {n}: top normal {:?}", m.normals[top]);
            let bottom = m.positions.iter().enumerate().min_by(|a, b| a.1.z.total_cmp(&b.1.z)).unwrap().0;
            assert!(m.normals[bottom].z < -0.9);
        }
    }
}

#[test]
fn single_patch_stays_open() {
    for n in 3..=6 {
        let s = pillow(n);
        let one = Surface {
            patches: vec![s.patches[0].clone()],
            neighbors: vec![vec![None; n]],
            sources: vec![PatchSource::Vertex(0)],
            curves: Vec::new(),
            warnings: Vec::new(),
            creases: Vec::new(),
            cage: Vec::new(),
        };
        let r = 4;
        let (m, stats) = tessellate_surface(&one, r, WeightForm::Squared, None).unwrap();
        let c = check_mesh(&m.positions, &m.triangles);
        assert!(c.is_two_manifold(), "{c:?}");
        assert_eq!(c.boundary_edges, n * r);
        assert_eq!(c.euler_characteristic, 1);
        assert_eq!(stats.max_g1_deg, 0.0);
        assert_eq!(stats.shared_vertices, 0);
        assert!(m.g1_deviation_deg.iter().all(|&g| g == 0.0));
    }
}

#[test]
fn broken_adjacency_is_an_error_naming_the_side() {
    let mut s = pillow(4);
    s.neighbors[1][2] = Some(SideRef { patch: 0, side: 3 });
    let e = tessellate_surface(&s, 3, WeightForm::Squared, None).unwrap_err();
    assert!(matches!(e, TessellateError::Adjacency { .. }), "{e}");
    let mut s = pillow(4);
    s.neighbors[0].pop();
    let e = tessellate_surface(&s, 3, WeightForm::Squared, None).unwrap_err();
    assert_eq!(e, TessellateError::NeighborCount { patch: 0, sides: 4, entries: 3 });
    let s = pillow(4);
    let e = tessellate_surface(&s, 0, WeightForm::Squared, None).unwrap_err();
    assert!(matches!(e, TessellateError::Layout { patch: 0, .. }), "{e}");
}

#[test]
fn cancel_stops_tessellation() {
    let s = pillow(5);
    let mut calls = 0;
    let mut cb = |_f: f32| {
        calls += 1;
        false
    };
    let e = tessellate_surface(&s, 3, WeightForm::Squared, Some(&mut cb)).unwrap_err();
    assert_eq!(e, TessellateError::Cancelled);
    assert_eq!(calls, 1);
}

#[test]
fn welded_positions_match_patch_evaluation() {
    // Every output vertex is a point of its patch: compare interior samples with direct
    // evaluation of the GB patch at the layout's domain points.
    let s = pillow(5);
    let r = 3;
    let (m, _) = tessellate_surface(&s, r, WeightForm::Squared, None).unwrap();
    let Patch::Gb(a) = &s.patches[0] else { unreachable!() };
    let dom = gbsurf::gb::Domain::regular(5).unwrap();
    let layout = SampleLayout::new(dom.vertices(), r).unwrap();
    // Patch 0 is emitted first: its samples are vertices 0.. in layout order.
    for (k, &uv) in layout.uv.iter().enumerate() {
        let d = a.eval_derivs(uv, WeightForm::Squared);
        gbsurf::assert_near!(m.positions[k], d.p, 1e-12);
        let c = d.curvature().unwrap();
        if !layout.is_boundary(k) {
            gbsurf::assert_near!(m.mean_curvature[k], c.mean, 1e-9);
            gbsurf::assert_near!(m.gaussian_curvature[k], c.gaussian, 1e-9);
            gbsurf::assert_near!(m.normals[k], d.normal().unwrap(), 1e-12);
        }
    }
}

/// The welding's parallel parts (corner measurements per chunk of patches, kept corner samples
/// summed per vertex range, each vertex in patch order) give bit-identical meshes and figures in
/// pools of 1, 2 and 3 threads, with the quality arrays kept and without them (the CLI's path),
/// in both structures.
#[test]
fn welding_is_the_same_in_every_pool_size() {
    use gbsurf::api::{convert, ConvertOptions, Method};
    // 4800 patches: more than one chunk of the corner measurements (PATCH_CHUNK = 4096).
    let cage = gbsurf::mesh::generate::torus(80, 60, 3.0, 1.0).unwrap();
    for method in [Method::Dual, Method::Topology] {
        for quality in [true, false] {
            let opts = ConvertOptions { method, quality_arrays: quality, keep_surface: quality, ..Default::default() };
            let run = |threads: usize| {
                let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
                let c = pool.install(|| convert(&cage, &opts, None)).unwrap();
                let r = &c.report;
                let figures = [r.max_g1_deg, r.mean_g1_deg, r.max_abs_mean_curvature_times_diagonal].map(f64::to_bits);
                (c.mesh, figures)
            };
            let one = run(1);
            for threads in [2, 3] {
                let other = run(threads);
                assert!(other.0 == one.0, "{method} quality {quality}: mesh differs with {threads} threads");
                assert_eq!(other.1, one.1, "{method} quality {quality}: figures differ with {threads} threads");
            }
        }
    }
}

//! The output size guard (estimate before any work, typed refusal) and scale normalisation
//! (every extent in limits::EXTENT_RANGE converts the same way up to the scale factor).

use gbsurf::api::{convert, estimate_output, read_mesh, ConvertError, ConvertOptions, Conversion, Method};
use gbsurf::mesh::halfedge::HalfEdgeMesh;
use gbsurf::mesh::PolyMesh;
use proptest::prelude::*;

const MODELS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/models");

fn model(name: &str) -> PolyMesh {
    read_mesh(format!("{MODELS}/{name}")).unwrap()
}

fn estimate(mesh: &PolyMesh, o: &ConvertOptions) -> gbsurf::api::OutputEstimate {
    estimate_output(&HalfEdgeMesh::from_polymesh(mesh).unwrap(), o)
}

#[test]
fn catmull_clark_levels_8_is_refused_before_any_work() {
    let torus = model("torus.obj");
    let o = ConvertOptions { method: Method::CatmullClark, levels: 8, ..ConvertOptions::triangles_r8() };
    let e = estimate(&torus, &o);
    // 96 quads, closed: every level multiplies the vertices by 4.
    assert_eq!(e.vertices, 96 * 4u64.pow(8));
    assert_eq!(e.bytes, gbsurf::api::BASE_BYTES + e.vertices * gbsurf::api::SUBDIV_BYTES_PER_VERTEX);
    // Refused before any work: no progress beyond the start is ever reported.
    let mut furthest = 0.0f32;
    let mut count = |f: f32| {
        furthest = furthest.max(f);
        true
    };
    let err = convert(&torus, &o, Some(&mut count)).unwrap_err();
    assert_eq!(furthest, 0.0, "progress {furthest} was reported before the refusal");
    match &err {
        ConvertError::OutputTooLarge { method, vertices, bytes, limit_mb } => {
            assert_eq!((*method, *vertices, *bytes, *limit_mb), ("catmull-clark", e.vertices, e.bytes, gbsurf::limits::DEFAULT_MAX_MEMORY_MB));
        }
        other => panic!("{other}"),
    }
    assert_eq!(
        err.to_string(),
        format!(
            "output too large: catmull-clark would make about 6291456 output vertices and need about {} MiB, above the limit of 2048 MiB; lower --resolution or --levels, or raise --max-memory-mb (C ABI: GbsurfOptions.max_memory_mb; Blender: Memory Limit)",
            e.bytes.div_ceil(1 << 20)
        )
    );
    // Raising the limit lets the estimate through (checked without converting: the bound is exact).
    assert!(e.bytes <= ConvertOptions { max_memory_mb: 8192, ..o }.max_memory_mb << 20);
}

/// Each layout's figure: the triangle layout carries per-loop cage coordinates and corners.
#[test]
fn the_estimate_per_sample_follows_the_layout() {
    use gbsurf::api::{BASE_BYTES, GB_BYTES_PER_SAMPLE, GB_TRIANGLE_BYTES_PER_SAMPLE};
    let torus = model("torus.obj");
    for method in [Method::Dual, Method::Topology] {
        let tri = ConvertOptions { method, ..ConvertOptions::triangles_r8() };
        let e = estimate(&torus, &tri);
        // 96 quad patches (dual: 96 valence-4 vertices), 1 + 4·8·9/2 samples each.
        assert_eq!(e.vertices, 96 * 145, "{method}");
        assert_eq!(e.bytes, BASE_BYTES + e.vertices * GB_TRIANGLE_BYTES_PER_SAMPLE, "{method}");
        let quads = ConvertOptions { method, ..ConvertOptions::default() };
        let e = estimate(&torus, &quads);
        assert_eq!(e.vertices, 96 * 25, "{method}");
        assert_eq!(e.bytes, BASE_BYTES + e.vertices * GB_BYTES_PER_SAMPLE, "{method}");
    }
}

#[test]
fn a_small_limit_refuses_the_default_conversion_and_a_large_one_accepts_it() {
    let cube = model("cube.obj");
    let small = ConvertOptions { max_memory_mb: 1, ..ConvertOptions::triangles_r8() };
    assert!(matches!(convert(&cube, &small, None), Err(ConvertError::OutputTooLarge { limit_mb: 1, .. })));
    assert!(convert(&cube, &ConvertOptions::triangles_r8(), None).is_ok());
    let zero = ConvertOptions { max_memory_mb: 0, ..ConvertOptions::triangles_r8() };
    assert_eq!(convert(&cube, &zero, None).unwrap_err().to_string(), "invalid --max-memory-mb 0: must be in 1..=1048576");
}

#[test]
fn the_estimate_bounds_the_output_of_every_model_and_method() {
    for name in ["cube.obj", "torus.obj", "grid_open.obj", "house.obj", "l_prism.obj", "star_prism.obj", "pyramid.obj"] {
        let mesh = model(name);
        for (method, resolution, levels) in
            [(Method::Dual, 3, 0), (Method::Topology, 3, 0), (Method::CatmullClark, 1, 2), (Method::DooSabin, 1, 2), (Method::CatmullClark, 1, 0)]
        {
            let o = ConvertOptions { method, resolution, levels, ..ConvertOptions::triangles_r8() };
            let e = estimate(&mesh, &o);
            let c = convert(&mesh, &o, None).unwrap_or_else(|err| panic!("{name} {method}: {err}"));
            assert!(e.vertices >= c.report.vertices as u64, "{name} {method}: {} < {}", e.vertices, c.report.vertices);
            if !method.is_patch_method() && c.report.input_closed {
                assert_eq!(e.vertices, c.report.vertices as u64, "{name} {method}: closed subdivision counts are exact");
            }
        }
    }
}

fn scaled(mesh: &PolyMesh, s: f64) -> PolyMesh {
    PolyMesh { positions: mesh.positions.iter().map(|&p| p * s).collect(), faces: mesh.faces.clone(), creases: mesh.creases.clone(), holes: mesh.holes.clone() }
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / a.abs().max(b.abs()).max(f64::MIN_POSITIVE)
}

/// `c` (converted at scale s) equals `base` (scale 1) up to the scale factor, relative 1e-12.
fn same_up_to_scale(base: &Conversion, c: &Conversion, s: f64, what: &str) {
    let (m0, m) = (&base.mesh, &c.mesh);
    assert_eq!((m0.positions.len(), &m0.triangles, &m0.patch, &m0.triangle_patch), (m.positions.len(), &m.triangles, &m.patch, &m.triangle_patch), "{what}");
    let size = m0.positions.iter().fold(0.0f64, |a, p| a.max(p.abs().max_element()));
    for (p0, p) in m0.positions.iter().zip(&m.positions) {
        assert!((*p / s - *p0).abs().max_element() <= 1e-12 * size, "{what}: {p0} vs {p}/{s}");
    }
    for (n0, n) in m0.normals.iter().zip(&m.normals) {
        assert!((*n - *n0).abs().max_element() <= 1e-12, "{what}: normal {n0} vs {n}");
    }
    let hmax = m0.mean_curvature.iter().fold(0.0f64, |a, h| a.max(h.abs()));
    let kmax = m0.gaussian_curvature.iter().fold(0.0f64, |a, k| a.max(k.abs()));
    for (h0, h) in m0.mean_curvature.iter().zip(&m.mean_curvature) {
        assert!((h * s - h0).abs() <= 1e-12 * hmax.max(1e-300), "{what}: H {h0} vs {h}·{s}");
    }
    for (k0, k) in m0.gaussian_curvature.iter().zip(&m.gaussian_curvature) {
        assert!((k * s * s - k0).abs() <= 1e-12 * kmax.max(1e-300), "{what}: K {k0} vs {k}·{s}²");
    }
    for (g0, g) in m0.g1_deviation_deg.iter().zip(&m.g1_deviation_deg) {
        assert!((g - g0).abs() <= 1e-9, "{what}: G1 {g0} vs {g}");
    }
    let (r0, r) = (&base.report, &c.report);
    let mut r0c = r0.clone();
    let mut rc = r.clone();
    assert!(rel(r.max_boundary_gap / s, r0.max_boundary_gap) <= 1e-12 || (r.max_boundary_gap / s - r0.max_boundary_gap).abs() <= 1e-15 * size, "{what}: gap");
    assert!((r.max_g1_deg - r0.max_g1_deg).abs() <= 1e-9 && (r.mean_g1_deg - r0.mean_g1_deg).abs() <= 1e-9, "{what}: G1");
    assert!(rel(r.max_abs_mean_curvature_times_diagonal, r0.max_abs_mean_curvature_times_diagonal) <= 1e-12, "{what}: |H|·diag");
    for x in [&mut r0c, &mut rc] {
        x.max_boundary_gap = 0.0;
        x.max_g1_deg = 0.0;
        x.mean_g1_deg = 0.0;
        x.max_abs_mean_curvature_times_diagonal = 0.0;
        x.seconds = 0.0;
    }
    assert_eq!(r0c, rc, "{what}: report");
    assert!(r.valid, "{what}: {:?}", r.validity_problems());
    match (&base.surface, &c.surface) {
        (Some(s0), Some(s1)) => {
            for (c0, c1) in s0.curves.iter().flatten().zip(s1.curves.iter().flatten()) {
                assert!((*c1 / s - *c0).abs().max_element() <= 1e-12 * size, "{what}: curve {c0} vs {c1}");
            }
            assert_eq!(s0.patches.len(), s1.patches.len());
        }
        (None, None) => {}
        _ => panic!("{what}: surface"),
    }
}

const SCALES: [f64; 5] = [1e-100, 1e-20, 1.0, 1e20, 1e100];

#[test]
fn cube_and_torus_convert_the_same_at_every_scale() {
    for name in ["cube.obj", "torus.obj"] {
        let mesh = model(name);
        for (method, resolution, levels) in [(Method::Dual, 3, 0), (Method::Topology, 3, 0), (Method::CatmullClark, 1, 2), (Method::DooSabin, 1, 2)] {
            let o = ConvertOptions { method, resolution, levels, ..ConvertOptions::triangles_r8() };
            let base = convert(&mesh, &o, None).unwrap();
            for s in SCALES {
                let what = format!("{name} {method} scale {s:e}");
                let c = convert(&scaled(&mesh, s), &o, None).unwrap_or_else(|e| panic!("{what}: {e}"));
                same_up_to_scale(&base, &c, s, &what);
            }
        }
    }
}

#[test]
fn extents_beyond_the_range_are_refused_with_it() {
    let cube = model("cube.obj");
    // (Beyond 1e150 the mesh validation refuses the coordinates themselves.)
    for s in [1e-160, 1e145] {
        let e = convert(&scaled(&cube, s), &ConvertOptions::triangles_r8(), None).unwrap_err();
        let ConvertError::ScaleOutOfRange { extent, min, max } = e else { panic!("{s:e}: {e}") };
        assert_eq!((min, max), gbsurf::limits::EXTENT_RANGE);
        assert!(rel(extent, 2.0 * s) <= 1e-15 || rel(extent, s) <= 1e-15, "{extent:e}");
        assert!(e.to_string().contains("outside the supported range 1e-140..1e140"), "{e}");
    }
    // Far translation stays a mesh error (validation comes first).
    let far = PolyMesh { positions: cube.positions.iter().map(|&p| p + glam::DVec3::splat(1e15)).collect(), faces: cube.faces.clone(), creases: cube.creases.clone(), holes: cube.holes.clone() };
    assert!(matches!(convert(&far, &ConvertOptions::triangles_r8(), None), Err(ConvertError::Mesh(gbsurf::mesh::MeshError::UnresolvableExtent { .. }))));
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]
    /// A cube at any power-of-ten scale in the range, shifted by up to 100 extents, converts with
    /// the same report as at scale 1.
    #[test]
    fn cube_reports_are_scale_invariant(exp in -130i32..=130, shift in -100.0f64..100.0) {
        let cube = model("cube.obj");
        let s = 10f64.powi(exp);
        let o = ConvertOptions { resolution: 2, ..ConvertOptions::triangles_r8() };
        let moved = PolyMesh { positions: cube.positions.iter().map(|&p| (p + glam::DVec3::new(shift, 0.0, 0.0)) * s).collect(), faces: cube.faces.clone(), creases: cube.creases.clone(), holes: cube.holes.clone() };
        let c = convert(&moved, &o, None).unwrap();
        let base = convert(&cube, &o, None).unwrap();
        prop_assert!(c.report.valid, "{:?}", c.report.validity_problems());
        prop_assert_eq!((c.report.vertices, c.report.triangles, c.report.folds, c.report.closed), (base.report.vertices, base.report.triangles, base.report.folds, base.report.closed));
    }
}

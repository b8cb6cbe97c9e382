//! Every good model in ../shared/models, both structures: with twists `approx` and `interp` the
//! surface is G1 (max normal angle ≤ 1e-4°) and watertight (gap ≤ 1e-12), and the output is a
//! closed, clean two-manifold for closed input (checked by quality::check_mesh); with twist `none`
//! the G1 deviation is reported and clearly larger where non-four-sided patches meet.

use gbsurf::api::{convert_file, ConvertOptions, Method, Twist};
use gbsurf::quality::check_mesh;

const MODELS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/models");

fn models() -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(MODELS)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "obj"))
        .map(|p| p.to_string_lossy().into_owned())
        .collect();
    v.sort();
    assert!(v.len() >= 10, "{v:?}");
    v
}

#[test]
fn good_models_are_g1_and_watertight() {
    for path in models() {
        let closed_input = gbsurf::mesh::read_mesh(&path).unwrap().is_closed();
        for method in [Method::Dual, Method::Topology] {
            for twist in [Twist::Approx, Twist::Interp] {
                let opts = ConvertOptions { method, twist, resolution: 4, ..ConvertOptions::triangles_r8() };
                let c = convert_file(&path, &opts, None).unwrap_or_else(|e| panic!("{path} {method}: {e}"));
                let what = format!("{path} {method} {}", twist.name());
                let r = &c.report;
                assert!(r.max_g1_deg <= 1e-4, "{what}: max G1 {}°", r.max_g1_deg);
                assert!(r.max_boundary_gap <= 1e-12, "{what}: gap {}", r.max_boundary_gap);
                let chk = check_mesh(&c.mesh.positions, &c.mesh.triangles);
                assert!(chk.is_two_manifold(), "{what}: {chk:?}");
                assert_eq!(chk.duplicate_vertices, 0, "{what}");
                assert_eq!(chk.zero_area_triangles, 0, "{what}");
                assert_eq!(r.closed, closed_input, "{what}");
                assert_eq!(chk.boundary_edges == 0, closed_input, "{what}");
                if closed_input {
                    assert!(chk.is_clean_closed(), "{what}: {chk:?}");
                }
                // Report consistency.
                assert_eq!(r.vertices, c.mesh.positions.len());
                assert_eq!(r.triangles, c.mesh.triangles.len());
                assert_eq!(r.sides_histogram.values().sum::<usize>(), r.patches);
                let s = c.surface.as_ref().unwrap();
                assert_eq!(s.patches.len(), r.patches);
                // Per-vertex arrays are complete and finite; G1 deviation only on shared boundaries.
                let m = &c.mesh;
                for a in [&m.mean_curvature, &m.gaussian_curvature, &m.g1_deviation_deg] {
                    assert_eq!(a.len(), m.positions.len());
                    assert!(a.iter().all(|x| x.is_finite()), "{what}");
                }
                assert!(m.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-9), "{what}");
                assert!(m.patch.iter().all(|&p| (p as usize) < r.patches));
                let max_vertex_g1 = m.g1_deviation_deg.iter().cloned().fold(0.0, f64::max);
                assert_eq!(max_vertex_g1, r.max_g1_deg, "{what}");
            }
        }
    }
}

#[test]
fn twist_none_is_reported_and_larger_on_non_quad_junctions() {
    // Junctions (network nodes) are the mesh faces for the dual structure and the mesh vertices
    // for the topology structure. Where only four-sided patches meet four at a node (all-quad
    // faces in the dual, valence-4 vertices in the topology structure) the first-approximation
    // twists are already G1; elsewhere the deviation is reported and clearly larger.
    let g1 = |model: &str, method: Method, twist: Twist| {
        let path = format!("{MODELS}/{model}.obj");
        let c = convert_file(&path, &ConvertOptions { method, twist, resolution: 4, ..ConvertOptions::triangles_r8() }, None).unwrap();
        assert!(c.report.closed);
        assert!(c.report.max_boundary_gap <= 1e-12);
        (c.report.max_g1_deg, c.report.mean_g1_deg)
    };
    for (model, method) in [
        ("dodecahedron", Method::Dual),    // pentagonal faces
        ("octahedron", Method::Dual),      // triangular faces
        ("house", Method::Dual),
        ("cube", Method::Topology),        // valence-3 vertices
        ("dodecahedron", Method::Topology),
        ("star_prism", Method::Topology),
    ] {
        let (none, mean) = g1(model, method, Twist::None);
        let (interp, _) = g1(model, method, Twist::Interp);
        assert!(none > 1.0 && none > 1e4 * interp.max(1e-12), "{model} {method}: none {none}°, interp {interp}°");
        assert!(mean > 0.0);
    }
    // All junctions quad: the torus (both structures), the cube's dual (quad faces).
    for (model, method) in [("torus", Method::Dual), ("torus", Method::Topology), ("cube", Method::Dual)] {
        let (none, _) = g1(model, method, Twist::None);
        assert!(none <= 1e-4, "{model} {method}: none {none}°");
    }
}

#[test]
fn subdivision_methods_on_good_models() {
    for path in models() {
        let closed_input = gbsurf::mesh::read_mesh(&path).unwrap().is_closed();
        for method in [Method::CatmullClark, Method::DooSabin] {
            let c = convert_file(&path, &ConvertOptions { method, levels: 2, ..ConvertOptions::triangles_r8() }, None).unwrap_or_else(|e| panic!("{path} {method}: {e}"));
            let chk = check_mesh(&c.mesh.positions, &c.mesh.triangles);
            assert!(chk.is_two_manifold(), "{path} {method}: {chk:?}");
            assert_eq!(c.report.closed, closed_input, "{path} {method}");
            assert!(c.surface.is_none());
            assert_eq!(c.report.max_g1_deg, 0.0);
            let faces = gbsurf::mesh::read_mesh(&path).unwrap().n_faces();
            assert!(c.mesh.patch.iter().all(|&p| (p as usize) < faces), "{path} {method}");
            assert!(c.mesh.triangle_patch.iter().all(|&p| (p as usize) < faces));
        }
    }
}

#[test]
fn progress_is_monotone_and_cancel_works() {
    let path = format!("{MODELS}/torus.obj");
    let mut seen = Vec::new();
    let mut cb = |f: f32| {
        seen.push(f);
        true
    };
    convert_file(&path, &ConvertOptions::triangles_r8(), Some(&mut cb)).unwrap();
    assert!(seen.windows(2).all(|w| w[0] <= w[1]), "{seen:?}");
    assert_eq!(seen.first(), Some(&0.0));
    assert_eq!(seen.last(), Some(&1.0));
    let mut stop = |f: f32| f < 0.5;
    let e = convert_file(&path, &ConvertOptions::triangles_r8(), Some(&mut stop)).unwrap_err();
    assert!(matches!(e, gbsurf::api::ConvertError::Cancelled), "{e}");
}

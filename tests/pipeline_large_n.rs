//! Large faces and valences (n = 1000): a face of 1000 sides and a vertex of valence 1000
//! convert to valid surfaces. Not timed (the cost per sample is O(n), see
//! docs/math.md#cost-per-point); before the O(n) Wachspress coordinates these took minutes.

use gbsurf::api::{convert, ConvertOptions, Method};
use gbsurf::gb::{Domain, GbBasisEvaluator, WeightForm};
use gbsurf::mesh::generate::{cone, polygon, prism};
use gbsurf::DVec2;

fn opts(method: Method) -> ConvertOptions {
    ConvertOptions { method, resolution: 1, ..ConvertOptions::triangles_r8() }
}

#[test]
fn cone_with_apex_of_valence_1000_converts_valid() {
    let c = convert(&cone(1000).unwrap(), &opts(Method::Dual), None).unwrap();
    assert!(c.report.closed && c.report.valid, "{:?}", c.report.valid);
    assert!(c.report.vertices >= 1000);
}

#[test]
fn face_of_1000_sides_converts_valid() {
    let c = convert(&polygon(1000).unwrap(), &opts(Method::Topology), None).unwrap();
    assert!(c.report.valid);
    assert!(c.report.vertices >= 1000);
}

#[test]
fn generators_reject_fewer_than_three_sides() {
    assert!(polygon(2).is_err() && cone(2).is_err() && prism(1).is_err());
    let p = prism(5).unwrap();
    assert_eq!((p.positions.len(), p.faces.len()), (10, 7));
    let c = cone(7).unwrap();
    assert_eq!((c.positions.len(), c.faces.len(), c.faces[7].len()), (8, 8, 7));
}

/// The basis of a 1024-sided patch (the `.gbp` maximum) is a partition of unity with finite
/// derivatives at the centre, inside and on the boundary.
#[test]
fn basis_of_1024_sides_is_a_partition_of_unity() {
    let n = 1024;
    let mut ev = GbBasisEvaluator::new(n, 3).unwrap();
    let dom = Domain::regular(n).unwrap();
    for uv in [DVec2::ZERO, dom.side_point(5, 0.5) * 0.5, dom.side_point(9, 0.25), dom.vertex(3)] {
        let b = ev.eval(uv, WeightForm::Squared);
        assert!(b.weights.iter().all(|w| w.is_finite()), "at {uv:?}");
        let sum: f64 = b.weights.iter().map(|w| w.val).sum();
        assert!((sum - 1.0).abs() < 1e-9, "sum {sum} at {uv:?}");
    }
}

/// Patches of more than MAX_UNSPLIT_SIDES sides are split into fans of three-sided patches
/// (docs/math.md#high-valence-split), with a warning; 64 sides are kept. The split surfaces are
/// closed, G1 and valid, every output face keeps its cage face, and the size guard's estimate
/// still bounds the output.
#[test]
fn patches_of_more_than_64_sides_are_split_into_fans() {
    use gbsurf::api::estimate_output;
    use gbsurf::limits::MAX_UNSPLIT_SIDES;
    use gbsurf::mesh::HalfEdgeMesh;
    let quads = |method| ConvertOptions { method, ..ConvertOptions::default() };
    let kept = convert(&polygon(MAX_UNSPLIT_SIDES).unwrap(), &quads(Method::Topology), None).unwrap();
    assert_eq!(kept.surface.as_ref().unwrap().patches.len(), 1);
    assert!(!kept.warnings.iter().any(|w| w.contains("split")));
    let n = MAX_UNSPLIT_SIDES + 1;
    let split = convert(&polygon(n).unwrap(), &quads(Method::Topology), None).unwrap();
    assert_eq!(split.surface.as_ref().unwrap().patches.len(), n);
    assert!(split.warnings.iter().any(|w| w.contains("face 0") && w.contains(&format!("split into {n}"))), "{:?}", split.warnings);
    for method in [Method::Dual, Method::Topology] {
        for (name, mesh) in [("cone", cone(100).unwrap()), ("prism", prism(100).unwrap())] {
            let c = convert(&mesh, &quads(method), None).unwrap();
            let r = &c.report;
            assert!(r.closed && r.max_g1_deg < 1e-4 && r.max_boundary_gap < 1e-9, "{method} {name}: {} {}", r.max_g1_deg, r.max_boundary_gap);
            assert_eq!(r.self_intersections, 0, "{method} {name}");
            // The topology structure folds the cone's base (its boundary sits high on the side
            // and the base patch turns by more than 90°, split or not): only the others are valid.
            assert!(r.valid || (method == Method::Topology && name == "cone"), "{method} {name}");
            // The dual prism has no vertex of valence above 3 (its caps are nodes): nothing split.
            let split = !(method == Method::Dual && name == "prism");
            assert_eq!(c.warnings.iter().any(|w| w.contains("split into 100")), split, "{method} {name}: {:?}", c.warnings);
            assert!(c.mesh.cage_corner.iter().all(|f| f[0] != u32::MAX), "{method} {name}: a face without its cage face");
            let est = estimate_output(&HalfEdgeMesh::from_polymesh(&mesh).unwrap(), &quads(method));
            assert!(est.vertices >= r.vertices as u64, "{method} {name}: estimate {} < {}", est.vertices, r.vertices);
        }
    }
}

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

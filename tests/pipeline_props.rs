//! Property tests: random convex polyhedra (hulls of random points) and random quad-dominant
//! meshes convert without error, closed and G1, with both structures.

use gbsurf::api::{convert, ConvertOptions, Method, Twist};
use gbsurf::mesh::generate::{convex_hull, torus};
use gbsurf::mesh::PolyMesh;
use gbsurf::quality::check_mesh;
use gbsurf::DVec3;
use proptest::prelude::*;

fn check_converts(mesh: &PolyMesh, what: &str) -> Result<(), TestCaseError> {
    for method in [Method::Dual, Method::Topology] {
        for twist in [Twist::Approx, Twist::Interp] {
            let opts = ConvertOptions { method, twist, resolution: 3, ..ConvertOptions::triangles_r8() };
            let c = convert(mesh, &opts, None).map_err(|e| TestCaseError::fail(format!("{what} {method} {}: {e}", twist.name())))?;
            let chk = check_mesh(&c.mesh.positions, &c.mesh.triangles);
            prop_assert!(chk.is_clean_closed(), "{} {} {}: {:?}", what, method, twist.name(), chk);
            prop_assert!(c.report.closed);
            prop_assert!(c.report.max_boundary_gap <= 1e-12, "{} {}: gap {}", what, method, c.report.max_boundary_gap);
            prop_assert!(c.report.max_g1_deg <= 1e-4, "{} {} {}: G1 {}", what, method, twist.name(), c.report.max_g1_deg);
        }
    }
    Ok(())
}

fn point() -> impl Strategy<Value = DVec3> {
    (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64).prop_map(|(x, y, z)| DVec3::new(x, y, z))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]

    #[test]
    fn random_convex_polyhedra(points in prop::collection::vec(point(), 6..24)) {
        let hull = match convex_hull(&points) {
            Ok(h) => h,
            Err(_) => return Ok(()), // (nearly) coplanar samples: no polyhedron
        };
        check_converts(&hull, "hull")?;
    }

    #[test]
    fn random_quad_dominant_tori(
        n_major in 3usize..9,
        n_minor in 3usize..7,
        jitter in prop::collection::vec(point(), 64),
        splits in prop::collection::vec(any::<bool>(), 48),
    ) {
        let mut m = torus(n_major, n_minor, 3.0, 1.0).unwrap();
        for (p, j) in m.positions.iter_mut().zip(&jitter) {
            *p += *j * 0.15;
        }
        // Split some quads into two triangles along a diagonal (quad-dominant, mixed valences).
        let mut faces = Vec::new();
        for (f, face) in m.faces.iter().enumerate() {
            if splits.get(f).copied().unwrap_or(false) && f % 3 == 0 {
                faces.push(vec![face[0], face[1], face[2]]);
                faces.push(vec![face[0], face[2], face[3]]);
            } else {
                faces.push(face.clone());
            }
        }
        m.faces = faces;
        check_converts(&m, "torus")?;
    }

    #[test]
    fn random_subdivided_hulls(points in prop::collection::vec(point(), 6..14)) {
        // One Catmull–Clark step of a hull: all quads, extraordinary vertices of many valences.
        let hull = match convex_hull(&points) {
            Ok(h) => h,
            Err(_) => return Ok(()),
        };
        let quads = gbsurf::subdiv::catmull_clark(&hull, 1).unwrap();
        check_converts(&quads, "quad hull")?;
    }
}

//! Generators: torus and convex hull / convex polyhedra.

use gbsurf::mesh::generate::{convex_hull, merge_coplanar, torus};
use gbsurf::mesh::geometry::{is_convex_polygon, newell_normal, planarity};
use gbsurf::mesh::{read_mesh, HalfEdgeMesh, MeshError};
use gbsurf::{assert_near, DVec3};
use proptest::prelude::*;

const MODELS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/models");

#[test]
fn torus_matches_model_file() {
    let t = torus(12, 8, 2.0, 0.7).unwrap();
    let file = read_mesh(format!("{MODELS}/torus.obj")).unwrap().to_polymesh();
    assert_eq!(t.faces, file.faces);
    assert_near!(t.positions, file.positions, 1e-6);
}

#[test]
fn torus_topology_and_geometry() {
    for (nu, nv) in [(3, 3), (5, 4), (16, 9)] {
        let t = torus(nu, nv, 3.0, 1.0).unwrap();
        let he = HalfEdgeMesh::from_polymesh(&t).unwrap();
        assert_eq!(he.euler_characteristic(), 0);
        assert!(he.is_closed());
        assert_eq!(he.n_faces(), nu * nv);
        assert!(he.vertices().all(|v| he.valence(v) == 4));
        for p in &t.positions {
            // distance from the core circle is r
            let rho = (p.x * p.x + p.y * p.y).sqrt();
            assert_near!(((rho - 3.0).powi(2) + p.z * p.z).sqrt(), 1.0, 1e-12);
        }
        // outward: the enclosed signed volume (divergence theorem over fan triangles) is
        // positive and close to the torus volume 2π²Rr² for the finer meshes
        let mut vol = 0.0;
        for f in &t.faces {
            let p: Vec<DVec3> = f.iter().map(|&i| t.positions[i as usize]).collect();
            for k in 1..p.len() - 1 {
                vol += p[0].dot(p[k].cross(p[k + 1])) / 6.0;
            }
        }
        let exact = 2.0 * std::f64::consts::PI.powi(2) * 3.0;
        assert!(vol > 0.0);
        if nu >= 16 {
            assert!(vol < exact && vol > 0.85 * exact, "{vol} {exact}"); // inscribed: a bit less
        }
    }
    assert!(matches!(torus(2, 8, 2.0, 0.5), Err(MeshError::Degenerate(_))));
    assert!(matches!(torus(8, 8, 1.0, 1.5), Err(MeshError::Degenerate(_))));
}

#[test]
fn hull_of_cube_corners_with_interior_points() {
    let mut pts: Vec<DVec3> = (0..8).map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64)).collect();
    pts.push(DVec3::splat(0.5));
    pts.push(DVec3::new(0.2, 0.3, 0.9));
    let h = convex_hull(&pts).unwrap();
    assert_eq!(h.positions.len(), 8);
    assert_eq!(h.faces.len(), 12);
    let he = HalfEdgeMesh::from_polymesh(&h).unwrap();
    assert_eq!(he.euler_characteristic(), 2);
    let merged = merge_coplanar(&h, 1e-9);
    assert_eq!(merged.faces.len(), 6);
    let he = HalfEdgeMesh::from_polymesh(&merged).unwrap();
    assert_eq!((he.n_vertices(), he.n_edges(), he.n_faces()), (8, 12, 6));
    for f in &merged.faces {
        let q: Vec<DVec3> = f.iter().map(|&i| merged.positions[i as usize]).collect();
        assert_eq!(q.len(), 4);
        assert!(is_convex_polygon(&q));
        assert_near!(planarity(&q), 0.0);
        assert_near!(newell_normal(&q).length(), 2.0);
    }
}

#[test]
fn hull_of_dodecahedron_merges_to_pentagons() {
    let d = read_mesh(format!("{MODELS}/dodecahedron.obj")).unwrap().to_polymesh();
    let h = merge_coplanar(&convex_hull(&d.positions).unwrap(), 1e-6);
    assert_eq!(h.faces.len(), 12);
    assert!(h.faces.iter().all(|f| f.len() == 5));
    assert_eq!(HalfEdgeMesh::from_polymesh(&h).unwrap().euler_characteristic(), 2);
}

#[test]
fn hull_errors() {
    assert!(matches!(convex_hull(&[DVec3::ZERO, DVec3::X, DVec3::Y]), Err(MeshError::Degenerate(_))));
    let flat: Vec<DVec3> = (0..10).map(|i| DVec3::new(i as f64, (i * i) as f64, 0.0)).collect();
    assert!(matches!(convex_hull(&flat), Err(MeshError::Degenerate(_))));
    let mut bad = flat.clone();
    bad[3].z = f64::NAN;
    assert!(matches!(convex_hull(&bad), Err(MeshError::Degenerate(_))));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// Random points: the hull is a valid closed genus-0 mesh, every input point is inside or on
    /// every face plane, and every face is outward (the hull centroid is behind it).
    #[test]
    fn hull_random_points(pts in prop::collection::vec((-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0), 4..120)) {
        let pts: Vec<DVec3> = pts.into_iter().map(|(x, y, z)| DVec3::new(x, y, z)).collect();
        let h = match convex_hull(&pts) {
            Ok(h) => h,
            Err(MeshError::Degenerate(_)) => return Ok(()),
            Err(e) => return Err(TestCaseError::fail(e.to_string())),
        };
        let he = HalfEdgeMesh::from_polymesh(&h).map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert!(he.is_closed());
        prop_assert_eq!(he.euler_characteristic(), 2);
        let c = h.positions.iter().sum::<DVec3>() / h.positions.len() as f64;
        for f in &h.faces {
            let q: Vec<DVec3> = f.iter().map(|&i| h.positions[i as usize]).collect();
            let n = newell_normal(&q).normalize();
            prop_assert!(n.dot(q[0] - c) > 0.0);
            for p in &pts {
                prop_assert!(n.dot(*p - q[0]) <= 1e-9);
            }
        }
        let merged = merge_coplanar(&h, 1e-12);
        prop_assert_eq!(HalfEdgeMesh::from_polymesh(&merged).map(|m| m.euler_characteristic()), Ok(2));
    }
}

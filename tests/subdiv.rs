//! Catmull–Clark and Doo–Sabin subdivision (seed 000 §1.2.1, §6.4): hand-computed first levels
//! on the cube and the open saddle grid, counts, closedness, Euler characteristic, boundary
//! rules, face ancestry, the half-edge input, invalid input, and affine invariance as a property.

use gbsurf::mesh::{HalfEdgeMesh, MeshError, PolyMesh};
use gbsurf::subdiv::{
    catmull_clark, doo_sabin, subdivide, SubdivError, Subdivided, SubdivisionScheme,
};
use gbsurf::{assert_near, DVec3};
use proptest::prelude::*;
use std::collections::HashMap;

const MODELS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/models");

/// Minimal OBJ reader for the test models (`v x y z`, `f a[/..] b ...`, 1-based), in f64.
fn load(name: &str) -> PolyMesh {
    let text = std::fs::read_to_string(format!("{MODELS}/{name}")).unwrap();
    let mut m = PolyMesh::default();
    for line in text.lines() {
        let mut it = line.split_whitespace();
        match it.next() {
            Some("v") => {
                let c: Vec<f64> = it.take(3).map(|s| s.parse().unwrap()).collect();
                m.positions.push(DVec3::new(c[0], c[1], c[2]));
            }
            Some("f") => m.faces.push(
                it.map(|s| s.split('/').next().unwrap().parse::<u32>().unwrap() - 1)
                    .collect(),
            ),
            _ => {}
        }
    }
    m
}

const CLOSED_MODELS: [&str; 12] = [
    "cube.obj",
    "cube_extruded.obj",
    "cube_nonplanar.obj",
    "cube_corner_pulled.obj",
    "dodecahedron.obj",
    "house.obj",
    "l_prism.obj",
    "octahedron.obj",
    "prism3.obj",
    "pyramid.obj",
    "star_prism.obj",
    "torus.obj",
];

/// Directed-edge use counts: (undirected edge count, boundary edge count); panics (test failure)
/// if a directed edge is used twice.
fn edge_stats(m: &PolyMesh) -> (usize, usize) {
    let mut directed: HashMap<(u32, u32), usize> = HashMap::new();
    for f in &m.faces {
        for i in 0..f.len() {
            *directed.entry((f[i], f[(i + 1) % f.len()])).or_default() += 1;
        }
    }
    assert!(
        directed.values().all(|&c| c == 1),
        "a directed edge is used twice"
    );
    let boundary = directed
        .keys()
        .filter(|&&(a, b)| !directed.contains_key(&(b, a)))
        .count();
    let interior = directed.len() - boundary;
    (interior / 2 + boundary, boundary)
}

fn euler(m: &PolyMesh) -> i64 {
    let (e, _) = edge_stats(m);
    let mut used = vec![false; m.positions.len()];
    m.faces
        .iter()
        .flatten()
        .for_each(|&v| used[v as usize] = true);
    let v = used.iter().filter(|&&u| u).count();
    v as i64 - e as i64 + m.faces.len() as i64
}

/// The index of the output vertex at `p` (exactly one within 1e-12).
fn find(m: &PolyMesh, p: DVec3) -> usize {
    let hits: Vec<usize> = (0..m.positions.len())
        .filter(|&i| (m.positions[i] - p).length() <= 1e-12)
        .collect();
    assert_eq!(hits.len(), 1, "point {p:?} found {} times", hits.len());
    hits[0]
}

fn boundary_vertices(m: &PolyMesh) -> Vec<u32> {
    let mut directed = std::collections::HashSet::new();
    for f in &m.faces {
        for i in 0..f.len() {
            directed.insert((f[i], f[(i + 1) % f.len()]));
        }
    }
    let mut out: Vec<u32> = directed
        .iter()
        .filter(|&&(a, b)| !directed.contains(&(b, a)))
        .map(|&(a, _)| a)
        .collect();
    out.sort();
    out.dedup();
    out
}

// ---------------------------------------------------------------- Catmull–Clark, cube ±1

#[test]
fn catmull_clark_cube_first_level_by_hand() {
    let cube = load("cube.obj");
    let s = catmull_clark(&cube, 1).unwrap();
    assert_eq!((s.positions.len(), s.faces.len()), (26, 24));
    // Vertex points: n = 3, Q = (1/3)(1,1,1) (face centres), R = (2/3)(1,1,1) (edge midpoints),
    // V' = (Q + 2R + 0·V)/3 = (1/3 + 4/3)/3 = 5/9 per coordinate.
    for v in 0..8 {
        assert_near!(s.positions[v], cube.positions[v] * (5.0 / 9.0));
    }
    // Edge points: edge (1,1,−1)–(1,1,1) with faces x = 1 and y = 1:
    // ((1,1,−1) + (1,1,1) + (1,0,0) + (0,1,0))/4 = (3/4, 3/4, 0); all 12 are sign/axis permutations.
    let mut edge_points: Vec<DVec3> = s.positions[8..20].to_vec();
    for p in &edge_points {
        let mut a = [p.x.abs(), p.y.abs(), p.z.abs()];
        a.sort_by(f64::total_cmp);
        assert_near!(a.to_vec(), vec![0.0, 0.75, 0.75]);
    }
    edge_points.sort_by(|a, b| a.to_array().partial_cmp(&b.to_array()).unwrap());
    edge_points.dedup_by(|a, b| (*a - *b).length() < 1e-12);
    assert_eq!(edge_points.len(), 12);
    // Face points at the face centres, in face order.
    let centres = [
        DVec3::new(0.0, 0.0, -1.0),
        DVec3::new(0.0, 0.0, 1.0),
        DVec3::new(0.0, -1.0, 0.0),
        DVec3::new(0.0, 1.0, 0.0),
        DVec3::new(-1.0, 0.0, 0.0),
        DVec3::new(1.0, 0.0, 0.0),
    ];
    assert_near!(s.positions[20..26].to_vec(), centres.to_vec());
    // Face 0 = (1 3 4 2) → first quad [V'0, E'(0→2), F'0, E'(1→0)].
    let q = &s.faces[0];
    assert_eq!(q[0], 0);
    assert_near!(s.positions[q[1] as usize], DVec3::new(-0.75, 0.0, -0.75));
    assert_near!(s.positions[q[2] as usize], DVec3::new(0.0, 0.0, -1.0));
    assert_near!(s.positions[q[3] as usize], DVec3::new(0.0, -0.75, -0.75));
}

#[test]
fn catmull_clark_cube_second_level_corner() {
    // Second level at a corner (all new vertices have valence 3 or 4): the corner is
    // 5/9·(5/9) = 25/81 times V plus contributions; computed by hand for V = (1,1,1):
    // level-1 neighbours of V' = (5/9)(1,1,1): edge points e = (3/4,3/4,0) (perms), faces are
    // quads [V', e1, f, e2] with f = (1,0,0) (perms). Level-2 face point of quad
    // [V', (3/4,3/4,0), (1,0,0), (3/4,0,3/4)] = (5/9+3/4+1+3/4, 5/9+3/4, 5/9+3/4)/4;
    // Q, R by symmetry per coordinate, V'' = (Q + 2R)/3 (n = 3):
    let v = 5.0 / 9.0;
    let fx = (v + 0.75 + 1.0 + 0.75) / 4.0; // coordinate along the face normal
    let fo = (v + 0.75) / 4.0; // the two other coordinates
    let q = (fx + 2.0 * fo) / 3.0; // mean of the 3 face points, per coordinate (by symmetry)
    let r = (v + (0.75 + 0.75 + 0.0) / 3.0) / 2.0; // mean of the 3 edge midpoints
    let expected = (q + 2.0 * r) / 3.0;
    let s = catmull_clark(&load("cube.obj"), 2).unwrap();
    assert_near!(s.positions[7], DVec3::splat(expected));
    assert_eq!((s.positions.len(), s.faces.len()), (98, 96));
}

// ---------------------------------------------------------------- Doo–Sabin, cube ±1

#[test]
fn doo_sabin_cube_first_level_by_hand() {
    let cube = load("cube.obj");
    let s = doo_sabin(&cube, 1).unwrap();
    // Quad weights α = (9, 3, 1, 3)/16. Corner (1,1,1) of face x = 1 with neighbours (1,−1,1),
    // (1,1,−1) and opposite (1,−1,−1): y = (9 − 3 + 3 − 1)/16 = 1/2, z likewise, x = 1.
    // So every new point has one coordinate ±1 and two ±1/2, lying on the face's plane.
    assert_eq!(s.positions.len(), 24);
    let p = s.positions[find(&s, DVec3::new(1.0, 0.5, 0.5))];
    assert_near!(p, DVec3::new(1.0, 0.5, 0.5));
    for (f, face) in cube.faces.iter().enumerate() {
        let centre = face
            .iter()
            .map(|&v| cube.positions[v as usize])
            .sum::<DVec3>()
            / 4.0;
        for (i, &v) in face.iter().enumerate() {
            let expected = 0.5 * (cube.positions[v as usize] + centre);
            assert_near!(s.positions[4 * f + i], expected);
        }
    }
    // F-faces 6, E-faces 12, V-faces 8 (triangles).
    assert_eq!(s.faces.len(), 26);
    assert_eq!(s.faces.iter().filter(|f| f.len() == 3).count(), 8);
    // The V-face of vertex 7 = (1,1,1) is the triangle of the three points (1,½,½) perms.
    let tri: Vec<DVec3> = s.faces[18 + 7]
        .iter()
        .map(|&i| s.positions[i as usize])
        .collect();
    for p in &tri {
        let mut a = p.to_array();
        a.sort_by(f64::total_cmp);
        assert_near!(a.to_vec(), vec![0.5, 0.5, 1.0]);
    }
    // Counter-clockwise seen from outside: the normal points along +(1,1,1).
    let n = (tri[1] - tri[0]).cross(tri[2] - tri[0]);
    assert!(n.dot(DVec3::ONE) > 0.0);
}

#[test]
fn doo_sabin_weights_by_hand() {
    use gbsurf::subdiv::doo_sabin_weights;
    assert_near!(
        doo_sabin_weights(4),
        vec![9.0 / 16.0, 3.0 / 16.0, 1.0 / 16.0, 3.0 / 16.0]
    );
    assert_near!(doo_sabin_weights(3), vec![2.0 / 3.0, 1.0 / 6.0, 1.0 / 6.0]);
    // n = 5: α0 = 1/4 + 1/4 = 1/2, α1 = (3 + 2cos72°)/20.
    let w = doo_sabin_weights(5);
    assert_near!(w[0], 0.5);
    assert_near!(w[1], (3.0 + 2.0 * (72f64).to_radians().cos()) / 20.0);
    assert_near!(w[1], w[4]);
}

#[test]
fn doo_sabin_triangle_corner_on_octahedron() {
    // Triangles: α = (2/3, 1/6, 1/6).
    let m = load("octahedron.obj");
    let s = doo_sabin(&m, 1).unwrap();
    let f = &m.faces[0];
    let p = |i: usize| m.positions[f[i] as usize];
    assert_near!(s.positions[0], p(0) * (2.0 / 3.0) + (p(1) + p(2)) / 6.0);
    assert_near!(s.positions[1], p(1) * (2.0 / 3.0) + (p(0) + p(2)) / 6.0);
}

// ---------------------------------------------------------------- counts, closedness, Euler

#[test]
fn counts_after_one_and_two_levels_on_cube() {
    let cube = load("cube.obj");
    let cc: Vec<(usize, usize, usize)> = (1..=2)
        .map(|l| {
            let s = catmull_clark(&cube, l).unwrap();
            (s.positions.len(), edge_stats(&s).0, s.faces.len())
        })
        .collect();
    // V' = V+E+F, E' = 2E + Σ|f|, F' = Σ|f|: (8,12,6) → (26,48,24) → (98,192,96).
    assert_eq!(cc, vec![(26, 48, 24), (98, 192, 96)]);
    let ds: Vec<(usize, usize, usize)> = (1..=2)
        .map(|l| {
            let s = doo_sabin(&cube, l).unwrap();
            (s.positions.len(), edge_stats(&s).0, s.faces.len())
        })
        .collect();
    // V' = 2E, E' = 4E, F' = F+E+V: (8,12,6) → (24,48,26) → (96,192,98).
    assert_eq!(ds, vec![(24, 48, 26), (96, 192, 98)]);
}

#[test]
fn closed_stays_closed_and_euler_is_kept_on_all_models() {
    for name in CLOSED_MODELS {
        let m = load(name);
        let (e, b) = edge_stats(&m);
        assert_eq!(b, 0, "{name} is closed");
        let chi = euler(&m);
        let sum: usize = m.faces.iter().map(Vec::len).sum();
        for scheme in [SubdivisionScheme::CatmullClark, SubdivisionScheme::DooSabin] {
            for levels in 1..=2 {
                let s = subdivide(&m, scheme, levels).unwrap().mesh;
                assert_eq!(edge_stats(&s).1, 0, "{name} {scheme:?} {levels}: open");
                assert_eq!(euler(&s), chi, "{name} {scheme:?} {levels}: Euler");
            }
            let s = subdivide(&m, scheme, 1).unwrap().mesh;
            let (v, f) = (m.positions.len(), m.faces.len());
            match scheme {
                SubdivisionScheme::CatmullClark => {
                    assert_eq!(s.positions.len(), v + e + f, "{name}");
                    assert_eq!(s.faces.len(), sum, "{name}");
                    assert!(s.faces.iter().all(|q| q.len() == 4));
                }
                SubdivisionScheme::DooSabin => {
                    assert_eq!(s.positions.len(), sum, "{name}");
                    assert_eq!(s.faces.len(), f + e + v, "{name}");
                    assert_eq!(edge_stats(&s).0, 4 * e, "{name}");
                }
            }
        }
    }
}

#[test]
fn zero_levels_is_a_copy() {
    let m = load("house.obj");
    assert_eq!(catmull_clark(&m, 0).unwrap(), m);
    assert_eq!(doo_sabin(&m, 0).unwrap(), m);
}

// ---------------------------------------------------------------- open grid (saddle z = 0.15(x²−y²))

#[test]
fn catmull_clark_open_grid_boundary_rules() {
    let m = load("grid_open.obj");
    assert_eq!(euler(&m), 1);
    let s = catmull_clark(&m, 1).unwrap();
    assert_eq!(
        (s.positions.len(), edge_stats(&s).0, s.faces.len()),
        (81, 144, 64)
    );
    assert_eq!(euler(&s), 1);
    assert_eq!(edge_stats(&s).1, 32);
    // Corner (valence 2) fixed.
    assert_near!(s.positions[0], DVec3::new(-2.0, -2.0, 0.0));
    assert_near!(s.positions[24], DVec3::new(2.0, 2.0, 0.0));
    // Boundary vertex 2 = (0,−2,−0.6) with neighbours (±1,−2,−0.45): (a + 6V + b)/8,
    // z = (−0.45·2 − 3.6)/8 = −0.5625.
    assert_near!(s.positions[2], DVec3::new(0.0, -2.0, -0.5625));
    // Boundary edge point = midpoint of (−2,−2,0) and (−1,−2,−0.45).
    find(&s, DVec3::new(-1.5, -2.0, -0.225));
    // Interior rules on a uniform grid are the tensor cubic B-spline masks, which reproduce the
    // quadratic z = c(x² − y²) with c = 0.15 exactly (x² ↦ x² + 1/4 under (1,6,1)/8 in both
    // directions, cancelling in x² − y²). Boundary rules are the 1D masks along the boundary:
    // z = c(x² + 1/4 − 4) on y = ±2, z = c(4 − y² − 1/4) on x = ±2, corners fixed.
    let bnd = boundary_vertices(&s);
    assert_eq!(bnd.len(), 32);
    let c = 0.15;
    for (i, p) in s.positions.iter().enumerate() {
        let expected = if !bnd.contains(&(i as u32)) {
            c * (p.x * p.x - p.y * p.y)
        } else if p.x.abs() == 2.0 && p.y.abs() == 2.0 {
            0.0
        } else if p.y.abs() == 2.0 {
            c * (p.x * p.x + 0.25 - 4.0)
        } else {
            assert_eq!(p.x.abs(), 2.0, "boundary point {p:?} left the boundary");
            c * (4.0 - p.y * p.y - 0.25)
        };
        assert_near!(p.z, expected, 1e-12, "vertex {i} at {p:?}");
    }
    // Two levels: still 4 corners fixed, boundary stays in the four boundary planes.
    let s2 = catmull_clark(&m, 2).unwrap();
    assert_eq!(euler(&s2), 1);
    for &i in &boundary_vertices(&s2) {
        let p = s2.positions[i as usize];
        assert!(p.x.abs() == 2.0 || p.y.abs() == 2.0, "{p:?}");
    }
    assert_near!(s2.positions[0], DVec3::new(-2.0, -2.0, 0.0));
}

#[test]
fn doo_sabin_open_grid_boundary_rules() {
    let m = load("grid_open.obj");
    let s = doo_sabin(&m, 1).unwrap();
    // V' = Σ|f| + 2·16 = 96; F' = 16 F + 24 E + 16 boundary quads + 9 + 16 V-faces = 81;
    // E' = 176 (χ = 96 − 176 + 81 = 1), 32 boundary edges (Chaikin polygon of 16 edges).
    assert_eq!(
        (s.positions.len(), edge_stats(&s).0, s.faces.len()),
        (96, 176, 81)
    );
    assert_eq!(edge_stats(&s).1, 32);
    assert_eq!(euler(&s), 1);
    // Corner point of face 0 = (v0 v1 v6 v5) at v0: (9v0 + 3v1 + 3v5 + v6)/16 =
    // ((−18−3−6−1)/16, same, (0 − 1.35 + 1.35 + 0)/16) = (−1.75, −1.75, 0).
    assert_near!(s.positions[0], DVec3::new(-1.75, -1.75, 0.0));
    // Chaikin points of boundary edge (−2,−2,0)→(−1,−2,−0.45): 3/4·a + 1/4·b, 1/4·a + 3/4·b.
    let b = boundary_vertices(&s);
    assert!(b.contains(&(find(&s, DVec3::new(-1.75, -2.0, -0.1125)) as u32)));
    assert!(b.contains(&(find(&s, DVec3::new(-1.25, -2.0, -0.3375)) as u32)));
    // Every new boundary vertex lies on the old boundary polygon, the corner is cut
    // (the corner V-face is the triangle [(−2,−1.75,..), P, (−1.75,−2,..)]).
    for &i in &b {
        let p = s.positions[i as usize];
        assert!(p.x.abs() == 2.0 || p.y.abs() == 2.0, "{p:?}");
    }
    assert_eq!(s.faces.iter().filter(|f| f.len() == 3).count(), 4);
    let s2 = doo_sabin(&m, 2).unwrap();
    assert_eq!(euler(&s2), 1);
    assert_eq!(edge_stats(&s2).1, 64);
}

// ---------------------------------------------------------------- face ancestry, half-edge input

/// Doo–Sabin's rule, recomputed from one level's output: a face descends from the old face of
/// its first new corner point (points `0..Σ|f|` are the corners, faces in order).
fn doo_sabin_parents(old: &PolyMesh, new: &PolyMesh) -> Vec<u32> {
    let corner_face: Vec<u32> = old
        .faces
        .iter()
        .enumerate()
        .flat_map(|(f, face)| std::iter::repeat(f as u32).take(face.len()))
        .collect();
    new.faces
        .iter()
        .map(|face| {
            let c = face
                .iter()
                .find(|&&v| (v as usize) < corner_face.len())
                .unwrap();
            corner_face[*c as usize]
        })
        .collect()
}

#[test]
fn face_ancestry_over_levels() {
    for name in [
        "house.obj",
        "grid_open.obj",
        "torus.obj",
        "bad/isolated_vertex.obj",
    ] {
        let m = load(name);
        for scheme in [SubdivisionScheme::CatmullClark, SubdivisionScheme::DooSabin] {
            let zero = subdivide(&m, scheme, 0).unwrap();
            assert_eq!(zero.mesh, m);
            assert_eq!(
                zero.face_ancestor,
                (0..m.faces.len() as u32).collect::<Vec<_>>()
            );
            let mut prev = m.clone();
            let mut expected: Vec<u32> = (0..m.faces.len() as u32).collect();
            for levels in 1..=3 {
                let s = subdivide(&m, scheme, levels).unwrap();
                let one = subdivide(&prev, scheme, 1).unwrap();
                assert_eq!(s.mesh, one.mesh, "{name} {scheme:?} {levels}");
                let parents: Vec<u32> = match scheme {
                    // Children of a face are consecutive, one per corner.
                    SubdivisionScheme::CatmullClark => prev
                        .faces
                        .iter()
                        .enumerate()
                        .flat_map(|(f, face)| std::iter::repeat(f as u32).take(face.len()))
                        .collect(),
                    SubdivisionScheme::DooSabin => doo_sabin_parents(&prev, &s.mesh),
                };
                assert_eq!(one.face_ancestor, parents, "{name} {scheme:?} {levels}");
                expected = parents.iter().map(|&f| expected[f as usize]).collect();
                assert_eq!(s.face_ancestor, expected, "{name} {scheme:?} {levels}");
                prev = s.mesh;
            }
        }
    }
}

#[test]
fn half_edge_input_equals_face_list_input() {
    for name in ["cube.obj", "house.obj", "grid_open.obj", "torus.obj"] {
        let m = load(name);
        let he = HalfEdgeMesh::from_polymesh(&m).unwrap();
        for scheme in [SubdivisionScheme::CatmullClark, SubdivisionScheme::DooSabin] {
            for levels in 0..=2 {
                assert_eq!(
                    subdivide(&he, scheme, levels).unwrap(),
                    subdivide(&m, scheme, levels).unwrap(),
                    "{name} {scheme:?} {levels}"
                );
            }
        }
    }
    // A half-edge mesh has no unused vertices: its numbering is the cleaned one.
    let m = load("bad/isolated_vertex.obj");
    let he = HalfEdgeMesh::from_polymesh(&m).unwrap();
    let s = catmull_clark(&he, 1).unwrap();
    assert_eq!(s, catmull_clark(&he.to_polymesh(), 1).unwrap());
    assert_eq!(s.positions.len(), 8 + 12 + 6);
}

// ---------------------------------------------------------------- invalid input

/// The mesh validator's error, as subdivision reports it.
fn mesh_err(e: MeshError) -> SubdivError {
    SubdivError::Mesh(e)
}

#[test]
fn invalid_input_is_a_typed_error() {
    // The input is checked by the mesh layer's validator; errors name the element.
    let cube = load("cube.obj");
    let cases: Vec<(PolyMesh, SubdivError)> = vec![
        (
            load("bad/index_out_of_range.obj"),
            mesh_err(MeshError::IndexOutOfRange {
                face: 5,
                corner: 3,
                index: 41,
                n_vertices: 8,
                line: None,
            }),
        ),
        (
            load("bad/flipped_face.obj"),
            mesh_err(MeshError::InconsistentOrientation {
                edge: (5, 7),
                faces: (1, 5),
                line: None,
            }),
        ),
        (
            load("bad/bowtie_vertex.obj"),
            mesh_err(MeshError::NonManifoldVertex {
                vertex: 0,
                fans: 2,
                line: None,
            }),
        ),
        (
            PolyMesh::new(cube.positions.clone(), vec![vec![0, 1]]),
            mesh_err(MeshError::FaceTooSmall {
                face: 0,
                len: 2,
                line: None,
            }),
        ),
        (
            PolyMesh::new(cube.positions.clone(), vec![vec![0, 1, 2], vec![3, 4, 3]]),
            mesh_err(MeshError::RepeatedIndex {
                face: 1,
                vertex: 3,
                line: None,
            }),
        ),
        (
            {
                let mut m = cube.clone();
                m.positions[3].y = f64::NAN;
                m
            },
            mesh_err(MeshError::NonFiniteCoordinate {
                vertex: 3,
                axis: 1,
                value: f64::NAN,
                line: None,
            }),
        ),
        (
            {
                let mut m = cube.clone();
                m.positions[6].z = f64::INFINITY;
                m
            },
            mesh_err(MeshError::NonFiniteCoordinate {
                vertex: 6,
                axis: 2,
                value: f64::INFINITY,
                line: None,
            }),
        ),
    ];
    for (m, err) in cases {
        for scheme in [SubdivisionScheme::CatmullClark, SubdivisionScheme::DooSabin] {
            for levels in 0..=1 {
                // Debug text compares every field, NaN included.
                assert_eq!(
                    format!("{:?}", subdivide(&m, scheme, levels)),
                    format!("{:?}", Err::<Subdivided, _>(err.clone())),
                    "{scheme:?} {levels}"
                );
            }
        }
    }
    let e = load("bad/nonmanifold_edge.obj");
    assert_eq!(
        catmull_clark(&e, 1),
        Err(mesh_err(MeshError::NonManifoldEdge {
            edge: (0, 1),
            faces: vec![0, 2, 6, 7],
            line: None,
        }))
    );
    // Two triangles glued along all three edges: the same face twice, rejected by the validator.
    let pillow = PolyMesh::new(
        cube.positions[..3].to_vec(),
        vec![vec![0, 1, 2], vec![0, 2, 1]],
    );
    for scheme in [SubdivisionScheme::CatmullClark, SubdivisionScheme::DooSabin] {
        assert_eq!(
            subdivide(&pillow, scheme, 1),
            Err(mesh_err(MeshError::DuplicateFace {
                face: 1,
                first: 0,
                line: None,
            }))
        );
    }
    // A valid mesh with an interior vertex of valence 2: the cube with its edge 1–3 split by
    // vertex 8 (the two faces at that edge become pentagons). Catmull–Clark handles it,
    // Doo–Sabin cannot (its V-face would have two sides).
    let mut split = cube.clone();
    let (a, b) = (split.positions[1], split.positions[3]);
    split.positions.push(0.5 * (a + b));
    for face in &mut split.faces {
        for i in 0..face.len() {
            let (p, q) = (face[i], face[(i + 1) % face.len()]);
            if (p, q) == (1, 3) || (p, q) == (3, 1) {
                face.insert(i + 1, 8);
                break;
            }
        }
    }
    assert_eq!(split.faces.iter().filter(|f| f.len() == 5).count(), 2);
    assert_eq!(
        doo_sabin(&split, 1),
        Err(SubdivError::InteriorValenceTwo { vertex: 8 })
    );
    let cc = catmull_clark(&split, 1).unwrap();
    assert_eq!(euler(&cc), 2);
    assert_eq!(edge_stats(&cc).1, 0);
    // Messages name the element; validator errors pass through unchanged.
    assert_eq!(
        mesh_err(MeshError::NonManifoldVertex {
            vertex: 7,
            fans: 2,
            line: None
        })
        .to_string(),
        "vertex 7 is non-manifold: its faces form 2 separate fans"
    );
    assert_eq!(
        SubdivError::InteriorValenceTwo { vertex: 8 }.to_string(),
        "vertex 8 is an interior vertex of valence 2; Doo–Sabin would make a two-sided face"
    );
}

#[test]
fn isolated_vertex_is_kept_by_catmull_clark_and_dropped_by_doo_sabin() {
    let m = load("bad/isolated_vertex.obj");
    let cc = catmull_clark(&m, 1).unwrap();
    assert_near!(cc.positions[8], DVec3::splat(5.0));
    assert_eq!(cc.positions.len(), 9 + 12 + 6);
    let ds = doo_sabin(&m, 1).unwrap();
    assert_eq!(ds.positions.len(), 24);
}

// ---------------------------------------------------------------- properties

fn affine(m: &PolyMesh, a: [[f64; 3]; 3], t: [f64; 3]) -> PolyMesh {
    let f = |p: DVec3| {
        DVec3::new(
            a[0][0] * p.x + a[0][1] * p.y + a[0][2] * p.z + t[0],
            a[1][0] * p.x + a[1][1] * p.y + a[1][2] * p.z + t[1],
            a[2][0] * p.x + a[2][1] * p.y + a[2][2] * p.z + t[2],
        )
    };
    PolyMesh::new(m.positions.iter().map(|&p| f(p)).collect(), m.faces.clone())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    /// Both schemes are affine combinations of the input points: subdividing an affine image
    /// equals the affine image of the subdivision, and the topology does not depend on positions.
    #[test]
    fn subdivision_commutes_with_affine_maps(
        model in 0usize..CLOSED_MODELS.len(),
        a in prop::array::uniform3(prop::array::uniform3(-2.0f64..2.0)),
        t in prop::array::uniform3(-3.0f64..3.0),
        jitter in prop::collection::vec(-0.2f64..0.2, 3 * 64),
        ds in any::<bool>(),
    ) {
        let mut m = load(CLOSED_MODELS[model]);
        for (i, p) in m.positions.iter_mut().enumerate() {
            let k = 3 * (i % 64);
            *p += DVec3::new(jitter[k], jitter[k + 1], jitter[k + 2]);
        }
        let scheme = if ds { SubdivisionScheme::DooSabin } else { SubdivisionScheme::CatmullClark };
        let s1 = affine(&subdivide(&m, scheme, 1).unwrap().mesh, a, t);
        let s2 = subdivide(&affine(&m, a, t), scheme, 1).unwrap().mesh;
        prop_assert_eq!(&s1.faces, &s2.faces);
        let d = gbsurf::tol::Near::dist(&s1.positions, &s2.positions);
        prop_assert!(d < 1e-11, "distance {}", d);
    }

    /// Doo–Sabin weights are a partition of unity, symmetric (α_k = α_{n−k}).
    #[test]
    fn doo_sabin_weights_partition_of_unity(n in 3usize..64) {
        let w = gbsurf::subdiv::doo_sabin_weights(n);
        prop_assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-14);
        for k in 1..n {
            prop_assert!((w[k] - w[n - k]).abs() < 1e-15);
        }
    }
}

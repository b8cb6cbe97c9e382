//! Cage attributes at the output's face corners (gbsurf::tessellate::cage_values, the keep-corners
//! rule of docs/math.md#cage-corners): exact values at the four points of a cage corner, bilinear
//! in between (proptest over face sizes, dimensions and coordinates), the cage's own positions
//! reproduced at the loops of real conversions in both layouts and structures, and a typed error
//! for every wrong input.

use gbsurf::api::{convert, ConvertOptions, Method};
use gbsurf::gb::Layout;
use gbsurf::mesh::PolyMesh;
use gbsurf::tessellate::{cage_loop_values, CageFaces, CageLoops, CageValuesError};
use glam::DVec3;
use proptest::prelude::*;

mod common_cage;
use common_cage::{cage_point, loop_jump, neighbour_difference};

const MODELS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/models");

fn model(name: &str) -> PolyMesh {
    gbsurf::api::read_mesh(format!("{MODELS}/{name}")).unwrap()
}

/// One face of size n, values a_j = (j, j²) (dim 2), the loops `coords` in corner k.
fn one_face(n: u32, k: u32, coords: &[[f64; 2]]) -> Vec<f32> {
    let values: Vec<f32> = (0..n).flat_map(|j| [j as f32, (j * j) as f32]).collect();
    let corners = vec![[0u32, k]; coords.len()];
    cage_loop_values(&[n], &values, 2, CageLoops { face_corner: &[], loop_corner: &corners, coords }).unwrap()
}

#[test]
fn the_four_points_of_a_corner_take_the_rule_values() {
    // Pentagon, corner 0: a_0 = (0,0), a_1 = (1,1), a_4 = (4,16), mean (2, 6).
    let out = one_face(5, 0, &[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.5, 0.5]]);
    assert_eq!(&out[0..2], &[0.0, 0.0]);
    assert_eq!(&out[2..4], &[0.5, 0.5]); // ½(a_0 + a_1)
    assert_eq!(&out[4..6], &[2.0, 6.0]); // the face mean
    assert_eq!(&out[6..8], &[2.0, 8.0]); // ½(a_0 + a_4)
    // centre of the corner: the mean of the four
    assert_eq!(&out[8..10], &[(0.0 + 0.5 + 2.0 + 2.0) / 4.0, (0.0 + 0.5 + 6.0 + 8.0) / 4.0]);
}

proptest! {
    #[test]
    fn values_are_bilinear_in_the_corner(n in 3u32..9, k in 0u32..9, dim in 1usize..4, s in 0.0f64..1.0, t in 0.0f64..1.0,
                                         seed in proptest::collection::vec(-100.0f32..100.0, 8 * 3)) {
        let k = k % n;
        let values: Vec<f32> = (0..n as usize * dim).map(|i| seed[i % seed.len()] + i as f32).collect();
        let corners = vec![[0u32, k]; 1];
        let out = cage_loop_values(&[n], &values, dim, CageLoops { face_corner: &[], loop_corner: &corners, coords: &[[s, t]] }).unwrap();
        let a = |j: u32, d: usize| values[(j % n) as usize * dim + d] as f64;
        for (d, &got) in out.iter().enumerate() {
            let mean = (0..n).map(|j| a(j, d)).sum::<f64>() / n as f64;
            let (v, next, prev) = (a(k, d), 0.5 * (a(k, d) + a(k + 1, d)), 0.5 * (a(k, d) + a(k + n - 1, d)));
            let want = (1.0 - s) * (1.0 - t) * v + s * (1.0 - t) * next + s * t * mean + (1.0 - s) * t * prev;
            prop_assert!((got as f64 - want).abs() <= 1e-4 * (1.0 + want.abs()), "{} vs {}", got, want);
        }
    }
}

#[test]
fn conversions_carry_the_cage_positions_to_every_loop() {
    for name in ["cube.obj", "star_prism.obj"] {
        let cage = model(name);
        let sizes: Vec<u32> = cage.faces.iter().map(|f| f.len() as u32).collect();
        let values: Vec<f32> = cage.faces.iter().flatten().flat_map(|&v| cage.positions[v as usize].to_array().map(|x| x as f32)).collect();
        for method in [Method::Dual, Method::Topology] {
            for layout in [Layout::Quads, Layout::Triangles] {
                let opts = ConvertOptions { method, layout, resolution: 4, ..Default::default() };
                let m = convert(&cage, &opts, None).unwrap().mesh;
                let out = m.cage_loop_values(&sizes, &values, 3).unwrap();
                let loops = m.cage_coords.len();
                assert!(loops > 0);
                assert_eq!(out.len(), 3 * loops);
                let per_face = if m.quads.is_empty() { 3 } else { 4 };
                for i in 0..loops {
                    let corner = if m.cage_loop_corner.is_empty() { m.cage_corner[i / per_face] } else { m.cage_loop_corner[i] };
                    let want = cage_point(&cage, corner, m.cage_coords[i]);
                    let got = DVec3::new(out[3 * i] as f64, out[3 * i + 1] as f64, out[3 * i + 2] as f64);
                    assert!(got.distance(want) <= 1e-5 * (1.0 + want.length()), "{name} {method:?} {layout:?} loop {i}: {got} vs {want}");
                }
            }
        }
    }
}

#[test]
fn wrong_inputs_are_typed_errors() {
    let coords = [[0.5, 0.5]; 4];
    let quad = [[0u32, 1u32]];
    let loops = CageLoops { face_corner: &quad, loop_corner: &[], coords: &coords };
    let v8 = [0f32; 8];
    assert_eq!(cage_loop_values(&[4], &v8, 0, loops), Err(CageValuesError::ZeroDimension));
    assert_eq!(
        cage_loop_values(&[4], &v8[..7], 2, loops),
        Err(CageValuesError::WrongLength { what: "values (dim per cage face corner)", expected: 8, got: 7 })
    );
    // A huge dimension is refused before any size is computed from it.
    let max = gbsurf::limits::MAX_CAGE_VALUE_DIM;
    assert_eq!(cage_loop_values(&[4], &v8, 1 << 62, loops), Err(CageValuesError::DimensionTooLarge { dim: 1 << 62, max }));
    assert_eq!(cage_loop_values(&[], &[], usize::MAX, CageLoops { face_corner: &[], loop_corner: &[], coords: &[] }), Err(CageValuesError::DimensionTooLarge { dim: usize::MAX, max }));
    assert_eq!(cage_loop_values(&[2, 2], &v8, 2, loops), Err(CageValuesError::FaceTooSmall { face: 0, size: 2 }));
    let far = [[3u32, 0u32]];
    let e = cage_loop_values(&[4], &v8, 2, CageLoops { face_corner: &far, ..loops }).unwrap_err();
    assert_eq!(e, CageValuesError::FaceOutOfRange { index: 0, face: 3, faces: 1 });
    assert!(e.to_string().contains("cage face 3"), "{e}");
    let big = [[0u32, 7u32]];
    assert_eq!(
        cage_loop_values(&[4], &v8, 2, CageLoops { face_corner: &big, ..loops }),
        Err(CageValuesError::CornerOutOfRange { index: 0, face: 0, corner: 7, size: 4 })
    );
    let three = [[0.5, 0.5]; 3];
    assert_eq!(
        cage_loop_values(&[4], &v8, 2, CageLoops { face_corner: &[[0, 0], [0, 1]], loop_corner: &[], coords: &three }),
        Err(CageValuesError::UnevenFaces { loops: 3, faces: 2 })
    );
    assert_eq!(
        cage_loop_values(&[4], &v8, 2, CageLoops { face_corner: &quad, loop_corner: &[[0, 0]; 3], coords: &coords }),
        Err(CageValuesError::WrongLength { what: "loop_corner pairs (one per coords pair)", expected: 4, got: 3 })
    );
    let nan = [[f64::NAN, 0.0]; 4];
    assert_eq!(cage_loop_values(&[4], &v8, 2, CageLoops { coords: &nan, ..loops }), Err(CageValuesError::NotFinite { index: 0 }));
    // An unknown corner (a hand-built surface) gives 0, not an error.
    let unknown = [[u32::MAX, u32::MAX]];
    let out = cage_loop_values(&[4], &[1f32; 8], 2, CageLoops { face_corner: &unknown, ..loops }).unwrap();
    assert_eq!(out, vec![0f32; 8]);
}

/// A face with holes: a corner's neighbours are in its own loop, the mean is over all the face's
/// loops, and values are given face by face (outer loop, then the face's holes in hole order,
/// whatever the order of the hole list).
#[test]
fn a_corner_of_a_hole_takes_its_own_loop_and_the_whole_face_mean() {
    // Face 0: triangle (values 0, 1, 2) with holes 1 (values 10, 11, 12) and 2 (20, 21, 22, 23);
    // face 1: a triangle (30, 31, 32) with hole 0 (40, 41, 42) listed first.
    let values = [0., 1., 2., 10., 11., 12., 20., 21., 22., 23., 30., 31., 32., 40., 41., 42.];
    let faces = CageFaces { sizes: &[3, 3], hole_faces: &[1, 0, 0], hole_sizes: &[3, 3, 4] };
    let mean0 = (3.0 + 33.0 + 86.0) / 10.0;
    let st = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    let at = |corner: [u32; 2]| {
        let corners = [corner; 4];
        cage_loop_values(faces, &values, 1, CageLoops { face_corner: &[], loop_corner: &corners, coords: &st }).unwrap()
    };
    // corner 3 of face 0 is the first of hole 1 (value 10; next 11, previous 12)
    assert_eq!(at([0, 3]), vec![10.0, 10.5, mean0 as f32, 11.0]);
    // corner 9 of face 0 is the last of hole 2 (value 23; next 20, previous 22)
    assert_eq!(at([0, 9]), vec![23.0, 21.5, mean0 as f32, 22.5]);
    // corner 4 of face 1 is the second of its hole (value 41)
    assert_eq!(at([1, 4]), vec![41.0, 41.5, 36.0, 40.5]);
    let one = CageLoops { face_corner: &[], loop_corner: &[[1, 6]], coords: &[[0.0, 0.0]] };
    let e = cage_loop_values(faces, &values, 1, one);
    assert_eq!(e, Err(CageValuesError::CornerOutOfRange { index: 0, face: 1, corner: 6, size: 6 }));
    // wrong hole inputs
    let bad = |hole_faces: &[u32], hole_sizes: &[u32]| {
        let faces = CageFaces { sizes: &[3, 3], hole_faces, hole_sizes };
        cage_loop_values(faces, &values, 1, CageLoops { face_corner: &[], loop_corner: &[], coords: &[] }).unwrap_err()
    };
    let what = "hole sizes (one per hole face)";
    assert_eq!(bad(&[1, 0, 0], &[3, 3]), CageValuesError::WrongLength { what, expected: 3, got: 2 });
    assert_eq!(bad(&[1, 2, 0], &[3, 3, 4]), CageValuesError::HoleFaceOutOfRange { hole: 1, face: 2, faces: 2 });
    assert_eq!(bad(&[1, 0, 0], &[3, 2, 4]), CageValuesError::HoleTooSmall { hole: 1, size: 2 });
    assert_eq!(
        bad(&[1, 0, 0], &[3, 3, 5]),
        CageValuesError::WrongLength { what: "values (dim per cage face corner)", expected: 17, got: 16 }
    );
}

/// Concave faces split into convex pieces: a per-vertex attribute (the cage positions over the
/// bounding box's largest extent, a UV-like coordinate) is continuous across the split diagonals
/// (docs/math.md#cage-corners: a diagonal's midpoint maps to the face centre). Bound: f32 values
/// ≤ 1 after a mean and three lerps, a few ulps; 1e-5. Prints the measurement of the issue: the
/// largest jump at an output vertex and the largest difference across an output quad's edge.
#[test]
fn values_are_continuous_across_concave_splits() {
    for name in ["l_prism.obj", "star_prism.obj"] {
        let cage = model(name);
        let sizes: Vec<u32> = cage.faces.iter().map(|f| f.len() as u32).collect();
        let lo = cage.positions.iter().fold(DVec3::INFINITY, |l, p| l.min(*p));
        let hi = cage.positions.iter().fold(DVec3::NEG_INFINITY, |h, p| h.max(*p));
        let extent = (hi - lo).max_element();
        let uv = |v: u32| ((cage.positions[v as usize] - lo) / extent).to_array().map(|x| x as f32);
        let values: Vec<f32> = cage.faces.iter().flatten().flat_map(|&v| uv(v)).collect();
        for method in [Method::Dual, Method::Topology] {
            let m = convert(&cage, &ConvertOptions { method, ..Default::default() }, None).unwrap().mesh;
            let out = m.cage_loop_values(&sizes, &values, 3).unwrap();
            let (jump, step) = (loop_jump(&m, &out, 3, false), neighbour_difference(&m, &out, 3, false));
            eprintln!("{name} {method:?}: jump {jump:.3e}, max neighbour difference {step:.3}");
            assert!(jump <= 1e-5, "{name} {method:?}: the values jump by {jump} at an output vertex");
        }
    }
}

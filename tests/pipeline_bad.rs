//! Every file in ../shared/models/bad through `convert_file`: its named error (one test per file),
//! for both structures; the isolated vertex is dropped with a warning.

use gbsurf::api::{convert_file, ConvertError, ConvertOptions, Method};
use gbsurf::mesh::{MeshError, COORDINATE_LIMIT};

const BAD: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/models/bad");

fn err(name: &str) -> Vec<MeshError> {
    [Method::Dual, Method::Topology, Method::CatmullClark, Method::DooSabin]
        .into_iter()
        .map(|method| {
            let opts = ConvertOptions { method, resolution: 2, levels: 1, ..ConvertOptions::triangles_r8() };
            match convert_file(format!("{BAD}/{name}"), &opts, None) {
                Ok(c) => panic!("{name} ({method}): accepted ({} vertices)", c.mesh.positions.len()),
                Err(ConvertError::Mesh(e)) => e,
                Err(e) => panic!("{name} ({method}): not a mesh error: {e}"),
            }
        })
        .collect()
}

fn all_eq(name: &str, expected: MeshError) {
    for e in err(name) {
        assert_eq!(e, expected, "{name}");
    }
}

#[test]
fn bowtie_vertex() {
    for e in err("bowtie_vertex.obj") {
        assert!(matches!(e, MeshError::NonManifoldVertex { vertex: 1, fans: 2, line: Some(2) }), "{e}");
    }
}

#[test]
fn duplicate_face() {
    all_eq("duplicate_face.obj", MeshError::DuplicateFace { face: 6, first: 0, line: Some(16) });
}

#[test]
fn empty() {
    all_eq("empty.obj", MeshError::Empty);
}

#[test]
fn flipped_face() {
    all_eq("flipped_face.obj", MeshError::InconsistentOrientation { edge: (6, 8), faces: (1, 5), line: Some(15) });
}

#[test]
fn garbage() {
    for e in err("garbage.obj") {
        assert!(matches!(e, MeshError::Parse { line: Some(1), .. }), "{e}");
    }
}

#[test]
fn huge_coordinates() {
    for e in err("huge_coordinates.obj") {
        assert!(
            matches!(e, MeshError::CoordinateRange { vertex: 1, axis: 0, limit, line: Some(2), .. } if limit == COORDINATE_LIMIT),
            "{e}"
        );
    }
}

#[test]
fn index_out_of_range() {
    all_eq("index_out_of_range.obj", MeshError::ObjIndexOutOfRange { face: 5, corner: 3, index: 42, available: 8, line: Some(15) });
}

#[test]
fn inf() {
    for e in err("inf.obj") {
        assert!(matches!(e, MeshError::NonFiniteCoordinate { vertex: 1, axis: 0, value, line: Some(2) } if value == f64::INFINITY), "{e}");
    }
}

#[test]
fn nan() {
    for e in err("nan.obj") {
        assert!(matches!(e, MeshError::NonFiniteCoordinate { vertex: 1, axis: 0, value, line: Some(2) } if value.is_nan()), "{e}");
    }
}

#[test]
fn nonmanifold_edge() {
    all_eq("nonmanifold_edge.obj", MeshError::NonManifoldEdge { edge: (1, 2), faces: vec![0, 2, 6, 7], line: Some(18) });
}

#[test]
fn repeated_index() {
    all_eq("repeated_index.obj", MeshError::RepeatedIndex { face: 5, vertex: 4, line: Some(15) });
}

#[test]
fn zero_area() {
    // "f 5 6 9" has collinear corners (see tests/bad_models.rs).
    all_eq("zero_area.obj", MeshError::ZeroAreaFace { face: 6, area: 0.0, line: Some(17) });
}

#[test]
fn isolated_vertex_converts_with_a_warning() {
    for method in [Method::Dual, Method::Topology, Method::CatmullClark, Method::DooSabin] {
        let opts = ConvertOptions { method, resolution: 3, levels: 2, ..ConvertOptions::triangles_r8() };
        let c = convert_file(format!("{BAD}/isolated_vertex.obj"), &opts, None).unwrap_or_else(|e| panic!("{method}: {e}"));
        assert_eq!(c.warnings.len(), 1, "{method}: {:?}", c.warnings);
        assert!(c.warnings[0].contains("vertex 9") && c.warnings[0].contains("line 10"), "{}", c.warnings[0]);
        assert_eq!(c.report.warnings, c.warnings);
        assert!(c.report.closed, "{method}");
    }
}

#[test]
fn invalid_options_name_the_option() {
    let cases: Vec<(ConvertOptions, &str)> = vec![
        (ConvertOptions { resolution: 0, ..ConvertOptions::triangles_r8() }, "resolution"),
        (ConvertOptions { resolution: 5000, ..ConvertOptions::triangles_r8() }, "resolution"),
        (ConvertOptions { fullness: 1.0, ..ConvertOptions::triangles_r8() }, "fullness"),
        (ConvertOptions { fullness: f64::NAN, ..ConvertOptions::triangles_r8() }, "fullness"),
        (ConvertOptions { tile_depth: 2.0, ..ConvertOptions::triangles_r8() }, "tile-depth"),
        (ConvertOptions { mid_scale: f64::INFINITY, ..ConvertOptions::triangles_r8() }, "mid-scale"),
        (ConvertOptions { levels: 9, ..ConvertOptions::triangles_r8() }, "levels"),
    ];
    for (o, name) in cases {
        match o.validate().map_err(ConvertError::from) {
            Err(ConvertError::InvalidOption { name: n, .. }) => assert_eq!(n, name),
            r => panic!("{name}: {r:?}"),
        }
        // Options are checked before the file is even read.
        let e = convert_file(format!("{BAD}/does_not_exist.obj"), &o, None).unwrap_err();
        assert!(matches!(e, ConvertError::InvalidOption { .. }), "{e}");
    }
    let e = convert_file(format!("{BAD}/does_not_exist.obj"), &ConvertOptions::triangles_r8(), None).unwrap_err();
    assert!(matches!(e, ConvertError::Mesh(MeshError::Io { .. })), "{e}");
}

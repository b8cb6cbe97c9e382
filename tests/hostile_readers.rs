//! Hostile input through the mesh readers: counts that overflow or lie, truncated and padded
//! files, misleading errors, real-world files that must be accepted, non-files and size limits,
//! unresolvable scale; and a proptest of byte mutations of every shared model through every
//! reader. The small files are in tests/data/hostile/.

use gbsurf::export::PlyFormat;
use gbsurf::limits::{MAX_INPUT_BYTES, MIN_RELATIVE_EXTENT};
use gbsurf::mesh::io::{parse_mesh_bytes, parse_obj, parse_off, parse_ply, parse_stl};
use gbsurf::mesh::{read_mesh, read_polymesh, HalfEdgeMesh, MeshError, MeshWarning, PolyMesh};
use proptest::prelude::*;
use std::path::PathBuf;
use std::time::{Duration, Instant};

const HOSTILE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/hostile");
const MODELS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/models");

fn path(name: &str) -> String {
    format!("{HOSTILE}/{name}")
}

/// The reader's error for a hostile file, and its message.
fn err(name: &str) -> (MeshError, String) {
    let e = read_mesh(path(name)).map(|m| m.n_faces()).unwrap_err();
    let s = e.to_string();
    (e, s)
}

fn parse_line(e: &MeshError) -> Option<usize> {
    match e {
        MeshError::Parse { line, .. } => *line,
        e => panic!("not a parse error: {e}"),
    }
}

/// A closed cube (8 vertices, 6 quads or 12 triangles).
fn assert_cube(m: &HalfEdgeMesh, faces: usize) {
    assert_eq!(m.n_vertices(), 8);
    assert_eq!(m.n_faces(), faces);
    assert!(m.is_closed());
}

fn tmp_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("gbsurf_hostile_{tag}_{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

// ------------------------------------------------------------ counts that overflow or lie

#[test]
fn off_face_size_u64_max_is_an_error_not_a_panic() {
    let (e, s) = err("off_face_size_overflow.off");
    assert_eq!(parse_line(&e), Some(6), "{s}");
    assert!(s.contains("announces 18446744073709551615 indices but has 3"), "{s}");
}

#[test]
fn off_vertex_count_u64_max_ends_in_the_vertices() {
    let (e, s) = err("off_vertex_count_huge.off");
    assert_eq!(parse_line(&e), Some(2), "{s}");
    assert!(s.contains("ends after 1 of the 18446744073709551615 vertices"), "{s}");
}

#[test]
fn off_face_count_one_low_or_high_names_the_line() {
    // count 5, six face lines: the sixth face (line 16) is left over
    let (e, s) = err("off_face_count_low.off");
    assert_eq!(parse_line(&e), Some(16), "{s}");
    assert!(s.contains("data after the 5 faces declared on line 2"), "{s}");
    // count 7, six face lines: the count line is named
    let (e, s) = err("off_face_count_high.off");
    assert_eq!(parse_line(&e), Some(2), "{s}");
    assert!(s.contains("ends after 6 of the 7 faces"), "{s}");
}

#[test]
fn ply_face_count_one_low_or_high_names_the_line() {
    let (e, s) = err("ply_face_count_low.ply");
    assert_eq!(parse_line(&e), Some(23), "{s}");
    assert!(s.contains("data after the last PLY element"), "{s}");
    let (e, s) = err("ply_face_count_high.ply");
    assert_eq!(parse_line(&e), Some(7), "{s}");
    assert!(s.contains("element 'face' record 6 of the 7"), "{s}");
}

#[test]
fn binary_ply_counts_are_checked_against_the_data() {
    // An element with no properties and count u64::MAX has empty records: nothing to read, at once.
    let t = Instant::now();
    let m = read_mesh(path("ply_empty_element_huge.ply")).unwrap();
    assert!(t.elapsed() < Duration::from_secs(2));
    assert_eq!((m.n_vertices(), m.n_faces()), (4, 4));
    // 4e9 vertices of 12 bytes are refused before anything is read or allocated.
    let (e, s) = err("ply_vertex_count_huge.ply");
    assert_eq!(parse_line(&e), Some(4), "{s}");
    assert!(s.contains("'vertex' declares 4000000000 records (at least 48000000000 bytes)"), "{s}");
    // one face too few or too many in a binary PLY made by the writer
    let cube = read_mesh(format!("{MODELS}/cube.obj")).unwrap().to_polymesh();
    let mut buf = Vec::new();
    cube.write_ply(&mut buf, PlyFormat::BinaryLittleEndian, &[]).unwrap();
    let text = String::from_utf8_lossy(&buf).into_owned();
    assert!(text.contains("element face 6\n"));
    let with_count = |n: &str| {
        let i = buf.windows(14).position(|w| w == b"element face 6").unwrap();
        let mut b = buf[..i].to_vec();
        b.extend_from_slice(format!("element face {n}").as_bytes());
        b.extend_from_slice(&buf[i + 14..]);
        b
    };
    let s = parse_ply(&with_count("5")).unwrap_err().to_string();
    assert!(s.contains("bytes after the last PLY element"), "{s}");
    let s = parse_ply(&with_count("7")).unwrap_err().to_string();
    assert!(s.contains("element 'face' record 6 of the 7"), "{s}");
    // a list length of u32::MAX is proven by no data: an error, no allocation
    let i = buf.len() - 17; // the last face: uchar 4 + 4 ints
    let mut b = buf.clone();
    b[i] = 255;
    let s = parse_ply(&b).unwrap_err().to_string();
    assert!(s.contains("record 5"), "{s}");
}

#[test]
fn ascii_stl_cut_inside_a_facet_is_an_error() {
    let (e, s) = err("stl_ascii_truncated.stl");
    assert!(parse_line(&e).is_some(), "{s}");
    assert!(s.contains("ends inside the facet of line"), "{s}");
    // cut between facets: no endsolid
    let text = std::fs::read_to_string(path("stl_bom.stl")).unwrap();
    let cut = &text[..text.rfind("endsolid").unwrap()];
    let s = parse_stl(cut.as_bytes()).unwrap_err().to_string();
    assert!(s.contains("ends without endsolid"), "{s}");
    // the full file is a closed cube
    assert_cube(&read_mesh(path("stl_bom.stl")).unwrap(), 12);
}

#[test]
fn binary_stl_size_errors_say_what_is_wrong() {
    let (_, s) = err("stl_binary_count_high.stl");
    assert!(s.contains("binary STL: expected 734 bytes for 13 triangles, got 684"), "{s}");
    let (_, s) = err("stl_binary_trailing.stl");
    assert!(s.contains("expected 684 bytes for 12 triangles, got 686"), "{s}");
    let (_, s) = err("stl_binary_truncated.stl");
    assert!(s.contains("expected 684 bytes for 12 triangles, got 351"), "{s}");
    for (_, s) in [err("stl_binary_count_high.stl"), err("stl_binary_trailing.stl")] {
        assert!(!s.contains("UTF-8"), "{s}");
    }
    // too short for a header
    let s = parse_stl(b"\x01\x02").unwrap_err().to_string();
    assert!(s.contains("neither ASCII STL") && s.contains("2 bytes"), "{s}");
}

// ------------------------------------------------------------ -0.0 equals 0.0

#[test]
fn stl_negative_zero_is_welded_to_zero() {
    for name in ["stl_ascii_negzero.stl", "stl_binary_negzero.stl"] {
        let m = read_mesh(path(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_cube(&m, 12);
        assert_eq!(m.euler_characteristic(), 2, "{name}");
        // the welded positions carry +0.0
        assert!(m.to_polymesh().positions.iter().flat_map(|p| p.to_array()).all(|x| x != 0.0 || x.is_sign_positive()));
    }
}

// ------------------------------------------------------------ misleading errors

#[test]
fn ply_fractional_or_nan_index_names_value_and_line() {
    let (e, s) = err("ply_index_fraction.ply");
    assert_eq!(parse_line(&e), Some(22), "{s}");
    assert!(s.contains("face 4 corner 3: vertex index 2.5 is not a non-negative integer"), "{s}");
    let (e, s) = err("ply_index_nan.ply");
    assert_eq!(parse_line(&e), Some(23), "{s}");
    assert!(s.contains("face 5 corner 1: vertex index NaN"), "{s}");
}

#[test]
fn obj_index_errors_name_the_index_as_written() {
    let (e, s) = err("obj_index_high.obj");
    assert_eq!(e, MeshError::ObjIndexOutOfRange { face: 6, corner: 2, index: 9, available: 8, line: Some(15) });
    assert!(s.contains("vertex index 9 out of range (1..=8)"), "{s}");
    let (e, s) = err("obj_relative_index.obj");
    assert_eq!(e, MeshError::ObjIndexOutOfRange { face: 6, corner: 2, index: -9, available: 8, line: Some(15) });
    assert!(s.contains("vertex index -9 out of range (-8..=-1 relative to the 8 vertices above)"), "{s}");
    // relative to the vertices above the face, not to all of them
    let e = parse_obj("v 0 0 0\nv 1 0 0\nf 1 2 -3\nv 0 1 0\n").unwrap_err();
    assert_eq!(e, MeshError::ObjIndexOutOfRange { face: 0, corner: 2, index: -3, available: 2, line: Some(3) });
}

// ------------------------------------------------------------ real-world files accepted

#[test]
fn byte_order_mark_is_skipped() {
    assert_cube(&read_mesh(path("obj_bom.obj")).unwrap(), 6);
    assert_cube(&read_mesh(path("ply_bom.ply")).unwrap(), 6);
    assert_cube(&read_mesh(path("stl_bom.stl")).unwrap(), 12);
    let (m, map) = parse_off(b"\xef\xbb\xbfOFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").unwrap();
    assert_eq!((m.faces.len(), map.face_lines[0]), (1, 6));
}

#[test]
fn obj_backslash_continuation_joins_lines() {
    let (m, map) = read_polymesh(path("obj_continuation.obj")).unwrap();
    assert_eq!(m.positions[0].to_array(), [-1.0, -1.0, -1.0]);
    assert_eq!(m.faces[0], vec![0, 2, 3, 1]);
    // elements are numbered by the line they start on
    assert_eq!(map.vertex_lines[..2], [1, 3]);
    assert_eq!(map.face_lines[0], 10);
    assert_cube(&read_mesh(path("obj_continuation.obj")).unwrap(), 6);
}

#[test]
fn obj_latin1_names_and_comments_are_not_geometry() {
    assert_cube(&read_mesh(path("obj_latin1.obj")).unwrap(), 6);
    // but a non-UTF-8 byte where numbers are parsed is an error naming the line
    let e = parse_obj(b"v 0 0 0\nv 1 0 0\xe9\n").unwrap_err();
    assert_eq!(parse_line(&e), Some(2));
}

#[test]
fn obj_free_form_and_tags_are_skipped_with_warnings() {
    let m = read_mesh(path("obj_freeform.obj")).unwrap();
    assert_cube(&m, 6);
    let w = m.warnings();
    let skipped = |s: &str, line: usize, count: usize| MeshWarning::SkippedStatement { statement: s.into(), line, count };
    assert_eq!(
        w,
        &[
            skipped("cstype", 15, 1),
            skipped("deg", 16, 1),
            skipped("curv", 17, 1),
            skipped("parm", 18, 1),
            skipped("end", 19, 1),
            skipped("usemap", 20, 1),
            skipped("lod", 21, 1),
            skipped("bevel", 22, 1),
            skipped("c_interp", 23, 1),
            skipped("t interpolateboundary", 26, 1),
        ]
    );
    assert!(w[9].to_string().contains("\"t interpolateboundary\" (first on line 26)"), "{}", w[9]);
    // the crease tags are read (tests/creases.rs has the details)
    let (pm, map) = read_polymesh(path("obj_freeform.obj")).unwrap();
    let c = gbsurf::mesh::io::obj_sharpness(4.0);
    assert_eq!(pm.creases.edges, vec![([0, 1], c), ([1, 3], c)]);
    assert_eq!(map.edge_crease_lines, vec![24, 25]);
    // the same path feeds the conversion's warnings
    let opts = gbsurf::api::ConvertOptions { method: gbsurf::api::Method::CatmullClark, levels: 1, ..gbsurf::api::ConvertOptions::triangles_r8() };
    let c = gbsurf::convert_file(path("obj_freeform.obj"), &opts, None).unwrap();
    assert!(c.warnings.iter().any(|s| s.contains("t interpolateboundary")), "{:?}", c.warnings);
    // still an error: a statement OBJ does not have
    assert!(matches!(parse_obj("v 0 0 0\nfoo 1\n"), Err(MeshError::Parse { line: Some(2), .. })));
}

// ------------------------------------------------------------ non-files and size

#[test]
fn only_regular_files_of_known_extension_are_read() {
    let t = Instant::now();
    // /dev/zero: refused by its (missing) extension before it is opened
    assert!(matches!(read_polymesh("/dev/zero"), Err(MeshError::Parse { line: None, .. })));
    let d = tmp_dir("files");
    #[cfg(unix)]
    {
        let link = d.join("zero.obj");
        let _ = std::fs::remove_file(&link);
        std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
        assert!(matches!(read_polymesh(&link), Err(MeshError::NotAFile { .. })));
        let fifo = d.join("fifo.stl");
        let _ = std::fs::remove_file(&fifo);
        if std::process::Command::new("mkfifo").arg(&fifo).status().is_ok_and(|s| s.success()) {
            let e = read_polymesh(&fifo).unwrap_err();
            assert!(e.to_string().contains("is not a regular file"), "{e}");
        }
    }
    let dir = d.join("dir.ply");
    std::fs::create_dir_all(&dir).unwrap();
    assert!(matches!(read_polymesh(&dir), Err(MeshError::NotAFile { .. })));
    // a (sparse) file above the limit is refused before it is read
    let big = d.join("big.off");
    std::fs::File::create(&big).unwrap().set_len(MAX_INPUT_BYTES + 1).unwrap();
    let e = read_polymesh(&big).unwrap_err();
    assert!(matches!(e, MeshError::InputTooLarge { limit: MAX_INPUT_BYTES, .. }), "{e}");
    assert!(e.to_string().contains("limit of 2147483648 bytes"), "{e}");
    let _ = std::fs::remove_dir_all(&d);
    assert!(t.elapsed() < Duration::from_secs(5));
}

// ------------------------------------------------------------ scale f64 cannot resolve

#[test]
fn cube_far_from_the_origin_is_refused_with_the_range() {
    let (e, s) = err("obj_far.obj");
    match e {
        MeshError::UnresolvableExtent { extent, magnitude, min_ratio, vertex: 4, line: Some(4) } => {
            assert_eq!((extent, magnitude, min_ratio), (2.0, 1000000000000001.0, MIN_RELATIVE_EXTENT));
        }
        e => panic!("{e}"),
    }
    assert!(s.contains("mesh extent 2e0 is below 1e-9 times the coordinate magnitude 1.000000000000001e15 of vertex 4 (line 4)"), "{s}");
    // the same cube nearer (extent/magnitude = 2e-6) is accepted
    let text = std::fs::read_to_string(path("obj_far.obj")).unwrap().replace("999999999999999", "999999").replace("1000000000000001", "1000001");
    let (m, _) = parse_obj(&text).unwrap();
    assert!(HalfEdgeMesh::from_polymesh(&m).is_ok(), "{:?}", m.positions);
}

// ------------------------------------------------------------ mutations of every shared model

/// The shared good models in every readable encoding: (extension, bytes).
fn corpus() -> Vec<(&'static str, Vec<u8>)> {
    let mut out = Vec::new();
    let mut names: Vec<_> = std::fs::read_dir(MODELS)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "obj"))
        .collect();
    names.sort();
    for p in names {
        let bytes = std::fs::read(&p).unwrap();
        let (m, _) = parse_obj(&bytes).unwrap();
        out.push(("obj", bytes));
        out.push(("off", off_text(&m).into_bytes()));
        for format in [PlyFormat::Ascii, PlyFormat::BinaryLittleEndian] {
            let mut b = Vec::new();
            m.write_ply(&mut b, format, &[]).unwrap();
            out.push(("ply", b));
        }
        let mut stl = Vec::new();
        m.write_stl(&mut stl).unwrap();
        let tri = parse_stl(&stl).unwrap();
        out.push(("stl", stl));
        out.push(("stl", ascii_stl(&tri).into_bytes()));
    }
    out
}

fn off_text(m: &PolyMesh) -> String {
    let mut s = format!("OFF\n{} {} 0\n", m.positions.len(), m.faces.len());
    for p in &m.positions {
        s += &format!("{} {} {}\n", p.x, p.y, p.z);
    }
    for f in &m.faces {
        s += &format!("{} {}\n", f.len(), f.iter().map(|i| i.to_string()).collect::<Vec<_>>().join(" "));
    }
    s
}

fn ascii_stl(m: &PolyMesh) -> String {
    let mut s = String::from("solid model\n");
    for f in &m.faces {
        s += "facet normal 0 0 0\nouter loop\n";
        for &i in f {
            let p = m.positions[i as usize];
            s += &format!("vertex {} {} {}\n", p.x, p.y, p.z);
        }
        s += "endloop\nendfacet\n";
    }
    s + "endsolid model\n"
}

fn mutate(bytes: &[u8], kind: u8, at: usize, len: usize, byte: u8) -> Vec<u8> {
    let mut b = bytes.to_vec();
    let n = b.len().max(1);
    let i = at % n;
    match kind % 5 {
        0 => {
            if let Some(x) = b.get_mut(i) {
                *x ^= byte | 1;
            }
        }
        1 => b.insert(i.min(b.len()), byte),
        2 => {
            let end = (i + len).min(b.len());
            b.drain(i.min(end)..end);
        }
        3 => b.truncate(i),
        _ => {
            // duplicate the line containing `i`
            let start = b[..i.min(b.len())].iter().rposition(|&c| c == b'\n').map_or(0, |p| p + 1);
            let end = b[start..].iter().position(|&c| c == b'\n').map_or(b.len(), |p| start + p + 1);
            let line = b[start..end].to_vec();
            b.splice(end..end, line);
        }
    }
    b
}

/// No panic; either a mesh (validated without panic) or an error naming a line or an element.
fn check_reader(ext: &str, bytes: &[u8]) -> Result<(), TestCaseError> {
    let named = |e: &MeshError| {
        let s = e.to_string();
        matches!(e, MeshError::Empty)
            || ["line", "face", "vertex", "element", "triangle", "edge"].iter().any(|w| s.contains(w))
    };
    match parse_mesh_bytes(bytes, ext) {
        Ok((m, map)) => {
            if let Err(e) = HalfEdgeMesh::from_polymesh(&m).map_err(|e| e.with_source(&map)) {
                prop_assert!(named(&e), "{ext}: {e}");
            }
        }
        Err(e) => prop_assert!(named(&e), "{ext}: {e}"),
    }
    Ok(())
}

#[test]
fn every_encoding_of_every_model_reads_back() {
    let c = corpus();
    assert_eq!(c.len(), 13 * 6);
    for (ext, b) in &c {
        let (m, _) = parse_mesh_bytes(b, ext).unwrap();
        HalfEdgeMesh::from_polymesh(&m).unwrap();
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 600, failure_persistence: None, ..ProptestConfig::default() })]

    /// Mutated bytes (flip, insert, delete, truncate, duplicate a line; up to three in a row)
    /// of every shared model in every encoding never panic any reader.
    #[test]
    fn mutated_models_never_panic(
        which in 0usize..1000,
        edits in prop::collection::vec((any::<u8>(), any::<usize>(), 1usize..40, any::<u8>()), 1..4),
    ) {
        thread_local!(static CORPUS: Vec<(&'static str, Vec<u8>)> = corpus());
        let (ext, mut bytes) = CORPUS.with(|c| c[which % c.len()].clone());
        for (kind, at, len, byte) in edits {
            bytes = mutate(&bytes, kind, at, len, byte);
        }
        check_reader(ext, &bytes)?;
        // the same bytes through the other readers too
        for other in ["obj", "off", "ply", "stl"] {
            check_reader(other, &bytes)?;
        }
    }
}

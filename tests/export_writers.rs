//! The mesh writers' number text and float32 fields: OBJ and ASCII PLY numbers parse back to the
//! same `f64` bits (also across the parallel chunks of a large mesh, in order); no writer writes
//! `inf` for a finite value (PLY curvatures are `double`, `float` fields are clamped, STL refuses
//! positions beyond `f32` with the vertex named).

use gbsurf::api::{convert, ConvertOptions};
use gbsurf::export::{Float32RangeError, PlyFormat, VertexScalar};
use gbsurf::mesh::io::parse_ply;
use gbsurf::mesh::{read_mesh, PolyMesh, TriMesh};
use gbsurf::DVec3;
use proptest::prelude::*;

const MODELS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/models");

/// The numbers of every line of `text` that starts with `tag ` (in line order).
fn numbers(text: &str, tag: &str) -> Vec<Vec<f64>> {
    let prefix = format!("{tag} ");
    text.lines()
        .filter_map(|l| l.strip_prefix(&prefix))
        .map(|l| l.split(' ').map(|t| t.parse::<f64>().unwrap_or_else(|e| panic!("{t:?}: {e}"))).collect())
        .collect()
}

fn bits(p: &[DVec3]) -> Vec<[u64; 3]> {
    p.iter().map(|q| q.to_array().map(f64::to_bits)).collect()
}

fn finite_f64() -> impl Strategy<Value = f64> {
    // every finite f64 bit pattern: subnormals, extremes, negative zero
    any::<u64>().prop_map(f64::from_bits).prop_filter("finite", |x| x.is_finite())
}

fn tri_mesh(positions: Vec<DVec3>, normals: Vec<DVec3>) -> TriMesh {
    let n = positions.len() as u32;
    let triangles = (0..n.saturating_sub(2)).map(|i| [i, i + 1, i + 2]).collect();
    TriMesh { positions, normals, triangles }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn obj_text_round_trips_every_f64(coords in proptest::collection::vec(finite_f64(), 3..60)) {
        let positions: Vec<DVec3> = coords.chunks_exact(3).map(|c| DVec3::new(c[0], c[1], c[2])).collect();
        let normals: Vec<DVec3> = positions.iter().map(|p| DVec3::new(p.z, p.x, p.y)).collect();
        let m = tri_mesh(positions.clone(), normals.clone());
        let mut buf = Vec::new();
        m.write_obj(&mut buf).unwrap();
        let text = String::from_utf8(buf).unwrap();
        let back: Vec<DVec3> = numbers(&text, "v").iter().map(|v| DVec3::from_slice(v)).collect();
        let back_n: Vec<DVec3> = numbers(&text, "vn").iter().map(|v| DVec3::from_slice(v)).collect();
        prop_assert_eq!(bits(&back), bits(&positions));
        prop_assert_eq!(bits(&back_n), bits(&normals));
    }

    #[test]
    fn ascii_ply_round_trips_every_f64(coords in proptest::collection::vec(finite_f64(), 9..60)) {
        let positions: Vec<DVec3> = coords.chunks_exact(3).map(|c| DVec3::new(c[0], c[1], c[2])).collect();
        let face = vec![(0..positions.len() as u32).collect()];
        let m = PolyMesh::new(positions, face);
        let mut buf = Vec::new();
        m.write_ply(&mut buf, PlyFormat::Ascii, &[]).unwrap();
        let text = String::from_utf8(buf).unwrap();
        let body = text.split("end_header\n").nth(1).unwrap();
        let back: Vec<[u64; 3]> = body
            .lines()
            .take(m.positions.len())
            .map(|l| {
                let v: Vec<f64> = l.split(' ').map(|t| t.parse().unwrap()).collect();
                [v[0], v[1], v[2]].map(f64::to_bits)
            })
            .collect();
        prop_assert_eq!(back, bits(&m.positions));
    }
}

/// Enough vertices for several windows of parallel chunks (in a pool of 2 threads, so that
/// whatever the machine's cores the next window is encoded while one is written): every line in
/// its place.
#[test]
fn large_obj_and_ply_keep_order_and_bits() {
    rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap().install(large_obj_and_ply_keep_order_and_bits_in_pool);
}

fn large_obj_and_ply_keep_order_and_bits_in_pool() {
    let n = 300_001;
    let positions: Vec<DVec3> = (0..n).map(|i| DVec3::new(i as f64 * 0.1, -(i as f64) / 3.0, 1e-300 * i as f64)).collect();
    let normals: Vec<DVec3> = positions.iter().map(|p| p.normalize_or_zero()).collect();
    let m = tri_mesh(positions.clone(), normals);
    let mut buf = Vec::new();
    m.write_obj(&mut buf).unwrap();
    let text = String::from_utf8(buf).unwrap();
    let back: Vec<DVec3> = numbers(&text, "v").iter().map(|v| DVec3::from_slice(v)).collect();
    assert_eq!(bits(&back), bits(&positions));
    let faces: Vec<&str> = text.lines().filter(|l| l.starts_with("f ")).collect();
    assert_eq!(faces.len(), n - 2);
    assert_eq!(faces[0], "f 1//1 2//2 3//3");
    assert_eq!(faces[n - 3], format!("f {a}//{a} {b}//{b} {c}//{c}", a = n - 2, b = n - 1, c = n));
    for format in [PlyFormat::Ascii, PlyFormat::BinaryLittleEndian] {
        let mut ply = Vec::new();
        m.write_ply(&mut ply, format, &[]).unwrap();
        let (back, _) = parse_ply(&ply).unwrap();
        assert_eq!(bits(&back.positions), bits(&positions), "{format:?}");
        assert_eq!(back.faces, m.triangles.iter().map(|t| t.to_vec()).collect::<Vec<_>>(), "{format:?}");
    }
}

/// A writer that takes `left` bytes and then fails.
struct FailAfter {
    out: Vec<u8>,
    left: usize,
}

impl std::io::Write for FailAfter {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        if self.left == 0 {
            return Err(std::io::Error::other("disk full"));
        }
        let k = buf.len().min(self.left);
        self.out.extend_from_slice(&buf[..k]);
        self.left -= k;
        Ok(k)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// A write that fails part-way (in the first window, in a later one, at the very end) returns the
/// error, and what reached the writer is exactly the start of the full output, in 1- and
/// 2-thread pools and for OBJ, binary PLY and STL.
#[test]
fn a_failing_writer_gets_a_prefix_and_the_error() {
    let n = 200_001;
    let positions: Vec<DVec3> = (0..n).map(|i| DVec3::new(i as f64, 0.5 * i as f64, (i % 7) as f64)).collect();
    let normals: Vec<DVec3> = positions.iter().map(|p| p.normalize_or_zero()).collect();
    let m = tri_mesh(positions, normals);
    type Writer = fn(&TriMesh, &mut dyn std::io::Write) -> std::io::Result<()>;
    let writers: [(&str, Writer); 3] = [
        ("obj", |m, w| m.write_obj(w)),
        ("ply", |m, w| m.write_ply(w, PlyFormat::BinaryLittleEndian, &[])),
        ("stl", |m, w| m.write_stl(w)),
    ];
    for threads in [1, 2] {
        rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap().install(|| {
            for (name, write) in writers {
                let mut full = Vec::new();
                write(&m, &mut full).unwrap();
                for left in [1000, full.len() / 2, full.len() - 1] {
                    let mut w = FailAfter { out: Vec::new(), left };
                    let r = write(&m, &mut w);
                    assert!(r.is_err(), "{name}, {threads} threads, {left} bytes: no error");
                    assert_eq!(w.out.len(), left, "{name}, {threads} threads");
                    assert!(w.out == full[..left], "{name}, {threads} threads, {left} bytes: not a prefix");
                }
            }
        });
    }
}

/// The vertex records of a binary PLY written by gbsurf: per vertex, every property as f64 (in
/// header order), and the header's property types.
fn ply_vertex_values(bytes: &[u8]) -> (Vec<(String, String)>, Vec<Vec<f64>>) {
    let end = bytes.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
    let header = std::str::from_utf8(&bytes[..end]).unwrap();
    assert!(header.contains("format binary_little_endian 1.0"));
    let mut nv = 0;
    let mut props = Vec::new();
    let mut in_vertex = false;
    for line in header.lines() {
        let w: Vec<&str> = line.split(' ').collect();
        match w[..] {
            ["element", "vertex", n] => {
                nv = n.parse().unwrap();
                in_vertex = true;
            }
            ["element", ..] => in_vertex = false,
            ["property", ty, name] if in_vertex => props.push((ty.to_string(), name.to_string())),
            _ => {}
        }
    }
    let mut at = end;
    let mut rows = Vec::new();
    for _ in 0..nv {
        let row = props
            .iter()
            .map(|(ty, _)| match ty.as_str() {
                "double" => {
                    at += 8;
                    f64::from_le_bytes(bytes[at - 8..at].try_into().unwrap())
                }
                "float" => {
                    at += 4;
                    f32::from_le_bytes(bytes[at - 4..at].try_into().unwrap()) as f64
                }
                t => panic!("type {t}"),
            })
            .collect();
        rows.push(row);
    }
    (props, rows)
}

/// A mesh converted without its quality arrays (`ConvertOptions::quality_arrays` off, as the
/// command line converts for OBJ and STL) still writes as PLY: positions, normals, the fold flag
/// and the faces, without the four scalars it does not have.
#[test]
fn ply_of_a_mesh_without_quality_arrays_leaves_their_scalars_out() {
    let cube = read_mesh(format!("{MODELS}/cube.obj")).unwrap().to_polymesh();
    let conv = convert(&cube, &ConvertOptions { quality_arrays: false, ..ConvertOptions::default() }, None).unwrap();
    let m = &conv.mesh;
    assert!(m.patch.is_empty() && m.mean_curvature.is_empty());
    let mut buf = Vec::new();
    m.write_ply(&mut buf).unwrap();
    let (props, rows) = ply_vertex_values(&buf);
    let names: Vec<&str> = props.iter().map(|(_, n)| n.as_str()).collect();
    assert_eq!(names, ["x", "y", "z", "nx", "ny", "nz", "fold"]);
    assert_eq!(rows.len(), m.positions.len());
    for (i, row) in rows.iter().enumerate() {
        assert_eq!(row[0..3], m.positions[i].to_array());
        assert_eq!(row[6], m.fold[i] as f64);
    }
}

/// A cube scaled by 1e-20: Gaussian curvatures near 1e40 (beyond f32). Every written value is
/// finite, and the per-vertex data equal the f64 values exactly.
#[test]
fn tiny_cube_ply_has_no_inf_and_exact_curvatures() {
    let mut cube = read_mesh(format!("{MODELS}/cube.obj")).unwrap().to_polymesh();
    for p in &mut cube.positions {
        *p *= 1e-20;
    }
    let conv = convert(&cube, &ConvertOptions::triangles_r8(), None).unwrap();
    let m = &conv.mesh;
    let max_k = m.gaussian_curvature.iter().fold(0.0f64, |a, &k| a.max(k.abs()));
    assert!(max_k > f32::MAX as f64, "the case needs curvatures beyond f32: {max_k:e}");
    let mut buf = Vec::new();
    m.write_ply(&mut buf).unwrap();
    let (props, rows) = ply_vertex_values(&buf);
    let names: Vec<&str> = props.iter().map(|(_, n)| n.as_str()).collect();
    assert_eq!(names, ["x", "y", "z", "nx", "ny", "nz", "patch", "mean_curvature", "gaussian_curvature", "g1_deviation", "fold"]);
    for (ty, name) in &props[6..10] {
        assert_eq!(ty, "double", "{name}");
    }
    assert_eq!(props[10].0, "float");
    assert_eq!(rows.len(), m.positions.len());
    for (i, row) in rows.iter().enumerate() {
        assert!(row.iter().all(|x| x.is_finite()), "vertex {i}: {row:?}");
        assert_eq!(row[0..3], m.positions[i].to_array());
        assert_eq!(row[3..6], m.normals[i].to_array().map(|c| c as f32 as f64));
        assert_eq!(row[6], m.patch[i] as f64);
        assert_eq!(row[7].to_bits(), m.mean_curvature[i].to_bits());
        assert_eq!(row[8].to_bits(), m.gaussian_curvature[i].to_bits());
        assert_eq!(row[9].to_bits(), m.g1_deviation_deg[i].to_bits());
        assert_eq!(row[10], m.fold[i] as f64);
    }
}

/// `float` scalars beyond the f32 range are written as ±f32::MAX (never inf), values that are
/// f32 exactly, and NaN as NaN; in ASCII as well as binary.
#[test]
fn float_scalars_are_clamped_not_inf() {
    let m = read_mesh(format!("{MODELS}/cube.obj")).unwrap().to_polymesh();
    let mut q = vec![0.0; m.positions.len()];
    q[..5].copy_from_slice(&[1e39, -1e300, 0.1, f32::MAX as f64, 0.5]);
    let want = [f32::MAX, -f32::MAX, 0.1f32, f32::MAX, 0.5];
    let mut buf = Vec::new();
    m.write_ply(&mut buf, PlyFormat::BinaryLittleEndian, &[VertexScalar::float("q", &q)]).unwrap();
    let (_, rows) = ply_vertex_values(&buf);
    for (k, w) in want.iter().enumerate() {
        assert_eq!(rows[k][3], *w as f64, "vertex {k}");
    }
    let mut text = Vec::new();
    m.write_ply(&mut text, PlyFormat::Ascii, &[VertexScalar::float("q", &q)]).unwrap();
    let text = String::from_utf8(text).unwrap();
    let body: Vec<f32> = text.split("end_header\n").nth(1).unwrap().lines().take(5).map(|l| l.split(' ').nth(3).unwrap().parse().unwrap()).collect();
    assert_eq!(body, want);
    // double scalars are exact
    let mut buf = Vec::new();
    m.write_ply(&mut buf, PlyFormat::BinaryLittleEndian, &[VertexScalar::double("q", &q)]).unwrap();
    let (_, rows) = ply_vertex_values(&buf);
    assert_eq!(rows.iter().map(|r| r[3]).collect::<Vec<_>>(), q);
}

/// STL is float32: a position beyond the f32 range is refused with the vertex named, not written
/// as inf; the readers accept such coordinates (up to `COORDINATE_LIMIT`), so this can happen.
#[test]
fn stl_refuses_positions_beyond_f32() {
    let mut cube = read_mesh(format!("{MODELS}/cube.obj")).unwrap().to_polymesh();
    for p in &mut cube.positions {
        *p *= 1e39;
    }
    assert!(gbsurf::mesh::validate::validate(&cube).is_ok(), "1e39 coordinates are valid input");
    let mut buf = Vec::new();
    let e = cube.write_stl(&mut buf).unwrap_err();
    let inner = e.get_ref().and_then(|e| e.downcast_ref::<Float32RangeError>()).expect("typed error");
    assert_eq!(inner.vertex, 0);
    assert_eq!(inner.format, "STL");
    assert!(e.to_string().contains("vertex 0: coordinate -1e39 is beyond the float32 range of STL"), "{e}");
    // at the edge of the range it is written, finite
    let mut edge = cube.clone();
    for p in &mut edge.positions {
        *p *= (f32::MAX as f64) / 1e39;
    }
    let mut buf = Vec::new();
    edge.write_stl(&mut buf).unwrap();
    let floats: Vec<f32> = buf[84..].chunks(50).flat_map(|t| t[..48].chunks(4).map(|b| f32::from_le_bytes(b.try_into().unwrap())).collect::<Vec<_>>()).collect();
    assert!(floats.iter().all(|x| x.is_finite()));
}

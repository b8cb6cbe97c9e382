//! The C ABI called from Rust: every misuse returns its own status code with a message naming the
//! element, nothing panics across the boundary, handles are freed.


use crate::*;
use std::ffi::{c_void, CStr};
use std::ptr::{null, null_mut};

fn last() -> String {
    // SAFETY: never NULL, valid until the next call on this thread.
    unsafe { CStr::from_ptr(gbsurf_last_error_message()) }.to_string_lossy().into_owned()
}

/// The unit cube as flat arrays (outward CCW quads).
fn cube() -> (Vec<f64>, Vec<u32>, Vec<u32>) {
    let p = vec![
        0., 0., 0., 1., 0., 0., 1., 1., 0., 0., 1., 0., 0., 0., 1., 1., 0., 1., 1., 1., 1., 0., 1., 1.,
    ];
    let f = vec![
        0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7,
    ];
    (p, vec![4; 6], f)
}

unsafe fn convert(
    p: &[f64],
    s: &[u32],
    f: &[u32],
    o: *const GbsurfOptions,
    out: *mut *mut GbsurfResult,
) -> u32 {
    unsafe { gbsurf_convert(p.as_ptr(), p.len(), s.as_ptr(), s.len(), f.as_ptr(), f.len(), o, None, null_mut(), out) }
}

#[test]
fn versions() {
    // SAFETY: static string.
    let v = unsafe { CStr::from_ptr(gbsurf_version()) }.to_str().unwrap();
    assert_eq!(v, env!("CARGO_PKG_VERSION"));
    assert_eq!(gbsurf_abi_version(), GBSURF_ABI_VERSION);
}

#[test]
fn options_init_matches_rust_defaults_and_validates() {
    let mut o = std::mem::MaybeUninit::<GbsurfOptions>::uninit();
    // SAFETY: writable struct.
    assert_eq!(unsafe { gbsurf_options_init(o.as_mut_ptr()) }, GBSURF_OK);
    // SAFETY: initialized by gbsurf_options_init.
    let mut o = unsafe { o.assume_init() };
    assert_eq!(o.struct_size as usize, std::mem::size_of::<GbsurfOptions>());
    let d = gbsurf::api::ConvertOptions::default();
    assert_eq!(o.resolution as usize, d.resolution);
    assert_eq!((o.layout, o.resolution), (GBSURF_LAYOUT_QUADS, 2));
    assert_eq!(o.method, GBSURF_METHOD_DUAL);
    assert_eq!(o.twist, GBSURF_TWIST_INTERP);
    assert_eq!(o.middle, GBSURF_MIDDLE_SEED);
    assert_eq!(o.fullness, d.fullness);
    assert_eq!(o.max_memory_mb, d.max_memory_mb);
    // SAFETY: valid struct.
    assert_eq!(unsafe { gbsurf_options_validate(&o) }, GBSURF_OK);
    // SAFETY: NULL is allowed and reported.
    assert_eq!(unsafe { gbsurf_options_init(null_mut()) }, GBSURF_ERR_NULL);
    assert!(last().contains("options"), "{}", last());

    type Case = (fn(&mut GbsurfOptions), u32, &'static str);
    // The limits are the core's (gbsurf::limits), whatever the width of the C field.
    let cases: [Case; 16] = [
        (|o| o.layout = 2, GBSURF_ERR_INVALID_OPTION, "layout"),
        (|o| o.struct_size = 12, GBSURF_ERR_INVALID_OPTION, "struct_size"),
        (|o| o.method = 4, GBSURF_ERR_INVALID_OPTION, "method"),
        (|o| o.twist = 99, GBSURF_ERR_INVALID_OPTION, "twist"),
        (|o| o.middle = 2, GBSURF_ERR_INVALID_OPTION, "middle"),
        (|o| o.weights = 2, GBSURF_ERR_INVALID_OPTION, "weights"),
        (|o| o.best_plane = 2, GBSURF_ERR_INVALID_OPTION, "best_plane"),
        (|o| o.resolution = 0, GBSURF_ERR_INVALID_OPTION, "resolution"),
        (|o| o.levels = 9, GBSURF_ERR_INVALID_OPTION, "levels"),
        (|o| o.resolution = gbsurf::limits::MAX_RESOLUTION as u32 + 1, GBSURF_ERR_INVALID_OPTION, "must be in 1..=1024"),
        (|o| o.resolution = u32::MAX, GBSURF_ERR_INVALID_OPTION, "resolution 4294967295"),
        (|o| o.levels = u32::MAX, GBSURF_ERR_INVALID_OPTION, "levels 4294967295"),
        (|o| o.fullness = f64::NAN, GBSURF_ERR_NAN, "fullness"),
        (|o| o.fullness = 1.0, GBSURF_ERR_INVALID_OPTION, "fullness"),
        (|o| o.max_memory_mb = 0, GBSURF_ERR_INVALID_OPTION, "max-memory-mb 0"),
        (|o| o.max_memory_mb = u64::MAX, GBSURF_ERR_INVALID_OPTION, "max-memory-mb"),
    ];
    for (edit, code, word) in cases {
        let mut bad = o;
        edit(&mut bad);
        // SAFETY: valid struct.
        assert_eq!(unsafe { gbsurf_options_validate(&bad) }, code, "{word}: {}", last());
        assert!(last().contains(word), "{word}: {}", last());
        // The same code from gbsurf_convert, which then leaves `out` NULL.
        let (p, s, f) = cube();
        let mut out = 1usize as *mut GbsurfResult;
        // SAFETY: valid arrays and out pointer.
        assert_eq!(unsafe { convert(&p, &s, &f, &bad, &mut out) }, code);
        assert!(out.is_null());
    }
    o.tile_depth = 2.5;
    // SAFETY: valid struct.
    assert_eq!(unsafe { gbsurf_options_validate(&o) }, GBSURF_OK);
}

#[test]
fn null_pointers_each_named() {
    let (p, s, f) = cube();
    let mut out = null_mut();
    // SAFETY: each call passes one NULL where a pointer is required; the rest valid.
    unsafe {
        assert_eq!(
            gbsurf_convert(p.as_ptr(), p.len(), s.as_ptr(), s.len(), f.as_ptr(), f.len(), null(), None, null_mut(), null_mut()),
            GBSURF_ERR_NULL
        );
        assert!(last().contains("out"), "{}", last());
        assert_eq!(
            gbsurf_convert(null(), p.len(), s.as_ptr(), s.len(), f.as_ptr(), f.len(), null(), None, null_mut(), &mut out),
            GBSURF_ERR_NULL
        );
        assert!(last().contains("positions"), "{}", last());
        assert_eq!(
            gbsurf_convert(p.as_ptr(), p.len(), null(), s.len(), f.as_ptr(), f.len(), null(), None, null_mut(), &mut out),
            GBSURF_ERR_NULL
        );
        assert!(last().contains("face_sizes"), "{}", last());
        assert_eq!(
            gbsurf_convert(p.as_ptr(), p.len(), s.as_ptr(), s.len(), null(), f.len(), null(), None, null_mut(), &mut out),
            GBSURF_ERR_NULL
        );
        assert!(last().contains("face_indices"), "{}", last());
        assert_eq!(gbsurf_convert_file(null(), null(), None, null_mut(), &mut out), GBSURF_ERR_NULL);
        assert!(out.is_null());
        let mut n = 0usize;
        assert_eq!(gbsurf_mesh_vertex_count(null(), &mut n), GBSURF_ERR_NULL);
        assert!(last().contains("result"), "{}", last());
        let mut d = null();
        assert_eq!(gbsurf_mesh_positions(null(), &mut d, &mut n), GBSURF_ERR_NULL);
        assert_eq!(gbsurf_patch_count(null(), &mut n), GBSURF_ERR_NULL);
        assert_eq!(gbsurf_curve_count(null(), &mut n), GBSURF_ERR_NULL);
        assert_eq!(gbsurf_result_report(null(), null_mut()), GBSURF_ERR_NULL);
        // Freeing NULL is a no-op.
        gbsurf_result_free(null_mut());
    }
}

#[test]
fn wrong_counts_out_of_range_and_nan_get_their_codes() {
    let (p, s, f) = cube();
    let mut out = null_mut();
    // SAFETY: all slices valid for the lengths passed.
    unsafe {
        assert_eq!(convert(&p[..23], &s, &f, null(), &mut out), GBSURF_ERR_COUNT);
        assert!(last().contains("23"), "{}", last());
        assert_eq!(convert(&p, &s, &f[..23], null(), &mut out), GBSURF_ERR_COUNT);
        assert!(last().contains("24") && last().contains("23"), "{}", last());
        let mut f2 = f.clone();
        f2[9] = 8; // face 2 corner 1
        assert_eq!(convert(&p, &s, &f2, null(), &mut out), GBSURF_ERR_INDEX);
        assert!(last().contains("face 2 corner 1") && last().contains("vertex index 8"), "{}", last());
        let mut p2 = p.clone();
        p2[13] = f64::NAN; // vertex 4, axis 1
        assert_eq!(convert(&p2, &s, &f, null(), &mut out), GBSURF_ERR_NAN);
        assert!(last().contains("vertex 4") && last().contains("coordinate 1"), "{}", last());
        p2[13] = f64::INFINITY;
        assert_eq!(convert(&p2, &s, &f, null(), &mut out), GBSURF_ERR_NAN);
        // Validation errors name the element: a face listed twice.
        let mut s3 = s.clone();
        s3.push(4);
        let mut f3 = f.clone();
        f3.extend_from_slice(&f[..4]);
        assert_eq!(convert(&p, &s3, &f3, null(), &mut out), GBSURF_ERR_INVALID_MESH);
        assert!(last().contains("face 6"), "{}", last());
        // A face with two corners.
        assert_eq!(convert(&p, &[2, 4], &[0, 1, 0, 3, 2, 1], null(), &mut out), GBSURF_ERR_INVALID_MESH);
        assert!(last().contains("face 0"), "{}", last());
        // Empty input.
        assert_eq!(convert(&[], &[], &[], null(), &mut out), GBSURF_ERR_INVALID_MESH);
        assert!(out.is_null());
    }
}

unsafe extern "C" fn cancel_at_once(fraction: f32, user: *mut c_void) -> bool {
    // SAFETY: the test passes a pointer to a Vec<f32>.
    unsafe { (*(user as *mut Vec<f32>)).push(fraction) };
    false
}

#[test]
fn cancelling_progress_gives_cancelled() {
    let (p, s, f) = cube();
    let mut seen: Vec<f32> = Vec::new();
    let mut out = null_mut();
    // SAFETY: valid arrays; user data is a live Vec<f32>.
    let code = unsafe {
        gbsurf_convert(
            p.as_ptr(), p.len(), s.as_ptr(), s.len(), f.as_ptr(), f.len(), null(),
            Some(cancel_at_once), &mut seen as *mut Vec<f32> as *mut c_void, &mut out,
        )
    };
    assert_eq!(code, GBSURF_ERR_CANCELLED, "{}", last());
    assert!(out.is_null());
    assert_eq!(seen, vec![0.0]);
    assert!(last().contains("cancelled"), "{}", last());
}

#[test]
fn convert_file_reports_io_and_named_validation_errors() {
    let bad = concat!(env!("CARGO_MANIFEST_DIR"), "/../../shared/models/bad/");
    let cases = [
        ("garbage.obj", GBSURF_ERR_IO, "line 1"),
        // Vertices as the OBJ file numbers them (1-based).
        ("nan.obj", GBSURF_ERR_NAN, "vertex 1 (line 2)"),
        ("inf.obj", GBSURF_ERR_NAN, "vertex 1 (line 2)"),
        ("index_out_of_range.obj", GBSURF_ERR_INDEX, "face 5"),
        ("duplicate_face.obj", GBSURF_ERR_INVALID_MESH, "face 6"),
        ("flipped_face.obj", GBSURF_ERR_INVALID_MESH, "line 15"),
        ("nonmanifold_edge.obj", GBSURF_ERR_INVALID_MESH, "edge"),
        ("bowtie_vertex.obj", GBSURF_ERR_INVALID_MESH, "vertex 1 (line 2)"),
        ("repeated_index.obj", GBSURF_ERR_INVALID_MESH, "face"),
        ("zero_area.obj", GBSURF_ERR_INVALID_MESH, "face 6 (line 17) has zero area"),
        ("huge_coordinates.obj", GBSURF_ERR_INVALID_MESH, "exceeds"),
        ("empty.obj", GBSURF_ERR_INVALID_MESH, "empty"),
        ("no_such_file.obj", GBSURF_ERR_IO, "no_such_file"),
    ];
    for (name, code, word) in cases {
        let path = std::ffi::CString::new(format!("{bad}{name}")).unwrap();
        let mut out = null_mut();
        // SAFETY: NUL-terminated path, valid out pointer.
        let got = unsafe { gbsurf_convert_file(path.as_ptr(), null(), None, null_mut(), &mut out) };
        assert_eq!(got, code, "{name}: {}", last());
        assert!(last().contains(word), "{name}: {}", last());
        assert!(out.is_null());
    }
}

/// Converts the cube with `method` (levels/resolution 2) and returns the handle.
fn cube_result(method: u32) -> *mut GbsurfResult {
    let (p, s, f) = cube();
    let mut o = std::mem::MaybeUninit::<GbsurfOptions>::uninit();
    // SAFETY: writable struct, then initialized.
    let mut o = unsafe {
        gbsurf_options_init(o.as_mut_ptr());
        o.assume_init()
    };
    o.method = method;
    o.levels = 2;
    o.resolution = 2;
    o.layout = GBSURF_LAYOUT_TRIANGLES;
    let mut out = null_mut();
    // SAFETY: valid arrays and out pointer.
    let code = unsafe { convert(&p, &s, &f, &o, &mut out) };
    assert_eq!(code, GBSURF_OK, "method {method}: {}", last());
    assert!(!out.is_null());
    out
}

/// The views, copies and report of a result agree with the Rust API's conversion.
fn check_result_matches_rust(method: u32, rust_method: gbsurf::api::Method) {
    let r = cube_result(method);
    let (p, s, f) = cube();
    let mut faces = Vec::new();
    let mut at = 0;
    for &n in &s {
        faces.push(f[at..at + n as usize].to_vec());
        at += n as usize;
    }
    let mesh = gbsurf::mesh::PolyMesh::new(p.chunks(3).map(gbsurf::DVec3::from_slice).collect(), faces);
    let opts = gbsurf::api::ConvertOptions { method: rust_method, levels: 2, resolution: 2, ..gbsurf::api::ConvertOptions::triangles_r8() };
    let conv = gbsurf::api::convert(&mesh, &opts, None).unwrap();
    // SAFETY: `r` is a live handle; all outputs are valid locals.
    unsafe {
        let (mut n, mut t) = (0usize, 0usize);
        assert_eq!(gbsurf_mesh_vertex_count(r, &mut n), GBSURF_OK);
        assert_eq!(gbsurf_mesh_triangle_count(r, &mut t), GBSURF_OK);
        assert_eq!(n, conv.mesh.positions.len());
        assert_eq!(t, conv.mesh.triangles.len());
        let (mut d, mut len) = (null(), 0usize);
        assert_eq!(gbsurf_mesh_positions(r, &mut d, &mut len), GBSURF_OK);
        let pos = std::slice::from_raw_parts(d, len);
        let expect: Vec<f64> = conv.mesh.positions.iter().flat_map(|v| v.to_array()).collect();
        assert_eq!(pos, &expect[..]);
        let mut buf = vec![0.0; len];
        let mut written = 0usize;
        assert_eq!(gbsurf_mesh_copy_normals(r, buf.as_mut_ptr(), buf.len(), &mut written), GBSURF_OK);
        let normals: Vec<f64> = conv.mesh.normals.iter().flat_map(|v| v.to_array()).collect();
        assert_eq!((written, &buf[..]), (normals.len(), &normals[..]));
        assert_eq!(gbsurf_mesh_copy_normals(r, buf.as_mut_ptr(), 5, &mut written), GBSURF_ERR_CAPACITY);
        assert_eq!(written, normals.len());
        assert!(last().contains("5") && last().contains(&normals.len().to_string()), "{}", last());
        let (mut u, mut ulen) = (null(), 0usize);
        assert_eq!(gbsurf_mesh_triangles(r, &mut u, &mut ulen), GBSURF_OK);
        let tris: Vec<u32> = conv.mesh.triangles.iter().flatten().copied().collect();
        assert_eq!(std::slice::from_raw_parts(u, ulen), &tris[..]);
        assert_eq!(gbsurf_mesh_patch_index(r, &mut u, &mut ulen), GBSURF_OK);
        assert_eq!(std::slice::from_raw_parts(u, ulen), &conv.mesh.patch[..]);
        for (f, v) in [
            (gbsurf_mesh_mean_curvature as unsafe extern "C" fn(_, _, _) -> u32, &conv.mesh.mean_curvature),
            (gbsurf_mesh_gaussian_curvature, &conv.mesh.gaussian_curvature),
            (gbsurf_mesh_g1_deviation, &conv.mesh.g1_deviation_deg),
        ] {
            assert_eq!(f(r, &mut d, &mut len), GBSURF_OK);
            assert_eq!(std::slice::from_raw_parts(d, len), &v[..]);
        }
        let mut rep = GbsurfReport { struct_size: std::mem::size_of::<GbsurfReport>() as u32, ..Default::default() };
        assert_eq!(gbsurf_result_report(r, &mut rep), GBSURF_OK);
        assert_eq!(rep.method, method);
        assert_eq!(rep.vertices as usize, n);
        assert_eq!(rep.triangles as usize, t);
        assert_eq!(rep.closed, conv.report.closed as u32);
        assert_eq!(rep.patches as usize, conv.report.patches);
        let mut c = 0usize;
        assert_eq!(gbsurf_report_patches_with_sides(r, 4, &mut c), GBSURF_OK);
        assert_eq!(Some(&c), conv.report.sides_histogram.get("4").or(Some(&0)));
        rep.struct_size = 3;
        assert_eq!(gbsurf_result_report(r, &mut rep), GBSURF_ERR_INVALID_OPTION);
        gbsurf_result_free(r);
    }
}

#[test]
fn catmull_clark_result_matches_rust_api() {
    check_result_matches_rust(GBSURF_METHOD_CATMULL_CLARK, gbsurf::api::Method::CatmullClark);
}

#[test]
fn doo_sabin_result_matches_rust_api_and_has_no_patches() {
    check_result_matches_rust(GBSURF_METHOD_DOO_SABIN, gbsurf::api::Method::DooSabin);
    let r = cube_result(GBSURF_METHOD_DOO_SABIN);
    // SAFETY: live handle, valid outputs.
    unsafe {
        let mut n = 9usize;
        assert_eq!(gbsurf_patch_count(r, &mut n), GBSURF_OK);
        assert_eq!(n, 0);
        assert_eq!(gbsurf_curve_count(r, &mut n), GBSURF_OK);
        assert_eq!(n, 0);
        let mut k = 0u32;
        assert_eq!(gbsurf_patch_kind(r, 0, &mut k), GBSURF_ERR_INDEX);
        assert!(last().contains("patch index 0 out of range (0..0)"), "{}", last());
        let (mut d, mut len) = (null(), 0usize);
        assert_eq!(gbsurf_curve_points(r, 0, &mut d, &mut len), GBSURF_ERR_INDEX);
        assert_eq!(gbsurf_curve_cubic_points(r, 0, &mut d, &mut len), GBSURF_ERR_INDEX);
        assert_eq!(gbsurf_control_net_positions(r, &mut d, &mut len), GBSURF_OK);
        assert_eq!(len, 0);
        let mut w = 7usize;
        assert_eq!(gbsurf_control_net_copy_face_indices(r, null_mut(), 0, &mut w), GBSURF_OK);
        assert_eq!(w, 0);
        gbsurf_result_free(r);
    }
}

/// Patches and curves through the C ABI are the Rust surface's, flattened as documented.
fn check_patches_match_rust(method: u32, rust_method: gbsurf::api::Method) {
    let r = cube_result(method);
    let (p, s, f) = cube();
    let faces: Vec<Vec<u32>> = f.chunks(4).map(|c| c.to_vec()).collect();
    assert_eq!(s.len(), faces.len());
    let mesh = gbsurf::mesh::PolyMesh::new(p.chunks(3).map(gbsurf::DVec3::from_slice).collect(), faces);
    let opts = gbsurf::api::ConvertOptions { method: rust_method, levels: 2, resolution: 2, ..gbsurf::api::ConvertOptions::triangles_r8() };
    let surface = gbsurf::api::convert(&mesh, &opts, None).unwrap().surface.unwrap();
    // SAFETY: `r` is a live handle; outputs are valid locals.
    unsafe {
        let mut n = 0usize;
        assert_eq!(gbsurf_patch_count(r, &mut n), GBSURF_OK);
        assert_eq!(n, surface.patches.len());
        for (pi, patch) in surface.patches.iter().enumerate() {
            let (kind, ribbons, center) = match patch {
                gbsurf::construct::Patch::Gb(g) => (GBSURF_PATCH_GB, &g.ribbons, Some(g.center)),
                gbsurf::construct::Patch::Cgb(c) => (GBSURF_PATCH_CGB, &c.ribbons, None),
            };
            let mut k = 99u32;
            assert_eq!(gbsurf_patch_kind(r, pi, &mut k), GBSURF_OK);
            assert_eq!(k, kind);
            let mut sides = 0usize;
            assert_eq!(gbsurf_patch_sides(r, pi, &mut sides), GBSURF_OK);
            assert_eq!(sides, ribbons.len());
            for (si, rb) in ribbons.iter().enumerate() {
                let (mut d, mut l) = (0usize, 0usize);
                assert_eq!(gbsurf_patch_degree(r, pi, si, &mut d, &mut l), GBSURF_OK);
                assert_eq!((d, l), (rb.degree, rb.layers()));
                let (mut ptr, mut len) = (null(), 0usize);
                assert_eq!(gbsurf_patch_ribbon_points(r, pi, si, &mut ptr, &mut len), GBSURF_OK);
                let pts = std::slice::from_raw_parts(ptr, len);
                assert_eq!(len, 3 * l * (d + 1));
                for (kk, row) in rb.rows().enumerate() {
                    for (j, q) in row.iter().enumerate() {
                        let at = 3 * (kk * (d + 1) + j);
                        assert_eq!(&pts[at..at + 3], &q.to_array(), "patch {pi} side {si} P[{j},{kk}]");
                    }
                }
            }
            assert_eq!(gbsurf_patch_degree(r, pi, sides, &mut 0, &mut 0), GBSURF_ERR_INDEX);
            let mut xyz = [0.0; 3];
            match center {
                Some(c) => {
                    assert_eq!(gbsurf_patch_center(r, pi, xyz.as_mut_ptr()), GBSURF_OK);
                    assert_eq!(xyz, c.to_array());
                }
                None => {
                    assert_eq!(gbsurf_patch_center(r, pi, xyz.as_mut_ptr()), GBSURF_ERR_KIND);
                    assert!(last().contains(&format!("patch {pi}")), "{}", last());
                }
            }
        }
        assert_eq!(gbsurf_curve_count(r, &mut n), GBSURF_OK);
        assert_eq!(n, surface.curves.len());
        for (ci, c) in surface.curves.iter().enumerate() {
            let expect: Vec<f64> = c.iter().flat_map(|q| q.to_array()).collect();
            let mut buf = vec![0.0; expect.len()];
            let mut w = 0usize;
            assert_eq!(gbsurf_curve_copy_points(r, ci, buf.as_mut_ptr(), buf.len(), &mut w), GBSURF_OK);
            assert_eq!((w, buf), (expect.len(), expect));
        }
        check_derived_match_rust(r, &surface);
        gbsurf_result_free(r);
    }
}

/// The control net and the cubic curves through the C ABI are the core's, views and copies alike.
///
/// # Safety
/// `r` is a live handle of a conversion that built `surface`.
unsafe fn check_derived_match_rust(r: *const GbsurfResult, surface: &gbsurf::construct::Surface) {
    let net = surface.control_net();
    let cubic = surface.default_cubic_curves();
    // SAFETY: live handle; every output is a valid local.
    unsafe {
        let (mut d, mut len) = (null(), 0usize);
        assert_eq!(gbsurf_control_net_positions(r, &mut d, &mut len), GBSURF_OK);
        let expect: Vec<f64> = net.positions.iter().flat_map(|q| q.to_array()).collect();
        assert!(!expect.is_empty());
        assert_eq!(std::slice::from_raw_parts(d, len), &expect[..]);
        let mut buf = vec![0.0; len];
        let mut w = 0usize;
        assert_eq!(gbsurf_control_net_copy_positions(r, buf.as_mut_ptr(), len, &mut w), GBSURF_OK);
        assert_eq!((w, &buf[..]), (len, &expect[..]));
        let edges: Vec<u32> = net.edges.iter().flatten().copied().collect();
        for (view, copy, expect) in [
            (
                gbsurf_control_net_face_sizes as unsafe extern "C" fn(_, _, _) -> u32,
                gbsurf_control_net_copy_face_sizes as unsafe extern "C" fn(_, _, _, _) -> u32,
                &net.face_sizes,
            ),
            (gbsurf_control_net_face_indices, gbsurf_control_net_copy_face_indices, &net.face_indices),
            (gbsurf_control_net_edges, gbsurf_control_net_copy_edges, &edges),
            (gbsurf_control_net_patch_index, gbsurf_control_net_copy_patch_index, &net.patch),
        ] {
            let (mut u, mut ulen) = (null(), 0usize);
            assert_eq!(view(r, &mut u, &mut ulen), GBSURF_OK);
            assert_eq!(std::slice::from_raw_parts(u, ulen), &expect[..]);
            let mut buf = vec![0u32; ulen];
            assert_eq!(copy(r, buf.as_mut_ptr(), ulen, &mut w), GBSURF_OK);
            assert_eq!((w, &buf), (ulen, expect));
            if ulen > 0 {
                assert_eq!(copy(r, buf.as_mut_ptr(), ulen - 1, &mut w), GBSURF_ERR_CAPACITY);
                assert_eq!(w, ulen);
            }
        }
        for (ci, c) in cubic.iter().enumerate() {
            let expect: Vec<f64> = c.iter().flat_map(|q| q.to_array()).collect();
            assert_eq!(gbsurf_curve_cubic_points(r, ci, &mut d, &mut len), GBSURF_OK);
            assert_eq!(std::slice::from_raw_parts(d, len), &expect[..]);
            assert_eq!(len % 9, 3, "3k + 1 points");
            let mut buf = vec![0.0; len];
            assert_eq!(gbsurf_curve_copy_cubic_points(r, ci, buf.as_mut_ptr(), len, &mut w), GBSURF_OK);
            assert_eq!(buf, expect);
        }
        assert_eq!(gbsurf_curve_cubic_points(r, cubic.len(), &mut d, &mut len), GBSURF_ERR_INDEX);
        assert!(last().contains("curve index"), "{}", last());
        assert_eq!(gbsurf_control_net_positions(null(), &mut d, &mut len), GBSURF_ERR_NULL);
        assert_eq!(gbsurf_control_net_edges(r, null_mut(), &mut len), GBSURF_ERR_NULL);
        assert!(last().contains("gbsurf_control_net_edges") && last().contains("data"), "{}", last());
    }
}

#[test]
fn dual_patches_and_curves_match_rust_surface() {
    check_patches_match_rust(GBSURF_METHOD_DUAL, gbsurf::api::Method::Dual);
}

#[test]
fn topology_patches_and_curves_match_rust_surface() {
    check_patches_match_rust(GBSURF_METHOD_TOPOLOGY, gbsurf::api::Method::Topology);
}

unsafe extern "C" fn record_until(fraction: f32, user: *mut c_void) -> bool {
    // SAFETY: the tests pass a pointer to (stop fraction, seen fractions).
    let (stop, seen) = unsafe { &mut *(user as *mut (f32, Vec<f32>)) };
    seen.push(fraction);
    fraction < *stop
}

#[test]
fn progress_reaches_one_and_cancels_mid_run() {
    let (p, s, f) = cube();
    for (stop, code) in [(2.0f32, GBSURF_OK), (0.5, GBSURF_ERR_CANCELLED)] {
        let mut state: (f32, Vec<f32>) = (stop, Vec::new());
        let mut out = null_mut();
        // SAFETY: valid arrays; user data is a live (f32, Vec<f32>).
        let got = unsafe {
            gbsurf_convert(
                p.as_ptr(), p.len(), s.as_ptr(), s.len(), f.as_ptr(), f.len(), null(),
                Some(record_until), &mut state as *mut (f32, Vec<f32>) as *mut c_void, &mut out,
            )
        };
        assert_eq!(got, code, "{}", last());
        let seen = &state.1;
        assert!(seen.windows(2).all(|w| w[0] <= w[1]), "{seen:?}");
        if code == GBSURF_OK {
            assert_eq!(seen.last(), Some(&1.0));
            // SAFETY: live handle.
            unsafe { gbsurf_result_free(out) };
        } else {
            assert!(out.is_null());
            assert!(*seen.last().unwrap() >= 0.5 && seen.len() >= 2, "{seen:?}");
            // The callback is not called again after it returned false.
            assert_eq!(seen.iter().filter(|&&x| x >= 0.5).count(), 1, "{seen:?}");
        }
    }
}

#[test]
fn misaligned_pointers_are_rejected_not_dereferenced() {
    let (p, s, f) = cube();
    let mut out = null_mut();
    // One byte past an f64: inside the allocation, but misaligned for f64/u32/structs. Only the
    // first 21 doubles' worth of bytes is claimed, so the memory is in bounds either way.
    let bytes = p.as_ptr() as *const u8;
    // SAFETY: offset 1 and 2 stay inside the vector's allocation.
    let (p1, f1) = unsafe { (bytes.add(1) as *const f64, (f.as_ptr() as *const u8).add(2) as *const u32) };
    // SAFETY: misaligned pointers must be reported, never read.
    unsafe {
        assert_eq!(
            gbsurf_convert(p1, 21, s.as_ptr(), s.len(), f.as_ptr(), f.len(), null(), None, null_mut(), &mut out),
            GBSURF_ERR_NULL
        );
        assert!(last().contains("positions") && last().contains("aligned"), "{}", last());
        assert_eq!(
            gbsurf_convert(p.as_ptr(), p.len(), s.as_ptr(), s.len(), f1, 20, null(), None, null_mut(), &mut out),
            GBSURF_ERR_NULL
        );
        assert!(last().contains("face_indices"), "{}", last());
        // A misaligned options struct (f64 fields) and a misaligned output pointer.
        let mut store = [0u64; 16];
        let o1 = (store.as_mut_ptr() as *mut u8).add(4) as *mut GbsurfOptions;
        assert_eq!(gbsurf_options_init(o1), GBSURF_ERR_NULL);
        assert!(last().contains("options"), "{}", last());
        assert_eq!(convert(&p, &s, &f, o1, &mut out), GBSURF_ERR_NULL);
        assert!(last().contains("options"), "{}", last());
        let out1 = (store.as_mut_ptr() as *mut u8).add(3) as *mut *mut GbsurfResult;
        assert_eq!(convert(&p, &s, &f, null(), out1), GBSURF_ERR_NULL);
        assert!(last().contains("out"), "{}", last());
        assert!(out.is_null());
        // A misaligned handle or accessor output.
        let r = cube_result(GBSURF_METHOD_DUAL);
        let mut n = 0usize;
        let bad_r = (r as *const u8).add(1) as *const GbsurfResult;
        assert_eq!(gbsurf_mesh_vertex_count(bad_r, &mut n), GBSURF_ERR_NULL);
        assert!(last().contains("result"), "{}", last());
        let n1 = (store.as_mut_ptr() as *mut u8).add(1) as *mut usize;
        assert_eq!(gbsurf_mesh_vertex_count(r, n1), GBSURF_ERR_NULL);
        let mut buf = [0f64; 64];
        let b1 = (buf.as_mut_ptr() as *mut u8).add(1) as *mut f64;
        let mut w = 0usize;
        assert_eq!(gbsurf_patch_center(r, 0, b1), GBSURF_ERR_NULL);
        assert_eq!(gbsurf_curve_copy_points(r, 0, b1, 60, &mut w), GBSURF_ERR_NULL);
        assert!(w <= 60, "{w}");
        gbsurf_result_free(r);
    }
}

#[test]
fn lengths_beyond_any_array_are_count_errors() {
    let (p, s, f) = cube();
    let mut out = null_mut();
    // Lengths whose byte size overflows usize, or exceeds isize::MAX: `from_raw_parts` must not
    // see them (undefined behaviour even if nothing is read).
    for huge in [usize::MAX, usize::MAX / 2, (isize::MAX as usize) / 4 + 1] {
        // SAFETY: the huge lengths must be rejected before any pointer is read.
        unsafe {
            let huge3 = huge - huge % 3;
            assert_eq!(
                gbsurf_convert(p.as_ptr(), huge3, s.as_ptr(), s.len(), f.as_ptr(), f.len(), null(), None, null_mut(), &mut out),
                GBSURF_ERR_COUNT,
                "{huge}"
            );
            assert!(last().contains("positions"), "{}", last());
            assert_eq!(
                gbsurf_convert(p.as_ptr(), p.len(), s.as_ptr(), huge, f.as_ptr(), f.len(), null(), None, null_mut(), &mut out),
                GBSURF_ERR_COUNT
            );
            assert!(last().contains("face_sizes"), "{}", last());
            assert_eq!(
                gbsurf_convert(p.as_ptr(), p.len(), s.as_ptr(), s.len(), f.as_ptr(), huge, null(), None, null_mut(), &mut out),
                GBSURF_ERR_COUNT
            );
            assert!(last().contains("face_indices"), "{}", last());
            assert!(out.is_null());
        }
    }
}

#[test]
fn calls_from_a_thread_local_destructor_do_not_abort() {
    use std::sync::atomic::{AtomicU32, AtomicUsize, Ordering::SeqCst};
    static CODE: AtomicU32 = AtomicU32::new(u32::MAX);
    static LEN: AtomicUsize = AtomicUsize::new(usize::MAX);
    // A C/C++ thread-local destructor (or atexit handler of a thread) calling the library after
    // the library's own thread-local message is gone: the call must still return its code
    // (a panic in an `extern "C"` function would abort the whole process).
    struct Late;
    impl Drop for Late {
        fn drop(&mut self) {
            // SAFETY: NULL is a reported error.
            let code = unsafe { gbsurf_options_init(null_mut()) };
            CODE.store(code, SeqCst);
            // SAFETY: never NULL, NUL-terminated.
            let m = unsafe { CStr::from_ptr(gbsurf_last_error_message()) };
            LEN.store(m.to_bytes().len().min(gbsurf_last_error_length()), SeqCst);
        }
    }
    thread_local!(static LATE: Late = const { Late });
    std::thread::spawn(|| {
        // Registered first, destroyed last (thread-local destructors run in reverse order of
        // registration), i.e. after the library's message, which the next call creates.
        LATE.with(|_| ());
        // SAFETY: NULL is a reported error.
        assert_eq!(unsafe { gbsurf_options_init(null_mut()) }, GBSURF_ERR_NULL);
    })
    .join()
    .unwrap();
    assert_eq!(CODE.load(SeqCst), GBSURF_ERR_NULL);
    assert_ne!(LEN.load(SeqCst), usize::MAX);
}

/// The cube's 12 edges as vertex pairs.
fn cube_edges() -> Vec<u32> {
    let (_, s, f) = cube();
    let mut e = Vec::new();
    let mut at = 0;
    for &n in &s {
        let face = &f[at..at + n as usize];
        for i in 0..face.len() {
            let (a, b) = (face[i], face[(i + 1) % face.len()]);
            if a < b {
                e.extend([a, b]);
            }
        }
        at += n as usize;
    }
    e
}

/// The output positions of a live result handle, as points.
fn out_positions(r: *const GbsurfResult) -> Vec<glam::DVec3> {
    let (mut data, mut len) = (null(), 0usize);
    // SAFETY: live handle, writable out-params; the view lives as long as the handle.
    assert_eq!(unsafe { gbsurf_mesh_positions(r, &mut data, &mut len) }, GBSURF_OK);
    // SAFETY: `len` readable values at `data`.
    unsafe { std::slice::from_raw_parts(data, len) }.chunks_exact(3).map(glam::DVec3::from_slice).collect()
}

unsafe fn convert_creased(c: &GbsurfCreases, out: *mut *mut GbsurfResult) -> u32 {
    let (p, s, f) = cube();
    let mut o = std::mem::MaybeUninit::<GbsurfOptions>::uninit();
    // SAFETY: writable struct, then initialized.
    let mut o = unsafe {
        gbsurf_options_init(o.as_mut_ptr());
        o.assume_init()
    };
    o.method = GBSURF_METHOD_TOPOLOGY;
    o.resolution = 4;
    // SAFETY: valid arrays and out pointer (caller).
    unsafe {
        gbsurf_convert_creased(p.as_ptr(), p.len(), s.as_ptr(), s.len(), f.as_ptr(), f.len(), c, &o, None, null_mut(), out)
    }
}

#[test]
fn creased_cube_keeps_its_corners_and_bad_creases_get_their_codes() {
    let e = cube_edges();
    assert_eq!(e.len(), 24);
    let sharp = vec![1.0; 12];
    let mut c = GbsurfCreases {
        edge_vertices: e.as_ptr(),
        edge_sharpness: sharp.as_ptr(),
        edge_count: 12,
        vertices: null(),
        vertex_sharpness: null(),
        vertex_count: 0,
    };
    let mut out = null_mut();
    // SAFETY: valid arrays and out pointer.
    assert_eq!(unsafe { convert_creased(&c, &mut out) }, GBSURF_OK, "{}", last());
    let pos = out_positions(out);
    let (lo, hi) = pos.iter().flat_map(|p| p.to_array()).fold((1.0f64, 0.0f64), |(l, h), x| (l.min(x), h.max(x)));
    assert!(lo.abs() <= 1e-12 && (hi - 1.0).abs() <= 1e-12, "{lo} {hi}");
    let (p, _, _) = cube();
    for q in p.chunks_exact(3) {
        let q = glam::DVec3::from_slice(q);
        assert!(pos.iter().any(|x| x.distance(q) <= 1e-12), "corner {q} missing");
    }
    // SAFETY: live handle.
    unsafe { gbsurf_result_free(out) };
    // NULL creases: the plain conversion
    let mut a = null_mut();
    let mut b = null_mut();
    let (p, s, f) = cube();
    // SAFETY: valid arrays and out pointers.
    unsafe {
        assert_eq!(convert_creased(&GbsurfCreases { edge_count: 0, ..c }, &mut a), GBSURF_OK);
        let mut o = std::mem::MaybeUninit::<GbsurfOptions>::uninit();
        gbsurf_options_init(o.as_mut_ptr());
        let mut o = o.assume_init();
        o.method = GBSURF_METHOD_TOPOLOGY;
        o.resolution = 4;
        assert_eq!(convert(&p, &s, &f, &o, &mut b), GBSURF_OK);
        assert_eq!(out_positions(a), out_positions(b));
        gbsurf_result_free(a);
        gbsurf_result_free(b);
    }
    // NaN, out of range, missing edge, corner index, NULL with a count
    let nan = vec![f64::NAN; 12];
    c.edge_sharpness = nan.as_ptr();
    // SAFETY: as above.
    assert_eq!(unsafe { convert_creased(&c, &mut out) }, GBSURF_ERR_NAN);
    assert!(last().contains("edge crease 0"), "{}", last());
    let big = vec![2.0; 12];
    c.edge_sharpness = big.as_ptr();
    // SAFETY: as above.
    assert_eq!(unsafe { convert_creased(&c, &mut out) }, GBSURF_ERR_INVALID_MESH);
    assert!(last().contains("edge crease 0 on edge"), "{}", last());
    let diag = [0u32, 2];
    c.edge_sharpness = sharp.as_ptr();
    let c2 = GbsurfCreases { edge_vertices: diag.as_ptr(), edge_count: 1, ..c };
    // SAFETY: as above.
    assert_eq!(unsafe { convert_creased(&c2, &mut out) }, GBSURF_ERR_INVALID_MESH);
    assert!(last().contains("(0, 2) is not an edge"), "{}", last());
    let v = [8u32];
    let c3 = GbsurfCreases { edge_count: 0, vertices: v.as_ptr(), vertex_sharpness: sharp.as_ptr(), vertex_count: 1, ..c };
    // SAFETY: as above.
    assert_eq!(unsafe { convert_creased(&c3, &mut out) }, GBSURF_ERR_INDEX);
    assert!(last().contains("vertex 8 out of range"), "{}", last());
    let c4 = GbsurfCreases { edge_vertices: null(), ..c };
    // SAFETY: as above (the NULL array is the error under test).
    assert_eq!(unsafe { convert_creased(&c4, &mut out) }, GBSURF_ERR_NULL);
    assert!(last().contains("creases.edge_vertices"), "{}", last());
    assert!(out.is_null());
}

#[test]
fn output_too_large_is_refused_with_its_code_and_message() {
    let (p, s, f) = cube();
    let mut o = std::mem::MaybeUninit::<GbsurfOptions>::uninit();
    // SAFETY: writable struct, then initialized.
    let mut o = unsafe {
        gbsurf_options_init(o.as_mut_ptr());
        o.assume_init()
    };
    o.method = GBSURF_METHOD_CATMULL_CLARK;
    o.levels = 8;
    o.max_memory_mb = 64;
    let mut out = 1usize as *mut GbsurfResult;
    // SAFETY: valid arrays and out pointer.
    assert_eq!(unsafe { convert(&p, &s, &f, &o, &mut out) }, GBSURF_ERR_TOO_LARGE);
    assert!(out.is_null());
    let m = last();
    assert!(m.contains("output too large: catmull-clark would make about 393218 output vertices"), "{m}");
    assert!(m.contains("above the limit of 64 MiB") && m.contains("GbsurfOptions.max_memory_mb"), "{m}");
    // The default limit lets a smaller conversion through.
    o.max_memory_mb = 1024;
    o.levels = 4;
    let mut out = null_mut();
    // SAFETY: valid arrays and out pointer.
    assert_eq!(unsafe { convert(&p, &s, &f, &o, &mut out) }, GBSURF_OK, "{}", last());
    // SAFETY: a result of gbsurf_convert.
    unsafe { gbsurf_result_free(out) };
}

/// Converts `mesh` (dual, resolution 3) through the C ABI and through Rust.
fn dual_report(mesh: &gbsurf::mesh::PolyMesh) -> (*mut GbsurfResult, gbsurf::quality::Report) {
    let options = gbsurf::api::ConvertOptions { method: gbsurf::api::Method::Dual, resolution: 3, ..Default::default() };
    let rust = gbsurf::api::convert(mesh, &options, None).unwrap().report;
    let p: Vec<f64> = mesh.positions.iter().flat_map(|q| q.to_array()).collect();
    let s: Vec<u32> = mesh.faces.iter().map(|f| f.len() as u32).collect();
    let f: Vec<u32> = mesh.faces.iter().flatten().copied().collect();
    let mut o = std::mem::MaybeUninit::<GbsurfOptions>::uninit();
    // SAFETY: writable struct, then initialized; valid arrays and out pointer.
    unsafe {
        gbsurf_options_init(o.as_mut_ptr());
        let mut o = o.assume_init();
        o.resolution = 3;
        o.method = GBSURF_METHOD_DUAL;
        let mut r = null_mut();
        assert_eq!(convert(&p, &s, &f, &o, &mut r), GBSURF_OK, "{}", last());
        (r, rust)
    }
}

/// The report's validity fields (second version) equal the Rust report's, the first version's size
/// is still accepted and gets only its own fields, and the fold sites are listed.
#[test]
fn report_carries_validity_and_accepts_the_first_version() {
    // A torus with one cage vertex pushed through the tube: the cage and the dual surface cross
    // themselves (valid: no intersections beyond the cage's own). OpenSubdiv's bishop without its
    // creases: its dual report at r = 3 counts 2 folded patches and 5 self-intersecting pairs (not
    // valid; docs/math.md#fold-clearing). A borderline fixture: the 2 folds are dual patches 844 and
    // 846, next to the cage vertex 844 where the topology structure is refused, so a change to the
    // construction may clear them; hence only folds > 0 is asserted. (OpenSubdiv's rook without
    // its creases served here until the direction blends were kept on their side of the curve,
    // docs/math.md#blend-side: its 24 folded patches are gone; before it, a cube with a corner
    // pulled inside, until the fold rule's blended reference.) The plain torus: no self-intersections, so the cage is not checked
    // (GBSURF_NOT_CHECKED).
    let plain = gbsurf::mesh::generate::torus(10, 6, 10.0, 3.0).unwrap();
    let mut torus = gbsurf::mesh::generate::torus(10, 6, 10.0, 3.0).unwrap();
    let c = torus.positions[0];
    torus.positions[0] = c - 10.0 * glam::DVec3::new(c.x, c.y, 0.0).normalize();
    // Without its crease tags (the C call below passes positions and faces only).
    let tagged = gbsurf::read_mesh(concat!(env!("CARGO_MANIFEST_DIR"), "/../tests/data/opensubdiv/catmark_bishop.obj")).unwrap();
    let bishop = gbsurf::mesh::PolyMesh::new(tagged.positions, tagged.faces);
    for (mesh, kind) in [(torus, "crossing"), (bishop, "folded"), (plain, "plain")] {
        let (r, rust) = dual_report(&mesh);
        match kind {
            "folded" => assert!(rust.folds > 0 && !rust.fold_sites.is_empty() && !rust.valid, "{rust:?}"),
            "crossing" => assert!(
                rust.self_intersections > 0 && rust.input_self_intersections > Some(0) && rust.valid,
                "{rust:?}"
            ),
            _ => assert!(
                rust.self_intersections == 0 && rust.input_self_intersections.is_none() && rust.valid,
                "{rust:?}"
            ),
        }
        // SAFETY: `r` is a live handle; the out pointers are writable locals.
        unsafe {
            let mut rep = GbsurfReport { struct_size: REPORT_SIZE, ..Default::default() };
            assert_eq!(gbsurf_result_report(r, &mut rep), GBSURF_OK);
            assert_eq!(rep.struct_size, REPORT_SIZE);
            assert_eq!(rep.valid, rust.valid as u32);
            assert_eq!(rep.input_closed, rust.input_closed as u32);
            assert_eq!(rep.self_intersections as usize, rust.self_intersections);
            let cage = rust.input_self_intersections.map_or(GBSURF_NOT_CHECKED, |n| n as u64);
            assert_eq!(rep.input_self_intersections, cage);
            assert_eq!(rep.input_self_intersections == GBSURF_NOT_CHECKED, rep.self_intersections == 0);
            assert_eq!(rep.folds as usize, rust.folds);
            assert_eq!(rep.flipped_triangles as usize, rust.flipped_triangles);
            assert_eq!(rep.fold_sites as usize, rust.fold_sites.len());
            assert_eq!(rep.max_abs_mean_curvature_times_diagonal, rust.max_abs_mean_curvature_times_diagonal);
            assert_eq!(rep.quads as usize, rust.quads);
            for (k, site) in rust.fold_sites.iter().enumerate() {
                let (mut patch, mut u, mut v) = (0usize, 0.0, 0.0);
                assert_eq!(gbsurf_report_fold_site(r, k, &mut patch, &mut u, &mut v), GBSURF_OK);
                assert_eq!((patch, u, v), (site.patch, site.u, site.v));
            }
            let (mut patch, mut u, mut v) = (0usize, 0.0, 0.0);
            let n = rust.fold_sites.len();
            assert_eq!(gbsurf_report_fold_site(r, n, &mut patch, &mut u, &mut v), GBSURF_ERR_INDEX);
            assert!(last().contains(&format!("fold site {n} out of range")), "{}", last());
            if n > 0 {
                assert_eq!(gbsurf_report_fold_site(r, 0, null_mut(), &mut u, &mut v), GBSURF_ERR_NULL);
            }
            // The first version: its size is accepted, and nothing past it is written.
            let mut old = GbsurfReport { struct_size: REPORT_SIZE_V1, valid: 7, folds: 7, ..Default::default() };
            assert_eq!(gbsurf_result_report(r, &mut old), GBSURF_OK);
            assert_eq!(old.struct_size, REPORT_SIZE_V1);
            assert_eq!((old.vertices, old.triangles), (rep.vertices, rep.triangles));
            assert_eq!((old.valid, old.folds), (7, 7));
            gbsurf_result_free(r);
        }
    }
}

/// The quad layout through the C ABI (the default): quads, their count, the per-face corner and
/// patch views, equal to the Rust API's; the cube at r = 2 has Catmull–Clark level 2's counts.
#[test]
fn quad_layout_views_match_rust() {
    let (p, s, f) = cube();
    let mut o = std::mem::MaybeUninit::<GbsurfOptions>::uninit();
    // SAFETY: writable struct, then initialized.
    let mut o = unsafe {
        gbsurf_options_init(o.as_mut_ptr());
        o.assume_init()
    };
    o.method = GBSURF_METHOD_TOPOLOGY;
    let mut r = null_mut();
    // SAFETY: valid arrays and out pointer.
    assert_eq!(unsafe { convert(&p, &s, &f, &o, &mut r) }, GBSURF_OK, "{}", last());
    let mut faces = Vec::new();
    for k in 0..6 {
        faces.push(f[4 * k..4 * k + 4].to_vec());
    }
    let mesh = gbsurf::mesh::PolyMesh::new(p.chunks(3).map(gbsurf::DVec3::from_slice).collect(), faces);
    let opts = gbsurf::api::ConvertOptions { method: gbsurf::api::Method::Topology, ..gbsurf::api::ConvertOptions::default() };
    let conv = gbsurf::api::convert(&mesh, &opts, None).unwrap();
    // SAFETY: `r` is a live handle; all outputs are valid locals.
    unsafe {
        let (mut n, mut q, mut t) = (0usize, 0usize, 0usize);
        assert_eq!(gbsurf_mesh_vertex_count(r, &mut n), GBSURF_OK);
        assert_eq!(gbsurf_mesh_quad_count(r, &mut q), GBSURF_OK);
        assert_eq!(gbsurf_mesh_triangle_count(r, &mut t), GBSURF_OK);
        assert_eq!((n, q, t), (98, 96, 192));
        let (mut u, mut len) = (null(), 0usize);
        assert_eq!(gbsurf_mesh_quads(r, &mut u, &mut len), GBSURF_OK);
        assert_eq!(std::slice::from_raw_parts(u, len), conv.mesh.quads.as_flattened());
        let mut buf = vec![0u32; len];
        let mut written = 0usize;
        assert_eq!(gbsurf_mesh_copy_quads(r, buf.as_mut_ptr(), buf.len(), &mut written), GBSURF_OK);
        assert_eq!(&buf[..written], conv.mesh.quads.as_flattened());
        assert_eq!(gbsurf_mesh_face_corner(r, &mut u, &mut len), GBSURF_OK);
        assert_eq!(std::slice::from_raw_parts(u, len), &conv.mesh.face_corner[..]);
        assert_eq!(len, 96);
        assert_eq!(gbsurf_mesh_cage_corner(r, &mut u, &mut len), GBSURF_OK);
        assert_eq!(std::slice::from_raw_parts(u, len), conv.mesh.cage_corner.as_flattened());
        assert_eq!(len, 2 * 96);
        let (mut c, mut clen) = (null(), 0usize);
        assert_eq!(gbsurf_mesh_cage_coords(r, &mut c, &mut clen), GBSURF_OK);
        assert_eq!(std::slice::from_raw_parts(c, clen), conv.mesh.cage_coords.as_flattened());
        assert_eq!(clen, 8 * 96);
        assert_eq!(gbsurf_mesh_cage_coords(r, null_mut(), &mut clen), GBSURF_ERR_NULL);
        assert_eq!(gbsurf_mesh_cage_loop_corner(r, &mut u, &mut len), GBSURF_OK);
        assert_eq!(len, 0, "quad layout: the quads' cage corners serve their corners");
        assert_eq!(gbsurf_mesh_triangle_patch(r, &mut u, &mut len), GBSURF_OK);
        assert_eq!(std::slice::from_raw_parts(u, len), &conv.mesh.triangle_patch[..]);
        // The edge table of the quads: the Rust API's; closed (E = 192, so V − E + F = 98 − 192 +
        // 96 = 2) and every edge is named by two corners.
        let edges = conv.mesh.edges();
        assert_eq!(gbsurf_mesh_edges(r, &mut u, &mut len), GBSURF_OK);
        assert_eq!(std::slice::from_raw_parts(u, len), edges.edges.as_flattened());
        assert_eq!(len, 2 * 192);
        let mut ebuf = vec![0u32; len];
        assert_eq!(gbsurf_mesh_copy_edges(r, ebuf.as_mut_ptr(), ebuf.len(), &mut written), GBSURF_OK);
        assert_eq!(&ebuf[..written], edges.edges.as_flattened());
        assert_eq!(gbsurf_mesh_corner_edges(r, &mut u, &mut len), GBSURF_OK);
        let corner_edge = std::slice::from_raw_parts(u, len);
        assert_eq!(corner_edge, &edges.corner_edge[..]);
        assert_eq!(len, 4 * 96);
        let mut uses = vec![0; 192];
        corner_edge.iter().for_each(|&e| uses[e as usize] += 1);
        assert!(uses.iter().all(|&n| n == 2), "{uses:?}");
        let quads = conv.mesh.quads.as_flattened();
        for (c, &e) in corner_edge.iter().enumerate() {
            let (a, b) = (quads[c], quads[if c % 4 == 3 { c - 3 } else { c + 1 }]);
            assert_eq!(edges.edges[e as usize], [a.min(b), a.max(b)], "corner {c}");
        }
        assert_eq!(gbsurf_mesh_copy_corner_edges(r, ebuf.as_mut_ptr(), 3, &mut written), GBSURF_ERR_CAPACITY);
        assert_eq!(written, 4 * 96, "the needed count");
        assert_eq!(gbsurf_mesh_edges(null(), &mut u, &mut len), GBSURF_ERR_NULL);
        gbsurf_result_free(r);
    }
}

/// A slab of thickness 1 over the square [-2, 2]² with the square hole [-1, 1]² cut through it,
/// as flat arrays: top face 0 and bottom face 1 carry one inner loop each.
fn ring_slab() -> (Vec<f64>, Vec<u32>, Vec<u32>, [u32; 2], [u32; 2], Vec<u32>) {
    let mut p = Vec::new();
    for (r, z) in [(2.0, 0.0), (2.0, 1.0), (1.0, 0.0), (1.0, 1.0)] {
        for (x, y) in [(-r, -r), (r, -r), (r, r), (-r, r)] {
            p.extend([x, y, z]);
        }
    }
    let f: Vec<u32> = vec![
        4, 5, 6, 7, 3, 2, 1, 0, // top, bottom (outer loops)
        0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7, // outer walls
        9, 8, 12, 13, 10, 9, 13, 14, 11, 10, 14, 15, 8, 11, 15, 12, // hole walls
    ];
    (p, vec![4; 10], f, [0, 1], [4, 4], vec![15, 14, 13, 12, 8, 9, 10, 11])
}

unsafe fn convert_holed(h: *const GbsurfHoles, out: *mut *mut GbsurfResult) -> u32 {
    let (p, s, f, ..) = ring_slab();
    let mut o = std::mem::MaybeUninit::<GbsurfOptions>::uninit();
    // SAFETY: writable struct, then initialized.
    let mut o = unsafe {
        gbsurf_options_init(o.as_mut_ptr());
        o.assume_init()
    };
    o.resolution = 4;
    // SAFETY: valid arrays and out pointer (caller).
    unsafe {
        gbsurf_convert_holed(p.as_ptr(), p.len(), s.as_ptr(), s.len(), f.as_ptr(), f.len(), null(), h, &o, None, null_mut(), out)
    }
}

#[test]
fn holed_slab_converts_and_bad_holes_get_their_codes() {
    let (_, _, _, faces, sizes, idx) = ring_slab();
    let mut h = GbsurfHoles { faces: faces.as_ptr(), sizes: sizes.as_ptr(), count: 2, indices: idx.as_ptr(), indices_len: 8 };
    let mut out = null_mut();
    // SAFETY: valid arrays and out pointer.
    assert_eq!(unsafe { convert_holed(&h, &mut out) }, GBSURF_OK, "{}", last());
    let pos = out_positions(out);
    assert!(!pos.is_empty());
    // the hole stays open: no output point near the slab's centre line
    assert!(pos.iter().all(|q| q.truncate().length() > 0.9), "a point inside the hole");
    // SAFETY: live handle.
    unsafe { gbsurf_result_free(out) };
    // counts, face index, orientation, NULL with a count
    h.indices_len = 7;
    // SAFETY: as above (7 readable indices).
    assert_eq!(unsafe { convert_holed(&h, &mut out) }, GBSURF_ERR_COUNT, "{}", last());
    h.indices_len = 8;
    let bad_face = [0u32, 99];
    h.faces = bad_face.as_ptr();
    // SAFETY: as above.
    assert_eq!(unsafe { convert_holed(&h, &mut out) }, GBSURF_ERR_INDEX, "{}", last());
    assert!(last().contains("face 99"), "{}", last());
    h.faces = faces.as_ptr();
    let same_way = [12u32, 13, 14, 15, 8, 9, 10, 11];
    h.indices = same_way.as_ptr();
    // SAFETY: as above.
    assert_eq!(unsafe { convert_holed(&h, &mut out) }, GBSURF_ERR_INVALID_MESH);
    assert!(last().contains("hole 0 of face 0"), "{}", last());
    h.indices = null();
    // SAFETY: as above.
    assert_eq!(unsafe { convert_holed(&h, &mut out) }, GBSURF_ERR_NULL);
    assert!(last().contains("holes.indices"), "{}", last());
}

/// The triangle layout through the C ABI: per triangle corner the cage coordinates and the
/// corner's own cage corner, equal to the Rust API's (6 values per triangle each).
#[test]
fn triangle_layout_cage_views_match_rust() {
    let (p, s, f) = cube();
    let mut o = std::mem::MaybeUninit::<GbsurfOptions>::uninit();
    // SAFETY: writable struct, then initialized.
    let mut o = unsafe {
        gbsurf_options_init(o.as_mut_ptr());
        o.assume_init()
    };
    o.method = GBSURF_METHOD_DUAL;
    o.layout = GBSURF_LAYOUT_TRIANGLES;
    o.resolution = 3;
    let mut r = null_mut();
    // SAFETY: valid arrays and out pointer.
    assert_eq!(unsafe { convert(&p, &s, &f, &o, &mut r) }, GBSURF_OK, "{}", last());
    let faces = f.chunks(4).map(<[u32]>::to_vec).collect();
    let mesh = gbsurf::mesh::PolyMesh::new(p.chunks(3).map(gbsurf::DVec3::from_slice).collect(), faces);
    let opts = gbsurf::api::ConvertOptions {
        method: gbsurf::api::Method::Dual,
        layout: gbsurf::gb::Layout::Triangles,
        resolution: 3,
        ..gbsurf::api::ConvertOptions::default()
    };
    let conv = gbsurf::api::convert(&mesh, &opts, None).unwrap();
    let nt = conv.mesh.triangles.len();
    // SAFETY: `r` is a live handle; all outputs are valid locals.
    unsafe {
        let (mut u, mut len) = (null(), 0usize);
        assert_eq!(gbsurf_mesh_cage_loop_corner(r, &mut u, &mut len), GBSURF_OK);
        assert_eq!(len, 6 * nt);
        assert_eq!(std::slice::from_raw_parts(u, len), conv.mesh.cage_loop_corner.as_flattened());
        let (mut c, mut clen) = (null(), 0usize);
        assert_eq!(gbsurf_mesh_cage_coords(r, &mut c, &mut clen), GBSURF_OK);
        assert_eq!(clen, 6 * nt);
        assert_eq!(std::slice::from_raw_parts(c, clen), conv.mesh.cage_coords.as_flattened());
        assert_eq!(gbsurf_mesh_cage_loop_corner(r, null_mut(), &mut len), GBSURF_ERR_NULL);
        assert_eq!(gbsurf_mesh_cage_loop_corner(null(), &mut u, &mut len), GBSURF_ERR_NULL);
        gbsurf_result_free(r);
    }
}

/// `gbsurf_cage_loop_values` on the views of a result equals the Rust API's keep-corners values,
/// in both layouts, and names every wrong argument.
#[test]
fn cage_loop_values_through_the_views() {
    let (p, s, f) = cube();
    // The cage positions per face corner as the attribute (dim 3).
    let values: Vec<f32> = f.iter().flat_map(|&v| [0, 1, 2].map(|c| p[3 * v as usize + c] as f32)).collect();
    let faces = f.chunks(4).map(<[u32]>::to_vec).collect();
    let mesh = gbsurf::mesh::PolyMesh::new(p.chunks(3).map(gbsurf::DVec3::from_slice).collect(), faces);
    for layout in [GBSURF_LAYOUT_QUADS, GBSURF_LAYOUT_TRIANGLES] {
        let mut o = std::mem::MaybeUninit::<GbsurfOptions>::uninit();
        // SAFETY: writable struct, then initialized.
        let mut o = unsafe {
            gbsurf_options_init(o.as_mut_ptr());
            o.assume_init()
        };
        o.layout = layout;
        o.resolution = 3;
        let mut r = null_mut();
        // SAFETY: valid arrays and out pointer.
        assert_eq!(unsafe { convert(&p, &s, &f, &o, &mut r) }, GBSURF_OK, "{}", last());
        let opts = gbsurf::api::ConvertOptions {
            layout: if layout == GBSURF_LAYOUT_QUADS { gbsurf::gb::Layout::Quads } else { gbsurf::gb::Layout::Triangles },
            resolution: 3,
            ..gbsurf::api::ConvertOptions::default()
        };
        let want = gbsurf::api::convert(&mesh, &opts, None).unwrap().mesh.cage_loop_values(&s, &values, 3).unwrap();
        // SAFETY: `r` is a live handle; the views live until it is freed; outputs are locals.
        unsafe {
            let (mut fc, mut fl, mut lc, mut ll, mut cc, mut cl) = (null(), 0usize, null(), 0usize, null(), 0usize);
            assert_eq!(gbsurf_mesh_cage_corner(r, &mut fc, &mut fl), GBSURF_OK);
            assert_eq!(gbsurf_mesh_cage_loop_corner(r, &mut lc, &mut ll), GBSURF_OK);
            assert_eq!(gbsurf_mesh_cage_coords(r, &mut cc, &mut cl), GBSURF_OK);
            let mut out = vec![0f32; 3 * cl / 2];
            let call = |values: *const f32, vlen: usize, dim: usize, out: *mut f32, olen: usize| {
                gbsurf_cage_loop_values(s.as_ptr(), s.len(), values, vlen, dim, fc, fl, lc, ll, cc, cl, out, olen)
            };
            assert_eq!(call(values.as_ptr(), values.len(), 3, out.as_mut_ptr(), out.len()), GBSURF_OK, "{}", last());
            assert_eq!(out, want);
            // Wrong arguments: each its code and a message naming it; `out` untouched.
            let before = out.clone();
            assert_eq!(call(null(), values.len(), 3, out.as_mut_ptr(), out.len()), GBSURF_ERR_NULL);
            assert!(last().contains("values"), "{}", last());
            assert_eq!(call(values.as_ptr(), values.len() - 1, 3, out.as_mut_ptr(), out.len()), GBSURF_ERR_COUNT);
            assert!(last().contains("values (dim per cage face corner)"), "{}", last());
            // A huge dim is a count error, never a panic; an `out` on top of an input is refused.
            assert_eq!(call(values.as_ptr(), values.len(), 1 << 62, out.as_mut_ptr(), out.len()), GBSURF_ERR_COUNT);
            assert_eq!(call(values.as_ptr(), 0, usize::MAX, null_mut(), usize::MAX), GBSURF_ERR_COUNT, "{}", last());
            let mut alias = values.clone();
            alias.resize(out.len().max(values.len()), 0.0);
            let (pm, len) = (alias.as_mut_ptr(), alias.len());
            assert!(len >= out.len());
            let code = gbsurf_cage_loop_values(s.as_ptr(), s.len(), pm as *const f32, values.len(), 3, fc, fl, lc, ll, cc, cl, pm, out.len());
            assert_eq!(code, GBSURF_ERR_COUNT, "{}", last());
            assert!(last().contains("out overlaps the input `values`"), "{}", last());
            assert_eq!(call(values.as_ptr(), values.len(), 3, out.as_mut_ptr(), out.len() - 1), GBSURF_ERR_COUNT);
            assert!(last().contains("out_len"), "{}", last());
            assert_eq!(call(values.as_ptr(), values.len(), 0, out.as_mut_ptr(), 0), GBSURF_ERR_COUNT);
            assert_eq!(call(values.as_ptr(), values.len(), 3, null_mut(), out.len()), GBSURF_ERR_NULL);
            let three = [4u32; 3];
            let code = gbsurf_cage_loop_values(three.as_ptr(), 3, values.as_ptr(), 36, 3, fc, fl, lc, ll, cc, cl, out.as_mut_ptr(), out.len());
            assert_eq!(code, GBSURF_ERR_INDEX, "{}", last());
            assert!(last().contains("cage face"), "{}", last());
            assert_eq!(out, before);
            gbsurf_result_free(r);
        }
    }
}

/// `gbsurf_cage_loop_values_holed` on a holed slab: the result's cage corners name the user's
/// faces and corners (outer loop, then the hole's), values per user corner give the Rust API's
/// values, the plain entry refuses them (a corner past the outer loop), bad holes get their codes.
#[test]
fn cage_loop_values_holed_takes_the_users_corners() {
    let (p, s, f, hf, hs, idx) = ring_slab();
    let h = GbsurfHoles { faces: hf.as_ptr(), sizes: hs.as_ptr(), count: 2, indices: idx.as_ptr(), indices_len: 8 };
    let mut r = null_mut();
    // SAFETY: valid arrays and out pointer.
    assert_eq!(unsafe { convert_holed(&h, &mut r) }, GBSURF_OK, "{}", last());
    // The user's loops per face: outer loop, then the face's holes.
    let mut loops: Vec<Vec<u32>> = f.chunks(4).map(<[u32]>::to_vec).collect();
    loops[0].extend_from_slice(&idx[..4]);
    loops[1].extend_from_slice(&idx[4..]);
    let values: Vec<f32> =
        loops.iter().flatten().flat_map(|&v| [0, 1, 2].map(|c| p[3 * v as usize + c] as f32)).collect();
    let holes = vec![
        gbsurf::mesh::Hole { face: 0, vertices: idx[..4].to_vec() },
        gbsurf::mesh::Hole { face: 1, vertices: idx[4..].to_vec() },
    ];
    let faces = f.chunks(4).map(<[u32]>::to_vec).collect();
    let positions = p.chunks(3).map(gbsurf::DVec3::from_slice).collect();
    let mesh = gbsurf::mesh::PolyMesh { holes, ..gbsurf::mesh::PolyMesh::new(positions, faces) };
    let opts = gbsurf::api::ConvertOptions { resolution: 4, ..gbsurf::api::ConvertOptions::default() };
    let cage = gbsurf::tessellate::CageFaces { sizes: &s, hole_faces: &hf, hole_sizes: &hs };
    let conv = gbsurf::api::convert(&mesh, &opts, None).unwrap();
    let want = conv.mesh.cage_loop_values(cage, &values, 3).unwrap();
    // Faces 0 and 1 (with holes) have 8 user corners; every corner of them is used.
    let mut used = [[false; 8]; 2];
    for &[face, corner] in &conv.mesh.cage_corner {
        assert!((face as usize) < s.len(), "face {face}");
        if face < 2 {
            used[face as usize][corner as usize] = true;
        } else {
            assert!(corner < 4);
        }
    }
    assert_eq!(used, [[true; 8]; 2]);
    // SAFETY: `r` is a live handle; the views live until it is freed; outputs are locals.
    unsafe {
        let (mut fc, mut fl, mut lc, mut ll, mut cc, mut cl) = (null(), 0usize, null(), 0usize, null(), 0usize);
        assert_eq!(gbsurf_mesh_cage_corner(r, &mut fc, &mut fl), GBSURF_OK);
        assert_eq!(gbsurf_mesh_cage_loop_corner(r, &mut lc, &mut ll), GBSURF_OK);
        assert_eq!(gbsurf_mesh_cage_coords(r, &mut cc, &mut cl), GBSURF_OK);
        assert_eq!(std::slice::from_raw_parts(fc, fl), conv.mesh.cage_corner.as_flattened());
        let mut out = vec![0f32; 3 * cl / 2];
        let call = |hole_faces: &[u32], hole_sizes: &[u32], n: usize, out: &mut [f32]| {
            gbsurf_cage_loop_values_holed(
                s.as_ptr(), s.len(), hole_faces.as_ptr(), hole_sizes.as_ptr(), n, values.as_ptr(), values.len(), 3,
                fc, fl, lc, ll, cc, cl, out.as_mut_ptr(), out.len(),
            )
        };
        assert_eq!(call(&hf, &hs, 2, &mut out), GBSURF_OK, "{}", last());
        assert_eq!(out, want);
        let before = out.clone();
        // Without the holes the values are too many, and with the faces' outer sizes alone
        // (values to match) the corners past the outer loops are out of range.
        let plain = |vlen: usize, out: &mut [f32]| {
            let (o, olen) = (out.as_mut_ptr(), out.len());
            gbsurf_cage_loop_values(s.as_ptr(), s.len(), values.as_ptr(), vlen, 3, fc, fl, lc, ll, cc, cl, o, olen)
        };
        assert_eq!(plain(values.len(), &mut out), GBSURF_ERR_COUNT, "{}", last());
        assert_eq!(plain(3 * 40, &mut out), GBSURF_ERR_INDEX, "{}", last());
        assert!(last().contains("which has 4 corners"), "{}", last());
        assert_eq!(call(&[0, 99], &hs, 2, &mut out), GBSURF_ERR_INDEX, "{}", last());
        assert!(last().contains("hole 1 belongs to cage face 99"), "{}", last());
        assert_eq!(call(&hf, &[4, 2], 2, &mut out), GBSURF_ERR_COUNT, "{}", last());
        assert!(last().contains("hole 1 has 2 corners"), "{}", last());
        let code = gbsurf_cage_loop_values_holed(
            s.as_ptr(), s.len(), null(), hs.as_ptr(), 2, values.as_ptr(), values.len(), 3, fc, fl, lc, ll, cc, cl,
            out.as_mut_ptr(), out.len(),
        );
        assert_eq!(code, GBSURF_ERR_NULL, "{}", last());
        assert_eq!(out, before);
        gbsurf_result_free(r);
    }
}

/// `middle = GBSURF_MIDDLE_FAIR` reaches the construction: a cube with one corner pulled out
/// converts to a different closed surface than with `GBSURF_MIDDLE_SEED` (the default).
#[test]
fn middle_fair_changes_the_surface() {
    let (mut p, s, f) = cube();
    p[18..21].copy_from_slice(&[1.6, 1.4, 1.5]);
    let run = |middle: u32| {
        let mut o = std::mem::MaybeUninit::<GbsurfOptions>::uninit();
        // SAFETY: writable struct, then initialized by gbsurf_options_init.
        let mut o = unsafe {
            assert_eq!(gbsurf_options_init(o.as_mut_ptr()), GBSURF_OK);
            o.assume_init()
        };
        o.middle = middle;
        let mut r = null_mut();
        // SAFETY: valid arrays and options, writable out-param.
        assert_eq!(unsafe { convert(&p, &s, &f, &o, &mut r) }, GBSURF_OK, "{}", last());
        let points = out_positions(r);
        // SAFETY: a live handle, freed once.
        unsafe { gbsurf_result_free(r) };
        points
    };
    let (seed, fair) = (run(GBSURF_MIDDLE_SEED), run(GBSURF_MIDDLE_FAIR));
    assert_eq!(seed.len(), fair.len());
    let moved = seed.iter().zip(&fair).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max);
    assert!(moved > 1e-4, "the fair rule moved the surface by {moved:e} only");
}

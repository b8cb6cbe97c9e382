#![no_main]
//! The C ABI convert entry (`gbsurf_convert_creased`, which `gbsurf_convert` is with NULL
//! creases) on arrays with arbitrary counts, indices, NaNs and bounded options: either a typed
//! error (status other than GBSURF_ERR_PANIC, NULL handle, a message) or a handle whose output
//! mesh is consistent (finite positions, triangle indices in range, counts as in the report;
//! closed when the validated input is closed), then freed.
//!
//! The mesh is either the raw arrays or one of a few closed meshes edited by the input (vertex
//! nudges, corner rewrites), so that conversion itself, not only the argument checks, is reached.
use gbsurf::mesh::{generate, HalfEdgeMesh, PolyMesh};
use gbsurf_capi::*;
use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use std::ffi::CStr;

/// Largest mesh handed to the entry (vertices, faces): conversion stays in milliseconds.
const MAX_VERTICES: usize = 64;
const MAX_FACES: usize = 64;

#[derive(Arbitrary, Debug)]
struct Input {
    /// 0: the raw arrays below; 1..: a closed base mesh, edited.
    base: u8,
    positions: Vec<f64>,
    sizes: Vec<u8>,
    indices: Vec<u16>,
    /// (corner, vertex): overwrites a corner of a base mesh.
    edits: Vec<(u16, u16)>,
    /// Declared lengths shorter than the arrays (never longer: the buffers must hold them).
    short_positions: u8,
    short_indices: u8,
    creases: Vec<(u16, u16, f64)>,
    corners: Vec<(u16, f64)>,
    method: u8,
    resolution: u8,
    twist: u8,
    weights: u8,
    levels: u8,
    best_plane: u8,
    fullness: f64,
    tile_depth: f64,
    mid_scale: f64,
}

fn base_mesh(k: u8) -> PolyMesh {
    let v = |p: &[[f64; 3]]| p.iter().map(|&a| a.into()).collect();
    match k % 4 {
        0 => PolyMesh::new(
            v(&[[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.], [0., 0., 1.], [1., 0., 1.], [1., 1., 1.], [0., 1., 1.]]),
            vec![vec![0, 3, 2, 1], vec![4, 5, 6, 7], vec![0, 1, 5, 4], vec![1, 2, 6, 5], vec![2, 3, 7, 6], vec![3, 0, 4, 7]],
        ),
        1 => PolyMesh::new(
            v(&[[1., 0., 0.], [-1., 0., 0.], [0., 1., 0.], [0., -1., 0.], [0., 0., 1.], [0., 0., -1.]]),
            vec![
                vec![0, 2, 4], vec![2, 1, 4], vec![1, 3, 4], vec![3, 0, 4],
                vec![2, 0, 5], vec![1, 2, 5], vec![3, 1, 5], vec![0, 3, 5],
            ],
        ),
        2 => PolyMesh::new(
            v(&[[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.], [0.5, 0.5, 1.]]),
            vec![vec![0, 3, 2, 1], vec![0, 1, 4], vec![1, 2, 4], vec![2, 3, 4], vec![3, 0, 4]],
        ),
        _ => generate::torus(6, 4, 2.0, 0.7).expect("torus"),
    }
}

/// Flat arrays (positions, face sizes, face indices) of the input.
fn arrays(input: &Input) -> (Vec<f64>, Vec<u32>, Vec<u32>) {
    if input.base == 0 {
        let p: Vec<f64> = input.positions.iter().copied().take(3 * MAX_VERTICES + 2).collect();
        let s: Vec<u32> = input.sizes.iter().map(|&s| u32::from(s)).take(MAX_FACES).collect();
        let i: Vec<u32> = input.indices.iter().map(|&i| u32::from(i)).take(8 * MAX_FACES).collect();
        return (p, s, i);
    }
    let mesh = base_mesh(input.base - 1);
    let mut p: Vec<f64> = mesh.positions.iter().flat_map(|q| q.to_array()).collect();
    for (k, d) in input.positions.iter().enumerate().take(p.len()) {
        // nudges (NaN and infinities pass through): small ones keep the mesh valid
        p[k] += if d.is_finite() { d.clamp(-1e3, 1e3) * 1e-3 } else { *d };
    }
    let s: Vec<u32> = mesh.faces.iter().map(|f| f.len() as u32).collect();
    let mut i: Vec<u32> = mesh.faces.iter().flatten().copied().collect();
    for &(c, v) in input.edits.iter().take(4) {
        let n = i.len();
        i[usize::from(c) % n] = u32::from(v) % (mesh.positions.len() as u32 + 2);
    }
    (p, s, i)
}

fn options(input: &Input) -> GbsurfOptions {
    let mut o = std::mem::MaybeUninit::<GbsurfOptions>::uninit();
    // SAFETY: a writable GbsurfOptions.
    assert_eq!(unsafe { gbsurf_options_init(o.as_mut_ptr()) }, GBSURF_OK);
    // SAFETY: initialized by gbsurf_options_init.
    let mut o = unsafe { o.assume_init() };
    // bounded: one out-of-range code per enum, small resolutions and levels
    o.method = u32::from(input.method % 5);
    o.resolution = u32::from(input.resolution % 7); // 0 is out of range
    o.twist = u32::from(input.twist % 4);
    o.weights = u32::from(input.weights % 3);
    o.levels = u32::from(input.levels % 3);
    o.best_plane = u32::from(input.best_plane % 3);
    let bounded = |x: f64, d: f64| if x.is_finite() { x.clamp(-10.0, 10.0) } else if x.is_nan() { d } else { x };
    o.fullness = bounded(input.fullness, o.fullness);
    o.tile_depth = bounded(input.tile_depth, o.tile_depth);
    o.mid_scale = bounded(input.mid_scale, o.mid_scale);
    o
}

fn last_error() -> String {
    // SAFETY: the library's NUL-terminated thread-local message.
    unsafe { CStr::from_ptr(gbsurf_last_error_message()) }.to_string_lossy().into_owned()
}

/// The validated input, if the core accepts it (closedness is checked on the output).
fn validated(p: &[f64], s: &[u32], i: &[u32]) -> Option<HalfEdgeMesh> {
    if p.len() % 3 != 0 || s.iter().map(|&x| x as usize).sum::<usize>() != i.len() {
        return None;
    }
    let positions = p.chunks_exact(3).map(glam::DVec3::from_slice).collect();
    let mut faces = Vec::new();
    let mut at = 0;
    for &n in s {
        faces.push(i[at..at + n as usize].to_vec());
        at += n as usize;
    }
    HalfEdgeMesh::from_polymesh(&PolyMesh::new(positions, faces)).ok()
}

fuzz_target!(|input: Input| {
    let (p, s, i) = arrays(&input);
    let np = p.len().saturating_sub(usize::from(input.short_positions % 4));
    let ni = i.len().saturating_sub(usize::from(input.short_indices % 2));
    let (p, i) = (&p[..np], &i[..ni]);
    let ev: Vec<u32> = input.creases.iter().take(8).flat_map(|&(a, b, _)| [u32::from(a) % 70, u32::from(b) % 70]).collect();
    let es: Vec<f64> = input.creases.iter().take(8).map(|&(_, _, x)| x).collect();
    let cv: Vec<u32> = input.corners.iter().take(8).map(|&(v, _)| u32::from(v) % 70).collect();
    let cs: Vec<f64> = input.corners.iter().take(8).map(|&(_, x)| x).collect();
    let creases = GbsurfCreases {
        edge_vertices: ev.as_ptr(),
        edge_sharpness: es.as_ptr(),
        edge_count: es.len(),
        vertices: cv.as_ptr(),
        vertex_sharpness: cs.as_ptr(),
        vertex_count: cs.len(),
    };
    let o = options(&input);
    let mut out: *mut GbsurfResult = std::ptr::null_mut();
    // SAFETY: every pointer/length pair is a live Vec/slice of that length; `out` is writable.
    let status = unsafe {
        gbsurf_convert_creased(
            p.as_ptr(), p.len(), s.as_ptr(), s.len(), i.as_ptr(), i.len(),
            &creases, &o, None, std::ptr::null_mut(), &mut out,
        )
    };
    if status != GBSURF_OK {
        let message = last_error();
        assert_ne!(status, GBSURF_ERR_PANIC, "panic inside gbsurf_convert_creased: {message}");
        assert!(status <= GBSURF_ERR_CONSTRUCTION, "unknown status {status}: {message}");
        assert!(out.is_null(), "handle set on error");
        assert!(!message.trim().is_empty(), "status {status} without a message");
        return;
    }
    assert!(!out.is_null());
    assert!(p.iter().all(|x| x.is_finite()), "converted despite a non-finite coordinate");
    let nv_in = p.len() / 3;
    assert!(i.iter().all(|&v| (v as usize) < nv_in), "converted despite an index out of range");
    let (mut pos, mut npos, mut tri, mut ntri) = (std::ptr::null(), 0usize, std::ptr::null(), 0usize);
    let mut report = GbsurfReport { struct_size: std::mem::size_of::<GbsurfReport>() as u32, ..Default::default() };
    // SAFETY: `out` is a live handle; the outputs are writable.
    unsafe {
        assert_eq!(gbsurf_mesh_positions(out, &mut pos, &mut npos), GBSURF_OK, "{}", last_error());
        assert_eq!(gbsurf_mesh_triangles(out, &mut tri, &mut ntri), GBSURF_OK, "{}", last_error());
        assert_eq!(gbsurf_result_report(out, &mut report), GBSURF_OK, "{}", last_error());
    }
    // SAFETY: views valid until the handle is freed (below).
    let (pos, tri) = unsafe { (std::slice::from_raw_parts(pos, npos), std::slice::from_raw_parts(tri, ntri)) };
    assert_eq!(npos % 3, 0);
    assert_eq!(ntri % 3, 0);
    assert!(ntri > 0, "empty output");
    let nv = npos / 3;
    assert!(pos.iter().all(|x| x.is_finite()), "non-finite output position");
    if let Some(t) = tri.iter().find(|&&t| t as usize >= nv) {
        panic!("triangle index {t} out of range (0..{nv})");
    }
    assert_eq!(report.vertices as usize, nv);
    assert_eq!(report.triangles as usize, ntri / 3);
    if let Some(he) = validated(p, &s, i) {
        if he.is_closed() && input.creases.is_empty() && input.corners.is_empty() {
            assert_eq!(report.closed, 1, "closed input, open output ({} boundary edges)", report.boundary_edges);
        }
    }
    // SAFETY: a live handle, freed once.
    unsafe { gbsurf_result_free(out) };
});

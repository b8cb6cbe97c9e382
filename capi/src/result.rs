//! The conversion entry points and the opaque result handle with its accessors.

use super::*;
use gbsurf::api::{Conversion, ConvertError, ConvertOptions};
use gbsurf::construct::{ControlNet, Patch, Surface};
use gbsurf::mesh::{MeshError, PolyMesh};
use glam::DVec3;
use std::ffi::{c_void, CStr};
use std::sync::OnceLock;
use gbsurf::tessellate::SurfaceMesh;

/// Patch kind: an n-sided Generalized Bézier patch (ribbons plus a central control point).
pub const GBSURF_PATCH_GB: u32 = 0;
/// Patch kind: a ribbon-only patch (CGB), no central control point.
pub const GBSURF_PATCH_CGB: u32 = 1;

/// Progress callback: called with the finished fraction in [0, 1] and the caller's `user_data`;
/// return `true` to continue, `false` to cancel (the conversion then fails with
/// `GBSURF_ERR_CANCELLED`). It runs on the calling thread and must not unwind.
pub type GbsurfProgressFn =
    Option<unsafe extern "C" fn(fraction: f32, user_data: *mut c_void) -> bool>;

/// One ribbon, flattened: `points[3 * (k * (degree + 1) + j) + c]` is coordinate c of P_{j,k}.
struct FlatRibbon {
    degree: usize,
    layers: usize,
    points: Vec<f64>,
}

struct FlatPatch {
    kind: u32,
    center: Option<[f64; 3]>,
    ribbons: Vec<FlatRibbon>,
}

/// The opaque result of a conversion: the output triangle mesh with its per-vertex data, the
/// patches (none for the subdivision methods), the curve network, the report and the warnings.
/// Free it with `gbsurf_result_free`.
// The mesh arrays and curves are handed out as views of the conversion's own vectors (no copy);
// the flattened patches, the control net and the cubic curves are built on first access (most
// callers never ask for them).
pub struct GbsurfResult {
    mesh: SurfaceMesh,
    surface: Option<Surface>,
    flat: OnceLock<Vec<FlatPatch>>,
    control_net: OnceLock<ControlNet>,
    cubic_curves: OnceLock<Vec<Vec<DVec3>>>,
    edges: OnceLock<gbsurf::tessellate::MeshEdges>,
    report: GbsurfReport,
    sides_histogram: Vec<(u64, u64)>,
    fold_sites: Vec<gbsurf::quality::FoldSite>,
    warnings: Vec<CString>,
}

/// The coordinates of `v` as one flat `[x0, y0, z0, x1, …]` slice, without copying.
fn coords(v: &[DVec3]) -> &[f64] {
    // SAFETY: `DVec3` is `#[repr(C)]` with exactly three `f64` fields (glam), so a slice of n
    // of them is a valid, aligned slice of 3n `f64` with the same lifetime.
    unsafe { std::slice::from_raw_parts(v.as_ptr().cast::<f64>(), v.len() * 3) }
}

impl GbsurfResult {
    fn positions(&self) -> &[f64] {
        coords(&self.mesh.positions)
    }
    fn normals(&self) -> &[f64] {
        coords(&self.mesh.normals)
    }
    fn triangles(&self) -> &[u32] {
        self.mesh.triangles.as_flattened()
    }
    fn quads(&self) -> &[u32] {
        self.mesh.quads.as_flattened()
    }
    /// The edge table of the output faces, computed on first use.
    fn edges(&self) -> &gbsurf::tessellate::MeshEdges {
        self.edges.get_or_init(|| self.mesh.edges())
    }
    fn flat(&self) -> &[FlatPatch] {
        self.flat.get_or_init(|| {
            self.surface
                .as_ref()
                .map(flatten_patches)
                .unwrap_or_default()
        })
    }
    /// The control nets of all patches (empty for the subdivision methods).
    fn control_net(&self) -> &ControlNet {
        self.control_net.get_or_init(|| {
            self.surface
                .as_ref()
                .map(Surface::control_net)
                .unwrap_or_default()
        })
    }
    /// The curve network as cubic Bézier chains (empty for the subdivision methods).
    fn cubic_curves(&self) -> &[Vec<DVec3>] {
        self.cubic_curves.get_or_init(|| {
            self.surface
                .as_ref()
                .map(Surface::default_cubic_curves)
                .unwrap_or_default()
        })
    }
    fn patch_count(&self) -> usize {
        self.surface.as_ref().map_or(0, |s| s.patches.len())
    }
    fn curves(&self) -> &[Vec<DVec3>] {
        self.surface.as_ref().map_or(&[][..], |s| s.curves.as_slice())
    }
    fn curve_count(&self) -> usize {
        self.curves().len()
    }
}

const _: () = assert!(std::mem::size_of::<DVec3>() == 3 * std::mem::size_of::<f64>());

fn flatten(v: &[DVec3]) -> Vec<f64> {
    v.iter().flat_map(|p| p.to_array()).collect()
}

fn flatten_patches(s: &Surface) -> Vec<FlatPatch> {
    let flat_ribbon = |r: &gbsurf::gb::Ribbon| FlatRibbon {
        degree: r.degree,
        layers: r.layers(),
        points: flatten(r.points()),
    };
    s.patches
        .iter()
        .map(|p| match p {
            Patch::Gb(g) => FlatPatch {
                kind: GBSURF_PATCH_GB,
                center: Some(g.center.to_array()),
                ribbons: g.ribbons.iter().map(flat_ribbon).collect(),
            },
            Patch::Cgb(c) => FlatPatch {
                kind: GBSURF_PATCH_CGB,
                center: None,
                ribbons: c.ribbons.iter().map(flat_ribbon).collect(),
            },
        })
        .collect()
}

/// The status code of a mesh error.
pub(crate) fn mesh_error_code(e: &MeshError) -> u32 {
    match e {
        MeshError::Parse { .. } | MeshError::Io { .. } | MeshError::NotAFile { .. } | MeshError::InputTooLarge { .. } => {
            GBSURF_ERR_IO
        }
        MeshError::NonFiniteCoordinate { .. } => GBSURF_ERR_NAN,
        MeshError::IndexOutOfRange { .. }
        | MeshError::ObjIndexOutOfRange { .. }
        | MeshError::CreaseVertexOutOfRange { .. }
        | MeshError::HoleFaceOutOfRange { .. }
        | MeshError::Hole { defect: gbsurf::mesh::HoleDefect::IndexOutOfRange { .. }, .. } => GBSURF_ERR_INDEX,
        _ => GBSURF_ERR_INVALID_MESH,
    }
}

/// Checks the flat input arrays and builds the polygon mesh. Counts, NaN and indices are checked
/// here so each gets its own code and a message naming the element.
pub(crate) fn build_mesh(positions: &[f64], face_sizes: &[u32], face_indices: &[u32]) -> FfiResult<PolyMesh> {
    if positions.len() % 3 != 0 {
        return Err(FfiError::new(
            GBSURF_ERR_COUNT,
            format!("positions_len = {} is not a multiple of 3", positions.len()),
        ));
    }
    let total: u64 = face_sizes.iter().map(|&s| s as u64).sum();
    if total != face_indices.len() as u64 {
        return Err(FfiError::new(
            GBSURF_ERR_COUNT,
            format!(
                "face sizes sum to {total} but face_indices_len = {}",
                face_indices.len()
            ),
        ));
    }
    if let Some(i) = positions.iter().position(|x| !x.is_finite()) {
        return Err(FfiError::new(
            GBSURF_ERR_NAN,
            format!(
                "vertex {}: coordinate {} is {} (not finite)",
                i / 3,
                i % 3,
                positions[i]
            ),
        ));
    }
    let nv = positions.len() / 3;
    let pts: Vec<DVec3> = positions.chunks_exact(3).map(DVec3::from_slice).collect();
    let mut faces = Vec::with_capacity(face_sizes.len());
    let mut at = 0usize;
    for (f, &size) in face_sizes.iter().enumerate() {
        let face = &face_indices[at..at + size as usize];
        if let Some(c) = face.iter().position(|&v| v as usize >= nv) {
            return Err(FfiError::new(
                GBSURF_ERR_INDEX,
                format!(
                    "face {f} corner {c}: vertex index {} out of range (0..{nv})",
                    face[c]
                ),
            ));
        }
        faces.push(face.to_vec());
        at += size as usize;
    }
    Ok(PolyMesh::new(pts, faces))
}

/// Runs a conversion (`job`: the options and the progress closure → the result) with the C
/// progress callback and packs the result.
fn run(
    options: *const GbsurfOptions,
    progress: GbsurfProgressFn,
    user_data: *mut c_void,
    job: impl FnOnce(&ConvertOptions, gbsurf::api::Progress<'_>) -> Result<Conversion, ConvertError>,
) -> FfiResult<Box<GbsurfResult>> {
    let opts = read_options(options)?;
    let mut cb = |fraction: f32| -> bool {
        match progress {
            // SAFETY: the caller passed a valid function pointer (NULL is the None case).
            Some(f) => unsafe { f(fraction, user_data) },
            None => true,
        }
    };
    let progress_arg: gbsurf::api::Progress<'_> = if progress.is_some() {
        Some(&mut cb)
    } else {
        None
    };
    let conv = job(&opts, progress_arg).map_err(convert_error)?;
    let method = GbsurfOptions::from(&opts).method;
    Ok(Box::new(pack(conv, method)))
}

pub(crate) fn pack(conv: gbsurf::api::Conversion, method: u32) -> GbsurfResult {
    GbsurfResult {
        report: GbsurfReport::from_report(&conv.report, method),
        sides_histogram: conv
            .report
            .sides_histogram
            .iter()
            .filter_map(|(k, &v)| Some((k.parse::<u64>().ok()?, v as u64)))
            .collect(),
        fold_sites: conv.report.fold_sites.clone(),
        warnings: conv
            .warnings
            .iter()
            .map(|w| CString::new(w.replace('\0', "\\0")).unwrap_or_default())
            .collect(),
        mesh: conv.mesh,
        surface: conv.surface,
        flat: OnceLock::new(),
        control_net: OnceLock::new(),
        cubic_curves: OnceLock::new(),
        edges: OnceLock::new(),
    }
}

pub(crate) fn write_out(out: *mut *mut GbsurfResult, r: Box<GbsurfResult>) {
    // SAFETY: `out` was checked non-null by the caller of this helper and points to a writable
    // pointer (header contract).
    unsafe { *out = Box::into_raw(r) };
}

/// Converts a polygon mesh given as flat arrays into a smooth surface.
///
/// - `positions`: `positions_len` doubles, x y z per vertex (`positions_len` a multiple of 3);
/// - `face_sizes`: `face_count` corner counts (each ≥ 3);
/// - `face_indices`: `face_indices_len` 0-based vertex indices, the faces one after another,
///   counter-clockwise seen from outside (`face_indices_len` = sum of `face_sizes`);
/// - `options`: NULL for the defaults, else initialized by `gbsurf_options_init`;
/// - `progress`: may be NULL; `user_data` is passed to it unchanged;
/// - `out`: receives the result handle (set to NULL first; set only on success).
///
/// Errors: `GBSURF_ERR_NULL`, `_COUNT`, `_NAN`, `_INDEX` (message names vertex/face/corner),
/// `_INVALID_MESH`, `_INVALID_OPTION`, `_CANCELLED`, `_CONSTRUCTION`, `_PANIC`.
///
/// # Safety
/// Every non-null pointer must point to the stated number of readable elements; `out` to a
/// writable pointer.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_convert(
    positions: *const f64,
    positions_len: usize,
    face_sizes: *const u32,
    face_count: usize,
    face_indices: *const u32,
    face_indices_len: usize,
    options: *const GbsurfOptions,
    progress: GbsurfProgressFn,
    user_data: *mut c_void,
    out: *mut *mut GbsurfResult,
) -> u32 {
    // SAFETY: the same contract, with no creases.
    unsafe {
        convert_arrays(
            "gbsurf_convert",
            (positions, positions_len, face_sizes, face_count, face_indices, face_indices_len),
            std::ptr::null(),
            std::ptr::null(),
            options,
            progress,
            user_data,
            out,
        )
    }
}

/// The polygon mesh of the flat array arguments of every entry taking a mesh (positions, face
/// sizes, face indices; see `gbsurf_convert`), checked and built by [`build_mesh`].
///
/// # Safety
/// Each pointer is NULL with length 0 or points to its stated number of readable elements.
pub(crate) unsafe fn mesh_arg(
    (positions, positions_len, face_sizes, face_count, face_indices, face_indices_len): (*const f64, usize, *const u32, usize, *const u32, usize),
) -> FfiResult<PolyMesh> {
    // SAFETY: pointer/length pairs (contract).
    let (p, s, i) = unsafe {
        (
            slice_arg(positions, positions_len, "positions")?,
            slice_arg(face_sizes, face_count, "face_sizes")?,
            slice_arg(face_indices, face_indices_len, "face_indices")?,
        )
    };
    build_mesh(p, s, i)
}

/// The one body of `gbsurf_convert`, `gbsurf_convert_creased` and `gbsurf_convert_holed`
/// (`creases` and `holes` may be NULL), behind the panic boundary named `name`.
///
/// # Safety
/// As `gbsurf_convert_holed`.
#[allow(clippy::type_complexity)]
unsafe fn convert_arrays(
    name: &str,
    (positions, positions_len, face_sizes, face_count, face_indices, face_indices_len): (
        *const f64,
        usize,
        *const u32,
        usize,
        *const u32,
        usize,
    ),
    creases: *const GbsurfCreases,
    holes: *const GbsurfHoles,
    options: *const GbsurfOptions,
    progress: GbsurfProgressFn,
    user_data: *mut c_void,
    out: *mut *mut GbsurfResult,
) -> u32 {
    boundary(name, || {
        let out = non_null_mut(out, "out")?;
        // SAFETY: non-null, writable (contract).
        unsafe { *out = std::ptr::null_mut() };
        // SAFETY: pointer/length pairs per the contract of the callers.
        let mut mesh = unsafe { mesh_arg((positions, positions_len, face_sizes, face_count, face_indices, face_indices_len))? };
        // SAFETY: NULL or a readable struct (contract of the callers).
        unsafe { read_creases(creases, &mut mesh)? };
        // SAFETY: NULL or a readable struct (contract of the callers).
        unsafe { read_holes(holes, &mut mesh)? };
        let r = run(options, progress, user_data, |o, cb| {
            gbsurf::api::convert(&mesh, o, cb)
        })?;
        write_out(out, r);
        Ok(())
    })
}

/// Edge and vertex sharpness of the input mesh for `gbsurf_convert_creased` (docs/math.md#creases).
/// Sharpness c is in [0, 1]: 0 smooth (the same surface as without the entry), 1 infinitely
/// sharp (edge: G0 across it; vertex: a corner); Blender's `crease_edge` / `crease_vert` values
/// are c as they are. Both structures build creases (the dual along closed chains of sharp edges,
/// docs/math.md#dual-creases); the subdivision methods warn and ignore them.
/// A pointer may be NULL when its count is 0; a zeroed struct means "no creases".
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct GbsurfCreases {
    /// `2 * edge_count` 0-based vertex indices: edge k joins `edge_vertices[2k]` and
    /// `edge_vertices[2k + 1]` (either order; it must be an edge of some face).
    pub edge_vertices: *const u32,
    /// `edge_count` sharpness values, one per edge.
    pub edge_sharpness: *const f64,
    /// Number of creased edges.
    pub edge_count: usize,
    /// `vertex_count` 0-based vertex indices of corner vertices.
    pub vertices: *const u32,
    /// `vertex_count` corner sharpness values, one per vertex.
    pub vertex_sharpness: *const f64,
    /// Number of corner vertices.
    pub vertex_count: usize,
}

/// Reads the crease arrays into the mesh's [`gbsurf::mesh::Creases`] (NaN gets its own code;
/// range, index and edge checks are the validator's, named in the message).
///
/// # Safety
/// `c` must be NULL or point to a `GbsurfCreases` whose pointers hold the stated counts.
unsafe fn read_creases(c: *const GbsurfCreases, mesh: &mut PolyMesh) -> FfiResult<()> {
    if c.is_null() {
        return Ok(());
    }
    // SAFETY: non-null and readable (contract).
    let c = unsafe { *c };
    let two = c
        .edge_count
        .checked_mul(2)
        .ok_or_else(|| FfiError::new(GBSURF_ERR_COUNT, format!("edge_count = {} is too large", c.edge_count)))?;
    // SAFETY: pointer/length pairs per the contract.
    let (ev, es, vv, vs) = unsafe {
        (
            slice_arg(c.edge_vertices, two, "creases.edge_vertices")?,
            slice_arg(c.edge_sharpness, c.edge_count, "creases.edge_sharpness")?,
            slice_arg(c.vertices, c.vertex_count, "creases.vertices")?,
            slice_arg(c.vertex_sharpness, c.vertex_count, "creases.vertex_sharpness")?,
        )
    };
    let nan = |what: &str, k: usize, x: f64| {
        FfiError::new(GBSURF_ERR_NAN, format!("{what} crease {k}: sharpness {x} is not finite"))
    };
    for (k, &x) in es.iter().enumerate() {
        if !x.is_finite() {
            return Err(nan("edge", k, x));
        }
        mesh.creases.edges.push(([ev[2 * k], ev[2 * k + 1]], x));
    }
    for (k, &x) in vs.iter().enumerate() {
        if !x.is_finite() {
            return Err(nan("vertex", k, x));
        }
        mesh.creases.vertices.push((vv[k], x));
    }
    Ok(())
}

/// `gbsurf_convert` with edge and vertex sharpness (`creases`: NULL for none, see
/// `GbsurfCreases`). Additional errors: `GBSURF_ERR_NAN` (a sharpness is NaN or infinite),
/// `GBSURF_ERR_INDEX` (a corner vertex out of range), `GBSURF_ERR_INVALID_MESH` (a sharpness
/// outside [0, 1], or a vertex pair that is no edge: the message names the entry and its
/// vertices), `GBSURF_ERR_NULL` (a NULL array with a non-zero count).
///
/// # Safety
/// As for `gbsurf_convert`; `creases` must be NULL or point to a `GbsurfCreases` whose arrays
/// hold the stated counts.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_convert_creased(
    positions: *const f64,
    positions_len: usize,
    face_sizes: *const u32,
    face_count: usize,
    face_indices: *const u32,
    face_indices_len: usize,
    creases: *const GbsurfCreases,
    options: *const GbsurfOptions,
    progress: GbsurfProgressFn,
    user_data: *mut c_void,
    out: *mut *mut GbsurfResult,
) -> u32 {
    // SAFETY: per the contract above.
    unsafe {
        convert_arrays(
            "gbsurf_convert_creased",
            (positions, positions_len, face_sizes, face_count, face_indices, face_indices_len),
            creases,
            std::ptr::null(),
            options,
            progress,
            user_data,
            out,
        )
    }
}

/// Inner loops (holes) of faces for `gbsurf_convert_holed` (docs/math.md#holes): hole k belongs to
/// face `faces[k]` (0-based) and is the loop of `sizes[k]` vertex indices taken in order from
/// `indices`. The face's own loop is then its outer loop (counter-clockwise seen from outside);
/// an inner loop runs the opposite way, lies strictly inside, and shares no vertex with the
/// face's other loops. A face may have several holes. A pointer may be NULL when its count is 0;
/// a zeroed struct means "no holes".
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct GbsurfHoles {
    /// `count` face indices, one per hole.
    pub faces: *const u32,
    /// `count` loop sizes (at least 3 each), one per hole.
    pub sizes: *const u32,
    /// Number of holes.
    pub count: usize,
    /// The loops' vertex indices, concatenated (`indices_len` = sum of `sizes`).
    pub indices: *const u32,
    /// Length of `indices`.
    pub indices_len: usize,
}

/// Reads the hole arrays into [`PolyMesh::holes`] (counts here; face, vertex and geometry checks
/// are the validator's, named in the message).
///
/// # Safety
/// `h` must be NULL or point to a `GbsurfHoles` whose pointers hold the stated counts.
unsafe fn read_holes(h: *const GbsurfHoles, mesh: &mut PolyMesh) -> FfiResult<()> {
    if h.is_null() {
        return Ok(());
    }
    // SAFETY: non-null and readable (contract).
    let h = unsafe { *h };
    // SAFETY: pointer/length pairs per the contract.
    let (faces, sizes, indices) = unsafe {
        (
            slice_arg(h.faces, h.count, "holes.faces")?,
            slice_arg(h.sizes, h.count, "holes.sizes")?,
            slice_arg(h.indices, h.indices_len, "holes.indices")?,
        )
    };
    let total: u64 = sizes.iter().map(|&s| s as u64).sum();
    if total != indices.len() as u64 {
        return Err(FfiError::new(
            GBSURF_ERR_COUNT,
            format!("hole sizes sum to {total} but holes.indices_len = {}", indices.len()),
        ));
    }
    let mut at = 0usize;
    for (&face, &size) in faces.iter().zip(sizes) {
        let lp = &indices[at..at + size as usize];
        mesh.holes.push(gbsurf::mesh::Hole { face, vertices: lp.to_vec() });
        at += size as usize;
    }
    Ok(())
}

/// `gbsurf_convert_creased` with faces with holes (`holes`: NULL for none, see `GbsurfHoles`;
/// `creases` NULL for none). Each face with holes is split into convex simple faces before the
/// conversion. Additional errors: `GBSURF_ERR_COUNT` (hole sizes do not sum to
/// `holes.indices_len`), `GBSURF_ERR_INDEX` (a hole names a face or vertex out of range),
/// `GBSURF_ERR_INVALID_MESH` (a hole that is too small, repeats or shares a vertex, has zero area
/// or the outer loop's orientation, is not strictly inside its face, or meets another loop: the
/// message names the face and the hole), `GBSURF_ERR_NULL` (a NULL array with a non-zero count).
///
/// # Safety
/// As for `gbsurf_convert_creased`; `holes` must be NULL or point to a `GbsurfHoles` whose arrays
/// hold the stated counts.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_convert_holed(
    positions: *const f64,
    positions_len: usize,
    face_sizes: *const u32,
    face_count: usize,
    face_indices: *const u32,
    face_indices_len: usize,
    creases: *const GbsurfCreases,
    holes: *const GbsurfHoles,
    options: *const GbsurfOptions,
    progress: GbsurfProgressFn,
    user_data: *mut c_void,
    out: *mut *mut GbsurfResult,
) -> u32 {
    // SAFETY: per the contract above.
    unsafe {
        convert_arrays(
            "gbsurf_convert_holed",
            (positions, positions_len, face_sizes, face_count, face_indices, face_indices_len),
            creases,
            holes,
            options,
            progress,
            user_data,
            out,
        )
    }
}

/// Reads a mesh file (OBJ, OFF, PLY, STL; strict readers, errors name the line) and converts it
/// like `gbsurf_convert`. `path` is a NUL-terminated UTF-8 path. Errors additionally include
/// `GBSURF_ERR_IO` (unreadable or malformed file).
///
/// # Safety
/// `path` must be a NUL-terminated string; the other pointers as for `gbsurf_convert`.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_convert_file(
    path: *const c_char,
    options: *const GbsurfOptions,
    progress: GbsurfProgressFn,
    user_data: *mut c_void,
    out: *mut *mut GbsurfResult,
) -> u32 {
    boundary("gbsurf_convert_file", || {
        let out = non_null_mut(out, "out")?;
        // SAFETY: non-null, writable (contract).
        unsafe { *out = std::ptr::null_mut() };
        let path = non_null(path, "path")?;
        // SAFETY: NUL-terminated (contract).
        let path = unsafe { CStr::from_ptr(path) }
            .to_str()
            .map_err(|_| FfiError::new(GBSURF_ERR_IO, "path is not valid UTF-8"))?;
        let r = run(options, progress, user_data, |o, cb| {
            gbsurf::api::convert_file(path, o, cb)
        })
        .map_err(|mut e| {
            e.message = format!("{path}: {}", e.message);
            e
        });
        write_out(out, r?);
        Ok(())
    })
}

/// Frees a result handle. NULL is a no-op.
///
/// # Safety
/// `result` must be NULL or a handle from `gbsurf_convert*` not freed before.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_result_free(result: *mut GbsurfResult) {
    // SAFETY: NULL or a live handle of this type (contract).
    unsafe { free_handle(result) }
}

// ---------------------------------------------------------------------------------------------
// Accessors
// ---------------------------------------------------------------------------------------------

fn handle<'a>(r: *const GbsurfResult) -> FfiResult<&'a GbsurfResult> {
    let r = non_null(r, "result")?;
    // SAFETY: a live handle from gbsurf_convert* (contract of every accessor).
    Ok(unsafe { &*r })
}

pub(crate) fn put<T>(out: *mut T, arg: &str, v: T) -> FfiResult {
    let out = non_null_mut(out, arg)?;
    // SAFETY: non-null, writable (contract).
    unsafe { out.write(v) };
    Ok(())
}

/// Copies `src` into a caller buffer of `capacity` elements; `written` receives `src.len()` (also
/// on `GBSURF_ERR_CAPACITY`, so the caller learns the size needed). `buf` may be NULL when
/// `capacity` is 0 (a size query, which then fails with `_CAPACITY` unless `src` is empty).
pub(crate) fn copy_out<T: Copy>(src: &[T], buf: *mut T, capacity: usize, written: *mut usize) -> FfiResult {
    put(written, "written", src.len())?;
    if src.len() > capacity {
        return Err(FfiError::new(
            GBSURF_ERR_CAPACITY,
            format!("buffer holds {capacity} values, {} needed", src.len()),
        ));
    }
    if src.is_empty() {
        return Ok(());
    }
    let buf = non_null_mut(buf, "buf")?;
    // SAFETY: `buf` has `capacity` ≥ src.len() writable elements (contract); distinct regions.
    unsafe { std::ptr::copy_nonoverlapping(src.as_ptr(), buf, src.len()) };
    Ok(())
}

fn view<T>(src: &[T], data: *mut *const T, len: *mut usize) -> FfiResult {
    let data = non_null_mut(data, "data")?;
    let len = non_null_mut(len, "len")?;
    // SAFETY: both checked non-null and writable (contract).
    unsafe {
        *data = src.as_ptr();
        *len = src.len();
    }
    Ok(())
}

/// The body of a view accessor: `get` picks the array from the handle (or fails, e.g. on an
/// index out of range); `*data` and `*len` receive it.
fn view_array<'a, T: 'a>(
    name: &str,
    result: *const GbsurfResult,
    get: impl FnOnce(&'a GbsurfResult) -> FfiResult<&'a [T]>,
    data: *mut *const T,
    len: *mut usize,
) -> u32 {
    boundary(name, || view(get(handle(result)?)?, data, len))
}

/// The body of the copy-out variant of a view accessor (see [`copy_out`]).
fn copy_array<'a, T: Copy + 'a>(
    name: &str,
    result: *const GbsurfResult,
    get: impl FnOnce(&'a GbsurfResult) -> FfiResult<&'a [T]>,
    buf: *mut T,
    capacity: usize,
    written: *mut usize,
) -> u32 {
    boundary(name, || {
        copy_out(get(handle(result)?)?, buf, capacity, written)
    })
}

// Every array a result hands out has a view (`gbsurf_<what>_<array>`, zero-copy) and a copy
// (`gbsurf_<what>_copy_<array>`). Each pair is spelt out, not generated by a macro, because
// cbindgen reads the source without expanding macros; the bodies are the two helpers above.

/// View of the output vertex positions (x y z per vertex: 3 × vertex count doubles): `*data`
/// points into the handle (valid until it is freed), `*len` is the number of values.
///
/// # Safety
/// `result` is a live handle or NULL; `data` and `len` are writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_mesh_positions(
    result: *const GbsurfResult,
    data: *mut *const f64,
    len: *mut usize,
) -> u32 {
    view_array("gbsurf_mesh_positions", result, |r| Ok(r.positions()), data, len)
}

/// Copies what `gbsurf_mesh_positions` views into `buf` (`capacity` values); `*written` receives the
/// number of values (also on `GBSURF_ERR_CAPACITY`, so `capacity` 0 with `buf` NULL queries the
/// size). Every `*_copy_*` function of a view works this way.
///
/// # Safety
/// `result` is a live handle or NULL; `buf` has `capacity` writable values.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_mesh_copy_positions(
    result: *const GbsurfResult,
    buf: *mut f64,
    capacity: usize,
    written: *mut usize,
) -> u32 {
    copy_array("gbsurf_mesh_copy_positions", result, |r| Ok(r.positions()), buf, capacity, written)
}

/// View of the unit vertex normals (x y z per vertex); `*data` is valid until the handle is freed,
/// `*len` is the number of values.
///
/// # Safety
/// `result` is a live handle or NULL; `data` and `len` are writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_mesh_normals(
    result: *const GbsurfResult,
    data: *mut *const f64,
    len: *mut usize,
) -> u32 {
    view_array("gbsurf_mesh_normals", result, |r| Ok(r.normals()), data, len)
}

/// Copy-out variant of `gbsurf_mesh_normals`.
///
/// # Safety
/// `result` is a live handle or NULL; `buf` has `capacity` writable values.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_mesh_copy_normals(
    result: *const GbsurfResult,
    buf: *mut f64,
    capacity: usize,
    written: *mut usize,
) -> u32 {
    copy_array("gbsurf_mesh_copy_normals", result, |r| Ok(r.normals()), buf, capacity, written)
}

/// View of the triangles (3 vertex indices each, counter-clockwise seen from outside); `*data` is
/// valid until the handle is freed, `*len` is the number of values.
///
/// # Safety
/// `result` is a live handle or NULL; `data` and `len` are writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_mesh_triangles(
    result: *const GbsurfResult,
    data: *mut *const u32,
    len: *mut usize,
) -> u32 {
    view_array("gbsurf_mesh_triangles", result, |r| Ok(r.triangles()), data, len)
}

/// Copy-out variant of `gbsurf_mesh_triangles`.
///
/// # Safety
/// `result` is a live handle or NULL; `buf` has `capacity` writable values.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_mesh_copy_triangles(
    result: *const GbsurfResult,
    buf: *mut u32,
    capacity: usize,
    written: *mut usize,
) -> u32 {
    copy_array("gbsurf_mesh_copy_triangles", result, |r| Ok(r.triangles()), buf, capacity, written)
}

/// View of the quads of the quad layout (4 vertex indices each, counter-clockwise seen from
/// outside; empty for the triangle layout and the subdivision methods). When not empty they are
/// the output faces, and triangles 2k and 2k+1 of `gbsurf_mesh_triangles` are quad k split along
/// its diagonal (0, 2). `*data` is valid until the handle is freed, `*len` is the number of
/// values.
///
/// # Safety
/// `result` is a live handle or NULL; `data` and `len` are writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_mesh_quads(
    result: *const GbsurfResult,
    data: *mut *const u32,
    len: *mut usize,
) -> u32 {
    view_array("gbsurf_mesh_quads", result, |r| Ok(r.quads()), data, len)
}

/// Copy-out variant of `gbsurf_mesh_quads`.
///
/// # Safety
/// `result` is a live handle or NULL; `buf` has `capacity` writable values.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_mesh_copy_quads(
    result: *const GbsurfResult,
    buf: *mut u32,
    capacity: usize,
    written: *mut usize,
) -> u32 {
    copy_array("gbsurf_mesh_copy_quads", result, |r| Ok(r.quads()), buf, capacity, written)
}

/// View of the output mesh's edges: every undirected edge once, as 2 vertex indices (smaller
/// first), sorted; for the output faces (the quads of the quad layout, else the triangles). A
/// host that stores edges (Blender's `.edge_verts`, OpenMesh) can take them instead of deriving
/// them. Computed on the first call (linear time), then kept with the handle. `*data` is valid
/// until the handle is freed, `*len` is the number of values (2 per edge).
///
/// # Safety
/// `result` is a live handle or NULL; `data` and `len` are writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_mesh_edges(
    result: *const GbsurfResult,
    data: *mut *const u32,
    len: *mut usize,
) -> u32 {
    view_array("gbsurf_mesh_edges", result, |r| Ok(r.edges().edges.as_flattened()), data, len)
}

/// Copy-out variant of `gbsurf_mesh_edges`.
///
/// # Safety
/// `result` is a live handle or NULL; `buf` has `capacity` writable values.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_mesh_copy_edges(
    result: *const GbsurfResult,
    buf: *mut u32,
    capacity: usize,
    written: *mut usize,
) -> u32 {
    copy_array("gbsurf_mesh_copy_edges", result, |r| Ok(r.edges().edges.as_flattened()), buf, capacity, written)
}

/// View of the edge of each face corner of the output faces (in the order of
/// `gbsurf_mesh_quads`, or of `gbsurf_mesh_triangles` when there are no quads): the index into
/// `gbsurf_mesh_edges` of the edge from the corner's vertex to the next corner's (Blender's
/// `.corner_edge`). Computed with `gbsurf_mesh_edges`. `*len` is the number of face corners.
///
/// # Safety
/// `result` is a live handle or NULL; `data` and `len` are writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_mesh_corner_edges(
    result: *const GbsurfResult,
    data: *mut *const u32,
    len: *mut usize,
) -> u32 {
    view_array("gbsurf_mesh_corner_edges", result, |r| Ok(r.edges().corner_edge.as_slice()), data, len)
}

/// Copy-out variant of `gbsurf_mesh_corner_edges`.
///
/// # Safety
/// `result` is a live handle or NULL; `buf` has `capacity` writable values.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_mesh_copy_corner_edges(
    result: *const GbsurfResult,
    buf: *mut u32,
    capacity: usize,
    written: *mut usize,
) -> u32 {
    copy_array("gbsurf_mesh_copy_corner_edges", result, |r| Ok(r.edges().corner_edge.as_slice()), buf, capacity, written)
}

/// View of the per-output-face patch corner (one value per quad, or per triangle in the
/// triangle layout; empty for the subdivision methods): the corner i of the face's patch whose
/// sector holds it (domain vertex i, the end of side i). With the per-face patch it names the
/// cage face corner the output face descends from. `*data` is valid until the handle is freed.
///
/// # Safety
/// `result` is a live handle or NULL; `data` and `len` are writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_mesh_face_corner(
    result: *const GbsurfResult,
    data: *mut *const u32,
    len: *mut usize,
) -> u32 {
    view_array("gbsurf_mesh_face_corner", result, |r| Ok(&r.mesh.face_corner[..]), data, len)
}

/// View of the per-output-face cage corner (2 values per face: the face of the control mesh and
/// the position of the vertex in its vertex list as given, for a face with holes in "outer loop,
/// then each hole's loop in order"; one pair per quad, or per triangle in
/// the triangle layout and for the subdivision methods, whose corner is `UINT32_MAX`): the cage
/// corner the output face lies in (docs/math.md#cage-corners). `*len` is the number of values;
/// `*data` is valid until the handle is freed.
///
/// # Safety
/// `result` is a live handle or NULL; `data` and `len` are writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_mesh_cage_corner(
    result: *const GbsurfResult,
    data: *mut *const u32,
    len: *mut usize,
) -> u32 {
    view_array("gbsurf_mesh_cage_corner", result, |r| Ok(r.mesh.cage_corner.as_flattened()), data, len)
}

/// View of the cage coordinates of the output face corners (empty for the subdivision methods):
/// 2 doubles (σ, τ) per corner of every quad, in the order of `gbsurf_mesh_quads` (8 per quad),
/// or in the triangle layout per corner of every triangle, in the order of
/// `gbsurf_mesh_triangles` (6 per triangle): the bilinear coordinates in the quad's cage corner
/// (triangle layout: the corner's own, `gbsurf_mesh_cage_loop_corner`), (0,0) the cage vertex,
/// (1,0) the midpoint of the edge to the next vertex, (0,1) the midpoint of the edge from the
/// previous vertex, (1,1) the face centre (docs/math.md#cage-corners). `*data` is valid until
/// the handle is freed.
///
/// # Safety
/// `result` is a live handle or NULL; `data` and `len` are writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_mesh_cage_coords(
    result: *const GbsurfResult,
    data: *mut *const f64,
    len: *mut usize,
) -> u32 {
    view_array("gbsurf_mesh_cage_coords", result, |r| Ok(r.mesh.cage_coords.as_flattened()), data, len)
}

/// View of the per-corner cage corner of the triangle layout (empty for the quad layout, whose
/// corners take their quad's `gbsurf_mesh_cage_corner`, and for the subdivision methods): 2
/// values (face of the control mesh, position of the vertex in its vertex list as given, holes'
/// loops after the outer loop) per corner of
/// every triangle, in the order of `gbsurf_mesh_triangles` (6 per triangle): the cage corner the
/// corner's `gbsurf_mesh_cage_coords` are in, which differs from the triangle's where it
/// straddles two sectors (docs/math.md#cage-corners); `UINT32_MAX` pairs without a cage map.
/// `*len` is the number of values; `*data` is valid until the handle is freed.
///
/// # Safety
/// `result` is a live handle or NULL; `data` and `len` are writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_mesh_cage_loop_corner(
    result: *const GbsurfResult,
    data: *mut *const u32,
    len: *mut usize,
) -> u32 {
    view_array("gbsurf_mesh_cage_loop_corner", result, |r| Ok(r.mesh.cage_loop_corner.as_flattened()), data, len)
}

/// Carries an attribute of the control mesh, given per cage face corner, to the output's face
/// corners by Subdivision Surface's "keep corners" rule (docs/math.md#cage-corners): at cage
/// coordinates (σ, τ) in corner k of face f, bilinear between a_k, ½(a_k + a_{k+1}), the face
/// mean and ½(a_k + a_{k−1}). For UV maps (dim 2), colours, weights per corner.
///
/// - `face_sizes[n_faces]`: the corner count of every face of the control mesh the result was
///   built from, in input order (faces with holes: `gbsurf_cage_loop_values_holed`);
/// - `values[values_len]`: `dim` floats per cage face corner, in face-corner order
///   (`values_len` = dim × Σ face_sizes);
/// - `face_corner[face_corner_len]`, `loop_corner[loop_corner_len]`, `coords[coords_len]`: the
///   result's `gbsurf_mesh_cage_corner`, `gbsurf_mesh_cage_loop_corner` (may be empty: NULL, 0)
///   and `gbsurf_mesh_cage_coords` views, or copies of them;
/// - `out[out_len]`: receives `dim` floats per output face corner (`out_len` = dim ×
///   coords_len / 2), in the order of the corners of `gbsurf_mesh_quads` (quad layout) or
///   `gbsurf_mesh_triangles` (triangle layout). Corners with an unknown cage corner get 0.
///
/// Errors: `_COUNT` (lengths that do not match, dim = 0 or above 256, a face with fewer than 3
/// corners, `out` overlapping an input),
/// `_INDEX` (a cage corner outside `face_sizes`: sizes of another cage), `_NAN` (non-finite
/// coordinates), `_NULL`. `out` is written only on success.
///
/// # Safety
/// Every pointer points to its length of readable values (`out`: writable); NULL only with
/// length 0. An `out` that overlaps an input is refused (`_COUNT`).
#[no_mangle]
pub unsafe extern "C" fn gbsurf_cage_loop_values(
    face_sizes: *const u32,
    n_faces: usize,
    values: *const f32,
    values_len: usize,
    dim: usize,
    face_corner: *const u32,
    face_corner_len: usize,
    loop_corner: *const u32,
    loop_corner_len: usize,
    coords: *const f64,
    coords_len: usize,
    out: *mut f32,
    out_len: usize,
) -> u32 {
    // SAFETY: the same contract, no holes.
    unsafe {
        cage_loop_values_body(
            "gbsurf_cage_loop_values",
            (face_sizes, n_faces, std::ptr::null(), std::ptr::null(), 0),
            (values, values_len, dim),
            (face_corner, face_corner_len, loop_corner, loop_corner_len, coords, coords_len),
            (out, out_len),
        )
    }
}

/// `gbsurf_cage_loop_values` for a control mesh with faces with holes (as given to
/// `gbsurf_convert_holed`). Values are given per face corner in the user's numbering
/// (docs/math.md#cage-corners): face by face, the corners of its outer loop
/// (`face_sizes[f]`), then those of each of its holes in hole order; the result's cage corners
/// use the same numbering. A corner's neighbours a_{k±1} are those in its own loop, the face mean
/// is over all its loops' corners.
///
/// - `hole_faces[n_holes]`, `hole_sizes[n_holes]`: per hole, its face and corner count
///   (`GbsurfHoles::faces`, `GbsurfHoles::sizes`); NULL with `n_holes` = 0 for none;
/// - the other arguments as for `gbsurf_cage_loop_values` (`values_len` = dim × (Σ face_sizes +
///   Σ hole_sizes)).
///
/// Errors: as `gbsurf_cage_loop_values`; also `_INDEX` (a hole naming a face outside
/// `face_sizes`) and `_COUNT` (a hole with fewer than 3 corners).
///
/// # Safety
/// As for `gbsurf_cage_loop_values`; `hole_faces` and `hole_sizes` point to `n_holes` readable
/// values (NULL only when `n_holes` is 0).
#[no_mangle]
pub unsafe extern "C" fn gbsurf_cage_loop_values_holed(
    face_sizes: *const u32,
    n_faces: usize,
    hole_faces: *const u32,
    hole_sizes: *const u32,
    n_holes: usize,
    values: *const f32,
    values_len: usize,
    dim: usize,
    face_corner: *const u32,
    face_corner_len: usize,
    loop_corner: *const u32,
    loop_corner_len: usize,
    coords: *const f64,
    coords_len: usize,
    out: *mut f32,
    out_len: usize,
) -> u32 {
    // SAFETY: the contract above.
    unsafe {
        cage_loop_values_body(
            "gbsurf_cage_loop_values_holed",
            (face_sizes, n_faces, hole_faces, hole_sizes, n_holes),
            (values, values_len, dim),
            (face_corner, face_corner_len, loop_corner, loop_corner_len, coords, coords_len),
            (out, out_len),
        )
    }
}

/// The cage faces of [`cage_loop_values_body`]: face sizes, their count, hole faces, hole sizes,
/// the hole count.
type CageFacesArgs = (*const u32, usize, *const u32, *const u32, usize);
/// The cage maps of [`cage_loop_values_body`]: face corners, loop corners and coordinates with
/// their lengths.
type CageMapArgs = (*const u32, usize, *const u32, usize, *const f64, usize);

/// The one body of `gbsurf_cage_loop_values` and `gbsurf_cage_loop_values_holed`, behind the
/// panic boundary named `name`.
///
/// # Safety
/// As `gbsurf_cage_loop_values_holed`.
unsafe fn cage_loop_values_body(
    name: &'static str,
    (face_sizes, n_faces, hole_faces, hole_sizes, n_holes): CageFacesArgs,
    (values, values_len, dim): (*const f32, usize, usize),
    (face_corner, face_corner_len, loop_corner, loop_corner_len, coords, coords_len): CageMapArgs,
    (out, out_len): (*mut f32, usize),
) -> u32 {
    boundary(name, || {
        // SAFETY: pointer/length pairs (contract).
        let (sizes, hole_faces, hole_sizes, values, face_corner, loop_corner, coords) = unsafe {
            (
                slice_arg(face_sizes, n_faces, "face_sizes")?,
                slice_arg(hole_faces, n_holes, "hole_faces")?,
                slice_arg(hole_sizes, n_holes, "hole_sizes")?,
                slice_arg(values, values_len, "values")?,
                slice_arg(face_corner, face_corner_len, "face_corner")?,
                slice_arg(loop_corner, loop_corner_len, "loop_corner")?,
                slice_arg(coords, coords_len, "coords")?,
            )
        };
        fn pairs<'a, T>(flat: &'a [T], arg: &str) -> FfiResult<&'a [[T; 2]]> {
            match flat.as_chunks::<2>() {
                (pairs, []) => Ok(pairs),
                _ => Err(FfiError::new(GBSURF_ERR_COUNT, format!("{arg}: {} values, not pairs", flat.len()))),
            }
        }
        let (face_corner, loop_corner, coords) = (pairs(face_corner, "face_corner")?, pairs(loop_corner, "loop_corner")?, pairs(coords, "coords")?);
        let want = coords.len().saturating_mul(dim);
        if out_len != want {
            return Err(FfiError::new(GBSURF_ERR_COUNT, format!("out_len is {out_len}: {} face corners × dim {dim} = {want} floats are written", coords.len())));
        }
        let bytes = |x: usize, size: usize| x.saturating_mul(size);
        let inputs = [
            ("face_sizes", face_sizes as *const u8, bytes(n_faces, 4)),
            ("hole_faces", hole_faces.as_ptr() as *const u8, bytes(hole_faces.len(), 4)),
            ("hole_sizes", hole_sizes.as_ptr() as *const u8, bytes(hole_sizes.len(), 4)),
            ("values", values.as_ptr() as *const u8, bytes(values.len(), 4)),
            ("face_corner", face_corner.as_ptr() as *const u8, bytes(face_corner.len(), 8)),
            ("loop_corner", loop_corner.as_ptr() as *const u8, bytes(loop_corner.len(), 8)),
            ("coords", coords.as_ptr() as *const u8, bytes(coords.len(), 16)),
        ];
        // SAFETY: `out` has out_len writable floats (contract); overlap with the inputs is refused.
        let out = unsafe { slice_arg_mut(out, out_len, "out", &inputs)? };
        let loops = gbsurf::tessellate::CageLoops { face_corner, loop_corner, coords };
        let faces = gbsurf::tessellate::CageFaces { sizes, hole_faces, hole_sizes };
        gbsurf::tessellate::cage_loop_values_into(faces, values, dim, loops, out).map_err(|e| {
            use gbsurf::tessellate::CageValuesError as E;
            let code = match e {
                E::FaceOutOfRange { .. } | E::CornerOutOfRange { .. } | E::HoleFaceOutOfRange { .. } => {
                    GBSURF_ERR_INDEX
                }
                E::NotFinite { .. } => GBSURF_ERR_NAN,
                _ => GBSURF_ERR_COUNT,
            };
            FfiError::new(code, e.to_string())
        })?;
        Ok(())
    })
}

/// View of the per-triangle patch index (patch methods: the patch it was sampled from;
/// subdivision methods: the input face it descends from); quad k's patch is triangle 2k's.
/// `*data` is valid until the handle is freed.
///
/// # Safety
/// `result` is a live handle or NULL; `data` and `len` are writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_mesh_triangle_patch(
    result: *const GbsurfResult,
    data: *mut *const u32,
    len: *mut usize,
) -> u32 {
    view_array("gbsurf_mesh_triangle_patch", result, |r| Ok(&r.mesh.triangle_patch[..]), data, len)
}

/// View of the per-vertex patch index (patch methods: the patch the vertex was sampled from;
/// subdivision methods: the input face it descends from); `*data` is valid until the handle is
/// freed, `*len` is the number of values.
///
/// # Safety
/// `result` is a live handle or NULL; `data` and `len` are writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_mesh_patch_index(
    result: *const GbsurfResult,
    data: *mut *const u32,
    len: *mut usize,
) -> u32 {
    view_array("gbsurf_mesh_patch_index", result, |r| Ok(&r.mesh.patch), data, len)
}

/// Copy-out variant of `gbsurf_mesh_patch_index`.
///
/// # Safety
/// `result` is a live handle or NULL; `buf` has `capacity` writable values.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_mesh_copy_patch_index(
    result: *const GbsurfResult,
    buf: *mut u32,
    capacity: usize,
    written: *mut usize,
) -> u32 {
    copy_array("gbsurf_mesh_copy_patch_index", result, |r| Ok(&r.mesh.patch), buf, capacity, written)
}

/// View of the per-vertex mean curvature H = (k1 + k2)/2 (sign relative to the normal); `*data` is
/// valid until the handle is freed, `*len` is the number of values.
///
/// # Safety
/// `result` is a live handle or NULL; `data` and `len` are writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_mesh_mean_curvature(
    result: *const GbsurfResult,
    data: *mut *const f64,
    len: *mut usize,
) -> u32 {
    view_array("gbsurf_mesh_mean_curvature", result, |r| Ok(&r.mesh.mean_curvature), data, len)
}

/// Copy-out variant of `gbsurf_mesh_mean_curvature`.
///
/// # Safety
/// `result` is a live handle or NULL; `buf` has `capacity` writable values.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_mesh_copy_mean_curvature(
    result: *const GbsurfResult,
    buf: *mut f64,
    capacity: usize,
    written: *mut usize,
) -> u32 {
    copy_array("gbsurf_mesh_copy_mean_curvature", result, |r| Ok(&r.mesh.mean_curvature), buf, capacity, written)
}

/// View of the per-vertex Gaussian curvature K = k1 k2; `*data` is valid until the handle is freed,
/// `*len` is the number of values.
///
/// # Safety
/// `result` is a live handle or NULL; `data` and `len` are writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_mesh_gaussian_curvature(
    result: *const GbsurfResult,
    data: *mut *const f64,
    len: *mut usize,
) -> u32 {
    view_array("gbsurf_mesh_gaussian_curvature", result, |r| Ok(&r.mesh.gaussian_curvature), data, len)
}

/// Copy-out variant of `gbsurf_mesh_gaussian_curvature`.
///
/// # Safety
/// `result` is a live handle or NULL; `buf` has `capacity` writable values.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_mesh_copy_gaussian_curvature(
    result: *const GbsurfResult,
    buf: *mut f64,
    capacity: usize,
    written: *mut usize,
) -> u32 {
    copy_array("gbsurf_mesh_copy_gaussian_curvature", result, |r| Ok(&r.mesh.gaussian_curvature), buf, capacity, written)
}

/// View of the per-vertex G1 deviation in degrees (largest normal angle between patches sharing the
/// vertex; 0 inside patches); `*data` is valid until the handle is freed, `*len` is the number of
/// values.
///
/// # Safety
/// `result` is a live handle or NULL; `data` and `len` are writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_mesh_g1_deviation(
    result: *const GbsurfResult,
    data: *mut *const f64,
    len: *mut usize,
) -> u32 {
    view_array("gbsurf_mesh_g1_deviation", result, |r| Ok(&r.mesh.g1_deviation_deg), data, len)
}

/// Copy-out variant of `gbsurf_mesh_g1_deviation`.
///
/// # Safety
/// `result` is a live handle or NULL; `buf` has `capacity` writable values.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_mesh_copy_g1_deviation(
    result: *const GbsurfResult,
    buf: *mut f64,
    capacity: usize,
    written: *mut usize,
) -> u32 {
    copy_array("gbsurf_mesh_copy_g1_deviation", result, |r| Ok(&r.mesh.g1_deviation_deg), buf, capacity, written)
}

/// View of the per-vertex fold flag: 1 where the vertex marks a fold (a folded sample of a patch
/// that turns over, or a vertex around its worst point; docs/math.md#folds) or a vertex of a
/// flipped triangle, else 0 (all 0 for the subdivision methods); `*data` is valid until the handle is freed, `*len` is the number of
/// values.
///
/// # Safety
/// `result` is a live handle or NULL; `data` and `len` are writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_mesh_fold(
    result: *const GbsurfResult,
    data: *mut *const u8,
    len: *mut usize,
) -> u32 {
    view_array("gbsurf_mesh_fold", result, |r| Ok(&r.mesh.fold), data, len)
}

/// Copy-out variant of `gbsurf_mesh_fold`.
///
/// # Safety
/// `result` is a live handle or NULL; `buf` has `capacity` writable values.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_mesh_copy_fold(
    result: *const GbsurfResult,
    buf: *mut u8,
    capacity: usize,
    written: *mut usize,
) -> u32 {
    copy_array("gbsurf_mesh_copy_fold", result, |r| Ok(&r.mesh.fold), buf, capacity, written)
}

/// Number of vertices of the output mesh.
///
/// # Safety
/// `result` is a live handle or NULL; `count` writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_mesh_vertex_count(
    result: *const GbsurfResult,
    count: *mut usize,
) -> u32 {
    boundary("gbsurf_mesh_vertex_count", || {
        put(count, "count", handle(result)?.positions().len() / 3)
    })
}

/// Number of quads of the output mesh (0 for the triangle layout and the subdivision methods).
///
/// # Safety
/// `result` is a live handle or NULL; `count` writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_mesh_quad_count(
    result: *const GbsurfResult,
    count: *mut usize,
) -> u32 {
    boundary("gbsurf_mesh_quad_count", || {
        put(count, "count", handle(result)?.quads().len() / 4)
    })
}

/// Number of triangles of the output mesh (two per quad in the quad layout).
///
/// # Safety
/// `result` is a live handle or NULL; `count` writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_mesh_triangle_count(
    result: *const GbsurfResult,
    count: *mut usize,
) -> u32 {
    boundary("gbsurf_mesh_triangle_count", || {
        put(count, "count", handle(result)?.triangles().len() / 3)
    })
}

fn patch_at(r: &GbsurfResult, patch: usize) -> FfiResult<&FlatPatch> {
    r.flat().get(patch).ok_or_else(|| {
        FfiError::new(
            GBSURF_ERR_INDEX,
            format!("patch index {patch} out of range (0..{})", r.patch_count()),
        )
    })
}

fn ribbon_at(r: &GbsurfResult, patch: usize, side: usize) -> FfiResult<&FlatRibbon> {
    let p = patch_at(r, patch)?;
    p.ribbons.get(side).ok_or_else(|| {
        FfiError::new(
            GBSURF_ERR_INDEX,
            format!(
                "patch {patch}: side index {side} out of range (0..{})",
                p.ribbons.len()
            ),
        )
    })
}

/// Number of patches (0 for the subdivision methods).
///
/// # Safety
/// `result` is a live handle or NULL; `count` writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_patch_count(result: *const GbsurfResult, count: *mut usize) -> u32 {
    boundary("gbsurf_patch_count", || {
        put(count, "count", handle(result)?.patch_count())
    })
}

/// Kind of patch `patch`: `GBSURF_PATCH_GB` or `GBSURF_PATCH_CGB`.
///
/// # Safety
/// `result` is a live handle or NULL; `kind` writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_patch_kind(
    result: *const GbsurfResult,
    patch: usize,
    kind: *mut u32,
) -> u32 {
    boundary("gbsurf_patch_kind", || {
        put(kind, "kind", patch_at(handle(result)?, patch)?.kind)
    })
}

/// Number of sides n of patch `patch`.
///
/// # Safety
/// `result` is a live handle or NULL; `sides` writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_patch_sides(
    result: *const GbsurfResult,
    patch: usize,
    sides: *mut usize,
) -> u32 {
    boundary("gbsurf_patch_sides", || {
        put(
            sides,
            "sides",
            patch_at(handle(result)?, patch)?.ribbons.len(),
        )
    })
}

/// Degree d and layer count l of the ribbon on side `side` of patch `patch` (a GB patch has
/// the same d on all sides; a CGB patch may differ per side).
///
/// # Safety
/// `result` is a live handle or NULL; `degree` and `layers` writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_patch_degree(
    result: *const GbsurfResult,
    patch: usize,
    side: usize,
    degree: *mut usize,
    layers: *mut usize,
) -> u32 {
    boundary("gbsurf_patch_degree", || {
        let rb = ribbon_at(handle(result)?, patch, side)?;
        non_null_mut(layers, "layers")?;
        put(degree, "degree", rb.degree)?;
        put(layers, "layers", rb.layers)
    })
}

/// View of the control points of the ribbon on side `side` of patch `patch`:
/// `(*data)[3 * (k * (degree + 1) + j) + c]` is coordinate c of P_{j,k} (row k = 0 is the
/// boundary curve); `*len` = 3 · layers · (degree + 1).
///
/// # Safety
/// `result` is a live handle or NULL; `data` and `len` writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_patch_ribbon_points(
    result: *const GbsurfResult,
    patch: usize,
    side: usize,
    data: *mut *const f64,
    len: *mut usize,
) -> u32 {
    view_array("gbsurf_patch_ribbon_points", result, |r| Ok(&ribbon_at(r, patch, side)?.points), data, len)
}

/// Copy-out variant of `gbsurf_patch_ribbon_points`.
///
/// # Safety
/// `result` is a live handle or NULL; `buf` has `capacity` writable doubles.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_patch_copy_ribbon_points(
    result: *const GbsurfResult,
    patch: usize,
    side: usize,
    buf: *mut f64,
    capacity: usize,
    written: *mut usize,
) -> u32 {
    copy_array("gbsurf_patch_copy_ribbon_points", result, |r| Ok(&ribbon_at(r, patch, side)?.points), buf, capacity, written)
}

/// The central control point of GB patch `patch` into `xyz[0..3]`. A CGB patch has none:
/// `GBSURF_ERR_KIND`.
///
/// # Safety
/// `result` is a live handle or NULL; `xyz` has 3 writable doubles or is NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_patch_center(
    result: *const GbsurfResult,
    patch: usize,
    xyz: *mut f64,
) -> u32 {
    boundary("gbsurf_patch_center", || {
        let p = patch_at(handle(result)?, patch)?;
        let c = p.center.ok_or_else(|| {
            FfiError::new(
                GBSURF_ERR_KIND,
                format!("patch {patch} is a ribbon-only (CGB) patch: no central control point"),
            )
        })?;
        let xyz = non_null_mut(xyz, "xyz")?;
        // SAFETY: 3 writable doubles (contract).
        unsafe { std::ptr::copy_nonoverlapping(c.as_ptr(), xyz, 3) };
        Ok(())
    })
}

/// Number of curves of the curve network (each boundary curve once).
///
/// # Safety
/// `result` is a live handle or NULL; `count` writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_curve_count(result: *const GbsurfResult, count: *mut usize) -> u32 {
    boundary("gbsurf_curve_count", || {
        put(count, "count", handle(result)?.curve_count())
    })
}

/// The coordinates of curve `curve` of `curves` (the network or its cubic chains).
fn curve_at(curves: &[Vec<DVec3>], curve: usize) -> FfiResult<&[f64]> {
    curves.get(curve).map(|c| coords(c)).ok_or_else(|| {
        FfiError::new(
            GBSURF_ERR_INDEX,
            format!("curve index {curve} out of range (0..{})", curves.len()),
        )
    })
}

/// View of the Bézier control points of curve `curve` (x y z each; degree = len / 3 − 1).
///
/// # Safety
/// `result` is a live handle or NULL; `data` and `len` writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_curve_points(
    result: *const GbsurfResult,
    curve: usize,
    data: *mut *const f64,
    len: *mut usize,
) -> u32 {
    view_array("gbsurf_curve_points", result, |r| curve_at(r.curves(), curve), data, len)
}

/// Copy-out variant of `gbsurf_curve_points`.
///
/// # Safety
/// `result` is a live handle or NULL; `buf` has `capacity` writable doubles.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_curve_copy_points(
    result: *const GbsurfResult,
    curve: usize,
    buf: *mut f64,
    capacity: usize,
    written: *mut usize,
) -> u32 {
    copy_array("gbsurf_curve_copy_points", result, |r| curve_at(r.curves(), curve), buf, capacity, written)
}

/// View of curve `curve` as a chain of cubic Bézier segments: 3k + 1 points (x y z each), segment
/// i = points 3i..3i+3, consecutive segments sharing an end point. A curve of degree ≤ 3 is one
/// exact segment; a higher degree is split until each segment's error bound is below 1e-9 times
/// the curve network's bounding-box diagonal (see `Surface::cubic_curves` of the gbsurf crate).
/// Built on the first call for any curve.
///
/// # Safety
/// `result` is a live handle or NULL; `data` and `len` writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_curve_cubic_points(
    result: *const GbsurfResult,
    curve: usize,
    data: *mut *const f64,
    len: *mut usize,
) -> u32 {
    view_array("gbsurf_curve_cubic_points", result, |r| curve_at(r.cubic_curves(), curve), data, len)
}

/// Copy-out variant of `gbsurf_curve_cubic_points`.
///
/// # Safety
/// `result` is a live handle or NULL; `buf` has `capacity` writable doubles.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_curve_copy_cubic_points(
    result: *const GbsurfResult,
    curve: usize,
    buf: *mut f64,
    capacity: usize,
    written: *mut usize,
) -> u32 {
    copy_array("gbsurf_curve_copy_cubic_points", result, |r| curve_at(r.cubic_curves(), curve), buf, capacity, written)
}

/// View of the control net's vertex positions, x y z each (`*data` valid until the handle is
/// freed, `*len` values). The control net shows the control points of all patches as one mesh
/// (empty for the subdivision methods). Vertices, patch by patch: each ribbon's points row by
/// row as in `gbsurf_patch_ribbon_points`, then a GB patch's central point. Faces: the quads
/// between consecutive rows of a ribbon. Edges: the control polygons of one-row ribbons and the
/// spokes from the middle point of a GB patch's innermost rows to its centre.
///
/// # Safety
/// `result` is a live handle or NULL; `data` and `len` are writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_control_net_positions(
    result: *const GbsurfResult,
    data: *mut *const f64,
    len: *mut usize,
) -> u32 {
    view_array("gbsurf_control_net_positions", result, |r| Ok(coords(&r.control_net().positions)), data, len)
}

/// Copy-out variant of `gbsurf_control_net_positions`.
///
/// # Safety
/// `result` is a live handle or NULL; `buf` has `capacity` writable values.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_control_net_copy_positions(
    result: *const GbsurfResult,
    buf: *mut f64,
    capacity: usize,
    written: *mut usize,
) -> u32 {
    copy_array("gbsurf_control_net_copy_positions", result, |r| Ok(coords(&r.control_net().positions)), buf, capacity, written)
}

/// View of the corner count of each control net face (all 4); `*data` is valid until the handle is
/// freed, `*len` is the number of values.
///
/// # Safety
/// `result` is a live handle or NULL; `data` and `len` are writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_control_net_face_sizes(
    result: *const GbsurfResult,
    data: *mut *const u32,
    len: *mut usize,
) -> u32 {
    view_array("gbsurf_control_net_face_sizes", result, |r| Ok(&r.control_net().face_sizes), data, len)
}

/// Copy-out variant of `gbsurf_control_net_face_sizes`.
///
/// # Safety
/// `result` is a live handle or NULL; `buf` has `capacity` writable values.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_control_net_copy_face_sizes(
    result: *const GbsurfResult,
    buf: *mut u32,
    capacity: usize,
    written: *mut usize,
) -> u32 {
    copy_array("gbsurf_control_net_copy_face_sizes", result, |r| Ok(&r.control_net().face_sizes), buf, capacity, written)
}

/// View of the corners of the control net faces (0-based vertex indices, one face after another);
/// `*data` is valid until the handle is freed, `*len` is the number of values.
///
/// # Safety
/// `result` is a live handle or NULL; `data` and `len` are writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_control_net_face_indices(
    result: *const GbsurfResult,
    data: *mut *const u32,
    len: *mut usize,
) -> u32 {
    view_array("gbsurf_control_net_face_indices", result, |r| Ok(&r.control_net().face_indices), data, len)
}

/// Copy-out variant of `gbsurf_control_net_face_indices`.
///
/// # Safety
/// `result` is a live handle or NULL; `buf` has `capacity` writable values.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_control_net_copy_face_indices(
    result: *const GbsurfResult,
    buf: *mut u32,
    capacity: usize,
    written: *mut usize,
) -> u32 {
    copy_array("gbsurf_control_net_copy_face_indices", result, |r| Ok(&r.control_net().face_indices), buf, capacity, written)
}

/// View of the control net's lines that bound no face (2 vertex indices each); `*data` is valid
/// until the handle is freed, `*len` is the number of values.
///
/// # Safety
/// `result` is a live handle or NULL; `data` and `len` are writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_control_net_edges(
    result: *const GbsurfResult,
    data: *mut *const u32,
    len: *mut usize,
) -> u32 {
    view_array("gbsurf_control_net_edges", result, |r| Ok(r.control_net().edges.as_flattened()), data, len)
}

/// Copy-out variant of `gbsurf_control_net_edges`.
///
/// # Safety
/// `result` is a live handle or NULL; `buf` has `capacity` writable values.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_control_net_copy_edges(
    result: *const GbsurfResult,
    buf: *mut u32,
    capacity: usize,
    written: *mut usize,
) -> u32 {
    copy_array("gbsurf_control_net_copy_edges", result, |r| Ok(r.control_net().edges.as_flattened()), buf, capacity, written)
}

/// View of the patch of each control net vertex; `*data` is valid until the handle is freed, `*len`
/// is the number of values.
///
/// # Safety
/// `result` is a live handle or NULL; `data` and `len` are writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_control_net_patch_index(
    result: *const GbsurfResult,
    data: *mut *const u32,
    len: *mut usize,
) -> u32 {
    view_array("gbsurf_control_net_patch_index", result, |r| Ok(&r.control_net().patch), data, len)
}

/// Copy-out variant of `gbsurf_control_net_patch_index`.
///
/// # Safety
/// `result` is a live handle or NULL; `buf` has `capacity` writable values.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_control_net_copy_patch_index(
    result: *const GbsurfResult,
    buf: *mut u32,
    capacity: usize,
    written: *mut usize,
) -> u32 {
    copy_array("gbsurf_control_net_copy_patch_index", result, |r| Ok(&r.control_net().patch), buf, capacity, written)
}

/// Number of warnings (things accepted but changed, e.g. dropped isolated vertices).
///
/// # Safety
/// `result` is a live handle or NULL; `count` writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_warning_count(
    result: *const GbsurfResult,
    count: *mut usize,
) -> u32 {
    boundary("gbsurf_warning_count", || {
        put(count, "count", handle(result)?.warnings.len())
    })
}

/// Warning `index` as a NUL-terminated UTF-8 string owned by the handle.
///
/// # Safety
/// `result` is a live handle or NULL; `message` writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_warning_message(
    result: *const GbsurfResult,
    index: usize,
    message: *mut *const c_char,
) -> u32 {
    boundary("gbsurf_warning_message", || {
        let r = handle(result)?;
        let w = r.warnings.get(index).ok_or_else(|| {
            FfiError::new(
                GBSURF_ERR_INDEX,
                format!(
                    "warning index {index} out of range (0..{})",
                    r.warnings.len()
                ),
            )
        })?;
        put(message, "message", w.as_ptr())
    })
}

/// Fills `*report` with the report figures. Set `report->struct_size = sizeof(GbsurfReport)`
/// first (unknown sizes: `GBSURF_ERR_INVALID_OPTION`).
///
/// # Safety
/// `result` is a live handle or NULL; `report` NULL or a writable `GbsurfReport`.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_result_report(
    result: *const GbsurfResult,
    report: *mut GbsurfReport,
) -> u32 {
    boundary("gbsurf_result_report", || {
        let r = handle(result)?;
        let out = non_null_mut(report, "report")?;
        // SAFETY: non-null; at least the size field is readable (contract).
        let size = unsafe { std::ptr::read_unaligned(out as *const u32) };
        if size != REPORT_SIZE && size != REPORT_SIZE_V1 {
            return Err(FfiError::new(
                GBSURF_ERR_INVALID_OPTION,
                format!("report struct_size = {size}: unknown size (this library expects {REPORT_SIZE}, or {REPORT_SIZE_V1} for the first version)"),
            ));
        }
        let mut report = r.report;
        report.struct_size = size;
        // SAFETY: the caller's struct is `size` bytes long (one of the two versions, checked
        // above); the first `size` bytes of ours are the same fields at the same offsets.
        unsafe {
            std::ptr::copy_nonoverlapping(
                (&report as *const GbsurfReport).cast::<u8>(),
                out.cast::<u8>(),
                size as usize,
            )
        };
        Ok(())
    })
}

/// Fold site `index` (0-based, below the report's `fold_sites`): the patch and the domain point
/// (regular n-gon domain) where it folds most.
///
/// Errors: `GBSURF_ERR_NULL`, `GBSURF_ERR_INDEX` (index out of range).
///
/// # Safety
/// `result` is a live handle or NULL; `patch`, `u`, `v` writable (NULL gives `GBSURF_ERR_NULL`).
#[no_mangle]
pub unsafe extern "C" fn gbsurf_report_fold_site(
    result: *const GbsurfResult,
    index: usize,
    patch: *mut usize,
    u: *mut f64,
    v: *mut f64,
) -> u32 {
    boundary("gbsurf_report_fold_site", || {
        let r = handle(result)?;
        let site = r.fold_sites.get(index).ok_or_else(|| {
            FfiError::new(GBSURF_ERR_INDEX, format!("fold site {index} out of range (the report lists {})", r.fold_sites.len()))
        })?;
        put(patch, "patch", site.patch)?;
        put(u, "u", site.u)?;
        put(v, "v", site.v)
    })
}

/// Number of patches (subdivision methods: faces) with `sides` sides (0 when there are none).
///
/// # Safety
/// `result` is a live handle or NULL; `count` writable or NULL.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_report_patches_with_sides(
    result: *const GbsurfResult,
    sides: usize,
    count: *mut usize,
) -> u32 {
    boundary("gbsurf_report_patches_with_sides", || {
        let r = handle(result)?;
        let c = r
            .sides_histogram
            .iter()
            .find(|(n, _)| *n == sides as u64)
            .map_or(0, |&(_, c)| c);
        put(count, "count", c as usize)
    })
}

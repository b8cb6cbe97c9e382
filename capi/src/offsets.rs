//! Exact offsets through the C ABI (docs/math/ph.md, docs/math/pn.md): planar PH quintic Hermite
//! interpolation with its rational offsets (`GbsurfPh5`), and PN surfaces interpolating a grid of
//! points with normals, evaluated exactly with their offsets (`GbsurfPn`).

use super::*;
use gbsurf::offset::ph::{HermiteSolutions, OpenEnds, PhError, PlanarPhQuintic, PlanarPhSpline};
use gbsurf::offset::pn::{PnError, PnGrid, PnOptions, PnSurface};
use glam::{DVec2, DVec3};

/// Most cusps a PH quintic offset can have (roots of the degree-8 polynomial σ² + 2dN).
pub const GBSURF_PH5_MAX_CUSPS: usize = 8;
/// Control points (and weights) of the rational offset of a PH quintic (degree 9).
pub const GBSURF_PH5_OFFSET_POINTS: usize = 10;

/// The four planar PH quintic Hermite interpolants of `gbsurf_ph5_hermite` (opaque; free with
/// `gbsurf_ph5_free`).
pub struct GbsurfPh5 {
    solutions: HermiteSolutions,
}

/// Shape measures of one PH quintic.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct GbsurfPh5Measures {
    /// Exact arc length.
    pub arc_length: f64,
    /// Elastic bending energy ∫ κ² ds (infinite when the hodograph vanishes).
    pub bending_energy: f64,
    /// Absolute rotation index (1/2π) ∫ |κ| ds.
    pub abs_rotation_index: f64,
    /// Minimum radius of curvature (infinite for a straight segment, 0 when the hodograph
    /// vanishes on [0, 1]).
    pub min_curvature_radius: f64,
    /// Signs of the start and end roots of the solution (Algorithm 952's labelling), ±1.
    pub eta0: i32,
    pub eta2: i32,
}

/// The status code of a PH error.
fn ph_code(e: &PhError) -> u32 {
    match e {
        PhError::NonFinite { .. } => GBSURF_ERR_NAN,
        PhError::TooFewPoints { .. } | PhError::LengthMismatch { .. } => GBSURF_ERR_COUNT,
        _ => GBSURF_ERR_DEGENERATE,
    }
}

fn ph_err(e: PhError) -> FfiError {
    FfiError::new(ph_code(&e), e.to_string())
}

/// The status code of a PN error.
fn pn_code(e: &PnError) -> u32 {
    match e {
        PnError::NotFinite { .. } | PnError::BadOffset { .. } => GBSURF_ERR_NAN,
        PnError::BadParameter { value, .. } if !value.is_finite() => GBSURF_ERR_NAN,
        PnError::BadParameter { .. } | PnError::NoSuchPatch { .. } => GBSURF_ERR_INDEX,
        PnError::GridTooSmall { .. } | PnError::RaggedGrid { .. } | PnError::RowCount { .. } => GBSURF_ERR_COUNT,
        _ => GBSURF_ERR_DEGENERATE,
    }
}

fn pn_err(e: PnError) -> FfiError {
    FfiError::new(pn_code(&e), e.to_string())
}

/// Two doubles at `p`.
///
/// # Safety
/// `p` is NULL or points to 2 readable doubles.
unsafe fn vec2_arg(p: *const f64, arg: &str) -> FfiResult<DVec2> {
    let p = non_null(p, arg)?;
    // SAFETY: 2 readable doubles (contract).
    let s = unsafe { std::slice::from_raw_parts(p, 2) };
    Ok(DVec2::new(s[0], s[1]))
}

/// Writes `values` to `out`, which must hold `values.len()` doubles.
fn write_doubles(out: *mut f64, arg: &str, values: &[f64]) -> FfiResult {
    let out = non_null_mut(out, arg)?;
    // SAFETY: `out` has room for values.len() doubles (contract stated per entry); distinct.
    unsafe { std::ptr::copy_nonoverlapping(values.as_ptr(), out, values.len()) };
    Ok(())
}

fn ph5<'a>(h: *const GbsurfPh5) -> FfiResult<&'a GbsurfPh5> {
    let h = non_null(h, "ph5")?;
    // SAFETY: a live handle from gbsurf_ph5_hermite (contract).
    Ok(unsafe { &*h })
}

fn solution(h: &GbsurfPh5, index: usize) -> FfiResult<&PlanarPhQuintic> {
    h.solutions.solutions.get(index).map(|s| &s.curve).ok_or_else(|| {
        FfiError::new(GBSURF_ERR_INDEX, format!("solution {index} does not exist; there are 4"))
    })
}

/// The four planar PH quintic Hermite interpolants r(0) = p0, r'(0) = d0, r(1) = p1,
/// r'(1) = d1 (each argument 2 doubles x y). `*out` receives the handle (NULL first; set only on
/// success). Errors: `GBSURF_ERR_NULL`, `_NAN` (naming the argument), `_DEGENERATE` (a zero
/// derivative, coincident p0 and p1).
///
/// # Safety
/// `p0`, `d0`, `p1`, `d1` point to 2 readable doubles each; `out` to a writable pointer.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_ph5_hermite(
    p0: *const f64,
    d0: *const f64,
    p1: *const f64,
    d1: *const f64,
    out: *mut *mut GbsurfPh5,
) -> u32 {
    boundary("gbsurf_ph5_hermite", || {
        let out = non_null_mut(out, "out")?;
        // SAFETY: non-null, writable (contract).
        unsafe { *out = std::ptr::null_mut() };
        // SAFETY: 2 readable doubles each (contract).
        let (p0, d0, p1, d1) = unsafe { (vec2_arg(p0, "p0")?, vec2_arg(d0, "d0")?, vec2_arg(p1, "p1")?, vec2_arg(d1, "d1")?) };
        let solutions = PlanarPhQuintic::hermite(p0, d0, p1, d1).map_err(ph_err)?;
        // SAFETY: checked non-null and writable above.
        unsafe { *out = Box::into_raw(Box::new(GbsurfPh5 { solutions })) };
        Ok(())
    })
}

/// Frees a PH quintic handle. NULL is a no-op.
///
/// # Safety
/// `ph5` is NULL or a handle from `gbsurf_ph5_hermite` not freed before.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_ph5_free(ph5: *mut GbsurfPh5) {
    // SAFETY: NULL or a live handle of this type (contract).
    unsafe { free_handle(ph5) }
}

/// Number of solutions (always 4) and the index of the chosen one (least absolute rotation
/// index, ties broken by bending energy). Either output may be NULL.
///
/// # Safety
/// `ph5` is a live handle; the outputs are NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_ph5_solutions(ph5: *const GbsurfPh5, count: *mut usize, chosen: *mut usize) -> u32 {
    boundary("gbsurf_ph5_solutions", || {
        let h = self::ph5(ph5)?;
        if !count.is_null() {
            put(count, "count", h.solutions.solutions.len())?;
        }
        if !chosen.is_null() {
            put(chosen, "chosen", h.solutions.best)?;
        }
        Ok(())
    })
}

/// The 6 Bézier control points of solution `index` (0..4) as 12 doubles x y into `points`.
///
/// # Safety
/// `ph5` is a live handle; `points` has room for 12 doubles.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_ph5_control_points(ph5: *const GbsurfPh5, index: usize, points: *mut f64) -> u32 {
    boundary("gbsurf_ph5_control_points", || {
        let c = solution(self::ph5(ph5)?, index)?;
        let flat: Vec<f64> = c.control_points().iter().flat_map(|p| p.to_array()).collect();
        write_doubles(points, "points", &flat)
    })
}

/// Arc length, bending energy, absolute rotation index, minimum curvature radius and root signs
/// of solution `index` (0..4).
///
/// # Safety
/// `ph5` is a live handle; `measures` is writable.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_ph5_measures(ph5: *const GbsurfPh5, index: usize, measures: *mut GbsurfPh5Measures) -> u32 {
    boundary("gbsurf_ph5_measures", || {
        let h = self::ph5(ph5)?;
        let c = solution(h, index)?;
        let s = &h.solutions.solutions[index];
        let m = GbsurfPh5Measures {
            arc_length: s.arc_length,
            bending_energy: s.bending_energy,
            abs_rotation_index: s.rotation_index,
            min_curvature_radius: c.min_radius_of_curvature().unwrap_or(0.0),
            eta0: i32::from(s.eta0),
            eta2: i32::from(s.eta2),
        };
        put(measures, "measures", m)
    })
}

/// The exact offset of solution `index` at signed distance `d` (positive to the right of the
/// direction of travel): a rational Bézier curve of degree 9. `points` receives 20 doubles (10
/// control points x y), `weights` 10 doubles; `cusps` (`cusps_capacity` doubles, may be NULL when
/// 0) receives the cusp parameters in [0, 1], ascending, and `*cusp_count` their number (at most
/// `GBSURF_PH5_MAX_CUSPS`; also set on `GBSURF_ERR_CAPACITY`). Errors: `_NAN` (d), `_DEGENERATE`
/// (d = 0, a hodograph vanishing on [0, 1], a zero weight), `_INDEX`, `_CAPACITY`, `_NULL`.
///
/// # Safety
/// `ph5` is a live handle; `points` has room for 20 doubles, `weights` for 10, `cusps` for
/// `cusps_capacity`; `cusp_count` is writable.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_ph5_offset(
    ph5: *const GbsurfPh5,
    index: usize,
    d: f64,
    points: *mut f64,
    weights: *mut f64,
    cusps: *mut f64,
    cusps_capacity: usize,
    cusp_count: *mut usize,
) -> u32 {
    boundary("gbsurf_ph5_offset", || {
        let c = solution(self::ph5(ph5)?, index)?;
        write_offset(c, d, points, weights, cusps, cusps_capacity, cusp_count)
    })
}

/// The rational offset of `c` at `d` into the outputs of `gbsurf_ph5_offset`.
fn write_offset(
    c: &PlanarPhQuintic,
    d: f64,
    points: *mut f64,
    weights: *mut f64,
    cusps: *mut f64,
    cusps_capacity: usize,
    cusp_count: *mut usize,
) -> FfiResult {
    let o = c.offset(d).map_err(ph_err)?;
    let flat: Vec<f64> = o.points.iter().flat_map(|p| p.to_array()).collect();
    write_doubles(points, "points", &flat)?;
    write_doubles(weights, "weights", &o.weights)?;
    copy_out(&o.cusps, cusps, cusps_capacity, cusp_count)
}

/// A planar PH quintic spline (`gbsurf::offset::ph::PlanarPhSpline`, opaque; free with
/// `gbsurf_ph_spline_free`): segment i runs from point i to point i + 1 (closed: the last one
/// back to point 0).
pub struct GbsurfPhSpline {
    spline: PlanarPhSpline,
}

fn ph_spline<'a>(h: *const GbsurfPhSpline) -> FfiResult<&'a GbsurfPhSpline> {
    let h = non_null(h, "spline")?;
    // SAFETY: a live handle from gbsurf_ph_spline_hermite / _c2 (contract).
    Ok(unsafe { &*h })
}

fn spline_segment(h: &GbsurfPhSpline, index: usize) -> FfiResult<&PlanarPhQuintic> {
    let n = h.spline.segments.len();
    h.spline.segments.get(index).ok_or_else(|| {
        FfiError::new(GBSURF_ERR_INDEX, format!("segment {index} does not exist; there are {n}"))
    })
}

/// `len` doubles as x y pairs.
fn vec2s(flat: &[f64], arg: &str) -> FfiResult<Vec<DVec2>> {
    if flat.len() % 2 != 0 {
        return Err(FfiError::new(GBSURF_ERR_COUNT, format!("{arg} has {} values; x y pairs need an even number", flat.len())));
    }
    Ok(flat.chunks_exact(2).map(|p| DVec2::new(p[0], p[1])).collect())
}

/// Stores a new spline handle in `out` (checked non-null by the caller).
fn put_spline(out: *mut *mut GbsurfPhSpline, spline: PlanarPhSpline) {
    // SAFETY: checked non-null and writable by the caller.
    unsafe { *out = Box::into_raw(Box::new(GbsurfPhSpline { spline })) };
}

/// Segment-wise PH quintic Hermite spline through `points` with derivatives `tangents` (each
/// `2 * count` doubles x y, `points_len` = `tangents_len` ≥ 4): segment i is the chosen (least
/// absolute rotation index) interpolant of points i, i + 1 with tangents i, i + 1; C¹.
/// `*out` receives the handle (NULL first). Errors: `_COUNT` (fewer than 2 points, lengths
/// differ or odd), `_NAN` (naming the element), `_DEGENERATE` (a zero tangent, coincident
/// consecutive points), `_NULL`.
///
/// # Safety
/// `points` / `tangents` point to `points_len` / `tangents_len` readable doubles; `out` to a
/// writable pointer.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_ph_spline_hermite(
    points: *const f64,
    points_len: usize,
    tangents: *const f64,
    tangents_len: usize,
    out: *mut *mut GbsurfPhSpline,
) -> u32 {
    boundary("gbsurf_ph_spline_hermite", || {
        let out = non_null_mut(out, "out")?;
        // SAFETY: non-null, writable (contract).
        unsafe { *out = std::ptr::null_mut() };
        // SAFETY: pointer/length pairs per the contract.
        let (p, t) = unsafe { (slice_arg(points, points_len, "points")?, slice_arg(tangents, tangents_len, "tangents")?) };
        let spline = PlanarPhSpline::hermite(&vec2s(p, "points")?, &vec2s(t, "tangents")?).map_err(ph_err)?;
        put_spline(out, spline);
        Ok(())
    })
}

/// C² PH quintic spline through `points` (`points_len` = 2 × count doubles x y): `closed` ≠ 0
/// closes it (at least 3 points, the first not repeated), else an open spline with cubic end
/// spans (at least 3 points). `*out` receives the handle (NULL first). Errors as
/// `gbsurf_ph_spline_hermite` (and `_DEGENERATE` when the Newton iteration fails).
///
/// # Safety
/// `points` points to `points_len` readable doubles; `out` to a writable pointer.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_ph_spline_c2(
    points: *const f64,
    points_len: usize,
    closed: u32,
    out: *mut *mut GbsurfPhSpline,
) -> u32 {
    boundary("gbsurf_ph_spline_c2", || {
        let out = non_null_mut(out, "out")?;
        // SAFETY: non-null, writable (contract).
        unsafe { *out = std::ptr::null_mut() };
        // SAFETY: pointer/length pair per the contract.
        let p = vec2s(unsafe { slice_arg(points, points_len, "points")? }, "points")?;
        let spline = if closed != 0 {
            PlanarPhSpline::c2_closed(&p)
        } else {
            PlanarPhSpline::c2_open(&p, OpenEnds::CubicEndSpans)
        }
        .map_err(ph_err)?;
        put_spline(out, spline);
        Ok(())
    })
}

/// Frees a PH spline handle. NULL is a no-op.
///
/// # Safety
/// `spline` is NULL or a handle from `gbsurf_ph_spline_hermite` / `_c2` not freed before.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_ph_spline_free(spline: *mut GbsurfPhSpline) {
    // SAFETY: NULL or a live handle of this type (contract).
    unsafe { free_handle(spline) }
}

/// Number of segments and whether the spline is closed (either output may be NULL).
///
/// # Safety
/// `spline` is a live handle; the outputs are NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_ph_spline_segment_count(spline: *const GbsurfPhSpline, count: *mut usize, closed: *mut u32) -> u32 {
    boundary("gbsurf_ph_spline_segment_count", || {
        let h = ph_spline(spline)?;
        if !count.is_null() {
            put(count, "count", h.spline.segments.len())?;
        }
        if !closed.is_null() {
            put(closed, "closed", u32::from(h.spline.closed))?;
        }
        Ok(())
    })
}

/// The 6 Bézier control points of segment `index` as 12 doubles x y into `points`.
///
/// # Safety
/// `spline` is a live handle; `points` has room for 12 doubles.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_ph_spline_control_points(spline: *const GbsurfPhSpline, index: usize, points: *mut f64) -> u32 {
    boundary("gbsurf_ph_spline_control_points", || {
        let c = spline_segment(ph_spline(spline)?, index)?;
        let flat: Vec<f64> = c.control_points().iter().flat_map(|p| p.to_array()).collect();
        write_doubles(points, "points", &flat)
    })
}

/// The exact offset of segment `index` at signed distance `d`, as `gbsurf_ph5_offset` (a rational
/// Bézier curve of degree 9: 20 doubles of points, 10 weights, the cusp parameters).
///
/// # Safety
/// As `gbsurf_ph5_offset`, with `spline` a live spline handle.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_ph_spline_offset(
    spline: *const GbsurfPhSpline,
    index: usize,
    d: f64,
    points: *mut f64,
    weights: *mut f64,
    cusps: *mut f64,
    cusps_capacity: usize,
    cusp_count: *mut usize,
) -> u32 {
    boundary("gbsurf_ph_spline_offset", || {
        let c = spline_segment(ph_spline(spline)?, index)?;
        write_offset(c, d, points, weights, cusps, cusps_capacity, cusp_count)
    })
}

/// A PN surface interpolating a grid of points with normals (opaque; free with `gbsurf_pn_free`).
pub struct GbsurfPn {
    surface: PnSurface,
}

fn pn<'a>(h: *const GbsurfPn) -> FfiResult<&'a GbsurfPn> {
    let h = non_null(h, "pn")?;
    // SAFETY: a live handle from gbsurf_pn_interpolate (contract).
    Ok(unsafe { &*h })
}

/// A rows × cols grid of xyz triples, row-major.
fn grid(flat: &[f64], rows: usize, cols: usize, arg: &str) -> FfiResult<Vec<Vec<DVec3>>> {
    let need = rows.checked_mul(cols).and_then(|n| n.checked_mul(3));
    if need != Some(flat.len()) {
        return Err(FfiError::new(
            GBSURF_ERR_COUNT,
            format!("{arg} has {} values; a {rows} × {cols} grid needs 3 × {rows} × {cols}", flat.len()),
        ));
    }
    Ok(flat
        .chunks_exact(3 * cols.max(1))
        .map(|row| row.chunks_exact(3).map(|p| DVec3::new(p[0], p[1], p[2])).collect())
        .collect())
}

/// Interpolates a `rows` × `cols` grid (both ≥ 2) of points with normals by a G1 PN surface of
/// (rows − 1) × (cols − 1) patches (docs/math/pn.md). `points` and `normals` hold
/// `3 * rows * cols` doubles each, row-major (`[3 * (i * cols + j) + c]`); normals need not be
/// unit. `*out` receives the handle (NULL first). Errors: `_COUNT` (lengths, a grid smaller than
/// 2 × 2), `_NAN` (naming [i][j]), `_DEGENERATE` (a zero normal, a singular point), `_NULL`.
///
/// # Safety
/// `points` and `normals` point to `points_len` / `normals_len` readable doubles; `out` to a
/// writable pointer.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_pn_interpolate(
    rows: usize,
    cols: usize,
    points: *const f64,
    points_len: usize,
    normals: *const f64,
    normals_len: usize,
    out: *mut *mut GbsurfPn,
) -> u32 {
    boundary("gbsurf_pn_interpolate", || {
        let out = non_null_mut(out, "out")?;
        // SAFETY: non-null, writable (contract).
        unsafe { *out = std::ptr::null_mut() };
        if rows < 2 || cols < 2 {
            return Err(pn_err(PnError::GridTooSmall { rows, cols }));
        }
        // SAFETY: pointer/length pairs (contract).
        let (p, n) = unsafe { (slice_arg(points, points_len, "points")?, slice_arg(normals, normals_len, "normals")?) };
        let g = PnGrid::new(&grid(p, rows, cols, "points")?, &grid(n, rows, cols, "normals")?).map_err(pn_err)?;
        let surface = PnSurface::interpolate(&g, &PnOptions::default()).map_err(pn_err)?;
        // SAFETY: checked non-null and writable above.
        unsafe { *out = Box::into_raw(Box::new(GbsurfPn { surface })) };
        Ok(())
    })
}

/// Frees a PN surface handle. NULL is a no-op.
///
/// # Safety
/// `pn` is NULL or a handle from `gbsurf_pn_interpolate` not freed before.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_pn_free(pn: *mut GbsurfPn) {
    // SAFETY: NULL or a live handle of this type (contract).
    unsafe { free_handle(pn) }
}

/// The number of patches: `*rows` = grid rows − 1, `*cols` = grid columns − 1.
///
/// # Safety
/// `pn` is a live handle; `rows` and `cols` are writable.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_pn_patch_count(pn: *const GbsurfPn, rows: *mut usize, cols: *mut usize) -> u32 {
    boundary("gbsurf_pn_patch_count", || {
        let (m, n) = self::pn(pn)?.surface.patch_count();
        put(rows, "rows", m)?;
        put(cols, "cols", n)
    })
}

/// Exact point and unit normal of patch [i][j] at (u, v) ∈ [0, 1]², 3 doubles each (`normal`
/// may be NULL). Errors: `_INDEX` (patch, or u, v outside [0, 1]), `_NAN`, `_DEGENERATE` (a
/// singular point), `_NULL`.
///
/// # Safety
/// `pn` is a live handle; `point` has room for 3 doubles, `normal` is NULL or has room for 3.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_pn_eval(pn: *const GbsurfPn, i: usize, j: usize, u: f64, v: f64, point: *mut f64, normal: *mut f64) -> u32 {
    boundary("gbsurf_pn_eval", || {
        let s = self::pn(pn)?.surface.eval(i, j, u, v).map_err(pn_err)?;
        write_doubles(point, "point", &s.point.to_array())?;
        if !normal.is_null() {
            write_doubles(normal, "normal", &s.normal.to_array())?;
        }
        Ok(())
    })
}

/// The offset point x + d·n of patch [i][j] at (u, v) (3 doubles; d = 0 gives the point).
/// Errors as `gbsurf_pn_eval`, and `_NAN` for a non-finite d.
///
/// # Safety
/// `pn` is a live handle; `point` has room for 3 doubles.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_pn_offset_point(pn: *const GbsurfPn, i: usize, j: usize, u: f64, v: f64, d: f64, point: *mut f64) -> u32 {
    boundary("gbsurf_pn_offset_point", || {
        let x = self::pn(pn)?.surface.offset(i, j, u, v, d).map_err(pn_err)?;
        write_doubles(point, "point", &x.to_array())
    })
}

/// The exact rational form of the offset x + d·n of patch [i][j] at signed distance d, or, with
/// d = 0 exactly, of patch [i][j] itself (the PN surface). Unlike `gbsurf_offset` (and the Rust
/// `PnSurface::rational_offset`), d = 0 is not an error here: it selects the surface; the two
/// forms share their weights. A non-finite d is `GBSURF_ERR_NAN`. The result is a rational
/// tensor-product Bézier patch of degree (`*degree_u`, `*degree_v`) = (11, 11), given by its
/// homogeneous control points (w·x, w·y, w·z, w): `homogeneous[4 * (a * (degree_v + 1) + b) + c]`.
/// Weights may be zero or negative. `*written` receives the number of doubles (also on
/// `GBSURF_ERR_CAPACITY`: `capacity` 0 with `homogeneous` NULL queries the size).
///
/// # Safety
/// `pn` is a live handle; `homogeneous` has room for `capacity` doubles; the other outputs are
/// writable.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_pn_rational(
    pn: *const GbsurfPn,
    i: usize,
    j: usize,
    d: f64,
    degree_u: *mut usize,
    degree_v: *mut usize,
    homogeneous: *mut f64,
    capacity: usize,
    written: *mut usize,
) -> u32 {
    boundary("gbsurf_pn_rational", || {
        let s = &self::pn(pn)?.surface;
        let r = if d == 0.0 { s.rational(i, j) } else { s.rational_offset(i, j, d) }.map_err(pn_err)?;
        let (du, dv) = r.degree();
        put(degree_u, "degree_u", du)?;
        put(degree_v, "degree_v", dv)?;
        let flat: Vec<f64> = r.homogeneous.points().iter().flatten().flat_map(|h| h.to_array()).collect();
        copy_out(&flat, homogeneous, capacity, written)
    })
}

/// The numbers of `gbsurf::api::OffsetReport` (docs/math/pn.md §11), filled by `gbsurf_offset`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct GbsurfOffsetReport {
    /// Quad pieces (Σ n over the patches) and those whose PN fit was singular (their offset is
    /// the GB surface's own x + d·n).
    pub pieces: u64,
    pub singular_pieces: u64,
    /// Largest distance between the PN pieces and the GB surface at dense samples.
    pub max_fit_error: f64,
    /// Largest |n·x_u|/|x_u|, |n·x_v|/|x_v| over dense samples of the PN pieces and of their
    /// offset (away from cusps), by finite differences.
    pub max_normal_residual: f64,
    /// Largest deviation of | offset point − point | from |d| away from cusps.
    pub max_offset_error: f64,
    /// Largest gap between two pieces' evaluations of a shared sample, and the same between PN
    /// pieces sharing their data and frame.
    pub max_gap: f64,
    pub max_gap_pn: f64,
    /// Shared grid points whose derivative rays could not be matched (valence ≠ 4).
    pub unmatched_points: u64,
    /// Samples where |d| reaches the local radius of curvature on the concave side.
    pub cusps: u64,
    pub closed: u32,
    pub two_manifold: u32,
    pub seconds: f64,
    /// Shared piece edges whose two sides are in different isotropic frames (their gap is in
    /// `max_gap`, not `max_gap_pn`). Added in ABI version 3.
    pub frame_seams: u64,
    /// Largest angle (radians) between two PN pieces' normals at a shared sample, over the pairs
    /// of `max_gap_pn` (G1 across pieces). Added in ABI version 3.
    pub max_normal_angle_pn: f64,
}

/// The offset at signed distance `distance` of the GB surface of a polygon mesh (arrays as in
/// `gbsurf_convert`), through PN pieces on a `grid` × `grid` grid each (2..=64; 0 for the
/// default 4); `shell` ≠ 0 makes a closed solid. The mesh goes to `out` (a result handle: read it
/// with the `gbsurf_mesh_*` accessors, free it with `gbsurf_result_free`; it has no patches),
/// the figures to `report` (may be NULL).
///
/// Errors: as `gbsurf_convert`, plus `GBSURF_ERR_NAN` (non-finite distance) and
/// `GBSURF_ERR_INVALID_OPTION` (distance 0, grid out of range, a subdivision method).
///
/// # Safety
/// As `gbsurf_convert`; `report` is NULL or writable.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn gbsurf_offset(
    positions: *const f64,
    positions_len: usize,
    face_sizes: *const u32,
    face_count: usize,
    face_indices: *const u32,
    face_indices_len: usize,
    options: *const GbsurfOptions,
    distance: f64,
    grid: usize,
    shell: u32,
    report: *mut GbsurfOffsetReport,
    out: *mut *mut GbsurfResult,
) -> u32 {
    use gbsurf::api::{OffsetError, OffsetOptions};
    boundary("gbsurf_offset", || {
        let out = non_null_mut(out, "out")?;
        // SAFETY: non-null, writable (contract).
        unsafe { *out = std::ptr::null_mut() };
        // SAFETY: pointer/length pairs per the contract.
        let mesh = unsafe { crate::result::mesh_arg((positions, positions_len, face_sizes, face_count, face_indices, face_indices_len))? };
        let opts = crate::options::read_options(options)?;
        let grid = if grid == 0 { gbsurf::limits::DEFAULT_OFFSET_GRID } else { grid };
        let off = OffsetOptions { distance, grid, shell: shell != 0 };
        let o = gbsurf::api::offset(&mesh, &opts, &off).map_err(|e| match e {
            OffsetError::Convert(c) => crate::options::convert_error(c),
            OffsetError::BadDistance { .. } => FfiError::new(GBSURF_ERR_NAN, e.to_string()),
            OffsetError::ZeroDistance | OffsetError::BadGrid { .. } => FfiError::new(GBSURF_ERR_INVALID_OPTION, e.to_string()),
            OffsetError::Export { .. } => FfiError::new(GBSURF_ERR_DEGENERATE, e.to_string()),
        })?;
        let r = &o.report;
        if !report.is_null() {
            let numbers = GbsurfOffsetReport {
                pieces: r.pieces as u64,
                singular_pieces: r.singular_pieces as u64,
                max_fit_error: r.max_fit_error,
                max_normal_residual: r.max_normal_residual,
                max_offset_error: r.max_offset_error,
                max_gap: r.max_gap,
                max_gap_pn: r.max_gap_pn,
                unmatched_points: r.unmatched_points as u64,
                cusps: r.cusps as u64,
                closed: r.closed as u32,
                two_manifold: r.two_manifold as u32,
                seconds: r.seconds,
                frame_seams: r.frame_seams as u64,
                max_normal_angle_pn: r.max_normal_angle_pn,
            };
            crate::result::put(report, "report", numbers)?;
        }
        let normals = gbsurf::mesh::geometry::vertex_normals(&o.positions, &o.triangles);
        let quality = gbsurf::quality::Report {
            method: opts.method.name().to_string(),
            input_vertices: mesh.positions.len(),
            input_faces: mesh.faces.len(),
            vertices: o.positions.len(),
            triangles: o.triangles.len(),
            closed: r.closed,
            two_manifold: r.two_manifold,
            seconds: r.seconds,
            ..Default::default()
        };
        let conv = gbsurf::api::Conversion {
            mesh: gbsurf::tessellate::SurfaceMesh { positions: o.positions, normals, triangles: o.triangles, ..Default::default() },
            surface: None,
            report: quality,
            warnings: Vec::new(),
        };
        let method = GbsurfOptions::from(&opts).method;
        crate::result::write_out(out, Box::new(crate::result::pack(conv, method)));
        Ok(())
    })
}

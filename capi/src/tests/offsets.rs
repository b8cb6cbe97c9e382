//! The exact-offset entries of the C ABI: the numbers are the core's, every misuse has its code
//! and a message naming the argument, handles are freed.

use crate::*;
use gbsurf::offset::ph::{OpenEnds, PlanarPhQuintic, PlanarPhSpline};
use gbsurf::offset::pn::{PnGrid, PnOptions, PnSurface};
use glam::{DVec2, DVec3};
use std::ffi::CStr;
use std::ptr::{null, null_mut};

fn last() -> String {
    // SAFETY: never NULL, valid until the next call on this thread.
    unsafe { CStr::from_ptr(gbsurf_last_error_message()) }.to_string_lossy().into_owned()
}

const P0: [f64; 2] = [0.0, 0.0];
const D0: [f64; 2] = [1.0, 2.0];
const P1: [f64; 2] = [2.0, 0.0];
const D1: [f64; 2] = [1.0, -2.0];

fn hermite(p0: [f64; 2], d0: [f64; 2], p1: [f64; 2], d1: [f64; 2]) -> (u32, *mut GbsurfPh5) {
    let mut h = 1usize as *mut GbsurfPh5;
    // SAFETY: 2 doubles each; `h` writable.
    let code = unsafe { gbsurf_ph5_hermite(p0.as_ptr(), d0.as_ptr(), p1.as_ptr(), d1.as_ptr(), &mut h) };
    (code, h)
}

#[test]
fn ph5_gives_the_core_numbers() {
    let (code, h) = hermite(P0, D0, P1, D1);
    assert_eq!(code, GBSURF_OK, "{}", last());
    let v = |a: [f64; 2]| DVec2::from_array(a);
    let want = PlanarPhQuintic::hermite(v(P0), v(D0), v(P1), v(D1)).unwrap();
    let (mut count, mut chosen) = (0usize, 9usize);
    // SAFETY: live handle, writable outputs.
    unsafe {
        assert_eq!(gbsurf_ph5_solutions(h, &mut count, &mut chosen), GBSURF_OK);
        assert_eq!(gbsurf_ph5_solutions(h, null_mut(), null_mut()), GBSURF_OK);
    }
    assert_eq!((count, chosen), (4, want.best));
    for (k, s) in want.solutions.iter().enumerate() {
        let mut pts = [0.0; 12];
        let mut m = GbsurfPh5Measures::default();
        // SAFETY: 12 doubles; writable struct.
        unsafe {
            assert_eq!(gbsurf_ph5_control_points(h, k, pts.as_mut_ptr()), GBSURF_OK);
            assert_eq!(gbsurf_ph5_measures(h, k, &mut m), GBSURF_OK);
        }
        let flat: Vec<f64> = s.curve.control_points().iter().flat_map(|p| p.to_array()).collect();
        assert_eq!(pts.to_vec(), flat);
        assert_eq!(m.arc_length, s.arc_length);
        assert_eq!(m.bending_energy, s.bending_energy);
        assert_eq!(m.abs_rotation_index, s.rotation_index);
        assert_eq!(m.min_curvature_radius, s.curve.min_radius_of_curvature().unwrap());
        assert_eq!((m.eta0, m.eta2), (i32::from(s.eta0), i32::from(s.eta2)));

        // The offset at a distance between the curvature radii at t = 0 and 1/2 of the chosen one.
        let d = 0.3;
        let o = s.curve.offset(d).unwrap();
        let (mut op, mut ow, mut cusps, mut n) = ([0.0; 20], [0.0; 10], [0.0; GBSURF_PH5_MAX_CUSPS], 99usize);
        // SAFETY: buffers of the documented sizes.
        let code = unsafe { gbsurf_ph5_offset(h, k, d, op.as_mut_ptr(), ow.as_mut_ptr(), cusps.as_mut_ptr(), cusps.len(), &mut n) };
        assert_eq!(code, GBSURF_OK, "{}", last());
        assert_eq!(op.to_vec(), o.points.iter().flat_map(|p| p.to_array()).collect::<Vec<_>>());
        assert_eq!(ow.to_vec(), o.weights);
        assert_eq!(&cusps[..n], &o.cusps[..]);
    }
    // Cusps of the chosen solution: a distance between its curvature radii at t = 0 and t = 1/2.
    let best = want.best().curve;
    let r = |t: f64| 1.0 / best.curvature(t).abs();
    let d = 0.5 * (r(0.0) + r(0.5));
    let (mut op, mut ow, mut n) = ([0.0; 20], [0.0; 10], 0usize);
    // SAFETY: size query with NULL cusps and capacity 0.
    let code = unsafe { gbsurf_ph5_offset(h, want.best, d, op.as_mut_ptr(), ow.as_mut_ptr(), null_mut(), 0, &mut n) };
    assert_eq!(code, GBSURF_ERR_CAPACITY, "{}", last());
    assert_eq!(n, best.offset(d).unwrap().cusps.len());
    assert!(n > 0 && n <= GBSURF_PH5_MAX_CUSPS);
    // SAFETY: handle from gbsurf_ph5_hermite.
    unsafe { gbsurf_ph5_free(h) };
}

#[test]
fn ph5_misuse_has_codes_and_messages() {
    let (code, h) = hermite(P0, [0.0, 0.0], P1, D1);
    assert_eq!((code, h), (GBSURF_ERR_DEGENERATE, null_mut()));
    assert!(last().contains("gbsurf_ph5_hermite: derivative `d0` is zero"), "{}", last());
    let (code, _) = hermite([1.0, 1.0], D0, [1.0, 1.0], D1);
    assert_eq!(code, GBSURF_ERR_DEGENERATE);
    assert!(last().contains("coincide"), "{}", last());
    let (code, _) = hermite(P0, D0, [f64::NAN, 0.0], D1);
    assert_eq!(code, GBSURF_ERR_NAN);
    assert!(last().contains("`p1` is not finite"), "{}", last());
    let mut out = null_mut();
    // SAFETY: NULL arguments are reported.
    unsafe {
        assert_eq!(gbsurf_ph5_hermite(null(), D0.as_ptr(), P1.as_ptr(), D1.as_ptr(), &mut out), GBSURF_ERR_NULL);
        assert!(last().contains("`p0` is NULL"), "{}", last());
        assert_eq!(gbsurf_ph5_hermite(P0.as_ptr(), D0.as_ptr(), P1.as_ptr(), D1.as_ptr(), null_mut()), GBSURF_ERR_NULL);
    }
    let (code, h) = hermite(P0, D0, P1, D1);
    assert_eq!(code, GBSURF_OK);
    let (mut op, mut ow, mut cusps, mut n) = ([0.0; 20], [0.0; 10], [0.0; 8], 0usize);
    // SAFETY: buffers of the documented sizes; NULL and bad values are reported.
    unsafe {
        assert_eq!(gbsurf_ph5_offset(h, 0, 0.0, op.as_mut_ptr(), ow.as_mut_ptr(), cusps.as_mut_ptr(), 8, &mut n), GBSURF_ERR_DEGENERATE);
        assert!(last().contains("offset distance `d` is zero"), "{}", last());
        assert_eq!(gbsurf_ph5_offset(h, 0, f64::NAN, op.as_mut_ptr(), ow.as_mut_ptr(), cusps.as_mut_ptr(), 8, &mut n), GBSURF_ERR_NAN);
        assert_eq!(gbsurf_ph5_offset(h, 4, 0.1, op.as_mut_ptr(), ow.as_mut_ptr(), cusps.as_mut_ptr(), 8, &mut n), GBSURF_ERR_INDEX);
        assert!(last().contains("solution 4 does not exist"), "{}", last());
        assert_eq!(gbsurf_ph5_offset(h, 0, 0.1, null_mut(), ow.as_mut_ptr(), cusps.as_mut_ptr(), 8, &mut n), GBSURF_ERR_NULL);
        assert_eq!(gbsurf_ph5_control_points(null(), 0, op.as_mut_ptr()), GBSURF_ERR_NULL);
        assert_eq!(gbsurf_ph5_measures(h, 0, null_mut()), GBSURF_ERR_NULL);
        gbsurf_ph5_free(h);
        gbsurf_ph5_free(null_mut());
    }
}

/// A cap of the unit sphere, normals = points, row-major flat.
fn cap(rows: usize, cols: usize) -> Vec<f64> {
    (0..rows)
        .flat_map(|i| (0..cols).map(move |j| DVec3::new(0.3 * i as f64 - 0.45, 0.25 * j as f64 - 0.25, -1.0).normalize()))
        .flat_map(|p| p.to_array())
        .collect()
}

fn interpolate(rows: usize, cols: usize, p: &[f64], n: &[f64]) -> (u32, *mut GbsurfPn) {
    let mut h = 1usize as *mut GbsurfPn;
    // SAFETY: pointer/length pairs; writable out.
    let code = unsafe { gbsurf_pn_interpolate(rows, cols, p.as_ptr(), p.len(), n.as_ptr(), n.len(), &mut h) };
    (code, h)
}

#[test]
fn pn_grid_gives_the_core_numbers() {
    let (rows, cols) = (4, 3);
    let g = cap(rows, cols);
    let (code, h) = interpolate(rows, cols, &g, &g);
    assert_eq!(code, GBSURF_OK, "{}", last());
    let nested: Vec<Vec<DVec3>> = g.chunks(3 * cols).map(|r| r.chunks(3).map(|p| DVec3::new(p[0], p[1], p[2])).collect()).collect();
    let s = PnSurface::interpolate(&PnGrid::new(&nested, &nested).unwrap(), &PnOptions::default()).unwrap();
    let (mut pr, mut pc) = (0, 0);
    // SAFETY: live handle, writable outputs.
    assert_eq!(unsafe { gbsurf_pn_patch_count(h, &mut pr, &mut pc) }, GBSURF_OK);
    assert_eq!((pr, pc), (3, 2));
    for (i, j, u, v) in [(0, 0, 0.25, 0.5), (2, 1, 1.0, 0.0), (1, 1, 0.5, 0.5)] {
        let want = s.eval(i, j, u, v).unwrap();
        let (mut x, mut n, mut o) = ([0.0; 3], [0.0; 3], [0.0; 3]);
        // SAFETY: 3 doubles each.
        unsafe {
            assert_eq!(gbsurf_pn_eval(h, i, j, u, v, x.as_mut_ptr(), n.as_mut_ptr()), GBSURF_OK);
            assert_eq!(gbsurf_pn_offset_point(h, i, j, u, v, 0.5, o.as_mut_ptr()), GBSURF_OK);
        }
        assert_eq!(x, want.point.to_array());
        assert_eq!(n, want.normal.to_array());
        assert_eq!(o, want.offset(0.5).to_array());
    }
    for d in [0.0, 0.5] {
        let r = if d == 0.0 { s.rational(1, 0) } else { s.rational_offset(1, 0, d) }.unwrap();
        let flat: Vec<f64> = r.homogeneous.points().iter().flatten().flat_map(|p| p.to_array()).collect();
        let (mut du, mut dv, mut written) = (0, 0, 0);
        // SAFETY: size query (NULL buffer, capacity 0).
        let code = unsafe { gbsurf_pn_rational(h, 1, 0, d, &mut du, &mut dv, null_mut(), 0, &mut written) };
        assert_eq!(code, GBSURF_ERR_CAPACITY);
        assert_eq!((du, dv, written), (r.degree().0, r.degree().1, flat.len()));
        assert_eq!(written, 4 * (du + 1) * (dv + 1));
        let mut buf = vec![0.0; written];
        // SAFETY: buffer of `written` doubles.
        let code = unsafe { gbsurf_pn_rational(h, 1, 0, d, &mut du, &mut dv, buf.as_mut_ptr(), buf.len(), &mut written) };
        assert_eq!(code, GBSURF_OK, "{}", last());
        assert_eq!(buf, flat);
    }
    // SAFETY: handle from gbsurf_pn_interpolate.
    unsafe { gbsurf_pn_free(h) };
}

#[test]
fn pn_misuse_has_codes_and_messages() {
    let g = cap(3, 3);
    let (code, h) = interpolate(1, 9, &g, &g);
    assert_eq!((code, h), (GBSURF_ERR_COUNT, null_mut()));
    assert!(last().contains("the grid is 1 × 9"), "{}", last());
    let (code, _) = interpolate(3, 3, &g[..26], &g);
    assert_eq!(code, GBSURF_ERR_COUNT);
    assert!(last().contains("points has 26 values"), "{}", last());
    let mut bad = g.clone();
    bad[3 * 4 + 1] = f64::NAN;
    let (code, _) = interpolate(3, 3, &bad, &g);
    assert_eq!(code, GBSURF_ERR_NAN);
    assert!(last().contains("points[1][1] is not finite"), "{}", last());
    let mut zero = g.clone();
    zero[3 * 5..3 * 6].fill(0.0);
    let (code, _) = interpolate(3, 3, &g, &zero);
    assert_eq!(code, GBSURF_ERR_DEGENERATE);
    assert!(last().contains("normal [1][2] has length zero"), "{}", last());
    let mut out = null_mut();
    // SAFETY: NULL with a non-zero length is reported.
    assert_eq!(unsafe { gbsurf_pn_interpolate(3, 3, null(), 27, g.as_ptr(), 27, &mut out) }, GBSURF_ERR_NULL);

    let (code, h) = interpolate(3, 3, &g, &g);
    assert_eq!(code, GBSURF_OK);
    let mut x = [0.0; 3];
    let (mut du, mut dv, mut w) = (0, 0, 0);
    // SAFETY: 3-double buffers; bad indices and values are reported.
    unsafe {
        assert_eq!(gbsurf_pn_eval(h, 2, 0, 0.5, 0.5, x.as_mut_ptr(), null_mut()), GBSURF_ERR_INDEX);
        assert!(last().contains("patch [2][0] does not exist"), "{}", last());
        assert_eq!(gbsurf_pn_eval(h, 0, 0, 1.5, 0.5, x.as_mut_ptr(), null_mut()), GBSURF_ERR_INDEX);
        assert_eq!(gbsurf_pn_eval(h, 0, 0, f64::NAN, 0.5, x.as_mut_ptr(), null_mut()), GBSURF_ERR_NAN);
        assert_eq!(gbsurf_pn_offset_point(h, 0, 0, 0.5, 0.5, f64::INFINITY, x.as_mut_ptr()), GBSURF_ERR_NAN);
        assert_eq!(gbsurf_pn_eval(h, 0, 0, 0.5, 0.5, null_mut(), null_mut()), GBSURF_ERR_NULL);
        assert_eq!(gbsurf_pn_rational(h, 0, 0, f64::NAN, &mut du, &mut dv, null_mut(), 0, &mut w), GBSURF_ERR_NAN);
        assert_eq!(gbsurf_pn_patch_count(null(), &mut du, &mut dv), GBSURF_ERR_NULL);
        gbsurf_pn_free(h);
        gbsurf_pn_free(null_mut());
    }
}

/// `gbsurf_offset` gives the library's mesh and figures through the result handle.
#[test]
fn offset_gives_the_core_mesh_and_report() {
    let pm = gbsurf::mesh::generate::torus(12, 8, 2.0, 0.6).unwrap();
    let p: Vec<f64> = pm.positions.iter().flat_map(|v| v.to_array()).collect();
    let s: Vec<u32> = pm.faces.iter().map(|f| f.len() as u32).collect();
    let f: Vec<u32> = pm.faces.iter().flatten().map(|&i| i as u32).collect();
    let mut opts = std::mem::MaybeUninit::<GbsurfOptions>::uninit();
    // SAFETY: writable struct.
    assert_eq!(unsafe { gbsurf_options_init(opts.as_mut_ptr()) }, GBSURF_OK);
    // SAFETY: initialized above.
    let opts = unsafe { opts.assume_init() };
    let mut rep = GbsurfOffsetReport::default();
    let mut out = null_mut();
    // SAFETY: arrays with their lengths; writable outputs.
    let code = unsafe {
        gbsurf_offset(p.as_ptr(), p.len(), s.as_ptr(), s.len(), f.as_ptr(), f.len(), &opts, 0.1, 0, 1, &mut rep, &mut out)
    };
    assert_eq!(code, GBSURF_OK, "{}", last());
    let want = gbsurf::api::offset(
        &pm,
        &crate::options::read_options(&opts).unwrap(),
        &gbsurf::api::OffsetOptions { distance: 0.1, grid: 4, shell: true },
    )
    .unwrap();
    let (mut nv, mut nt) = (0usize, 0usize);
    // SAFETY: live handle.
    unsafe {
        assert_eq!(gbsurf_mesh_vertex_count(out, &mut nv), GBSURF_OK);
        assert_eq!(gbsurf_mesh_triangle_count(out, &mut nt), GBSURF_OK);
    }
    assert_eq!((nv, nt), (want.positions.len(), want.triangles.len()));
    assert_eq!(rep.pieces as usize, want.report.pieces);
    assert_eq!(rep.max_gap_pn, want.report.max_gap_pn);
    assert_eq!((rep.frame_seams as usize, rep.max_normal_angle_pn), (want.report.frame_seams, want.report.max_normal_angle_pn));
    // The torus's normals cover the sphere: both isotropic frames are used, so there are seams.
    assert!(rep.frame_seams > 0 && rep.max_normal_angle_pn <= 1e-9, "{rep:?}");
    assert_eq!((rep.closed, rep.two_manifold), (1, 1));
    // SAFETY: the handle from gbsurf_offset, freed once.
    unsafe { gbsurf_result_free(out) };
    // Bad distances and grids: typed codes, no handle.
    for (d, grid, code) in [(0.0, 4, GBSURF_ERR_INVALID_OPTION), (f64::NAN, 4, GBSURF_ERR_NAN), (0.1, 1, GBSURF_ERR_INVALID_OPTION), (0.1, 65, GBSURF_ERR_INVALID_OPTION)] {
        let mut out = 1usize as *mut GbsurfResult;
        // SAFETY: as above.
        let c = unsafe { gbsurf_offset(p.as_ptr(), p.len(), s.as_ptr(), s.len(), f.as_ptr(), f.len(), null(), d, grid, 0, null_mut(), &mut out) };
        assert_eq!(c, code, "{d} {grid}: {}", last());
        assert!(out.is_null());
        assert!(last().contains("--distance") || last().contains("--grid"), "{}", last());
    }
    // SAFETY: NULL out.
    let c = unsafe { gbsurf_offset(p.as_ptr(), p.len(), s.as_ptr(), s.len(), f.as_ptr(), f.len(), null(), 0.1, 4, 0, null_mut(), null_mut()) };
    assert_eq!(c, GBSURF_ERR_NULL);
}

/// The control points and offsets of every segment of `h` equal the core spline's, bit for bit.
fn same_as_core(h: *mut GbsurfPhSpline, want: &PlanarPhSpline, d: f64) {
    let (mut n, mut closed) = (0usize, 9u32);
    // SAFETY: live handle, writable outputs.
    assert_eq!(unsafe { gbsurf_ph_spline_segment_count(h, &mut n, &mut closed) }, GBSURF_OK);
    assert_eq!((n, closed), (want.segments.len(), u32::from(want.closed)));
    for (k, seg) in want.segments.iter().enumerate() {
        let mut pts = [0.0; 12];
        // SAFETY: room for 12 doubles.
        assert_eq!(unsafe { gbsurf_ph_spline_control_points(h, k, pts.as_mut_ptr()) }, GBSURF_OK);
        let cp: Vec<f64> = seg.control_points().iter().flat_map(|p| p.to_array()).collect();
        assert_eq!(pts.to_vec(), cp);
        let (mut op, mut ow, mut cusps, mut nc) = ([0.0; 20], [0.0; 10], [0.0; 8], 99usize);
        // SAFETY: room per the contract.
        let code = unsafe { gbsurf_ph_spline_offset(h, k, d, op.as_mut_ptr(), ow.as_mut_ptr(), cusps.as_mut_ptr(), 8, &mut nc) };
        assert_eq!(code, GBSURF_OK, "{}", last());
        let o = seg.offset(d).unwrap();
        assert_eq!(op.to_vec(), o.points.iter().flat_map(|p| p.to_array()).collect::<Vec<_>>());
        assert_eq!(ow.to_vec(), o.weights);
        assert_eq!(&cusps[..nc], &o.cusps[..]);
    }
    let (mut op, mut ow, mut nc) = ([0.0; 20], [0.0; 10], 0usize);
    // SAFETY: as above; segment n does not exist.
    let code = unsafe { gbsurf_ph_spline_offset(h, n, d, op.as_mut_ptr(), ow.as_mut_ptr(), null_mut(), 0, &mut nc) };
    assert_eq!(code, GBSURF_ERR_INDEX);
    assert!(last().contains(&format!("segment {n} does not exist")), "{}", last());
}

#[test]
fn ph_spline_gives_the_core_numbers() {
    let pts = [0.0, 0.0, 1.0, 1.0, 2.0, 0.0, 3.0, 1.0];
    let tans = [1.0, 1.0, 1.0, 0.0, 1.0, -1.0, 1.0, 1.0];
    let v = |f: &[f64]| f.chunks(2).map(|p| DVec2::new(p[0], p[1])).collect::<Vec<_>>();
    let mut h = null_mut();
    // SAFETY: pointer/length pairs, writable out.
    assert_eq!(unsafe { gbsurf_ph_spline_hermite(pts.as_ptr(), 8, tans.as_ptr(), 8, &mut h) }, GBSURF_OK);
    same_as_core(h, &PlanarPhSpline::hermite(&v(&pts), &v(&tans)).unwrap(), 0.1);
    // SAFETY: handle from gbsurf_ph_spline_hermite.
    unsafe { gbsurf_ph_spline_free(h) };
    for closed in [0u32, 1] {
        let mut h = null_mut();
        // SAFETY: as above.
        assert_eq!(unsafe { gbsurf_ph_spline_c2(pts.as_ptr(), 8, closed, &mut h) }, GBSURF_OK, "{}", last());
        let want = if closed == 1 {
            PlanarPhSpline::c2_closed(&v(&pts))
        } else {
            PlanarPhSpline::c2_open(&v(&pts), OpenEnds::CubicEndSpans)
        };
        same_as_core(h, &want.unwrap(), -0.05);
        // SAFETY: handle from gbsurf_ph_spline_c2.
        unsafe { gbsurf_ph_spline_free(h) };
    }
}

#[test]
fn ph_spline_misuse_has_codes_and_messages() {
    let pts = [0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
    let tans = [1.0, 0.0, 1.0, 0.0, 0.0, 0.0];
    let mut h = 1usize as *mut GbsurfPhSpline;
    // SAFETY: pointer/length pairs, writable out; every call fails and leaves `h` NULL.
    unsafe {
        let distinct = [0.0, 0.0, 1.0, 1.0, 2.0, 0.0];
        assert_eq!(gbsurf_ph_spline_hermite(distinct.as_ptr(), 6, tans.as_ptr(), 4, &mut h), GBSURF_ERR_COUNT);
        assert!(h.is_null());
        assert!(last().contains("gbsurf_ph_spline_hermite"), "{}", last());
        assert_eq!(gbsurf_ph_spline_hermite(pts.as_ptr(), 5, tans.as_ptr(), 5, &mut h), GBSURF_ERR_COUNT);
        assert_eq!(gbsurf_ph_spline_hermite(pts.as_ptr(), 4, tans.as_ptr(), 4, &mut h), GBSURF_OK);
        gbsurf_ph_spline_free(h);
        assert_eq!(gbsurf_ph_spline_hermite(pts.as_ptr(), 6, tans.as_ptr(), 6, &mut h), GBSURF_ERR_DEGENERATE);
        assert!(h.is_null());
        assert_eq!(gbsurf_ph_spline_c2(pts.as_ptr(), 6, 0, &mut h), GBSURF_ERR_DEGENERATE);
        assert_eq!(gbsurf_ph_spline_c2(pts.as_ptr(), 4, 1, &mut h), GBSURF_ERR_COUNT);
        let nan = [0.0, f64::NAN, 1.0, 0.0, 2.0, 1.0];
        assert_eq!(gbsurf_ph_spline_c2(nan.as_ptr(), 6, 0, &mut h), GBSURF_ERR_NAN);
        assert_eq!(gbsurf_ph_spline_c2(null(), 6, 0, &mut h), GBSURF_ERR_NULL);
        assert_eq!(gbsurf_ph_spline_c2(pts.as_ptr(), 6, 0, null_mut()), GBSURF_ERR_NULL);
        assert_eq!(gbsurf_ph_spline_segment_count(null(), null_mut(), null_mut()), GBSURF_ERR_NULL);
        gbsurf_ph_spline_free(null_mut());
    }
}

"""Exact offsets through the C ABI (cpp/include/gbsurf.h: `gbsurf_offset`, `gbsurf_ph5_*`): the
offset of a GB surface through PN pieces (docs/math/pn.md §11), and planar PH quintic Hermite
segments with their degree-9 rational offsets (docs/math/ph.md). Imports no `bpy`.

The signatures are declared in `native._SIGNATURES`; status codes become `native.GbsurfError`.
"""

import ctypes
from ctypes import POINTER, c_double, c_size_t, c_uint32

import numpy as np

from . import native

PH5_MAX_CUSPS = 8  # GBSURF_PH5_MAX_CUSPS
PH5_OFFSET_POINTS = 10  # GBSURF_PH5_OFFSET_POINTS


def _dp(a):
    return a.ctypes.data_as(POINTER(c_double))


def offset_mesh(positions, face_sizes, face_indices, options, distance, grid=0, shell=False):
    """`gbsurf_offset`: (positions (V,3) float64, triangles (T,3) uint32, report dict) of the
    offset at signed `distance` (negative inward) of the GB surface of a polygon mesh; `options`
    an `native.Options` (a patch method), `grid` 0 for the library's default."""
    lib = native.load()
    pos = np.ascontiguousarray(positions, dtype=np.float64).reshape(-1)
    sizes = np.ascontiguousarray(face_sizes, dtype=np.uint32).reshape(-1)
    idx = np.ascontiguousarray(face_indices, dtype=np.uint32).reshape(-1)
    rep = native.OffsetReport()
    handle = native._R()
    status = lib.gbsurf_offset(
        _dp(pos), pos.size, sizes.ctypes.data_as(POINTER(c_uint32)), sizes.size,
        idx.ctypes.data_as(POINTER(c_uint32)), idx.size, ctypes.byref(options),
        float(distance), int(grid), 1 if shell else 0, ctypes.byref(rep), ctypes.byref(handle))
    native._check(lib, status)
    try:
        p = native._view(lib, lib.gbsurf_mesh_positions, handle, c_double).reshape(-1, 3)
        t = native._view(lib, lib.gbsurf_mesh_triangles, handle, c_uint32).reshape(-1, 3)
    finally:
        lib.gbsurf_result_free(handle)
    return p, t, {name: getattr(rep, name) for name, _ in native.OffsetReport._fields_}


class Ph5Segment:
    """The chosen planar PH quintic Hermite interpolant of one segment (`gbsurf_ph5_hermite`,
    least absolute rotation index): its 6 Bezier control points (6,2), and `offset(d)`."""

    def __init__(self, p0, d0, p1, d1):
        lib = native.load()
        args = [np.ascontiguousarray(v, dtype=np.float64).reshape(2) for v in (p0, d0, p1, d1)]
        handle = native._P5()
        native._check(lib, lib.gbsurf_ph5_hermite(*(_dp(a) for a in args), ctypes.byref(handle)))
        self._lib, self._handle = lib, handle
        try:
            chosen = c_size_t()
            native._check(lib, lib.gbsurf_ph5_solutions(handle, None, ctypes.byref(chosen)))
            self.index = chosen.value
            pts = np.zeros(12)
            native._check(lib, lib.gbsurf_ph5_control_points(handle, self.index, _dp(pts)))
            self.control_points = pts.reshape(6, 2)
        except Exception:
            self.free()
            raise

    def offset(self, d):
        """(points (10,2), weights (10,), cusp parameters) of the exact offset at signed `d`
        (positive to the right of the direction of travel)."""
        lib = self._lib
        pts, w, cusps = np.zeros(2 * PH5_OFFSET_POINTS), np.zeros(PH5_OFFSET_POINTS), np.zeros(PH5_MAX_CUSPS)
        n = c_size_t()
        native._check(lib, lib.gbsurf_ph5_offset(
            self._handle, self.index, float(d), _dp(pts), _dp(w), _dp(cusps), cusps.size, ctypes.byref(n)))
        return pts.reshape(-1, 2), w, [float(c) for c in cusps[: n.value]]

    def free(self):
        if self._handle:
            self._lib.gbsurf_ph5_free(self._handle)
            self._handle = native._P5()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.free()


def _bernstein(degree, t):
    """(len(t), degree+1) Bernstein basis values."""
    t = np.asarray(t, dtype=np.float64).reshape(-1, 1)
    k = np.arange(degree + 1)
    binom = np.array([float(np.prod(np.arange(degree - j + 1, degree + 1)) / np.prod(np.arange(1, j + 1)))
                      for j in k])
    return binom * t ** k * (1.0 - t) ** (degree - k)


def bezier_eval(points, t):
    """Points of a Bezier curve (control points (n+1, dim)) at parameters t."""
    points = np.asarray(points, dtype=np.float64)
    return _bernstein(len(points) - 1, t) @ points


def bezier_derivative(points, t):
    points = np.asarray(points, dtype=np.float64)
    n = len(points) - 1
    return bezier_eval(n * np.diff(points, axis=0), t)


def rational_eval(points, weights, t):
    """Points of a rational Bezier curve (control points (n+1, dim), weights (n+1,)) at t."""
    points = np.asarray(points, dtype=np.float64)
    w = np.asarray(weights, dtype=np.float64)
    b = _bernstein(len(points) - 1, t)
    return (b @ (points * w[:, None])) / (b @ w)[:, None]

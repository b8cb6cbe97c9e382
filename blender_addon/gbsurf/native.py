"""ctypes loader of the gbsurf C ABI (libgbsurf.so, see cpp/include/gbsurf.h).

Where the library is looked for, first hit wins:
1. the environment variable GBSURF_LIB (a file path; when set, nothing else is tried),
2. `lib/libgbsurf.so` inside this add-on (placed there by scripts/build-addon),
3. `target/release/libgbsurf.so` of the source checkout this add-on lives in (development).

Every function gets its `argtypes`/`restype`; a non-zero status becomes a `GbsurfError` carrying
the status name and the library's thread-local message. This module imports no `bpy`, so it runs in
worker threads.
"""

import ctypes
import os
from ctypes import (
    POINTER,
    Structure,
    c_bool,
    c_char_p,
    c_double,
    c_float,
    c_size_t,
    c_uint32,
    c_uint8,
    c_uint64,
    c_void_p,
)

import numpy as np

ABI_VERSION = 5

# GBSURF_NOT_CHECKED: a report count that was not computed (read as None).
NOT_CHECKED = 2**64 - 1

METHODS = {"DUAL": 0, "TOPOLOGY": 1, "DOO_SABIN": 2, "CATMULL_CLARK": 3}
TWISTS = {"NONE": 0, "APPROX": 1, "INTERP": 2}
MIDDLES = {"SEED": 0, "FAIR": 1}
WEIGHTS = {"SQUARED": 0, "LINEAR": 1}
# GBSURF_LAYOUT_*: output faces (the option is `face_layout` here: `layout` is taken by Blender's
# operators and panels).
LAYOUTS = {"TRIANGLES": 0, "QUADS": 1}

ERR_CANCELLED = 7
PATCH_GB = 0


class GbsurfError(Exception):
    """A failed library call: `code` (status), `status` (its name) and the library's message."""

    def __init__(self, code, status, message):
        super().__init__(message or status)
        self.code = code
        self.status = status
        self.message = message


class LibraryMissing(GbsurfError):
    """The native library was not found or could not be loaded."""

    def __init__(self, message):
        super().__init__(-1, "LIBRARY_MISSING", message)


class Cancelled(GbsurfError):
    """The progress callback asked to stop."""


class Options(Structure):
    _fields_ = [
        ("struct_size", c_uint32),
        ("method", c_uint32),
        ("resolution", c_uint32),
        ("twist", c_uint32),
        ("weights", c_uint32),
        ("levels", c_uint32),
        ("best_plane", c_uint32),
        ("face_layout", c_uint32),
        ("fullness", c_double),
        ("tile_depth", c_double),
        ("mid_scale", c_double),
        ("max_memory_mb", c_uint64),
        ("middle", c_uint32),
    ]


class Report(Structure):
    _fields_ = [
        ("struct_size", c_uint32),
        ("method", c_uint32),
        ("closed", c_uint32),
        ("two_manifold", c_uint32),
        ("patches", c_uint64),
        ("vertices", c_uint64),
        ("triangles", c_uint64),
        ("boundary_edges", c_uint64),
        ("duplicate_vertices", c_uint64),
        ("zero_area_triangles", c_uint64),
        ("resolution", c_uint64),
        ("input_vertices", c_uint64),
        ("input_faces", c_uint64),
        ("warnings", c_uint64),
        ("max_g1_deg", c_double),
        ("mean_g1_deg", c_double),
        ("max_boundary_gap", c_double),
        ("seconds", c_double),
        # Second version: validity, quads.
        ("valid", c_uint32),
        ("input_closed", c_uint32),
        ("folds", c_uint64),
        ("fold_sites", c_uint64),
        ("flipped_triangles", c_uint64),
        ("self_intersections", c_uint64),
        ("input_self_intersections", c_uint64),
        ("sharp_edges", c_uint64),
        ("quads", c_uint64),
        ("max_abs_mean_curvature_times_diagonal", c_double),
    ]


class OffsetReport(Structure):
    """GbsurfOffsetReport (figures of `gbsurf_offset`; see offset_native.py)."""

    _fields_ = [(n, c_uint64) for n in ("pieces", "singular_pieces")] + [
        (n, c_double) for n in ("max_fit_error", "max_normal_residual", "max_offset_error", "max_gap", "max_gap_pn")] + [
        ("unmatched_points", c_uint64), ("cusps", c_uint64), ("closed", c_uint32), ("two_manifold", c_uint32), ("seconds", c_double),
        ("frame_seams", c_uint64), ("max_normal_angle_pn", c_double)]


class Creases(Structure):
    """GbsurfCreases: edge pairs with sharpness and corner vertices with sharpness, in [0, 1]."""

    _fields_ = [
        ("edge_vertices", POINTER(c_uint32)),
        ("edge_sharpness", POINTER(c_double)),
        ("edge_count", c_size_t),
        ("vertices", POINTER(c_uint32)),
        ("vertex_sharpness", POINTER(c_double)),
        ("vertex_count", c_size_t),
    ]


class _Result(Structure):
    """Opaque handle type (only used through pointers)."""


ProgressFn = ctypes.CFUNCTYPE(c_bool, c_float, c_void_p)

_R = POINTER(_Result)
_Ph5 = type("_Ph5", (Structure,), {"__doc__": "Opaque GbsurfPh5."})
_P5 = POINTER(_Ph5)
_PD = POINTER(POINTER(c_double))
_PU = POINTER(POINTER(c_uint32))
_PB = POINTER(POINTER(c_uint8))
_S = POINTER(c_size_t)

# name: (restype, argtypes); a restype of c_uint32 means a status code.
_SIGNATURES = {
    "gbsurf_version": (c_char_p, []),
    "gbsurf_abi_version": (c_uint32, []),
    "gbsurf_last_error_message": (c_char_p, []),
    "gbsurf_status_name": (c_char_p, [c_uint32]),
    "gbsurf_options_init": (c_uint32, [POINTER(Options)]),
    "gbsurf_options_validate": (c_uint32, [POINTER(Options)]),
    "gbsurf_convert": (
        c_uint32,
        [
            POINTER(c_double), c_size_t,
            POINTER(c_uint32), c_size_t,
            POINTER(c_uint32), c_size_t,
            POINTER(Options), ProgressFn, c_void_p, POINTER(_R),
        ],
    ),
    "gbsurf_convert_creased": (
        c_uint32,
        [
            POINTER(c_double), c_size_t,
            POINTER(c_uint32), c_size_t,
            POINTER(c_uint32), c_size_t,
            POINTER(Creases),
            POINTER(Options), ProgressFn, c_void_p, POINTER(_R),
        ],
    ),
    "gbsurf_result_free": (None, [_R]),
    "gbsurf_mesh_vertex_count": (c_uint32, [_R, _S]),
    "gbsurf_mesh_triangle_count": (c_uint32, [_R, _S]),
    "gbsurf_mesh_positions": (c_uint32, [_R, _PD, _S]),
    "gbsurf_mesh_normals": (c_uint32, [_R, _PD, _S]),
    "gbsurf_mesh_triangles": (c_uint32, [_R, _PU, _S]),
    "gbsurf_mesh_quads": (c_uint32, [_R, _PU, _S]),
    "gbsurf_mesh_edges": (c_uint32, [_R, _PU, _S]),
    "gbsurf_mesh_corner_edges": (c_uint32, [_R, _PU, _S]),
    "gbsurf_mesh_face_corner": (c_uint32, [_R, _PU, _S]),
    "gbsurf_mesh_cage_corner": (c_uint32, [_R, _PU, _S]),
    "gbsurf_mesh_cage_coords": (c_uint32, [_R, _PD, _S]),
    "gbsurf_mesh_cage_loop_corner": (c_uint32, [_R, _PU, _S]),
    "gbsurf_mesh_triangle_patch": (c_uint32, [_R, _PU, _S]),
    "gbsurf_mesh_patch_index": (c_uint32, [_R, _PU, _S]),
    "gbsurf_mesh_mean_curvature": (c_uint32, [_R, _PD, _S]),
    "gbsurf_mesh_gaussian_curvature": (c_uint32, [_R, _PD, _S]),
    "gbsurf_mesh_g1_deviation": (c_uint32, [_R, _PD, _S]),
    "gbsurf_mesh_fold": (c_uint32, [_R, _PB, _S]),
    "gbsurf_patch_count": (c_uint32, [_R, _S]),
    "gbsurf_patch_kind": (c_uint32, [_R, c_size_t, POINTER(c_uint32)]),
    "gbsurf_patch_sides": (c_uint32, [_R, c_size_t, _S]),
    "gbsurf_patch_degree": (c_uint32, [_R, c_size_t, c_size_t, _S, _S]),
    "gbsurf_patch_ribbon_points": (c_uint32, [_R, c_size_t, c_size_t, _PD, _S]),
    "gbsurf_patch_center": (c_uint32, [_R, c_size_t, POINTER(c_double)]),
    "gbsurf_curve_count": (c_uint32, [_R, _S]),
    "gbsurf_curve_points": (c_uint32, [_R, c_size_t, _PD, _S]),
    "gbsurf_curve_cubic_points": (c_uint32, [_R, c_size_t, _PD, _S]),
    "gbsurf_control_net_positions": (c_uint32, [_R, _PD, _S]),
    "gbsurf_control_net_face_sizes": (c_uint32, [_R, _PU, _S]),
    "gbsurf_control_net_face_indices": (c_uint32, [_R, _PU, _S]),
    "gbsurf_control_net_edges": (c_uint32, [_R, _PU, _S]),
    "gbsurf_control_net_patch_index": (c_uint32, [_R, _PU, _S]),
    "gbsurf_warning_count": (c_uint32, [_R, _S]),
    "gbsurf_warning_message": (c_uint32, [_R, c_size_t, POINTER(c_char_p)]),
    "gbsurf_result_report": (c_uint32, [_R, POINTER(Report)]),
    "gbsurf_cage_loop_values": (c_uint32, [POINTER(c_uint32), c_size_t, POINTER(c_float), c_size_t, c_size_t, POINTER(c_uint32), c_size_t,
                                           POINTER(c_uint32), c_size_t, POINTER(c_double), c_size_t, POINTER(c_float), c_size_t]),
    # Exact offsets (wrapped in offset_native.py).
    "gbsurf_offset": (c_uint32, [POINTER(c_double), c_size_t, POINTER(c_uint32), c_size_t, POINTER(c_uint32),
                                 c_size_t, POINTER(Options), c_double, c_size_t, c_uint32, POINTER(OffsetReport), POINTER(_R)]),
    "gbsurf_ph5_hermite": (c_uint32, [POINTER(c_double)] * 4 + [POINTER(_P5)]),
    "gbsurf_ph5_free": (None, [_P5]),
    "gbsurf_ph5_solutions": (c_uint32, [_P5, _S, _S]),
    "gbsurf_ph5_control_points": (c_uint32, [_P5, c_size_t, POINTER(c_double)]),
    "gbsurf_ph5_offset": (c_uint32, [_P5, c_size_t, c_double, POINTER(c_double), POINTER(c_double),
                                     POINTER(c_double), c_size_t, _S]),
}

_lib = None
_lib_path = None


def candidate_paths():
    """The paths tried, in order (see the module doc)."""
    env = os.environ.get("GBSURF_LIB")
    if env:
        return [env]
    here = os.path.dirname(os.path.abspath(__file__))
    return [
        os.path.join(here, "lib", "libgbsurf.so"),
        os.path.normpath(os.path.join(here, "..", "..", "target", "release", "libgbsurf.so")),
    ]


def library_path():
    """Path of the loaded library (None before the first successful `load`)."""
    return _lib_path


def load():
    """Loads (once) and returns the library; raises `LibraryMissing`."""
    global _lib, _lib_path
    if _lib is not None and (os.environ.get("GBSURF_LIB") in (None, "", _lib_path)):
        return _lib
    tried = []
    for path in candidate_paths():
        if not os.path.isfile(path):
            tried.append(f"{path} (not found)")
            continue
        try:
            lib = ctypes.CDLL(path)
        except OSError as e:
            tried.append(f"{path} ({e})")
            continue
        missing = [name for name in _SIGNATURES if not hasattr(lib, name)]
        if missing:
            tried.append(f"{path} (lacks {', '.join(missing[:3])}{'...' if len(missing) > 3 else ''})")
            continue
        for name, (restype, argtypes) in _SIGNATURES.items():
            fn = getattr(lib, name)
            fn.restype = restype
            fn.argtypes = argtypes
        abi = lib.gbsurf_abi_version()
        if abi != ABI_VERSION:
            tried.append(f"{path} (ABI version {abi}, this add-on needs {ABI_VERSION})")
            continue
        _lib, _lib_path = lib, path
        return lib
    raise LibraryMissing("gbsurf native library missing: tried " + "; ".join(tried))


def version():
    return load().gbsurf_version().decode()


def _check(lib, status):
    if status != 0:
        name = lib.gbsurf_status_name(status).decode()
        message = lib.gbsurf_last_error_message().decode("utf-8", "replace")
        cls = Cancelled if status == ERR_CANCELLED else GbsurfError
        raise cls(status, name, message)


_ENUMS = {"method": METHODS, "twist": TWISTS, "middle": MIDDLES, "weights": WEIGHTS, "face_layout": LAYOUTS}
# The `Options` fields that are Python values as they are (the others: enums, best_plane).
_PLAIN = {"resolution": int, "levels": int, "fullness": float, "tile_depth": float, "mid_scale": float, "max_memory_mb": int}
# The library options by their Python names (as the add-on's properties and keyword options).
OPTION_NAMES = ("method", "resolution", "fullness", "tile_depth", "twist", "mid_scale", "middle", "best_plane",
                "weights", "levels", "max_memory_mb", "face_layout")


def _init_options(lib):
    o = Options()
    _check(lib, lib.gbsurf_options_init(ctypes.byref(o)))
    if o.struct_size != ctypes.sizeof(Options):
        raise LibraryMissing(
            f"{_lib_path}: GbsurfOptions has {o.struct_size} bytes, this add-on expects "
            f"{ctypes.sizeof(Options)} (library and add-on from different versions)")
    return o


def library_defaults():
    """The default options, read from `gbsurf_options_init` (enum names as in the UI): the one
    definition of the defaults, used by the properties and by `make_options`."""
    o = _init_options(load())
    values = {}
    for name in OPTION_NAMES:
        raw = getattr(o, name)
        if name in _ENUMS:
            values[name] = next(k for k, v in _ENUMS[name].items() if v == raw)
        elif name == "best_plane":
            values[name] = bool(raw)
        else:
            values[name] = _PLAIN[name](raw)
    return values


def make_options(**overrides):
    """An `Options` struct initialized by the library (`gbsurf_options_init`) with only the
    values passed here changed (names as in `OPTION_NAMES`, enum names as in the UI), validated."""
    lib = load()
    o = _init_options(lib)
    unknown = set(overrides) - set(OPTION_NAMES)
    if unknown:
        raise GbsurfError(6, "GBSURF_ERR_INVALID_OPTION", f"unknown option(s): {', '.join(sorted(unknown))}")
    for name, value in overrides.items():
        if name in _ENUMS:
            try:
                value = _ENUMS[name][value]
            except KeyError:
                raise GbsurfError(6, "GBSURF_ERR_INVALID_OPTION", f"unknown {name} {value!r}") from None
        elif name == "best_plane":
            value = 1 if value else 0
        else:
            value = _PLAIN[name](value)
        setattr(o, name, value)
    _check(lib, lib.gbsurf_options_validate(ctypes.byref(o)))
    return o


class Conversion:
    """A conversion's data as numpy: the mesh arrays below are read-only views of the result's
    own memory, which stays alive as long as any of them does (`_Handle`); the curves, the
    control net and the patches are copies.

    positions (V,3) float64, normals (V,3), triangles (T,3) uint32, quads (Q,4) uint32 (quad
    layout; quad k is triangles 2k, 2k+1), faces (the quads when there are any, else the
    triangles), edges (E,2) uint32 (every edge of the faces once, smaller vertex first) and
    corner_edges (k·F,) uint32 (per face corner the edge to the next corner), face_patch (F,)
    uint32 (the patch or input face of each face), face_corner (F,)
    uint32 (the patch corner whose sector holds each face; empty for subdivision), cage_corner
    (F,2) uint32 (the cage face and the corner in it each face lies in; corner 0xFFFFFFFF for
    subdivision), cage_coords (4Q,2) or (3T,2) float64 (per face corner its bilinear
    coordinates in its cage corner, docs/math.md#cage-corners; empty for subdivision),
    cage_loop_corner (3T,2) uint32 (triangle layout: per face corner the cage corner its
    coordinates are in; empty otherwise, where a face's cage_corner serves its corners),
    patch_index (V,) uint32,
    mean_curvature, gaussian_curvature, g1_deviation (V,) float64 (degrees), fold (V,) uint8
    (1 on folded samples and the vertices of flipped triangles),
    curves: list of (3k+1,3) arrays, each curve's cubic Bezier chain (segment i = rows 3i..3i+3),
    control_net: dict of positions (N,3), face_sizes (F,), face_indices, edges (E,2), patch (N,)
    or None, patches: list of dicts {"kind", "center" (3,) or None, "ribbons": [(layers,
    degree+1, 3) arrays]}, report: dict, warnings: list of str.
    """


class _Handle:
    """Owns a result handle: it is freed when this object goes, i.e. after the last zero-copy
    view of it (each view's buffer holds a reference to its `_Handle`)."""

    def __init__(self, lib, handle):
        self._lib, self._handle = lib, handle

    def __del__(self):
        try:
            self._lib.gbsurf_result_free(self._handle)
        except Exception:  # interpreter shutdown: nothing left to free into
            pass


def _view(lib, fn, handle, ctype, *args, owner=None):
    """A result array as numpy: a copy, or with `owner` (a `_Handle`) a read-only view of the
    library's own memory that keeps the handle alive (no copy: 0.3 s of copying on a 40k-quad
    torus at r = 2)."""
    data = POINTER(ctype)()
    n = c_size_t()
    _check(lib, fn(handle, *args, ctypes.byref(data), ctypes.byref(n)))
    dtype = {c_double: np.float64, c_uint8: np.uint8}.get(ctype, np.uint32)
    if n.value == 0:
        return np.zeros(0, dtype=dtype)
    if owner is None:
        return np.ctypeslib.as_array(data, shape=(n.value,)).copy()
    buf = (ctype * n.value).from_address(ctypes.addressof(data.contents))
    buf._owner = owner
    # A read-only buffer: the flag cannot be switched back on, so nothing writes library memory.
    return np.frombuffer(memoryview(buf).toreadonly(), dtype=dtype)


def _count(lib, fn, handle, *args):
    n = c_size_t()
    _check(lib, fn(handle, *args, ctypes.byref(n)))
    return n.value


def convert(positions, face_sizes, face_indices, options=None, progress=None,
            want_patches=False, want_curves=False, want_control_net=False, creases=None):
    """Converts a polygon mesh given as numpy arrays.

    positions: (V,3) or flat float64; face_sizes: (F,) uint32; face_indices: flat uint32.
    creases: None or (edge_vertices (E,2), edge_sharpness (E,), vertices (K,), vertex_sharpness
    (K,)) with sharpness in [0, 1] (see `mesh_io.read_creases`); both structures build them
    (the dual along closed sharp chains, docs/math.md#dual-creases); the subdivision methods ignore them.
    options: an `Options` (see `make_options`) or None for the defaults.
    progress: callable(fraction) -> bool (False cancels) or None.
    Raises `GbsurfError` (`Cancelled` when cancelled) with the library's message.
    """
    lib = load()
    pos = np.ascontiguousarray(positions, dtype=np.float64).reshape(-1)
    sizes = np.ascontiguousarray(face_sizes, dtype=np.uint32).reshape(-1)
    idx = np.ascontiguousarray(face_indices, dtype=np.uint32).reshape(-1)
    failure = []

    def trampoline(fraction, _user):
        if progress is None:
            return True
        try:
            return bool(progress(float(fraction)))
        except BaseException as e:  # never unwind into the library
            failure.append(e)
            return False

    cb = ProgressFn(trampoline)
    handle = _R()
    mesh_args = (
        pos.ctypes.data_as(POINTER(c_double)), pos.size,
        sizes.ctypes.data_as(POINTER(c_uint32)), sizes.size,
        idx.ctypes.data_as(POINTER(c_uint32)), idx.size,
    )
    rest = (ctypes.byref(options) if options is not None else None, cb, None, ctypes.byref(handle))
    if creases is None:
        status = lib.gbsurf_convert(*mesh_args, *rest)
    else:
        ev = np.ascontiguousarray(creases[0], dtype=np.uint32).reshape(-1)
        es = np.ascontiguousarray(creases[1], dtype=np.float64).reshape(-1)
        vv = np.ascontiguousarray(creases[2], dtype=np.uint32).reshape(-1)
        vs = np.ascontiguousarray(creases[3], dtype=np.float64).reshape(-1)
        if ev.size != 2 * es.size or vv.size != vs.size:
            raise ValueError("creases: need two edge vertices per edge sharpness and one sharpness per vertex")
        cr = Creases(
            ev.ctypes.data_as(POINTER(c_uint32)), es.ctypes.data_as(POINTER(c_double)), es.size,
            vv.ctypes.data_as(POINTER(c_uint32)), vs.ctypes.data_as(POINTER(c_double)), vs.size,
        )
        status = lib.gbsurf_convert_creased(*mesh_args, ctypes.byref(cr), *rest)
    if failure:
        if handle:
            lib.gbsurf_result_free(handle)
        raise failure[0]
    _check(lib, status)
    # The mesh arrays are views of the result; the handle is freed with the last of them.
    return _unpack(lib, handle, want_patches, want_curves, want_control_net, _Handle(lib, handle))


def cage_loop_values(face_sizes, values, face_corner, loop_corner, coords):
    """A cage attribute per cage face corner (`values` (sum face_sizes, k)) at the output's face
    corners, by the library's keep-corners rule (docs/math.md#cage-corners): `face_corner` (F,2)
    per output face, `loop_corner` (N,2) per loop or empty, `coords` (N,2) per loop. Returns (N, k)
    float32; loops with an unknown cage corner (0xFFFFFFFF) get 0. Raises `GbsurfError` for sizes
    that do not fit (a corner outside `face_sizes` names the loop and the corner)."""
    lib = load()
    sizes = np.ascontiguousarray(face_sizes, dtype=np.uint32).reshape(-1)
    vals = np.asarray(values, dtype=np.float32)
    k = vals.shape[1] if vals.ndim == 2 else 1
    vals = np.ascontiguousarray(vals.reshape(-1))
    fc = np.ascontiguousarray(face_corner, dtype=np.uint32).reshape(-1)
    lc = np.ascontiguousarray(loop_corner if loop_corner is not None else (), dtype=np.uint32).reshape(-1)
    st = np.ascontiguousarray(coords, dtype=np.float64).reshape(-1)
    out = np.empty((st.size // 2, k), dtype=np.float32)
    u32 = POINTER(c_uint32)
    _check(lib, lib.gbsurf_cage_loop_values(
        sizes.ctypes.data_as(u32), sizes.size, vals.ctypes.data_as(POINTER(c_float)), vals.size, k,
        fc.ctypes.data_as(u32), fc.size, lc.ctypes.data_as(u32), lc.size,
        st.ctypes.data_as(POINTER(c_double)), st.size, out.ctypes.data_as(POINTER(c_float)), out.size))
    return out


def _unpack(lib, h, want_patches, want_curves, want_control_net, owner=None):
    c = Conversion()
    c.positions = _view(lib, lib.gbsurf_mesh_positions, h, c_double, owner=owner).reshape(-1, 3)
    c.normals = _view(lib, lib.gbsurf_mesh_normals, h, c_double, owner=owner).reshape(-1, 3)
    c.triangles = _view(lib, lib.gbsurf_mesh_triangles, h, c_uint32, owner=owner).reshape(-1, 3)
    c.quads = _view(lib, lib.gbsurf_mesh_quads, h, c_uint32, owner=owner).reshape(-1, 4)
    c.faces = c.quads if len(c.quads) else c.triangles
    c.edges = _view(lib, lib.gbsurf_mesh_edges, h, c_uint32, owner=owner).reshape(-1, 2)
    c.corner_edges = _view(lib, lib.gbsurf_mesh_corner_edges, h, c_uint32, owner=owner)
    c.face_corner = _view(lib, lib.gbsurf_mesh_face_corner, h, c_uint32, owner=owner)
    c.cage_corner = _view(lib, lib.gbsurf_mesh_cage_corner, h, c_uint32, owner=owner).reshape(-1, 2)
    c.cage_coords = _view(lib, lib.gbsurf_mesh_cage_coords, h, c_double, owner=owner).reshape(-1, 2)
    c.cage_loop_corner = _view(lib, lib.gbsurf_mesh_cage_loop_corner, h, c_uint32, owner=owner).reshape(-1, 2)
    triangle_patch = _view(lib, lib.gbsurf_mesh_triangle_patch, h, c_uint32, owner=owner)
    c.face_patch = triangle_patch[::2] if len(c.quads) else triangle_patch
    c.patch_index = _view(lib, lib.gbsurf_mesh_patch_index, h, c_uint32, owner=owner)
    c.mean_curvature = _view(lib, lib.gbsurf_mesh_mean_curvature, h, c_double, owner=owner)
    c.gaussian_curvature = _view(lib, lib.gbsurf_mesh_gaussian_curvature, h, c_double, owner=owner)
    c.g1_deviation = _view(lib, lib.gbsurf_mesh_g1_deviation, h, c_double, owner=owner)
    c.fold = _view(lib, lib.gbsurf_mesh_fold, h, c_uint8, owner=owner)
    rep = Report()
    rep.struct_size = ctypes.sizeof(Report)
    _check(lib, lib.gbsurf_result_report(h, ctypes.byref(rep)))
    c.report = {name: getattr(rep, name) for name, _ in Report._fields_ if name != "struct_size"}
    # The cage is checked only when the output self-intersects (GbsurfReport docs).
    if c.report["input_self_intersections"] == NOT_CHECKED:
        c.report["input_self_intersections"] = None
    c.warnings = []
    for i in range(_count(lib, lib.gbsurf_warning_count, h)):
        msg = c_char_p()
        _check(lib, lib.gbsurf_warning_message(h, i, ctypes.byref(msg)))
        c.warnings.append(msg.value.decode("utf-8", "replace"))
    c.curves = []
    if want_curves:
        for i in range(_count(lib, lib.gbsurf_curve_count, h)):
            c.curves.append(_view(lib, lib.gbsurf_curve_cubic_points, h, c_double, i).reshape(-1, 3))
    c.control_net = None
    if want_control_net:
        c.control_net = {
            "positions": _view(lib, lib.gbsurf_control_net_positions, h, c_double).reshape(-1, 3),
            "face_sizes": _view(lib, lib.gbsurf_control_net_face_sizes, h, c_uint32),
            "face_indices": _view(lib, lib.gbsurf_control_net_face_indices, h, c_uint32),
            "edges": _view(lib, lib.gbsurf_control_net_edges, h, c_uint32).reshape(-1, 2),
            "patch": _view(lib, lib.gbsurf_control_net_patch_index, h, c_uint32),
        }
    c.patches = []
    if want_patches:
        for p in range(_count(lib, lib.gbsurf_patch_count, h)):
            kind = c_uint32()
            _check(lib, lib.gbsurf_patch_kind(h, p, ctypes.byref(kind)))
            center = None
            if kind.value == PATCH_GB:
                xyz = (c_double * 3)()
                _check(lib, lib.gbsurf_patch_center(h, p, xyz))
                center = np.array(xyz[:], dtype=np.float64)
            ribbons = []
            for s in range(_count(lib, lib.gbsurf_patch_sides, h, p)):
                d, l = c_size_t(), c_size_t()
                _check(lib, lib.gbsurf_patch_degree(h, p, s, ctypes.byref(d), ctypes.byref(l)))
                pts = _view(lib, lib.gbsurf_patch_ribbon_points, h, c_double, p, s)
                ribbons.append(pts.reshape(l.value, d.value + 1, 3))
            c.patches.append({"kind": kind.value, "center": center, "ribbons": ribbons})
    return c

"""The ctypes loader: library lookup, status codes as exceptions with the library's message."""

import ctypes
import re

import bpy
import numpy as np
import pytest

import helpers

CUBE_POS = np.array([[x, y, z] for z in (-1, 1) for y in (-1, 1) for x in (-1, 1)], float)
CUBE_FACES = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]


def native():
    return helpers.mesh_module().native


def flat(faces):
    return (np.array([len(f) for f in faces], np.uint32),
            np.array([i for f in faces for i in f], np.uint32))


def test_every_declared_function_has_a_signature():
    lib = native().load()
    for name in native()._SIGNATURES:
        fn = getattr(lib, name)
        assert fn.argtypes is not None
    assert native().load().gbsurf_abi_version() == native().ABI_VERSION


def _header():
    """cpp/include/gbsurf.h without comments."""
    text = (helpers.ROOT / "cpp" / "include" / "gbsurf.h").read_text()
    return re.sub(r"//[^\n]*|/\*.*?\*/", "", text, flags=re.S)


def _ctype(n, decl):
    """The ctypes type of a C type from the header (`const` ignored)."""
    words = decl.replace("*", " * ").split()
    base = [w for w in words if w not in ("const", "*", "struct")]
    assert len(base) == 1, decl
    stars = words.count("*")
    if base[0] == "char" and stars >= 1:
        t, stars = ctypes.c_char_p, stars - 1
    elif base[0] == "void" and stars >= 1:
        t, stars = ctypes.c_void_p, stars - 1
    else:
        t = {
            "uint8_t": ctypes.c_uint8, "uint32_t": ctypes.c_uint32, "uint64_t": ctypes.c_uint64, "double": ctypes.c_double,
            "float": ctypes.c_float, "size_t": ctypes.c_size_t, "bool": ctypes.c_bool, "void": None,
            "GbsurfResult": n._Result, "GbsurfOptions": n.Options, "GbsurfReport": n.Report,
            "GbsurfProgressFn": n.ProgressFn, "GbsurfCreases": n.Creases,
            "GbsurfOffsetReport": n.OffsetReport, "GbsurfPh5": n._Ph5,
        }[base[0]]
    for _ in range(stars):
        t = ctypes.POINTER(t)
    return t


def test_ctypes_structs_match_the_header():
    """The ctypes structs are hand copies of the generated header's: same fields, types, order."""
    n = native()
    structs = {name: body for body, name in re.findall(r"typedef struct \{(.*?)\} (\w+);", _header(), re.S)}
    for name, cls in (("GbsurfOptions", n.Options), ("GbsurfReport", n.Report), ("GbsurfCreases", n.Creases),
                      ("GbsurfOffsetReport", n.OffsetReport)):
        fields = re.findall(r"([\w ]+?\s*\**)\s*(\w+);", structs[name])
        # The one renamed field: `layout` is taken by Blender's operators, so the add-on calls
        # the option `face_layout` (same type and position).
        renamed = {("GbsurfOptions", "layout"): "face_layout"}
        assert [(renamed.get((name, f), f), _ctype(n, t)) for t, f in fields] == list(cls._fields_), name


def test_not_checked_is_the_header_sentinel():
    """`native.NOT_CHECKED` (a report count not computed, read as None) is GBSURF_NOT_CHECKED."""
    m = re.search(r"#define GBSURF_NOT_CHECKED (\d+)ull", _header())
    assert m and int(m.group(1)) == native().NOT_CHECKED == 2**64 - 1


def test_ctypes_signatures_match_the_header():
    """Every function the add-on declares exists in the header with the same argument and
    result types."""
    n = native()
    decls = {name: (ret, args) for ret, name, args in
             re.findall(r"^([\w ]+?\**)\s*(gbsurf_\w+)\((.*?)\);", _header(), re.S | re.M)}
    for name, (restype, argtypes) in n._SIGNATURES.items():
        assert name in decls, f"{name} is not in gbsurf.h"
        ret, args = decls[name]
        params = [] if args.strip() == "void" else [a.strip() for a in args.split(",")]
        # Drop the parameter name: the last word (after any '*').
        types = [re.sub(r"\w+$", "", p).strip() for p in params]
        assert _ctype(n, ret) == restype, name
        assert [_ctype(n, t) for t in types] == list(argtypes), name


def test_defaults_come_from_the_library():
    """`make_options()` is `gbsurf_options_init` unchanged; the properties' defaults are the
    library's."""
    n = native()
    lib = n.load()
    raw = n.Options()
    assert lib.gbsurf_options_init(ctypes.byref(raw)) == 0
    o = n.make_options()
    assert bytes(o) == bytes(raw)
    d = n.library_defaults()
    assert set(d) == set(n.OPTION_NAMES)
    assert (d["method"], d["twist"], d["middle"], d["weights"]) == ('DUAL', 'INTERP', 'SEED', 'SQUARED')
    assert (d["resolution"], d["levels"], d["best_plane"]) == (raw.resolution, raw.levels, True)
    assert (d["fullness"], d["tile_depth"], d["mid_scale"]) == (raw.fullness, raw.tile_depth, raw.mid_scale)
    op = bpy.ops.object.gbsurf_convert.get_rna_type().properties
    for name, value in d.items():
        default = op[name].default
        if isinstance(value, float):
            assert default == pytest.approx(value, rel=1e-7), name
        else:
            assert default == value, name
    with pytest.raises(n.GbsurfError, match="unknown option"):
        n.make_options(bogus=1)


def test_library_missing(monkeypatch, tmp_path):
    missing = tmp_path / "nowhere" / "libgbsurf.so"
    monkeypatch.setenv("GBSURF_LIB", str(missing))
    with pytest.raises(native().LibraryMissing) as e:
        native().load()
    assert str(missing) in str(e.value)
    not_a_lib = tmp_path / "libgbsurf.so"
    not_a_lib.write_text("not an ELF file")
    monkeypatch.setenv("GBSURF_LIB", str(not_a_lib))
    with pytest.raises(native().LibraryMissing):
        native().load()
    monkeypatch.delenv("GBSURF_LIB")
    assert native().load() is not None  # the bundled library again


def test_library_missing_operator_cancels(monkeypatch, tmp_path):
    monkeypatch.setenv("GBSURF_LIB", str(tmp_path / "missing.so"))
    helpers.add_primitive("cube")
    before = helpers.snapshot()
    with helpers.refused("library missing"):
        bpy.ops.object.gbsurf_convert()
    assert helpers.snapshot() == before


def test_options_are_validated():
    n = native()
    o = n.make_options(method="TOPOLOGY", resolution=5, twist="APPROX", weights="LINEAR")
    assert (o.method, o.resolution, o.twist, o.weights) == (1, 5, 1, 1)
    with pytest.raises(n.GbsurfError) as e:
        n.make_options(resolution=0)
    assert e.value.status == "GBSURF_ERR_INVALID_OPTION" and "resolution" in e.value.message
    with pytest.raises(n.GbsurfError) as e:
        n.make_options(fullness=1.5)
    assert "fullness" in e.value.message
    with pytest.raises(n.GbsurfError) as e:
        n.make_options(method="BOGUS")
    assert e.value.status == "GBSURF_ERR_INVALID_OPTION"


def test_input_errors_name_the_element():
    n = native()
    sizes, idx = flat(CUBE_FACES)
    pos = CUBE_POS.copy()
    pos[5, 1] = np.nan
    with pytest.raises(n.GbsurfError) as e:
        n.convert(pos, sizes, idx)
    assert e.value.status == "GBSURF_ERR_NAN" and "vertex 5" in e.value.message
    bad = idx.copy()
    bad[7] = 42
    with pytest.raises(n.GbsurfError) as e:
        n.convert(CUBE_POS, sizes, bad)
    assert e.value.status == "GBSURF_ERR_INDEX" and "face 1" in e.value.message
    with pytest.raises(n.GbsurfError) as e:
        n.convert(CUBE_POS, sizes[:-1], idx)
    assert e.value.status == "GBSURF_ERR_COUNT"
    # Non-manifold: a face repeated.
    s2, i2 = flat(CUBE_FACES + [CUBE_FACES[0]])
    with pytest.raises(n.GbsurfError) as e:
        n.convert(CUBE_POS, s2, i2)
    assert e.value.status == "GBSURF_ERR_INVALID_MESH"


def test_cancel_from_progress_and_exceptions_in_callback():
    n = native()
    sizes, idx = flat(CUBE_FACES)
    with pytest.raises(n.Cancelled):
        n.convert(CUBE_POS, sizes, idx, progress=lambda f: False)

    class Boom(Exception):
        pass

    def boom(f):
        raise Boom("from the callback")

    with pytest.raises(Boom):
        n.convert(CUBE_POS, sizes, idx, progress=boom)


def test_convert_cube_arrays():
    n = native()
    sizes, idx = flat(CUBE_FACES)
    seen = []
    c = n.convert(CUBE_POS, sizes, idx, n.make_options(resolution=4),
                  progress=lambda f: seen.append(f) or True, want_patches=True, want_curves=True)
    nv = len(c.positions)
    assert nv > 8 and c.positions.shape == (nv, 3) and c.normals.shape == (nv, 3)
    assert c.triangles.max() < nv
    for a in (c.patch_index, c.mean_curvature, c.gaussian_curvature, c.g1_deviation):
        assert a.shape == (nv,)
    assert np.allclose(np.linalg.norm(c.normals, axis=1), 1.0, atol=1e-9)
    assert seen and seen[-1] == pytest.approx(1.0) and seen == sorted(seen)
    assert c.report["closed"] == 1 and c.report["patches"] == len(c.patches) == 8
    assert all(p["center"] is not None and len(p["ribbons"]) == 3 for p in c.patches)
    assert len(c.curves) == 12 and all(cv.shape == (4, 3) for cv in c.curves)


def test_cancel_from_another_thread_like_the_modal_operator():
    """The interactive Convert runs the library in a worker thread and cancels through the
    progress callback when Esc is pressed on the main thread: the same contract, without UI."""
    import threading

    n = native()
    sizes, idx = flat(CUBE_FACES)
    started, cancel = threading.Event(), threading.Event()
    outcome = []

    def progress(f):
        started.set()
        cancel.wait(timeout=30)  # the "user" decides while the library waits in the callback
        return not cancel.is_set()

    def work():
        try:
            n.convert(CUBE_POS, sizes, idx, n.make_options(resolution=4), progress)
            outcome.append("finished")
        except n.Cancelled as e:
            outcome.append(e.status)

    t = threading.Thread(target=work)
    t.start()
    assert started.wait(timeout=30)
    cancel.set()  # "Esc"
    t.join(timeout=30)
    assert outcome == ["GBSURF_ERR_CANCELLED"]

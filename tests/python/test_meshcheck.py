"""Checks the mesh checker itself on small meshes with known defects."""

import subprocess
import sys
from pathlib import Path

import pytest

import meshcheck  # imports bpy before pymeshlab (see its docstring)

# Cube [-1, 1]^3, quads listed counter-clockwise seen from outside (outward normals).
CUBE_V = [
    (-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1),
    (-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1),
]
CUBE_QUADS = [
    (0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4),
    (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7),
]


def cube_triangles():
    return [t for a, b, c, d in CUBE_QUADS for t in ((a, b, c), (a, c, d))]


def grid(n):
    """Open n x n grid of unit squares in z = 0, two triangles each, normals +z."""
    v = [(i, j, 0.0) for j in range(n + 1) for i in range(n + 1)]
    f = []
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            b, c, d = a + 1, a + n + 2, a + n + 1
            f += [(a, b, c), (a, c, d)]
    return v, f


def write_obj(path: Path, vertices, faces) -> Path:
    lines = [f"v {x} {y} {z}" for x, y, z in vertices]
    lines += ["f " + " ".join(str(i + 1) for i in face) for face in faces]
    path.write_text("\n".join(lines) + "\n")
    return path


def write_ply(path: Path, vertices, faces) -> Path:
    head = [
        "ply", "format ascii 1.0", f"element vertex {len(vertices)}",
        "property float x", "property float y", "property float z",
        f"element face {len(faces)}", "property list uchar int vertex_indices", "end_header",
    ]
    body = [f"{x} {y} {z}" for x, y, z in vertices]
    body += [f"{len(face)} " + " ".join(map(str, face)) for face in faces]
    path.write_text("\n".join(head + body) + "\n")
    return path


def test_closed_cube_is_clean_with_volume_8(tmp_path):
    r = meshcheck.check_mesh(write_obj(tmp_path / "cube.obj", CUBE_V, cube_triangles()))
    assert (r.vertices, r.faces, r.edges) == (8, 12, 18)
    assert r.two_manifold and r.closed and r.coherently_oriented
    assert r.boundary_edges == 0
    assert r.self_intersecting_faces == r.zero_area_faces == r.duplicate_vertices == 0
    assert r.volume == pytest.approx(8.0, abs=1e-12)
    assert r.problems(expect_closed=True) == []


def test_quad_obj_and_ply_give_the_same_report(tmp_path):
    from_quads = meshcheck.check_mesh(write_obj(tmp_path / "q.obj", CUBE_V, CUBE_QUADS))
    from_ply = meshcheck.check_mesh(write_ply(tmp_path / "c.ply", CUBE_V, cube_triangles()))
    from_arrays = meshcheck.check_arrays(CUBE_V, cube_triangles())
    assert from_quads == from_ply == from_arrays
    assert from_quads.volume == pytest.approx(8.0, abs=1e-12)


def test_inverted_cube_is_coherent_with_negative_volume(tmp_path):
    inverted = [(a, c, b) for a, b, c in cube_triangles()]
    r = meshcheck.check_mesh(write_obj(tmp_path / "inv.obj", CUBE_V, inverted))
    assert r.closed and r.coherently_oriented
    assert r.volume == pytest.approx(-8.0, abs=1e-12)
    assert r.problems(expect_closed=True) == [
        "volume -8.0 not positive (faces point inward?)"
    ]


def test_one_flipped_triangle_breaks_coherence(tmp_path):
    faces = cube_triangles()
    a, b, c = faces[5]
    faces[5] = (a, c, b)
    r = meshcheck.check_mesh(write_obj(tmp_path / "flip.obj", CUBE_V, faces))
    assert r.two_manifold and r.boundary_edges == 0
    assert not r.coherently_oriented
    assert "orientation not coherent" in r.problems(expect_closed=True)


def test_open_grid_has_its_border_as_boundary(tmp_path):
    v, f = grid(3)
    r = meshcheck.check_mesh(write_obj(tmp_path / "grid.obj", v, f))
    assert r.boundary_edges == 12
    assert r.two_manifold and not r.closed and r.coherently_oriented
    assert r.volume is None
    assert r.problems(expect_closed=False) == []
    assert r.problems(expect_closed=True) == ["12 boundary edges"]


def test_duplicated_vertex_is_counted_and_opens_a_seam(tmp_path):
    v, f = grid(2)  # 9 vertices, centre vertex 4 used by all 8 triangles
    v.append(v[4])  # vertex 9 = copy of the centre, used by the two triangles of the last cell
    f = [tuple(9 if i == 4 else i for i in t) if k >= 6 else t for k, t in enumerate(f)]
    r = meshcheck.check_mesh(write_obj(tmp_path / "dup.obj", v, f))
    assert r.vertices == 10
    assert r.duplicate_vertices == 1
    assert r.boundary_edges > 8  # the split centre adds seam edges to the 8 border edges
    assert "1 duplicate vertices" in r.problems(expect_closed=False)


def test_crossing_triangles_are_self_intersecting():
    v = [(0, 0, 0), (2, 0, 0), (1, 2, 0), (1, 1, -1), (1, 1, 1), (1, -3, 0)]
    r = meshcheck.check_arrays(v, [(0, 1, 2), (3, 4, 5)])
    assert r.self_intersecting_faces == 2
    apart = [(x, y, z + 10 * (i >= 3)) for i, (x, y, z) in enumerate(v)]
    assert meshcheck.check_arrays(apart, [(0, 1, 2), (3, 4, 5)]).self_intersecting_faces == 0


def test_intersections_between_shells_are_told_from_those_within_one():
    # Two closed cubes passing through each other: separate shells, each clean on its own.
    tris = cube_triangles()
    shifted = [(x + 0.5, y + 0.3, z + 0.2) for x, y, z in CUBE_V]
    both_v = list(CUBE_V) + shifted
    both_f = tris + [(a + 8, b + 8, c + 8) for a, b, c in tris]
    r = meshcheck.check_arrays(both_v, both_f)
    assert r.connected_components == 2
    assert r.self_intersecting_faces > 0
    assert r.self_intersecting_faces_within_shells == 0
    assert r.problems(expect_closed=True) and not r.problems(expect_closed=True, shells_may_intersect=True)
    # One shell whose own faces cross (a triangle pair glued to a crossing pair) still counts.
    v = [(0, 0, 0), (2, 0, 0), (1, 2, 0), (1, 1, -1), (1, 1, 1), (1, -3, 0)]
    cross = meshcheck.check_arrays(v, [(0, 1, 2), (3, 4, 5), (1, 0, 5), (5, 4, 1)])
    assert cross.connected_components == 1
    assert cross.self_intersecting_faces_within_shells == cross.self_intersecting_faces > 0
    assert cross.problems(expect_closed=False, shells_may_intersect=True)


def test_zero_area_faces_are_counted():
    v = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (2, 0, 0), (1, 1e-20, 0)]
    r = meshcheck.check_arrays(v, [(0, 1, 2), (0, 1, 3), (0, 3, 4)])
    assert r.zero_area_faces == 2
    assert meshcheck.check_arrays(v, [(0, 1, 2)]).zero_area_faces == 0


def test_three_faces_on_one_edge_are_not_manifold():
    v = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1)]
    r = meshcheck.check_arrays(v, [(0, 1, 2), (1, 0, 3), (0, 1, 4)])
    assert not r.two_manifold
    assert r.non_manifold_edges >= 1
    assert not r.closed and r.volume is None


def test_cli_prints_one_json_report_per_file(tmp_path):
    path = write_obj(tmp_path / "cube.obj", CUBE_V, cube_triangles())
    out = subprocess.run(
        [sys.executable, meshcheck.__file__, str(path), str(path)],
        check=True, capture_output=True, text=True,
    ).stdout.splitlines()
    assert len(out) == 2 and '"volume": 8.0' in out[0] and '"closed": true' in out[0]


def test_importing_meshcheck_first_keeps_bpy_importable():
    # pymeshlab before bpy breaks `import bpy`; meshcheck must guard against that.
    code = "import meshcheck, bpy; print(bpy.app.version_string)"
    done = subprocess.run(
        [sys.executable, "-c", code], cwd=Path(meshcheck.__file__).parent,
        capture_output=True, text=True,
    )
    assert done.returncode == 0, done.stderr

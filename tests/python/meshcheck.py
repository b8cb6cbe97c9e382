"""Mesh sanity checks for gbsurf outputs, built on pymeshlab.

    report = check_mesh("out/demo/patch.obj")      # OBJ, PLY (anything pymeshlab loads)
    report = check_arrays(vertices, triangles)      # numpy (n,3) float, (m,3) int
    assert not report.problems(expect_closed=True), report.problems(expect_closed=True)

Command line: `.venv/bin/python tests/python/meshcheck.py FILE...` prints one JSON report per file.

IMPORT ORDER: bpy must be imported BEFORE pymeshlab in any process that uses both. With
pymeshlab first, `import bpy` fails with "undefined symbol: rtcGetSceneTraversable" (both ship
their own Embree; measured with bpy 5.0.1 + pymeshlab 2025.7.post1). This module therefore
imports bpy first whenever it is installed, so importing meshcheck early is always safe.

What comes from where (pymeshlab 2025.7.post1, whose filters return None and report counts only
through the mesh they change, hence the copies below):
- manifoldness, boundary edges, components, genus: `MeshSet.get_topological_measures()`;
- self-intersecting faces: `compute_selection_by_self_intersections_per_face` + selected count,
  over the whole mesh and within each connected component (shell) separately, after
  `generate_splitting_by_connected_components` (separate shells that pass through each other,
  like Suzanne's eyes and head, intersect without any shell intersecting itself);
- duplicate vertices: vertex count drop of `meshing_remove_duplicate_vertices` on a copy
  (exactly equal positions);
- volume: `get_geometric_measures()['mesh_volume']` (signed: positive for outward normals),
  reported only for closed two-manifold meshes;
- zero-area faces and coherent orientation: numpy on the mesh's vertex/face matrices (pymeshlab
  has no measure for them: `meshing_remove_null_faces` only drops exactly-zero faces and
  `meshing_re_orient_faces_coherently` reports nothing).
"""

from __future__ import annotations

import json
import sys
from dataclasses import asdict, dataclass
from pathlib import Path

try:  # see IMPORT ORDER above
    import bpy  # noqa: F401
except ImportError:
    pass

import numpy as np
import pymeshlab

#: Faces with area <= ZERO_AREA_REL_TOL * (bounding-box diagonal)^2 count as zero-area.
ZERO_AREA_REL_TOL = 1e-12


@dataclass(frozen=True)
class MeshReport:
    vertices: int
    faces: int
    edges: int
    connected_components: int
    #: True when every edge has at most two faces and every vertex a single fan of faces.
    two_manifold: bool
    non_manifold_edges: int
    non_manifold_vertices: int
    boundary_edges: int
    #: Two-manifold without boundary.
    closed: bool
    self_intersecting_faces: int
    #: Self-intersecting faces counted within each connected component (shell) on its own.
    self_intersecting_faces_within_shells: int
    zero_area_faces: int
    #: Vertices that have the exact position of an earlier vertex.
    duplicate_vertices: int
    #: No edge is traversed twice in the same direction by the faces using it.
    coherently_oriented: bool
    #: Signed enclosed volume (positive for outward orientation); None unless closed.
    volume: float | None

    def problems(self, expect_closed: bool, shells_may_intersect: bool = False) -> list[str]:
        """Human-readable list of everything wrong; empty for a clean mesh.

        `expect_closed`: a boundary counts as a problem (and the volume must be positive).
        `shells_may_intersect`: only intersections within one shell count (for inputs whose
        separate shells already pass through each other)."""
        out = []
        if not self.two_manifold:
            out.append(
                f"not two-manifold: {self.non_manifold_edges} edges, "
                f"{self.non_manifold_vertices} vertices"
            )
        if expect_closed and self.boundary_edges:
            out.append(f"{self.boundary_edges} boundary edges")
        if shells_may_intersect:
            if self.self_intersecting_faces_within_shells:
                out.append(
                    f"{self.self_intersecting_faces_within_shells} faces intersect their own shell"
                )
        elif self.self_intersecting_faces:
            out.append(f"{self.self_intersecting_faces} self-intersecting faces")
        if self.zero_area_faces:
            out.append(f"{self.zero_area_faces} zero-area faces")
        if self.duplicate_vertices:
            out.append(f"{self.duplicate_vertices} duplicate vertices")
        if not self.coherently_oriented:
            out.append("orientation not coherent")
        if expect_closed and self.closed and not (self.volume is not None and self.volume > 0):
            out.append(f"volume {self.volume} not positive (faces point inward?)")
        return out


def check_mesh(path: str | Path) -> MeshReport:
    """Loads `path` with pymeshlab (polygons are triangulated on load) and checks it."""
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(str(path))
    return _check(ms)


def check_arrays(vertices, triangles) -> MeshReport:
    """Checks a triangle mesh given as arrays: vertices (n, 3) floats, triangles (m, 3) indices."""
    ms = pymeshlab.MeshSet()
    ms.add_mesh(
        pymeshlab.Mesh(
            vertex_matrix=np.asarray(vertices, dtype=np.float64).reshape(-1, 3),
            face_matrix=np.asarray(triangles, dtype=np.int32).reshape(-1, 3),
        )
    )
    return _check(ms)


def _check(ms: pymeshlab.MeshSet) -> MeshReport:
    original = ms.current_mesh_id()
    mesh = ms.current_mesh()
    positions = mesh.vertex_matrix()
    triangles = mesh.face_matrix()
    vertex_count = mesh.vertex_number()

    topo = ms.get_topological_measures()
    two_manifold = bool(topo["is_mesh_two_manifold"])
    closed = two_manifold and topo["boundary_edges"] == 0
    volume = float(ms.get_geometric_measures()["mesh_volume"]) if closed else None

    ms.compute_selection_by_self_intersections_per_face()
    self_intersecting = mesh.selected_face_number()
    ms.set_selection_none()
    within_shells = self_intersecting
    if self_intersecting and topo["connected_components_number"] > 1:
        within_shells = _self_intersections_within_shells(ms, original)

    ms.generate_copy_of_current_mesh()
    ms.meshing_remove_duplicate_vertices()
    duplicates = vertex_count - ms.current_mesh().vertex_number()
    ms.delete_current_mesh()
    ms.set_current_mesh(original)

    return MeshReport(
        vertices=vertex_count,
        faces=len(triangles),
        edges=int(topo["edges_number"]),
        connected_components=int(topo["connected_components_number"]),
        two_manifold=two_manifold,
        non_manifold_edges=int(topo["non_two_manifold_edges"]),
        non_manifold_vertices=int(topo["non_two_manifold_vertices"]),
        boundary_edges=int(topo["boundary_edges"]),
        closed=closed,
        self_intersecting_faces=int(self_intersecting),
        self_intersecting_faces_within_shells=int(within_shells),
        zero_area_faces=_zero_area_faces(positions, triangles),
        duplicate_vertices=int(duplicates),
        coherently_oriented=_coherently_oriented(triangles),
        volume=volume,
    )


def _self_intersections_within_shells(ms: pymeshlab.MeshSet, original: int) -> int:
    """Self-intersecting faces of each connected component checked alone, summed."""
    before = set(_mesh_ids(ms))
    ms.generate_splitting_by_connected_components(delete_source_mesh=False)
    parts = [i for i in _mesh_ids(ms) if i not in before]
    total = 0
    for i in parts:
        ms.set_current_mesh(i)
        ms.compute_selection_by_self_intersections_per_face()
        total += ms.current_mesh().selected_face_number()
    for i in parts:
        ms.set_current_mesh(i)
        ms.delete_current_mesh()
    ms.set_current_mesh(original)
    return total


def _mesh_ids(ms: pymeshlab.MeshSet) -> list[int]:
    ids = []
    i = 0
    while len(ids) < ms.mesh_number():
        if ms.mesh_id_exists(i):
            ids.append(i)
        i += 1
    return ids


def _zero_area_faces(positions: np.ndarray, triangles: np.ndarray) -> int:
    if len(triangles) == 0:
        return 0
    diag = float(np.linalg.norm(positions.max(axis=0) - positions.min(axis=0)))
    p = positions[triangles]
    areas = 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
    return int(np.count_nonzero(areas <= ZERO_AREA_REL_TOL * diag * diag))


def _coherently_oriented(triangles: np.ndarray) -> bool:
    """Coherent iff no directed edge (a -> b) occurs in two faces."""
    if len(triangles) == 0:
        return True
    directed = np.concatenate(
        [triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]
    )
    return len(np.unique(directed, axis=0)) == len(directed)


def main(argv: list[str]) -> int:
    if not argv:
        print("usage: meshcheck.py FILE...", file=sys.stderr)
        return 2
    for path in argv:
        print(json.dumps({"file": path, **asdict(check_mesh(path))}))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

"""`gbsurf offset --shell` on the shared cube and torus, checked with MeshLab (meshcheck): the solid
between the GB surface and its exact offset is closed, two-manifold, coherently oriented with a
positive volume, free of self-intersections, and it has the two sheets of a shell.

The CLI binary: `GBSURF_BIN` if set (as scripts/bench_cli), else the newer of target/release/gbsurf
and target/debug/gbsurf of this repository (scripts/test builds the debug one in its cargo step).
The models: ../shared/models next to the repository (as the Rust tests use them).
"""

import json
import os
import subprocess
from pathlib import Path

import pytest

import meshcheck  # imports bpy before pymeshlab (see its docstring)

ROOT = Path(__file__).resolve().parents[2]
MODELS = ROOT.parent / "shared" / "models"


def gbsurf_bin() -> Path:
    env = os.environ.get("GBSURF_BIN")
    if env:
        return Path(env)
    built = [p for p in (ROOT / "target" / "release" / "gbsurf", ROOT / "target" / "debug" / "gbsurf") if p.is_file()]
    if not built:
        pytest.fail("no gbsurf binary: build it (cargo build -p gbsurf-cli) or set GBSURF_BIN")
    return max(built, key=lambda p: p.stat().st_mtime)


@pytest.mark.parametrize("model,method,distance", [
    ("cube.obj", "topology", 0.05), ("cube.obj", "dual", 0.05), ("cube.obj", "topology", -0.05),
    ("torus.obj", "topology", 0.05), ("torus.obj", "dual", -0.05)])
def test_offset_shell_is_a_closed_meshlab_valid_solid(tmp_path, model, method, distance):
    out, report = tmp_path / "shell.ply", tmp_path / "report.json"
    done = subprocess.run(
        [str(gbsurf_bin()), "offset", str(MODELS / model), "-o", str(out), "--distance", str(distance),
         "--method", method, "--resolution", "6", "--shell", "--report", str(report)],
        capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    r = json.loads(report.read_text())
    assert r["shell"] and r["closed"] and r["two_manifold"], r
    assert r["cusps"] == 0, r
    m = meshcheck.check_mesh(out)
    assert m.problems(expect_closed=True) == [], m
    assert m.closed and m.two_manifold and m.coherently_oriented and m.boundary_edges == 0, m
    assert m.self_intersecting_faces == 0, m
    # Two sheets (the surface and its offset), nothing else; the counts are the report's.
    assert m.connected_components == 2, m
    assert (m.vertices, m.faces) == (r["vertices"], r["triangles"]), (m, r)

"""Fixtures of the add-on tests: headless bpy 5.0.1, the add-on installed from its built zip.

- BLENDER_USER_RESOURCES points Blender's user folders at a temporary directory (scripts/test
  sets it; otherwise this file does), so the extension is installed there, never in ~/.config.
- The zip comes from GBSURF_ADDON_ZIP or is built once per session with scripts/build-addon.
- Every test starts from `read_factory_settings(use_empty=True)` with the add-on enabled.
- bpy is imported before pymeshlab (the other order fails to load).
"""

import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
if not os.environ.get("BLENDER_USER_RESOURCES"):
    os.environ["BLENDER_USER_RESOURCES"] = tempfile.mkdtemp(prefix="gbsurf-blender-")
os.environ.pop("GBSURF_LIB", None)  # the tests use the library inside the zip

import bpy  # noqa: E402  (before pymeshlab)
import addon_utils  # noqa: E402
import pytest  # noqa: E402

sys.path.insert(0, str(ROOT / "tests" / "python"))  # meshcheck.py

MODULE = "bl_ext.user_default.gbsurf"
METRICS = []  # lines for the terminal summary (Hausdorff distances, timings)


def build_zip():
    env_zip = os.environ.get("GBSURF_ADDON_ZIP")
    if env_zip:
        return Path(env_zip)
    out = subprocess.run(
        [str(ROOT / "scripts" / "build-addon")], cwd=ROOT, check=True,
        stdout=subprocess.PIPE, text=True).stdout
    return Path(out.strip().splitlines()[-1])


@pytest.fixture(scope="session")
def addon_zip():
    z = build_zip()
    assert z.is_file(), z
    return z


@pytest.fixture(scope="session")
def addon(addon_zip):
    """The add-on module, installed from the zip into the temporary user repository."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    result = bpy.ops.extensions.package_install_files(
        filepath=str(addon_zip), repo="user_default", enable_on_install=True)
    assert result == {'FINISHED'}, result
    mod = sys.modules.get(MODULE)
    assert mod is not None, "the installed extension was not imported"
    yield mod


def ensure_enabled():
    if not hasattr(bpy.types.Object, "gbsurf"):
        addon_utils.enable(MODULE, default_set=True)


@pytest.fixture(autouse=True)
def fresh_scene(request):
    """An empty factory scene with the add-on enabled (tests marked `no_addon` skip the install)."""
    if "no_addon" in request.keywords:
        bpy.ops.wm.read_factory_settings(use_empty=True)
        yield None
        return
    mod = request.getfixturevalue("addon")
    bpy.ops.wm.read_factory_settings(use_empty=True)
    ensure_enabled()
    yield mod


def pytest_configure(config):
    config.addinivalue_line("markers", "no_addon: the test does not need the installed add-on")


def pytest_terminal_summary(terminalreporter):
    if METRICS:
        terminalreporter.section("gbsurf add-on metrics")
        for line in METRICS:
            terminalreporter.write_line(line)

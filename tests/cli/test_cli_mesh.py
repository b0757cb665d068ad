"""``--mesh FILE``: a student's own mesh on the shading lab's turntable, as a user types it —
an OBJ the test writes, rendered; a mesh file that is not one, a scene without a turntable, a
missing file and the broken files fuzzing found each refused in one line (exit 2) before any
rendering."""

from __future__ import annotations

import base64
import json
import struct

import numpy as np
import pytest

from tests.helpers.cli import SMALL, run, usage_error

CUBE_OBJ = """# a unit cube
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 4 8 7 3
f 1 5 8 4
f 2 3 7 6
"""


def test_an_obj_of_yours_is_rendered_on_the_turntable(tmp_path):
    (tmp_path / "cube.obj").write_text(CUBE_OBJ)
    r = run("render", "shading", "--mesh", "cube.obj", "--size", SMALL, "--out", "mine.png",
            cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    from PIL import Image

    img = np.asarray(Image.open(tmp_path / "mine.png"))[..., :3].astype(int)
    assert np.ptp(img) > 20  # something lit, not only the background


def test_a_bad_mesh_file_is_one_line_and_nothing_is_written(tmp_path):
    (tmp_path / "junk.obj").write_bytes(b"\x00\x01 not a mesh \xff")
    r = run("render", "shading", "--mesh", "junk.obj", "--size", SMALL, "--out", "x.png",
            cwd=tmp_path)
    line = usage_error(r)
    assert "junk.obj" in line and "allowed" in line
    assert not (tmp_path / "x.png").exists()


def test_a_missing_mesh_and_a_wrong_extension_are_one_line(tmp_path):
    line = usage_error(run("render", "shading", "--mesh", "nope.obj", "--size", SMALL,
                           cwd=tmp_path))
    assert "nope.obj" in line
    (tmp_path / "model.fbx").write_text("x")
    line = usage_error(run("render", "shading", "--mesh", "model.fbx", "--size", SMALL,
                           cwd=tmp_path))
    assert ".obj" in line and ".glb" in line


def test_a_scene_without_a_turntable_refuses_a_mesh(tmp_path):
    (tmp_path / "cube.obj").write_text(CUBE_OBJ)
    line = usage_error(run("render", "sky", "--mesh", "cube.obj", "--size", SMALL,
                           cwd=tmp_path))
    assert "--mesh" in line and "shading" in line
    assert not list(tmp_path.glob("*.png"))


def test_a_pipe_named_like_a_mesh_is_refused_without_blocking(tmp_path):
    import os

    os.mkfifo(tmp_path / "pipe.obj")
    line = usage_error(run("render", "shading", "--mesh", "pipe.obj", "--size", SMALL,
                           cwd=tmp_path))
    assert "pipe.obj" in line and "regular file" in line


def _stl_claiming_more_triangles_than_it_holds() -> bytes:
    corners = np.random.default_rng(0).random((12, 3, 3)).astype("<f4")
    records = b"".join(bytes(12) + c.tobytes() + bytes(2) for c in corners)
    return b"x" * 80 + struct.pack("<I", 5) + records


def _gltf_view_past_its_buffer() -> bytes:
    data = "data:application/octet-stream;base64," + base64.b64encode(bytes(72)).decode()
    return json.dumps({"asset": {"version": "2.0"},
                       "buffers": [{"byteLength": 72, "uri": data}],
                       "bufferViews": [{"buffer": 0, "byteOffset": 24, "byteLength": 4000}]
                       }).encode()


#: inputs fuzzing found (issue 36), each as a user hands it over, and what its line says
FUZZED = [
    ("deep.gltf", b"[" * 100000 + b"]" * 100000, "nests its JSON more than 100 levels deep"),
    ("huge.obj", b"v 1e39 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "coordinate 1e+39 at line 1"),
    ("zero.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "vertex index 0 at line 4"),
    ("count.stl", _stl_claiming_more_triangles_than_it_holds(),
     "claims 5 triangles (binary STL header) but its 684 bytes hold 12"),
    ("view.gltf", _gltf_view_past_its_buffer(),
     "bufferView 0 ending at byte 4,024 of buffer 0's 72"),
]


@pytest.mark.parametrize("name, content, says", FUZZED, ids=[c[0] for c in FUZZED])
def test_fuzzed_mesh_files_are_one_line_without_warnings(tmp_path, name, content, says):
    """Each was a traceback-free but wrong answer before: an internal error (RecursionError),
    ten lines of numpy warnings, a silently invisible mesh, "not UTF-8 text",
    "(AssertionError)"."""
    (tmp_path / name).write_bytes(content)
    r = run("render", "shading", "--mesh", name, "--size", SMALL, "--out", "x.png",
            cwd=tmp_path)
    line = usage_error(r)
    assert line.startswith(f"natura: mesh file '{name}' ") and says in line, line
    assert ": allowed " in line and len(line) <= 200
    assert "Warning" not in r.stderr and "Error" not in line
    assert not (tmp_path / "x.png").exists()

"""Loading a user's own mesh (app/sim/mesh_files.py): OBJ, ascii and binary STL, glTF and GLB
files the tests write themselves (by hand and with trimesh's exporters) — triangle counts,
bounds, outward normals, flattened scene graphs — and one-line errors for what cannot be
loaded."""

from __future__ import annotations

import base64
import json
import re
import struct
import warnings

import numpy as np
import pytest

from app.errors import NaturaError
from app.sim import mesh_files
from app.sim.mesh_files import MeshFileError, fit, load_mesh
from app.sim.mesh_formats import STL_RECORD, read_obj
from tests.helpers.meshes import cube

pytestmark = pytest.mark.unit

trimesh = pytest.importorskip("trimesh")

TETRA = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
TETRA_FACES = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])  # outward


def check(m, triangles, lo, hi):
    assert m.triangle_count == triangles
    for a in (m.positions, m.normals, m.smooth_normals, m.uvs, m.tangents):
        assert np.isfinite(a).all()
    got_lo, got_hi = m.bounds()
    np.testing.assert_allclose(got_lo, lo, atol=1e-5)
    np.testing.assert_allclose(got_hi, hi, atol=1e-5)
    np.testing.assert_allclose(np.linalg.norm(m.normals, axis=1), 1, atol=1e-4)
    np.testing.assert_allclose(np.linalg.norm(m.tangents[:, :3], axis=1), 1, atol=1e-4)
    assert np.abs(np.einsum("ij,ij->i", m.normals, m.tangents[:, :3])).max() < 1e-4


def outward(m, centre):
    """Every triangle's winding and its vertex normals point away from ``centre`` (a convex
    solid)."""
    p = m.positions.astype(float)
    t = m.indices.astype(np.int64)
    fn = np.cross(p[t[:, 1]] - p[t[:, 0]], p[t[:, 2]] - p[t[:, 0]])
    away = p[t].mean(axis=1) - centre
    assert (np.einsum("ij,ij->i", fn, away) > 0).all()
    assert (np.einsum("ij,ij->i", m.normals[t].sum(axis=1), away) > 0).all()


def write_obj(path, p, faces, normals=False, objects=1, offset=(3.0, 0.0, 0.0)):
    lines = []
    for k in range(objects):
        lines.append(f"o part{k}")
        for v in p + np.asarray(offset) * k:
            lines.append("v {:.6f} {:.6f} {:.6f}".format(*v))
        base = k * len(p) + 1
        if normals:
            for v in p - p.mean(axis=0):
                n = v / np.linalg.norm(v)
                lines.append("vn {:.6f} {:.6f} {:.6f}".format(*n))
            lines += ["f " + " ".join(f"{i + base}//{i + base}" for i in f) for f in faces]
        else:
            lines += ["f " + " ".join(str(i + base) for i in f) for f in faces]
    path.write_text("\n".join(lines) + "\n")
    return path


def write_ascii_stl(path, p, faces):
    lines = ["solid test"]
    for f in faces:
        a, b, c = p[f]
        n = np.cross(b - a, c - a)
        n /= np.linalg.norm(n)
        lines += ["facet normal {:e} {:e} {:e}".format(*n), "  outer loop"]
        lines += ["    vertex {:e} {:e} {:e}".format(*v) for v in (a, b, c)]
        lines += ["  endloop", "endfacet"]
    lines.append("endsolid test")
    path.write_text("\n".join(lines) + "\n")
    return path


def write_binary_stl(path, p, faces, zero_normals=True):
    out = bytearray(b"binary stl written by the tests".ljust(80, b" "))
    out += struct.pack("<I", len(faces))
    for f in faces:
        tri = p[f].astype("<f4")
        out += struct.pack("<3f", 0, 0, 0) if zero_normals else np.zeros(3, "<f4").tobytes()
        out += tri.tobytes() + b"\x00\x00"
    path.write_bytes(bytes(out))
    return path


def write_gltf(path, nodes, scene_nodes):
    """A glTF with one tetrahedron mesh (embedded base64 buffer) used by ``nodes``."""
    pos = TETRA.astype("<f4")
    idx = TETRA_FACES.astype("<u2").reshape(-1)
    blob = idx.tobytes() + b"\x00\x00" * (len(idx) % 2) + pos.tobytes()
    off = len(blob) - pos.nbytes
    doc = {
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64,"
                     + base64.b64encode(blob).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": idx.nbytes,
                         "target": 34963},
                        {"buffer": 0, "byteOffset": off, "byteLength": pos.nbytes,
                         "target": 34962}],
        "accessors": [{"bufferView": 0, "componentType": 5123, "count": len(idx),
                       "type": "SCALAR"},
                      {"bufferView": 1, "componentType": 5126, "count": len(pos),
                       "type": "VEC3", "min": pos.min(0).tolist(), "max": pos.max(0).tolist()}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 1}, "indices": 0}]}],
        "nodes": nodes,
        "scenes": [{"nodes": scene_nodes}],
        "scene": 0,
    }
    path.write_text(json.dumps(doc))
    return path


# ---------------------------------------------------------------------------------------------
# files that load


def test_an_obj_cube_without_normals_is_faceted(tmp_path):
    p, f = cube(2.0)
    m = load_mesh(write_obj(tmp_path / "cube.obj", p, f))
    check(m, 12, [-1, -1, -1], [1, 1, 1])
    outward(m, np.zeros(3))
    assert m.vertex_count == 24 and m.name == "cube"
    n = m.normals[m.indices]
    assert np.abs(n - n[:, :1]).max() < 1e-6  # flat faces
    assert np.abs(m.normals - m.smooth_normals).max() > 0.5  # hard edges


def test_obj_normals_from_the_file_are_kept(tmp_path):
    p, f = cube(2.0)
    m = load_mesh(write_obj(tmp_path / "round.obj", p, f, normals=True))
    check(m, 12, [-1, -1, -1], [1, 1, 1])
    radial = m.positions / np.linalg.norm(m.positions, axis=1, keepdims=True)
    np.testing.assert_allclose(m.normals, radial, atol=1e-5)


def test_an_obj_with_several_objects_is_flattened(tmp_path):
    m = load_mesh(write_obj(tmp_path / "two.obj", TETRA, TETRA_FACES, objects=2))
    check(m, 8, [0, 0, 0], [4, 1, 1])


def test_an_ascii_stl_tetrahedron(tmp_path):
    m = load_mesh(write_ascii_stl(tmp_path / "tetra.stl", TETRA, TETRA_FACES))
    check(m, 4, [0, 0, 0], [1, 1, 1])
    outward(m, TETRA.mean(axis=0))
    assert m.vertex_count == 12  # every corner of a tetrahedron is hard
    np.testing.assert_allclose(m.smooth_normals[m.positions.sum(axis=1) == 0],
                               -np.ones((3, 3)) / np.sqrt(3), atol=1e-5)


def test_a_binary_stl_cube_ignores_its_zero_facet_normals(tmp_path):
    p, f = cube(1.0, centre=(0, 0.5, 0))
    m = load_mesh(write_binary_stl(tmp_path / "cube.stl", p, f))
    check(m, 12, [-0.5, 0, -0.5], [0.5, 1, 0.5])
    outward(m, np.array([0, 0.5, 0]))


@pytest.mark.parametrize("kind", ["stl", "stl_ascii", "obj", "glb"])
def test_trimesh_exports_load_back(tmp_path, kind):
    box = trimesh.creation.box((2.0, 1.0, 0.5))
    ext = "stl" if kind.startswith("stl") else kind
    path = tmp_path / f"box_{kind}.{ext}"
    box.export(path, file_type=kind)
    m = load_mesh(path)
    check(m, 12, [-1, -0.5, -0.25], [1, 0.5, 0.25])
    outward(m, np.zeros(3))


def test_a_gltf_scene_graph_is_flattened_with_its_transforms(tmp_path):
    nodes = [{"mesh": 0},  # at the origin
             {"translation": [2, 0, 0], "children": [2]},  # a parent moving its child
             {"mesh": 0, "scale": [2, 2, 2]},  # child: [2, 4] × [0, 2] × [0, 2]
             {"mesh": 0, "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, -3, 1]}]
    m = load_mesh(write_gltf(tmp_path / "scene.gltf", nodes, [0, 1, 3]))
    check(m, 12, [0, 0, -3], [4, 2, 2])  # three instances of the tetrahedron
    for lo in ([0, 0, 0], [2, 0, 0], [0, 0, -3]):
        assert np.all(np.isclose(m.positions, lo), axis=1).any()


def test_a_mirroring_node_keeps_the_triangles_outward(tmp_path):
    nodes = [{"mesh": 0, "scale": [-1, 1, 1]}]
    m = load_mesh(write_gltf(tmp_path / "mirror.gltf", nodes, [0]))
    check(m, 4, [-1, 0, 0], [0, 1, 1])
    outward(m, TETRA.mean(axis=0) * [-1, 1, 1])


def test_a_glb_scene_from_trimesh(tmp_path):
    scene = trimesh.Scene()
    scene.add_geometry(trimesh.creation.box((1, 1, 1)), node_name="box",
                       transform=trimesh.transformations.translation_matrix([0, 0.5, 0]))
    scene.add_geometry(trimesh.creation.icosphere(1, radius=0.5), node_name="ball",
                       transform=trimesh.transformations.translation_matrix([2, 0.5, 0]))
    path = tmp_path / "scene.glb"
    scene.export(path)
    m = load_mesh(path)
    check(m, 12 + 80, [-0.5, 0, -0.5], [2.5, 1, 0.5])


def test_nothing_is_normalised_and_fit_puts_it_on_the_floor(tmp_path):
    p, f = cube(10.0, centre=(100, 50, -20))
    m = load_mesh(write_obj(tmp_path / "far.obj", p, f))
    check(m, 12, [95, 45, -25], [105, 55, -15])  # the file's own units and placement
    assert "bounds (95, 45, -25)–(105, 55, -15)" in m.summary()
    fitted = fit(m, size=1.5)
    lo, hi = fitted.bounds()
    np.testing.assert_allclose(lo, [-0.75, 0, -0.75], atol=1e-5)
    np.testing.assert_allclose(hi, [0.75, 1.5, 0.75], atol=1e-5)
    np.testing.assert_array_equal(fitted.normals, m.normals)
    with pytest.raises(ValueError):
        fit(m, size=0)


# ---------------------------------------------------------------------------------------------
# files that do not


def expect_error(path, *fragments):
    with pytest.raises(MeshFileError) as err:
        load_mesh(path)
    text = str(err.value)
    assert "\n" not in text and len(text) <= 200
    assert path.name in text and "allowed" in text
    for fragment in fragments:
        assert fragment in text, text
    assert isinstance(err.value, NaturaError) and err.value.exit_code == 2
    assert err.value.__cause__ is None  # no chained traceback
    return text


def test_a_missing_file(tmp_path):
    expect_error(tmp_path / "nothing.obj", "does not exist", ".obj, .stl, .gltf, .glb")


def test_a_folder(tmp_path):
    folder = tmp_path / "meshes.obj"
    folder.mkdir()
    expect_error(folder, "is a folder")


@pytest.mark.parametrize("name", ["model.ply", "model.fbx", "model"])
def test_an_extension_that_is_not_allowed(tmp_path, name):
    path = tmp_path / name
    path.write_text("ply\n")
    expect_error(path, "allowed .obj, .stl, .gltf, .glb")


def test_an_empty_file(tmp_path):
    path = tmp_path / "empty.stl"
    path.write_bytes(b"")
    expect_error(path, "is empty")


@pytest.mark.parametrize("name, content, says", [
    ("noise.obj", b"\x00\xff\xfe garbage \x00", "binary"),
    ("broken.glb", b"glTF but not really" * 4, "not a readable GLB"),
    ("broken.gltf", b"{ not json", "not glTF JSON"),
    ("lines.obj", b"v 0 0 0\nv 1 0 0\nl 1 2\n", "no triangles"),
    ("words.stl", b"solid x\nnot a facet\nendsolid x\n", "no triangles"),
    ("short.stl", b"\x00" * 90, "no triangles"),
])
def test_unreadable_content(tmp_path, name, content, says):
    path = tmp_path / name
    path.write_bytes(content)
    expect_error(path, says)


def test_a_gltf_pointing_at_the_network_is_refused_without_downloading(tmp_path):
    path = write_gltf(tmp_path / "remote.gltf", [{"mesh": 0}], [0])
    doc = json.loads(path.read_text())
    doc["buffers"][0]["uri"] = "http://example.invalid/tetra.bin"
    path.write_text(json.dumps(doc))
    expect_error(path, "not a readable GLTF")


def test_a_huge_mesh_is_refused(tmp_path, monkeypatch):
    p, f = cube(1.0)
    path = write_obj(tmp_path / "big.obj", p, f)
    monkeypatch.setattr(mesh_files, "MAX_TRIANGLES", 10)
    expect_error(path, "has 12 triangles", "at most 10")


def test_a_huge_binary_stl_is_refused_from_its_header(tmp_path, monkeypatch):
    p, f = cube(1.0)
    path = write_binary_stl(tmp_path / "big.stl", p, f)
    monkeypatch.setattr(mesh_files, "MAX_TRIANGLES", 10)
    monkeypatch.setattr(trimesh, "load_scene", None)  # refused before trimesh is asked
    expect_error(path, "has 12 triangles", "at most 10")


# ---------------------------------------------------------------------------------------------
# every bad input found by fuzzing gets its one-line answer (issue 36): the exact input, a line
# naming the culprit and what is allowed, no numpy warning, no Python exception in the words

PYTHON_WORDS = re.compile(r"[A-Z][a-z]+Error\b|Exception|has no attribute|NoneType|'list'|"
                          r"'dict'|'str'|list index|object is not|\(\)|Traceback")


def refused(path, *fragments):
    """:func:`expect_error`, with every warning an error (numpy's RuntimeWarnings included)
    and no Python exception or type named in the message."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        text = expect_error(path, *fragments)
    assert not PYTHON_WORDS.search(text), text
    return text


TRIANGLE = "v 0 0 0\nv 1 0 0\nv 0 1 0\n"


def test_a_gltf_nested_100000_deep_is_refused(tmp_path):
    path = tmp_path / "deep.gltf"
    path.write_text("[" * 100000 + "]" * 100000)
    refused(path, "nests its JSON more than 100 levels deep", "at most 100 levels")


def test_gltf_json_nested_deeper_than_100_but_readable_is_refused(tmp_path):
    path = write_gltf(tmp_path / "extras.gltf", [{"mesh": 0}], [0])
    doc = json.loads(path.read_text())
    doc["extras"] = json.loads("[" * 150 + "]" * 150)
    path.write_text(json.dumps(doc))
    refused(path, "more than 100 levels deep")


def glb(doc, blob=b"", length=None, version=2):
    """A GLB container of ``doc`` and a binary chunk ``blob`` (padded to 4 bytes)."""
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    blob += b"\x00" * (-len(blob) % 4)
    body = struct.pack("<II", len(text), 0x4E4F534A) + text
    if blob:
        body += struct.pack("<II", len(blob), 0x004E4942) + blob
    total = 12 + len(body)
    return struct.pack("<4sII", b"glTF", version, total if length is None else length) + body


def gltf_in_glb(tmp_path, name="tetra.glb", **changes):
    """write_gltf's tetrahedron as a GLB, its buffer in the binary chunk."""
    doc = json.loads(write_gltf(tmp_path / "src.gltf", [{"mesh": 0}], [0]).read_text())
    blob = base64.b64decode(doc["buffers"][0].pop("uri").split(",", 1)[1])
    doc.update(changes)
    path = tmp_path / name
    path.write_bytes(glb(doc, blob))
    return path, doc, blob


def test_a_glb_loads_and_its_deep_json_chunk_is_refused(tmp_path):
    path, doc, blob = gltf_in_glb(tmp_path)
    assert load_mesh(path).triangle_count == 4
    deep = tmp_path / "deep.glb"
    deep.write_bytes(glb(json.loads("[" * 500 + "]" * 500), blob))
    refused(deep, "nests its JSON more than 100 levels deep")
    deeper = tmp_path / "deeper.glb"
    text = b"[" * 100000 + b"]" * 100000
    deeper.write_bytes(struct.pack("<4sII", b"glTF", 2, 20 + len(text))
                       + struct.pack("<II", len(text), 0x4E4F534A) + text)
    refused(deeper, "nests its JSON more than 100 levels deep")


@pytest.mark.parametrize("name, text, says", [
    ("huge.obj", "v 1e39 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
     ["coordinate 1e+39 at line 1", "within ±3.4e38 (float32)"]),
    ("inf.obj", "v inf 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", ["coordinate inf at line 1"]),
    ("nan.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n", ["coordinate nan at line 2"]),
    ("small.obj", "v 0 0 0\nv -1e39 0 0\nv 0 1 0\nf 1 2 3\n", ["coordinate -1e+39 at line 2"]),
    ("uv.obj", TRIANGLE + "vt 0 0\nvt 1e39 0\nf 1/1 2/2 3/1\n",
     ["texture coordinate 1e+39 at line 5", "float32"]),
])
def test_obj_coordinates_beyond_float32_are_refused_without_warnings(tmp_path, name, text, says):
    path = tmp_path / name
    path.write_text(text)
    refused(path, *says)


def test_an_unused_vertex_out_of_range_is_ignored(tmp_path):
    path = tmp_path / "spare.obj"
    path.write_text(TRIANGLE + "v 1e39 0 0\nvn 0 0 0\nvt nan nan\nf 1 2 3\n")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert load_mesh(path).triangle_count == 1


def test_coordinates_beyond_float32_in_stl_and_gltf_are_refused(tmp_path):
    text = write_ascii_stl(tmp_path / "a.stl", TETRA, TETRA_FACES).read_text()
    (tmp_path / "huge.stl").write_text(text.replace("vertex 1.000000e+00", "vertex 1e39", 1))
    refused(tmp_path / "huge.stl", "coordinate 1e+39 at line 6", "float32")
    p, f = cube(1.0)
    path = write_binary_stl(tmp_path / "inf.stl", p, f)
    data = bytearray(path.read_bytes())
    data[84 + 50 * 2 + 12 + 4:84 + 50 * 2 + 12 + 8] = struct.pack("<f", float("inf"))
    path.write_bytes(bytes(data))
    refused(path, "coordinate inf in triangle 3", "float32")
    refused(write_gltf(tmp_path / "far.gltf", [{"mesh": 0, "scale": [1e300] * 3}], [0]),
            "coordinate 1e+300", "after its node transforms", "float32")


@pytest.mark.parametrize("name, text, says", [
    ("zero.obj", TRIANGLE + "f 0 1 2\n",
     ["vertex index 0 at line 4", "allowed 1 to 3, or -1 to -3 counting back",
      "OBJ counts from 1"]),
    ("beyond.obj", TRIANGLE + "f 1 2 4\n", ["vertex index 4 at line 4", "allowed 1 to 3"]),
    ("back.obj", TRIANGLE + "f -1 -2 -4\n", ["vertex index -4 at line 4", "-1 to -3"]),
    ("early.obj", "v 0 0 0\nf -1 -2 -3\nv 1 0 0\nv 0 1 0\n", ["vertex index -2 at line 2",
                                                            "-1 to -1"]),
    ("texture.obj", TRIANGLE + "vt 0 0\nf 1/1 2/5 3/1\n",
     ["texture index 5 at line 5", "allowed 1 to 1"]),
    ("no_vt.obj", TRIANGLE + "f 1/1 2/1 3/1\n", ["texture index 1 at line 4",
                                                 "the file has no texture entries"]),
    ("normal.obj", TRIANGLE + "vn 0 0 1\nf 1//1 2//2 3//1\n", ["normal index 2 at line 5"]),
    ("some_vt.obj", TRIANGLE + "vt 0 0\nf 1 2 3\nf 1/1 2/1 3/9\n", ["texture index 9 at line 6"]),
    ("big_index.obj", TRIANGLE + "f 1 2 99999999999999999999\n",
     ["vertex index in '99999999999999999999' at line 4"]),
    ("zero_normal.obj", TRIANGLE + "vn 0 0 0\nf 1//1 2//1 3//1\n",
     ["normal (0, 0, 0) at line 4, used by a face", "non-zero length"]),
    ("nan_normal.obj", TRIANGLE + "vn 0 0 1\nvn nan 0 1\nf 1//1 2//2 3//1\n",
     ["normal (nan, 0, 1) at line 5"]),
    ("tiny_normal.obj", TRIANGLE + "vn 1e-300 0 0\nf 1//1 2//1 3//1\n", ["normal (1e-300, 0, 0)"]),
    ("line.obj", TRIANGLE + "f 1 2\n", ["face of 2 corners at line 4", "3 or more"]),
    ("word.obj", "v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n",
     ["'zero' at line 2 where a vertex number belongs", "allowed a number"]),
    ("short.obj", "v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n", ["vertex of 2 numbers at line 2"]),
    ("float_index.obj", TRIANGLE + "f 1 2 3.0\n", ["face corner '3.0' at line 4"]),
    ("slashes.obj", TRIANGLE + "f 1/ 2/ 3/\n", ["face corner '1/' at line 4"]),
    ("triple.obj", TRIANGLE + "f 1///1 2 3\n", ["face corner '1///1' at line 4"]),
    ("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n",
     ["only degenerate triangles (its one triangle has zero area)",
      "allowed at least one triangle of non-zero area"]),
    ("same.obj", TRIANGLE + "f 1 1 1\nf 2 2 2\n", ["only degenerate triangles (all 2 have"]),
    ("point.obj", "v 5 5 5\nv 5 5 5\nv 5 5 5\nf 1 2 3\n", ["only degenerate triangles"]),
])
def test_obj_faces_pointing_at_nothing_or_drawing_nothing_are_refused(tmp_path, name, text,
                                                                      says):
    path = tmp_path / name
    path.write_text(text)
    refused(path, *says)


def test_some_degenerate_triangles_among_good_ones_are_kept(tmp_path):
    path = tmp_path / "sliver.obj"
    path.write_text(TRIANGLE + "v 2 0 0\nf 1 2 3\nf 1 2 4\nf 3 3 3\n")
    m = load_mesh(path)
    check(m, 3, [0, 0, 0], [2, 1, 0])


def test_a_binary_stl_whose_count_does_not_match_its_size(tmp_path):
    p, f = cube(1.0)
    data = bytearray(write_binary_stl(tmp_path / "c.stl", p, f, zero_normals=False)
                     .read_bytes())
    data[80:84] = struct.pack("<I", 5)  # 12 triangles written, 5 claimed
    (tmp_path / "count.stl").write_bytes(bytes(data))
    refused(tmp_path / "count.stl", "claims 5 triangles (binary STL header) but its 684 bytes "
            "hold 12", "allowed 84 + 50 bytes a triangle, or ASCII STL")
    data[:80] = b"solid but binary".ljust(80, b" ")  # as some exporters write the header
    (tmp_path / "solid.stl").write_bytes(bytes(data[:-7]))
    refused(tmp_path / "solid.stl", "claims 5 triangles", "677 bytes hold 11.86")


@pytest.mark.parametrize("name, change, says", [
    ("typo.stl", lambda t: t.replace("    vertex", "    veftex", 1),
     ["a facet of 2 vertices at line 2", "allowed 3 vertices a facet"]),
    ("word.stl", lambda t: t.replace("vertex 0.000000e+00", "vertex zero", 1),
     ["'zero' at line 4 where a vertex number belongs"]),
    ("four.stl", lambda t: t.replace("vertex 0.000000e+00 0.000000e+00 0.000000e+00",
                                     "vertex 0 0 0 0", 1), ["a vertex of 4 numbers at line 4"]),
    ("loose.stl", lambda t: t.replace("facet normal", "facet_normal", 1),
     ["a vertex outside a facet at line 4"]),
])
def test_broken_ascii_stl_is_named_by_line(tmp_path, name, change, says):
    text = write_ascii_stl(tmp_path / "tetra.stl", TETRA, TETRA_FACES).read_text()
    (tmp_path / name).write_text(change(text))
    refused(tmp_path / name, *says)


def gltf_case(path, change):
    doc = json.loads(write_gltf(path, [{"mesh": 0}], [0]).read_text())
    change(doc)
    path.write_text(json.dumps(doc))
    return path


def _data_uri(doc, blob):
    doc["buffers"][0]["uri"] = ("data:application/octet-stream;base64,"
                                + base64.b64encode(blob).decode())


def _buffer(doc):
    return base64.b64decode(doc["buffers"][0]["uri"].split(",", 1)[1])


@pytest.mark.parametrize("name, change, says", [
    ("list.gltf", None, ["holds a list where a glTF object belongs"]),
    ("buffers.gltf", lambda d: d.update(buffers=["abc"]),
     ["buffers[0] as a string", "allowed buffer objects"]),
    ("buffers_obj.gltf", lambda d: d.update(buffers={"a": 1}),
     ["'buffers' as an object", "a list of buffer objects"]),
    ("meshes.gltf", lambda d: d.update(meshes=[[]]), ["meshes[0] as a list"]),
    ("view_length.gltf", lambda d: d["bufferViews"][1].update(byteLength=4000),
     ["bufferView 1 ending at byte 4,024 of buffer 0's 72", "inside their buffer"]),
    ("short_buffer.gltf", lambda d: _data_uri(d, _buffer(d)[:40]),
     ["buffer 0 of 40 bytes, byteLength says 72"]),
    ("accessor.gltf", lambda d: d["accessors"][1].update(count=400),
     ["accessor 1 needing 4,800 bytes of bufferView 1's 48", "inside their bufferView"]),
    ("offset.gltf", lambda d: d["accessors"][1].update(byteOffset=40), ["accessor 1 needing"]),
    ("component.gltf", lambda d: d["accessors"][1].update(componentType=1),
     ["accessor 1 componentType 1", "5126"]),
    ("vec9.gltf", lambda d: d["accessors"][1].update(type="VEC9"), ["type 'VEC9'"]),
    ("position.gltf", lambda d: d["meshes"][0]["primitives"][0]["attributes"].update(
        POSITION=7), ["POSITION pointing at accessor 7, which does not exist"]),
    ("vec2.gltf", lambda d: d["accessors"][1].update(type="VEC2"),
     ["accessor 1 (POSITION of mesh 0 primitive 0) of VEC2 5126", "allowed VEC3"]),
    ("no_position.gltf", lambda d: d["meshes"][0]["primitives"][0].update(attributes={}),
     ["primitive 0 without POSITION"]),
    ("eleven.gltf", lambda d: d["accessors"][0].update(count=11),
     ["mesh 0 primitive 0 of 11 corners", "multiple of 3"]),
    ("indices.gltf", lambda d: _data_uri(d, np.full(12, 9, "<u2").tobytes() + _buffer(d)[24:]),
     ["a triangle using vertex 9 of 4", "allowed vertex indices 0 to 3"]),
    ("node.gltf", lambda d: d["nodes"][0].update(mesh=5),
     ["node 0 pointing at mesh 5, which does not exist", "allowed mesh 0 to 0"]),
    ("cycle.gltf", lambda d: d["nodes"][0].update(children=[0]), ["a tree of nodes"]),
    ("loop.gltf", lambda d: d.update(nodes=[{"mesh": 0, "children": [1]}, {"children": [0]}]),
     ["among its own ancestors"]),
    ("scene.gltf", lambda d: d.update(scene=3), ["'scene' pointing at scene 3"]),
    ("matrix.gltf", lambda d: d["nodes"][0].update(matrix=[1, 2]), ["not 16 finite numbers"]),
    ("uri.gltf", lambda d: d["buffers"][0].update(uri=5), ["buffer 0 uri as the number 5"]),
    ("base64.gltf", lambda d: d["buffers"][0].update(uri="data:x;base64,@@@"),
     ["base64 data is broken"]),
    ("missing.gltf", lambda d: d["buffers"][0].update(uri="nothere.bin"),
     ["'nothere.bin', which is not a file next to it"]),
    ("stride.gltf", lambda d: d["bufferViews"][1].update(byteStride=0),
     ["byteStride 0", "allowed 4 to 252"]),
    ("version.gltf", lambda d: d["asset"].update(version="1.0"), ["version '1.0'",
                                                                  "allowed glTF 2.0"]),
    ("draco.gltf", lambda d: d.update(extensionsRequired=["KHR_draco_mesh_compression"]),
     ["requires the glTF extension 'KHR_draco_mesh_compression'"]),
    ("sparse.gltf", lambda d: d["accessors"][1].update(sparse={"count": 1}),
     ["accessor 1 (POSITION of mesh 0 primitive 0) compressed or sparse"]),
    ("strip.gltf", lambda d: d["meshes"][0]["primitives"][0].update(mode="strip"),
     ["mode as a string", "an integer"]),
])
def test_broken_gltf_layouts_are_named_in_words(tmp_path, name, change, says):
    path = tmp_path / name
    if change is None:
        path.write_text("[1, 2]")
    else:
        gltf_case(path, change)
    refused(path, *says)


@pytest.mark.parametrize("name, make, says", [
    ("magic.glb", lambda d, b: b"glTX" + glb(d, b)[4:], ["does not start with 'glTF'"]),
    ("v1.glb", lambda d, b: glb(d, b, version=1), ["container version 1"]),
    ("cut.glb", lambda d, b: glb(d, b)[:-40], ["its header says", "a whole .glb file"]),
    ("no_bin.glb", lambda d, b: glb(d), ["buffer 0 without a uri"]),
    ("short_bin.glb", lambda d, b: glb(d, b[:40]), ["buffer 0 of 40 bytes, byteLength says 72"]),
    ("not_json.glb", lambda d, b: glb(d, b).replace(b'{"', b'{{', 1), ["is not glTF JSON"]),
])
def test_broken_glb_containers_are_named_in_words(tmp_path, name, make, says):
    _, doc, blob = gltf_in_glb(tmp_path)
    path = tmp_path / name
    path.write_bytes(make(doc, blob))
    refused(path, *says)


def test_the_obj_reader_agrees_with_trimesh(tmp_path):
    """v/vt/vn corners, quads and a pentagon, comments, CR LF: the same triangles as trimesh
    reads (corner by corner), as the loader read OBJ files before it read them itself."""
    lines = ["# a grid of quads, a pentagon and triangles"]
    k = 4
    for i in range(k + 1):
        for j in range(k + 1):
            lines += [f"v {j} {i} {0.1 * i * j}", f"vt {j / k} {i / k}",
                      f"vn {0.1 * i} {0.1 * j} 1"]
    n = lambda i, j: i * (k + 1) + j + 1  # noqa: E731
    for i in range(k):
        for j in range(k):
            c = [n(i, j), n(i, j + 1), n(i + 1, j + 1), n(i + 1, j)]
            lines.append("f " + " ".join(f"{x}/{x}/{x}" for x in c))
    path = tmp_path / "grid.obj"
    path.write_text("\r\n".join(lines) + "\r\n")
    ours = read_obj(path.read_bytes())
    theirs = trimesh.load(path, process=False)
    np.testing.assert_array_equal(ours.positions[ours.faces], theirs.vertices[theirs.faces])
    np.testing.assert_array_equal(ours.uvs[ours.faces], theirs.visual.uv[theirs.faces])
    np.testing.assert_array_equal(ours.normals[ours.faces],
                                  theirs.vertex_normals[theirs.faces])
    path.write_text("v 0 0 0\nv 1 0 0\nv 1.3 1 0\nv 0.5 1.6 0\nv -0.3 1 0\nf 1 2 3 4 5\n"
                    "f 1 2 3\n")
    ours = read_obj(path.read_bytes())
    theirs = trimesh.load(path, process=False)
    np.testing.assert_array_equal(ours.positions[ours.faces], theirs.vertices[theirs.faces])


def heightfield_stl(path, n):
    """A bumpy n × n grid of 2 n² triangles as binary STL, written with numpy."""
    x, z = np.meshgrid(np.linspace(-1, 1, n + 1), np.linspace(-1, 1, n + 1))
    p = np.stack([x, 0.1 * np.sin(6 * x) * np.cos(5 * z), z], -1).reshape(-1, 3)
    idx = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
    a, b = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel()
    c, d = idx[1:, 1:].ravel(), idx[1:, :-1].ravel()
    tri = np.concatenate([np.stack([a, d, c], 1), np.stack([a, c, b], 1)])
    rec = np.zeros(len(tri), STL_RECORD)
    rec["vertices"] = p[tri]
    path.write_bytes(b"heightfield".ljust(80, b" ") + struct.pack("<I", len(tri)) + rec.tobytes())
    return path


def test_a_binary_stl_is_read_in_one_pass_and_welded(tmp_path, monkeypatch):
    monkeypatch.setattr(trimesh, "load_scene", None)  # numpy alone reads binary STL
    m = load_mesh(heightfield_stl(tmp_path / "field.stl", 60))
    assert m.triangle_count == 7200
    lo, hi = m.bounds()
    np.testing.assert_allclose(lo[[0, 2]], [-1, -1])
    np.testing.assert_allclose(hi[[0, 2]], [1, 1])
    assert m.vertex_count == 61 * 61  # welded, smooth: no vertex split
    assert (m.normals[:, 1] > 0.5).all()


@pytest.mark.slow
def test_the_largest_binary_stl_allowed_loads(tmp_path):
    """2,000,000 triangles (mesh_files.MAX_TRIANGLES) of binary STL written by numpy: seconds,
    not minutes (it took 258 s for one frame before the loader read STL with numpy)."""
    m = load_mesh(heightfield_stl(tmp_path / "big.stl", 1000))
    assert m.triangle_count == mesh_files.MAX_TRIANGLES == 2_000_000
    assert m.vertex_count == 1001 * 1001


def test_a_hub_shared_by_thousands_of_triangles_does_not_compare_every_pair(tmp_path):
    """A fan of 5,000 triangles around one point (a pathological STL): the corners at the hub
    are not smoothed pair by pair (25 million pairs) but still come out unit and finite."""
    k = 5000
    a = np.linspace(0, 2 * np.pi, k, endpoint=False)
    rim = np.stack([np.cos(a), 0.05 * np.sin(7 * a), np.sin(a)], 1)
    tri = np.stack([np.zeros((k, 3)), rim[(np.arange(k) + 1) % k], rim], 1)
    rec = np.zeros(k, STL_RECORD)
    rec["vertices"] = tri
    path = tmp_path / "fan.stl"
    path.write_bytes(b"fan".ljust(80, b" ") + struct.pack("<I", k) + rec.tobytes())
    m = load_mesh(path)
    check(m, k, [-1, -0.05, -1], [1, 0.05, 1])


@pytest.mark.parametrize("mix", [False, True])
def test_unique_rows_matches_numpy_unique(monkeypatch, mix):
    """app.sim.lab_meshes.unique_rows (the welding of millions of corners) finds the same
    distinct rows as np.unique, also when every row's hash collides (the exact fallback)."""
    from app.sim import lab_meshes

    if mix:
        monkeypatch.setattr(lab_meshes, "_MIX", (np.uint64(0),))
    rows = np.random.default_rng(1).integers(0, 4, (5000, 3)).astype(np.float32)
    first, inverse = lab_meshes.unique_rows(rows)
    expected = np.unique(rows, axis=0)
    assert len(first) == len(expected)
    np.testing.assert_array_equal(rows[first][inverse], rows)
    _, numpy_first = np.unique(rows, axis=0, return_index=True)
    assert sorted(first) == sorted(numpy_first)  # each distinct row at its first occurrence


def test_a_hub_of_two_planes_is_faceted_as_pairs_would_make_it(monkeypatch):
    """2,000 triangles meeting at one point on two planes at 90°: more corners than are
    compared pair by pair, so the hub's corners are taken a distinct face normal at a time —
    the same normals as comparing every pair."""
    from app.sim import lab_meshes

    n = 1000
    a = np.linspace(0, np.pi, n + 1)
    p = np.vstack([[0, 0, 0], np.stack([np.cos(a), np.sin(a), 0 * a], 1),
                   np.stack([np.cos(a), 0 * a, -np.sin(a)], 1)])
    k = np.arange(n)
    tri = np.vstack([np.stack([0 * k, k + 2, k + 1], 1),
                     np.stack([0 * k, n + 2 + k, n + 3 + k], 1)])
    grouped = lab_meshes.from_arrays("book", p, tri)
    monkeypatch.setattr(lab_meshes, "_CREASE_GROUP", 10_000)
    paired = lab_meshes.from_arrays("book", p, tri)
    for m in (grouped, paired):  # each plane's corners at the hub: that plane's normal
        hub = m.indices[:, 0]
        np.testing.assert_allclose(m.normals[hub[:n]], np.tile([0, 0, -1], (n, 1)), atol=1e-12)
        np.testing.assert_allclose(m.normals[hub[n:]], np.tile([0, 1, 0], (n, 1)), atol=1e-12)
    np.testing.assert_allclose(grouped.normals[grouped.indices], paired.normals[paired.indices],
                               atol=1e-6)

"""Loading a user's own mesh (app/sim/mesh_files.py): OBJ, ascii and binary STL, glTF and GLB
files the tests write themselves (by hand and with trimesh's exporters) — triangle counts,
bounds, outward normals, flattened scene graphs — and one-line errors for what cannot be
loaded."""

from __future__ import annotations

import base64
import json
import struct

import numpy as np
import pytest

from app.errors import NaturaError
from app.sim import mesh_files
from app.sim.mesh_files import MeshFileError, fit, load_mesh

pytestmark = pytest.mark.unit

trimesh = pytest.importorskip("trimesh")

TETRA = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
TETRA_FACES = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])  # outward


def cube(size=1.0, centre=(0.0, 0.0, 0.0)):
    """8 welded corners and 12 outward triangles."""
    p = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)
    i = lambda x, y, z: x * 4 + y * 2 + z  # noqa: E731
    quads = [(i(1, 0, 0), i(1, 1, 0), i(1, 1, 1), i(1, 0, 1)),
             (i(0, 0, 0), i(0, 0, 1), i(0, 1, 1), i(0, 1, 0)),
             (i(0, 1, 0), i(0, 1, 1), i(1, 1, 1), i(1, 1, 0)),
             (i(0, 0, 0), i(1, 0, 0), i(1, 0, 1), i(0, 0, 1)),
             (i(0, 0, 1), i(1, 0, 1), i(1, 1, 1), i(0, 1, 1)),
             (i(0, 0, 0), i(0, 1, 0), i(1, 1, 0), i(1, 0, 0))]
    faces = np.array([t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))])
    return p * size / 2 + np.asarray(centre, float), faces


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

"""The shading lab's test objects and from_arrays (app/sim/lab_meshes.py): finite, unit and
orthogonal frames, the hard edges of the low-poly table and barrel against the smooth sphere,
one smooth normal per position, and no NaN from degenerate triangles or zero-area UVs."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from app.sim import lab_meshes
from app.sim.lab_meshes import TEST_OBJECTS, LabMesh, from_arrays, vertex_format
from tests.helpers.meshes import cube

pytestmark = pytest.mark.unit

OBJECTS = {name: build() for name, build in TEST_OBJECTS.items()}


def _face_normals(m: LabMesh) -> np.ndarray:
    p = m.positions.astype(np.float64)
    t = m.indices.astype(np.int64)
    return np.cross(p[t[:, 1]] - p[t[:, 0]], p[t[:, 2]] - p[t[:, 0]])


def _position_groups(m: LabMesh) -> np.ndarray:
    _, inverse = np.unique(m.positions + np.float32(0), axis=0, return_inverse=True)
    return inverse.reshape(-1)


def check_frames(m: LabMesh, tol: float = 1e-4) -> None:
    """The invariants every LabMesh keeps."""
    v = m.vertex_count
    assert m.positions.shape == (v, 3) and m.positions.dtype == np.float32
    assert m.normals.shape == (v, 3) and m.normals.dtype == np.float32
    assert m.smooth_normals.shape == (v, 3) and m.smooth_normals.dtype == np.float32
    assert m.uvs.shape == (v, 2) and m.uvs.dtype == np.float32
    assert m.tangents.shape == (v, 4) and m.tangents.dtype == np.float32
    assert m.indices.ndim == 2 and m.indices.shape[1] == 3 and m.indices.dtype == np.uint32
    for a in (m.positions, m.normals, m.smooth_normals, m.uvs, m.tangents):
        assert np.isfinite(a).all()
    if m.triangle_count:
        assert int(m.indices.max()) < v
    np.testing.assert_allclose(np.linalg.norm(m.normals, axis=1), 1.0, atol=tol)
    np.testing.assert_allclose(np.linalg.norm(m.smooth_normals, axis=1), 1.0, atol=tol)
    np.testing.assert_allclose(np.linalg.norm(m.tangents[:, :3], axis=1), 1.0, atol=tol)
    dot = np.einsum("ij,ij->i", m.tangents[:, :3], m.normals)
    assert np.abs(dot).max(initial=0.0) < tol
    assert set(np.unique(m.tangents[:, 3])) <= {-1.0, 1.0}


@pytest.mark.parametrize("name", list(TEST_OBJECTS))
def test_every_object_has_finite_unit_orthogonal_frames(name):
    m = OBJECTS[name]
    assert m.name == name
    assert m.triangle_count > 0
    check_frames(m)


@pytest.mark.parametrize("name", list(TEST_OBJECTS))
def test_every_object_is_wound_outward_without_degenerate_triangles(name):
    m = OBJECTS[name]
    fn = _face_normals(m)
    assert (np.linalg.norm(fn, axis=1) > 1e-8).all()
    vertex_n = m.normals[m.indices].sum(axis=1)
    assert (np.einsum("ij,ij->i", fn, vertex_n) > 0).all()


@pytest.mark.parametrize("name", list(TEST_OBJECTS))
def test_every_object_stands_on_the_floor_at_a_lab_size(name):
    lo, hi = OBJECTS[name].bounds()
    assert lo[1] == pytest.approx(0.0, abs=1e-6)
    assert 0.9 <= float(np.max(hi - lo)) <= 2.0
    # centred on the y axis
    assert abs(lo[0] + hi[0]) < 0.05 and abs(lo[2] + hi[2]) < 0.1


def test_the_sphere_is_centred_at_its_radius_with_about_2k_triangles():
    m = OBJECTS["sphere"]
    r = 0.5
    d = np.linalg.norm(m.positions - [0.0, r, 0.0], axis=1)
    np.testing.assert_allclose(d, r, atol=1e-5)
    assert 1500 <= m.triangle_count <= 3000


def test_the_low_poly_objects_are_low_poly():
    assert 24 <= OBJECTS["table"].triangle_count <= 80
    assert 40 <= OBJECTS["barrel"].triangle_count <= 120


@pytest.mark.parametrize("name", ["table", "barrel"])
def test_the_table_and_barrel_have_hard_edges(name):
    m = OBJECTS[name]
    diff = np.linalg.norm(m.normals - m.smooth_normals, axis=1)
    groups = _position_groups(m)
    split = np.bincount(groups)[groups] > 1  # a corner: several copies of one position
    assert split.any()
    assert (diff[split] > 0.1).all()  # every copy at a corner is faceted away from the mean
    # and the faces are flat: the three normals of each triangle are equal
    n = m.normals[m.indices]
    assert np.abs(n - n[:, :1]).max() < 1e-6


def test_the_sphere_is_smooth():
    m = OBJECTS["sphere"]
    np.testing.assert_allclose(m.normals, m.smooth_normals, atol=1e-5)
    expected = (m.positions - [0.0, 0.5, 0.0]) / 0.5
    np.testing.assert_allclose(m.normals, expected, atol=1e-5)


@pytest.mark.parametrize("name", list(TEST_OBJECTS))
def test_smooth_normals_are_one_per_position(name):
    m = OBJECTS[name]
    groups = _position_groups(m)
    first = np.zeros(groups.max() + 1, np.int64)
    first[groups[::-1]] = np.arange(len(groups))[::-1]
    np.testing.assert_array_equal(m.smooth_normals, m.smooth_normals[first[groups]])


def test_a_box_corner_gets_the_diagonal_smooth_normal():
    m = OBJECTS["table"]
    corner = np.array([0.7, 0.76, 0.4], np.float32)
    at = np.where(np.all(np.isclose(m.positions, corner), axis=1))[0]
    assert len(at) == 3
    np.testing.assert_allclose(m.smooth_normals[at], np.tile(np.ones(3) / np.sqrt(3), (3, 1)),
                               atol=1e-5)


@pytest.mark.parametrize("name", ["table", "barrel", "brick_wall"])
def test_tangents_run_along_plus_u(name):
    """On flat faces the tangent is the direction in which u grows: ∂p/∂u."""
    m = OBJECTS[name]
    p = m.positions.astype(np.float64)
    uv = m.uvs.astype(np.float64)
    t = m.indices.astype(np.int64)
    e1, e2 = p[t[:, 1]] - p[t[:, 0]], p[t[:, 2]] - p[t[:, 0]]
    d1, d2 = uv[t[:, 1]] - uv[t[:, 0]], uv[t[:, 2]] - uv[t[:, 0]]
    r = d1[:, 0] * d2[:, 1] - d2[:, 0] * d1[:, 1]
    dpdu = (e1 * d2[:, 1:2] - e2 * d1[:, 1:2]) / r[:, None]
    dpdu /= np.linalg.norm(dpdu, axis=1, keepdims=True)
    for k in range(3):
        dot = np.einsum("ij,ij->i", m.tangents[t[:, k], :3], dpdu)
        assert dot.min() > 0.99
    assert (m.tangents[:, 3] == 1.0).all()  # nothing mirrored


def test_the_brick_wall_is_2_by_1_5_metres_with_tangents_along_the_rows():
    m = OBJECTS["brick_wall"]
    lo, hi = m.bounds()
    assert hi[0] - lo[0] == pytest.approx(2.0) and hi[1] - lo[1] == pytest.approx(1.5)
    front = m.normals[:, 2] > 0.99
    np.testing.assert_allclose(m.tangents[front, :3], np.tile([1.0, 0.0, 0.0], (front.sum(), 1)),
                               atol=1e-6)
    # UVs in metres: the front spans 2 × 1.5 UV units
    assert np.ptp(m.uvs[front, 0]) == pytest.approx(2.0)
    assert np.ptp(m.uvs[front, 1]) == pytest.approx(1.5)


def test_the_figure_is_a_humanoid_height():
    lo, hi = OBJECTS["figure"].bounds()
    assert hi[1] == pytest.approx(1.8, abs=0.01)
    assert hi[0] - lo[0] < 1.0


def test_vertex_data_interleaves_the_attributes_asked_for():
    m = OBJECTS["barrel"]
    attrs = ["in_position", "normal", "smooth_normal", "uv", "tangent"]
    data = np.frombuffer(m.vertex_data(attrs), np.float32).reshape(m.vertex_count, -1)
    assert data.shape[1] == 15
    np.testing.assert_array_equal(data[:, :3], m.positions)
    np.testing.assert_array_equal(data[:, 6:9], m.smooth_normals)
    np.testing.assert_array_equal(data[:, 11:15], m.tangents)
    assert vertex_format(attrs) == "3f 3f 3f 2f 4f"
    assert len(m.index_data()) == m.triangle_count * 12


def test_an_unknown_attribute_is_one_line_naming_it_and_the_allowed():
    with pytest.raises(ValueError) as err:
        OBJECTS["sphere"].vertex_data(["position", "colour"])
    text = str(err.value)
    assert "\n" not in text and "'colour'" in text and "allowed" in text and "tangent" in text


# ---------------------------------------------------------------------------------------------
# from_arrays

#: the unit cube [0, 1]³ (8 welded corners)
CUBE_P = cube(1.0, centre=(0.5, 0.5, 0.5))[0]


def test_from_arrays_splits_a_welded_cube_at_its_hard_edges():
    m = from_arrays("cube", CUBE_P, cube()[1])
    check_frames(m)
    assert m.triangle_count == 12 and m.vertex_count == 24
    n = m.normals[m.indices]
    assert np.abs(n - n[:, :1]).max() < 1e-6  # faceted
    centre = m.positions[m.indices].mean(axis=1) - 0.5
    assert (np.einsum("ij,ij->i", n[:, 0], centre) > 0).all()  # outward
    np.testing.assert_allclose(np.abs(m.smooth_normals), 1 / np.sqrt(3), atol=1e-6)


def test_from_arrays_smooths_below_the_crease_angle():
    m = from_arrays("cube", CUBE_P, cube()[1], hard_angle_deg=180.0)
    check_frames(m)
    np.testing.assert_allclose(m.normals, m.smooth_normals, atol=1e-6)


def test_from_arrays_keeps_a_cylinder_smooth_around_and_hard_at_the_caps():
    k = 32
    a = np.linspace(0, 2 * np.pi, k, endpoint=False)
    ring = np.stack([np.cos(a), np.zeros(k), -np.sin(a)], 1)
    p = np.vstack([ring, ring + [0, 1, 0], [[0, 0, 0], [0, 1, 0]]])
    tris = []
    for i in range(k):
        j = (i + 1) % k
        tris += [(i, j, k + j), (i, k + j, k + i), (2 * k + 1, k + i, k + j), (2 * k, j, i)]
    m = from_arrays("cylinder", p, tris)
    check_frames(m)
    side = np.abs(m.normals[:, 1]) < 1e-6
    radial = m.positions[side] * [1, 0, 1]
    np.testing.assert_allclose(m.normals[side], radial, atol=0.01)  # smooth: radial normals
    caps = np.abs(np.abs(m.normals[:, 1]) - 1) < 1e-6
    assert side.sum() + caps.sum() == m.vertex_count  # nothing in between: hard cap edges


def test_from_arrays_keeps_given_normals_and_uvs():
    p = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    n = np.array([[0, 0, 1], [0, 0.6, 0.8], [0, 0, 2]], float)
    uv = np.array([[0, 0], [1, 0], [0, 1]], float)
    m = from_arrays("tri", p, [[0, 1, 2]], normals=n, uvs=uv)
    check_frames(m)
    np.testing.assert_allclose(m.normals, n / np.linalg.norm(n, axis=1, keepdims=True),
                               atol=1e-6)
    np.testing.assert_array_equal(m.uvs, uv)
    assert m.tangents[0, 0] > 0.99 and m.tangents[0, 3] == 1.0


def test_from_arrays_makes_uvs_when_there_are_none():
    m = from_arrays("cube", CUBE_P, cube()[1])
    assert np.ptp(m.uvs, axis=0).max() > 0.5
    # every face has a non-degenerate projection, so its tangent lies in it along ∂p/∂u
    assert (np.abs(np.einsum("ij,ij->i", m.tangents[:, :3], m.normals)) < 1e-6).all()


@pytest.mark.parametrize("case", ["collapsed", "collinear", "repeated_index", "isolated"])
def test_degenerate_triangles_give_no_nan(case):
    p = np.array([[0, 0, 0], [0, 0, 0], [0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0]], float)
    tris = {"collapsed": [[0, 1, 2], [0, 3, 5]],
            "collinear": [[0, 3, 4], [0, 3, 5]],
            "repeated_index": [[3, 3, 5], [0, 3, 5]],
            "isolated": [[0, 1, 2]]}[case]
    for uvs in (None, np.zeros((6, 2))):
        m = from_arrays(case, p, tris, uvs=uvs)
        check_frames(m)
    m = from_arrays(case, p, tris, normals=np.zeros((6, 3)))
    check_frames(m)


def test_a_degenerate_triangle_takes_its_neighbours_normal():
    p = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 0, 0]], float)
    m = from_arrays("sliver", p, [[0, 1, 2], [0, 1, 3]])
    np.testing.assert_allclose(m.normals, np.tile([0, 0, 1.0], (m.vertex_count, 1)), atol=1e-6)


@pytest.mark.parametrize("uvs", [np.zeros((3, 2)), np.array([[0, 0], [1, 1], [2, 2.0]]),
                                 np.full((3, 2), np.nan)])
def test_zero_area_uvs_give_a_fallback_tangent(uvs):
    p = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    m = from_arrays("tri", p, [[0, 1, 2]], uvs=uvs)
    check_frames(m)


def test_bad_arrays_are_one_line_errors():
    p3, tri = np.zeros((3, 3)), [[0, 1, 2]]
    bad: list[dict[str, Any]] = [
        dict(positions=np.zeros((3, 2)), indices=tri),
        dict(positions=np.full((3, 3), np.nan), indices=tri),
        dict(positions=p3, indices=[[0, 1, 3]]),
        dict(positions=p3, indices=[0, 1]),
        dict(positions=p3, indices=[[0.0, 1.0, 2.0]]),
        dict(positions=p3, indices=tri, normals=np.zeros((2, 3))),
        dict(positions=p3, indices=tri, uvs=np.zeros((3, 3))),
        dict(positions=p3, indices=tri, hard_angle_deg=-1),
    ]
    for kwargs in bad:
        with pytest.raises(ValueError) as err:
            from_arrays("bad", **kwargs)
        assert "\n" not in str(err.value) and str(err.value).startswith("bad:")


def test_an_empty_mesh_is_allowed():
    m = from_arrays("empty", np.zeros((0, 3)), np.zeros((0, 3), np.int64))
    check_frames(m)
    assert m.triangle_count == 0


def test_concatenate_shares_smooth_normals_where_parts_touch():
    a = from_arrays("a", CUBE_P, cube()[1])
    b = from_arrays("b", CUBE_P + [1, 0, 0], cube()[1])
    m = lab_meshes.concatenate("ab", [a, b])
    check_frames(m)
    assert m.triangle_count == 24
    at = np.all(np.isclose(m.positions, [1, 1, 1]), axis=1)
    assert at.sum() == 6
    np.testing.assert_allclose(m.smooth_normals[at], np.tile([0, 1, 1] / np.sqrt(2), (6, 1)),
                               atol=1e-5)


coord = st.integers(-2, 2).map(float)


@settings(max_examples=60, deadline=None)
@given(points=st.lists(st.tuples(coord, coord, coord), min_size=1, max_size=8),
       data=st.data(), with_uvs=st.booleans(), angle=st.floats(0, 180))
def test_from_arrays_never_gives_nan(points, data, with_uvs, angle):
    """Random little meshes on a coarse grid: coincident points, collinear and collapsed
    triangles, repeated indices and zero-area UVs all come out finite, unit and orthogonal."""
    p = np.array(points, float)
    n = len(p)
    tris = data.draw(st.lists(st.tuples(*[st.integers(0, n - 1)] * 3), min_size=1, max_size=10))
    uvs = None
    if with_uvs:
        uvs = np.array(data.draw(st.lists(st.tuples(st.integers(0, 1), st.integers(0, 1)),
                                          min_size=n, max_size=n)), float)
    m = from_arrays("random", p, tris, uvs=uvs, hard_angle_deg=angle)
    check_frames(m)
    assert m.triangle_count == len(tris)

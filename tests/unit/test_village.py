"""The village's island and layout (app/sim/village.py, app/sim/village_meshes.py): the height
field the mesh draws and the queries answer agree, the grass grows only where it may, the
houses face the plaza and stand on land, the lamps' clock, the hero's walk."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from app.effects.village.effect import lamps_lit
from app.frame import Terrain
from app.sim import village_meshes
from app.sim.village import (
    HALF,
    PLAZA_RADIUS,
    Island,
    house_corners,
    island_height,
    path_distance,
)


@pytest.fixture(scope="module")
def island():
    return Island(97)


def test_the_island_is_a_terrain(island):
    assert isinstance(island, Terrain)
    assert island.bounds == (-HALF, -HALF, HALF, HALF)
    assert island.sea_level == 0.0


def test_heights_at_the_grid_nodes_are_the_analytic_field(island):
    j, i = np.meshgrid(np.arange(0, 97, 7), np.arange(0, 97, 5), indexing="ij")
    x, z = island.axis[i], island.axis[j]
    assert np.allclose(island.height(x, z), island_height(x, z), atol=1e-9)


def test_an_island_a_plaza_a_hill_and_a_seabed(island):
    assert island.ground(0.0, 0.0) == pytest.approx(1.6, abs=1e-6)  # the flat plaza
    assert island.ground(30.0, -32.0) > 6.0  # the hill
    ring = [island.ground(80 * math.sin(a), 80 * math.cos(a)) for a in np.linspace(0, 6.28, 12)]
    assert max(ring) < -3.0  # the sea all round


@settings(max_examples=40, deadline=None)
@given(st.floats(-100, 100), st.floats(-100, 100))
def test_the_height_is_linear_on_the_mesh_triangles(x, z):
    """A point's height lies on the plane of the mesh triangle under it: the queries answer on
    the triangles the GPU draws (a grass root or a foot on the rendered ground)."""
    isl = Island(33)
    p, _, _, tri = isl.mesh_arrays()
    c = isl.cell
    i = min(int((x + HALF) // c), 31)
    j = min(int((z + HALF) // c), 31)
    u, v = (x + HALF) / c - i, (z + HALF) / c - j
    r = isl.resolution
    a, b = j * r + i, j * r + i + 1
    cc, d = (j + 1) * r + i + 1, (j + 1) * r + i
    corners = (a, d, cc) if v >= u else (a, cc, b)
    assert any(set(corners) == set(t) for t in tri[(tri == a).any(axis=1)].tolist())
    q = p[list(corners)]
    n = np.cross(q[1] - q[0], q[2] - q[0])
    assert n[1] > 0  # counter-clockwise seen from above
    h = q[0, 1] - (n[0] * (x - q[0, 0]) + n[2] * (z - q[0, 2])) / n[1]
    assert float(isl.height(x, z)) == pytest.approx(h, abs=1e-9)
    normal = isl.normal(x, z)
    assert np.allclose(normal, n / np.linalg.norm(n), atol=1e-9)


def test_grass_grows_only_on_the_meadow(island):
    rng = np.random.default_rng(3)
    x, z = rng.uniform(-100, 100, 40000), rng.uniform(-100, 100, 40000)
    d = island.grass_density(x, z)
    assert 0.0 <= d.min() and d.max() <= 1.0
    grow = d > 0.0
    assert 0.08 < grow.mean() < 0.4  # the meadow: most of an island of ~52 m radius
    assert np.all(island.height(x[grow], z[grow]) > 0.45)  # no grass on sand or under water
    assert not np.any(np.hypot(x[grow], z[grow]) < PLAZA_RADIUS - 1.0)  # nor on the plaza
    lay = island.layout
    assert not np.any(path_distance(x[grow], z[grow], lay) < lay.path_width / 2)
    for house in lay.houses:  # nor under a house
        c = house_corners(house)
        inside = _inside_polygon(x[grow], z[grow], c)
        assert not inside.any(), house.name


def _inside_polygon(x, z, corners):
    inside = np.ones(x.shape, bool)
    for k in range(4):
        a, b = corners[k], corners[(k + 1) % 4]
        cross = (b[0] - a[0]) * (z - a[1]) - (b[1] - a[1]) * (x - a[0])
        inside &= cross * _orientation(corners) >= 0
    return inside


def _orientation(c):
    return np.sign((c[1][0] - c[0][0]) * (c[2][1] - c[0][1]) - (c[1][1] - c[0][1])
                   * (c[2][0] - c[0][0]))


def test_the_houses_face_the_plaza_on_dry_land_apart(island):
    lay = island.layout
    for h in lay.houses:
        a = math.radians(h.facing)
        door = np.array([math.sin(a), -math.cos(a)])
        to_centre = -np.asarray(h.centre) / np.linalg.norm(h.centre)
        assert door @ to_centre > 0.99, h.name
        assert island.height(*house_corners(h).T).min() > 0.8, h.name
    centres = np.array([h.centre for h in lay.houses])
    gaps = np.linalg.norm(centres[:, None] - centres[None], axis=-1) + np.eye(len(centres)) * 99
    assert gaps.min() > 12.0
    for x, z in [*lay.lamps, lay.bonfire, *(p.position for p in lay.people)]:
        assert island.ground(x, z) > 0.5


@pytest.mark.parametrize("elevation, auto, lit", [
    (45.0, True, False), (2.0, True, True), (-20.0, True, True), (45.0, False, True),
    (None, True, True)])
def test_the_lamps_light_when_the_sun_sets(elevation, auto, lit):
    assert lamps_lit(elevation, auto, 3.0) is lit


def test_the_meshes_are_finite_and_lie_on_the_island():
    isl = Island(65)
    batches = village_meshes.village_batches(isl)
    assert set(batches) == {"terrain", "walls", "solids", "lanterns", "flame"}
    for name, b in batches.items():
        assert b.vertices.shape[1] == village_meshes.FLOATS, name
        assert np.isfinite(b.vertices).all(), name
        assert b.indices.max() < len(b.vertices), name
        n = b.vertices[:, 3:6]
        assert np.allclose(np.linalg.norm(n, axis=1), 1.0, atol=1e-4), name
    terrain = batches["terrain"].vertices
    assert terrain[:, 1].min() == pytest.approx(island_height(110.0, 110.0), abs=0.01)
    # the windows' mask: lit panes (R) have the specular mask (G), frames (B) are not glass
    m = village_meshes.window_mask()
    assert 0.05 < m[..., 0].mean() < 0.2
    assert np.all(m[..., 1] == m[..., 0])
    assert not np.any((m[..., 0] > 0) & (m[..., 2] > 0))


def test_the_walls_uv_put_the_door_between_two_windows():
    """The front wall's u is 0 at its middle, where the door is: the mask's panes lie in the
    middle of each bay (u mod 1 in [0.34, 0.66]), so the door (1.1 m of a 2.5 m bay: |u| ≤ 0.22)
    never cuts a window."""
    half_door = 0.55 / village_meshes.BAY
    m = village_meshes.window_mask(100)
    panes = np.nonzero(m[..., 0].any(axis=0))[0] / 100
    assert panes.min() > half_door and panes.max() < 1.0 - half_door

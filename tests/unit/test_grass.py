"""The grass's numpy twins (app/sim/grass.py, spec/003 §2.9): the geometry grass's wind
(spec/003 eq. 7.1 to spec/003 eq. 7.4) and blade (criterion 27 on the twin), the billboard's
frames (spec/003 eq. 7.5 to spec/003 eq. 7.12, criterion 28 on the twin) and wind (spec/003
eq. 7.13 to spec/003 eq. 7.17), the crossed planes and their side coverage (criterion 29 on the
twin), the placement on a terrain, the tuft textures, the culling tiles and the budgets."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from app.sim import grass as gs


class FakeTerrain:
    """A 10 m × 10 m sloping field: meadow (1) for x > 1, sparse (0.25) for x < −1, bare
    between."""

    bounds = (-5.0, -5.0, 5.0, 5.0)
    sea_level = 0.0
    revision = 1

    def height(self, x, z):
        return 1.0 + 0.1 * np.asarray(x, float) + 0.05 * np.asarray(z, float)

    def normal(self, x, z):
        n = np.array([-0.1, 1.0, -0.05]) / np.linalg.norm([-0.1, 1.0, -0.05])
        return np.broadcast_to(n, np.shape(x) + (3,))

    def grass_density(self, x, z):
        x = np.asarray(x, float) + 0.0 * np.asarray(z, float)
        return np.where(x > 1.0, 1.0, np.where(x < -1.0, 0.25, 0.0))


class Bare(FakeTerrain):
    def grass_density(self, x, z):
        return np.zeros(np.broadcast(np.asarray(x), np.asarray(z)).shape)


finite = st.floats(-1e4, 1e4, allow_nan=False)


# ---- (a) the geometry grass -------------------------------------------------------------------
@given(finite, finite)
def test_phase_in_0_2pi_and_omega_in_1_2(px, pz):
    """Criterion 27: φ ∈ [0, 2π), ω ∈ [1, 2] for any centroid."""
    phi = float(gs.gs_phase(px, pz))
    assert 0.0 <= phi < 2 * math.pi
    assert phi == pytest.approx(abs(px + pz) % (2 * math.pi), abs=1e-9)
    assert 1.0 <= float(gs.gs_omega(phi)) <= 2.0


@given(st.floats(0.0, 1.0), st.floats(0.0, 1.0), st.floats(0, 2 * math.pi),
       st.floats(-100.0, 100.0), st.floats(0.0, 360.0))
def test_wind_is_horizontal_along_the_direction_and_zero_at_the_root(h, wi, phi, t, deg):
    d = gs.compass_direction(deg)
    omega = float(gs.gs_omega(phi))
    w = gs.gs_wind(h, d, wi, phi, omega, t)
    assert w[1] == 0.0
    assert np.linalg.norm(np.cross(w, d)) < 1e-9  # along ±w_d
    expect = h * wi * (1.0 + h * wi * (omega - 1.0) * math.sin(omega * t + phi))
    assert float(w @ d) == pytest.approx(expect, abs=1e-12)  # spec/003 eq. 7.4
    assert np.all(gs.gs_wind(0.0, d, wi, phi, omega, t) == 0.0)


def test_amplitude_grows_with_height():
    """spec/003 eq. 7.3: A ∝ h, so the sway is largest at the tip."""
    h = np.linspace(0.0, 1.0, 11)
    a = gs.gs_amplitude(h, 0.8, 1.6)
    assert a[0] == 0.0 and np.all(np.diff(a) > 0)


@pytest.mark.parametrize("sections", [1, 2, 3, 4])
def test_blade_triangle_budget_base_fixed_tip_along_the_wind(sections):
    tri = np.array([[3.0, 1.0, 2.0], [3.1, 1.0, 2.0], [3.0, 1.0, 2.1]])
    d = np.array([0.6, 0.0, 0.8])
    t0, n0 = gs.gs_blade(tri, 0.487, sections, d, 0.9, 0.0)
    t1, n1 = gs.gs_blade(tri, 0.487, sections, d, 0.9, 1.0)
    calm, _ = gs.gs_blade(tri, 0.487, sections, d, 0.0, 1.0)
    assert len(t0) == gs.gs_triangles_per_blade(sections) == 6 * (sections - 1) + 3
    assert gs.gs_max_vertices(sections) == 3 * len(t0)
    base = np.abs(t0[..., 1] - 1.0) < 1e-12
    assert base.sum() >= 6  # the base ring appears in the first triangles
    assert np.array_equal(t0[base], t1[base])  # base vertices never move
    tip = np.argmax(t1[..., 1].ravel())
    moved = t1.reshape(-1, 3)[tip] - calm.reshape(-1, 3)[tip]
    assert abs(moved[1]) < 1e-12 and np.linalg.norm(np.cross(moved, d)) < 1e-12
    assert np.linalg.norm(moved) > 0.1
    assert t1[..., 1].max() == pytest.approx(1.487)  # the apex at the full height
    for n in (n0, n1):
        assert np.allclose(np.linalg.norm(n, axis=1), 1.0)
    # the shrunk base: halfway to the centroid
    c = tri.mean(axis=0)
    assert np.allclose(np.sort(t0[base][:, 0])[[0, -1]],
                       np.sort(((c + tri) / 2)[:, 0])[[0, -1]])


def test_blade_normals_point_outward():
    tri = np.array([[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [0.0, 0.0, 0.1]])
    t, n = gs.gs_blade(tri, 0.5, 3, (1, 0, 0), 0.0, 0.0)
    axis_xz = tri.mean(axis=0)[[0, 2]]
    out = t.mean(axis=1)[:, [0, 2]] - axis_xz
    assert np.all(np.sum(n[:, [0, 2]] * out, axis=1) > 0)


def test_blade_degenerate_height_zero_is_finite():
    tri = np.array([[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [0.0, 0.0, 0.1]])
    t, n = gs.gs_blade(tri, 0.0, 4, (0, 0, 0), 1.0, 5.0)
    assert np.isfinite(t).all() and np.isfinite(n).all()


def test_blade_sections_out_of_range_is_refused():
    with pytest.raises(ValueError, match="sections=5"):
        gs.gs_blade(np.zeros((3, 3)), 0.4, 5, (1, 0, 0), 0.5, 0.0)


# ---- (b) crossed billboards -------------------------------------------------------------------
def test_billboard_up_modes():
    u = np.array([0.0, 0.6, -0.8])
    assert np.allclose(gs.billboard_up("camera", u), u)
    assert np.allclose(gs.billboard_up("world", u), (0, 1, 0))
    avg = u + np.array([0.0, 1.0, 0.0])
    assert np.allclose(gs.billboard_up("average", u), avg / np.linalg.norm(avg))
    with pytest.raises(ValueError, match="billboard y 'up'"):
        gs.billboard_up("up", u)


def test_rotation_y_is_eq_7_9():
    r = gs.rotation_y(0.3)
    assert np.allclose(r @ r.T, np.eye(3))
    assert np.allclose(r @ [1.0, 0.0, 0.0], [math.cos(0.3), 0.0, -math.sin(0.3)])


cameras = st.tuples(st.floats(-20, 20), st.floats(0.2, 20), st.floats(-20, 20))


def _look_at(pos, target):
    from app.sim.camera import Camera
    cam = Camera(position=tuple(pos))
    cam.look_at_direction(np.asarray(target) - np.asarray(pos))
    return cam


@settings(max_examples=40, deadline=None)
@given(cameras)
def test_frames_on_the_twin(pos):
    """Criterion 28 on the twin: camera-up faces the camera's position; world-up keeps the up
    edge vertical; the average is normalize(u + ŷ)."""
    centre = np.array([0.5, 0.25, -0.3])
    if np.linalg.norm(np.asarray(pos) - centre) < 0.5:
        return
    cam = _look_at(pos, centre)
    r, u, _ = cam.basis()
    v = (np.asarray(pos) - centre) / np.linalg.norm(np.asarray(pos) - centre)
    f = gs.billboard_frame(centre, pos, u, r, "camera")
    assert f.normal @ v > 0.999
    w = gs.billboard_frame(centre, pos, u, r, "world")
    assert np.allclose(w.up, (0, 1, 0)) and abs(w.right[1]) < 1e-12
    a = gs.billboard_frame(centre, pos, u, r, "average")
    assert np.allclose(a.up, (u + (0, 1, 0)) / np.linalg.norm(u + (0, 1, 0)))
    for fr in (f, w, a):
        assert np.allclose(np.linalg.norm(fr.right), 1.0) and fr.normal @ v > 0.0


def test_frame_from_straight_above_in_world_mode_uses_the_camera_right():
    from app.sim.camera import Camera
    cam = Camera(position=(0.0, 10.0, 0.0), yaw=30.0, pitch=-90.0)
    r, u, _ = cam.basis()
    f = gs.billboard_frame((0.0, 0.0, 0.0), cam.position, u, r, "world")
    assert np.allclose(f.right, r) and np.isfinite(f.normal).all()
    at = gs.billboard_frame(cam.position, cam.position, u, r, "camera")  # the camera at P_c
    assert np.isfinite(at.normal).all() and np.linalg.norm(at.normal) > 0.99


def test_vertex_is_eq_7_5_and_7_6():
    f = gs.BillboardFrame(np.array([1.0, 0, 0]), np.array([0, 1.0, 0]), np.array([0, 0, 1.0]))
    assert np.allclose(gs.billboard_vertex((1, 2, 3), (0.5, -0.5), 2.0, f), (2, 1, 3))


@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_planes_are_180_over_n_apart(n):
    for layout in gs.ANGLE_LAYOUTS:
        a = gs.plane_angles(n, layout)
        assert np.allclose(np.diff(a), 180.0 / n)
    assert gs.plane_angles(n, "document")[0] == 0.0


def test_repository_angles_are_fig_102s():
    assert list(gs.plane_angles(3, "repository")) == [-60.0, 0.0, 60.0]


def test_billboard_wind_eqs_7_13_to_7_17():
    seed, sin_seed, i, t = 0.3, 2.0, 0.6, 1.7
    s = gs.bb_sine(i, seed, sin_seed, t)
    assert s == pytest.approx(0.5 * (i + seed) * math.sin(t + sin_seed))
    d = gs.compass_direction(90.0)
    off = gs.bb_wind_offset(np.array([0.0, 0.5, 1.0]), d, i, seed, sin_seed, t, 0.5, 0.4, 1.0)
    assert np.all(off[0] == 0.0)  # the root stays
    assert np.allclose(off[:, 1], 0.0) and np.allclose(off[:, 2], 0.0, atol=1e-12)
    assert off[2, 0] == pytest.approx(4 * off[1, 0])  # v²
    assert off[2, 0] == pytest.approx(i * 0.4 * 0.5 * (1.0 + s))
    repo = gs.bb_wind_offset(1.0, d, i, seed, sin_seed, t, 0.5, 0.4, 3.0)
    assert repo[0] == pytest.approx(i * 0.4 * 0.5 * (3.0 + s))


def test_units_share_their_seeds_and_follow_the_generator():
    roots = np.array([[1.0, 0.0, 2.0], [-3.0, 0.5, 1.0]] * 2000)
    u = gs.make_units(roots, 3, variety=1.0, wellness=1.0)
    assert np.all((u.seed >= 0) & (u.seed <= 1))
    assert np.allclose(u.sin_seed, np.abs(roots[:, 0] + roots[:, 2]))
    frac = np.bincount(u.texture.astype(int), minlength=3) / len(u)
    assert np.allclose(frac, gs.variety_weights(1.0), atol=0.03)
    green = np.all(u.tint == 1.0, axis=1).mean()
    assert green == pytest.approx(gs.ripeness_weights(1.0)[0], abs=0.03)
    assert gs.ripeness_weights(0.0)[0] == 0.0
    rows = u.instance_data()
    assert rows.shape == (len(u), 10) and rows.dtype == np.float32


def test_side_coverage_rises_to_three_planes_then_levels_off():
    """Criterion 29 on the twin: with the generated tufts, the coverage of a unit seen from
    the side grows from one plane to three and changes by less than 10 % from three to
    four."""
    total = np.zeros(4)
    for kind in range(3):
        alpha = gs.tuft_texture(kind)[..., 3]
        c = [gs.side_coverage(alpha, gs.plane_angles(n)) for n in (1, 2, 3, 4)]
        assert c[0] <= c[1] + 1e-9 < c[2]
        total += c
    assert abs(total[3] / total[2] - 1.0) < 0.10


# ---- the tufts --------------------------------------------------------------------------------
@pytest.mark.parametrize("kind", [0, 1, 2])
def test_tufts_stand_on_the_bottom_and_stop_below_the_top(kind):
    img = gs.tuft_texture(kind, 64)
    a = img[..., 3]
    assert img.shape == (64, 64, 4) and np.isfinite(img).all()
    assert a[0].max() > 0.9  # roots on the bottom row (row 0 is v = 0)
    assert a[int(0.97 * 64):].max() == 0.0
    assert 0.1 < (a > 0.2).mean() < 0.5
    assert a[:, :4].max() == 0.0 and a[:, -4:].max() == 0.0  # never at a tile's side


def test_tuft_kind_out_of_range():
    with pytest.raises(ValueError, match="tuft kind 3"):
        gs.tuft_texture(3)


# ---- the placement ----------------------------------------------------------------------------
def test_roots_only_on_grass_deterministic_and_on_the_ground():
    t = FakeTerrain()
    r = gs.sample_roots(t, 4000, seed=5)
    assert r.shape == (4000, 3)
    assert np.all(t.grass_density(r[:, 0], r[:, 2]) > 0)
    assert np.allclose(r[:, 1], t.height(r[:, 0], r[:, 2]))
    assert np.array_equal(r, gs.sample_roots(t, 4000, seed=5))
    assert not np.array_equal(r, gs.sample_roots(t, 4000, seed=6))
    # rejection by the density: four times as many per m² where it is 1 as where it is 0.25
    dense, sparse = (r[:, 0] > 1.0).sum(), (r[:, 0] < -1.0).sum()
    assert dense / sparse == pytest.approx(4.0, rel=0.15)
    assert len(gs.sample_roots(Bare(), 100, 1)) == 0
    assert len(gs.sample_roots(t, 0, 1)) == 0
    with pytest.raises(ValueError, match="blade count -1"):
        gs.sample_roots(t, -1, 1)


def test_scatter_triangles_surround_their_roots():
    t = FakeTerrain()
    r = gs.sample_roots(t, 50, 1)
    tri = gs.scatter_triangles(t, r, 1)
    assert tri.shape == (50, 3, 3)
    assert np.allclose(tri.mean(axis=1)[:, [0, 2]], r[:, [0, 2]])
    legs = np.linalg.norm(tri[:, 1, [0, 2]] - tri[:, 0, [0, 2]], axis=1)
    assert np.allclose(legs, gs.GS_ROOT_LEG)


def test_grid_triangles_are_regular_and_on_grass():
    """The thesis's failure input: every blade on the same grid."""
    t = FakeTerrain()
    tri = gs.grid_triangles(t, 600, 2)
    assert tri.shape == (600, 3, 3)
    c = tri.mean(axis=1)
    assert np.all(t.grass_density(c[:, 0], c[:, 2]) >= 0.5)
    xs = np.unique(np.round(tri[..., 0], 9))
    steps = np.unique(np.round(np.diff(xs), 6))
    assert len(steps) == 1  # one spacing: a regular mesh


def test_units_for_and_budgets():
    assert gs.units_for(8) == 1 and gs.units_for(9) == 2 and gs.units_for(0) == 0
    assert gs.triangles("geometry", 200, sections=2) == 200 * 9
    assert gs.triangles("billboard", 80, planes=3) == 10 * 3 * 2
    assert gs.triangles("instanced", 10, segments=5) == 90
    with pytest.raises(ValueError, match="grass method 'x'"):
        gs.triangles("x", 1)


# ---- the instanced blades ---------------------------------------------------------------------
def test_blade_strip_and_bezier():
    s = gs.blade_strip(4)
    assert s.shape == (9, 2) and s[-1].tolist() == [1.0, 0.0]
    assert gs.blade_triangles(4) == 7
    p = [np.zeros(3), np.array([0, 1.0, 0]), np.array([0, 2.0, 1]), np.array([0, 3.0, 3])]
    b = gs.cubic_bezier(*p, np.array([0.0, 1.0]))
    assert np.allclose(b[0], p[0]) and np.allclose(b[1], p[3])


def test_tiles_cull_behind_and_far_and_merge_runs():
    from app.sim.camera import Camera
    rng = np.random.default_rng(0)
    roots = np.column_stack([rng.uniform(-40, 40, 5000), np.zeros(5000),
                             rng.uniform(-40, 40, 5000)])
    tiles = gs.make_tiles(roots, 0.6)
    assert tiles.count.sum() == 5000
    assert np.array_equal(np.sort(tiles.order), np.arange(5000))
    sorted_roots = roots[tiles.order]
    for k in range(len(tiles.start)):
        chunk = sorted_roots[tiles.start[k]:tiles.start[k] + tiles.count[k]]
        assert np.all(chunk >= tiles.lo[k]) and np.all(chunk <= tiles.hi[k])
    cam = Camera(position=(0.0, 1.5, 0.0), yaw=0.0, pitch=-10.0, fov=60.0, near=0.1, far=500.0)
    vp = cam.projection_matrix(16 / 9) @ cam.view_matrix()
    lods = gs.tile_lods(tiles, vp, cam.position, 10.0, 30.0)
    centres = (tiles.lo + tiles.hi) / 2
    assert np.all(lods[centres[:, 2] > 12.0] == -1)  # behind the camera (it looks to −z)
    assert np.all(lods[np.abs(centres[:, 0]) + np.abs(centres[:, 2]) > 60] == -1)  # far
    assert (lods == 0).any() and (lods == 1).any()
    runs = gs.draw_runs(tiles, lods, 1)
    assert sum(c for _, c in runs) == tiles.count[lods == 1].sum()
    assert all(a[0] + a[1] < b[0] for a, b in zip(runs, runs[1:]))  # merged, disjoint


# ---- the wind ---------------------------------------------------------------------------------
def test_wind_from_the_slot_and_own_parameters():
    w = gs.grass_wind(np.array([0.0, -10.0]), 0.0, 0.0)
    assert w.intensity == pytest.approx(0.5) and np.allclose(w.direction, (0, 0, -1))
    assert gs.grass_wind(np.array([40.0, 0.0]), 0.0, 0.0).intensity == 1.0
    calm = gs.grass_wind(np.array([0.0, 0.0]), 0.0, 0.0)
    assert calm.intensity == 0.0 and np.isfinite(calm.direction).all()
    own = gs.grass_wind(None, 90.0, 0.5)
    assert np.allclose(own.direction, (1, 0, 0)) and own.intensity == 0.5
    assert own.speed == pytest.approx(10.0)
    with pytest.raises(ValueError, match="not finite"):
        gs.grass_wind(np.array([np.nan, 0.0]), 0.0, 0.0)

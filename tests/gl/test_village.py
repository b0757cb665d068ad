"""The village scene's own effect (spec/003 §1): the lamps light at night and not at noon, the
windows glow at night, the sun's shadow falls away from the sun, the cameras walk the hero,
the slots the grass, the water and the markers read are filled."""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.render.shadow_maps import ShadowProbe
from app.runtime import open_session, scene_params
from app.sim.camera import Camera

SIZE = (96, 54)
#: a light village for the tests: a coarser island, no MSAA
LIGHT = ["village.resolution=65", "village.msaa=0"]


@pytest.fixture(scope="module")
def village(gl_ctx):
    s = open_session("village", scene_params("village", sets=LIGHT), ctx=gl_ctx)
    target = s.gpu.target("test", "image", SIZE)
    defaults = dict(s.params.values())
    yield s, target, defaults
    s.release()


def _render(village, **values):
    s, target, defaults = village
    for name, value in defaults.items():
        s.params.set(name, value)
    for name, value in values.items():
        s.params.set(name.replace("__", "."), value)
    frame = s.scene.frame(SIZE, 0.0)
    s.scene.render(frame, target)
    return target.read()[..., :3], frame


def test_the_frame_slots_are_filled(village):
    img, frame = _render(village)
    assert np.isfinite(img).all()
    assert frame.terrain is not None and frame.terrain.sea_level == 0.0
    names = {n.name for n in frame.npcs}
    assert {"Lord Barus", "the vendor"} <= names
    for npc in frame.npcs:
        x, y, z = npc.head
        assert y > frame.terrain.height(x, z) + 1.5


@pytest.mark.parametrize("hour, lit", [(12.0, False), (23.0, True)])
def test_the_lamps_light_at_night_and_not_at_noon(village, hour, lit):
    bright, _ = _render(village, time__hour=hour)
    dark, _ = _render(village, time__hour=hour, village__lamp_intensity=0.0,
                      village__window_glow=0.0)
    s = village[0]
    assert s.scene.effect("village").lights_on is lit
    changed = np.abs(bright - dark).max()
    if lit:
        assert changed > 0.02
        assert bright.mean() > dark.mean()
    else:
        assert changed == 0.0


def test_the_lamps_always_on_when_not_by_the_hour(village):
    _render(village, time__hour=12.0, village__lamps_auto=False)
    assert village[0].scene.effect("village").lights_on


def test_the_bonfire_flickers(village):
    s, target, _ = village
    _render(village, time__hour=23.0)
    lights = [s.scene.effect("village").point_lights[-1][1]]
    s.scene.frame(SIZE, 0.37)
    lights.append(s.scene.effect("village").point_lights[-1][1])
    assert lights[0] != lights[1]


def test_the_sun_shadow_falls_away_from_the_sun(village, gl_ctx):
    s, _, _ = village
    img_on, frame = _render(village, time__hour=16.0)
    img_off, _ = _render(village, time__hour=16.0, village__shadow_sun=False)
    assert np.abs(img_on - img_off).max() > 0.02
    _render(village, time__hour=16.0)
    effect = s.scene.effect("village")
    sun = np.asarray(s.scene.last_frame.main_light.direction)
    assert sun[1] > 0.2
    hx, hz, _ = effect.hero()
    away = -sun[[0, 2]] / np.linalg.norm(sun[[0, 2]])
    pts, normals = [], []
    for side in (1.0, -1.0):  # 0.6 m from the hero's feet, away from the sun and toward it
        x, z = hx + side * 0.6 * away[0], hz + side * 0.6 * away[1]
        pts.append((x, effect.ground(x, z) + 0.02, z))
        normals.append(tuple(effect.island.normal(x, z)))
    view = s.scene.camera.view_matrix()
    depth = [-(view @ (*p, 1.0))[2] for p in pts]
    vis, _ = ShadowProbe(s.gpu, "test").visibility(effect.shadows, pts, normals, depth)
    assert vis[0] < 0.5 < vis[1]


def test_first_person_hides_the_hero_at_eye_height(village):
    s, _, _ = village
    _render(village, village__camera="first")
    effect = s.scene.effect("village")
    hx, hz, heading = effect.hero()
    cam = s.scene.camera
    assert cam.position[0] == pytest.approx(hx) and cam.position[2] == pytest.approx(hz)
    assert cam.position[1] == pytest.approx(effect.ground(hx, hz) + 1.62, abs=0.01)
    assert cam.yaw == pytest.approx(heading)
    assert not effect.hero_visible
    assert all(k != "hero" for k in effect._people if effect._people[k] in effect.people())
    _render(village, village__camera="third")
    assert effect.hero_visible
    assert math.hypot(cam.position[0] - hx, cam.position[2] - hz) == pytest.approx(6.0, abs=0.1)


def test_the_fly_keys_walk_the_hero_in_third_person(village):
    s, _, _ = village
    _render(village, village__camera="third", village__hero_heading=0.0)
    effect = s.scene.effect("village")
    x0, z0, _ = effect.hero()
    s.scene.camera.move(forward=2.0)  # what W does in the window
    s.scene.frame(SIZE, 0.1)
    x1, z1, heading = effect.hero()
    step = 2.0 * math.cos(math.radians(s.scene.camera.pitch))  # the horizontal part of W's step
    assert (x1 - x0, z1 - z0) == pytest.approx((0.0, -step), abs=1e-6)  # heading 0: north
    s.scene.camera.rotate(90.0, 0.0)  # looking around turns the hero
    s.scene.frame(SIZE, 0.1)
    assert effect.hero()[2] == pytest.approx(90.0)


def test_the_hero_does_not_walk_into_the_sea(village):
    s, _, _ = village
    _render(village, village__camera="first", village__hero_z=46.0)
    effect = s.scene.effect("village")
    start = effect.hero()
    for _ in range(8):
        s.scene.camera.set(yaw=180.0)
        s.scene.camera.move(forward=3.0)  # south, toward the beach and the sea
        s.scene.frame(SIZE, 0.1)
    x, z, _ = effect.hero()
    assert z > start[1]  # walked onto the beach
    assert effect.island.ground(x, z) > -0.3  # and stopped at the water


def test_the_toon_look_changes_the_image(village):
    plain, _ = _render(village, village__toon=0)
    stepped, _ = _render(village, village__toon=2)
    assert np.abs(plain - stepped).max() > 0.05


def test_a_free_camera_sees_the_island_from_above(village):
    s, _, _ = village
    s.scene.camera.set(position=(0.0, 80.0, 0.1), pitch=-89.0, yaw=0.0)
    img, _ = _render(village, village__camera="free", fog__mode="off")
    assert s.scene.camera.position == (0.0, 80.0, 0.1)
    assert np.isfinite(img).all()
    green = (img[..., 1] > img[..., 0]) & (img[..., 1] > img[..., 2])
    assert green.mean() > 0.2  # the meadow fills much of the view


def test_a_stereo_pair_in_vr(gl_ctx):
    cam = Camera(position=(0.0, 3.0, 24.0), yaw=0.0, pitch=-8.0)
    s = open_session("village", scene_params("village", sets=[*LIGHT, "vr.enabled=true"]),
                     ctx=gl_ctx, camera=cam)
    try:
        target = s.gpu.target("test", "pair", (96, 40))
        s.scene.render(s.scene.frame((96, 40)), target)
        img = target.read()[..., :3]
        left, right = img[:, :48], img[:, 48:]
        assert np.isfinite(img).all()
        assert np.abs(left - right).max() > 0.01
        assert s.scene.camera_mode() == "first"  # the third person becomes the first in VR
    finally:
        s.release()


# ---- what the frame does not need: the same picture for less work -----------------------------
def test_the_specialised_surface_shader_draws_the_same_image(village):
    """village.specialise compiles the lighting model, toon mode and parallax method in as
    constants, and each material (terrain, walls, solids, lamps) into a program of its own: the
    same image as the one program of uniforms, for the default look and another."""
    for look in ({}, {"village__lighting_model": 1, "village__toon": 0,
                      "village__parallax_mode": 3}):
        generic, _ = _render(village, village__specialise="never", **look)
        special, _ = _render(village, village__specialise="always", **look)
        assert generic.std() > 0.01
        assert np.abs(generic - special).max() < 1e-5
    default, _ = _render(village)
    other, _ = _render(village, village__lighting_model=1, village__toon=0,
                       village__parallax_mode=3, village__specialise="always")
    assert np.abs(default - other).max() > 0.02  # the constants follow the parameters


def test_the_depth_prepass_and_the_terrain_chunks_draw_the_same_image(village):
    """The depth pre-pass (shading each visible pixel once) and the terrain drawn by culled
    chunks, front to back, each with the lamps that reach it: the picture of the single forward
    pass of the whole island, at night with the lamps lit and by day."""
    for hour in (9.0, 23.0):
        plain, _ = _render(village, time__hour=hour, village__depth_prepass=False,
                           village__terrain_culling=False)
        fast, _ = _render(village, time__hour=hour)
        drawn = village[0].scene.effect("village").last
        assert 0 < drawn["terrain_chunks"] < drawn["chunks"]  # some of the island is culled
        diff = np.abs(plain - fast).max(axis=-1)
        assert np.mean(diff > 2.0 / 255.0) < 0.002, hour

"""The toon water (spec/003 §2.10) swept where it could fail: the camera under the water,
exactly at its surface and a hair either side of it (the near plane straddling it), looking
straight down from 5 cm to 500 m, grazing views at the horizon, no environment, light, fog or
terrain, the tide lifting the water over the camera, the parameters at their ends, a large
time, tiny and huge near and far planes, targets of 1 × 1 and odd sizes; and the village
scene with the camera under, at and over the sea. Every image: no NaN or Inf, no negative
value, bounded; under the water the image is the water's colour, not the sky's."""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.bench.village_water import WaterRig, gradient_environment, seabed
from app.gpu.device import Gpu
from app.runtime import open_session, render_frames, scene_params
from app.sim import toon_water as tw
from app.sim.camera import Camera
from app.sim.daynight import Light

SIZE = (64, 36)
SUN = Light("sun", np.array([0.3, 0.8, -0.52]) / np.linalg.norm([0.3, 0.8, -0.52]),
            (1.0, 0.95, 0.9), 1.2, (0.2, 0.3, 0.45))
COLOUR = (0.05, 0.3, 0.36)


@pytest.fixture(scope="module")
def env(module_gpu):
    e = gradient_environment(module_gpu, "stability-water-sky")
    yield e
    module_gpu.free(e.cube)


@pytest.fixture
def rig(module_gpu):
    r = WaterRig(module_gpu, SIZE, owner="stability-water")
    yield r
    r.release()


def _check(img: np.ndarray, what) -> None:
    assert np.isfinite(img).all(), what
    assert img.min() >= 0.0, what
    assert img[..., :3].max() < 20.0, what  # sky ≤ 1, lit colour ≤ 2, highlight ≤ 4·1.2


def _lit(light: Light = SUN) -> np.ndarray:
    return tw.water_light(COLOUR, light.direction, light.radiance, light.ambient)


@pytest.mark.parametrize("pitch", [-60.0, 0.0, 30.0, 89.0])
def test_camera_under_the_water_sees_the_water_colour(rig, env, pitch):
    cam = Camera(position=(0.0, -3.0, 0.0), yaw=20.0, pitch=pitch, fov=70.0, near=0.1,
                 far=2000.0)
    rig.set(color=COLOUR, tide_height=0.0)
    img = rig.render(cam, seabed(cam, SIZE, y0=-12.0), time=1.0, light=SUN,
                     environment=env)[..., :3]
    _check(img, pitch)
    # 3 m of water or more on every ray: at least 1 − e^(−0.535·3) = 80 % the water's colour
    lit = _lit()
    assert np.abs(img - lit).max() < 0.2 * max(1.0, float(np.abs(img).max()))
    assert np.linalg.norm(img - lit, axis=-1).mean() < 0.15
    rig.set(output=1)  # no reflection from below
    refl = rig.render(cam, seabed(cam, SIZE, y0=-12.0), time=1.0, light=SUN,
                      environment=env)[..., :3]
    surface = rig.depth() < 1.0
    if pitch > 0:
        assert surface.any()
        assert refl[surface].max() == 0.0


@pytest.mark.parametrize("offset", [0.0, 1e-4, -1e-4, 0.05, -0.05])
def test_camera_at_the_surface_splits_the_image(rig, env, offset):
    cam = Camera(position=(0.0, offset, 0.0), yaw=0.0, pitch=0.0, fov=60.0, near=0.1,
                 far=2000.0)
    rig.set(color=COLOUR, tide_height=0.0)
    bd = seabed(cam, SIZE, y0=-6.0, sky=(0.5, 0.6, 0.9))
    img = rig.render(cam, bd, time=0.5, light=SUN, environment=env)[..., :3]
    _check(img, offset)
    h = SIZE[1]
    lit = _lit()
    top, bottom = img[: h // 2 - 2], img[h // 2 + 2:]
    assert np.linalg.norm(bottom - lit, axis=-1).mean() < 0.1  # under: the water's colour
    if offset >= 0.0:  # over or at it: the sky above the horizon, untouched
        assert np.abs(top - [0.5, 0.6, 0.9]).max() < 1e-5
    else:  # a hair under: the surface seen from below, the sky through the water above it
        d = cam.ray_directions(*SIZE)[: h // 2 - 2]
        up = d[..., 1] > 0.05
        t = -offset / np.where(up, d[..., 1], 1.0)
        # a surface nearer than the near plane is clipped: those rays start in the air
        w = np.where(t * (d @ cam.forward()) > cam.near, tw.fog_weight_thickness(t, 0.535), 0.0)
        want = tw.water_refraction(np.broadcast_to([0.5, 0.6, 0.9], top.shape), lit, 1.0, w)
        assert np.abs(top - want)[up].max() < 2.0 / 255.0


@pytest.mark.parametrize("height", [0.05, 1.0, 30.0, 500.0])
def test_looking_straight_down(rig, env, height):
    cam = Camera(position=(3.0, height, -2.0), yaw=0.0, pitch=-90.0, fov=60.0, near=0.01,
                 far=2000.0)
    for kind in ("simple", "complex"):
        rig.set(type=kind)
        img = rig.render(cam, seabed(cam, SIZE, y0=-4.0), time=2.0, light=SUN,
                         environment=env)
        _check(img, (height, kind))
        assert (rig.depth() < 1.0).all()  # water under every pixel


@pytest.mark.parametrize("height,pitch", [(0.01, 0.0), (0.01, -0.5), (2.0, 0.0),
                                          (2.0, -0.5), (2.0, 2.0), (0.3, -0.05)])
def test_grazing_views(rig, env, height, pitch):
    cam = Camera(position=(0.0, height, 0.0), yaw=135.0, pitch=pitch, fov=50.0, near=0.1,
                 far=2000.0)
    rig.set(tide_height=0.0)  # the camera stays over the water
    for kind in ("simple", "complex"):
        for method in tw.FOG_METHODS:
            rig.set(type=kind, fog_method=method)
            img = rig.render(cam, seabed(cam, SIZE, y0=-2.0, slope=(0.0, 0.0)), time=3.0,
                             light=SUN, environment=env)
            _check(img, (height, pitch, kind, method))
    # within 3° of the horizon the Complex water is mostly its reflection
    rig.set(type="complex", highlight=0.0, output=3)
    f = rig.render(cam, seabed(cam, SIZE, y0=-2.0, slope=(0.0, 0.0)), time=3.0, light=SUN,
                   environment=env)[..., 0]
    grazing = (rig.depth() < 1.0) & (cam.ray_directions(*SIZE)[..., 1] > -math.sin(
        math.radians(3.0)))
    if grazing.any():
        assert np.median(f[grazing]) > 0.5


def test_no_environment_light_fog_or_terrain(rig):
    cam = Camera(position=(0.0, 3.0, 0.0), yaw=0.0, pitch=-30.0, fov=60.0)
    for kind in ("simple", "complex"):
        rig.set(type=kind)
        img = rig.render(cam, seabed(cam, SIZE), light=None, environment=None, fog=None,
                         terrain=None)
        _check(img, kind)
        assert (rig.depth() < 1.0).mean() > 0.4


def test_the_tide_over_the_camera(rig, env):
    """Tide Height 20 m at t = π/2 puts the water 15 m over a camera 5 m up: under water."""
    cam = Camera(position=(0.0, 5.0, 0.0), yaw=0.0, pitch=-20.0, fov=60.0, near=0.1,
                 far=2000.0)
    rig.set(tide_height=20.0, color=COLOUR)
    img = rig.render(cam, seabed(cam, SIZE, y0=-3.0), time=math.pi / 2, light=SUN,
                     environment=env)[..., :3]
    _check(img, "tide")
    assert rig.effect.underwater and rig.effect.level == pytest.approx(20.0)
    assert np.linalg.norm(img - _lit(), axis=-1).mean() < 0.1


@pytest.mark.parametrize("values", [
    dict(wave_intensity=1.0, wave_scale=10.0, water_speed=0.25, toon_value=0.01),
    dict(wave_intensity=0.0, wave_scale=1.0, water_speed=0.01, toon_value=0.2),
    dict(water_fog_intensity=0.0, refraction=0.0, band_strength=2.0, highlight=4.0,
         highlight_exponent=1.0),
    dict(water_fog_intensity=1.0, highlight_exponent=4000.0, wave_tile=1.0, flip_y=True),
    dict(color=(8.0, 8.0, 8.0), tide_height=20.0),
])
def test_parameters_at_their_ends(rig, env, values):
    cam = Camera(position=(0.0, 30.0, 0.0), yaw=0.0, pitch=-30.0, fov=60.0)
    rig.set(**values)
    for kind in ("simple", "complex"):
        for output in range(5):
            rig.set(type=kind, output=output)
            img = rig.render(cam, seabed(cam, SIZE), time=1e5, light=SUN, environment=env)
            assert np.isfinite(img).all() and img.min() >= 0.0, (values, kind, output)
            assert img[..., :3].max() < 100.0


@pytest.mark.parametrize("near,far", [(0.001, 100000.0), (1.0, 5.0), (0.1, 2000.0)])
def test_near_and_far_planes(rig, env, near, far):
    cam = Camera(position=(0.0, 2.0, 0.0), yaw=0.0, pitch=-10.0, fov=90.0, near=near, far=far)
    for method in tw.FOG_METHODS:
        rig.set(fog_method=method)
        img = rig.render(cam, seabed(cam, SIZE), time=1.0, light=SUN, environment=env)
        _check(img, (near, far, method))


@pytest.mark.parametrize("size", [(1, 1), (7, 3), (2, 9)])
def test_tiny_and_odd_targets(gl_ctx, size):
    module_gpu = Gpu(gl_ctx)
    r = WaterRig(module_gpu, size, owner="stability-water-tiny")
    try:
        cam = Camera(position=(0.0, 3.0, 0.0), yaw=0.0, pitch=-45.0, fov=60.0)
        img = r.render(cam, seabed(cam, size), light=SUN)
        _check(img, size)
    finally:
        r.release()
        module_gpu.release()


def test_numpy_twins_at_the_ends():
    d = np.array([0.0, 1e-9, 0.5, 1.0 - 1e-9, 1.0, -1.0, 2.0])
    for near, far in ((0.1, 2000.0), (1e-4, 1e6)):
        z = tw.view_depth(d, near, far)
        assert np.isfinite(z).all() and z.min() >= near * 0.999 and z.max() <= far * 1.001
        for method in tw.FOG_METHODS:
            w = tw.depth_fog_weight(method, d, z[::-1], 1.0, 1.0, near, far)
            assert np.isfinite(w).all() and w.min() >= 0.0 and w.max() <= 1.0
    assert np.isfinite(tw.fog_weight_thickness(np.array([1e30, -1e30, 0.0]), 1.0)).all()
    n = tw.wave_normal(np.zeros(4), np.ones(4), 1.0)  # the most tilted texels
    assert np.isfinite(n).all() and n[1] >= 0.0


@pytest.fixture(scope="module")
def village(gl_ctx):
    s = open_session("village", scene_params("village", sets=["village.camera=free",
                                                               "village.msaa=0"]), ctx=gl_ctx)
    yield s
    s.release()


@pytest.mark.parametrize("y,pitch", [(-2.0, 10.0), (0.0, 0.0), (0.02, -2.0), (12.0, -40.0)])
def test_the_village_under_at_and_over_the_sea(village, y, pitch):
    village.scene.camera = Camera(position=(0.0, y, 80.0), yaw=0.0, pitch=pitch, fov=60.0,
                                  near=0.1, far=2000.0)
    village.params.set("toon_water.tide_height", 0.0)
    img = next(iter(render_frames(village, (64, 36), 1, 30.0)))
    _check(img, (y, pitch))

"""The Preetham analytic sky (spec/001 §1.8) on small float targets: the shader against its numpy
twin (app/sim/preetham.py) per pixel, and the sky's physical behaviour.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.effects.preetham.effect import Preetham
from app.effects.sky.effect import Sky
from app.frame import FrameContext
from app.gpu.device import Gpu
from app.params import ParamSet
from app.sim import preetham as model
from app.sim.camera import Camera
from tests.helpers.preetham import SIZE, render

# ---- the shader against the twin -----------------------------------------------------------------

@pytest.mark.parametrize("elev,az,turbidity", [(60.0, 135.0, 2.0), (8.0, 250.0, 6.0),
                                               (90.0, 0.0, 10.0), (0.0, 90.0, 3.0),
                                               (-3.0, 200.0, 2.5), (-30.0, 10.0, 2.5)])
def test_shader_matches_numpy_per_pixel(preetham_rig, elev, az, turbidity):
    sun = model.sun_direction(elev, az)
    if elev == 90.0:
        sun = np.array([0.0, 1.0, 0.0])  # exactly overhead
    cam = Camera(position=(0, 2, 0), fov=100.0).look_at_direction(
        model.sun_direction(max(elev, 0) * 0.5 + 10, az))
    img, twin, _ = render(preetham_rig, cam, {"preetham.turbidity": turbidity,
                                     "preetham.sun_disk_radius": 3.0}, sun=sun)
    assert np.isfinite(img).all()
    err = np.abs(img - twin)
    # the disk's edge may differ by a texel
    assert (err <= 2e-3 * np.abs(twin) + 1e-6).mean() > 0.995
    assert err.max() <= 0.02 * max(twin.max(), 1e-6)



@pytest.mark.parametrize("elev,az,turbidity,own_sun", [(50.0, 200.0, 2.5, True),
                                                       (6.0, 30.0, 4.0, True),
                                                       (25.0, 300.0, 2.0, False),
                                                       (-3.0, 120.0, 2.5, True)])
def test_sea_matches_numpy_per_pixel(preetham_rig, elev, az, turbidity, own_sun):
    """preetham.ground = sea: the shared sea plane reflecting this sky, against the twin; the
    camera looks down toward the sun's glitter, from 40 m."""
    sun = model.sun_direction(elev, az)
    cam = Camera(position=(0, 40, 0), fov=80.0).look_at_direction(
        model.sun_direction(-20.0, az + 15.0))
    sets = {"preetham.turbidity": turbidity, "preetham.ground": "sea",
            "preetham.sea_wind": 3.0}
    if own_sun:
        sets |= {"preetham.sun_elevation": elev, "preetham.sun_azimuth": az}
    img, _, frame = render(preetham_rig, cam, sets, sun=None if own_sun else sun)
    twin = preetham_rig[2].radiance_numpy(cam.ray_directions(*SIZE), eye_height=40.0)
    assert np.isfinite(img).all()
    below = cam.ray_directions(*SIZE)[..., 1] < 0.0
    assert below.mean() > 0.5
    err = np.abs(img - twin)
    assert (err <= 2e-3 * np.abs(twin) + 1e-5).mean() > 0.995, err.max()
    assert err.max() <= 0.02 * max(twin.max(), 1e-6)
    # the sea is not the clamped horizon colour: it changes down the image
    if elev > 0:
        assert np.abs(np.diff(img[below.all(axis=1)].mean(axis=1), axis=0)).max() > 1e-3
    # the light is the frame's main light (the clouds' light)
    sea = preetham_rig[2].sea(40.0)
    assert np.allclose(sea.light_radiance, frame.main_light.radiance)


def test_reddening_toward_sunset(preetham_rig):
    ratios, suns = [], []
    for elev in (60.0, 30.0, 10.0, 3.0):
        cam = Camera(position=(0, 2, 0), fov=60.0).look_at_direction(
            model.sun_direction(12.0, 270.0))
        img, _, frame = render(preetham_rig, cam, {"preetham.sun_elevation": elev,
                                          "preetham.sun_azimuth": 270.0,
                                          "preetham.sun_disk": False})
        low = img[-6:].reshape(-1, 3).mean(axis=0)  # the band just above the horizon toward the sun
        ratios.append(low[0] / low[2])
        suns.append(frame.main_light.color[0] / max(frame.main_light.color[2], 1e-12))
    assert all(b > a for a, b in zip(ratios, ratios[1:])), ratios
    assert all(b > a for a, b in zip(suns, suns[1:])), suns


def test_symmetric_about_the_sun_azimuth_plane(preetham_rig):
    az = 63.0
    cam = Camera(position=(0, 2, 0), yaw=az, pitch=20.0, fov=90.0)
    img, _, _ = render(preetham_rig, cam,
                       {"preetham.sun_elevation": 25.0, "preetham.sun_azimuth": az})
    mirrored = img[:, ::-1]
    assert np.abs(img - mirrored).max() <= 1e-4 * img.max()
    assert np.abs(img[:, 0] - img[:, SIZE[0] // 2]).max() > 1e-3  # and not trivially flat


def test_sets_the_lights_only_when_no_sky_did(gl_ctx):
    gpu = Gpu(gl_ctx)
    try:
        params = ParamSet(Sky.declare(gpu.shaders) + Preetham.declare(gpu.shaders))
        params.set("time.hour", 9.0)
        sky, pre = Sky(gpu, params), Preetham(gpu, params)
        frame = FrameContext(size=SIZE, camera=Camera())
        sky.update(frame, 0.0)
        from_sky = frame.sun
        pre.update(frame, 0.0)
        assert frame.sun is from_sky and not pre.owns_sun
        assert np.allclose(pre.sun_direction, from_sky.direction)
        alone = FrameContext(size=SIZE, camera=Camera())
        params.set("preetham.sun_elevation", 30.0)
        params.set("preetham.sun_azimuth", 90.0)
        pre.update(alone, 0.0)
        assert pre.owns_sun and alone.main_light is alone.sun
        assert np.allclose(alone.sun.direction, [math.cos(math.radians(30)), 0.5, 0.0], atol=1e-12)
        assert alone.sun.intensity == pytest.approx(1.0)
    finally:
        gpu.release()


def test_sea_ambient_is_integrated_only_when_the_sun_or_turbidity_change(preetham_rig):
    fx = preetham_rig[2]
    cam = Camera(position=(0, 10, 0), pitch=-10.0)
    sets = {"preetham.ground": "sea", "preetham.sun_elevation": 33.0}
    render(preetham_rig, cam, sets)
    builds = fx._ambient.builds
    render(preetham_rig, cam, sets | {"preetham.exposure": 0.1, "preetham.sea_wind": 9.0})
    render(preetham_rig, Camera(position=(5, 80, 0), yaw=90.0), sets)
    assert fx._ambient.builds == builds
    render(preetham_rig, cam, sets | {"preetham.turbidity": 4.0})
    render(preetham_rig, cam, sets | {"preetham.sun_elevation": 20.0})
    assert fx._ambient.builds == builds + 2

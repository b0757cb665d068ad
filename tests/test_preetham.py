"""The Preetham analytic sky (spec/001 §1.8; Preetham, Shirley & Smits 1999) on small float
targets: the shader against its numpy twin (app/sim/preetham.py) per pixel, the twin against
values worked by hand from the paper's appendix A.2 constants (the paper prints the formulas
and constants, not tables of results), and the sky's physical behaviour.
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
from app.sim.daynight import Light

SIZE = (48, 32)


@pytest.fixture(scope="module")
def rig(gl_ctx):
    gpu = Gpu(gl_ctx)
    params = ParamSet(Preetham.declare(gpu.shaders))
    fx = Preetham(gpu, params)
    target = gpu.target("test", "preetham", SIZE)
    yield gpu, params, fx, target
    gpu.release()


def render(rig, cam: Camera, sets: dict, sun=None):
    gpu, params, fx, target = rig
    for k in list(params):
        if k.group == "preetham":
            params.set(k.name, k.default)
    for k, v in sets.items():
        params.set(k, v)
    frame = FrameContext(size=SIZE, camera=cam)
    if sun is not None:
        frame.sun = frame.main_light = Light("sun", np.asarray(sun, float), (1.0, 1.0, 1.0), 1.0)
    fx.update(frame, 0.0)
    target.clear()
    fx.render(frame, target)
    return target.read()[..., :3], fx.radiance_numpy(cam.ray_directions(*SIZE)), frame


# ---- the paper's formulas -----------------------------------------------------------------------

def test_zenith_formulas_against_hand_worked_values():
    # Y_z = (4.0453 T − 4.9710) tan χ − 0.2155 T + 2.4192, χ = (4/9 − T/120)(π − 2θs)
    # T = 2, θs = 0: χ = 0.427778 π = 1.343904, tan χ = 4.331476 → 3.1196 · 4.331476 + 1.9882
    assert model.zenith_luminance(2.0, 0.0) == pytest.approx(15.50067, abs=1e-4)
    # θs = 90°: χ = 0, so Y_z = 2.4192 − 0.2155 T exactly
    for t in (2.0, 5.0, 10.0):
        assert model.zenith_luminance(t, math.pi / 2) == pytest.approx(2.4192 - 0.2155 * t, abs=1e-12)
    # x_z, y_z at θs = 0 are the last column: [T² T 1]·(0, 0.00394, 0.25886) and (0, 0.00516, 0.26688)
    assert model.zenith_chromaticity(2.0, 0.0) == pytest.approx([2 * 0.00394 + 0.25886, 2 * 0.00516 + 0.26688])
    # θs = 1 rad: the row sums; T² row of M_x sums to 0 → x_z = 2·0.00666 + 0.22435
    assert model.zenith_chromaticity(2.0, 1.0)[0] == pytest.approx(0.23767, abs=1e-9)
    # Perez coefficients at T = 2 (A_Y = 0.1787·2 − 1.4630, …)
    k = model.perez_coefficients(2.0)
    assert k[0] == pytest.approx([-1.1056, -0.2833, 5.2797, -2.3359, 0.2363])
    assert k[1][0] == pytest.approx(-0.2978) and k[2][3] == pytest.approx(-1.7419)


def test_zenith_of_the_distribution_is_the_zenith_value():
    # eq. 4 at θ = 0: F(0, θs)/F(0, θs) = 1, so the sky at the zenith is (x_z, y_z, Y_z)
    for t, elev in ((2.0, 70.0), (4.5, 30.0), (10.0, 5.0)):
        sun = model.sun_direction(elev, 123.0)
        xyY = model.sky_xyY(np.array([0.0, 1.0, 0.0]), sun, t)
        ts = math.radians(90.0 - elev)
        assert xyY[:2] == pytest.approx(model.zenith_chromaticity(t, ts), rel=1e-9)
        assert xyY[2] == pytest.approx(model.zenith_luminance(t, ts), rel=1e-9)


def test_xyY_to_srgb_white_point():
    # D65 white (x, y) = (0.3127, 0.3290) at Y = 1 maps to RGB ≈ (1, 1, 1)
    rgb = model.XYZ_to_linear_srgb(model.xyY_to_XYZ(np.array([0.3127, 0.3290, 1.0])))
    assert rgb == pytest.approx([1.0, 1.0, 1.0], abs=2e-3)


# ---- the shader against the twin ------------------------------------------------------------------

@pytest.mark.parametrize("elev,az,turbidity", [(60.0, 135.0, 2.0), (8.0, 250.0, 6.0), (90.0, 0.0, 10.0),
                                               (0.0, 90.0, 3.0), (-3.0, 200.0, 2.5), (-30.0, 10.0, 2.5)])
def test_shader_matches_numpy_per_pixel(rig, elev, az, turbidity):
    sun = model.sun_direction(elev, az)
    if elev == 90.0:
        sun = np.array([0.0, 1.0, 0.0])  # exactly overhead
    cam = Camera(position=(0, 2, 0), fov=100.0).look_at_direction(model.sun_direction(max(elev, 0) * 0.5 + 10, az))
    img, twin, _ = render(rig, cam, {"preetham.turbidity": turbidity, "preetham.sun_disk_radius": 3.0}, sun=sun)
    assert np.isfinite(img).all()
    err = np.abs(img - twin)
    assert (err <= 2e-3 * np.abs(twin) + 1e-6).mean() > 0.995  # the disk's edge may differ by a texel
    assert err.max() <= 0.02 * max(twin.max(), 1e-6)


# ---- behaviour ----------------------------------------------------------------------------------

def test_bluer_at_zenith_than_horizon_at_noon():
    sun = model.sun_direction(75.0, 180.0)
    zen = model.sky_radiance(np.array([0.0, 1.0, 0.0]), sun, 2.5)
    hor = model.sky_radiance(model.sun_direction(1.0, 0.0), sun, 2.5)  # horizon, away from the sun

    def blue(c):
        return c[2] / c.sum()

    assert blue(zen) > blue(hor) + 0.05


def test_reddening_toward_sunset(rig):
    ratios, suns = [], []
    for elev in (60.0, 30.0, 10.0, 3.0):
        cam = Camera(position=(0, 2, 0), fov=60.0).look_at_direction(model.sun_direction(12.0, 270.0))
        img, _, frame = render(rig, cam, {"preetham.sun_elevation": elev, "preetham.sun_azimuth": 270.0,
                                          "preetham.sun_disk": False})
        low = img[-6:].reshape(-1, 3).mean(axis=0)  # the band just above the horizon toward the sun
        ratios.append(low[0] / low[2])
        suns.append(frame.main_light.color[0] / max(frame.main_light.color[2], 1e-12))
    assert all(b > a for a, b in zip(ratios, ratios[1:])), ratios
    assert all(b > a for a, b in zip(suns, suns[1:])), suns


def test_symmetric_about_the_sun_azimuth_plane(rig):
    az = 63.0
    cam = Camera(position=(0, 2, 0), yaw=az, pitch=20.0, fov=90.0)
    img, _, _ = render(rig, cam, {"preetham.sun_elevation": 25.0, "preetham.sun_azimuth": az})
    mirrored = img[:, ::-1]
    assert np.abs(img - mirrored).max() <= 1e-4 * img.max()
    assert np.abs(img[:, 0] - img[:, SIZE[0] // 2]).max() > 1e-3  # and not trivially flat


@pytest.mark.parametrize("elev", [-90.0, -45.0, -6.0, -3.0, -0.01, 0.0])
def test_sun_below_horizon_no_nan_and_fades(rig, elev):
    cam = Camera(position=(0, 2, 0), yaw=0.0, pitch=0.0, fov=120.0)
    img, twin, frame = render(rig, cam, {"preetham.sun_elevation": elev, "preetham.sun_azimuth": 0.0})
    assert np.isfinite(img).all() and (img >= 0.0).all()
    assert np.allclose(img, twin, rtol=2e-3, atol=1e-6)
    if elev <= -6.0:
        assert img.max() == 0.0
        assert frame.main_light.intensity == 0.0
    assert np.isfinite(frame.main_light.color).all()


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

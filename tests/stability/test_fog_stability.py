"""The fog swept where it could fail (spec/003 §2.11; glsl/common/fog.glsl, glsl/fog/plane.*):
the camera inside the ground fog plane, a hair above and below it, under it looking up, far
above it, with a near plane of 10⁻⁴ m; the linear fog with e = s, the density 0 and at its
largest; the height fog on grazing rays (a camera at the ground looking along a kilometre of
it), with a camera far below its base and far above it, its falloff 0 and large. Every image:
no NaN or Inf, no negative value, bounded — and the height fog's per-pixel factors equal the
twin's at the pixels' world positions. The numpy twin: finite, in [0, 1], and never more
transparent farther along a ray."""

from __future__ import annotations

import math

import moderngl
import numpy as np
import pytest

from app.gpu.programs import ProgramSpec
from app.sim import fog as fs
from app.sim.camera import Camera
from tests.gl.test_fog import TILE, PlaneRig

SURFACE = ProgramSpec("fog/bench_surface")
OWNER = "test-fog-stability"
PLANE_Y = 1.95  # the flat test terrain's 1.6 m plus fog.plane_height's 0.35 m
SIZE = 48


def bounded(img, hi=4.0):
    assert np.isfinite(img).all()
    assert img[..., :3].min() >= 0.0 and img[..., :3].max() <= hi


@pytest.fixture
def rig(gpu):
    r = PlaneRig(gpu, "fog.mode=exp2", "fog.per_pixel=true", size=SIZE)
    yield r
    r.fog.release()


@pytest.mark.parametrize("dy, pitch", [(0.0, 0.0), (0.0, -30.0), (1e-4, 0.0), (-1e-4, 0.0),
                                       (-1e-4, 5.0), (1e-3, -0.01), (-0.2, 60.0), (-10.0, 90.0),
                                       (1000.0, -90.0), (0.5, -1.0)])
def test_plane_from_inside_above_below_and_far(rig, dy, pitch):
    cam = Camera(position=(TILE / 2, PLANE_Y + dy, TILE / 2), yaw=30.0, pitch=pitch, fov=60.0,
                 near=1e-4, far=5000.0)
    for t in (0.0, 4.0 * math.pi, 30.0):
        bounded(rig.render(t, camera=cam))
    assert np.all(rig.target.read_depth() == 1.0)


@pytest.mark.parametrize("sets", [
    ("fog.mode=linear", "fog.start=5", "fog.end=5"),  # e = s: a step
    ("fog.mode=linear", "fog.start=0", "fog.end=0"),
    ("fog.density=0",), ("fog.density=1", "fog.intensity=1", "fog.scale=0.25"),
    ("fog.height=true", "fog.height_falloff=0"), ("fog.height=true", "fog.height_falloff=5",
                                                   "fog.height_base=200"),
    ("fog.intensity=1", "fog.speed=1"), ("fog.plane_height=0",),
])
def test_plane_at_the_parameters_edges(gpu, sets):
    rig = PlaneRig(gpu, "fog.per_pixel=false", *sets, size=SIZE)
    try:
        for t in (0.0, 4.0 * math.pi):
            bounded(rig.render(t))
            bounded(rig.render(t, camera=Camera(position=(TILE / 2, PLANE_Y + 0.01, TILE / 2),
                                                pitch=-60.0, fov=60.0, near=1e-3)))
    finally:
        rig.fog.release()


# ---- the global fog on a large ground -------------------------------------------------------

GROUND = np.array([[-2000, 0, -2000], [2000, 0, -2000], [2000, 0, 2000],
                   [-2000, 0, -2000], [2000, 0, 2000], [-2000, 0, 2000]], "f4")


@pytest.fixture(scope="module")
def ground(gl_ctx):
    from app.gpu.device import Gpu

    gpu = Gpu(gl_ctx)
    size = (96, 64)
    tex = gpu.texture(OWNER, "colour", size, 4, dtype="f4")
    depth = gpu.depth_texture(OWNER, "depth", size)
    fbo = gpu.framebuffer(OWNER, "fbo", [tex], depth)
    vbo = gpu.buffer(OWNER, "ground", GROUND.tobytes())
    prog = gpu.program(OWNER, SURFACE)

    def draw(cfg: fs.FogSettings, cam: Camera) -> np.ndarray:
        aspect = size[0] / size[1]
        prog.set_many({"uViewProj": cam.projection_matrix(aspect) @ cam.view_matrix(),
                       "uObjectColor": (1.0, 1.0, 1.0),
                       **fs.fog_uniforms(cfg, cam.position, cam.near, cam.far)})
        fbo.use()
        fbo.clear(-1.0, -1.0, -1.0, 0.0, depth=1.0)
        gpu.ctx.enable(moderngl.DEPTH_TEST)
        prog.vao([(vbo, "3f", "in_position")]).render(moderngl.TRIANGLES)
        gpu.ctx.disable(moderngl.DEPTH_TEST)
        raw = np.frombuffer(fbo.read(components=4, dtype="f4"), np.float32)
        return raw.reshape(size[1], size[0], 4)[::-1]

    yield draw, size
    gpu.release()


def world_points(cam: Camera, size, w):
    """The ground points behind each pixel, from their view depth w (alpha of the probe)."""
    dirs = cam.ray_directions(*size)
    along = dirs @ cam.forward()
    return np.asarray(cam.position) + dirs * (w / along)[..., None]


CAMERAS = {
    "grazing": Camera(position=(0.0, 0.3, 0.0), yaw=10.0, pitch=0.0, fov=60.0, near=0.05,
                      far=5000.0),
    "at the ground": Camera(position=(0.0, 1e-3, 0.0), yaw=200.0, pitch=-0.5, fov=60.0,
                            near=1e-4, far=5000.0),
    "high above": Camera(position=(0.0, 3000.0, 0.0), yaw=0.0, pitch=-60.0, fov=60.0,
                         near=0.5, far=20000.0),
}


@pytest.mark.parametrize("cam", CAMERAS.values(), ids=CAMERAS.keys())
@pytest.mark.parametrize("a, b, y0", [(0.05, 0.35, 0.0), (0.5, 0.0, 0.0), (0.02, 5.0, 0.0),
                                      (0.05, 0.35, 1000.0), (0.05, 0.35, -1000.0),
                                      (0.0, 0.35, 0.0), (2.0, 1.0, 0.3)])
def test_height_fog_on_a_large_ground_matches_the_twin(ground, cam, a, b, y0):
    draw, size = ground
    cfg = fs.FogSettings(colour=(0.0, 0.0, 0.0), height=True, height_density=a,
                         height_falloff=b, height_base=y0)
    img = draw(cfg, cam)
    seen = img[..., 3] > 0
    assert seen.mean() > 0.2
    f = img[..., 0][seen]
    assert np.isfinite(f).all() and f.min() >= 0.0 and f.max() <= 1.0
    p = world_points(cam, size, img[..., 3])[seen]
    p[:, 1] = 0.0
    want = fs.fog_height_transmittance(p, np.asarray(cam.position), a, b, y0)
    assert np.abs(f - want).max() < 2e-3  # fp32 positions of pixels kilometres away


@pytest.mark.parametrize("cfg", [
    fs.FogSettings(mode="linear", start=5.0, end=5.0),
    fs.FogSettings(mode="linear", start=0.0, end=0.0),
    fs.FogSettings(mode="exp2", density=0.0), fs.FogSettings(mode="exp", density=1e3),
    fs.FogSettings(mode="exp2", density=1e3), fs.FogSettings(mode="exp2", density=0.02),
], ids=["e=s", "e=s=0", "density 0", "exp max", "exp2 max", "exp2"])
@pytest.mark.parametrize("per_pixel", [False, True], ids=["vertex", "pixel"])
@pytest.mark.parametrize("cam", CAMERAS.values(), ids=CAMERAS.keys())
def test_distance_fog_at_the_edges(ground, cfg, per_pixel, cam):
    """Per vertex, a triangle reaching behind the camera interpolates toward its vertex there
    (d clamped to 0, f = 1, as Unity clamps it): bounded, not exact; per pixel, each pixel's
    factor is the twin's at its own depth."""
    draw, size = ground
    img = draw(fs.FogSettings(**{**cfg.__dict__, "colour": (0.0, 0.0, 0.0),
                                 "per_pixel": per_pixel}), cam)
    seen = img[..., 3] > 0
    f = img[..., 0][seen]
    assert seen.mean() > 0.2
    assert np.isfinite(f).all() and f.min() >= 0.0 and f.max() <= 1.0
    if per_pixel:
        d = fs.fog_distance(img[..., 3][seen], cam.near, cam.far)
        want = fs.fog_factor(d, cfg)
        near_step = np.abs(d - cfg.start) < 1e-2 * max(1.0, cfg.start)
        assert np.abs(f - want)[~near_step].max() < 1e-3


# ---- the numpy twin --------------------------------------------------------------------------

def test_twin_height_fog_sweep():
    rng = np.random.default_rng(11)
    for y0 in (-1e4, -10.0, 0.0, 10.0, 1e4):
        for b in (0.0, 1e-6, 0.35, 5.0, 50.0):
            for a in (0.0, 1e-9, 0.05, 100.0):
                o = np.stack([rng.uniform(-1e3, 1e3, 64), rng.choice([-1e4, -1.0, 0.0, 1e-7,
                                                                      3.0, 1e4], 64),
                              rng.uniform(-1e3, 1e3, 64)], -1)
                d = rng.normal(size=(64, 3))
                d[:16, 1] = 0.0  # grazing
                d /= np.linalg.norm(d, axis=-1, keepdims=True)
                ts = np.array([0.0, 1e-6, 1.0, 100.0, 1e6])
                pts = o[:, None, :] + d[:, None, :] * ts[None, :, None]
                tr = fs.fog_height_transmittance(pts, o[:, None, :], a, b, y0)
                assert np.isfinite(tr).all() and tr.min() >= 0.0 and tr.max() <= 1.0
                assert np.all(tr[:, 0] == 1.0)
                # farther along a ray the fog never thins
                assert np.all(np.diff(tr, axis=1) <= 1e-12), (a, b, y0)


def test_twin_distance_sweep():
    for n, f in ((1e-9, 1e-9), (0.0, 10.0), (1e-4, 1e9), (5.0, 5.0), (10.0, 1.0)):
        w = np.array([-1e9, -1.0, 0.0, 1e-6, 1.0, 1e3, 1e12])
        d = fs.fog_distance(w, n, f)
        assert np.isfinite(d).all() and d.min() >= 0.0
        assert np.all(np.diff(d) >= 0.0)

"""VR mode where it could break (spec/003 §2.15): the village's stereo pair at the render
scale's extremes, odd widths, a frame 1 pixel wide or high — finite, bounded, each half filled;
the ring at the extremes of its parameters (Element Size 0 and 1, its centre on the viewport's
edges, Lives 1 and 64, Remaining beyond Lives, a 1 × 1 viewport) — finite, alpha within
[0, Visibility]; the twin swept over every Lives and Remaining; the disparity growing
steadily with the interpupillary distance."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from app.effects.vr import Vr
from app.frame import FrameContext
from app.gpu.device import Gpu
from app.params import ParamSet
from app.render.stereo import StereoRenderer, eye_viewport
from app.runtime import open_session, scene_params
from app.sim import vr
from app.sim.camera import Camera
from tests.gl.test_vr_stereo import HEAD, NEAR_DEPTH, BoxScene, halves
from tests.helpers import measures

VILLAGE_HEAD = Camera(position=(0.0, 3.2, -11.0), yaw=0.0, pitch=-5.0, fov=60.0, near=0.1,
                      far=2000.0)


@pytest.fixture(scope="module")
def village(gl_ctx):
    params = scene_params("village", sets=["village.camera=free", "vr.enabled=true",
                                           "vr.health_ring=always", "vr.markers=always"])
    session = open_session("village", params, ctx=gl_ctx, camera=VILLAGE_HEAD)
    yield session
    session.release()


@pytest.mark.parametrize("size, scale", [
    ((96, 54), 0.25), ((96, 54), 2.0), ((97, 54), 1.0), ((97, 55), 0.75), ((1, 54), 1.0),
    ((2, 54), 0.25), ((96, 1), 1.0), ((3, 3), 2.0),
])
def test_the_village_pair_stays_finite_at_extreme_scales_and_sizes(village, size, scale):
    village.params.set("vr.render_scale", scale)
    target = village.gpu.target("test", "pair", size)
    try:
        frame = village.scene.frame(size, 0.0)
        village.scene.render(frame, target)
        img = target.read()
    finally:
        village.gpu.free(target)
        village.params.reset("vr.render_scale")
    assert img.shape == (size[1], size[0], 4)
    assert np.isfinite(img).all() and img[..., :3].min() >= 0.0 and img[..., :3].max() < 1e4
    shown = [e for e in ("left", "right") if eye_viewport(size, e)[2] > 0]
    assert sorted(village.scene._stereo.last_eyes) == sorted(shown)
    for eye in shown:  # every pixel of each half came from its eye (the copy writes alpha 1)
        x, _, w, _ = eye_viewport(size, eye)
        assert np.all(img[:, x:x + w, 3] == 1.0)
        assert img[:, x:x + w, :3].max() > 0.0


@pytest.fixture(scope="module")
def ring(gl_ctx):
    gpu = Gpu(gl_ctx)
    params = ParamSet(Vr.declare(gpu.shaders))
    params.set("vr.health_ring", "always")
    effect = Vr(gpu, params)

    def draw(size, **sets):
        for k, v in sets.items():
            params.set(k, v)
        target = gpu.target("test", "ring", size)
        try:
            out = []
            for bg in (0.0, 1.0):
                target.clear((bg, bg, bg, 1.0))
                effect.draw_ring(FrameContext(size=size, camera=Camera()), target)
                out.append(target.read()[..., :3])
            return 1.0 - (out[1] - out[0]).mean(-1), out[0]
        finally:
            gpu.free(target)
            for k in sets:
                params.reset(k)

    yield draw
    effect.release()
    gpu.release()


@pytest.mark.parametrize("size, sets", [
    ((64, 48), {"vr.element_size": 0.0}),
    ((64, 48), {"vr.element_size": 1.0}),
    ((64, 48), {"vr.screen_x": 0.0, "vr.screen_y": 0.0, "vr.element_size": 0.1}),
    ((64, 48), {"vr.screen_x": 1.0, "vr.screen_y": 1.0, "vr.element_size": 0.1}),
    ((64, 48), {"vr.lives": 1, "vr.remaining": 64.0, "vr.element_size": 0.1}),
    ((64, 48), {"vr.lives": 64, "vr.remaining": 0.0, "vr.element_size": 0.1}),
    ((1, 1), {"vr.element_size": 0.1}),
    ((1, 64), {"vr.element_size": 0.1, "vr.ring_aspect": "document"}),
    ((64, 1), {"vr.element_size": 0.1, "vr.ring_aspect": "repository"}),
])
def test_the_ring_stays_finite_and_bounded_at_its_extremes(ring, size, sets):
    alpha, premultiplied = ring(size, **{"vr.visibility": 0.8, **sets})
    assert np.isfinite(alpha).all() and np.isfinite(premultiplied).all()
    assert alpha.min() > -1e-5 and alpha.max() < 0.8 + 1e-5
    assert premultiplied.min() > -1e-5 and premultiplied.max() <= 1.0 + 1e-5
    if sets.get("vr.element_size") == 0.0:
        assert np.abs(alpha).max() < 1e-6  # a quad of zero size draws nothing


def test_the_twin_is_bounded_over_every_lives_and_remaining():
    theta = np.radians(np.linspace(0.0, 360.0, 721))
    uv = 0.5 + 0.4 * np.stack([np.cos(theta), np.sin(theta)], -1)
    for lives, remaining in itertools.product(range(1, 65), (0.0, 0.5, 7.0, 12.35, 64.0, 99.0)):
        frag = vr.ring_fragment(uv, np.ones(len(uv)), lives, remaining, 0.7, (1, 0, 0),
                                (0, 0, 1))
        assert np.isfinite(frag).all()
        assert frag[:, 3].min() >= 0.0 and frag[:, 3].max() <= 0.7 + 1e-12
        full = frag[:, 0] > frag[:, 2]  # Color Full is red, Color Empty blue here
        n, rem = vr.clamp_ring(lives, remaining)
        # full sections are the first ceil(Remaining) (counter-clockwise from 0°)
        sections, _ = vr.ring_sections(vr.ring_angle(2 * uv - 1), n)
        assert np.array_equal(full & (frag[:, 3] > 0), (sections < rem) & (frag[:, 3] > 0))


def test_disparity_grows_steadily_with_the_ipd(gl_ctx):
    gpu = Gpu(gl_ctx)
    scene = BoxScene(gpu)
    stereo = StereoRenderer(gpu, "test-stereo")
    size = (240, 120)
    target = gpu.target("test", "pair", size)
    shifts = []
    try:
        for ipd in (0.0, 0.05, 0.1, 0.15, 0.2):
            stereo.render(FrameContext(size=size, camera=HEAD), target, ipd, 1.0,
                          scene.render_eye)
            pair = halves(target.read(), size)
            xs = [np.nonzero((h[..., 0] > 0.5) & (h[..., 1] < 0.25))[1].mean()
                  for h in (pair["left"], pair["right"])]
            shifts.append(xs[0] - xs[1])
    finally:
        stereo.release()
        gpu.release()
    steps = np.diff(shifts)
    assert shifts[0] == pytest.approx(0.0, abs=0.1)
    want = float(measures.disparity_px(NEAR_DEPTH, 0.05, size[1], HEAD.fov))  # per 5 cm: 3.5 px
    assert np.all(np.abs(steps - want) <= 1.0), (steps, want)  # linear, within a pixel

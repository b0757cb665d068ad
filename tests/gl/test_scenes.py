"""Scenes create only what they use, every scene renders finite, and the display pass agrees
with the PNG writer's tone map.
"""

from __future__ import annotations

import moderngl
import numpy as np

from app.colour import to_srgb8
from app.gpu.device import Gpu
from app.runtime import open_session, render_frames
from app.scenes import SCENES
from app.scenes.base import Scene
from app.ui.display import draw_display


class EmptyScene(Scene):
    name = "empty"
    effects = ()


def test_scene_without_an_effect_allocates_none_of_it(gl_ctx):
    gpu = Gpu(gl_ctx)
    params = EmptyScene.declare_params(gpu.shaders)
    scene = EmptyScene(gpu, params)
    target = gpu.target("output", "scene", (32, 18))
    scene.render(scene.frame((32, 18)), target)
    assert {a.owner for a in gpu.allocations} == {"output"}
    assert gpu.shaders.programs() == []
    gpu.release()


def test_sky_scene_allocates_no_cubemap_and_no_probe(gl_ctx):
    session = open_session("sky", ctx=gl_ctx)
    next(render_frames(session, (32, 18)))
    kinds = {(a.owner, a.kind) for a in session.gpu.allocations}
    assert ("sky", "cubemap") not in kinds
    assert not session.gpu.owned_by("probe")
    assert [p.name for p in session.gpu.shaders.programs()] == ["sky/sky"]
    session.release()


def test_every_scene_renders_finite(gl_ctx):
    for name in SCENES:
        session = open_session(name, ctx=gl_ctx)
        img = next(render_frames(session, (32, 18)))
        assert np.isfinite(img).all() and img[..., :3].mean() > 0.0
        session.release()


def test_display_pass_matches_png_tonemap(gl_ctx):
    gpu = Gpu(gl_ctx)
    rng = np.random.default_rng(1)
    hdr = np.concatenate([rng.uniform(0, 1, (8, 64, 3)),
                          rng.uniform(0, 30, (8, 64, 3))]).astype(np.float32)
    hdr[0, :3] = 0.0
    src = gpu.texture("test", "hdr", (64, 16), 3, hdr[::-1].tobytes(),
                      filter=(moderngl.NEAREST, moderngl.NEAREST))
    out = gl_ctx.texture((64, 16), 4)
    fbo = gl_ctx.framebuffer([out])
    for mode in ("aces", "reinhard", "clamp"):
        fbo.use()
        draw_display(gpu, src, 0.7, mode)
        got = np.frombuffer(fbo.read(components=3), dtype=np.uint8).reshape(16, 64, 3)[::-1]
        want = to_srgb8(hdr, 0.7, mode)
        assert np.abs(got.astype(int) - want.astype(int)).max() <= 1, mode
    fbo.release()
    out.release()
    gpu.release()

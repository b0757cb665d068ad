"""Compositing a premultiplied layer (in-scattered light, transmittance) over a scene target:
out = layer.rgb + layer.a · scene (``glsl/common/layer_composite.frag``). Both cloud models use
it."""

from __future__ import annotations

import moderngl

from ..gpu.programs import draw_fullscreen, fullscreen

LAYER_COMPOSITE = fullscreen("common/layer_composite")


def composite_layer(effect, layer_texture, target) -> None:
    """Blend ``layer_texture`` over ``target`` (its depth untouched)."""
    ctx = effect.gpu.ctx
    prog = effect.program(LAYER_COMPOSITE)
    prog.bind_textures({"uCloudLayer": layer_texture})
    target.use()
    ctx.disable(moderngl.DEPTH_TEST)
    draw_fullscreen(prog, blend=(moderngl.ONE, moderngl.SRC_ALPHA, moderngl.ZERO, moderngl.ONE))

"""Compositing a premultiplied layer (in-scattered light, transmittance) over a scene target:
out = layer.rgb + layer.a · scene (``glsl/common/layer_composite.frag``). Both cloud models use
it."""

from __future__ import annotations

import moderngl

from ..gpu.programs import draw_fullscreen, fullscreen

LAYER_COMPOSITE = fullscreen("common/layer_composite")


def composite_layer(effect, layer, target) -> None:
    """Blend ``layer`` (a target's or an amortised history's ``color``) over ``target`` (its
    depth untouched). An amortised history is blended through :meth:`LayerHistory.over`, which
    skips the pixels its near cut left without cloud."""
    ctx = effect.gpu.ctx
    prog = effect.program(LAYER_COMPOSITE)
    prog.bind_textures({"uCloudLayer": layer.color})
    over = layer.over(target) if hasattr(layer, "over") else None
    blend = (moderngl.ONE, moderngl.SRC_ALPHA, moderngl.ZERO, moderngl.ONE)
    if over is None:
        target.use()
        ctx.disable(moderngl.DEPTH_TEST)
        draw_fullscreen(prog, blend=blend)
        return
    over.use()
    over.depth_mask = False
    ctx.enable(moderngl.DEPTH_TEST)
    ctx.depth_func = "<"  # drawn at depth ½: the near cut's mark (½) fails, the rest (1) passes
    try:
        draw_fullscreen(prog, blend=blend)
    finally:
        ctx.disable(moderngl.DEPTH_TEST)
        over.depth_mask = True

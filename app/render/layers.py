"""Compositing a premultiplied layer (in-scattered light, transmittance) over a scene target:
out = layer.rgb + layer.a · scene (``glsl/common/layer_composite.frag``), and
:class:`MarchedLayer`, what both cloud models share around it."""

from __future__ import annotations

from typing import Any, Callable

import moderngl

from .. import bakes
from ..bakes.textures import BakedTextures
from ..gpu.programs import draw_fullscreen, fullscreen
from ..gpu.targets import depth_tested
from . import amortise
from .amortise import Amortiser, schedule_for

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
    # drawn at depth ½: the near cut's mark (½) fails, the rest (1) passes
    with depth_tested(ctx, over, "<"):
        draw_fullscreen(prog, blend=blend)


class MarchedLayer:
    """A mixin for an effect (listed before ``Effect``) that marches a layer from baked
    textures, amortised by :mod:`app.render.amortise` (``<name>.reprojection``), and composites
    it over the image. The effect gives ``FULL_MARCH_MS_PER_MPX`` (``auto``'s estimate of a
    full-resolution march, ms per megapixel: software renderer, hardware GPU), ``layer_state``
    and its passes."""

    FULL_MARCH_MS_PER_MPX: tuple[float, float]
    name: str
    params: Any
    gpu: Any
    layer_state: Callable

    @classmethod
    def context_paths(cls, caps, params) -> dict[str, str]:
        march = amortise.context_line(caps, params, cls.name)
        return {**bakes.context_path(caps), "amortised march": march}

    def __init__(self, gpu, params):
        super().__init__(gpu, params)  # type: ignore[call-arg]  # the Effect after it
        self.bakes = BakedTextures(gpu, self.name)
        self._layer = None  # what the composite reads: the marched target or the resolved history
        self.amortiser = Amortiser(gpu, self.name)

    def schedule(self, size):
        """The amortised march's schedule at ``size`` (``auto`` from the frame budget)."""
        return schedule_for(self.params, self.name, size, self.gpu.caps.software,
                            self.FULL_MARCH_MS_PER_MPX)

    def render_layer(self, frame, target, march: Callable, jitter_phase: float) -> None:
        """The layer for this frame: ``march(grid, depth)`` into each grid the amortiser asks
        for, with the image's depth readable as values (not comparisons)."""
        with frame.image_for(target).depth_values() as depth:
            self._layer = self.amortiser.render(
                frame, target.size, self.params, self.schedule, self.layer_state,
                lambda grid: march(grid, depth), depth, jitter_phase)

    def composite(self, target) -> None:
        """Pass 2: target = target·transmittance + in-scattered light (alpha kept)."""
        if self._layer is None:  # no march yet: nothing to lay over the image
            return
        composite_layer(self, self._layer, target)

    def panel_notes(self) -> list[str]:
        return self.amortiser.panel_notes(self.params, self.name)

    def release(self) -> None:
        super().release()  # type: ignore[misc]  # the Effect after it
        self.amortiser.forget()
        self._layer = None

"""The display pass: scene radiance → tone-mapped sRGB pixels in the window, enlarged to it
when dynamic resolution renders the scene smaller (``glsl/common/display.frag``)."""

from __future__ import annotations

import moderngl

from ..colour import TONEMAPS
from ..gpu.programs import draw_fullscreen, fullscreen

DISPLAY = fullscreen("common/display")


def draw_display(gpu, source_texture, exposure: float, tonemap: str,
                 bicubic: bool = False) -> None:
    """Draw ``source_texture`` over the whole currently bound framebuffer (its viewport):
    bilinear, or with ``bicubic`` Catmull-Rom when it is smaller than the window."""
    prog = gpu.program("window", DISPLAY)
    prog.bind_textures({"uScene": source_texture})
    prog.set_many({"uExposure": float(exposure), "uTonemap": TONEMAPS.index(tonemap),
                   "uBicubic": 1 if bicubic else 0})
    gpu.ctx.disable(moderngl.DEPTH_TEST)
    draw_fullscreen(prog)

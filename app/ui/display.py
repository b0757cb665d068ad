"""The display pass: scene radiance → tone-mapped sRGB pixels in the window."""

from __future__ import annotations

import moderngl

from ..colour import TONEMAPS
from ..gpu.programs import draw_fullscreen, fullscreen

DISPLAY = fullscreen("common/display")


def draw_display(gpu, source_texture, exposure: float, tonemap: str) -> None:
    """Draw ``source_texture`` into the currently bound framebuffer."""
    prog = gpu.program("window", DISPLAY)
    prog.bind_textures({"uScene": source_texture})
    prog.set("uExposure", float(exposure))
    prog.set("uTonemap", TONEMAPS.index(tonemap))
    gpu.ctx.disable(moderngl.DEPTH_TEST)
    draw_fullscreen(prog)

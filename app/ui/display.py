"""The display pass: scene radiance → tone-mapped sRGB pixels in the window."""

from __future__ import annotations

import moderngl

from ..effects.base import fullscreen
from ..imageio import TONEMAPS

DISPLAY = fullscreen("common/display")


def draw_display(gpu, source_texture, exposure: float, tonemap: str) -> None:
    """Draw ``source_texture`` into the currently bound framebuffer."""
    prog = gpu.program("window", DISPLAY.name, vert=DISPLAY.vert, frag=DISPLAY.frag)
    source_texture.use(0)
    prog.set("uScene", 0)
    prog.set("uExposure", float(exposure))
    prog.set("uTonemap", TONEMAPS.index(tonemap))
    gpu.ctx.disable(moderngl.DEPTH_TEST)
    prog.vao().render(moderngl.TRIANGLES, vertices=3)

"""A mirror ball showing the sky's environment cubemap (the thesis's reflection probe,
spec/000 §1.7).

It reads the frame's ``environment`` slot (required: the scene must have a sky that produces
it), so the cubemap exists only in scenes that reflect something, and is re-rendered only when
the sky changed.
"""

from __future__ import annotations

import math

import moderngl

from ...gpu.programs import draw_fullscreen, fullscreen
from ..base import Effect

MIRROR_BALL = fullscreen("probe/mirror_ball")


class Probe(Effect):
    name = "probe"
    title = "Reflection probe (mirror ball)"
    spec = "spec/000"
    programs = (MIRROR_BALL,)
    consumes = {"environment": "required", "main_light": "optional"}

    def draw(self, frame, target) -> None:
        cube = frame.require("environment", by=self.name).cubemap()
        prog = self.program(MIRROR_BALL)
        prog.bind_textures({"uEnvironment": cube})
        prog.set_many(frame.camera_uniforms())
        prog.set_many(frame.light_uniforms())
        prog.set("uEnvironmentLods", float(int(math.log2(cube.size[0]))))
        self.apply_params(prog)
        target.use()
        self.gpu.ctx.disable(moderngl.DEPTH_TEST)
        draw_fullscreen(prog)

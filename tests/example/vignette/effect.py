"""Natural vignetting: the image darkens toward its corners as cos⁴ θ (the example effect of
docs/architecture.md; shader ``glsl/vignette/vignette.frag``)."""

from __future__ import annotations

import moderngl

from app.effects.base import Effect
from app.frame import Stage
from app.gpu.programs import draw_fullscreen, fullscreen

VIGNETTE = fullscreen("vignette/vignette")


class Vignette(Effect):
    name = "vignette"  # its parameter group, GLSL folder and test file are named alike
    title = "Natural vignetting"
    programs = (VIGNETTE,)  # `natura shaders check` compiles it; its @param becomes vignette.amount
    stages = (Stage.POST,)  # on the finished radiance, after fog
    consumes = {"image": "required"}  # it darkens the image the earlier stages drew

    def draw(self, frame, target) -> None:
        prog = self.program(VIGNETTE)
        self.apply_params(prog)  # every @param uniform of the effect: uAmount
        prog.set_many(frame.camera_uniforms())
        target.use()
        self.gpu.ctx.disable(moderngl.DEPTH_TEST)
        multiply = (moderngl.ZERO, moderngl.SRC_COLOR, moderngl.ZERO, moderngl.ONE)  # rgb·factor
        draw_fullscreen(prog, blend=multiply)

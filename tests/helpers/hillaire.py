"""The rig of method 4 (Hillaire 2020) shared by tests/gl/test_hillaire.py and
tests/stability/test_hillaire_stability.py: a Gpu, small static LUTs and the probe program
(glsl/tests/hillaire_probe.frag).
"""

from __future__ import annotations

import math

import moderngl
import numpy as np

from app.effects.planet.hillaire import CameraFrame, HillaireLuts, model_uniforms
from app.gpu.device import Gpu
from app.gpu.programs import fullscreen
from app.gpu.targets import RenderTarget
from app.sim.camera import Camera

PROBE = fullscreen("tests/hillaire_probe")
SMALL = {
    "hillaire.transmittance_width": 64, "hillaire.transmittance_height": 16,
    "hillaire.ms_size": 16,
}
SIZE = (32, 18)
TOP = 60_000.0


class Rig:
    """A Gpu, a HillaireLuts and the probe program."""

    def __init__(self, ctx, **overrides):
        self.gpu = Gpu(ctx)
        self.settings = dict(SMALL, **overrides)
        self.luts = HillaireLuts(self.gpu, "test", self.settings)
        self.prog = self.gpu.program("test", PROBE.name, **PROBE.stages())
        self.target = RenderTarget(ctx, SIZE, depth=False)
        self.u = None
        self.frame = None

    def set(self, name: str, value) -> None:
        self.settings[f"hillaire.{name}"] = value

    def update(self, altitude=2.0, sun_el=90.0, pitch=30.0, yaw=0.0, fov=60.0, sun_az=0.0,
               **overrides):
        self.camera = Camera(position=(0, 0, 0), yaw=yaw, pitch=pitch, fov=fov)
        self.u = model_uniforms(altitude, sun_el, sun_az, **overrides)
        r, u, f = self.camera.basis()
        self.frame = CameraFrame(tuple(r), tuple(u), tuple(f),
                                 math.tan(math.radians(self.camera.fov) / 2.0), SIZE[0] / SIZE[1])
        self.luts.update(self.u, self.frame)
        return self

    def probe(self, mode: int, distance: float = 0.0, steps: int = 400,
              sun_steps: int = 120) -> np.ndarray:
        p = self.prog
        p.set_many(self.u)
        p.set_many(self.frame.uniforms())
        self.luts.bind(p)
        p.set("uProbeMode", mode)
        p.set("uProbeDistance", float(distance))
        p.set("uProbeSteps", steps)
        p.set("uProbeSunSteps", sun_steps)
        with self.gpu.ctx.scope(self.target.fbo, enable_only=moderngl.NOTHING):
            self.target.fbo.viewport = (0, 0, *SIZE)
            p.vao().render(moderngl.TRIANGLES, vertices=3)
        return self.target.read()

    def directions(self) -> np.ndarray:
        return self.camera.ray_directions(*SIZE)

    def release(self):
        self.luts.release()
        self.target.release()
        self.gpu.release()

"""The rig of cloud model B (spec/000 §1.6) shared by tests/gl/test_clouds_b.py and
tests/stability/test_clouds_b_stability.py: the effect alone on a Gpu, its parameters reset
to small bakes before each test; renders return the composite and the cloud layer.
"""

from __future__ import annotations

import numpy as np

from app.effects.clouds_b.effect import CloudsB
from app.frame import FrameContext
from app.gpu.device import Gpu
from app.params import ParamSet
from app.sim.camera import Camera
from app.sim.daynight import Light

SMALL = {"clouds_b.volume_resolution": 32, "clouds_b.detail_resolution": 16,
         "clouds_b.gradient_resolution": 64}


BG = (0.2, 0.3, 0.5, 1.0)


class Rig:
    def __init__(self, gpu: Gpu):
        self.gpu = gpu
        self.params = ParamSet(CloudsB.declare(gpu.shaders))
        self.fx = CloudsB(gpu, self.params)
        self.targets = {}

    def reset(self, **sets):
        for p in list(self.params):
            self.params.set(p.name, p.default)
        for k, v in {**SMALL, "clouds_b.wind_speed": 0.0, "clouds_b.fixed_step_size": 40.0,
                     **sets}.items():
            self.params.set(k if k.startswith("clouds_b.") else f"clouds_b.{k}", v)

    def target(self, size):
        if size not in self.targets:
            self.targets[size] = self.gpu.target("test", f"clouds {size}", size)
        return self.targets[size]

    def render(self, cam: Camera, size=(48, 27), light=None, time=0.0, background=BG, depth=1.0,
               prepare=None):
        """→ (composited rgb, layer (rgb light, a transmittance))."""
        frame = FrameContext(size=size, camera=cam, time=time)
        if light is not None:
            d = np.asarray(light, dtype=np.float64)
            frame.main_light = frame.sun = Light("sun", d / np.linalg.norm(d), (1.0, 1.0, 1.0), 1.0)
        self.fx.update(frame, 0.0)
        target = self.target(size)
        target.clear(background, depth=depth)
        if prepare is not None:
            prepare(target)
        self.fx.render(frame, target)
        return target.read()[..., :3], self.fx._layer.read()


def luminance(rgb):
    return rgb @ np.array([0.2126, 0.7152, 0.0722])

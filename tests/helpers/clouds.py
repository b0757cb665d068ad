"""The clouds-scene rig of cloud model A (spec/001) shared by tests/gl/test_clouds.py and
tests/stability/test_clouds_stability.py: one session re-rendered with changing parameters,
the light set by parameters so the geometry is known.
"""

from __future__ import annotations

import numpy as np

from app.runtime import open_session, scene_params
from app.sim.camera import Camera

SIZE = (64, 36)
# the light from parameters: up and toward −z (the direction the default test camera looks)
FIXED_LIGHT = ["clouds.sun_from_sky=false", "clouds.sun_direction=0,0.6,-1", "clouds.wind_speed=0"]


# ---- render rig ----------------------------------------------------------------------------

class Rig:
    """One clouds-scene session re-rendered with changing parameters; returns the composite,
    the cloud layer and the background (the sky alone, same frame)."""

    def __init__(self, gl_ctx, sets=(), camera=None, scene="clouds"):
        self.params = scene_params(scene, sets=list(sets))
        self.session = open_session(scene, self.params, ctx=gl_ctx,
                                    camera=camera or default_camera())
        self.scene = self.session.scene
        self.targets = {}

    def target(self, size):
        if size not in self.targets:
            self.targets[size] = self.session.gpu.target("test", "rig", size)
        return self.targets[size]

    def set(self, **values):
        for k, v in values.items():
            self.params.set(k if "." in k else f"clouds.{k}", v)
        return self

    def render(self, size=SIZE, dt=0.0, background=False):
        frame = self.scene.frame(size, dt=dt)
        target = self.target(size)
        self.scene.render(frame, target)
        image = target.read()
        layer = self.scene.effect("clouds")._layer.read()  # the last cloud layer
        if not background:
            return image, layer
        target.use()
        target.clear()
        self.scene.effect("sky").render(frame, target)
        return image, layer, target.read()

    def release(self):
        for t in self.targets.values():
            self.session.gpu.free(t)
        self.session.release()


def default_camera():
    # below the layer (1500-4000 m), looking north and up: the sky and cloud bottoms
    return Camera(position=(0.0, 300.0, 0.0), yaw=0.0, pitch=25.0, fov=70.0, far=200000.0)


def alpha(layer):
    return 1.0 - layer[..., 3]


def luminance(rgb):
    return rgb[..., 0] * 0.2126 + rgb[..., 1] * 0.7152 + rgb[..., 2] * 0.0722


def finite(*arrays):
    return all(np.isfinite(a).all() for a in arrays)

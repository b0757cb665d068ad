"""The Preetham effect rendered alone (tests/gl/test_preetham.py and
tests/stability/test_preetham_stability.py): parameters reset, one frame, the shader's image
and the numpy twin's radiance for the same rays.
"""

from __future__ import annotations

import numpy as np

from app.frame import FrameContext
from app.sim.camera import Camera
from app.sim.daynight import Light

SIZE = (48, 32)


def render(rig, cam: Camera, sets: dict, sun=None):
    gpu, params, fx, target = rig
    for k in list(params):
        if k.group == "preetham":
            params.set(k.name, k.default)
    for k, v in sets.items():
        params.set(k, v)
    frame = FrameContext(size=SIZE, camera=cam)
    if sun is not None:
        frame.sun = frame.main_light = Light("sun", np.asarray(sun, float), (1.0, 1.0, 1.0), 1.0)
    fx.update(frame, 0.0)
    target.clear()
    fx.render(frame, target)
    return target.read()[..., :3], fx.radiance_numpy(cam.ray_directions(*SIZE)), frame

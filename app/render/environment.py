"""Fallbacks for the frame's ``environment`` slot, for consumers in a scene with no probe."""

from __future__ import annotations

import numpy as np


def flat_environment(gpu, owner: str, rgba=(0.3, 0.35, 0.4, 1.0)):
    """A 1×1 cubemap of one colour (linear radiance), allocated under ``owner``."""
    cube = gpu.texture_cube(owner, "flat environment", 1, dtype="f4")
    for face in range(6):
        cube.write(face, np.array(rgba, dtype="f4").tobytes())
    return cube

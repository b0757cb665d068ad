"""The water's grab pass (spec/003 §2.10, Unity's GrabPass and _CameraDepthTexture): a float
copy of the image drawn so far — its colour and its depth, in one blit.

The copy is ``app.gpu.copy.ColourCopy`` with its depth: the water depth-tests against the
image and writes its own depth into it, so it cannot sample the image's depth attachment while
it draws (a feedback loop); colour and depth come over in one ``copy_framebuffer`` and share
the framebuffer's origin, which is why the water's one ``ScreenUV`` serves both lookups
(glsl/toon_water/water.glsl). A target without depth gets a 1 × 1 depth of 1 (the far plane:
nothing behind the water). One copy per target size is kept (the two eyes of an odd-width stereo
frame differ by a pixel), at most two.
"""

from __future__ import annotations

from typing import Any

import moderngl
import numpy as np

from ...gpu.copy import ColourCopy


class GrabPass:
    """Copies of a target's colour (RGBA32F) and depth, allocated under ``owner``."""

    def __init__(self, gpu, owner: str):
        self.gpu = gpu
        self.owner = owner
        self._copies: dict[tuple[int, int], ColourCopy] = {}
        self._far: Any = None

    def _far_depth(self) -> Any:
        if self._far is None:
            self._far = self.gpu.texture(self.owner, "grab far depth", (1, 1), 1,
                                         np.ones(1, np.float32).tobytes(), dtype="f4",
                                         filter=(moderngl.NEAREST, moderngl.NEAREST))
        return self._far

    def of(self, target: Any) -> tuple[Any, Any]:
        """Copy ``target``'s colour and depth now; returns (colour, depth) textures (the depth
        sampled as values: its compare mode off)."""
        key = (int(target.size[0]), int(target.size[1]))
        if key not in self._copies:
            if len(self._copies) >= 2:
                self._copies.pop(next(iter(self._copies))).release()
            self._copies[key] = ColourCopy(self.gpu, self.owner, "grab", depth=True)
        copy = self._copies[key]
        colour = copy.of(target)
        return colour, (copy.depth if copy.depth is not None else self._far_depth())

    def release(self) -> None:
        for copy in self._copies.values():
            copy.release()
        self._copies = {}
        if self._far is not None:
            self.gpu.free(self._far)
            self._far = None

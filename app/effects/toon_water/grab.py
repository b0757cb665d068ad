"""The water's grab pass (spec/003 §2.10, Unity's GrabPass and _CameraDepthTexture): a float
copy of the image drawn so far — its colour and its depth, in one blit.

Why not ``app.gpu.copy.ColourCopy`` alone: the water depth-tests against the image and writes
its own depth into it, so it cannot sample the image's depth attachment while it draws (a
feedback loop); the depth must be copied too, and moderngl's blit copies colour and depth
together only between framebuffers with the same number of colour attachments. So the copy is
one framebuffer of a float colour texture (as ColourCopy's) and a depth texture, filled by one
``copy_framebuffer``; both share the framebuffer's origin, which is why the water's one
``ScreenUV`` serves both lookups (glsl/toon_water/water.glsl). A target without depth gets a
1 × 1 depth of 1 (the far plane: nothing behind the water). One copy per target size is kept
(the two eyes of an odd-width stereo frame differ by a pixel), at most two.
"""

from __future__ import annotations

from typing import Any

import moderngl
import numpy as np


class GrabPass:
    """Copies of a target's colour (RGBA32F) and depth, allocated under ``owner``."""

    def __init__(self, gpu, owner: str):
        self.gpu = gpu
        self.owner = owner
        self._copies: dict[tuple[int, int, bool], tuple[Any, Any, Any]] = {}
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
        has_depth = getattr(target, "depth", None) is not None
        key = (int(target.size[0]), int(target.size[1]), has_depth)
        if key not in self._copies:
            if len(self._copies) >= 2:
                self._drop(next(iter(self._copies)))
            g = self.gpu
            colour = g.texture(self.owner, "grab colour", key[:2], 4, dtype="f4")
            depth = g.depth_texture(self.owner, "grab depth", key[:2]) if has_depth else None
            if depth is not None:
                depth.compare_func = ""
                depth.filter = (moderngl.NEAREST, moderngl.NEAREST)
            fbo = g.framebuffer(self.owner, "grab", [colour], depth)
            self._copies[key] = (fbo, colour, depth)
        fbo, colour, depth = self._copies[key]
        self.gpu.ctx.copy_framebuffer(fbo, target.fbo)
        return colour, (depth if depth is not None else self._far_depth())

    def _drop(self, key) -> None:
        for obj in self._copies.pop(key):
            if obj is not None:
                self.gpu.free(obj)

    def release(self) -> None:
        for key in list(self._copies):
            self._drop(key)
        if self._far is not None:
            self.gpu.free(self._far)
            self._far = None

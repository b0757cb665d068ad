"""Temporal reprojection of the cloud layer (beyond the thesis; Schneider 2015): each frame marches
one pixel of every 4×4 block at quarter size and reprojects the other fifteen from the previous
frame (``glsl/clouds/reproject.frag``: container-entry reprojection, off-screen and disocclusion
rejection, neighbourhood clamp). Without a history — the first frame, a resize, a jump of the
camera — the layer is marched at full size and becomes the history.
"""

from __future__ import annotations

import moderngl
import numpy as np

from ...gpu.programs import draw_fullscreen, fullscreen

REPROJECT = fullscreen("clouds/reproject")

#: 4×4 Bayer order: consecutive frames march well-spread pixels of each block
BAYER4 = (0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5)


def block_pixel(frame_number: int) -> tuple[int, int]:
    """The pixel (x, y) of each 4×4 block marched on a given frame."""
    i = BAYER4[frame_number % 16]
    return (i % 4, i // 4)


class _History:
    """A full-size pair: the resolved layer (RGBA32F) and the opaque-scene distance (R32F)."""

    def __init__(self, gpu, owner: str, size):
        self.layer = gpu.texture(owner, "cloud history", size, 4, dtype="f4")
        self.dist = gpu.texture(owner, "cloud history distance", size, 1, dtype="f4")
        self.fbo = gpu.framebuffer(owner, "cloud history", [self.layer, self.dist])
        self.size = tuple(size)
        self.color = self.layer  # what the composite pass reads

    def free(self, gpu) -> None:
        for obj in (self.fbo, self.layer, self.dist):
            gpu.free(obj)


class TemporalReprojection:
    def __init__(self, gpu, owner: str):
        self.gpu = gpu
        self.owner = owner
        self._pair: list[_History] = []
        self._low = None
        self._prev_view_proj = None
        self._prev_position = None
        self.frame_number = 0
        self.full_marches = 0  # frames marched at full size (no usable history)

    def reset(self) -> None:
        self._prev_view_proj = None

    def _ensure(self, size):
        size = tuple(size)
        if not self._pair or self._pair[0].size != size:
            for h in self._pair:
                h.free(self.gpu)
            self._pair = [_History(self.gpu, self.owner, size),
                          _History(self.gpu, self.owner, size)]
            if self._low is not None:
                self.gpu.free(self._low)
            low = ((size[0] + 3) // 4, (size[1] + 3) // 4)
            self._low = self.gpu.target(self.owner, "cloud quarter march", low, dtype="f4",
                                        depth=False)
            self._prev_view_proj = None

    def step(self, frame, size, march, resolve_uniforms: dict, scene_depth=None,
             moving: bool = False):
        """One frame. ``march(target, block_sub)`` draws the cloud layer into ``target`` —
        ``block_sub`` (-1, -1) for a full-size march, else the 4×4-block pixel to march.
        ``moving``: the clouds themselves move (wind): clamp the history even if the camera is
        still. Returns the resolved full-size layer (an object with ``.color``)."""
        self._ensure(size)
        cam = frame.camera
        view_proj = cam.projection_matrix(frame.aspect) @ cam.view_matrix()
        position = np.asarray(cam.position, dtype=np.float64)
        jumped = (self._prev_position is not None
                  and np.linalg.norm(position - self._prev_position) > 500.0)
        have_history = self._prev_view_proj is not None and not jumped
        src, dst = self._pair[0], self._pair[1]
        if have_history:
            sub = block_pixel(self.frame_number)
            march(self._low, sub)
            fresh = self._low.color
        else:
            full = self.gpu.target(self.owner, "cloud full march", size, dtype="f4", depth=False)
            march(full, (-1, -1))
            fresh = full.color
            sub = (-1, -1)
            self.full_marches += 1
        prog = self.gpu.program(self.owner, REPROJECT)
        prog.bind_textures({"uFresh": fresh, "uHistory": src.layer, "uHistoryDist": src.dist,
                            "uSceneDepth": scene_depth})
        prog.set_many(frame.camera_uniforms())
        prog.set_many(resolve_uniforms)
        prog.set_many({
            "uHasSceneDepth": scene_depth is not None, "uSub": sub, "uFullFresh": not have_history,
            "uPrevViewProj": self._prev_view_proj if have_history else np.identity(4),
            "uClampHistory": bool(moving or not have_history
                                  or not np.allclose(view_proj, self._prev_view_proj, rtol=0.0,
                                                     atol=1e-9)),
        })
        dst.fbo.use()
        self.gpu.ctx.disable(moderngl.DEPTH_TEST | moderngl.BLEND)
        draw_fullscreen(prog)
        if not have_history:
            self.gpu.free(full)
        self._pair.reverse()
        self._prev_view_proj = view_proj
        self._prev_position = position
        self.frame_number += 1
        return dst

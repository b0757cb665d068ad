"""Float render targets and readback to numpy."""

from __future__ import annotations

import moderngl
import numpy as np


class RenderTarget:
    """An RGBA float colour texture (linear radiance) with an optional depth texture.

    ``read()`` returns an ``(height, width, 4)`` float32 array with row 0 at the top of the
    image, as image files and numpy users expect (OpenGL's row 0 is the bottom).
    """

    def __init__(self, ctx: moderngl.Context, size: tuple[int, int], dtype: str = "f4",
                 depth: bool = True, samples: int = 0):
        self.ctx = ctx
        self.size = (int(size[0]), int(size[1]))
        #: samples per pixel (0: an ordinary target). A multisampled target is drawn into and
        #: resolved (``ctx.copy_framebuffer`` into an ordinary one: colour and depth), not read
        self.samples = int(samples)
        self.color = ctx.texture(self.size, 4, dtype=dtype, samples=self.samples)
        if not self.samples:
            self.color.filter = (moderngl.LINEAR, moderngl.LINEAR)
        self.depth = (ctx.depth_texture(self.size, samples=self.samples) if depth else None)
        self.fbo = ctx.framebuffer(color_attachments=[self.color], depth_attachment=self.depth)

    @property
    def aspect(self) -> float:
        return self.size[0] / self.size[1]

    def use(self) -> None:
        self.fbo.use()

    def clear(self, rgba=(0.0, 0.0, 0.0, 1.0), depth: float = 1.0) -> None:
        r, g, b, a = rgba
        self.fbo.clear(r, g, b, a, depth=depth)

    def read(self) -> np.ndarray:
        w, h = self.size
        data = np.frombuffer(self.fbo.read(components=4, dtype="f4"), dtype=np.float32)
        return data.reshape(h, w, 4)[::-1].copy()

    def read_depth(self) -> np.ndarray:
        w, h = self.size
        data = np.frombuffer(self.fbo.read(attachment=-1, components=1, dtype="f4"),
                             dtype=np.float32)
        return data.reshape(h, w)[::-1].copy()

    def release(self) -> None:
        for obj in (self.fbo, self.color, self.depth):
            if obj is not None:
                obj.release()

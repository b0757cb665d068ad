"""A float copy of a target's colour — and, when asked, its depth — for passes that read the
image they draw over (refraction, Snell's window, transparency, a grab pass that also reads the
depth it is about to write into).

moderngl's ``copy_framebuffer`` into a texture goes through 8 bits and would clamp linear
radiance; copying framebuffer to framebuffer keeps the float values. The copy's texture is
remade only when the target's size changes.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import moderngl

if TYPE_CHECKING:
    from .device import Gpu


class ColourCopy:
    """An RGBA32F texture holding a copy of a render target's colour, allocated under
    ``owner`` as ``label``. With ``depth``, the target's depth is copied in the same blit into
    :attr:`depth` (sampled as values: compare off, nearest), when the target has one: a pass
    that depth-tests against the image and writes into it cannot also sample its depth."""

    def __init__(self, gpu: Gpu, owner: str, label: str, depth: bool = False):
        self.gpu = gpu
        self.owner = owner
        self.label = label
        self.with_depth = depth
        self.texture: Any = None
        self.depth: Any = None
        self._fbo: Any = None
        self._key: tuple | None = None

    def of(self, target: Any) -> Any:
        """Copy ``target``'s colour (and depth) now and return the colour's texture."""
        depth = self.with_depth and getattr(target, "depth", None) is not None
        key = (tuple(target.size), depth)
        if self.texture is None or self._key != key:
            self.release()
            size = key[0]
            self.texture = self.gpu.texture(self.owner, self.label, size, 4, dtype="f4")
            if depth:
                self.depth = self.gpu.depth_texture(self.owner, f"{self.label} depth", size)
                self.depth.compare_func = ""
                self.depth.filter = (moderngl.NEAREST, moderngl.NEAREST)
            self._fbo = self.gpu.framebuffer(self.owner, self.label, [self.texture], self.depth)
            self._key = key
        self.gpu.ctx.copy_framebuffer(self._fbo, target.fbo)
        return self.texture

    def release(self) -> None:
        for obj in (self._fbo, self.texture, self.depth):
            if obj is not None:
                self.gpu.free(obj)
        self.texture = self.depth = self._fbo = None
        self._key = None

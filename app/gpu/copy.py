"""A float copy of a target's colour, for passes that read the image they draw over
(refraction, Snell's window, transparency).

moderngl's ``copy_framebuffer`` into a texture goes through 8 bits and would clamp linear
radiance; copying framebuffer to framebuffer keeps the float values. The copy's texture is
remade only when the target's size changes.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .device import Gpu


class ColourCopy:
    """An RGBA32F texture holding a copy of a render target's colour, allocated under
    ``owner`` as ``label``."""

    def __init__(self, gpu: Gpu, owner: str, label: str):
        self.gpu = gpu
        self.owner = owner
        self.label = label
        self.texture: Any = None
        self._fbo: Any = None

    def of(self, target: Any) -> Any:
        """Copy ``target``'s colour now and return the texture that holds it."""
        size = tuple(target.size)
        if self.texture is None or tuple(self.texture.size) != size:
            self.release()
            self.texture = self.gpu.texture(self.owner, self.label, size, 4, dtype="f4")
            self._fbo = self.gpu.framebuffer(self.owner, self.label, [self.texture])
        self.gpu.ctx.copy_framebuffer(self._fbo, target.fbo)
        return self.texture

    def release(self) -> None:
        if self._fbo is not None:
            self.gpu.free(self._fbo)
        if self.texture is not None:
            self.gpu.free(self.texture)
        self.texture = self._fbo = None

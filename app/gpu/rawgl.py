"""The few GL entry points moderngl does not wrap, loaded through the context's own loader.

moderngl makes its contexts with glcontext, whose backend for the platform (EGL, GLX, WGL,
CGL) knows how that platform hands out GL functions (``eglGetProcAddress``,
``wglGetProcAddress`` with ``opengl32.dll`` for the GL 1.1 ones, the OpenGL framework's
symbols). Going through it (``ctx.mglo._context.load``; a window's context carries moderngl's
own loader, which asks the current context the same way) instead of opening
``libGL``/``libOpenGL``/``libEGL`` by name is what makes a raw call safe on every platform.

Two users: :class:`CubeFaceCopy` — the bound framebuffer copied into one face and mip level of
a cubemap on the GPU (``glCopyTexSubImage2D``, GL 1.1: moderngl can attach neither a cube face
nor a mip level to a framebuffer, and writes level 0 only) — and the pipeline-statistics
queries of ``app.gpu.timing``.
"""

from __future__ import annotations

import ctypes
from typing import Any

from ..errors import GpuUnavailableError

_GL_TEXTURE_CUBE_MAP_POSITIVE_X = 0x8515


def loader_of(ctx: Any) -> Any:
    """The loader behind a moderngl context: glcontext's backend for a standalone context,
    moderngl's DefaultLoader for a detected one (None when moderngl hides it)."""
    return getattr(getattr(ctx, "mglo", None), "_context", None)


def gl_function(ctx: Any, name: str, *argtypes: Any, restype: Any = None) -> Any:
    """The GL function ``name`` of ``ctx``'s platform as a ctypes callable; a one-line
    GpuUnavailableError when the context's loader does not have it."""
    loader = loader_of(ctx)
    # glcontext's backends (headless) and moderngl's DefaultLoader (a window's context) both
    # have load_opengl_function; older glcontext backends only load
    load = getattr(loader, "load_opengl_function", None) or getattr(loader, "load", None)
    if load is None:
        raise GpuUnavailableError(f"{name}: this moderngl context exposes no GL loader "
                                  "(allowed: moderngl 5.10 or newer, which keeps its loader)")
    address = load(name)
    if not address:
        raise GpuUnavailableError(f"{name}: the context's GL loader does not provide it")
    return ctypes.CFUNCTYPE(restype, *argtypes)(address)


class CubeFaceCopy:
    """Copy the bound framebuffer's colour (its lower-left ``size`` × ``size`` square) into
    face ``face`` (GL order +X, −X, +Y, −Y, +Z, −Z), mip level ``level`` of a moderngl
    cubemap, without a round trip through the CPU. Rows go as they are: framebuffer row 0
    becomes the face's t = 0 row, as ``TextureCube.write`` of ``fbo.read()`` would put it.
    Float colour to a float cube is converted by GL (RGBA32F → RGBA16F rounds to nearest)."""

    def __init__(self, ctx: Any):
        self.ctx = ctx
        i, u = ctypes.c_int, ctypes.c_uint
        self._copy = gl_function(ctx, "glCopyTexSubImage2D", u, i, i, i, i, i, i, i)

    def __call__(self, cube: Any, face: int, level: int, size: int) -> None:
        if not 0 <= face < 6:
            raise ValueError(f"cube face {face}: allowed 0..5")
        unit = int(self.ctx.default_texture_unit)
        cube.use(location=unit)  # glActiveTexture + glBindTexture(GL_TEXTURE_CUBE_MAP)
        self._copy(_GL_TEXTURE_CUBE_MAP_POSITIVE_X + face, int(level), 0, 0, 0, 0,
                   int(size), int(size))

"""Float render targets and readback to numpy, and the largest target a context can hold."""

from __future__ import annotations

import contextlib
import math
from collections.abc import Iterator

import moderngl
import numpy as np

from ..errors import UsageError

#: bytes per pixel of a frame's float colour target (RGBA32F)
COLOUR_BYTES = 16
#: a target smaller than this is not probed before use (every renderer holds a few MiB)
PROBE_BYTES = 64 * 2**20
#: bytes per pixel the host needs to read a frame back: the float read, its flipped copy and the
#: tone-mapped float image written out (app.imageio)
READBACK_BYTES = 3 * COLOUR_BYTES


@contextlib.contextmanager
def depth_tested(ctx: moderngl.Context, fbo, func: str = "<=",
                 write: bool = False) -> Iterator[None]:
    """The depth test on with ``func``, and ``fbo``'s depth writes only with ``write``, for a
    ``with`` block; then the defaults again: the test off, ``<``, depth writes on."""
    ctx.enable(moderngl.DEPTH_TEST)
    ctx.depth_func = func
    fbo.depth_mask = write
    try:
        yield
    finally:
        fbo.depth_mask = True
        ctx.depth_func = "<"
        ctx.disable(moderngl.DEPTH_TEST)


class TargetSizeError(UsageError):
    """A frame size the context cannot hold: over its side limits or its memory."""


def _gib(n: float) -> str:
    return f"{n / 2**30:.1f} GiB" if n >= 2**30 else f"{n / 2**20:.0f} MiB"


def side_limit(ctx: moderngl.Context) -> int:
    """The longest side a render target may have here: the least of GL_MAX_TEXTURE_SIZE,
    GL_MAX_RENDERBUFFER_SIZE and GL_MAX_VIEWPORT_DIMS."""
    info = ctx.info
    sides = [int(info.get("GL_MAX_TEXTURE_SIZE") or 0),
             int(info.get("GL_MAX_RENDERBUFFER_SIZE") or 0)]
    dims = info.get("GL_MAX_VIEWPORT_DIMS")
    if isinstance(dims, (tuple, list)) and dims:
        sides.append(int(min(dims)))
    sides = [s for s in sides if s > 0]
    return min(sides) if sides else 4096  # GL 3.3's least maximum texture size


def _holds(ctx: moderngl.Context, size: tuple[int, int]) -> bool:
    """Whether ``ctx`` allocates a float colour target with depth of ``size`` (made and
    released: a refused allocation fails at once, a granted one costs its clearing)."""
    made: list = []
    try:
        for make in (lambda: ctx.texture(size, 4, dtype="f4"), lambda: ctx.depth_texture(size)):
            made.append(make())
            if ctx.error != "GL_NO_ERROR":
                return False
        made.append(ctx.framebuffer(color_attachments=[made[0]], depth_attachment=made[1]))
        return True
    except moderngl.Error:
        return False
    finally:
        for obj in reversed(made):
            obj.release()
        ctx.error  # noqa: B018 — clear what a refused allocation left


def _largest_held(ctx: moderngl.Context, size: tuple[int, int]) -> tuple[int, int] | None:
    """About the largest size of ``size``'s shape that ``ctx`` allocates (``size`` itself was
    refused): the area halves until one is granted, then two bisection steps."""
    w, h = size

    def at(scale: float) -> tuple[int, int]:
        return max(1, int(w * scale)), max(1, int(h * scale))

    def granted(scale: float) -> bool:
        trial = at(scale)
        return trial[0] * trial[1] * COLOUR_BYTES <= PROBE_BYTES or _holds(ctx, trial)

    hi, lo = 1.0, None
    for _ in range(24):
        scale = hi / math.sqrt(2.0)
        if granted(scale):
            lo = scale
            break
        hi = scale
    if lo is None:
        return None
    for _ in range(2):
        mid = math.sqrt(lo * hi)
        lo, hi = (mid, hi) if granted(mid) else (lo, mid)
    return at(lo)


def _available_memory() -> int | None:
    """The host's available memory in bytes (Linux's MemAvailable), None where unknown."""
    with contextlib.suppress(OSError, ValueError, IndexError), \
            open("/proc/meminfo", encoding="ascii") as f:
        for line in f:
            if line.startswith("MemAvailable:"):
                return int(line.split()[1]) * 1024
    return None


def check_frame_size(ctx: moderngl.Context, size: tuple[int, int],
                     option: str = "--size") -> None:
    """Refuse, before any work, a frame ``size`` this context cannot render: a side over
    :func:`side_limit`, a float target it cannot allocate (a software renderer caps one
    texture's bytes: llvmpipe at 2 GiB), or a readback larger than the host's available memory.
    The message gives the limit; for an allocation it names the largest size of the same
    shape that was granted."""
    w, h = int(size[0]), int(size[1])
    renderer = str(ctx.info.get("GL_RENDERER", "this renderer"))
    limit = side_limit(ctx)
    if w > limit or h > limit:
        raise TargetSizeError(f"{option} {w}x{h} is over this renderer's limit of {limit} on "
                              f"each side (GL_MAX_TEXTURE_SIZE, GL_MAX_RENDERBUFFER_SIZE, "
                              f"GL_MAX_VIEWPORT_DIMS of {renderer}): allowed 1..{limit}")
    colour = w * h * COLOUR_BYTES
    if colour > PROBE_BYTES and not _holds(ctx, (w, h)):
        largest = _largest_held(ctx, (w, h))
        hint = f"about {largest[0]}x{largest[1]}" if largest else "a smaller size"
        raise TargetSizeError(f"{option} {w}x{h} needs a {_gib(colour)} float colour target "
                              f"that {renderer} cannot allocate: allowed up to {hint} here")
    available = _available_memory()
    need = w * h * READBACK_BYTES
    if available is not None and need > available:
        side = math.sqrt(available / READBACK_BYTES / (w * h))
        raise TargetSizeError(f"{option} {w}x{h} needs about {_gib(need)} of memory to read "
                              f"the frame back, {_gib(available)} is available: allowed up to "
                              f"{max(1, int(w * side))}x{max(1, int(h * side))} now")


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
        try:
            self.fbo = ctx.framebuffer(color_attachments=[self.color],
                                       depth_attachment=self.depth)
        except moderngl.Error as exc:  # the context could not allocate a texture this large
            for obj in (self.color, self.depth):
                if obj is not None:
                    obj.release()
            w, h = self.size
            raise TargetSizeError(
                f"a {w}x{h} {dtype} render target "
                f"({_gib(w * h * 4 * int(dtype[1:] or 4))}) could not be made on "
                f"{ctx.info.get('GL_RENDERER', 'this renderer')} ({exc}): allowed a smaller "
                f"--size or map size") from None

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

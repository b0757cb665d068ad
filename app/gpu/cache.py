"""A value rebuilt only when what it depends on changes.

Many resources are expensive to make and cheap to keep: a lookup table that depends on the
model's constants, a mesh that depends on its segment count, a texture that depends on a seed.
:class:`Keyed` holds one such value with the key it was built for; :meth:`Keyed.get` returns it
while the key is unchanged and otherwise releases the old value and builds a new one::

    self._lut = Keyed(self._build_lut, release=self.gpu.free)
    ...
    lut = self._lut.get((model.lut_key(), size))   # built on the first call and on changes

Keys are compared with ``==``; use tuples of plain values (numbers, strings, tuples).

:data:`MEMO` is the other kind: pure numpy builds (noise fields, meshes, placements) shared by
every session of the process, read-only, within a byte budget (:class:`Memo`).
"""

from __future__ import annotations

import dataclasses
import math
from collections import OrderedDict
from typing import Any, Callable, Generic, TypeVar

import numpy as np

T = TypeVar("T")

_UNSET: Any = object()


class Keyed(Generic[T]):
    """One value and the key it was built for."""

    def __init__(self, build: Callable[[Any], T], release: Callable[[T], None] | None = None):
        self._build = build
        self._release = release
        self.key: Any = _UNSET
        self.value: T | None = None
        self.builds = 0  # how many times build() ran

    @property
    def built(self) -> bool:
        return self.key is not _UNSET

    def get(self, key: Any) -> T:
        """The value for ``key``: the held one when the key is unchanged, else a new one."""
        if self.key is _UNSET or key != self.key:
            self.clear()
            value = self._build(key)
            self.value, self.key = value, key
            self.builds += 1
        return self.value  # type: ignore[return-value]

    def clear(self) -> None:
        """Release the value (if any) and forget the key."""
        if self.value is not None and self._release is not None:
            self._release(self.value)
        self.value = None
        self.key = _UNSET


# ---- values shared by every session of a process --------------------------------------------

#: how many bytes of arrays :data:`MEMO` keeps (least recently used out first): every parity
#: job's memoised builds together (roots, noise textures and bakes, meshes, mip levels) are
#: ~40 MB; and how many entries at most (values without arrays count no bytes)
MEMO_BUDGET = 256 << 20
MEMO_ENTRIES = 4096


def freeze(value: Any) -> Any:
    """Make every numpy array in ``value`` read-only (in tuples, lists, dict values and
    dataclass fields, one level deep each), so no holder of a shared value can change it for
    the others; returns ``value``."""
    if isinstance(value, np.ndarray):
        value.flags.writeable = False
    elif isinstance(value, (tuple, list)):
        for v in value:
            freeze(v)
    elif isinstance(value, dict):
        for v in value.values():
            freeze(v)
    elif dataclasses.is_dataclass(value) and not isinstance(value, type):
        for f in dataclasses.fields(value):
            freeze(getattr(value, f.name))
    return value


def nbytes(value: Any) -> int:
    """Bytes of the numpy arrays (and bytes objects) in ``value``, walked as :func:`freeze`
    walks it."""
    if isinstance(value, np.ndarray):
        return int(value.nbytes)
    if isinstance(value, (bytes, bytearray)):
        return len(value)
    if isinstance(value, (tuple, list)):
        return sum(nbytes(v) for v in value)
    if isinstance(value, dict):
        return sum(nbytes(v) for v in value.values())
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return sum(nbytes(getattr(value, f.name)) for f in dataclasses.fields(value))
    return 0


class Memo:
    """Pure builds kept across sessions: ``get(key, build)`` returns the value built for
    ``key`` by any earlier caller in this process, else builds, freezes (:func:`freeze`) and
    keeps it. The key must name everything the value depends on (the function's name and
    every argument); the arrays held take at most ``budget`` bytes, the least recently used
    dropped first (a value larger than the budget is returned but not kept).

    Why: a process that opens many sessions (a test module, the gallery, a bench) otherwise
    rebuilds the same noise fields, meshes and placements in every one; a session's own
    :class:`Keyed` values still die with it."""

    def __init__(self, budget: int = MEMO_BUDGET):
        self.budget = int(budget)
        self._items: OrderedDict[Any, tuple[Any, int]] = OrderedDict()
        self.bytes = 0
        self.hits = 0
        self.builds = 0

    def __len__(self) -> int:
        return len(self._items)

    def __contains__(self, key: Any) -> bool:
        return key in self._items

    def get(self, key: Any, build: Callable[[], T]) -> T:
        held = self._items.get(key)
        if held is not None:
            self._items.move_to_end(key)
            self.hits += 1
            return held[0]
        value = freeze(build())
        self.builds += 1
        self.put(key, value)
        return value

    def held(self, key: Any) -> Any:
        """The value kept for ``key`` (now the most recently used), or None."""
        item = self._items.get(key)
        if item is None:
            return None
        self._items.move_to_end(key)
        self.hits += 1
        return item[0]

    def put(self, key: Any, value: Any) -> None:
        """Keep ``value`` (frozen) for ``key``, replacing what was there."""
        size = nbytes(freeze(value))
        if key in self._items:
            self.bytes -= self._items.pop(key)[1]
        if size > self.budget:
            return
        self._items[key] = (value, size)
        self.bytes += size
        while self.bytes > self.budget or len(self._items) > MEMO_ENTRIES:
            _, (_, dropped) = self._items.popitem(last=False)
            self.bytes -= dropped

    def clear(self) -> None:
        self._items.clear()
        self.bytes = 0


#: the process's memo of pure numpy builds (see :class:`Memo`)
MEMO = Memo()


def memoised(build: Callable[..., T], *args: Any) -> T:
    """``build(*args)`` shared by every session: ``MEMO.get((build, *args), …)``. The key holds
    the function itself, so a test that replaces a module's builder gets its own values."""
    return MEMO.get((build, *args), lambda: build(*args))


# ---- mip levels ---------------------------------------------------------------------------------

_GL_TEXTURE_2D = 0x0DE1
_GL_TEXTURE_3D = 0x806F
_GL_TEXTURE_CUBE_MAP = 0x8513
_GL_TEXTURE_CUBE_MAP_POSITIVE_X = 0x8515
_GL_TEXTURE_BASE_LEVEL = 0x813C
_GL_TEXTURE_MAX_LEVEL = 0x813D
_GL_TEXTURE_INTERNAL_FORMAT = 0x1003
_GL_UNPACK_ALIGNMENT = 0x0CF5
_GL_PACK_ALIGNMENT = 0x0D05
_GL_FORMATS = {1: 0x1903, 2: 0x8227, 3: 0x1907, 4: 0x1908}  # RED, RG, RGB, RGBA
_GL_TYPES = {"f1": 0x1401, "f2": 0x140B, "f4": 0x1406}  # UNSIGNED_BYTE, HALF_FLOAT, FLOAT
_BYTES = {"f1": 1, "f2": 2, "f4": 4}
_MODERNGL_MAX_LEVEL = 1000  # what moderngl's build_mipmaps leaves GL_TEXTURE_MAX_LEVEL at


class _LevelUpload:
    """The raw GL calls that define mip levels from bytes (moderngl writes only levels it
    allocated, and allocates them only by generating them)."""

    def __init__(self, ctx: Any):
        import ctypes

        from .rawgl import gl_function

        i, u, p = ctypes.c_int, ctypes.c_uint, ctypes.c_void_p
        self.ctypes = ctypes
        self.image2d = gl_function(ctx, "glTexImage2D", u, i, i, i, i, i, u, u, p)
        self.image3d = gl_function(ctx, "glTexImage3D", u, i, i, i, i, i, i, u, u, p)
        self.parameter = gl_function(ctx, "glTexParameteri", u, u, i)
        self.level_parameter = gl_function(ctx, "glGetTexLevelParameteriv", u, i, u,
                                           ctypes.POINTER(ctypes.c_int))
        self.pixel_store = gl_function(ctx, "glPixelStorei", u, i)
        self.get_image = gl_function(ctx, "glGetTexImage", u, i, u, u, p)


_UPLOADS: "dict[int, tuple[Any, _LevelUpload]]" = {}


def _levels(size: tuple[int, ...]) -> list[tuple[int, ...]]:
    out = [tuple(size)]
    while max(out[-1]) > 1:
        out.append(tuple(max(1, s // 2) for s in out[-1]))
    return out


def build_mipmaps(tex: Any) -> None:
    """``tex.build_mipmaps()`` for a 2D, 3D or cube texture, with the levels the driver
    generated kept in :data:`MEMO` under level 0's content (a hash of it read back) and
    defined from there, as bytes, by the next texture of the same content, format and driver.

    Why: on llvmpipe the first ``glGenerateMipmap`` of each format in a context costs
    50–130 ms (it compiles a blit shader) and every session makes its own context; reading
    level 0 back and uploading the levels costs a few milliseconds. The levels are the
    driver's own (read back from its first generation), so the texture sampled is
    bit-identical; the GL state afterwards is build_mipmaps' (base level 0, max level 1000,
    LINEAR_MIPMAP_LINEAR / LINEAR). Use it for content that repeats from session to session (a
    texture uploaded from numpy, the first render of a cubemap), not for content that changes
    every frame: each distinct content is kept. Multisampled, depth and array textures, and a
    context whose loader has no raw GL, take moderngl's path."""
    import hashlib

    import moderngl

    three_d = isinstance(tex, moderngl.Texture3D)
    cube = isinstance(tex, moderngl.TextureCube)
    plain_2d = isinstance(tex, moderngl.Texture) and not tex.samples and not tex.depth
    if not (three_d or cube or plain_2d) or tex.dtype not in _GL_TYPES:
        tex.build_mipmaps()
        return
    ctx = tex.ctx
    try:
        made = _UPLOADS.get(id(ctx))
        if made is None or made[0] is not ctx:
            made = (ctx, _LevelUpload(ctx))
            _UPLOADS.clear()  # one context at a time: an old one's entry points go with it
            _UPLOADS[id(ctx)] = made
        gl = made[1]
    except Exception:  # no raw GL through this context's loader: moderngl's way
        tex.build_mipmaps()
        return
    digest = hashlib.blake2b(digest_size=20)
    for face in range(6) if cube else (None,):
        digest.update(tex.read() if face is None else tex.read(face))
    info = ctx.info
    key = ("mip levels", info.get("GL_VENDOR"), info.get("GL_RENDERER"), info.get("GL_VERSION"),
           type(tex).__name__, tuple(tex.size), tex.components, tex.dtype, digest.digest())
    target = _GL_TEXTURE_3D if three_d else _GL_TEXTURE_CUBE_MAP if cube else _GL_TEXTURE_2D
    images = [_GL_TEXTURE_CUBE_MAP_POSITIVE_X + f for f in range(6)] if cube else [target]
    base, kind = _GL_FORMATS[tex.components], _GL_TYPES[tex.dtype]
    sizes = _levels(tex.size)
    held = MEMO.held(key)
    if held is None:
        tex.build_mipmaps()
        # llvmpipe renders the levels (a blit per level) on its rasterizer threads, and
        # glGetTexImage of a level > 0 right after has read back zeros for some of them, no
        # error set (now and then, in a busy context: a planet albedo level 2 in a test run);
        # remembered, those zeros became every later session's level. Waiting for the GPU
        # here, once per content and process, makes the bytes the ones the texture holds.
        ctx.finish()
        tex.use(location=ctx.default_texture_unit)
        gl.pixel_store(_GL_PACK_ALIGNMENT, 1)
        levels = []
        for level, size in enumerate(sizes[1:], start=1):
            for image in images:
                data = bytearray(math.prod(size) * tex.components * _BYTES[tex.dtype])
                buf = (gl.ctypes.c_char * len(data)).from_buffer(data)
                gl.get_image(image, level, base, kind, buf)
                del buf
                levels.append(bytes(data))
        MEMO.put(key, tuple(levels))
        return
    tex.use(location=ctx.default_texture_unit)
    fmt = gl.ctypes.c_int()
    gl.level_parameter(images[0], 0, _GL_TEXTURE_INTERNAL_FORMAT, gl.ctypes.byref(fmt))
    gl.pixel_store(_GL_UNPACK_ALIGNMENT, 1)
    data_of = iter(held)
    for level, size in enumerate(sizes[1:], start=1):
        for image in images:
            if three_d:
                gl.image3d(image, level, fmt.value, *size, 0, base, kind, next(data_of))
            else:
                gl.image2d(image, level, fmt.value, *size, 0, base, kind, next(data_of))
    # what build_mipmaps leaves: base level 0, max level 1000 (GL's defaults, set again in
    # case the texture's were changed) and the trilinear filter (moderngl's bookkeeping too;
    # only its own level check, for read/write of a level > 0, still knows level 0 alone)
    gl.parameter(target, _GL_TEXTURE_BASE_LEVEL, 0)
    gl.parameter(target, _GL_TEXTURE_MAX_LEVEL, _MODERNGL_MAX_LEVEL)
    tex.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
